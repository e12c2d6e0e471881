//! The large OBJ and GLB files `lumis-lab load` times, generated on the spot (a displaced
//! grid) so the benchmark needs no data from anywhere, and the peak-memory reading.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

/// A displaced `n x n` quad grid: `2 n^2` triangles, positions and 0-based triangle indices.
pub fn grid(n: u32) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let mut positions = Vec::with_capacity(((n + 1) * (n + 1)) as usize);
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (i as f32 / n as f32, j as f32 / n as f32);
            positions.push([x, 0.05 * (17.0 * x).sin() * (13.0 * z).cos(), z]);
        }
    }
    let mut indices = Vec::with_capacity(2 * (n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            let (b, c, d) = (a + 1, a + n + 2, a + n + 1);
            indices.push([a, c, b]);
            indices.push([a, d, c]);
        }
    }
    (positions, indices)
}

/// Writes the grid as a Wavefront OBJ (`v` and `f` lines, 1-based).
pub fn write_obj(path: &Path, n: u32) -> std::io::Result<()> {
    let (positions, indices) = grid(n);
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    for p in &positions {
        writeln!(out, "v {} {} {}", p[0], p[1], p[2])?;
    }
    for t in &indices {
        writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1)?;
    }
    out.flush()
}

/// Writes the grid as a binary glTF (GLB): one node, one mesh, u32 indices.
pub fn write_glb(path: &Path, n: u32) -> std::io::Result<()> {
    let (positions, indices) = grid(n);
    let mut bin: Vec<u8> = Vec::with_capacity(positions.len() * 12 + indices.len() * 12);
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for p in &positions {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
            bin.extend_from_slice(&p[k].to_le_bytes());
        }
    }
    let index_offset = bin.len();
    for t in &indices {
        for i in t {
            bin.extend_from_slice(&i.to_le_bytes());
        }
    }
    let mut json = String::new();
    let _ = write!(
        json,
        r#"{{"asset":{{"version":"2.0","generator":"lumis-lab load"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],"buffers":[{{"byteLength":{bl}}}],"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":{pl},"target":34962}},{{"buffer":0,"byteOffset":{io},"byteLength":{il},"target":34963}}],"accessors":[{{"bufferView":0,"componentType":5126,"count":{pc},"type":"VEC3","min":[{},{},{}],"max":[{},{},{}]}},{{"bufferView":1,"componentType":5125,"count":{ic},"type":"SCALAR"}}]}}"#,
        lo[0],
        lo[1],
        lo[2],
        hi[0],
        hi[1],
        hi[2],
        bl = bin.len(),
        pl = index_offset,
        io = index_offset,
        il = bin.len() - index_offset,
        pc = positions.len(),
        ic = indices.len() * 3,
    );
    // Chunks are 4-byte aligned: JSON padded with spaces, BIN with zeros.
    while !json.len().is_multiple_of(4) {
        json.push(' ');
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    out.write_all(b"glTF")?;
    out.write_all(&2u32.to_le_bytes())?;
    out.write_all(&(total as u32).to_le_bytes())?;
    out.write_all(&(json.len() as u32).to_le_bytes())?;
    out.write_all(b"JSON")?;
    out.write_all(json.as_bytes())?;
    out.write_all(&(bin.len() as u32).to_le_bytes())?;
    out.write_all(b"BIN\0")?;
    out.write_all(&bin)?;
    out.flush()
}

/// This process's peak resident memory in bytes (Linux `VmHWM`), if the OS tells.
pub fn peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_counts_and_winding() {
        let (p, t) = grid(3);
        assert_eq!((p.len(), t.len()), (16, 18));
        // Counter-clockwise seen from +y: the face normal points up.
        let [a, b, c] = t[0].map(|i| glam::Vec3::from(p[i as usize]));
        assert!((b - a).cross(c - a).y > 0.0);
    }
}
