//! glTF placements as instances (`tools/lumis_tools/gltf_instancing_assets.py` documents the
//! assets): a mesh placed by several nodes and `EXT_mesh_gpu_instancing` nodes load as
//! instances of one prototype, with the object names their flattened copies get; instanced and
//! flattened renders agree but on silhouettes; given pixels show the instance that the file's
//! transforms (mirrors, non-uniform scales, parents, quantised rotations) put there.
//! Broken extension data is refused naming the element: `gltf_instancing_bad`.

use crate::common;

use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::film::Film;
use lumis_core::scene::Scene;
use lumis_io::formats::{self, LoadOptions};

use common::files::gltf_asset as asset;

fn load(name: &str, flatten_instances: bool) -> Scene {
    let options = LoadOptions {
        flatten_instances,
        ..LoadOptions::default()
    };
    formats::load_with(&asset(name), &options).unwrap_or_else(|e| panic!("{name}: {e:#}"))
}

/// The assets' orthographic camera spans x in [-8, 8], y in [-4, 4]: 20 pixels a unit.
const SIZE: (u32, u32) = (320, 160);

fn render(scene: Scene) -> Film {
    common::render::film(scene, SIZE, AccelKind::Sah, &BuildOptions::default())
}

/// The pixel whose footprint holds world point (x, y) on the camera's plane.
fn pixel(x: f32, y: f32) -> usize {
    let col = ((x + 8.0) / 16.0 * SIZE.0 as f32).floor() as usize;
    let row = ((4.0 - y) / 8.0 * SIZE.1 as f32).floor() as usize;
    row * SIZE.0 as usize + col
}

