//! `[animation]` (docs/scene-format.md, "Animation"): the keys are checked, then the document
//! is posed at one frame, so the rest of the loader builds a still exactly as if the posed
//! values had been written into `[camera]`, `[[sphere]]` and `[[mesh]]` by hand.
//!
//! Each animated field is its own [`Track`] over the keys that give it (Blender's F-curves,
//! glTF's channels): a key may move the `position` alone and leave `fov` to other keys. Fields
//! no key gives keep the value the element itself has.

use std::path::Path;

use super::Override;
use super::schema::{
    AnimationDoc, CameraDoc, CameraKeyDoc, FpsDoc, InterpolationDoc, SceneDoc, SphereKeyDoc,
};
use crate::formats::SceneError;
use crate::math::Vec3;
use crate::scene::animation::{Frame, FrameRate, Interpolation, Key, MAX_FRAMES, Track};
use crate::scene::limits::check_point;

/// The checked animation of a document and the frame it is posed at.
pub(super) struct Animation {
    frame: Frame,
    camera: CameraTracks,
    /// The frame of each `[[animation.camera]]` key, in file order (to name a frame's key).
    camera_keys: Vec<u32>,
    spheres: Vec<ObjectTracks>,
    meshes: Vec<ObjectTracks>,
}

/// The tracks of the `[camera]` fields that keys animate.
#[derive(Default)]
struct CameraTracks {
    position: Option<Track<3>>,
    look_at: Option<Track<3>>,
    up: Option<Track<3>>,
    fov: Option<Track<1>>,
    aperture: Option<Track<1>>,
    focus_distance: Option<Track<1>>,
    height: Option<Track<1>>,
}

/// The tracks of one named sphere (`center`, `radius`) or mesh (`translate`, `rotate`).
struct ObjectTracks {
    /// Index into the document's `sphere` or `mesh` array.
    index: usize,
    /// The element's name, for `-D sphere.NAME.*`.
    name: String,
    /// `center` or `translate`.
    point: Option<Track<3>>,
    /// `radius` (spheres; `rotate` for meshes is in `angles`).
    size: Option<Track<1>>,
    /// `rotate` (meshes).
    angles: Option<Track<3>>,
}

impl Animation {
    /// Checks `doc`'s `[animation]` and picks the frame: `requested` (`--frame`), else 0.
    /// `None` for a still; asking a still for a frame is an error.
    pub(super) fn new(
        doc: &SceneDoc,
        requested: Option<u32>,
        origin: &Path,
    ) -> Result<Option<Self>, SceneError> {
        let err = |element: &str, message: String| SceneError::invalid(origin, element, message);
        let Some(a) = &doc.animation else {
            return match requested {
                None => Ok(None),
                Some(f) => Err(err(
                    &format!("--frame {f}"),
                    "the scene has no [animation] table, so it has no frames; render it \
                     without --frame, or give it `[animation] frames = N`"
                        .into(),
                )),
            };
        };
        if a.frames == 0 || a.frames > MAX_FRAMES {
            return Err(err(
                "animation",
                format!("frames = {}: expected 1..={MAX_FRAMES}", a.frames),
            ));
        }
        let rate = match a.fps {
            None => Ok(FrameRate::FILM),
            Some(FpsDoc::Whole(n)) => FrameRate::new(n, 1),
            Some(FpsDoc::Ratio([n, d])) => FrameRate::new(n, d),
        }
        .map_err(|m| err("animation", m))?;
        let number = requested.unwrap_or(0);
        if number >= a.frames {
            return Err(err(
                &format!("--frame {number}"),
                format!("out of range: {}", range(a.frames)),
            ));
        }
        let frame = Frame::new(number, a.frames, rate).map_err(|m| err("animation", m))?;
        let keys = Keys { a, origin };
        Ok(Some(Self {
            frame,
            camera: keys.camera(doc)?,
            camera_keys: a.camera.iter().map(|k| k.frame).collect(),
            spheres: keys.spheres(doc)?,
            meshes: keys.meshes(doc)?,
        }))
    }

    /// The frame the document is posed at.
    pub(super) fn frame(&self) -> Frame {
        self.frame
    }

