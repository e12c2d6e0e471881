//! Error of one rendering against the converged reference, and disagreement of one precision
//! and offset with float64 brute force on the same ray queries.

use lumis_core::accel::{AccelKind, BuildOptions, TraversalStats};
use lumis_core::film::Film;
use lumis_core::geometry::{Offset, Precision, SurfacePoint};
use lumis_core::math::{Ray, Vec2, Vec3};
use lumis_core::scene::{Scene, World};

/// Relative part of the acne / lost-shadow threshold: a pixel counts when its luminance is
/// off the reference's by more than `REL * Y_ref + ABS`.
pub const ACNE_REL: f32 = 0.25;
/// Absolute part of the acne / lost-shadow threshold (linear luminance).
pub const ACNE_ABS: f32 = 0.02;
/// The epsilon of relative MSE: `(x - ref)^2 / (ref^2 + REL_MSE_EPS)`, so black pixels of the
/// reference do not divide by zero (pbrt's and Mitsuba's convention uses 1e-2 too).
pub const REL_MSE_EPS: f32 = 1e-2;

/// Image error of one rendering against the reference.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImageError {
    /// Root mean squared error over pixels and linear RGB channels.
    pub rmse: f64,
    /// Mean of `(x - ref)^2 / (ref^2 + 1e-2)` over pixels and channels.
    pub rel_mse: f64,
    /// 99th percentile over pixels of the largest channel's absolute error.
    pub p99: f64,
    /// Interior pixels darker than the reference by more than the threshold (acne, holes).
    pub acne: usize,
    /// Interior pixels brighter than the reference by more than the threshold (lost shadows).
    pub lost: usize,
}

fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// Compares `img` with `reference` (same size). Acne and lost-shadow pixels are counted only
/// where the reference's pixel-centre ray and those of its 4 neighbours hit the same object
/// and `img`'s centre ray hits it too: this keeps silhouette aliasing (sampling noise) out of
/// the counts, which are meant for shading errors inside a surface.
pub fn image_error(img: &Film, reference: &Film) -> ImageError {
    let (w, h) = (reference.width() as usize, reference.height() as usize);
    assert_eq!((img.width() as usize, img.height() as usize), (w, h));
    let (a, r) = (img.rgba(), reference.rgba());
    let (aov, raov) = (img.aov(), reference.aov());
    let mut e = ImageError::default();
    let (mut sq, mut rel) = (0f64, 0f64);
    let mut per_pixel = Vec::with_capacity(w * h);
    for i in 0..w * h {
        let (x, y) = (a[i].truncate(), r[i].truncate());
        let d = x - y;
        sq += d.length_squared() as f64;
        rel += (d * d / (y * y + Vec3::splat(REL_MSE_EPS))).element_sum() as f64;
        per_pixel.push(d.abs().max_element());
        let (px, py) = (i % w, i / w);
        if px == 0 || py == 0 || px + 1 == w || py + 1 == h {
            continue;
        }
        let id = raov[i].object_id;
        let interior = aov[i].object_id == id
            && [i - 1, i + 1, i - w, i + w]
                .iter()
                .all(|&j| raov[j].object_id == id);
        if !interior {
            continue;
        }
        let (ly, lr) = (luminance(x), luminance(y));
        let tol = ACNE_REL * lr + ACNE_ABS;
        e.acne += usize::from(ly < lr - tol);
        e.lost += usize::from(ly > lr + tol);
    }
    let n = (w * h) as f64;
    e.rmse = (sq / (3.0 * n)).sqrt();
    e.rel_mse = rel / (3.0 * n);
    per_pixel.sort_by(f32::total_cmp);
    let k = ((0.99 * n).ceil() as usize).clamp(1, per_pixel.len()) - 1;
    e.p99 = per_pixel[k] as f64;
    e
}

/// Disagreements of one precision and offset with float64 brute force.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QueryError {
    /// Pixel-centre camera rays tested.
    pub rays: usize,
    /// Rays that hit under one and miss under the other.
    pub hit_miss: usize,
    /// Rays that hit a different primitive.
    pub prim: usize,
    /// Shadow rays compared (from pixel-centre hits on the same primitive, one per light).
    pub shadow_rays: usize,
    /// Shadow rays occluded under one and not under the other.
    pub shadow: usize,
}

