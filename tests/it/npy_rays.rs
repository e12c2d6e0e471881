//! The `.npy` ray files `lumis hits --rays` reads, written for tests.

use npyz::WriterBuilder;
use std::path::Path;

/// Writes rays (origin xyz, direction xyz, t_min, t_max) as the `(N, 8)` float32 `.npy` array.
pub fn write_rays(path: &Path, rays: &[[f32; 8]]) {
    let mut bytes = Vec::new();
    let mut w = npyz::WriteOptions::<f32>::new()
        .default_dtype()
        .shape(&[rays.len() as u64, 8])
        .writer(&mut bytes)
        .begin_nd()
        .unwrap();
    w.extend(rays.iter().flatten().copied()).unwrap();
    w.finish().unwrap();
    std::fs::write(path, bytes).unwrap();
}
