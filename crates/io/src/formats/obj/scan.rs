//! A cheap line-by-line pass over OBJ text before `tobj` parses it, for what `tobj` cannot
//! report well: the line of a bad face index or a non-finite vertex, the points and lines it
//! drops silently, and the line of every face (for warnings about degenerate polygons).

use std::path::Path;

use super::SceneError;

/// What the scan found.
#[derive(Debug, Default)]
pub(super) struct Scan {
    /// The text with `l` and `p` statements commented out: `tobj` would read an `l` with three
    /// or more vertices as a face.
    pub text: String,
    /// 1-based line of every face with at least 3 vertices, in file order (`tobj` keeps it).
    pub face_lines: Vec<usize>,
    /// `usemtl` names with their lines, to report names no MTL file defines.
    pub usemtl: Vec<(String, usize)>,
    /// Problems survived (ignored points and lines, two-vertex faces), each naming the file.
    pub warnings: Vec<String>,
}

/// Checks every vertex and face statement of `text` and returns the cleaned text. Errors name
/// `path` and the line: a vertex position that is not a finite number, a face index of 0 or
/// outside the elements defined before its line.
pub(super) fn scan(text: &str, path: &Path) -> Result<Scan, SceneError> {
    let mut out = Scan {
        text: String::with_capacity(text.len()),
        ..Scan::default()
    };
    // Elements defined so far: positions, texture coordinates, normals.
    let mut counts = [0usize; 3];
    let (mut points, mut lines) = (0usize, 0usize);
    let err = |line: usize, message: String| SceneError::Obj {
        path: path.to_path_buf(),
        message: format!("line {line}: {message}"),
    };
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let mut words = raw.split_whitespace();
        let keep = match words.next() {
            Some("v") => {
                let xyz: Vec<Option<f32>> = words.take(3).map(|w| w.parse().ok()).collect();
                if xyz.len() < 3 || xyz.iter().any(|c| !c.is_some_and(f32::is_finite)) {
                    return Err(err(
                        line,
                        format!("vertex position \"{raw}\" is not 3 finite numbers"),
                    ));
                }
                counts[0] += 1;
                true
            }
            Some("vt") => {
                counts[1] += 1;
                true
            }
            Some("vn") => {
                counts[2] += 1;
                true
            }
            Some("f") => {
                let corners: Vec<&str> = words.collect();
                for corner in &corners {
                    check_corner(corner, &counts).map_err(|m| err(line, m))?;
                }
                if corners.len() >= 3 {
                    out.face_lines.push(line);
                } else {
                    out.warnings.push(format!(
                        "{}: line {line}: face with {} vertices ignored",
                        path.display(),
                        corners.len()
                    ));
                }
                true
            }
            Some("usemtl") => {
                let name = raw
                    .trim()
                    .split_once(char::is_whitespace)
                    .map(|(_, n)| n.trim());
                if let Some(name) = name.filter(|n| !n.is_empty()) {
                    out.usemtl.push((name.to_string(), line));
                }
                true
            }
            Some("p") => {
                points += 1;
                false
            }
            Some("l") => {
                lines += 1;
                false
            }
            _ => true,
        };
        if !keep {
            out.text.push('#');
        }
        out.text.push_str(raw);
        out.text.push('\n');
    }
    if points + lines > 0 {
        out.warnings.push(format!(
            "{}: {points} point (p) and {lines} line (l) statements ignored: lumis renders only faces",
            path.display()
        ));
    }
    Ok(out)
}

/// Checks one face corner `v`, `v/vt`, `v//vn` or `v/vt/vn` against the element counts so far.
fn check_corner(corner: &str, counts: &[usize; 3]) -> Result<(), String> {
    const WHAT: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    let parts: Vec<&str> = corner.split('/').collect();
    if parts.len() > 3 || parts[0].is_empty() {
        return Err(format!(
            "face corner \"{corner}\" is not v, v/vt, v//vn or v/vt/vn"
        ));
    }
    for (k, part) in parts.iter().enumerate().filter(|(_, p)| !p.is_empty()) {
        let index: i64 = part
            .parse()
            .map_err(|_| format!("face corner \"{corner}\": \"{part}\" is not an integer"))?;
        let count = counts[k] as i64;
        // Positive indices count from 1; negative ones back from the last element defined.
        let ok = (1..=count).contains(&index) || (-count..=-1).contains(&index);
        if !ok {
            let why = if index == 0 {
                "OBJ indices start at 1".to_string()
            } else {
                format!("only {count} are defined before this line")
            };
            return Err(format!("face uses {} {index} ({why})", WHAT[k]));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_indices_name_the_line_and_points_lines_are_counted() {
        let p = Path::new("m.obj");
        let msg = |t: &str| scan(t, p).unwrap_err().to_string();
        let base = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
        assert!(msg(&format!("{base}f 0 1 2\n")).contains("line 4: face uses vertex 0"));
        assert!(msg(&format!("{base}f 1 2 4\n")).contains("line 4: face uses vertex 4 (only 3"));
        assert!(msg(&format!("{base}f -4 1 2\n")).contains("m.obj"));
        assert!(msg(&format!("{base}f 1/1 2 3\n")).contains("texture coordinate 1"));
        assert!(msg("v nan 0 0\n").contains("line 1: vertex position"));
        assert!(msg("v 1 2\n").contains("line 1"));
        let s = scan(&format!("{base}l 1 2 3\np 1\nf -3 -2 -1\nf 1 2\n"), p).unwrap();
        assert_eq!(s.face_lines, [6]);
        assert!(s.text.contains("#l 1 2 3"));
        assert_eq!(s.warnings.len(), 2, "{:?}", s.warnings);
        assert!(s.warnings[1].contains("1 point (p) and 1 line (l)"));
    }
}
