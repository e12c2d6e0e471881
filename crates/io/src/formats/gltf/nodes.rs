//! The node hierarchy: world transforms (parent x child, TRS or matrix), and the lights and
//! cameras that nodes carry. A node's local frame looks down -Z with +Y up; lights shine
//! along -Z.

use std::path::Path;

use super::super::SceneError;
use lumis_core::camera::Camera;
use lumis_core::light::{LUMENS_PER_WATT, Light};
use lumis_core::math::{Mat4, Vec3};

/// A node reached from the chosen scene, with its world transform.
pub(super) struct Placed<'a> {
    /// The node.
    pub node: gltf::Node<'a>,
    /// Node space to world space.
    pub world: Mat4,
}

/// Every node of scene `choice` (default: the file's `scene`, else scene 0, else every root
/// node) depth first in file order, with world transforms: `root` (the up-axis turn) times the
/// node hierarchy. A node reached twice (a cycle, or a child of two parents, both invalid glTF)
/// and a non-finite transform are errors.
pub(super) fn flatten<'a>(
    doc: &'a gltf::Document,
    choice: Option<usize>,
    root: Mat4,
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
    let mut stack: Vec<(gltf::Node, Mat4)> = roots.into_iter().rev().map(|n| (n, root)).collect();
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
/// becomes radiant intensity in W/sr and lux (directional) irradiance in W/m^2, both divided by
/// [`LUMENS_PER_WATT`] (as if all the light were at 555 nm; the colour stays the file's linear
/// RGB). A 68,300 lux sun is 100 W/m^2; the exposure brings that into range. `range` is
/// ignored (lights fall off as 1/d^2 without a cut-off).
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
    let power = color * (l.intensity() / LUMENS_PER_WATT);
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

/// A camera at `world`'s origin looking down its -Z with its +Y up, and the aspect ratio the
/// file gives, if any. Orthographic: the image spans `2 ymag` vertically and the width follows
/// from the image size; `xmag / ymag` is the file's aspect ratio. Rays start on the camera's
/// plane, not at `znear`: a Whitted renderer has no clipping planes.
pub(super) fn camera(
    c: &gltf::Camera,
    world: &Mat4,
    element: &str,
    origin: &Path,
) -> Result<(Camera, Option<f32>), SceneError> {
    let err = |m: String| SceneError::invalid(origin, element, m);
    let position = world.transform_point3(Vec3::ZERO);
    let forward = world.transform_vector3(-Vec3::Z);
    let up = world.transform_vector3(Vec3::Y);
    match c.projection() {
        gltf::camera::Projection::Perspective(p) => {
            let camera = Camera::look_at(
                position,
                position + forward,
                up,
                p.yfov().to_degrees(),
                0.0,
                None,
            )
            .map_err(|e| err(e.to_string()))?;
            let aspect = p.aspect_ratio().filter(|a| *a > 0.0 && a.is_finite());
            Ok((camera, aspect))
        }
        gltf::camera::Projection::Orthographic(o) => {
            // The specification forbids zero and discourages negative magnifications.
            let (xmag, ymag) = (o.xmag().abs(), o.ymag().abs());
            if !(xmag > 0.0 && xmag.is_finite() && ymag > 0.0 && ymag.is_finite()) {
                return Err(err(format!(
                    "orthographic xmag {} and ymag {} must be finite and non-zero",
                    o.xmag(),
                    o.ymag()
                )));
            }
            // `up` is scaled by the node: its length must not scale the view.
            let camera = Camera::orthographic(position, position + forward, up, 2.0 * ymag)
                .map_err(|e| err(e.to_string()))?;
            Ok((camera, Some(xmag / ymag)))
        }
    }
}
