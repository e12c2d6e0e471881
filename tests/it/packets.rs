//! Rays traced as a packet (`Accel::trace_packet`: up to eight rays from one origin walked
//! together) get bit for bit the answers they get one at a time, and brute force's: on every
//! test scene, for tight bundles (the samples of one pixel), wide ones (a whole tile of a wide
//! view) and every packet size; and packets the walk cannot share (several origins, direction
//! signs that differ within the packet) are refused, not answered wrongly.

use crate::common;

use common::{Rng, brute, closest, rays, same_hit, scene_box, scenes, simd};
use lumis_core::accel::{Accel, AccelKind, BuildOptions, BuildQuality, PACKET, SimdPath, Traced};
use lumis_core::geometry::{Geometry, Precision};
use lumis_core::math::{Ray, Vec3};

/// A packet of `n` rays from `origin` around `axis`, spread up to `spread` radians.
fn bundle(rng: &mut Rng, origin: Vec3, axis: Vec3, spread: f32, n: usize) -> Vec<Ray> {
    (0..n)
        .map(|_| {
            let jitter = rng.unit_vector() * rng.range(0.0, spread);
            Ray::new(origin, (axis + jitter).normalize())
        })
        .collect()
}

/// Traces `packet` as a packet and each ray alone; returns whether the packet was walked
/// together, after checking every answer against the single walk and brute force.
fn check_packet(
    what: &str,
    accel: &Accel,
    reference: &Accel,
    g: &Geometry,
    packet: &[Ray],
) -> bool {
    let mut stats = Default::default();
    let mut out: [Option<Traced>; PACKET] = [None; PACKET];
    let together = accel.trace_packet(g, Precision::Watertight, packet, &mut stats, &mut out);
    if !together {
        assert!(
            out.iter().all(Option::is_none),
            "{what}: a refused packet wrote answers"
        );
        return false;
    }
    for (i, (ray, got)) in packet.iter().zip(&out).enumerate() {
        let alone = accel.trace_geometry(g, Precision::Watertight, ray, &mut Default::default());
        assert_eq!(
            got, &alone,
            "{what} ray {i} {ray:?}: packet {got:?}, alone {alone:?}"
        );
        let got = got.map(|t| t.caller_hit());
        let want = closest(reference, g, ray);
        assert!(
            same_hit(&got, &want),
            "{what} ray {i}: packet {got:?}, brute {want:?}"
        );
    }
    true
}

/// Packets of every size and spread over `g`; returns how many were walked together.
fn check_scene(name: &str, g: &Geometry, seed: u64, packets: usize) -> usize {
    let reference = brute(g);
    let mut walked = 0;
    for quality in [BuildQuality::Full, BuildQuality::Fast] {
        let opts = BuildOptions {
            quality,
            ..Default::default()
        };
        let accel = Accel::build_for(AccelKind::Sah, g, &opts);
        let mut rng = Rng::new(seed);
        let scene = scene_box(g);
        for k in 0..packets {
            let first = rays::incoherent(&mut rng, &scene);
            let spread = [1e-4, 1e-2, 0.2, 1.0][k % 4];
            let n = 2 + k % (PACKET - 1);
            let packet = bundle(&mut rng, first.origin, first.dir, spread, n);
            let what = format!("{name} {quality:?} packet {k} ({n} rays, spread {spread})");
            walked += usize::from(check_packet(&what, &accel, &reference, g, &packet));
        }
    }
    walked
}

#[test]
fn packets_agree_with_single_rays_and_brute_force() {
    let paths = simd::simd_paths("packets");
    for path in paths.each() {
        let mut walked = 0;
        walked += check_scene("uniform", &scenes::uniform(1, 300, 700), 61, 600);
        walked += check_scene("clustered", &scenes::clustered(4, 300, 900), 62, 600);
        walked += check_scene("tessellated", &scenes::tessellated(6), 63, 600);
        walked += check_scene("duplicates", &scenes::duplicates(51).0, 64, 400);
        walked += check_scene("flat", &scenes::flat_axis_aligned(45), 65, 300);
        walked += check_scene("single triangle", &scenes::single_triangle(), 66, 100);
        if path == SimdPath::Scalar {
            // Without SIMD every packet goes one ray at a time.
            assert_eq!(walked, 0, "scalar: {walked} packets were walked together");
        } else {
            // Most packets share a walk (wide ones whose directions straddle an axis do not).
            assert!(
                walked > 3_000,
                "{}: only {walked} packets were walked together",
                path.name()
            );
        }
    }
}

