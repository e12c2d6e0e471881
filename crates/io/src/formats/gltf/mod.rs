//! glTF 2.0 scenes (`.gltf` with external or data-URI buffers, and binary `.glb`) through the
//! `gltf` crate's parser, with lumis's own buffer loading and bounds checks so that no input
//! can make the reader panic and every error names the file and the element.
//!
//! What is read: the chosen scene's node hierarchy, triangle primitives, metallic-roughness
//! materials (rules in [`materials`]), `KHR_lights_punctual` (photometric units converted, see
//! [`nodes::light`]), perspective and orthographic cameras. Files with no camera get the
//! automatic framing camera, files with no light the default rig placed relative to the camera
//! used. Valid files the `gltf` crate alone would refuse are read through [`lenient`]. The full
//! mapping is in `docs/gltf.md`.
//!
//! ```sh
//! lumis render model.glb --gltf-scene 0 --camera 1
//! ```

mod accessor;
mod buffers;
mod checks;
mod gpu_instancing;
mod lenient;
mod materials;
mod nodes;
mod parts;
mod placements;
mod primitives;
mod tangents;
mod textures;

use std::path::Path;

use super::{LoadOptions, Resolver, SceneError, read_file, read_file_bytes};
use crate::files::guard::guarded;
use lumis_core::scene::{Scene, SceneBuilder, default_rig, framing_camera};

/// Loads the `.gltf` or `.glb` file at `path`; external buffers are read from disk relative to
/// its folder.
pub fn load_gltf_file(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let bytes = read_file(path)?;
    load_gltf_bytes(&bytes, path, &read_file_bytes, options)
}

/// Loads a glTF scene from `bytes` (JSON or GLB). `origin` names the file in errors and is where
/// relative URIs start; `resolver` reads external buffers.
pub fn load_gltf_bytes(
    bytes: &[u8],
    origin: &Path,
    resolver: Resolver<'_>,
    options: &LoadOptions,
) -> Result<Scene, SceneError> {
    // The checks in `buffers` and `checks` cover every slice and unwrap of the crate's that
    // lumis reaches; this is the last line of defence should a hostile file find a path they
    // missed: the error names the file, and no panic text is printed.
    guarded(|| load_inner(bytes, origin, resolver, options)).unwrap_or_else(|message| {
        Err(SceneError::Gltf {
            path: origin.to_path_buf(),
            message,
        })
    })
}

fn load_inner(
    bytes: &[u8],
    origin: &Path,
    resolver: Resolver<'_>,
    options: &LoadOptions,
) -> Result<Scene, SceneError> {
    let mut warnings = Vec::new();
    let (doc, blob) = buffers::parse(bytes, origin, &mut warnings)?;
    let data = buffers::load_buffers(&doc, blob, origin, resolver)?;
    buffers::check_accessors(&doc, &data, origin)?;
    let placed = nodes::flatten(&doc, options.scene, options.up.to_y_up(), origin)?;

    let mut b = SceneBuilder::new();
    // One lumis material per glTF material, converted in file order; images decoded once.
    let mut images = textures::Images::new(&data, origin, resolver);
    let converted: Vec<_> = doc
        .materials()
        .map(|m| materials::convert(&m, &mut images, &mut warnings))
        .collect();
    // Material names (what Cryptomatte's material mattes are called): the file's, else the
    // glTF index, so an unnamed material keeps its name when others are added before it.
    let material_names: Vec<String> = doc
        .materials()
        .map(|m| {
            m.name().map_or_else(
                || format!("material{}", m.index().unwrap_or(0)),
                str::to_owned,
            )
        })
        .collect();
    let material_ids: Vec<u32> = converted
        .iter()
        .zip(&material_names)
        .map(|(c, name)| b.add_named_material(name.clone(), c.material.clone()))
        .collect();
    warnings.extend(images.unused(&doc));
    warnings.extend(materials::unused_extensions(&doc, origin));
    let mut parts = parts::Parts::new(&converted, &material_ids, &material_names);
    let mut plan = placements::Plan::new(
        &placed,
        &doc,
        &data,
        origin,
        options.flatten_instances,
        &mut warnings,
    )?;
    let mut cameras = Vec::new();
    let mut file_has_lights = false;

    for p in &placed {
        let Placed { node, world } = p;
        let node_name = node
            .name()
            .map_or_else(|| format!("node{}", node.index()), str::to_string);
        if let Some(mesh) = node.mesh() {
            let drawn = parts.of(&mesh, &mut b, &data, origin, &mut warnings)?;
            plan.draw(p, &node_name, mesh.index(), &drawn, &mut b, origin)?;
        }
        if let Some(light) = node.light() {
            file_has_lights = true;
            let element = format!(
                "KHR_lights_punctual.lights[{}] at nodes[{}]",
                light.index(),
                node.index()
            );
            let l = nodes::light(&light, world, &element, origin)?;
            // The light's own name, else its node's: what its pass is called.
            match light.name().or(node.name()) {
                Some(name) => b.add_named_light(name, l),
                None => b.add_light(l),
            }
        }
        if let Some(camera) = node.camera() {
            let element = format!("cameras[{}] at nodes[{}]", camera.index(), node.index());
            cameras.push(nodes::camera(&camera, world, &element, origin)?);
        }
    }

    let bounds = b.bounds();
    if bounds.is_empty() {
        // A scene without nodes, or whose meshes draw nothing, is valid glTF.
        warnings.push(format!(
            "{}: the scene has no triangles: the image shows only the background",
            origin.display()
        ));
    }
    let chosen = match options.camera {
        Some(i) => Some(cameras.get(i).cloned().ok_or_else(|| {
            SceneError::invalid(
                origin,
                "cameras",
                format!(
                    "camera {i} was asked for, but the scene places {} cameras",
                    cameras.len()
                ),
            )
        })?),
        None if options.auto_camera => None,
        None => cameras.first().cloned(),
    };
    let settings = b.settings_mut();
    let camera = match chosen {
        Some((camera, aspect)) => {
            if let Some(aspect) = aspect {
                // The file's aspect ratio wins over the default size; CLI flags still override.
                settings.height =
                    (settings.width as f32 / aspect).round().clamp(1.0, 65536.0) as u32;
            }
            camera
        }
        None => framing_camera(bounds, settings.width, settings.height),
    };
    if !file_has_lights && !bounds.is_empty() {
        for light in default_rig(bounds, &camera) {
            b.add_rig_light(light);
        }
    }
    for w in warnings {
        b.warn(w);
    }
    b.build(camera)
        .map_err(|e| SceneError::invalid(origin, e.element, e.message))
}

use nodes::Placed;
