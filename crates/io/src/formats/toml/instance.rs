//! `[[instance]]` elements: a `[[mesh]]` or `[[sphere]]` (named by `of`) becomes a prototype,
//! built once and drawn only where instances place it (pbrt's `ObjectBegin`/`ObjectInstance`,
//! Mitsuba's `shapegroup`/`instance`). Elements no instance names are drawn as before.
//!
//! A placement is `translate * rz * ry * rx * scale` (the `[[mesh]]` convention) or a
//! row-major `matrix`, computed in `f64`; `translations` (with optional `rotations` and
//! `scales`) give one placement per entry, named `NAME/k`.

use std::collections::HashMap;

use glam::{DAffine3, DMat3, DVec3};

use super::schema::{InstanceDoc, Scale, SceneDoc};
use super::{Loader, SceneError};
use lumis_core::geometry::Placement;
use lumis_core::scene::Part;

/// The most objects a scene's instances may make (placements times the parts of what they
/// place): each is a transform, a name and a top-level primitive, so a count read from a
/// file is bounded before anything is allocated for it.
pub const MAX_INSTANCE_OBJECTS: usize = 1_000_000;

/// The element an instance's `of` names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Target {
    Sphere(usize),
    Mesh(usize),
}

/// How errors name instance table `i`.
pub(super) fn element(i: usize, d: &InstanceDoc) -> String {
    match &d.name {
        Some(n) => format!("instance[{i}] \"{n}\""),
        None => format!("instance[{i}]"),
    }
}

/// The target of every `[[instance]]`, in order. `of` matches an element's name (its `name`,
/// else its default `sphereN`/`meshN`), which must be unique.
pub(super) fn targets(doc: &SceneDoc, loader: &Loader<'_>) -> Result<Vec<Target>, SceneError> {
    if doc.instance.is_empty() {
        return Ok(Vec::new());
    }
    let mut by_name: HashMap<String, Vec<Target>> = HashMap::new();
    for (i, s) in doc.sphere.iter().enumerate() {
        let name = s.name.clone().unwrap_or_else(|| format!("sphere{i}"));
        by_name.entry(name).or_default().push(Target::Sphere(i));
    }
    for (i, m) in doc.mesh.iter().enumerate() {
        let name = m.name.clone().unwrap_or_else(|| format!("mesh{i}"));
        by_name.entry(name).or_default().push(Target::Mesh(i));
    }
    doc.instance
        .iter()
        .enumerate()
        .map(|(i, d)| match by_name.get(&d.of).map(Vec::as_slice) {
            Some([t]) => Ok(*t),
            Some(many) => Err(loader.err(
                &element(i, d),
                format!(
                    "of = \"{}\": {} elements have that name; an instanced one needs a unique \
                     name",
                    d.of,
                    many.len()
                ),
            )),
            None => {
                let mut known: Vec<&str> = by_name.keys().map(String::as_str).collect();
                known.sort_unstable();
                Err(loader.err(
                    &element(i, d),
                    format!(
                        "of = \"{}\": no [[mesh]] or [[sphere]] has that name (named: {known:?})",
                        d.of
                    ),
                ))
            }
        })
        .collect()
}

impl Loader<'_> {
    /// Makes `parts` (one `(name, shape, material)` each) the prototype of `target`.
    pub(super) fn add_prototype_of(&mut self, target: Target, parts: Vec<Part>) {
        let count = parts.len();
        let id = self.builder.add_prototype(parts);
        self.prototypes.insert(target, (id, count));
    }

    /// Places the prototypes: one instance per placement of every `[[instance]]`.
    pub(super) fn add_instances(
        &mut self,
        docs: &[InstanceDoc],
        targets: &[Target],
    ) -> Result<(), SceneError> {
        let mut objects = 0usize;
        for (i, (d, target)) in docs.iter().zip(targets).enumerate() {
            let e = element(i, d);
            let (prototype, parts) = self.prototypes[target];
            if parts == 0 {
                return Err(self.err(&e, format!("of = \"{}\": it has no geometry", d.of)));
            }
            let count = placement_count(d).map_err(|m| self.err(&e, m))?;
            objects = objects.saturating_add(count.saturating_mul(parts));
            if objects > MAX_INSTANCE_OBJECTS {
                return Err(self.err(
                    &e,
                    format!(
                        "{count} placements of {parts} object(s) bring the scene's instances \
                         to {objects} objects; at most {MAX_INSTANCE_OBJECTS} are allowed"
                    ),
                ));
            }
            let name = d.name.clone().unwrap_or_else(|| format!("instance{i}"));
            for (label, to_world) in placements(d, &name).map_err(|m| self.err(&e, m))? {
                self.builder.add_instance(prototype, label, to_world);
            }
        }
        Ok(())
    }
}