#[test]
fn packets_the_walk_cannot_share_are_refused() {
    let g = scenes::uniform(2, 40, 400);
    let accel = Accel::build_for(AccelKind::Sah, &g, &BuildOptions::default());
    let reference = brute(&g);
    let o = Vec3::new(0.5, -40.0, 0.25);
    let up = Vec3::new(0.01, 1.0, 0.02);
    // Two origins.
    let mut two = vec![Ray::new(o, up); 4];
    two[3].origin.x += 1e-3;
    // Direction signs differ within the packet (x crosses zero).
    let straddle = vec![
        Ray::new(o, Vec3::new(0.2, 1.0, 0.0)),
        Ray::new(o, Vec3::new(-0.2, 1.0, 0.1)),
    ];
    // A zero direction component.
    let flat = vec![Ray::new(o, up), Ray::new(o, Vec3::new(0.0, 1.0, 0.02))];
    // More rays than a packet holds.
    let many = vec![Ray::new(o, up); PACKET + 1];
    for (what, packet) in [
        ("two origins", two),
        ("straddle", straddle),
        ("zero", flat),
        ("many", many),
    ] {
        assert!(
            !check_packet(what, &accel, &reference, &g, &packet),
            "{what} was walked"
        );
    }
    // Brute force has no hierarchy to walk a packet through.
    let pair = vec![Ray::new(o, up); 2];
    assert!(!check_packet("brute", &reference, &reference, &g, &pair));
}

/// `lumis hits --packets` (groups of eight consecutive rays walked together) writes the same
/// bytes as one ray at a time: a pinhole camera's rays in 4x2 tiles, and a scrambled set whose
/// groups mostly cannot share a walk.
#[test]
fn hits_with_packets_writes_the_same_records() {
    use crate::common::cli::assert_ok;
    use crate::npy_rays::write_rays;
    let dir = tempfile::tempdir().unwrap();
    // A wavy 24 x 24 height field and a sphere above it.
    let n = 24;
    let mut positions = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            let h = ((i as f32 * 0.7).sin() + (j as f32 * 0.45).cos()) * 0.6;
            positions.push(format!("[{}, {h}, {}]", i as f32 - 12.0, j as f32 - 12.0));
        }
    }
    let mut indices = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let (a, b) = (i * (n + 1) + j, (i + 1) * (n + 1) + j);
            indices.push(format!("[{a}, {b}, {}]", a + 1));
            indices.push(format!("[{}, {b}, {}]", a + 1, b + 1));
        }
    }
    let scene = format!(
        "[materials.m]\ndiffuse = [0.5, 0.5, 0.5]\n\n[[sphere]]\ncenter = [1.0, 2.0, 0.5]\n\
         radius = 1.5\nmaterial = \"m\"\n\n[[mesh]]\nmaterial = \"m\"\npositions = [{}]\n\
         indices = [{}]\n",
        positions.join(", "),
        indices.join(", ")
    );
    std::fs::write(dir.path().join("scene.toml"), scene).unwrap();
    // A 64 x 48 camera at (3, 9, 14) looking at the origin, in 4 x 2 pixel tiles.
    let eye = Vec3::new(3.0, 9.0, 14.0);
    let forward = (-eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    let (w, h) = (64, 48);
    let mut camera = Vec::new();
    for ty in (0..h).step_by(2) {
        for tx in (0..w).step_by(4) {
            for y in ty..ty + 2 {
                for x in tx..tx + 4 {
                    let px = (x as f32 + 0.5) / w as f32 * 2.0 - 1.0;
                    let py = 1.0 - (y as f32 + 0.5) / h as f32 * 2.0;
                    let d = forward + right * (px * 0.7) + up * (py * 0.5);
                    camera.push([eye.x, eye.y, eye.z, d.x, d.y, d.z, 0.0, f32::INFINITY]);
                }
            }
        }
    }
    let mut rng = Rng::new(71);
    let scrambled: Vec<[f32; 8]> = (0..3000)
        .map(|_| {
            let o = Vec3::new(
                rng.range(-15.0, 15.0),
                rng.range(2.0, 12.0),
                rng.range(-15.0, 15.0),
            );
            let d = rng.unit_vector();
            [o.x, o.y, o.z, d.x, d.y, d.z, 0.0, rng.range(1.0, 40.0)]
        })
        .collect();
    for (name, rays) in [("camera", camera), ("scrambled", scrambled)] {
        let path = dir.path().join(format!("{name}.npy"));
        write_rays(&path, &rays);
        let out = |packets: bool| {
            let file = dir.path().join(format!("{name}-{packets}.npy"));
            let mut args = vec!["hits", "scene.toml", "--rays"];
            let (p, f) = (path.to_str().unwrap(), file.to_str().unwrap());
            args.extend([p, "--out", f, "--threads", "2"]);
            if packets {
                args.push("--packets");
            }
            let o = std::process::Command::new(common::cli::binary())
                .args(&args)
                .current_dir(dir.path())
                .output()
                .unwrap();
            assert_ok(&o);
            std::fs::read(&file).unwrap()
        };
        let (single, packets) = (out(false), out(true));
        assert!(single == packets, "{name}: --packets changed the records");
    }
    // Nothing to combine it with.
    let o = std::process::Command::new(common::cli::binary())
        .args([
            "hits",
            "scene.toml",
            "--rays",
            "camera.npy",
            "--out",
            "x.npy",
            "--packets",
            "--any-hit",
        ])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(
        !o.status.success(),
        "--packets with --any-hit must be refused"
    );
}
