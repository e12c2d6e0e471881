//! Seeded scene generators: mixed sphere + triangle scenes, closed tessellated meshes and the
//! degenerate inputs a builder must survive (empty, one primitive, coincident centroids,
//! duplicate triangles, zero-thickness boxes).

use super::Rng;
use lumis_core::geometry::{Geometry, Mesh, Sphere};
use lumis_core::math::{Aabb, Vec3};
use std::collections::HashMap;

/// A mesh of independent triangles (no shared vertices).
pub fn soup(tris: &[[Vec3; 3]]) -> Mesh {
    let positions = tris.iter().flatten().copied().collect();
    let indices = (0..tris.len() as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    Mesh::new(positions, None, None, indices).expect("generated mesh is valid")
}

/// A random triangle with corners within `size` of `center`.
pub fn random_triangle(rng: &mut Rng, center: Vec3, size: f32) -> [Vec3; 3] {
    [(); 3].map(|_| center + rng.unit_vector() * rng.range(0.2, 1.0) * size)
}

/// Adds `spheres` spheres and `tris` triangles at positions from `place`, interleaved in chunks
/// so sphere and triangle primitive indices alternate (ties then cross primitive types).
fn add_mixed(
    g: &mut Geometry,
    rng: &mut Rng,
    spheres: usize,
    tris: usize,
    mut place: impl FnMut(&mut Rng) -> (Vec3, f32),
) {
    let chunks = 10;
    for c in 0..chunks {
        for _ in (c * spheres / chunks)..((c + 1) * spheres / chunks) {
            let (center, size) = place(rng);
            g.add_sphere(Sphere {
                center,
                radius: size,
            });
        }
        let t: Vec<_> = ((c * tris / chunks)..((c + 1) * tris / chunks))
            .map(|_| {
                let (center, size) = place(rng);
                random_triangle(rng, center, size * 2.0)
            })
            .collect();
        if !t.is_empty() {
            g.add_mesh(soup(&t));
        }
    }
}

/// Spheres and triangles spread uniformly in a 20-unit box.
pub fn uniform(seed: u64, spheres: usize, tris: usize) -> Geometry {
    let mut rng = Rng::new(seed);
    let mut g = Geometry::new();
    let b = Aabb::new(Vec3::splat(-10.0), Vec3::splat(10.0));
    add_mixed(&mut g, &mut rng, spheres, tris, |r| {
        (r.in_box(&b), r.range(0.05, 0.7))
    });
    g
}

/// Most primitives in a few tight clusters far apart, plus huge far outliers: the case where
/// binning over the centroid bounds puts a whole cluster in one bin.
pub fn clustered(seed: u64, spheres: usize, tris: usize) -> Geometry {
    let mut rng = Rng::new(seed);
    let mut g = Geometry::new();
    let centers: Vec<Vec3> = (0..4)
        .map(|_| rng.in_box(&Aabb::new(Vec3::splat(-30.0), Vec3::splat(30.0))))
        .collect();
    add_mixed(&mut g, &mut rng, spheres, tris, |r| {
        if r.chance(0.03) {
            (r.unit_vector() * r.range(500.0, 3000.0), r.range(1.0, 40.0))
        } else {
            let c = centers[r.below(centers.len())];
            (
                c + r.unit_vector() * r.range(0.0, 0.3),
                r.range(0.005, 0.05),
            )
        }
    });
    g
}

/// A closed UV sphere with pole vertices and a shared seam; `bump(unit_dir)` scales the radius.
pub fn uv_sphere(
    center: Vec3,
    radius: f32,
    rings: u32,
    segments: u32,
    bump: impl Fn(Vec3) -> f32,
) -> Mesh {
    let at = |d: Vec3| center + d * radius * bump(d);
    let mut p = vec![at(Vec3::Y), at(-Vec3::Y)];
    for i in 1..rings {
        let theta = std::f32::consts::PI * i as f32 / rings as f32;
        for j in 0..segments {
            let phi = std::f32::consts::TAU * j as f32 / segments as f32;
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            p.push(at(d));
        }
    }
    let v = |ring: u32, seg: u32| 2 + (ring - 1) * segments + seg % segments;
    let mut idx = Vec::new();
    for j in 0..segments {
        idx.push([0, v(1, j + 1), v(1, j)]);
        idx.push([1, v(rings - 1, j), v(rings - 1, j + 1)]);
    }
    for i in 1..rings - 1 {
        for j in 0..segments {
            let (a, b, c, d) = (v(i, j), v(i, j + 1), v(i + 1, j), v(i + 1, j + 1));
            idx.push([a, b, d]);
            idx.push([a, d, c]);
        }
    }
    Mesh::new(p, None, None, idx).expect("generated mesh is valid")
}

/// A closed icosphere of radius 1 at the origin, `subdiv` times subdivided, every vertex moved
/// radially by up to `jitter` (shared vertices move once, so the mesh stays closed).
pub fn icosphere(subdiv: u32, jitter: f32, rng: &mut Rng) -> Mesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut p: Vec<Vec3> = [
        (-1., t, 0.),
        (1., t, 0.),
        (-1., -t, 0.),
        (1., -t, 0.),
        (0., -1., t),
        (0., 1., t),
        (0., -1., -t),
        (0., 1., -t),
        (t, 0., -1.),
        (t, 0., 1.),
        (-t, 0., -1.),
        (-t, 0., 1.),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut idx: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdiv {
        // One midpoint vertex per edge, found by its sorted endpoint pair: keeps edges shared.
        let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, p: &mut Vec<Vec3>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                p.push(((p[a as usize] + p[b as usize]) * 0.5).normalize());
                p.len() as u32 - 1
            })
        };
        idx = idx
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = (
                    midpoint(a, b, &mut p),
                    midpoint(b, c, &mut p),
                    midpoint(c, a, &mut p),
                );
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    for v in &mut p {
        *v *= 1.0 + rng.range(-jitter, jitter);
    }
    Mesh::new(p, None, None, idx).expect("generated mesh is valid")
}

