//! The `.m` mesh format of the paper's scenes: `Vertex i x y z {attributes}` and `Face j a b c`
//! lines with 1-based vertex numbers; `#` starts a comment; attributes after the coordinates
//! are ignored, and so are the format's `Corner` and `Edge` attribute statements.

use super::super::{SceneError, read_text};
use lumis_core::geometry::Mesh;
use lumis_core::math::Vec3;
use std::collections::HashMap;
use std::path::Path;

/// Reads a `.m` file into a mesh (no normals: faceted, like the original renders them).
pub fn load_m_file(path: &Path) -> Result<Mesh, SceneError> {
    let text = read_text(path)?;
    parse_m(&text, path)
}

/// Parses `.m` text; `path` is only used in messages.
pub fn parse_m(text: &str, path: &Path) -> Result<Mesh, SceneError> {
    let err = |line: usize, message: String| SceneError::Line {
        path: path.to_owned(),
        line,
        message,
    };
    let mut slot_of_vertex: HashMap<u64, u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut faces: Vec<(usize, [u64; 3])> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.split('#').next().unwrap_or("");
        let mut tok = content.split_whitespace();
        let Some(keyword) = tok.next() else { continue };
        let mut int = |what: &str| -> Result<u64, SceneError> {
            let t = tok
                .next()
                .ok_or_else(|| err(line, format!("expected {what}, found end of line")))?;
            t.parse().map_err(|_| {
                err(
                    line,
                    format!("expected {what} (a whole number), found {t:?}"),
                )
            })
        };
        match keyword {
            "Vertex" => {
                let id = int("vertex number")?;
                let mut c = [0.0f32; 3];
                for (k, v) in c.iter_mut().enumerate() {
                    let t = tok.next().ok_or_else(|| {
                        err(
                            line,
                            format!("vertex {id}: expected 3 coordinates, found {k}"),
                        )
                    })?;
                    *v = t.parse().map_err(|_| {
                        err(line, format!("vertex {id}: expected a number, found {t:?}"))
                    })?;
                }
                let p = Vec3::from(c);
                if !p.is_finite() {
                    return Err(err(
                        line,
                        format!("vertex {id} has a non-finite coordinate"),
                    ));
                }
                if slot_of_vertex.insert(id, positions.len() as u32).is_some() {
                    return Err(err(line, format!("vertex {id} is defined twice")));
                }
                positions.push(p);
            }
            "Face" => {
                int("face number")?;
                let v = [
                    int("vertex number")?,
                    int("vertex number")?,
                    int("vertex number")?,
                ];
                faces.push((line, v));
            }
            // Per-corner and per-edge attributes (normals, creases): nothing lumis uses.
            "Corner" | "Edge" => {}
            other => {
                return Err(err(
                    line,
                    format!("unknown statement {other:?}; expected Vertex, Face, Corner or Edge"),
                ));
            }
        }
    }
    let mut indices = Vec::with_capacity(faces.len());
    for (line, v) in faces {
        let mut idx = [0u32; 3];
        for (slot, id) in idx.iter_mut().zip(v) {
            *slot = *slot_of_vertex
                .get(&id)
                .ok_or_else(|| err(line, format!("face uses vertex {id}, which is not defined")))?;
        }
        indices.push(idx);
    }
    if indices.is_empty() {
        return Err(err(
            text.lines().count().max(1),
            "the mesh has no faces".into(),
        ));
    }
    Mesh::new(positions, None, None, indices).map_err(|e| err(0, e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_vertices_faces_and_ignores_attributes() {
        let text = "# a quad\nVertex 1 0 0 0 {normal=(0 1 0)}\nVertex 2 1 0 0\nVertex 3 1 1 0\nVertex 4 0 1 0\nFace 1 1 2 3\nFace 2 1 3 4\n";
        let m = parse_m(text, Path::new("q.m")).unwrap();
        assert_eq!(m.triangle_count(), 2);
        assert_eq!(m.indices()[1], [0, 2, 3]);
    }

    #[test]
    fn errors_name_file_and_line() {
        let bad = "Vertex 1 0 0 0\nVertex 2 1 0\n";
        let e = parse_m(bad, Path::new("bad.m")).unwrap_err().to_string();
        assert!(e.starts_with("bad.m:2:"), "{e}");
        let missing = "Vertex 1 0 0 0\nVertex 2 1 0 0\nFace 1 1 2 7\n";
        let e = parse_m(missing, Path::new("m.m")).unwrap_err().to_string();
        assert!(e.contains("m.m:3:") && e.contains("vertex 7"), "{e}");
    }
}
