//! The node hierarchy: world transforms (parent x child, TRS or matrix), and the lights and
//! cameras that nodes carry. A node's local frame looks down -Z with +Y up; lights shine
//! along -Z.

use std::path::Path;

use super::super::SceneError;
use crate::camera::Camera;
use crate::light::Light;
use crate::math::{Mat4, Vec3};

/// A node reached from the chosen scene, with its world transform.
pub(super) struct Placed<'a> {
    /// The node.
    pub node: gltf::Node<'a>,
    /// Node space to world space.
    pub world: Mat4,
}

/// Every node of scene `choice` (default: the file's `scene`, else scene 0, else every root
/// node) depth first in file order, with world transforms. A node reached twice (a cycle, or a
/// child of two parents, both invalid glTF) and a non-finite transform are errors.
pub(super) fn flatten<'a>(
    doc: &'a gltf::Document,
    choice: Option<usize>,
    origin: &Path,
) -> Result<Vec<Placed<'a>>, SceneError> {
    let roots: Vec<gltf::Node> = match choice {
        Some(i) => doc
            .scenes()
            .nth(i)
            .ok_or_else(|| {
                SceneError::invalid(
                    origin,
                    "scenes",
                    format!(
                        "scene {i} was asked for, but the file has {}",
                        doc.scenes().len()
                    ),
                )
            })?
            .nodes()
            .collect(),
        None => match doc.default_scene().or_else(|| doc.scenes().next()) {
            Some(scene) => scene.nodes().collect(),
            None => {
                let mut child = vec![false; doc.nodes().len()];
                for n in doc.nodes().flat_map(|n| n.children()) {
                    child[n.index()] = true;
                }
                doc.nodes().filter(|n| !child[n.index()]).collect()
            }
        },
    };
    let mut seen = vec![false; doc.nodes().len()];
    let mut out = Vec::new();
    // An explicit stack: a long chain of nodes must not overflow the call stack.
    let mut stack: Vec<(gltf::Node, Mat4)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, Mat4::IDENTITY))
        .collect();
    while let Some((node, parent)) = stack.pop() {
        let element = format!("nodes[{}]", node.index());
        if std::mem::replace(&mut seen[node.index()], true) {
            return Err(SceneError::invalid(
                origin,
                element,
                "is reached twice: the hierarchy has a cycle or a node with two parents",
            ));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if !world.is_finite() {
            return Err(SceneError::invalid(
                origin,
                element,
                "the world transform is not finite",
            ));
        }
        let children: Vec<gltf::Node> = node.children().collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world)));
        out.push(Placed { node, world });
    }
    Ok(out)
}

/// A `KHR_lights_punctual` light placed by `world`. Units: intensity in candela (point, spot)
/// becomes lumis radiant intensity one to one, lux (directional) becomes irradiance one to one;
/// `range` is ignored (lights fall off as 1/d^2 without a cut-off).
pub(super) fn light(
    l: &gltf::khr_lights_punctual::Light,
    world: &Mat4,
    element: &str,
    origin: &Path,
) -> Result<Light, SceneError> {
    let err = |m: String| SceneError::invalid(origin, element, m);
    let color = Vec3::from(l.color());
    if !color.is_finite() || color.min_element() < 0.0 || l.intensity() < 0.0 {
        return Err(err(format!(
            "color {:?} and intensity {} must be >= 0",
            l.color(),
            l.intensity()
        )));
    }
    let power = color * l.intensity();
    let position = world.transform_point3(Vec3::ZERO);
    let direction = world.transform_vector3(-Vec3::Z).try_normalize();
    let direction = || direction.ok_or_else(|| err("the node's -Z axis is degenerate".into()));
    Ok(match l.kind() {
        gltf::khr_lights_punctual::Kind::Point => Light::Point {
            position,
            intensity: power,
        },
        gltf::khr_lights_punctual::Kind::Directional => Light::Directional {
            direction: direction()?,
            irradiance: power,
        },
        gltf::khr_lights_punctual::Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => {
            let half_pi = std::f32::consts::FRAC_PI_2;
            if !(0.0..=half_pi).contains(&outer_cone_angle)
                || !(0.0..=outer_cone_angle).contains(&inner_cone_angle)
            {
                return Err(err(format!(
                    "cone angles inner {inner_cone_angle}, outer {outer_cone_angle} must satisfy \
                     0 <= inner <= outer <= pi/2"
                )));
            }
            Light::Spot {
                position,
                direction: direction()?,
                intensity: power,
                cos_inner: inner_cone_angle.cos(),
                cos_outer: outer_cone_angle.cos(),
            }
        }
    })
}

/// A perspective camera at `world`'s origin looking down its -Z with its +Y up; the aspect
/// ratio the file gives, if any. `None` for orthographic cameras (lumis has no such camera).
pub(super) fn camera(
    c: &gltf::Camera,
    world: &Mat4,
    element: &str,
    origin: &Path,
) -> Result<Option<(Camera, Option<f32>)>, SceneError> {
    let gltf::camera::Projection::Perspective(p) = c.projection() else {
        return Ok(None);
    };
    let position = world.transform_point3(Vec3::ZERO);
    let forward = world.transform_vector3(-Vec3::Z);
    let up = world.transform_vector3(Vec3::Y);
    let camera = Camera::look_at(
        position,
        position + forward,
        up,
        p.yfov().to_degrees(),
        0.0,
        None,
    )
    .map_err(|e| SceneError::invalid(origin, element, e.to_string()))?;
    let aspect = p.aspect_ratio().filter(|a| *a > 0.0 && a.is_finite());
    Ok(Some((camera, aspect)))
}