    /// Writes the animated sphere and mesh fields at the frame into `doc` (the document
    /// [`Animation::new`] checked).
    pub(super) fn pose_objects(&self, doc: &mut SceneDoc) {
        let f = self.frame.number();
        for t in &self.spheres {
            if let Some(s) = doc.sphere.get_mut(t.index) {
                s.center = t.point.as_ref().map_or(s.center, |p| p.sample(f));
                s.radius = t.size.as_ref().map_or(s.radius, |r| r.sample(f)[0]);
            }
        }
        for t in &self.meshes {
            if let Some(m) = doc.mesh.get_mut(t.index) {
                m.translate = t.point.as_ref().map(|p| p.sample(f)).or(m.translate);
                m.rotate = t.angles.as_ref().map(|r| r.sample(f)).or(m.rotate);
            }
        }
    }

    /// Whether any key moves the camera (then every frame's camera is checked on load).
    pub(super) fn animates_camera(&self) -> bool {
        !self.camera_keys.is_empty()
    }

    /// `[camera]` as `base` with the animated fields at `frame`.
    pub(super) fn camera_at(&self, base: &CameraDoc, frame: u32) -> CameraDoc {
        let c = &self.camera;
        let v3 = |t: &Option<Track<3>>| t.as_ref().map(|t| t.sample(frame));
        let v1 = |t: &Option<Track<1>>| t.as_ref().map(|t| t.sample(frame)[0]);
        CameraDoc {
            position: v3(&c.position).unwrap_or(base.position),
            look_at: v3(&c.look_at).unwrap_or(base.look_at),
            up: v3(&c.up).or(base.up),
            fov: v1(&c.fov).or(base.fov),
            aperture: v1(&c.aperture).or(base.aperture),
            focus_distance: v1(&c.focus_distance).or(base.focus_distance),
            height: v1(&c.height).or(base.height),
            ..base.clone()
        }
    }

    /// How errors name the camera at `frame`: its key when one sits there.
    pub(super) fn camera_element(&self, frame: u32) -> String {
        match self.camera_keys.iter().position(|&k| k == frame) {
            Some(i) => camera_key(i, frame),
            None => format!("animation.camera at frame {frame}"),
        }
    }

    /// Warnings for `-D` overrides of fields that keys animate: the keys win, so the override
    /// would change nothing.
    pub(super) fn shadowed(&self, overrides: &[Override], origin: &Path) -> Vec<String> {
        let c = &self.camera;
        let mut out = Vec::new();
        for o in overrides {
            let path: Vec<&str> = o.key().split('.').collect();
            let animated = match path[..] {
                ["camera", field] => match field {
                    "position" => c.position.is_some(),
                    "look_at" => c.look_at.is_some(),
                    "up" => c.up.is_some(),
                    "fov" => c.fov.is_some(),
                    "aperture" => c.aperture.is_some(),
                    "focus_distance" => c.focus_distance.is_some(),
                    "height" => c.height.is_some(),
                    _ => false,
                },
                ["sphere", element, field] => find(&self.spheres, element).is_some_and(|t| {
                    (field == "center" && t.point.is_some())
                        || (field == "radius" && t.size.is_some())
                }),
                ["mesh", element, field] => find(&self.meshes, element).is_some_and(|t| {
                    (field == "translate" && t.point.is_some())
                        || (field == "rotate" && t.angles.is_some())
                }),
                _ => false,
            };
            if animated {
                let table = path[0];
                out.push(format!(
                    "{}: -D {o}: keys in [[animation.{table}]] animate this field and win over \
                     it; override a key instead (-D animation.{table}.N.{})",
                    origin.display(),
                    path[path.len() - 1]
                ));
            }
        }
        out
    }
}

/// The animated object `element` names in a `-D` key: an index into the array or a name.
fn find<'a>(tracks: &'a [ObjectTracks], element: &str) -> Option<&'a ObjectTracks> {
    match element.parse::<usize>() {
        Ok(i) => tracks.iter().find(|t| t.index == i),
        Err(_) => tracks.iter().find(|t| t.name == element),
    }
}