/// The object seen at world (x, y) (`None`: the background) and its colour.
fn seen(scene: &Scene, film: &Film, x: f32, y: f32) -> (Option<String>, [f32; 3]) {
    let i = pixel(x, y);
    let id = film.aov()[i].object_id;
    let name = (id >= 0).then(|| scene.objects()[id as usize].name.clone());
    let c = film.rgba()[i];
    (name, [c.x, c.y, c.z])
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Colour {
    Red,
    Blue,
    Green,
}

/// The channel that dominates `c` by a factor of 2 (the assets' materials are 0.8 in one
/// channel, at most 0.2 in the others for red and blue, 0.7 and 0.2 for green).
fn colour(c: [f32; 3]) -> Option<Colour> {
    let [r, g, b] = c;
    if r > 2.0 * g.max(b) {
        Some(Colour::Red)
    } else if b > 2.0 * r.max(g) {
        Some(Colour::Blue)
    } else if g > 2.0 * r.max(b) {
        Some(Colour::Green)
    } else {
        None
    }
}

/// Asserts what is seen at each `(x, y, object, colour)`; `None` object: the background.
fn assert_seen(
    name: &str,
    scene: &Scene,
    film: &Film,
    expected: &[(f32, f32, Option<&str>, Option<Colour>)],
) {
    for &(x, y, object, col) in expected {
        let (got, c) = seen(scene, film, x, y);
        assert_eq!(got.as_deref(), object, "{name} at ({x}, {y})");
        match col {
            Some(col) => assert_eq!(colour(c), Some(col), "{name} at ({x}, {y}): {c:?}"),
            None => assert_eq!(c, [0.0; 3], "{name} at ({x}, {y}): background expected"),
        }
    }
}

#[test]
fn shared_meshes_and_gpu_instances_load_as_instances_named_as_their_flattened_copies() {
    // (file, instances, objects, an object each mode must have)
    let cases = [
        ("shared_meshes.gltf", 4, 9, "mirrored/1"),
        ("gpu_instancing.gltf", 58, 116, "swarm/49/1"),
        ("instancing.gltf", 3, 3, "cube+3"),
        ("hierarchy.gltf", 2, 2, "mirrored"),
    ];
    for (file, instances, objects, name) in cases {
        let inst = load(file, false);
        let flat = load(file, true);
        let g = inst.geometry();
        assert_eq!(g.instances().len(), instances, "{file}");
        assert_eq!(g.prototypes().len(), 1, "{file}");
        assert_eq!(flat.geometry().instances().len(), 0, "{file}");
        assert_eq!(flat.geometry().prototypes().len(), 0, "{file}");
        let names = |s: &Scene| -> Vec<(String, u32)> {
            s.objects()
                .iter()
                .map(|o| (o.name.clone(), o.material))
                .collect()
        };
        assert_eq!(names(&inst).len(), objects, "{file}");
        // Same names, same materials, same order: Cryptomatte mattes do not change.
        assert_eq!(names(&inst), names(&flat), "{file}");
        assert!(inst.objects().iter().any(|o| o.name == name), "{file}");
        assert!(inst.warnings().is_empty(), "{file}: {:?}", inst.warnings());
    }
    // The mesh placed once stays flattened beside the instances: 12 triangles of its own.
    let s = load("shared_meshes.gltf", false);
    assert_eq!(s.geometry().meshes().len(), 1);
    assert_eq!(s.geometry().meshes()[0].triangle_count(), 12);
    // The mirrored node's instance keeps its mirror (negative determinant) as a transform.
    let mirrors: Vec<bool> = s
        .geometry()
        .instances()
        .iter()
        .map(|i| i.placement.mirrors())
        .collect();
    assert_eq!(mirrors, [false, true, false, false]);
}

/// Compares instanced and flattened renders of `file`: returns the share of pixels within
/// 1e-3 relative and the largest difference off silhouettes.
fn compare_modes(file: &str) -> (f64, f32, f32) {
    let inst = render(load(file, false));
    let flat = render(load(file, true));
    let w = SIZE.0 as usize;
    let ids: Vec<i32> = flat.aov().iter().map(|a| a.object_id).collect();
    // A silhouette pixel: its object, or a 4-neighbour's, differs (where the two modes may
    // see a neighbouring surface through the transforms' rounding).
    let silhouette = |i: usize| {
        let (r, c) = (i / w, i % w);
        let mut around = vec![i];
        if c > 0 {
            around.push(i - 1);
        }
        if c + 1 < w {
            around.push(i + 1);
        }
        if r > 0 {
            around.push(i - w);
        }
        if i + w < ids.len() {
            around.push(i + w);
        }
        around
            .iter()
            .any(|&j| ids[j] != ids[i] || inst.aov()[j].object_id != ids[i])
    };
    let (mut close, mut worst_inside, mut worst) = (0usize, 0.0f32, 0.0f32);
    for (i, (a, b)) in inst.rgba().iter().zip(flat.rgba()).enumerate() {
        let diff = (*a - *b).abs().max_element();
        let rel = diff / a.abs().max_element().max(b.abs().max_element()).max(1e-6);
        if diff == 0.0 || rel <= 1e-3 {
            close += 1;
        }
        worst = worst.max(diff);
        if !silhouette(i) {
            worst_inside = worst_inside.max(diff);
        }
    }
    let share = close as f64 / inst.rgba().len() as f64;
    eprintln!(
        "{file}: {:.4}% of pixels within 1e-3 relative; largest difference {worst:e}, \
         {worst_inside:e} off silhouettes",
        share * 100.0
    );
    (share, worst_inside, worst)
}

#[test]
fn instanced_and_flattened_renders_agree_but_on_silhouettes() {
    for file in ["shared_meshes.gltf", "gpu_instancing.gltf"] {
        let (share, inside, _) = compare_modes(file);
        assert!(share >= 0.995, "{file}: {share}");
        // A wrong transform moves a whole face: differences of the order of the colours
        // (0.1..1), far above the rounding of the two paths.
        assert!(inside <= 1e-3, "{file}: {inside} off silhouettes");
    }
}

#[test]
fn shared_mesh_instances_appear_where_their_nodes_put_them() {
    use Colour::*;
    let s = load("shared_meshes.gltf", false);
    let film = render(s.clone());
    assert_seen(
        "shared_meshes.gltf",
        &s,
        &film,
        &[
            (-6.0, 2.0, Some("plain/0"), Some(Red)),
            (-5.25, 2.0, Some("plain/1"), Some(Blue)),
            // Mirrored in x: the nose on the -X side, nothing where it would be unmirrored.
            (-2.0, 2.0, Some("mirrored/0"), Some(Red)),
            (-2.75, 2.0, Some("mirrored/1"), Some(Blue)),
            (-1.25, 2.0, None, None),
            // Scaled (2, 0.5, 1): x in [1, 3], y in [1.75, 2.25]; the nose in x [3, 4].
            (1.2, 2.0, Some("stretched/0"), Some(Red)),
            (3.5, 2.0, Some("stretched/1"), Some(Blue)),
            (2.0, 2.4, None, None),
            // Under a parent turned +90 degrees about Z and scaled 1.5: the nose up.
            (4.0, -0.5, Some("child/0"), Some(Red)),
            (3.35, -0.5, Some("child/0"), Some(Red)),
            (4.0, 0.6, Some("child/1"), Some(Blue)),
            (5.1, -0.5, None, None),
            (-5.0, -2.0, Some("single"), Some(Green)),
            (0.0, 0.0, None, None),
        ],
    );
    // The flattened copies show the same objects at the same points.
    let flat = load("shared_meshes.gltf", true);
    let flat_film = render(flat.clone());
    for (x, y) in [(-2.75, 2.0), (3.5, 2.0), (4.0, 0.6), (-5.0, -2.0)] {
        assert_eq!(
            seen(&s, &film, x, y).0,
            seen(&flat, &flat_film, x, y).0,
            "({x}, {y})"
        );
    }
}

#[test]
fn gpu_instances_follow_their_quantised_and_float_rotations() {
    use Colour::*;
    let s = load("gpu_instancing.gltf", false);
    let film = render(s.clone());
    assert_seen(
        "gpu_instancing.gltf",
        &s,
        &film,
        &[
            // swarm/2: at (-3.75, 3.2), scale 0.4, rotated 90 degrees (SHORT quaternion
            // (0, 0, 23170, 23170)): the nose up, none to the right.
            (-3.75, 3.2, Some("swarm/2/0"), Some(Red)),
            (-3.75, 3.5, Some("swarm/2/1"), Some(Blue)),
            (-3.45, 3.2, None, None),
            // swarm/12: at (-3.75, 2.4), scale 0.3, rotated 180 degrees: the nose to the left.
            (-3.975, 2.4, Some("swarm/12/1"), Some(Blue)),
            (-3.525, 2.4, None, None),
            // flock (node at y = -2.5): instance 4 at x = 1, float rotation 180 degrees.
            (1.0, -2.5, Some("flock/4/0"), Some(Red)),
            (0.55, -2.5, Some("flock/4/1"), Some(Blue)),
            (1.45, -2.5, None, None),
            // flock/2 at x = -3, rotated 90 degrees: the nose up.
            (-3.0, -2.05, Some("flock/2/1"), Some(Blue)),
            // The instancing nodes themselves draw nothing at their own transforms.
            (0.0, 0.0, None, None),
            (0.0, -2.5, None, None),
        ],
    );
}

#[test]
fn info_prints_instance_counts_and_the_flag_flattens_them() {
    let info = |flags: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_lumis"))
            .arg("info")
            .arg(asset("gpu_instancing.gltf"))
            .args(flags)
            .output()
            .unwrap();
        assert!(out.status.success(), "{out:?}");
        String::from_utf8(out.stdout).unwrap()
    };
    let instanced = info(&[]);
    assert!(
        instanced.contains("instances: 58 of 1 prototypes (24 primitives in the prototypes)"),
        "{instanced}"
    );
    assert!(
        instanced.contains("objects: 116 (0 spheres, 0 meshes"),
        "{instanced}"
    );
    let flat = info(&["--flatten-instances"]);
    assert!(!flat.contains("instances:"), "{flat}");
    assert!(
        flat.contains("objects: 116 (0 spheres, 116 meshes with 1392 triangles"),
        "{flat}"
    );
    // Without a model file the flag has nothing to act on.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_lumis"))
        .args(["render", "--flatten-instances", "--quiet"])
        .current_dir(tempfile::tempdir().unwrap().path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--flatten-instances need a model file"));
}