/// A tessellated scene: a bumpy closed UV sphere, a gently displaced grid below it (shared
/// edges everywhere) and a few spheres poking through both.
pub fn tessellated(seed: u64) -> Geometry {
    let mut rng = Rng::new(seed);
    let mut g = Geometry::new();
    g.add_mesh(uv_sphere(Vec3::ZERO, 2.0, 24, 40, |d| {
        1.0 + 0.05 * (7.0 * d.x).sin() * (5.0 * d.z).cos()
    }));
    let n = 30u32;
    let mut p = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            let (x, z) = (
                i as f32 / n as f32 * 8.0 - 4.0,
                j as f32 / n as f32 * 8.0 - 4.0,
            );
            p.push(Vec3::new(x, -2.2 + 0.1 * (x * 2.0).sin() * z.cos(), z));
        }
    }
    let v = |i: u32, j: u32| i * (n + 1) + j;
    let idx = (0..n)
        .flat_map(|i| {
            (0..n).flat_map(move |j| {
                [
                    [v(i, j), v(i + 1, j), v(i + 1, j + 1)],
                    [v(i, j), v(i + 1, j + 1), v(i, j + 1)],
                ]
            })
        })
        .collect();
    g.add_mesh(Mesh::new(p, None, None, idx).expect("grid is valid"));
    for _ in 0..12 {
        let c = rng.in_box(&Aabb::new(
            Vec3::new(-3.0, -2.5, -3.0),
            Vec3::new(3.0, 2.5, 3.0),
        ));
        g.add_sphere(Sphere {
            center: c,
            radius: rng.range(0.1, 0.8),
        });
    }
    g
}

/// No primitives at all.
pub fn empty() -> Geometry {
    Geometry::new()
}

/// A lone sphere.
pub fn single_sphere() -> Geometry {
    let mut g = Geometry::new();
    g.add_sphere(Sphere {
        center: Vec3::new(0.5, -0.25, 1.0),
        radius: 0.75,
    });
    g
}