/// How many placements `d` makes, checked before any is computed.
fn placement_count(d: &InstanceDoc) -> Result<usize, String> {
    let Some(ts) = &d.translations else {
        if d.rotations.is_some() || d.scales.is_some() {
            return Err(
                "rotations and scales go with translations (one placement per entry)".into(),
            );
        }
        return Ok(1);
    };
    if d.translate.is_some() || d.rotate.is_some() || d.scale.is_some() || d.matrix.is_some() {
        return Err(
            "translations places many instances, translate/rotate/scale/matrix one: \
                    give one or the other"
                .into(),
        );
    }
    let n = ts.len();
    for (key, len) in [
        ("rotations", d.rotations.as_ref().map(Vec::len)),
        ("scales", d.scales.as_ref().map(Vec::len)),
    ] {
        if let Some(len) = len
            && len != n
        {
            return Err(format!(
                "{key} has {len} entries but translations has {n}: one each per placement"
            ));
        }
    }
    if n == 0 {
        return Err("translations is empty: give at least one placement".into());
    }
    if n > MAX_INSTANCE_OBJECTS {
        return Err(format!(
            "translations has {n} entries; a scene places at most {MAX_INSTANCE_OBJECTS}"
        ));
    }
    Ok(n)
}

/// The named placements of `d` (already counted by [`placement_count`]).
fn placements(d: &InstanceDoc, name: &str) -> Result<Vec<(String, DAffine3)>, String> {
    let Some(ts) = &d.translations else {
        let to_world = match &d.matrix {
            Some(m) => {
                if d.translate.is_some() || d.rotate.is_some() || d.scale.is_some() {
                    return Err("matrix is the whole placement: give it without \
                                translate, rotate or scale"
                        .into());
                }
                matrix(m)?
            }
            None => trs("", d.translate, d.rotate, d.scale)?,
        };
        return Ok(vec![(name.to_owned(), to_world)]);
    };
    let mut out = Vec::with_capacity(ts.len());
    for (k, t) in ts.iter().enumerate() {
        let r = d.rotations.as_ref().map(|r| r[k]);
        let s = d.scales.as_ref().map(|s| s[k]);
        out.push((
            format!("{name}/{k}"),
            trs(&format!("[{k}]"), Some(*t), r, s)?,
        ));
    }
    Ok(out)
}

/// `translate * rz * ry * rx * scale` in `f64`; `at` is `[k]` for an array entry (errors
/// then name `translations[k]`, ...) and empty for a single placement.
fn trs(
    at: &str,
    t: Option<[f32; 3]>,
    r: Option<[f32; 3]>,
    s: Option<Scale>,
) -> Result<DAffine3, String> {
    // A single placement's keys, or `translations[k]`, ... for entry k of the arrays.
    let key = |single: &str, array: &str| {
        if at.is_empty() {
            single.to_owned()
        } else {
            format!("{array}{at}")
        }
    };
    let t = t.unwrap_or([0.0; 3]);
    let r = r.unwrap_or([0.0; 3]);
    let s = match s {
        None => [1.0; 3],
        Some(Scale::Uniform(s)) => [s; 3],
        Some(Scale::PerAxis(s)) => s,
    };
    for (single, array, v) in [
        ("translate", "translations", t),
        ("rotate", "rotations", r),
        ("scale", "scales", s),
    ] {
        if !v.iter().all(|x| x.is_finite()) {
            return Err(format!("{} {v:?} must be finite", key(single, array)));
        }
    }
    if s.contains(&0.0) {
        return Err(format!("{} {s:?} must be non-zero", key("scale", "scales")));
    }
    let v = |a: [f32; 3]| DVec3::from(a.map(f64::from));
    let [rx, ry, rz] = r.map(|a| f64::from(a).to_radians());
    let to_world = DAffine3::from_translation(v(t))
        * DAffine3::from_rotation_z(rz)
        * DAffine3::from_rotation_y(ry)
        * DAffine3::from_rotation_x(rx)
        * DAffine3::from_scale(v(s));
    check(to_world)?;
    Ok(to_world)
}

/// The placement of a row-major 4x4 `matrix` whose last row is `0 0 0 1`.
fn matrix(m: &[f64]) -> Result<DAffine3, String> {
    let m: &[f64; 16] = m.try_into().map_err(|_| {
        format!(
            "matrix has {} numbers: expected 16, a row-major 4x4 with last row 0 0 0 1",
            m.len()
        )
    })?;
    if !m.iter().all(|x| x.is_finite()) {
        return Err("matrix must be finite".into());
    }
    if m[12..] != [0.0, 0.0, 0.0, 1.0] {
        return Err(format!(
            "matrix's last row is {:?}: expected [0, 0, 0, 1] (an affine placement)",
            &m[12..]
        ));
    }
    let to_world = DAffine3 {
        matrix3: DMat3::from_cols(
            DVec3::new(m[0], m[4], m[8]),
            DVec3::new(m[1], m[5], m[9]),
            DVec3::new(m[2], m[6], m[10]),
        ),
        translation: DVec3::new(m[3], m[7], m[11]),
    };
    check(to_world).map_err(|e| format!("matrix: {e}"))?;
    Ok(to_world)
}

/// The core's own test (finite and invertible), here so the error names the table.
fn check(to_world: DAffine3) -> Result<(), String> {
    Placement::new(to_world)
        .map(|_| ())
        .map_err(|e| e.to_string())
}

#[cfg(test)]
#[path = "instance_tests.rs"]
mod tests;
