//! The `queries` fuzz target: ray queries on small random scenes, through every accelerator,
//! traversal, leaf size and precision, against brute force bit for bit and against an exact
//! oracle (issue 24, point 5: "fuzz the queries, not only the parsers").
//!
//! The bytes decode ([`decode`]) to 1..12 spheres and triangles anywhere up to the coordinate
//! limit and up to 8 rays with components across the whole `f32` range. Each ray
//! - outside the domain (non-finite origin, zero or non-finite direction, NaN `t_min` or
//!   `t_max`) must be refused by `scene::domain::check_ray` and by `rays::parse_rays`, and is
//!   not traced;
//! - inside it, must give every configuration exactly brute force's answer of the same
//!   precision, an occlusion answer that agrees, a finite `t` in `(t_min, t_max]`, finite
//!   barycentrics, and (for a sample of rays, watertight and double precision) answers the
//!   exact oracle allows ([`expect`], [`oracle`]).
//!
//! A failure panics with the scene and the ray as Rust to paste into a test. This file is
//! also included by path from tests/ (the regression replay and a seeded run in stable
//! `cargo test`), so it depends only on lumis, glam and the num crates.

pub mod decode;
pub mod expect;
pub mod fixed;
pub mod oracle;
pub mod scene;

use expect::Expect;
use lumis_core::accel::{
    Accel, AccelKind, BuildOptions, Hit, PAPER_SEGMENT_MAX, SegmentParams, Traversal,
    TraversalStats,
};
use lumis_core::geometry::{Geometry, Precision, WatertightRay};
use lumis_core::math::{Ray, Vec3};
use lumis_core::scene::domain;
use oracle::Frame;
pub use scene::{Prim, Scene};
use std::cell::RefCell;
use std::collections::BTreeSet;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::{Mutex, OnceLock};

/// Counts of what the checker saw (for tuning the decoder and for the seeded test's report):
/// scenes built, rays decoded, rays in the domain, rays the oracle checked, and of those the
/// rays where some hit was certain and where no hit was possible.
pub static COUNTS: [AtomicU64; 6] = [const { AtomicU64::new(0) }; 6];

/// What each of [`COUNTS`] counts.
pub const COUNT_NAMES: [&str; 6] = [
    "scenes",
    "rays",
    "in domain",
    "oracle",
    "must hit",
    "cannot hit",
];

fn count(i: usize) {
    COUNTS[i].fetch_add(1, Relaxed);
}

/// Runs the target on fuzz bytes: decode, then [`check`].
pub fn run(data: &[u8]) {
    if let Some((scene, rays)) = decode_input(data) {
        check(&scene, &rays);
    }
}

/// The scene and rays that fuzz bytes decode to ([`decode`]); `None` when the scene accepts
/// no primitive. The rays include those outside the domain.
pub fn decode_input(data: &[u8]) -> Option<(Scene, Vec<Ray>)> {
    let mut r = decode::Reader::new(data);
    let header = decode::scene(&mut r);
    let scene = Scene::build(&header.prims)?;
    let rays = decode::rays(&mut r, &header, &scene.prims);
    Some((scene, rays))
}

/// Checks every ray against `scene` (see the module docs). Panics with a report on failure.
pub fn check(scene: &Scene, rays: &[Ray]) {
    let configs = configurations(&scene.geometry);
    count(0);
    // Exact arithmetic is slow: the oracle sees every ray of a small scene, one in four
    // otherwise.
    let every = if scene.prims.len() <= 4 { 1 } else { 4 };
    for (i, ray) in rays.iter().enumerate() {
        count(1);
        set_context(scene, ray);
        set_step(Step::Domain);
        let domain = in_domain(ray);
        let lumis = domain::check_ray(ray.origin, ray.dir, ray.t_min, ray.t_max);
        if domain != lumis.is_ok() || domain != parse_rays_accepts(ray) {
            let what = format!(
                "in the domain by the stated rule: {domain}; scene::domain::check_ray: \
                 {lumis:?}; rays::parse_rays accepts: {}",
                parse_rays_accepts(ray)
            );
            fail(scene, ray, &what);
        }
        if domain {
            count(2);
            let run = || check_ray(scene, &configs, ray, i % every == 0);
            if survey() || only().is_some() {
                // A failure has been reported; go on with the next ray.
                let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(run));
            } else {
                run();
            }
        }
    }
    CONTEXT.with(|c| *c.borrow_mut() = None);
}

/// The domain of a ray query (issue 24), as stated, independently of
/// `lumis_core::scene::domain::check_ray` (which must agree): a finite origin, a finite non-zero
/// direction, and `t_min`, `t_max` not NaN (infinite ones are fine).
pub fn in_domain(r: &Ray) -> bool {
    r.origin.is_finite()
        && r.dir.is_finite()
        && r.dir != Vec3::ZERO
        && !r.t_min.is_nan()
        && !r.t_max.is_nan()
}

