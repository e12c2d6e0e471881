//! The keys of `[animation]`, checked one by one (each error names its key) and gathered into
//! one [`Track`] per animated field.

use std::collections::HashMap;
use std::path::Path;

use super::super::schema::{
    AnimationDoc, CameraKeyDoc, InterpolationDoc, MeshKeyDoc, SceneDoc, SphereKeyDoc,
};
use super::{CameraTracks, ObjectTracks, camera_key, range};
use crate::formats::SceneError;
use lumis_core::math::Vec3;
use lumis_core::scene::animation::{Interpolation, Key, Track};
use lumis_core::scene::limits::check_point;

/// The keys of one `[animation]` table, checked into tracks.
pub(super) struct Keys<'a> {
    pub(super) a: &'a AnimationDoc,
    pub(super) origin: &'a Path,
}

impl Keys<'_> {
    fn err(&self, element: &str, message: impl Into<String>) -> SceneError {
        SceneError::invalid(self.origin, element, message)
    }

    /// A key's interpolation: its own, else the table's, else linear.
    fn interpolation(&self, own: Option<InterpolationDoc>) -> Interpolation {
        match own.or(self.a.interpolation) {
            None | Some(InterpolationDoc::Linear) => Interpolation::Linear,
            Some(InterpolationDoc::Step) => Interpolation::Step,
        }
    }

    /// Checks that key `element` lies in the frame range and that no earlier key of the same
    /// target (`earlier`: their names by frame) sits on its frame; records it there.
    fn placed(
        &self,
        element: &str,
        frame: u32,
        earlier: &mut HashMap<u32, String>,
    ) -> Result<(), SceneError> {
        if frame >= self.a.frames {
            return Err(self.err(
                element,
                format!(
                    "frame {frame} is outside the animation: {}",
                    range(self.a.frames)
                ),
            ));
        }
        if let Some(other) = earlier.get(&frame) {
            return Err(self.err(
                element,
                format!("frame {frame} is keyed twice (also by {other})"),
            ));
        }
        earlier.insert(frame, element.to_owned());
        Ok(())
    }

    pub(super) fn camera(&self, doc: &SceneDoc) -> Result<CameraTracks, SceneError> {
        let keys = &self.a.camera;
        let mut earlier = HashMap::new();
        for (i, k) in keys.iter().enumerate() {
            let e = camera_key(i, k.frame);
            self.placed(&e, k.frame, &mut earlier)?;
            check_camera_key(k).map_err(|m| self.err(&e, m))?;
            if doc.camera.is_none() {
                return Err(self.err(
                    &e,
                    "camera keys animate the [camera] table, and the scene has none; give one \
                     (the fields no key animates come from it)",
                ));
            }
        }
        let track3 = |f: fn(&CameraKeyDoc) -> Option<[f32; 3]>| {
            self.track(keys.iter().map(|k| (k.frame, f(k), k.interpolation)))
        };
        let track1 = |f: fn(&CameraKeyDoc) -> Option<f32>| {
            self.track(
                keys.iter()
                    .map(|k| (k.frame, f(k).map(|v| [v]), k.interpolation)),
            )
        };
        Ok(CameraTracks {
            position: track3(|k| k.position)?,
            look_at: track3(|k| k.look_at)?,
            up: track3(|k| k.up)?,
            fov: track1(|k| k.fov)?,
            aperture: track1(|k| k.aperture)?,
            focus_distance: track1(|k| k.focus_distance)?,
            height: track1(|k| k.height)?,
        })
    }

    pub(super) fn spheres(&self, doc: &SceneDoc) -> Result<Vec<ObjectTracks>, SceneError> {
        let names = Names::of(doc.sphere.iter().map(|s| s.name.as_deref()));
        let keys = &self.a.sphere;
        let element = |i: usize, k: &SphereKeyDoc| {
            format!("animation.sphere[{i}] \"{}\" (frame {})", k.name, k.frame)
        };
        let mut out = Vec::new();
        for (name, members) in group(keys.iter().map(|k| k.name.as_str())) {
            let index = self.target(
                &element(members[0], &keys[members[0]]),
                "sphere",
                &names,
                name,
            )?;
            let mut earlier = HashMap::new();
            for &i in &members {
                let (k, e) = (&keys[i], element(i, &keys[i]));
                self.placed(&e, k.frame, &mut earlier)?;
                check_sphere_key(k).map_err(|m| self.err(&e, m))?;
            }
            let of = |i: &usize| &keys[*i];
            out.push(ObjectTracks {
                index,
                name: name.to_owned(),
                point: self.track(
                    members
                        .iter()
                        .map(of)
                        .map(|k| (k.frame, k.center, k.interpolation)),
                )?,
                size: self.track(
                    members
                        .iter()
                        .map(of)
                        .map(|k| (k.frame, k.radius.map(|r| [r]), k.interpolation)),
                )?,
                angles: None,
            });
        }
        Ok(out)
    }

    pub(super) fn meshes(&self, doc: &SceneDoc) -> Result<Vec<ObjectTracks>, SceneError> {
        let names = Names::of(doc.mesh.iter().map(|m| m.name.as_deref()));
        self.placed_objects("mesh", &names, &self.a.mesh, |_| Ok(()))
    }

    /// The tracks of `[[animation.instance]]`: only an instance of one `translate`/`rotate`
    /// placement can be keyed (keys give those two fields).
    pub(super) fn instances(&self, doc: &SceneDoc) -> Result<Vec<ObjectTracks>, SceneError> {
        let names = Names::of(doc.instance.iter().map(|d| d.name.as_deref()));
        self.placed_objects("instance", &names, &self.a.instance, |i| {
            let d = &doc.instance[i];
            let by = if d.translations.is_some() {
                "translations (one instance per entry)"
            } else if d.matrix.is_some() {
                "a matrix"
            } else {
                return Ok(());
            };
            Err(format!(
                "the [[instance]] is placed by {by}; keys animate the translate and rotate of                  an instance placed by translate/rotate/scale"
            ))
        })
    }

    /// The `translate` and `rotate` tracks of `keys` on the `[[kind]]` elements `names` names;
    /// `keyable` says why an element cannot take keys.
    fn placed_objects(
        &self,
        kind: &str,
        names: &Names<'_>,
        keys: &[MeshKeyDoc],
        keyable: impl Fn(usize) -> Result<(), String>,
    ) -> Result<Vec<ObjectTracks>, SceneError> {
        let mut out = Vec::new();
        for (name, members) in group(keys.iter().map(|k| k.name.as_str())) {
            let e =
                |i: usize| format!("animation.{kind}[{i}] \"{name}\" (frame {})", keys[i].frame);
            let index = self.target(&e(members[0]), kind, names, name)?;
            keyable(index).map_err(|m| self.err(&e(members[0]), m))?;
            let mut earlier = HashMap::new();
            for &i in &members {
                let k = &keys[i];
                self.placed(&e(i), k.frame, &mut earlier)?;
                check_mesh_key(k).map_err(|m| self.err(&e(i), m))?;
            }
            let of = |i: &usize| &keys[*i];
            out.push(ObjectTracks {
                index,
                name: name.to_owned(),
                point: self.track(
                    members
                        .iter()
                        .map(of)
                        .map(|k| (k.frame, k.translate, k.interpolation)),
                )?,
                size: None,
                angles: self.track(
                    members
                        .iter()
                        .map(of)
                        .map(|k| (k.frame, k.rotate, k.interpolation)),
                )?,
            });
        }
        Ok(out)
    }

    /// The index of the one `[[kind]]` element named `name`.
    fn target(
        &self,
        element: &str,
        kind: &str,
        names: &Names<'_>,
        name: &str,
    ) -> Result<usize, SceneError> {
        let matching = names.0.get(name).map_or(&[][..], Vec::as_slice);
        match matching {
            [index] => Ok(*index),
            [] => {
                let mut known: Vec<&str> = names.0.keys().copied().collect();
                known.sort_unstable();
                Err(self.err(
                    element,
                    format!("no [[{kind}]] is named \"{name}\" (named: {known:?})"),
                ))
            }
            _ => Err(self.err(
                element,
                format!(
                    "{} [[{kind}]] elements are named \"{name}\"; an animated one needs a \
                     unique name",
                    matching.len()
                ),
            )),
        }
    }

    /// The track of the keys that give a value (frame, value if given, own interpolation).
    fn track<const N: usize>(
        &self,
        keys: impl Iterator<Item = (u32, Option<[f32; N]>, Option<InterpolationDoc>)>,
    ) -> Result<Option<Track<N>>, SceneError> {
        let keys = keys
            .filter_map(|(frame, value, own)| {
                Some(Key {
                    frame,
                    value: value?,
                    interpolation: self.interpolation(own),
                })
            })
            .collect();
        // Frames and values were checked key by key, with the key's name, above.
        Track::new(keys).map_err(|e| self.err("animation", e.to_string()))
    }
}

