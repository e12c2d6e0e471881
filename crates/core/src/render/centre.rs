//! The AOV layers' ray: one pinhole ray through each pixel centre, the ray a compositor
//! rebuilds from the EXR's `worldToNDC`.

use crate::film::PixelAov;
use crate::integrator::{RayCounts, Whitted};
use crate::math::{Vec2, Vec3};
use crate::scene::{Interaction, Scene};

/// What the pinhole ray through the centre of pixel `(x, y)` hits: exactly the ray a compositor
/// rebuilds from the EXR's `worldToNDC`.
pub(super) fn centre_aov(
    scene: &Scene,
    integrator: &Whitted,
    x: u32,
    y: u32,
    counts: &mut RayCounts,
) -> PixelAov {
    let st = scene.settings();
    let cam = scene.camera();
    let ray = cam.centre_ray(
        integrator.world().accel().frame(),
        Vec2::new(x as f32 + 0.5, y as f32 + 0.5),
        st.width,
        st.height,
    );
    counts.aov += 1;
    let world = integrator.world();
    let Some(traced) = world.trace(&ray, &mut counts.traversal) else {
        return PixelAov::MISS;
    };
    // Texture coordinates always, for the uv layer (shading computes them only where a
    // texture reads them).
    let Interaction {
        prim,
        inner,
        object,
        instance,
        surface: s,
        ..
    } = world.interaction(&traced, true);
    let m = scene.material_of(object);
    // A textured material's albedo is the one shading uses at this hit.
    let albedo = match m.textured {
        Some(_) => m
            .at_hit(
                &scene.geometry().hit_attributes(prim, inner, &s),
                s.ns,
                s.ng,
            )
            .map_or(Vec3::ZERO, |a| a.material.diffuse.eval(s.p, s.uv)),
        None => m.diffuse.eval(s.p, s.uv),
    };
    // The normal is reported as the surface defines it (outward / winding), not flipped
    // towards the camera, so it compares directly with other engines' normals.
    PixelAov {
        depth: (s.p - cam.position()).dot(cam.forward()),
        normal: s.ns,
        prim_id: prim as i32,
        object_id: object as i32,
        instance_id: instance.map_or(-1, |i| i as i32),
        albedo,
        position: s.p,
        uv: s.uv,
        samples: 0,
    }
}