/// Whether `lumis hits --rays`'s reader accepts the ray, as a one-row `.npy` array.
fn parse_rays_accepts(r: &Ray) -> bool {
    let mut header = b"\x93NUMPY\x01\x00\x76\x00".to_vec();
    let dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (1, 8), }";
    header.extend(format!("{dict:<117}\n").bytes());
    let row = [r.origin.to_array(), r.dir.to_array()].concat();
    for x in row.into_iter().chain([r.t_min, r.t_max]) {
        header.extend(x.to_le_bytes());
    }
    lumis_io::rays::parse_rays(&header, std::path::Path::new("ray.npy")).is_ok()
}

/// One built accelerator and how it is named in a report.
struct Config {
    name: String,
    accel: Accel,
}

/// Every accelerator kind x leaf size (its default and 1) x traversal (ordered, exhaustive,
/// segments short and the paper's; not the original rule, wrong by design), named. Brute
/// force comes first, once: it has no leaves and ignores the traversal.
fn plan() -> Vec<(String, AccelKind, usize, Traversal)> {
    let traversals = [
        Traversal::Ordered,
        Traversal::Exhaustive,
        Traversal::Segments(SegmentParams {
            init: 0.05,
            max: 1.6,
        }),
        Traversal::Segments(SegmentParams {
            init: 2.0,
            max: PAPER_SEGMENT_MAX,
        }),
    ];
    let mut out = Vec::new();
    for kind in AccelKind::ALL {
        let mut leaves = vec![kind.default_leaf_size(), 1];
        leaves.dedup();
        for leaf in leaves {
            for t in traversals {
                out.push((format!("{kind:?} leaf {leaf} {t:?}"), kind, leaf, t));
                if kind == AccelKind::Brute {
                    break;
                }
            }
        }
    }
    out
}

/// The accelerators of [`plan`] built over `g` (each kind and leaf size built once).
fn configurations(g: &Geometry) -> Vec<Config> {
    let mut out: Vec<Config> = Vec::new();
    let mut built: Option<(AccelKind, usize, Accel)> = None;
    for (name, kind, leaf, t) in plan() {
        if built
            .as_ref()
            .is_none_or(|(k, l, _)| (*k, *l) != (kind, leaf))
        {
            let opts = BuildOptions {
                max_leaf_size: leaf,
                ..Default::default()
            };
            built = Some((kind, leaf, Accel::build_for(kind, g, &opts)));
        }
        let accel = built.as_ref().map(|b| b.2.clone()).expect("built above");
        out.push(Config {
            name,
            accel: accel.with_traversal(t),
        });
    }
    out
}

fn check_ray(scene: &Scene, configs: &[Config], ray: &Ray, oracle: bool) {
    let g = &scene.geometry;
    let wr = WatertightRay::new(ray.dir);
    let brute = &configs[0].accel;
    let stats = &mut TraversalStats::default();
    let expect = oracle.then(|| {
        let frame = Frame::new(ray, &g.bounds());
        let e = Expect::new(&frame, &scene.prims);
        count(3);
        let (must, none) = e.certain();
        if must {
            count(4);
        }
        if none {
            count(5);
        }
        (frame, e)
    });
    for precision in Precision::ALL {
        set_step(Step::Brute(precision));
        let test = |p: u32, r: &Ray| g.intersect_with(precision, p, r, &wr);
        let reference = brute.intersect(ray, stats, test);
        let occluded = brute.occluded(ray, stats, |p, r| test(p, r).is_some());
        let bad = |what: String| fail(scene, ray, &format!("precision {precision}: {what}"));
        if let Some(h) = &reference {
            in_range(ray, h).unwrap_or_else(|w| bad(format!("brute force: {w}")));
        }
        if occluded != reference.is_some() {
            bad(format!(
                "brute force: occluded = {occluded}, intersect = {reference:?}"
            ));
        }
        if let (Some((frame, e)), true) = (&expect, precision != Precision::Fast) {
            e.check(frame, &scene.prims, reference.as_ref(), occluded)
                .unwrap_or_else(|w| bad(format!("brute force: {w}\noracle:\n{}", e.describe())));
        }
        // After the oracle, which says more about a wrong hit than its NaN barycentrics.
        if let Some(h) = &reference {
            finite_barycentrics(h).unwrap_or_else(|w| bad(format!("brute force: {w}")));
        }
        for (i, c) in configs.iter().enumerate() {
            set_step(Step::Config(i, precision));
            let a = &c.accel;
            let answers = [
                (
                    "intersect_geometry",
                    a.intersect_geometry(g, precision, ray, stats),
                ),
                ("intersect", a.intersect(ray, stats, test)),
            ];
            for (query, got) in answers {
                if got != reference {
                    bad(format!(
                        "{} {query} returned {got:?}, brute force {reference:?}",
                        c.name
                    ));
                }
            }
            let occ = [
                (
                    "occluded_geometry",
                    a.occluded_geometry(g, precision, ray, stats),
                ),
                (
                    "occluded",
                    a.occluded(ray, stats, |p, r| test(p, r).is_some()),
                ),
            ];
            for (query, got) in occ {
                if got != occluded {
                    bad(format!(
                        "{} {query} returned {got}, brute force {occluded}",
                        c.name
                    ));
                }
            }
        }
    }
}

