//! `lumis info FILE`: what a scene or model file holds, without rendering.

use anyhow::Result;
use lumis_core::camera::Lens;
use lumis_core::effects::{Analysis, EffectMode};
use lumis_core::integrator::effects_text;
use lumis_core::light::Light;
use lumis_core::scene::Scene;
use std::fmt::Write as _;
use std::path::Path;

/// Loads `path` (every placement flattened with `flatten_instances`) and prints its contents.
pub fn run(path: &Path, flatten_instances: bool) -> Result<()> {
    let options = lumis_io::formats::LoadOptions {
        flatten_instances,
        ..Default::default()
    };
    let scene = lumis_io::formats::load_with(path, &options)?;
    print!("{}", describe(path, &scene));
    Ok(())
}

/// The report: geometry, materials, lights, camera, bounds, settings and warnings.
fn describe(path: &Path, scene: &Scene) -> String {
    let g = scene.geometry();
    let triangles: usize = g.meshes().iter().map(|m| m.triangle_count()).sum();
    let b = g.bounds();
    let mut s = String::new();
    let _ = writeln!(s, "file: {}", path.display());
    let _ = writeln!(
        s,
        "objects: {} ({} spheres, {} meshes with {} triangles; {} primitives)",
        scene.objects().len(),
        g.spheres().len(),
        g.meshes().len(),
        triangles,
        g.prims().len()
    );
    if g.has_instances() {
        // The counts above are the scene's own (flattened) geometry; instances add theirs.
        let inner: usize = g
            .prototypes()
            .iter()
            .map(|p| p.geometry().prims().len())
            .sum();
        let _ = writeln!(
            s,
            "instances: {} of {} prototypes ({} primitives in the prototypes)",
            g.instances().len(),
            g.prototypes().len(),
            inner
        );
    }
    if b.is_empty() {
        let _ = writeln!(s, "bounds: empty");
    } else {
        let _ = writeln!(s, "bounds: min {} max {}", b.min, b.max);
    }
    let _ = writeln!(s, "materials: {}", scene.materials().len());
    for (i, o) in scene.objects().iter().enumerate().take(20) {
        let m = &scene.materials()[o.material as usize];
        let _ = writeln!(
            s,
            "  object {i} {:?}: material {} (reflectivity {}, transmission {}, ior {}, emission {})",
            o.name, o.material, m.reflectivity, m.transmission, m.ior, m.emission
        );
    }
    if scene.objects().len() > 20 {
        let _ = writeln!(s, "  ... and {} more objects", scene.objects().len() - 20);
    }
    let _ = writeln!(s, "lights: {}", scene.lights().len());
    for (light, name) in scene.lights().iter().zip(scene.light_names()) {
        let _ = writeln!(s, "  {name}: {}", describe_light(light));
    }
    let cam = scene.camera();
    let _ = writeln!(
        s,
        "camera: {} at {} looking along {} ({})",
        if cam.is_orthographic() {
            "orthographic"
        } else {
            "perspective"
        },
        cam.position(),
        cam.forward(),
        describe_lens(cam.lens())
    );
    if let Some(f) = scene.frame() {
        let rate = f.rate();
        let _ = writeln!(
            s,
            "animation: {} frames (0..={}) at {}/{} fps; shown at frame {}",
            f.count(),
            f.count() - 1,
            rate.numerator(),
            rate.denominator(),
            f.number()
        );
    }
    let st = scene.settings();
    let _ = writeln!(
        s,
        "render: {}x{}, {}x{} samples, max depth {}, ambient {}, background {}",
        st.width, st.height, st.spp, st.spp, st.max_depth, st.ambient, st.background
    );
    // What a render would decide; AOV rays depend on the output, not on the scene.
    let mut analysis = Analysis::new(scene, EffectMode::Auto, true);
    analysis.aov.reason = "when an EXR is written (a PNG-only render traces none)".into();
    s += &effects_text(&analysis, None);
    let _ = writeln!(s, "warnings: {}", scene.warnings().len());
    for w in scene.warnings() {
        let _ = writeln!(s, "  {w}");
    }
    s
}

/// A light in the scene format's words (what `intensity` and `color` make, per kind).
fn describe_light(light: &Light) -> String {
    match *light {
        Light::Point {
            position,
            intensity,
        } => format!("point light at {position}, intensity {intensity} (color x intensity)"),
        Light::Unattenuated {
            position,
            irradiance,
        } => format!(
            "point light without distance falloff (a .scn light) at {position}, irradiance \
             {irradiance}"
        ),
        Light::Directional {
            direction,
            irradiance,
        } => format!("directional light along {direction}, irradiance {irradiance}"),
        Light::Spot {
            position,
            direction,
            intensity,
            cos_inner,
            cos_outer,
        } => format!(
            "spot light at {position} along {direction}, intensity {intensity}, cone {:.2} \
             degrees inside and {:.2} degrees outside",
            cos_inner.clamp(-1.0, 1.0).acos().to_degrees(),
            cos_outer.clamp(-1.0, 1.0).acos().to_degrees()
        ),
    }
}

/// The camera's lens in the scene format's words.
fn describe_lens(lens: Lens) -> String {
    match lens {
        Lens::Pinhole => "pinhole, no depth of field".to_string(),
        Lens::Disk(radius) => format!("thin lens of radius {radius}"),
        Lens::Square(size) => format!("square lens of side {size} (the .scn dispersion)"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lumis_core::math::Vec3;

    #[test]
    fn lights_and_lenses_read_as_words() {
        let v = Vec3::new(1.0, 2.0, 3.0);
        let lights = [
            Light::Point {
                position: v,
                intensity: v,
            },
            Light::Unattenuated {
                position: v,
                irradiance: v,
            },
            Light::Directional {
                direction: v,
                irradiance: v,
            },
            Light::Spot {
                position: v,
                direction: v,
                intensity: v,
                cos_inner: 1.0,
                cos_outer: 0.5,
            },
        ];
        for text in lights.iter().map(describe_light).chain(
            [Lens::Pinhole, Lens::Disk(0.1), Lens::Square(5.0)]
                .into_iter()
                .map(describe_lens),
        ) {
            for debug in ["{ ", "Vec3(", "Some(", "Square(", "Disk("] {
                assert!(!text.contains(debug), "{text}");
            }
        }
        assert!(describe_light(&lights[3]).contains("cone 0.00 degrees inside and 60.00"));
    }
}