/// A lone triangle.
pub fn single_triangle() -> Geometry {
    let mut g = Geometry::new();
    g.add_mesh(soup(&[[
        Vec3::new(-1.0, -1.0, 0.5),
        Vec3::new(1.5, -0.5, 0.0),
        Vec3::new(0.0, 1.0, -0.5),
    ]]));
    g
}

/// Concentric spheres and triangles whose boxes are all centred exactly at the origin: no
/// centroid split exists. Triangle corners are multiples of 1/8, so centring them is exact.
pub fn same_centroid(seed: u64) -> Geometry {
    let mut rng = Rng::new(seed);
    let mut g = Geometry::new();
    let q = |r: &mut Rng| {
        Vec3::new(r.below(33) as f32, r.below(33) as f32, r.below(33) as f32) / 8.0 - 2.0
    };
    let tris: Vec<[Vec3; 3]> = (0..60)
        .map(|_| {
            let t = [q(&mut rng), q(&mut rng), q(&mut rng)];
            let c = Aabb::from_points(t).center();
            t.map(|p| p - c)
        })
        .collect();
    for (i, chunk) in tris.chunks(15).enumerate() {
        g.add_mesh(soup(chunk));
        for k in 0..10 {
            g.add_sphere(Sphere {
                center: Vec3::ZERO,
                radius: 0.1 + 0.05 * (i * 10 + k) as f32,
            });
        }
    }
    g
}

/// Groups of coincident triangles (identical corners, identical order, so identical `t` bits)
/// scattered over several meshes between filler triangles, plus copies with rotated corner
/// order and flipped winding. Returns the scene and each exact-duplicate group's indices.
pub fn duplicates(seed: u64) -> (Geometry, Vec<Vec<u32>>) {
    let mut rng = Rng::new(seed);
    let base: Vec<[Vec3; 3]> = (0..40)
        .map(|_| {
            let c = rng.in_box(&Aabb::new(Vec3::splat(-3.0), Vec3::splat(3.0)));
            random_triangle(&mut rng, c, 0.8)
        })
        .collect();
    let mut g = Geometry::new();
    let mut groups = vec![Vec::new(); base.len()];
    for copy in 0..5 {
        // Shuffle the placement so the lowest index of a group is not always visited first.
        let mut order: Vec<usize> = (0..base.len()).collect();
        for i in (1..order.len()).rev() {
            order.swap(i, rng.below(i + 1));
        }
        let mut tris = Vec::new();
        let first = g.prims().len() as u32;
        for &b in &order {
            groups[b].push(first + tris.len() as u32);
            tris.push(base[b]);
            let c = rng.in_box(&Aabb::new(Vec3::splat(-3.0), Vec3::splat(3.0)));
            tris.push(random_triangle(&mut rng, c, 0.3));
        }
        g.add_mesh(soup(&tris));
        if copy == 2 {
            let [a, b, c] = [0, 1, 2];
            let rotated: Vec<_> = base.iter().map(|t| [t[b], t[c], t[a]]).collect();
            let flipped: Vec<_> = base.iter().map(|t| [t[a], t[c], t[b]]).collect();
            g.add_mesh(soup(&rotated));
            g.add_mesh(soup(&flipped));
        }
    }
    (g, groups)
}

/// Axis-aligned flat triangles (boxes of zero thickness) in a few shared planes, overlapping
/// each other, with corners on a 1/4 grid so rays can run exactly along their edges.
pub fn flat_axis_aligned(seed: u64) -> Geometry {
    let mut rng = Rng::new(seed);
    let mut tris = Vec::new();
    for _ in 0..150 {
        let axis = rng.below(3);
        let plane = rng.below(5) as f32 - 2.0;
        let mut corner = || {
            let mut p = Vec3::new(
                rng.below(17) as f32 / 4.0 - 2.0,
                rng.below(17) as f32 / 4.0 - 2.0,
                rng.below(17) as f32 / 4.0 - 2.0,
            );
            p[axis] = plane;
            p
        };
        let t = [corner(), corner(), corner()];
        tris.push(t);
    }
    let mut g = Geometry::new();
    g.add_mesh(soup(&tris));
    g
}