/// A hit's `t`: not NaN, finite, in `(t_min, t_max]`.
fn in_range(ray: &Ray, h: &Hit) -> Result<(), String> {
    let t = h.hit.t;
    if !(t.is_finite() && t > ray.t_min && t <= ray.t_max) {
        return Err(format!(
            "t = {t:e} is not finite and in (t_min, t_max]: {h:?}"
        ));
    }
    Ok(())
}

/// A hit's barycentrics: finite (shading interpolates with them).
fn finite_barycentrics(h: &Hit) -> Result<(), String> {
    if !(h.hit.u.is_finite() && h.hit.v.is_finite()) {
        return Err(format!("non-finite barycentrics: {h:?}"));
    }
    Ok(())
}

/// Which query of a ray is running.
#[derive(Clone, Copy)]
enum Step {
    Domain,
    Brute(Precision),
    /// A configuration's index in [`configurations`] and the precision.
    Config(usize, Precision),
}

thread_local! {
    /// The scene and ray being checked, for a panic inside lumis (the fuzz target's hook
    /// prints it). Set once per ray; the step is a cheap copy per query.
    static CONTEXT: RefCell<Option<(Vec<Prim>, Ray)>> = const { RefCell::new(None) };
    static STEP: std::cell::Cell<Step> = const { std::cell::Cell::new(Step::Domain) };
}

fn set_context(scene: &Scene, ray: &Ray) {
    CONTEXT.with(|c| {
        let mut c = c.borrow_mut();
        match c.as_mut() {
            Some((prims, r)) if prims == &scene.prims => *r = *ray,
            _ => *c = Some((scene.prims.clone(), *ray)),
        }
    });
}

fn set_step(step: Step) {
    STEP.with(|s| s.set(step));
}

/// The scene, ray and configuration being checked on this thread, as a report, if any.
pub fn context() -> Option<String> {
    let (prims, ray) = CONTEXT.with(|c| c.borrow().clone())?;
    let scene = Scene::build(&prims)?;
    let what = match STEP.with(|s| s.get()) {
        Step::Domain => "the domain check".to_string(),
        Step::Brute(p) => format!("brute force, {p}"),
        Step::Config(i, p) => format!("{}, {p}", plan()[i].0),
    };
    Some(report(&scene, &ray, &format!("while checking {what}")))
}

/// A self-contained failure report: what went wrong, then Rust that rebuilds the case.
fn report(scene: &Scene, ray: &Ray, what: &str) -> String {
    format!(
        "queries: {what}\n// use lumis_core::geometry::{{Geometry, Mesh, Sphere}}; use lumis_core::math::{{Ray, Vec3}};\n{}{}",
        scene.literal(),
        scene::ray_lit(ray)
    )
}

fn fail(scene: &Scene, ray: &Ray, what: &str) -> ! {
    CONTEXT.with(|c| *c.borrow_mut() = None);
    let report = report(scene, ray, what);
    if only().is_some_and(|o| !report.lines().next().unwrap_or("").contains(o.as_str())) {
        // Another class than the one being minimised: not a failure of this run.
        std::panic::resume_unwind(Box::new(()));
    }
    if survey() {
        // The first report of each class, then on without a crash: `resume_unwind` skips the
        // panic hook (which aborts in the fuzz target), and `check` catches it.
        let class = failure_class(&report);
        let all = std::env::var_os("LUMIS_QUERIES_SURVEY").is_some_and(|v| v == "all");
        if SEEN.lock().unwrap_or_else(|e| e.into_inner()).insert(class) || all {
            eprintln!("{report}\n");
        }
        std::panic::resume_unwind(Box::new(()));
    }
    panic!("{report}")
}

/// `LUMIS_QUERIES_SURVEY=1`: report each class of failure once and keep going instead of
/// stopping at the first (to measure a run and list what fails while bugs are open); `all`:
/// report every failure.
fn survey() -> bool {
    static ON: OnceLock<bool> = OnceLock::new();
    *ON.get_or_init(|| {
        std::env::var_os("LUMIS_QUERIES_SURVEY").is_some_and(|v| v == "1" || v == "all")
    })
}

/// `LUMIS_QUERIES_ONLY=text`: only failures whose first line contains `text` count, others
/// are ignored (for `cargo fuzz tmin`, which would otherwise drift to another class).
fn only() -> Option<&'static String> {
    static ONLY: OnceLock<Option<String>> = OnceLock::new();
    ONLY.get_or_init(|| std::env::var("LUMIS_QUERIES_ONLY").ok())
        .as_ref()
}

/// The failure classes reported so far in survey mode.
static SEEN: Mutex<BTreeSet<String>> = Mutex::new(BTreeSet::new());

/// A failure's class: its first line without the words holding digits (values, indices,
/// leaf sizes).
pub fn failure_class(report: &str) -> String {
    let line = report.lines().next().unwrap_or("");
    line.split_whitespace()
        .filter(|w| !w.chars().any(|c| c.is_ascii_digit()))
        .take(14)
        .collect::<Vec<_>>()
        .join(" ")
}
