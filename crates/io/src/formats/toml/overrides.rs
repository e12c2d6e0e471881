//! `-D KEY=VALUE` scene-parameter overrides (Mitsuba 3's `-D`): a dotted key into a TOML
//! scene document and a TOML value, applied to the parsed document before it is checked, so an
//! override meets exactly the schema and the checks the key meets in a file.
//!
//! ```text
//! -D render.spp=4                   [render] spp = 4
//! -D camera.fov=30                  [camera] fov = 30
//! -D materials.glass.ior=1.6        [materials.glass] ior = 1.6
//! -D sphere.0.radius=2              the first [[sphere]]'s radius
//! -D sphere.ball.center=[0,1,0]     the [[sphere]] with name = "ball"
//! -D instance.ring.translate=[1,0,0] the [[instance]] with name = "ring"
//! -D render.display=clamp           a bare word is a string
//! ```
//!
//! Other formats have no document to edit: there the `render.*` keys go through the same
//! `[render]` schema onto the settings the file set ([`apply_render_overrides`]).

use std::fmt;
use std::path::Path;
use std::str::FromStr;

use ::toml::{Table, Value};

use super::render::merge;
use super::schema::SceneDoc;
use crate::formats::SceneError;
use lumis_core::scene::Scene;

/// One `-D KEY=VALUE`: where in a scene document, and the value to put there.
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    /// The key as written (`materials.glass.ior`).
    key: String,
    /// Its dot-separated segments, none empty.
    path: Vec<String>,
    /// The value, as TOML parses it (a bare word becomes a string).
    value: Value,
}

impl Override {
    /// The dotted key, as the user wrote it.
    pub fn key(&self) -> &str {
        &self.key
    }

    /// Whether the key lies under `[render]` or `[environment]`, the tables every format
    /// has.
    pub fn is_render(&self) -> bool {
        self.path[0] == "render" || self.path[0] == "environment"
    }

    /// How errors name the override: `-D render.spp=abc`.
    fn element(&self) -> String {
        format!("-D {self}")
    }
}

impl Override {
    /// The override `key = value` with a string value (what a flag such as `--env FILE`
    /// stands for), without quoting it for the parser.
    pub fn string(key: &str, value: &str) -> Result<Self, String> {
        Self::with_value(key, Value::String(value.to_owned()))
    }

    /// The override `key = value` with a number value.
    pub fn number(key: &str, value: f64) -> Result<Self, String> {
        Self::with_value(key, Value::Float(value))
    }

    /// The override `key = value` with a boolean value.
    pub fn boolean(key: &str, value: bool) -> Result<Self, String> {
        Self::with_value(key, Value::Boolean(value))
    }

    fn with_value(key: &str, value: Value) -> Result<Self, String> {
        let mut o: Override = format!("{key}=0").parse()?;
        o.value = value;
        Ok(o)
    }
}

impl FromStr for Override {
    type Err = String;

    /// `KEY=VALUE`; the value is a TOML value (`4`, `30.5`, `"srgb"`, `[1, 2, 3]`, `true`), or
    /// a bare word (letters, digits, `-`, `_`, `.`) taken as a string.
    fn from_str(arg: &str) -> Result<Self, String> {
        let (key, text) = arg
            .split_once('=')
            .ok_or_else(|| format!("{arg:?}: expected KEY=VALUE, e.g. render.spp=4"))?;
        let key = key.trim();
        let path: Vec<String> = key.split('.').map(str::to_owned).collect();
        if path.iter().any(|s| s.is_empty()) {
            return Err(format!(
                "{arg:?}: the key must be dot-separated names, e.g. render.spp"
            ));
        }
        let text = text.trim();
        let bare_word = !text.is_empty()
            && text
                .chars()
                .all(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | '.'));
        let value = match text.parse::<Value>() {
            Ok(v) => v,
            Err(_) if bare_word => Value::String(text.to_owned()),
            Err(e) => return Err(format!("{key}={text}: not a TOML value: {}", e.message())),
        };
        Ok(Override {
            key: key.to_owned(),
            path,
            value,
        })
    }
}

impl fmt::Display for Override {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}={}", self.key, self.value)
    }
}

/// Puts `value` at `path` under `table` (`at` is the key so far, for messages): tables are
/// entered by key (a missing one is created, so a new material can be defined), arrays of
/// tables (`sphere`, `mesh`, `instance`, `light`) by index or by an element's `name`. Elements of arrays
/// are changed, never added.
fn put(table: &mut Table, path: &[String], value: &Value, at: &str) -> Result<(), String> {
    let (seg, rest) = path.split_first().expect("a key has at least one segment");
    let here = if at.is_empty() {
        seg.clone()
    } else {
        format!("{at}.{seg}")
    };
    let Some(next) = rest.first() else {
        table.insert(seg.clone(), value.clone());
        return Ok(());
    };
    if !table.contains_key(seg.as_str()) && next.parse::<usize>().is_ok() {
        return Err(format!(
            "the scene has no `{here}` to index; elements can be changed, not added"
        ));
    }
    match table
        .entry(seg.as_str())
        .or_insert_with(|| Value::Table(Table::new()))
    {
        Value::Table(t) => put(t, rest, value, &here),
        Value::Array(items) => {
            let count = items.len();
            let item = element(items, next).ok_or_else(|| {
                format!("`{here}` has no element {next} (an index below {count}, or a `name`)")
            })?;
            if rest.len() == 1 {
                return Err(format!(
                    "`{here}.{next}` is a whole element; override one of its keys"
                ));
            }
            put(item, &rest[1..], value, &format!("{here}.{next}"))
        }
        other => Err(format!(
            "`{here}` holds a value of type {}, not a table with a `{next}` key",
            other.type_str()
        )),
    }
}

