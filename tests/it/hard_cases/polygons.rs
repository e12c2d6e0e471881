//! OBJ faces that have real area must survive loading, however thin or far from the origin:
//! only faces whose area is exactly zero (decided by the rational oracle in [`super::exact`],
//! never by lumis's own predicates) may be dropped, and those with a `file:line` warning.
//! Every case loads OBJ text through `lumis_io::formats::obj::load_obj` and shoots rays, aimed by the
//! oracle at face interiors, through every accelerator x traversal ([`super::harness`]).

use std::collections::HashMap;
use std::path::Path;

use super::exact::{ExactHit, Q, V, exact_to_f64, ray_triangle, triangle_is_degenerate};
use super::harness::Everywhere;
use lumis_core::geometry::Geometry;
use lumis_core::math::{Ray, Vec3};
use lumis_io::formats::obj::{ObjModel, load_obj};
use num_traits::{Signed, Zero};

/// The OBJ text `obj` loaded as if read from `name`, without materials.
fn load(obj: &str, name: &str) -> ObjModel {
    load_obj(obj.as_bytes(), Path::new(name), None).unwrap_or_else(|e| panic!("{e:#?}"))
}

/// Every object's mesh in one geometry.
fn geometry(model: &ObjModel) -> Geometry {
    let mut g = Geometry::new();
    for o in &model.objects {
        g.add_mesh(o.mesh.clone());
    }
    g
}

/// Every loaded triangle's corners, in primitive order.
fn triangles(g: &Geometry) -> Vec<[Vec3; 3]> {
    g.meshes()
        .iter()
        .flat_map(|m| (0..m.triangle_count() as u32).map(move |t| m.corners(t)))
        .collect()
}

