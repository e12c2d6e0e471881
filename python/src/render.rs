//! `Scene.render`: a render developed as `lumis render` develops it ([`develop`]: exposure
//! fixed or automatic, finite check, encoding by extension), returned as the EXR's channels
//! ([`exr_channels`]: the very values the file stores) and, when paths are given, written as
//! the command writes them (staged, then renamed together).

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use numpy::PyArray2;
use numpy::ndarray::Array2;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::film::{Tonemap, check_finite};
use lumis_core::render::{RenderOptions, render as render_world, worker_threads};
use lumis_core::scene::World;
use lumis_io::display::{DisplayServer, LiveView};
use lumis_io::output::{
    ChannelLayout, Develop, ExrCamera, ExrMetadata, ExrSamples, StagedOutputs, develop,
    exr_channels,
};
use lumis_io::request::{
    Aov, SceneOrigin, SettingsFlags, aov_layers, check_exposure, exposure_to_apply, pass_request,
};

use crate::errors::{SceneError, chain};
use crate::scene::PyScene;

/// What `Scene.render` asks for, its names parsed ([`crate::choices`]).
pub struct Request {
    pub settings: SettingsFlags,
    pub aovs: Vec<Aov>,
    pub seed: u64,
    pub threads: Option<usize>,
    pub exposure: Option<f32>,
    pub accel: AccelKind,
    pub transparent: bool,
    pub float_rgba: bool,
    pub layout: ChannelLayout,
    pub tonemap: Tonemap,
    pub paths: Vec<PathBuf>,
    /// Stream the render into this viewer (tev's protocol), as `--display-server`.
    pub display_server: Option<DisplayServer>,
}

/// Renders `scene` as `request` says: a dict `{"channels": {name: (H, W) array}, "exposure":
/// stops applied, "auto_exposure": bool}`.
pub fn render<'py>(
    py: Python<'py>,
    scene: &PyScene,
    request: &Request,
) -> PyResult<Bound<'py, PyDict>> {
    // The settings as `lumis render`'s flags set them over the file's.
    let mut s = scene.scene().clone();
    let st = s.settings_mut();
    request.settings.apply(st);
    st.validate().map_err(|e| {
        PyValueError::new_err(format!(
            "the render settings after the arguments: {}",
            chain(&e)
        ))
    })?;
    if let Some(ev) = request.exposure {
        check_exposure(ev).map_err(|m| PyValueError::new_err(format!("exposure={ev}: {m}")))?;
    }
    let origin = scene.file().map_or(SceneOrigin::Arrays, SceneOrigin::File);
    let how = Develop {
        exposure: exposure_to_apply(request.exposure, origin, st.exposure),
        tonemap: request.tonemap,
        display: st.display,
    };
    let aov_layers = aov_layers(&request.aovs, s.geometry().has_instances());
    // A file's render records what made it, as the command does; an array scene has no file
    // to record.
    let identity = scene
        .file_source()
        .map(|file| crate::provenance::identity(file, request, s.settings()))
        .transpose()?;
    let settings_json = identity.as_ref().map(|id| id.settings.clone());
    let opts = RenderOptions {
        seed: request.seed,
        threads: worker_threads(request.threads).0,
        transparent: request.transparent,
        // The channels returned are the EXR's, so its pass layers are filled.
        passes: pass_request(&request.aovs, true),
        ..RenderOptions::default()
    };
    // Warnings come from the sender thread; they are raised as Python warnings afterwards.
    let warnings = Arc::new(Mutex::new(Vec::<String>::new()));
    let live = request.display_server.as_ref().map(|server| {
        let st = s.settings();
        let name = request
            .paths
            .first()
            .map_or_else(|| "lumis".to_string(), |p| p.display().to_string());
        let sink = Arc::clone(&warnings);
        LiveView::open(
            server,
            &name,
            (st.width, st.height),
            (0, 0, st.width, st.height),
            Arc::new(move |m| sink.lock().unwrap_or_else(|e| e.into_inner()).push(m)),
        )
    });
    let opts = match &live {
        Some(live) => RenderOptions {
            progress: opts.progress.clone().and(live.clone()),
            ..opts
        },
        None => opts,
    };
    let kind = request.accel;
    let result = py.detach(|| -> Result<_, String> {
        let options = BuildOptions {
            max_leaf_size: kind.default_leaf_size(),
            ..Default::default()
        };
        let world = World::build(s, kind, &options);
        let mut rendered = render_world(&world, &opts).map_err(|e| chain(&e))?;
        let scene = world.scene();
        let mut meta = ExrMetadata {
            float_rgba: request.float_rgba,
            spp_per_axis: scene.settings().spp,
            lens_samples: rendered.analysis.lens_rays,
            aov_layers,
            layout: request.layout,
            frame: scene.frame(),
            identity,
            ..ExrMetadata::default()
        };
        let paths: Vec<&Path> = request.paths.iter().map(PathBuf::as_path).collect();
        let (full_w, full_h) = rendered.film.full_size();
        let camera = ExrCamera::new(scene.camera(), full_w, full_h);
        let developed =
            develop(&mut rendered.film, &camera, &paths, &how, &mut meta).map_err(|e| chain(&e))?;
        check_finite(&rendered.film).map_err(|e| chain(&e))?;
        if let Some(live) = &live {
            live.finish_with_exr(&rendered.film, &meta);
        }
        if !developed.images.is_empty() {
            let mut staged = StagedOutputs::new();
            for (path, bytes) in &developed.images {
                staged.stage_bytes(path, bytes).map_err(|e| chain(&e))?;
            }
            staged.commit().map_err(|e| chain(&e))?;
        }
        let film = &rendered.film;
        let size = (film.height() as usize, film.width() as usize);
        Ok((
            exr_channels(film, &meta),
            size,
            developed.exposure,
            developed.auto_exposure,
        ))
    });
    let (channels, size, exposure, auto) = result.map_err(SceneError::new_err)?;
    let warned = std::mem::take(&mut *warnings.lock().unwrap_or_else(|e| e.into_inner()));
    for message in warned {
        let category = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
        PyErr::warn(
            py,
            &category,
            &std::ffi::CString::new(message).unwrap_or_default(),
            1,
        )?;
    }
    let arrays = PyDict::new(py);
    for (name, samples) in channels {
        match samples {
            // Half floats as their bits: the Python side views them as float16.
            ExrSamples::F16(v) => {
                let bits: Vec<u16> = v.iter().map(|h| h.to_bits()).collect();
                arrays.set_item(name, plane(py, size, bits)?)?;
            }
            ExrSamples::F32(v) => arrays.set_item(name, plane(py, size, v)?)?,
            ExrSamples::U32(v) => arrays.set_item(name, plane(py, size, v)?)?,
        }
    }
    let out = PyDict::new(py);
    out.set_item("channels", arrays)?;
    out.set_item("exposure", exposure)?;
    out.set_item("auto_exposure", auto)?;
    out.set_item("settings", settings_json)?;
    Ok(out)
}

/// One channel as an `(H, W)` array.
fn plane<T: numpy::Element>(
    py: Python<'_>,
    size: (usize, usize),
    v: Vec<T>,
) -> PyResult<Bound<'_, PyArray2<T>>> {
    let a = Array2::from_shape_vec(size, v).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(PyArray2::from_owned_array(py, a))
}