/// The array element `index` names: a position, or the element whose `name` it is.
fn element<'a>(items: &'a mut [Value], index: &str) -> Option<&'a mut Table> {
    let position = match index.parse::<usize>() {
        Ok(i) => i,
        Err(_) => items
            .iter()
            .position(|v| v.get("name").and_then(Value::as_str) == Some(index))?,
    };
    items.get_mut(position)?.as_table_mut()
}

/// `doc` with `overrides` applied in order (a later one wins), deserialized into the schema.
/// An error names the override at fault: the first whose addition breaks the schema.
fn apply(doc: &Table, overrides: &[Override], origin: &Path) -> Result<SceneDoc, SceneError> {
    let with = |n: usize| -> Result<Table, SceneError> {
        let mut t = doc.clone();
        for o in &overrides[..n] {
            put(&mut t, &o.path, &o.value, "")
                .map_err(|m| SceneError::invalid(origin, o.element(), m))?;
        }
        Ok(t)
    };
    match Value::Table(with(overrides.len())?).try_into::<SceneDoc>() {
        Ok(parsed) => Ok(parsed),
        Err(all) => {
            // The document alone is known to be valid: find the first override that breaks it.
            for (n, o) in overrides.iter().enumerate() {
                if let Err(e) = Value::Table(with(n + 1)?).try_into::<SceneDoc>() {
                    return Err(SceneError::invalid(origin, o.element(), e.message()));
                }
            }
            Err(SceneError::invalid(origin, "-D", all.message()))
        }
    }
}

/// The TOML scene `text` (already parsed once as a file, so its own errors keep their lines)
/// with `overrides` applied.
pub(super) fn apply_to_text(
    text: &str,
    origin: &Path,
    overrides: &[Override],
) -> Result<SceneDoc, SceneError> {
    let doc: Table = ::toml::from_str(text)
        .map_err(|e| SceneError::invalid(origin, "-D", e.message().to_owned()))?;
    apply(&doc, overrides, origin)
}

/// The error for a key other than `render.*` in a format without a TOML document.
pub(crate) fn refuse_non_render(origin: &Path, o: &Override) -> SceneError {
    let ext = origin
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("these");
    SceneError::invalid(
        origin,
        o.element(),
        format!(
            ".{ext} files take only render.* and environment.* overrides; `{}` exists only \
             in TOML scenes",
            o.key()
        ),
    )
}

/// Applies the `render.*` and `environment.*` overrides to a scene loaded from a format
/// without a TOML document, through the `[render]` and `[environment]` schemas and their
/// checks; any other key is refused by name.
pub fn apply_render_overrides(
    scene: &mut Scene,
    overrides: &[Override],
    origin: &Path,
) -> Result<(), SceneError> {
    if let Some(o) = overrides.iter().find(|o| !o.is_render()) {
        return Err(refuse_non_render(origin, o));
    }
    if overrides.is_empty() {
        return Ok(());
    }
    let doc = apply(&Table::new(), overrides, origin)?;
    let merged = merge(scene.settings(), &doc.render)
        .map_err(|m| SceneError::invalid(origin, "-D render", m))?;
    merged
        .validate()
        .map_err(|e| SceneError::invalid(origin, "-D render", e.to_string()))?;
    *scene.settings_mut() = merged;
    if let Some(env) = &doc.environment {
        super::environment::apply(scene, env, origin, &crate::formats::read_file_bytes)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn o(s: &str) -> Override {
        s.parse().unwrap()
    }

    #[test]
    fn values_parse_as_toml_and_bare_words_as_strings() {
        assert_eq!(o("render.spp=4").value, Value::Integer(4));
        assert_eq!(o("camera.fov=30.5").value, Value::Float(30.5));
        assert_eq!(
            o("render.display=\"clamp\"").value,
            o("render.display=clamp").value
        );
        assert_eq!(o("a.b=true").value, Value::Boolean(true));
        assert_eq!(o("a.b=[1, 2, 3]").value.as_array().map(Vec::len), Some(3));
        assert_eq!(o(" render.spp = 4 ").key(), "render.spp");
        assert!(o("render.spp=1").is_render() && !o("camera.fov=1").is_render());
        for bad in ["render.spp", "render..spp=1", "=1", "a=[1,", "a=x y"] {
            assert!(bad.parse::<Override>().is_err(), "{bad}");
        }
    }

    #[test]
    fn keys_address_tables_array_elements_by_index_or_name() {
        let mut doc: Table =
            ::toml::from_str("[[sphere]]\nname = \"a\"\nradius = 1\n[[sphere]]\nradius = 2\n")
                .unwrap();
        let mut set = |s: &str| {
            let o = o(s);
            put(&mut doc, &o.path, &o.value, "")
        };
        set("sphere.a.radius=5").unwrap();
        set("sphere.1.radius=6").unwrap();
        set("materials.new.ior=1.3").unwrap();
        assert!(
            set("sphere.2.radius=1")
                .unwrap_err()
                .contains("no element 2")
        );
        assert!(
            set("light.0.intensity=1")
                .unwrap_err()
                .contains("not added")
        );
        assert!(
            set("sphere.1.radius.x=1")
                .unwrap_err()
                .contains("not a table")
        );
        let radius = |i: usize| doc["sphere"][i]["radius"].as_integer();
        assert_eq!((radius(0), radius(1)), (Some(5), Some(6)));
        assert_eq!(doc["materials"]["new"]["ior"].as_float(), Some(1.3));
    }
}