/// OBJ text: `v` lines for `points`, then one `f` line per face (indices into `points`).
fn obj_text(points: &[Vec3], faces: &[Vec<usize>]) -> String {
    let mut s = String::new();
    for p in points {
        // `{}` prints the shortest decimal that reads back as the same f32.
        s += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    for f in faces {
        let idx: Vec<String> = f.iter().map(|i| (i + 1).to_string()).collect();
        s += &format!("f {}\n", idx.join(" "));
    }
    s
}

/// A ray from off the triangle's plane through its centroid, and the oracle's exact hit. The
/// origin and direction are rounded to f32, so the oracle re-decides where the actual ray
/// lands; it must land strictly inside (not on an edge) for the case to count.
fn aim(tri: [Vec3; 3], dist: f64) -> (Ray, ExactHit) {
    let [a, b, c] = tri.map(|p| p.as_dvec3());
    let centre = (a + b + c) / 3.0;
    let n = (b - a).cross(c - a).normalize();
    let origin = (centre + n * dist).as_vec3();
    let dir = (centre - origin.as_dvec3()).as_vec3();
    let hit = ray_triangle(origin, dir, tri).expect("the oracle sees the aimed ray hit");
    assert!(
        !hit.on_boundary() && hit.t.is_positive(),
        "aimed at an edge"
    );
    (Ray::new(origin, dir), hit)
}

/// Shoots `ray` through every configuration; the hit must be at the oracle's `t` (to a few
/// f32 ulps) on a loaded triangle for which `on_face` holds.
fn assert_hits(
    everywhere: &Everywhere,
    ray: &Ray,
    exact: &ExactHit,
    on_face: impl Fn([Vec3; 3]) -> bool,
) {
    let hit = everywhere
        .closest(ray)
        .unwrap_or_else(|| panic!("{ray:?} leaks through"));
    let want = exact_to_f64(&exact.t);
    assert!(
        (hit.hit.t as f64 - want).abs() <= 1e-5 * want,
        "t = {} but the oracle says {want}",
        hit.hit.t
    );
    let lumis_core::geometry::Primitive::Triangle { mesh, tri } =
        everywhere.geometry.prims()[hit.prim as usize]
    else {
        panic!("not a triangle");
    };
    let corners = everywhere.geometry.meshes()[mesh as usize].corners(tri);
    assert!(on_face(corners), "hit {corners:?}, not the aimed face");
}

/// Exact vector area (times 2) of a polygon: the sum of `p_i x p_(i+1)`.
fn polygon_area2(points: &[Vec3]) -> V {
    let zero = V([Q::zero(), Q::zero(), Q::zero()]);
    (0..points.len()).fold(zero, |acc, i| {
        let (a, b) = (V::of(points[i]), V::of(points[(i + 1) % points.len()]));
        acc.add(&a.cross(&b))
    })
}

/// Exact `(b - a) x (c - a)`.
fn tri_area2([a, b, c]: [Vec3; 3]) -> V {
    let [a, b, c] = [a, b, c].map(V::of);
    b.sub(&a).cross(&c.sub(&a))
}

/// The triangles of `tris` cover the polygon `points` exactly: their vector areas sum to the
/// polygon's in rationals, and each has nonzero area winding with the polygon.
fn assert_covers(points: &[Vec3], tris: &[[Vec3; 3]], what: &str) {
    let want = polygon_area2(points);
    let zero = V([Q::zero(), Q::zero(), Q::zero()]);
    let got = tris.iter().fold(zero, |acc, t| acc.add(&tri_area2(*t)));
    assert_eq!(
        got, want,
        "{what}: triangle areas do not add up to the polygon's"
    );
    for t in tris {
        assert!(
            tri_area2(*t).dot(&want).is_positive(),
            "{what}: {t:?} is empty or winds backwards"
        );
    }
}

/// The f32 spacing in the binade of `m`: multiples of it there are exact f32s.
fn ulp(m: f64) -> f64 {
    2f64.powi(m.abs().log2().floor() as i32 - 23)
}

/// The odd multiple of `ulp(c)` nearest `c`: sums of two such coordinates are not f32s, so
/// lumis's old f32 arithmetic on absolute coordinates rounded there.
fn odd(c: f64) -> f64 {
    let u = ulp(c);
    let k = (c / u).round();
    (if k % 2.0 == 0.0 { k + 1.0 } else { k }) * u
}

#[test]
fn issue_sliver_1000_by_0_001_is_kept_and_hit_at_t_1() {
    let model = load(
        "v 0 0 0\nv 1000 0 0\nv 1000 0.001 0\nf 1 2 3\n",
        "sliver.obj",
    );
    let g = geometry(&model);
    let tris = triangles(&g);
    assert_eq!(tris.len(), 1, "{:?}", model.warnings);
    assert!(!triangle_is_degenerate(tris[0]));
    let (o, d) = (Vec3::new(500.0, 0.0002, 1.0), Vec3::new(0.0, 0.0, -1.0));
    let exact = ray_triangle(o, d, tris[0]).expect("oracle: the ray hits the sliver");
    assert!(exact.t == super::exact::q(1.0) && !exact.on_boundary());
    let hit = Everywhere::new(&g).closest(&Ray::new(o, d)).expect("hit");
    assert_eq!(hit.hit.t, 1.0);
}

#[test]
fn far_triangle_of_area_1e_3_is_kept_and_hit_inside() {
    // The report's size of triangle, and one 50 long and one f32 spacing (1.2e-4) high that
    // the old f32 Newell test called zero area.
    let text = "v 148376 1235 -223423\nv 148376.05 1235.02 -223423\n\
                v 148376 1235.05 -223422.98\nf 1 2 3\n\
                v 148376 1235 -223423\nv 148425 1235 -223398.5\n\
                v 148400.5 1235.0001 -223410.75\nf 4 5 6\n";
    let model = load(text, "far.obj");
    let g = geometry(&model);
    let tris = triangles(&g);
    assert_eq!(tris.len(), 2, "{:?}", model.warnings);
    let everywhere = Everywhere::new(&g);
    for (tri, areas) in tris.iter().zip([1e-3..1.5e-3, 3e-3..4e-3]) {
        let area2 = tri_area2(*tri);
        let area = exact_to_f64(&area2.dot(&area2)).sqrt() / 2.0;
        assert!(areas.contains(&area), "area {area}");
        for dist in [0.01, 1.0, 100.0] {
            let (ray, exact) = aim(*tri, dist);
            assert_hits(&everywhere, &ray, &exact, |t| t == *tri);
        }
    }
}

/// A closed box of `cells` lattice cells of size `steps` from the corner `base` (all exact
/// f32s); faces alternate between quads and pairs of triangles, all wound outward.
fn lattice_box(base: [f64; 3], cells: [usize; 3], steps: [f64; 3]) -> (Vec<Vec3>, Vec<Vec<usize>>) {
    let mut index: HashMap<[usize; 3], usize> = HashMap::new();
    let mut points = Vec::new();
    let mut vertex = |l: [usize; 3]| {
        *index.entry(l).or_insert_with(|| {
            let p = [0, 1, 2].map(|k| base[k] + l[k] as f64 * steps[k]);
            points.push(Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32));
            points.len() - 1
        })
    };
    let mut faces = Vec::new();
    for a in 0..3 {
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        for side in [0, cells[a]] {
            for i in 0..cells[b] {
                for j in 0..cells[c] {
                    let corner = |di: usize, dj: usize| {
                        let mut l = [0; 3];
                        (l[a], l[b], l[c]) = (side, i + di, j + dj);
                        l
                    };
                    // Counter-clockwise seen from +a; reversed on the low side.
                    let mut f: Vec<usize> = [(0, 0), (1, 0), (1, 1), (0, 1)]
                        .map(|(di, dj)| vertex(corner(di, dj)))
                        .to_vec();
                    if side == 0 {
                        f.reverse();
                    }
                    if (i + j) % 2 == 0 {
                        faces.push(f);
                    } else {
                        faces.push(vec![f[0], f[1], f[2]]);
                        faces.push(vec![f[0], f[2], f[3]]);
                    }
                }
            }
        }
    }
    (points, faces)
}