/// `frames = N numbers them 0..=N-1`.
fn range(frames: u32) -> String {
    format!(
        "[animation] frames = {frames} numbers them 0..={}",
        frames - 1
    )
}

/// How errors name camera key `i`.
fn camera_key(i: usize, frame: u32) -> String {
    format!("animation.camera[{i}] (frame {frame})")
}

/// The keys of one `[animation]` table, checked into tracks.
struct Keys<'a> {
    a: &'a AnimationDoc,
    origin: &'a Path,
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
    /// target (`earlier`: their frames and names) sits on its frame.
    fn placed(
        &self,
        element: &str,
        frame: u32,
        earlier: &[(u32, String)],
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
        if let Some((_, other)) = earlier.iter().find(|(f, _)| *f == frame) {
            return Err(self.err(
                element,
                format!("frame {frame} is keyed twice (also by {other})"),
            ));
        }
        Ok(())
    }

    fn camera(&self, doc: &SceneDoc) -> Result<CameraTracks, SceneError> {
        let keys = &self.a.camera;
        let mut earlier = Vec::new();
        for (i, k) in keys.iter().enumerate() {
            let e = camera_key(i, k.frame);
            self.placed(&e, k.frame, &earlier)?;
            check_camera_key(k).map_err(|m| self.err(&e, m))?;
            if doc.camera.is_none() {
                return Err(self.err(
                    &e,
                    "camera keys animate the [camera] table, and the scene has none; give one \
                     (the fields no key animates come from it)",
                ));
            }
            earlier.push((k.frame, e));
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

    fn spheres(&self, doc: &SceneDoc) -> Result<Vec<ObjectTracks>, SceneError> {
        let names: Vec<Option<&str>> = doc.sphere.iter().map(|s| s.name.as_deref()).collect();
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
            let mut earlier = Vec::new();
            for &i in &members {
                let (k, e) = (&keys[i], element(i, &keys[i]));
                self.placed(&e, k.frame, &earlier)?;
                check_sphere_key(k).map_err(|m| self.err(&e, m))?;
                earlier.push((k.frame, e));
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

    fn meshes(&self, doc: &SceneDoc) -> Result<Vec<ObjectTracks>, SceneError> {
        let names: Vec<Option<&str>> = doc.mesh.iter().map(|m| m.name.as_deref()).collect();
        let keys = &self.a.mesh;
        let mut out = Vec::new();
        for (name, members) in group(keys.iter().map(|k| k.name.as_str())) {
            let e = |i: usize| format!("animation.mesh[{i}] \"{name}\" (frame {})", keys[i].frame);
            let index = self.target(&e(members[0]), "mesh", &names, name)?;
            let mut earlier = Vec::new();
            for &i in &members {
                let k = &keys[i];
                self.placed(&e(i), k.frame, &earlier)?;
                let checked = match (k.translate, k.rotate) {
                    (None, None) => {
                        Err("the key animates nothing: give translate or rotate".into())
                    }
                    (t, r) => t
                        .map_or(Ok(()), |t| point("translate", t))
                        .and_then(|()| r.map_or(Ok(()), |r| finite("rotate", &r))),
                };
                checked.map_err(|m| self.err(&e(i), m))?;
                earlier.push((k.frame, e(i)));
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

    /// The index of the one `[[kind]]` element named `name` (`names`: every element's name).
    fn target(
        &self,
        element: &str,
        kind: &str,
        names: &[Option<&str>],
        name: &str,
    ) -> Result<usize, SceneError> {
        let matching: Vec<usize> = (0..names.len())
            .filter(|&i| names[i] == Some(name))
            .collect();
        match matching[..] {
            [index] => Ok(index),
            [] => {
                let mut known: Vec<&str> = names.iter().flatten().copied().collect();
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

/// Key indices grouped by target name, in order of first appearance.
fn group<'a>(names: impl Iterator<Item = &'a str>) -> Vec<(&'a str, Vec<usize>)> {
    let mut groups: Vec<(&str, Vec<usize>)> = Vec::new();
    for (i, name) in names.enumerate() {
        match groups.iter_mut().find(|(n, _)| *n == name) {
            Some((_, members)) => members.push(i),
            None => groups.push((name, vec![i])),
        }
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
