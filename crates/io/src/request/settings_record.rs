//! The render settings as a JSON object for the EXR header (`lumis/settings`): the keys of the
//! TOML `[render]` table and of `-D render.*`, numbers as numbers, choices as the names scene
//! files and the command line use.

use lumis_core::geometry::Offset;
use lumis_core::scene::Settings;
use serde_json::{Map, Value, json};

/// `st` as `{"width": 640, "spp": 2, "precision": "watertight", ...}`: every setting, in the
/// TOML schema's words (`lens_samples` and `medium_ior`, which no TOML key sets, under their
/// own names); `epsilon` only with `offset = "epsilon"`, `adaptive` only when on.
pub fn settings_record(st: &Settings) -> Value {
    let mut m = Map::new();
    let mut put = |k: &str, v: Value| {
        m.insert(k.to_string(), v);
    };
    put("width", json!(st.width));
    put("height", json!(st.height));
    put("spp", json!(st.spp));
    put("max_depth", json!(st.max_depth));
    put("ambient", json!(st.ambient.to_array().map(shortest)));
    put("background", json!(st.background.to_array().map(shortest)));
    put("exposure", json!(shortest(st.exposure)));
    put("lens_samples", json!(st.lens_samples));
    put("medium_ior", json!(shortest(st.medium_ior)));
    put("precision", json!(st.precision.name()));
    put("offset", json!(st.offset.name()));
    if let Offset::Epsilon(e) = st.offset {
        put("epsilon", json!(shortest(e)));
    }
    put("cutoff", json!(shortest(st.cutoff)));
    put("display", json!(st.display.name()));
    if let Some(t) = st.adaptive {
        put("adaptive", json!(shortest(t)));
    }
    Value::Object(m)
}

/// `x` as the f64 of its shortest decimal (0.03, not 0.029999999329447746): the same f32 when
/// read back, and the number a person wrote. The settings are validated finite.
fn shortest(x: f32) -> f64 {
    x.to_string().parse().unwrap_or(f64::from(x))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_are_the_toml_schemas_and_values_plain() {
        let st = Settings {
            adaptive: Some(0.25),
            ..Settings::default()
        };
        let v = settings_record(&st);
        assert_eq!(v["width"], json!(st.width));
        assert_eq!(v["precision"], json!("watertight"));
        assert_eq!(v["adaptive"], json!(0.25));
        let ambient = Settings {
            ambient: lumis_core::math::Vec3::splat(0.03),
            ..Settings::default()
        };
        assert_eq!(
            settings_record(&ambient)["ambient"],
            json!([0.03, 0.03, 0.03])
        );
        let text = v.to_string();
        assert!(!text.contains("Vec3(") && !text.contains("Some("), "{text}");
        assert!(
            settings_record(&Settings::default())
                .get("adaptive")
                .is_none()
        );
    }
}