/// The elements of one array (`[[sphere]]`, `[[mesh]]`, `[[instance]]`) by name.
struct Names<'a>(HashMap<&'a str, Vec<usize>>);

impl<'a> Names<'a> {
    fn of(names: impl Iterator<Item = Option<&'a str>>) -> Self {
        let mut by_name: HashMap<&str, Vec<usize>> = HashMap::new();
        for (i, name) in names.enumerate() {
            if let Some(name) = name {
                by_name.entry(name).or_default().push(i);
            }
        }
        Self(by_name)
    }
}

/// Key indices grouped by target name, in order of first appearance.
fn group<'a>(names: impl Iterator<Item = &'a str>) -> Vec<(&'a str, Vec<usize>)> {
    let mut groups: Vec<(&str, Vec<usize>)> = Vec::new();
    let mut slot: HashMap<&str, usize> = HashMap::new();
    for (i, name) in names.enumerate() {
        let g = *slot.entry(name).or_insert_with(|| {
            groups.push((name, Vec::new()));
            groups.len() - 1
        });
        groups[g].1.push(i);
    }
    groups
}

/// Why a camera key's values cannot pose a camera (the checks `[camera]` has, key by key; the
/// combination at each frame is checked when the camera is built).
fn check_camera_key(k: &CameraKeyDoc) -> Result<(), String> {
    let given = [
        k.position.is_some(),
        k.look_at.is_some(),
        k.up.is_some(),
        k.fov.is_some(),
        k.aperture.is_some(),
        k.focus_distance.is_some(),
        k.height.is_some(),
    ];
    if !given.contains(&true) {
        return Err(
            "the key animates nothing: give at least one of position, look_at, up, fov, \
                    aperture, focus_distance, height"
                .into(),
        );
    }
    for (field, p) in [("position", k.position), ("look_at", k.look_at)] {
        p.map_or(Ok(()), |p| point(field, p))?;
    }
    if let Some(up) = k.up {
        finite("up", &up)?;
        if Vec3::from(up) == Vec3::ZERO {
            return Err("up must be non-zero".into());
        }
    }
    if let Some(fov) = k.fov
        && !(fov > 0.0 && fov < 180.0)
    {
        return Err(format!(
            "fov {fov} must lie strictly between 0 and 180 degrees"
        ));
    }
    if let Some(a) = k.aperture
        && !(a >= 0.0 && a.is_finite())
    {
        return Err(format!("aperture {a} must be finite and >= 0"));
    }
    for (field, v) in [("focus_distance", k.focus_distance), ("height", k.height)] {
        if let Some(v) = v
            && !(v > 0.0 && v.is_finite())
        {
            return Err(format!("{field} {v} must be finite and > 0"));
        }
    }
    Ok(())
}

/// Why a sphere key's values cannot pose a sphere.
fn check_sphere_key(k: &SphereKeyDoc) -> Result<(), String> {
    if k.center.is_none() && k.radius.is_none() {
        return Err("the key animates nothing: give center or radius".into());
    }
    k.center.map_or(Ok(()), |c| point("center", c))?;
    match k.radius {
        Some(r) if !(r > 0.0 && r.is_finite()) => Err(format!("radius {r} must be > 0")),
        _ => Ok(()),
    }
}

/// Why a mesh (or instance) key's values cannot pose it.
fn check_mesh_key(k: &MeshKeyDoc) -> Result<(), String> {
    if k.translate.is_none() && k.rotate.is_none() {
        return Err("the key animates nothing: give translate or rotate".into());
    }
    k.translate.map_or(Ok(()), |t| point("translate", t))?;
    k.rotate.map_or(Ok(()), |r| finite("rotate", &r))
}

/// A point: finite and within the coordinate limit.
fn point(field: &str, p: [f32; 3]) -> Result<(), String> {
    finite(field, &p)?;
    check_point(field, Vec3::from(p))
}

fn finite(field: &str, v: &[f32]) -> Result<(), String> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(format!("{field} {v:?} must be finite"))
    }
}
