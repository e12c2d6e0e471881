//! The fuzzed scene: spheres and triangles in primitive order, the lumis `Geometry` built from
//! them through the public API, and both written out as Rust a failure report can be pasted
//! from.

use lumis_core::geometry::{Geometry, Mesh, Sphere};
use lumis_core::math::{Aabb, Ray, Vec3};
use lumis_core::scene::limits::check_bounds;

/// One primitive as decoded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Prim {
    /// `Geometry::add_sphere`.
    Sphere { center: Vec3, radius: f32 },
    /// A triangle of a mesh.
    Triangle([Vec3; 3]),
}

impl Prim {
    /// The world-space box the scene limits are checked on (a sphere's as lumis rounds it).
    fn bounds(&self) -> Aabb {
        match *self {
            Prim::Sphere { center, radius } => Sphere { center, radius }.bounds(),
            Prim::Triangle(p) => Aabb::from_points(p),
        }
    }

    /// True when the scene builder would accept it: finite, a positive radius (as every
    /// loader requires), and the bounds within `MAX_COORDINATE`.
    fn accepted(&self) -> bool {
        let finite = match self {
            Prim::Sphere { center, radius } => {
                center.is_finite() && radius.is_finite() && *radius > 0.0
            }
            Prim::Triangle(p) => p.iter().all(|v| v.is_finite()),
        };
        finite && check_bounds(&self.bounds()).is_ok()
    }
}

/// The accepted primitives (index = lumis primitive index) and their geometry.
pub struct Scene {
    /// In primitive-index order.
    pub prims: Vec<Prim>,
    /// Built from `prims`: each run of consecutive triangles is one mesh.
    pub geometry: Geometry,
}

impl Scene {
    /// The scene of the primitives the API accepts (the others are left out, as a loader
    /// would refuse them); `None` when none is left.
    pub fn build(prims: &[Prim]) -> Option<Scene> {
        let prims: Vec<Prim> = prims.iter().copied().filter(Prim::accepted).collect();
        if prims.is_empty() {
            return None;
        }
        let mut geometry = Geometry::new();
        for run in runs(&prims) {
            match run {
                [Prim::Sphere { center, radius }] => {
                    geometry.add_sphere(Sphere {
                        center: *center,
                        radius: *radius,
                    });
                }
                tris => {
                    let (positions, indices) = shared_vertices(tris);
                    let mesh = Mesh::new(positions, None, None, indices)
                        .expect("finite positions and valid indices");
                    geometry.add_mesh(mesh);
                }
            }
        }
        Some(Scene { prims, geometry })
    }

    /// Rust statements that rebuild this geometry as `g`.
    pub fn literal(&self) -> String {
        let mut s = String::from("let mut g = Geometry::new();\n");
        for run in runs(&self.prims) {
            match run {
                [Prim::Sphere { center, radius }] => s.push_str(&format!(
                    "g.add_sphere(Sphere {{ center: {}, radius: {} }});\n",
                    vec_lit(*center),
                    f32_lit(*radius)
                )),
                tris => {
                    let (positions, indices) = shared_vertices(tris);
                    s.push_str("g.add_mesh(Mesh::new(vec![\n");
                    for p in positions {
                        s.push_str(&format!("    {},\n", vec_lit(p)));
                    }
                    s.push_str(&format!("], None, None, vec!{indices:?}).unwrap());\n"));
                }
            }
        }
        s
    }
}

/// Maximal runs of triangles, and each sphere alone, in order.
fn runs(prims: &[Prim]) -> Vec<&[Prim]> {
    let mut out = Vec::new();
    let mut start = 0;
    for i in 1..=prims.len() {
        let split = i == prims.len()
            || matches!(prims[i], Prim::Sphere { .. })
            || matches!(prims[i - 1], Prim::Sphere { .. });
        if split {
            out.push(&prims[start..i]);
            start = i;
        }
    }
    out
}

/// One vertex per distinct position (bit for bit), so triangles the decoder made share
/// vertices share indices too, as a loaded mesh's do.
fn shared_vertices(tris: &[Prim]) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut positions: Vec<Vec3> = Vec::new();
    let mut index = |p: Vec3| {
        let bits = p.to_array().map(f32::to_bits);
        let found = positions
            .iter()
            .position(|q| q.to_array().map(f32::to_bits) == bits);
        found.unwrap_or_else(|| {
            positions.push(p);
            positions.len() - 1
        }) as u32
    };
    let indices = tris
        .iter()
        .map(|t| match t {
            Prim::Triangle(p) => p.map(&mut index),
            Prim::Sphere { .. } => unreachable!("runs of triangles only"),
        })
        .collect();
    (positions, indices)
}

/// An `f32` as Rust that reproduces it bit for bit, with its value for the reader.
pub fn f32_lit(x: f32) -> String {
    if x.is_finite() {
        format!("f32::from_bits({:#010x}) /* {x:e} */", x.to_bits())
    } else {
        format!("f32::from_bits({:#010x}) /* {x} */", x.to_bits())
    }
}

/// A `Vec3` as Rust that reproduces it bit for bit.
pub fn vec_lit(v: Vec3) -> String {
    format!(
        "Vec3::new({}, {}, {})",
        f32_lit(v.x),
        f32_lit(v.y),
        f32_lit(v.z)
    )
}

/// A `Ray` as Rust that reproduces it bit for bit.
pub fn ray_lit(r: &Ray) -> String {
    format!(
        "let ray = Ray {{\n    origin: {},\n    dir: {},\n    t_min: {},\n    t_max: {},\n}};\n",
        vec_lit(r.origin),
        vec_lit(r.dir),
        f32_lit(r.t_min),
        f32_lit(r.t_max)
    )
}
