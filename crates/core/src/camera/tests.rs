//! Camera unit tests: rays against the EXR matrices, the thin lens, degenerate setups.

use super::*;

fn cam() -> Camera {
    Camera::look_at(
        Vec3::new(1.0, 2.0, 5.0),
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::Y,
        50.0,
        0.0,
        None,
    )
    .unwrap()
}

#[test]
fn world_to_ndc_maps_a_ray_point_back_to_its_pixel() {
    let c = cam();
    let (w, h) = (64, 48);
    let m = c.world_to_ndc(w, h);
    for film in [
        Vec2::new(10.5, 7.5),
        Vec2::new(60.25, 40.75),
        Vec2::new(32.0, 24.0),
    ] {
        let p = c
            .ray(&RayFrame::unbounded(), film, w, h, Vec2::ZERO)
            .at(3.7);
        let q = m * p.extend(1.0);
        let ndc = q.truncate() / q.w;
        assert!(
            (ndc.x * w as f32 - film.x).abs() < 1e-3,
            "{ndc:?} vs {film:?}"
        );
        assert!(
            (ndc.y * h as f32 - film.y).abs() < 1e-3,
            "{ndc:?} vs {film:?}"
        );
    }
}

#[test]
fn thin_lens_rays_converge_on_the_focus_plane() {
    let c = Camera::look_at(Vec3::ZERO, -Vec3::Z, Vec3::Y, 40.0, 0.5, Some(4.0)).unwrap();
    let film = Vec2::new(20.0, 10.0);
    let a = c.ray(&RayFrame::unbounded(), film, 64, 32, Vec2::new(0.1, 0.9));
    let b = c.ray(&RayFrame::unbounded(), film, 64, 32, Vec2::new(0.8, 0.3));
    let pa = a.at((4.0 - 0.0) / -a.dir.z);
    let pb = b.at(4.0 / -b.dir.z);
    assert!((pa - pb).length() < 1e-4, "{pa} vs {pb}");
}

#[test]
fn rejects_degenerate_setups() {
    assert_eq!(
        Camera::look_at(Vec3::ONE, Vec3::ONE, Vec3::Y, 40.0, 0.0, None),
        Err(CameraError::NoViewDirection)
    );
    assert_eq!(
        Camera::look_at(Vec3::ZERO, Vec3::Y, Vec3::Y, 40.0, 0.0, None),
        Err(CameraError::UpParallel)
    );
    assert_eq!(
        Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 180.0, 0.0, None),
        Err(CameraError::BadFov(180.0))
    );
}

#[test]
fn orthographic_rays_are_parallel_and_world_to_ndc_maps_them_back() {
    let c = Camera::orthographic(
        Vec3::new(1.0, 2.0, 5.0),
        Vec3::new(1.0, 2.0, 0.0),
        Vec3::Y,
        4.0,
    )
    .unwrap();
    let (w, h) = (64, 32);
    let m = c.world_to_ndc(w, h);
    for film in [
        Vec2::new(0.5, 0.5),
        Vec2::new(60.25, 20.75),
        Vec2::new(32.0, 16.0),
    ] {
        let r = c.ray(&RayFrame::unbounded(), film, w, h, Vec2::new(0.3, 0.7));
        assert_eq!(r.dir, -Vec3::Z);
        // The image spans 4 units vertically and 8 horizontally, centred on the position.
        let expect_x = 1.0 + (film.x / w as f32 - 0.5) * 8.0;
        let expect_y = 2.0 - (film.y / h as f32 - 0.5) * 4.0;
        assert!(
            (r.origin - Vec3::new(expect_x, expect_y, 5.0)).length() < 1e-5,
            "{r:?}"
        );
        let q = m * r.at(2.5).extend(1.0);
        assert!(
            (q.x / q.w * w as f32 - film.x).abs() < 1e-3,
            "{q:?} vs {film:?}"
        );
        assert!(
            (q.y / q.w * h as f32 - film.y).abs() < 1e-3,
            "{q:?} vs {film:?}"
        );
        assert!((q.z / q.w - 2.5).abs() < 1e-5, "depth {q:?}");
    }
    assert!(!c.has_depth_of_field());
    assert_eq!(
        Camera::orthographic(Vec3::ZERO, -Vec3::Z, Vec3::Y, 0.0),
        Err(CameraError::BadHeight(0.0))
    );
}