/// What float64 brute force says about one pixel-centre ray.
#[derive(Clone, Debug)]
struct Truth {
    ray: Ray,
    hit: Option<(u32, SurfacePoint)>,
    /// Per light: `None` when the light is behind the surface, else whether it is occluded.
    shadows: Vec<Option<bool>>,
}

/// Float64 brute-force answers for a scene's pixel-centre rays, computed once per scene.
pub struct Oracle {
    truths: Vec<Truth>,
}

/// The geometric normal facing the side the ray came from.
fn facing(s: &SurfacePoint, ray: &Ray) -> Vec3 {
    if s.ng.dot(ray.dir) > 0.0 { -s.ng } else { s.ng }
}

/// The shadow ray the integrator would cast from `s` towards `light`, or `None` when the
/// light is behind the geometric surface.
fn shadow_ray(
    s: &SurfacePoint,
    ng: Vec3,
    light: &lumis_core::light::Light,
    offset: Offset,
) -> Option<Ray> {
    let ls = light.sample(s.p);
    if ng.dot(ls.wi) <= 0.0 {
        return None;
    }
    let t_max = if ls.distance.is_finite() {
        ls.distance * (1.0 - 1e-4)
    } else {
        f32::INFINITY
    };
    Some(Ray::segment(s.spawn_origin(ls.wi, offset), ls.wi, t_max))
}

/// The pinhole rays through every pixel centre, as the AOV layers trace them.
fn centre_rays(scene: &Scene) -> Vec<Ray> {
    let (w, h) = (scene.settings().width, scene.settings().height);
    let cam = scene.camera();
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            Ray::new(cam.position(), cam.pinhole_dir(film, w, h))
        })
        .collect()
}

impl Oracle {
    /// Traces every pixel-centre ray and its shadow rays (error-bound offsets) in float64
    /// through brute force: no accelerator and no f32 test can be wrong here.
    pub fn new(scene: &Scene) -> Self {
        let mut s64 = scene.clone();
        s64.settings_mut().precision = Precision::Double;
        let s64 = World::build(s64, AccelKind::Brute, &BuildOptions::default());
        let mut stats = TraversalStats::default();
        let truths = centre_rays(scene)
            .into_iter()
            .map(|ray| {
                let hit = s64.intersect(&ray, &mut stats);
                let shadows = match &hit {
                    None => Vec::new(),
                    Some(i) => {
                        let ng = facing(&i.surface, &ray);
                        s64.scene()
                            .lights()
                            .iter()
                            .map(|l| {
                                shadow_ray(&i.surface, ng, l, Offset::ErrorBound)
                                    .map(|r| s64.occluded(&r, &mut stats))
                            })
                            .collect()
                    }
                };
                Truth {
                    ray,
                    hit: hit.map(|i| (i.prim, i.surface)),
                    shadows,
                }
            })
            .collect();
        Oracle { truths }
    }

    /// Compares `world` (with the precision and offset under test in its settings) with the
    /// oracle on the same camera rays, and on the shadow rays of the hits
    /// where both find the same primitive (each side spawning from its own hit point).
    pub fn compare(&self, world: &World) -> QueryError {
        let scene = world.scene();
        let offset = scene.settings().offset;
        let mut stats = TraversalStats::default();
        let mut e = QueryError::default();
        for t in &self.truths {
            e.rays += 1;
            let got = world.intersect(&t.ray, &mut stats);
            let (Some((prim, _)), Some(i)) = (&t.hit, &got) else {
                e.hit_miss += usize::from(t.hit.is_some() != got.is_some());
                continue;
            };
            if *prim != i.prim {
                e.prim += 1;
                continue;
            }
            let ng = facing(&i.surface, &t.ray);
            for (light, truth) in scene.lights().iter().zip(&t.shadows) {
                let (Some(truth), Some(r)) = (truth, shadow_ray(&i.surface, ng, light, offset))
                else {
                    continue;
                };
                e.shadow_rays += 1;
                e.shadow += usize::from(world.occluded(&r, &mut stats) != *truth);
            }
        }
        e
    }
}
