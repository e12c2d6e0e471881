use super::*;

fn unit_box() -> Aabb {
    Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0))
}

#[test]
fn origins_in_the_near_region_are_traced_as_given() {
    let f = RayFrame::new(unit_box());
    // Bounds of extent 2 grown by 4 x 2 = 8 on every side.
    assert!(f.holds(Vec3::new(9.0, -9.0, 0.0)));
    assert!(!f.holds(Vec3::new(9.5, 0.0, 0.0)));
    assert!(!f.holds(Vec3::new(f32::NAN, 0.0, 0.0)));
    let r = Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z);
    assert_eq!(f.frame(&r), Framing::AsGiven);
}

#[test]
fn a_far_origin_is_moved_onto_its_own_line_near_the_bounds() {
    let f = RayFrame::new(unit_box());
    let o = Vec3::new(1e19, 2e19, 3e19);
    let r = Ray::new(o, -o);
    let Framing::Moved(m) = f.frame(&r) else {
        panic!("not moved")
    };
    assert!(f.holds(m.ray.origin), "{:?}", m.ray);
    // The exact line passes through 0 at t = 1: the moved origin is on it to f32 precision
    // of the near region, and t measured from it maps back to the caller's.
    let along = m.ray.origin / o;
    assert!(m.ray.origin.length() < 20.0, "{along}");
    let t_centre = -m.ray.origin.dot(m.ray.dir) / m.ray.dir.length_squared();
    assert_eq!(m.world_t(t_centre), Some(1.0));
    assert!(m.ray.t_min < t_centre && t_centre < m.ray.t_max);
}

#[test]
fn moves_converge_from_the_largest_origins_to_the_smallest_scenes() {
    let tiny = Aabb::new(Vec3::splat(-1e-30), Vec3::splat(1e-30));
    let f = RayFrame::new(tiny);
    let o = Vec3::new(3e38, -1e38, 2e38);
    let Framing::Moved(m) = f.frame(&Ray::new(o, -o)) else {
        panic!("not moved")
    };
    assert!(f.holds(m.ray.origin), "{:?}", m.ray);
}

#[test]
fn lines_that_miss_the_bounds_or_whose_interval_does_not_reach_them_miss() {
    let f = RayFrame::new(unit_box());
    let o = Vec3::new(0.0, 0.0, 1e10);
    assert_eq!(f.frame(&Ray::new(o, Vec3::Z)), Framing::Miss);
    assert_eq!(
        f.frame(&Ray::new(o + Vec3::X * 2.0, -Vec3::Z)),
        Framing::Miss
    );
    assert_eq!(f.frame(&Ray::segment(o, -Vec3::Z, 1e9)), Framing::Miss);
    assert!(matches!(
        f.frame(&Ray::segment(o, -Vec3::Z, 2e10)),
        Framing::Moved(_)
    ));
    let bad = Ray::new(Vec3::new(f32::INFINITY, 0.0, 0.0), Vec3::X);
    assert_eq!(f.frame(&bad), Framing::Miss);
}

#[test]
fn the_empty_frame_holds_nothing_and_everything_misses() {
    let f = RayFrame::new(Aabb::EMPTY);
    assert!(!f.holds(Vec3::ZERO));
    assert_eq!(f.frame(&Ray::new(Vec3::ZERO, Vec3::X)), Framing::Miss);
}

#[test]
fn world_t_stays_in_the_callers_interval() {
    let f = RayFrame::new(unit_box());
    let r = Ray {
        origin: Vec3::new(0.0, 0.0, 1e12),
        dir: -Vec3::Z,
        t_min: 1e12 - 65536.0,
        t_max: 1e12,
    };
    let Framing::Moved(m) = f.frame(&r) else {
        panic!("not moved")
    };
    let t = m.world_t(m.ray.t_max).unwrap();
    assert!(t > r.t_min && t <= r.t_max);
}

#[test]
fn a_small_object_far_from_the_world_origin_keeps_nearby_origins_as_given() {
    // A sphere of radius 1e-3 at 1e7, where f32 coordinates are 1 apart: moving an origin 300
    // away would round it by up to 0.5, far more than the 2e-5 of t resolution it keeps.
    let c = Vec3::new(1e7, -3e6, 2e6);
    let f = RayFrame::new(Aabb::new(c - 1e-3, c + 1e-3));
    assert!(f.holds(c + Vec3::new(300.0, -200.0, 100.0)));
    assert!(f.holds(Vec3::ZERO));
    assert!(!f.holds(c * 3.0));
}