#[test]
fn far_closed_box_of_ulp_thin_faces_keeps_every_face_and_has_no_leaks() {
    for s in [1e4, 1e5, 1e6, 1e7] {
        // Cells 400 long in x, one f32 spacing high in y (at y = 1235: 1.2e-4) and 8 deep in z:
        // the x-y faces are slivers 3.3e6 times longer than high, 1e4..1e7 from the origin.
        let base = [odd(s), odd(1235.0), odd(-0.37 * s)];
        let steps = [400.0, ulp(1235.0), 8.0 * ulp(base[2])];
        let (points, faces) = lattice_box(base, [4, 2, 3], steps);
        let model = load(&obj_text(&points, &faces), "box.obj");
        let g = geometry(&model);
        let loaded = triangles(&g);
        assert!(loaded.iter().all(|t| t.iter().all(|p| points.contains(p))));
        // Oracle: a face keeps n - 2 triangles when no three of its corners are collinear.
        let mut want = 0;
        for f in &faces {
            let c: Vec<Vec3> = f.iter().map(|&i| points[i]).collect();
            let triples = (0..c.len()).map(|k| [c[k], c[(k + 1) % c.len()], c[(k + 2) % c.len()]]);
            let triples: Vec<bool> = triples.map(triangle_is_degenerate).collect();
            assert!(
                triples.iter().all(|d| !d),
                "the lattice has no collinear corners"
            );
            want += c.len() - 2;
        }
        assert_eq!(loaded.len(), want, "s = {s}: {:?}", model.warnings);
        let everywhere = Everywhere::new(&g);
        for f in &faces {
            let tri = [0, 1, 2].map(|k| points[f[k]]);
            // Axis-aligned faces: the axis where all three corners agree is the face's.
            let axis = (0..3)
                .find(|&k| tri.iter().all(|p| p[k] == tri[0][k]))
                .unwrap();
            let (ray, exact) = aim(tri, 8.0 * ulp(s));
            assert_hits(&everywhere, &ray, &exact, |t| {
                t.iter().all(|p| p[axis] == tri[0][axis])
            });
        }
    }
}

#[test]
fn exactly_degenerate_faces_are_dropped_with_file_and_line_and_near_ones_kept() {
    let (x, y) = (1.0e7f32, -2.5e6f32);
    let points = [
        Vec3::new(x, y, 4.0),
        Vec3::new(x + 2.0, y + 4.0, 8.0),
        Vec3::new(x + 4.0, y + 8.0, 12.0),
        Vec3::new(x + 6.0, y + 12.0, 16.0),
        // One ulp off the line through the first three.
        Vec3::new(x + 4.0, y + 8.0, 12.0f32.next_up()),
    ];
    let faces = [
        vec![0, 1, 4],    // line 6: nearly collinear, real area: kept
        vec![0, 1, 2],    // line 7: exactly collinear
        vec![0, 0, 3],    // line 8: coincident corners
        vec![0, 1, 2, 3], // line 9: a collinear quad
        vec![2, 2, 2],    // line 10: one point
    ];
    let model = load(&obj_text(&points, &faces), "flat.obj");
    for (k, f) in faces.iter().enumerate() {
        let c: Vec<Vec3> = f.iter().map(|&i| points[i]).collect();
        let degenerate = (1..c.len() - 1).all(|j| triangle_is_degenerate([c[0], c[j], c[j + 1]]));
        let note = format!("flat.obj: line {}: ", k + 6);
        let warned = model.warnings.iter().any(|w| w.contains(&note));
        assert_eq!(warned, degenerate, "face {k}: {:?}", model.warnings);
    }
    let g = geometry(&model);
    assert_eq!(triangles(&g), [[points[0], points[1], points[4]]]);
}

