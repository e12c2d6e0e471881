//! `[animation]` (docs/scene-format.md, "Animation"): the keys are checked, then the document
//! is posed at one frame, so the rest of the loader builds a still exactly as if the posed
//! values had been written into `[camera]`, `[[sphere]]`, `[[mesh]]` and `[[instance]]` by
//! hand.
//!
//! Each animated field is its own [`Track`] over the keys that give it (Blender's F-curves,
//! glTF's channels): a key may move the `position` alone and leave `fov` to other keys. Fields
//! no key gives keep the value the element itself has.

use std::path::Path;

mod keys;

use super::Override;
use super::schema::{CameraDoc, FpsDoc, SceneDoc};
use crate::formats::SceneError;
use keys::Keys;
use lumis_core::scene::animation::{Frame, FrameRate, MAX_FRAMES, Track};

/// The checked animation of a document and the frame it is posed at.
pub(super) struct Animation {
    frame: Frame,
    camera: CameraTracks,
    /// The frame of each `[[animation.camera]]` key, in file order (to name a frame's key).
    camera_keys: Vec<u32>,
    spheres: Vec<ObjectTracks>,
    meshes: Vec<ObjectTracks>,
    instances: Vec<ObjectTracks>,
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

/// The tracks of one named sphere (`center`, `radius`), mesh or instance (`translate`,
/// `rotate`).
struct ObjectTracks {
    /// Index into the document's `sphere`, `mesh` or `instance` array.
    index: usize,
    /// The element's name, for `-D sphere.NAME.*`.
    name: String,
    /// `center` or `translate`.
    point: Option<Track<3>>,
    /// `radius` (spheres; `rotate` for meshes is in `angles`).
    size: Option<Track<1>>,
    /// `rotate` (meshes, instances).
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
            instances: keys.instances(doc)?,
        }))
    }

    /// The frame the document is posed at.
    pub(super) fn frame(&self) -> Frame {
        self.frame
    }

    /// Writes the animated sphere, mesh and instance fields at the frame into `doc` (the document
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
        for t in &self.instances {
            if let Some(d) = doc.instance.get_mut(t.index) {
                d.translate = t.point.as_ref().map(|p| p.sample(f)).or(d.translate);
                d.rotate = t.angles.as_ref().map(|r| r.sample(f)).or(d.rotate);
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
                ["instance", element, field] => find(&self.instances, element).is_some_and(|t| {
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
