//! MTL text to `tobj` materials, parsed by lumis rather than by `tobj::load_mtl_buf`, which
//! panics on a colour with fewer than three numbers and reports other malformed lines without
//! saying which. Here a malformed statement is skipped with a warning naming the MTL file and
//! line, and the rest of the library still loads (docs/obj-mtl.md: a bad MTL never fails the
//! model).
//!
//! Statements read (the others are kept in `unknown_param`, where the converter finds `Tr`):
//! `newmtl`, `Ka`/`Kd`/`Ks`/`Ke` (`r g b`, or one value for a grey as the MTL specification
//! allows), `Ns`, `Ni`, `d`, `illum`, and the texture maps' file names. `#` at the start of a word starts a comment.

use std::path::Path;

/// The materials of MTL `bytes` read from `mtl`, in file order, and the warnings about the
/// statements skipped.
pub(super) fn parse_mtl(bytes: &[u8], mtl: &Path) -> (Vec<tobj::Material>, Vec<String>) {
    let text = String::from_utf8_lossy(bytes);
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    let mut materials = Vec::new();
    let mut warnings = Vec::new();
    // The material being filled; `None` before the first `newmtl` (statements there belong to
    // no material and are dropped, as tobj drops them) or after a nameless one.
    let mut current: Option<tobj::Material> = None;
    for (i, raw) in text.lines().enumerate() {
        let line = without_comment(raw).trim();
        let Some(key) = line.split_whitespace().next() else {
            continue;
        };
        let rest = line[key.len()..].trim();
        if key == "newmtl" {
            materials.extend(current.take());
            if rest.is_empty() {
                warnings.push(format!(
                    "{}: line {}: newmtl without a name; the statements up to the next newmtl \
                     are ignored",
                    mtl.display(),
                    i + 1
                ));
            } else {
                current = Some(tobj::Material {
                    name: rest.to_string(),
                    ..Default::default()
                });
            }
            continue;
        }
        let Some(m) = current.as_mut() else {
            continue;
        };
        if let Err(why) = statement(m, key, rest) {
            warnings.push(format!(
                "{}: line {}: \"{line}\": {why}; the statement is ignored",
                mtl.display(),
                i + 1
            ));
        }
    }
    materials.extend(current);
    (materials, warnings)
}

/// `raw` up to a `#` that starts the line or follows whitespace (a `#` inside a word, as in a
/// texture file name `tex#1.png`, is kept).
fn without_comment(raw: &str) -> &str {
    let starts = raw
        .char_indices()
        .find(|&(i, c)| c == '#' && raw[..i].chars().next_back().is_none_or(char::is_whitespace));
    starts.map_or(raw, |(i, _)| &raw[..i])
}

/// Applies one statement `key rest` to `m`; the error says what is malformed.
fn statement(m: &mut tobj::Material, key: &str, rest: &str) -> Result<(), String> {
    match key {
        "Ka" => m.ambient = Some(colour(rest)?),
        "Kd" => m.diffuse = Some(colour(rest)?),
        "Ks" => m.specular = Some(colour(rest)?),
        "Ke" => m.emissive = Some(colour(rest)?),
        "Ns" => m.shininess = Some(number(rest)?),
        "Ni" => m.optical_density = Some(number(rest)?),
        "d" => m.dissolve = Some(number(rest)?),
        "illum" => {
            m.illumination_model = Some(
                rest.parse()
                    .map_err(|_| format!("illum needs an integer 0..=255, got \"{rest}\""))?,
            )
        }
        "map_Ka" | "map_Kd" | "map_Ks" | "map_Bump" | "map_bump" | "bump" | "map_Ns" | "map_ns"
        | "map_NS" | "map_d" => {
            if rest.is_empty() {
                return Err(format!("{key} needs a file name"));
            }
            let slot = match key {
                "map_Ka" => &mut m.ambient_texture,
                "map_Kd" => &mut m.diffuse_texture,
                "map_Ks" => &mut m.specular_texture,
                "map_Bump" | "map_bump" | "bump" => &mut m.normal_texture,
                "map_d" => &mut m.dissolve_texture,
                _ => &mut m.shininess_texture,
            };
            *slot = Some(rest.to_string());
        }
        _ => {
            m.unknown_param.insert(key.to_string(), rest.to_string());
        }
    }
    Ok(())
}

/// `r g b`, or a single `r` meaning a grey (the MTL specification makes g and b optional).
fn colour(rest: &str) -> Result<[f32; 3], String> {
    let words: Vec<&str> = rest.split_whitespace().collect();
    if matches!(words.first(), Some(&("spectral" | "xyz"))) {
        return Err(format!("{} colours are not supported", words[0]));
    }
    let values: Vec<f32> = words
        .iter()
        .map(|w| w.parse())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("a colour is 1 or 3 numbers, got \"{rest}\""))?;
    match values[..] {
        [v] => Ok([v; 3]),
        [r, g, b] => Ok([r, g, b]),
        _ => Err(format!(
            "a colour is 1 or 3 numbers, got {} values",
            values.len()
        )),
    }
}

/// Exactly one number.
fn number(rest: &str) -> Result<f32, String> {
    match rest.split_whitespace().collect::<Vec<_>>()[..] {
        [w] => w.parse().map_err(|_| format!("\"{w}\" is not a number")),
        _ => Err(format!("expected one number, got \"{rest}\"")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn malformed_statements_warn_with_their_line_and_the_rest_loads() {
        let text = "Kd 1 1 1\nnewmtl a\nKd 1\nKs 0.5 0.25\nNs\nillum 300\nKe 1 2 3 # glow\n\
                    newmtl\nKd 0 0 0\nnewmtl b\nd 0.5\nmap_Kd  my tex#1.png \nTr 0.1\n";
        let (m, w) = parse_mtl(text.as_bytes(), Path::new("lib.mtl"));
        assert_eq!(m.len(), 2);
        assert_eq!(m[0].name, "a");
        assert_eq!(m[0].diffuse, Some([1.0; 3]));
        assert_eq!(m[0].specular, None);
        assert_eq!(m[0].emissive, Some([1.0, 2.0, 3.0]));
        assert_eq!(m[1].dissolve, Some(0.5));
        assert_eq!(m[1].diffuse_texture.as_deref(), Some("my tex#1.png"));
        assert_eq!(m[1].unknown_param["Tr"], "0.1");
        assert_eq!(w.len(), 4, "{w:?}");
        for (warning, line) in w.iter().zip([4, 5, 6, 8]) {
            assert!(
                warning.starts_with(&format!("lib.mtl: line {line}: ")),
                "{warning}"
            );
        }
    }
}