#[test]
fn far_sliver_ngons_keep_their_exact_area() {
    // Exactly planar (z constant) polygons 400 long and one or two f32 spacings of y thin
    // (1.2e-4 at y = 1235), 2.7e5 from the origin: 6e-7 times thinner than long.
    let (x0, y0, z) = (odd(148376.0), odd(1235.0), odd(-223423.0) as f32);
    let (ux, uy) = (ulp(x0), ulp(y0));
    let at = |i: f64, j: f64| Vec3::new((x0 + i * ux) as f32, (y0 + j * uy) as f32, z);
    let n = 400.0 / ux;
    let quad = vec![at(0., 0.), at(n, 0.), at(n, 1.), at(0., 1.)];
    let skew = vec![
        at(0., 0.),
        at(0.75 * n, 1.),
        at(0.75 * n + 1., 2.),
        at(1., 1.),
    ];
    // A comb: a long bottom edge (with collinear vertices on it), a zigzag top 1 and 2 high.
    let mut comb: Vec<Vec3> = (0..=8).map(|i| at(i as f64 * n / 8.0, 0.)).collect();
    comb.extend(
        (0..=16)
            .rev()
            .map(|i| at(i as f64 * n / 16.0, 1.0 + (i % 2) as f64)),
    );
    let ccw = comb.clone();
    comb.reverse();
    let polygons = [quad, skew, ccw, comb];
    let mut text = String::new();
    let mut base = 0;
    for (k, p) in polygons.iter().enumerate() {
        text += &format!("o poly{k}\n");
        text += &obj_text(p, &[]);
        let idx: Vec<String> = (0..p.len()).map(|i| (base + i + 1).to_string()).collect();
        text += &format!("f {}\n", idx.join(" "));
        base += p.len();
    }
    let model = load(&text, "slivers.obj");
    assert_eq!(model.objects.len(), polygons.len(), "{:?}", model.warnings);
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    for (k, (p, o)) in polygons.iter().zip(&model.objects).enumerate() {
        let tris: Vec<[Vec3; 3]> = (0..o.mesh.triangle_count() as u32)
            .map(|t| o.mesh.corners(t))
            .collect();
        assert_covers(p, &tris, &format!("polygon {k}"));
    }
}

#[test]
fn coplanar_overlapping_faces_are_all_kept_and_hit() {
    let (x0, y0, z) = (odd(-148376.0), odd(223423.0), odd(1235.0) as f32);
    let u = ulp(y0);
    let at = |i: f64, j: f64| Vec3::new((x0 + i * u) as f32, (y0 + j * u) as f32, z);
    let points = [
        at(0., 0.),
        at(8., 0.),
        at(8., 2.),
        at(0., 2.),
        at(4., 0.),
        at(12., 0.),
        at(12., 2.),
        at(4., 2.),
    ];
    // Two overlapping quads and a copy of the first's triangle wound the other way.
    let faces = [vec![0, 1, 2, 3], vec![4, 5, 6, 7], vec![0, 2, 1]];
    let model = load(&obj_text(&points, &faces), "overlap.obj");
    let g = geometry(&model);
    assert_eq!(triangles(&g).len(), 2 + 2 + 1, "{:?}", model.warnings);
    let everywhere = Everywhere::new(&g);
    for tri in [[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7], [1, 2, 4]] {
        let tri = tri.map(|k| points[k]);
        let (ray, exact) = aim(tri, 16.0 * u);
        assert_hits(&everywhere, &ray, &exact, |t| t.iter().all(|p| p.z == z));
    }
}

#[test]
fn convex_5000_gon_and_star_2000_gon_are_ear_clipped_covering_their_area() {
    let ngon = |n: usize, radius: &dyn Fn(usize) -> f64| -> Vec<Vec3> {
        (0..n)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / n as f64;
                let r = radius(k);
                Vec3::new((r * a.cos()) as f32, (r * a.sin()) as f32, 5.0)
            })
            .collect()
    };
    let convex = ngon(5000, &|_| 1.0);
    let star = ngon(2000, &|k| if k % 2 == 0 { 1.0 } else { 0.6 });
    for (name, p) in [("convex", &convex), ("star", &star)] {
        // Oracle: the convex one really is strictly convex in f32 (every turn is left).
        if name == "convex" {
            let n = p.len();
            assert!(
                (0..n).all(|i| {
                    tri_area2([p[i], p[(i + 1) % n], p[(i + 2) % n]]).0[2].is_positive()
                })
            );
        }
        let model = load(&obj_text(p, &[(0..p.len()).collect()]), "big.obj");
        assert!(model.warnings.is_empty(), "{name}: {:?}", model.warnings);
        let g = geometry(&model);
        let tris = triangles(&g);
        assert_eq!(tris.len(), p.len() - 2, "{name}");
        assert_covers(p, &tris, name);
    }
}
