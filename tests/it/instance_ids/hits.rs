//! The batch query's records and rows: the instance in [`HitRecord::instance`], as a tenth
//! column with `--instance-ids` (twelfth with `--all`), the old columns unchanged.

use super::{instance_of_name, scene};
use crate::common::{all_kinds, cli::assert_ok};
use crate::npy_rays::write_rays;
use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::batch::{
    ALL_HIT_COLUMNS, ALL_HIT_INSTANCE_COLUMNS, HIT_COLUMNS, HIT_INSTANCE_COLUMNS, HitRecord,
    PrimKind, RayRow, trace_all_hits, trace_rays,
};
use lumis_core::scene::World;
use std::path::Path;
use std::process::Command;

const INF: f32 = f32::INFINITY;

fn world(kind: AccelKind) -> World {
    let options = BuildOptions {
        max_leaf_size: kind.default_leaf_size(),
        ..Default::default()
    };
    World::build(scene(8, 8), kind, &options)
}

/// A ray from `(x, y, 12)` straight down -z.
fn down(x: f32, y: f32) -> RayRow {
    [x, y, 12.0, 0.0, 0.0, -1.0, 0.0, INF]
}

/// A ray with its known answer: distance (`None` for a miss), instance, object name, kind.
type Known = (RayRow, Option<f32>, Option<u32>, &'static str, PrimKind);

/// Rays with known answers.
fn known() -> Vec<Known> {
    use PrimKind::{Sphere, Triangle};
    vec![
        (down(-3.0, 0.0), Some(11.0), Some(0), "copy0/ball", Sphere),
        (down(0.0, 0.0), Some(11.0), Some(1), "copy1/ball", Sphere),
        // copy2 is scaled by 0.8: its ball's radius is 0.8, its tile lower.
        (down(3.0, 0.0), Some(11.2), Some(2), "copy2/ball", Sphere),
        (
            down(0.0, -1.55),
            Some(12.0),
            Some(1),
            "copy1/tile",
            Triangle,
        ),
        (
            down(3.0, -1.24),
            Some(12.0),
            Some(2),
            "copy2/tile",
            Triangle,
        ),
        (down(10.0, 10.0), Some(15.0), None, "ground", Triangle),
        (
            [0.0, 0.0, 12.0, 0.0, 0.0, 1.0, 0.0, INF],
            None,
            None,
            "",
            Triangle,
        ),
    ]
}

#[test]
fn nearest_rows_append_the_instance_and_keep_the_nine_columns() {
    let rays: Vec<RayRow> = known().iter().map(|k| k.0).collect();
    for kind in all_kinds() {
        let world = world(kind);
        let objects = world.scene().objects();
        let records = trace_rays(&world, &rays[..], false);
        let mut ball_prims = Vec::new();
        for (r, (ray, t, instance, name, prim_kind)) in records.iter().zip(known()) {
            let what = format!("{kind:?}, ray {ray:?}");
            let row = r.row();
            let wide = r.row_with_instance();
            assert_eq!(row.len(), HIT_COLUMNS);
            assert_eq!(wide.len(), HIT_INSTANCE_COLUMNS);
            assert_eq!(wide[..HIT_COLUMNS], row, "{what}");
            let Some(t) = t else {
                assert_eq!(*r, HitRecord::MISS, "{what}");
                assert_eq!(wide[HIT_COLUMNS], -1.0, "{what}");
                continue;
            };
            assert!((r.t - t).abs() < 1e-4, "{what}: t {} not {t}", r.t);
            assert_eq!(r.instance, instance, "{what}");
            assert_eq!(r.kind, Some(prim_kind), "{what}");
            let object = r.object.expect("a hit has an object");
            assert_eq!(objects[object as usize].name, name, "{what}");
            assert_eq!(instance_of_name(name), instance, "{what}");
            // The row: the object id in column 2, the instance last (-1 for the ground).
            assert_eq!(row[2], object as f32, "{what}");
            assert_eq!(
                wide[HIT_COLUMNS],
                instance.map_or(-1.0, |i| i as f32),
                "{what}"
            );
            if prim_kind == PrimKind::Sphere {
                ball_prims.push(r.prim);
            }
        }
        // Every instance's ball is the prototype's one primitive (Embree's primID).
        assert_eq!(ball_prims.len(), 3);
        assert!(
            ball_prims.iter().all(|p| *p == ball_prims[0]),
            "{ball_prims:?}"
        );
    }
}

#[test]
fn all_hit_rows_append_the_instance_after_the_graze_flag() {
    // Along the x axis through the three balls: in and out of each.
    let rays = [down(10.0, 10.0), [-10.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, INF]];
    let world = world(AccelKind::Sah);
    let records = trace_all_hits(&world, &rays[..]);
    let rows: Vec<_> = records.iter().map(|r| r.row_with_instance()).collect();
    let want: [(f32, f32, f32); 7] = [
        (0.0, 15.0, -1.0),
        (1.0, 6.0, 0.0),
        (1.0, 8.0, 0.0),
        (1.0, 9.0, 1.0),
        (1.0, 11.0, 1.0),
        (1.0, 12.2, 2.0),
        (1.0, 13.8, 2.0),
    ];
    assert_eq!(rows.len(), want.len(), "{rows:?}");
    for ((r, row), (ray, t, instance)) in records.iter().zip(&rows).zip(want) {
        assert_eq!(row.len(), ALL_HIT_INSTANCE_COLUMNS);
        assert_eq!(
            row[..ALL_HIT_COLUMNS],
            r.row(),
            "the eleven columns as before"
        );
        assert_eq!(row[0], ray);
        assert!((row[1] - t).abs() < 1e-4, "{row:?}");
        assert_eq!(
            row[ALL_HIT_COLUMNS - 1],
            0.0,
            "crossings, not grazes: {row:?}"
        );
        assert_eq!(row[ALL_HIT_COLUMNS], instance, "{row:?}");
    }
}

/// A scene file without instances (the loaders on this branch make none).
pub(super) const PLAIN: &str = "[camera]
position = [0.0, 0.0, 10.0]
look_at = [0.0, 0.0, 0.0]

[materials.m]

[[sphere]]
name = \"ball\"
center = [0.0, 0.0, 0.0]
radius = 1.0
material = \"m\"
";

fn read_f32(path: &Path) -> (Vec<u64>, Vec<f32>) {
    let bytes = std::fs::read(path).unwrap();
    let npy = npyz::NpyFile::new(&bytes[..]).unwrap();
    let shape = npy.shape().to_vec();
    (shape, npy.into_vec().unwrap())
}

#[test]
fn the_flag_appends_minus_one_and_changes_no_other_byte() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, PLAIN).unwrap();
    let rays = dir.path().join("rays.npy");
    write_rays(&rays, &[down(0.0, 0.0), down(5.0, 5.0)]);
    for (all, columns) in [(false, HIT_COLUMNS), (true, ALL_HIT_COLUMNS)] {
        let run = |out: &str, flag: bool| {
            let mut cmd = Command::new(env!("CARGO_BIN_EXE_lumis"));
            cmd.arg("hits").arg(&scene).arg("--rays").arg(&rays);
            cmd.arg("--out").arg(dir.path().join(out));
            if all {
                cmd.arg("--all");
            }
            if flag {
                cmd.arg("--instance-ids");
            }
            assert_ok(&cmd.output().unwrap());
            read_f32(&dir.path().join(out))
        };
        let (shape, plain) = run("plain.npy", false);
        let (wide_shape, wide) = run("wide.npy", true);
        // Without --all: a hit and a miss; with it: the ball's two crossings.
        assert_eq!(shape, [2, columns as u64], "all: {all}");
        assert_eq!(wide_shape, [2, columns as u64 + 1], "all: {all}");
        for (old, new) in plain.chunks(columns).zip(wide.chunks(columns + 1)) {
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(old), bits(&new[..columns]), "all: {all}");
            assert_eq!(new[columns], -1.0, "all: {all}");
        }
    }
}
