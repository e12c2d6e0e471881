//! Inputs that are not regular files: a FIFO (which would block a reader forever) or a device
//! such as `/dev/zero` (which never ends) in every place a run reads a file. Each run must end
//! promptly, naming the file and saying it is not a regular file; where a missing file is an
//! error, so is this one (and nothing is written), where it is a warning (an MTL library, a
//! texture), so is this one.

#![cfg(unix)]

use crate::support_io as support;

use std::path::Path;
use std::time::Duration;
use support::{lumis, mkfifo, names, rays_npy, toml_scene};

const FIFO: &str = "not a regular file (a FIFO)";
const CHAR_DEVICE: &str = "not a regular file (a character device)";

/// A triangle with texture coordinates: 36 bytes of positions, then 24 of UVs.
fn triangle_bin() -> Vec<u8> {
    [
        0.0f32, 0.0, -3.0, 1.0, 0.0, -3.0, 0.0, 1.0, -3.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0,
    ]
    .iter()
    .flat_map(|v| v.to_le_bytes())
    .collect()
}

/// A glTF triangle whose buffer is `bin`, textured by the image `image` when given.
fn gltf(bin: &str, image: Option<&str>) -> String {
    let material = match image {
        Some(uri) => format!(
            r#","materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}}}],
            "textures":[{{"source":0}}],"images":[{{"uri":"{uri}"}}]"#
        ),
        None => String::new(),
    };
    let prim_material = if image.is_some() {
        r#","material":0"#
    } else {
        ""
    };
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"TEXCOORD_0":1}}{prim_material}}}]}}],
        "accessors":[
          {{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,-3],"max":[1,1,-3]}},
          {{"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":24}}],
        "buffers":[{{"uri":"{bin}","byteLength":60}}]{material}}}"#
    )
}

const OBJ: &str = "mtllib m.mtl\nv 0 0 -3\nv 1 0 -3\nv 0 1 -3\nvt 0 0\nvt 1 0\nvt 0 1\n\
                   usemtl m\nf 1/1 2/2 3/3\n";

fn render(dir: &Path, scene: &str) -> support::Run {
    lumis(
        dir,
        &[
            "render", scene, "-o", "out.exr", "--width", "8", "--height", "8",
        ],
    )
}

/// A run that had to fail: the message says it all, and nothing new is in `dir`.
fn assert_refused(dir: &Path, run: &support::Run, before: &[String], parts: &[&str]) {
    run.assert_error(parts);
    assert_eq!(names(dir), before, "a failed run wrote something");
}

#[test]
fn fifo_scene_is_refused_by_render_and_info() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["s.toml", "s.scn", "s.obj", "s.gltf", "s.glb"] {
        mkfifo(&dir.path().join(name));
    }
    let before = names(dir.path());
    for name in ["s.toml", "s.scn", "s.obj", "s.gltf", "s.glb"] {
        assert_refused(
            dir.path(),
            &render(dir.path(), name),
            &before,
            &[name, FIFO],
        );
        let info = lumis(dir.path(), &["info", name]);
        assert_refused(dir.path(), &info, &before, &[name, FIFO]);
    }
}

#[test]
fn fifo_mesh_file_names_the_mesh() {
    let dir = tempfile::tempdir().unwrap();
    mkfifo(&dir.path().join("x.obj"));
    let mesh = "[[mesh]]\nname = \"bunny\"\nfile = \"x.obj\"\nmaterial = \"m\"\n";
    std::fs::write(dir.path().join("scene.toml"), toml_scene(mesh)).unwrap();
    let before = names(dir.path());
    let run = render(dir.path(), "scene.toml");
    assert_refused(
        dir.path(),
        &run,
        &before,
        &["scene.toml", "mesh[0] \"bunny\"", "x.obj", FIFO],
    );
}

#[test]
fn fifo_gltf_buffer_names_the_buffer() {
    let dir = tempfile::tempdir().unwrap();
    mkfifo(&dir.path().join("b.bin"));
    std::fs::write(dir.path().join("t.gltf"), gltf("b.bin", None)).unwrap();
    let before = names(dir.path());
    let run = render(dir.path(), "t.gltf");
    assert_refused(
        dir.path(),
        &run,
        &before,
        &["t.gltf", "buffers[0]", "b.bin", FIFO],
    );
}

#[test]
fn fifo_m_mesh_names_the_scn_line() {
    let dir = tempfile::tempdir().unwrap();
    mkfifo(&dir.path().join("f.m"));
    std::fs::write(
        dir.path().join("s.scn"),
        "\nmodel f.m 10 0 0 0 FlatColor 1 1 1 null\n",
    )
    .unwrap();
    let before = names(dir.path());
    let run = render(dir.path(), "s.scn");
    assert_refused(dir.path(), &run, &before, &["s.scn:2", "f.m", FIFO]);
}

#[test]
fn fifo_rays_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), toml_scene("")).unwrap();
    mkfifo(&dir.path().join("rays.npy"));
    let before = names(dir.path());
    let run = lumis(
        dir.path(),
        &["hits", "s.toml", "--rays", "rays.npy", "--out", "h.npy"],
    );
    assert_refused(dir.path(), &run, &before, &["rays.npy", FIFO]);
}

/// An unreadable MTL library or texture is a warning (docs/obj-mtl.md, docs/gltf.md); a FIFO
/// is one too, and the render goes on without blocking.
#[test]
fn fifo_mtl_and_textures_are_warnings_that_do_not_block() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // An OBJ whose MTL library is a FIFO.
    std::fs::create_dir(d.join("a")).unwrap();
    std::fs::write(d.join("a/m.obj"), OBJ).unwrap();
    mkfifo(&d.join("a/m.mtl"));
    // An OBJ whose map_Kd is a FIFO.
    std::fs::create_dir(d.join("b")).unwrap();
    std::fs::write(d.join("b/m.obj"), OBJ).unwrap();
    std::fs::write(d.join("b/m.mtl"), "newmtl m\nKd 1 1 1\nmap_Kd t.png\n").unwrap();
    mkfifo(&d.join("b/t.png"));
    // A glTF whose image is a FIFO.
    std::fs::create_dir(d.join("c")).unwrap();
    std::fs::write(d.join("c/b.bin"), triangle_bin()).unwrap();
    std::fs::write(d.join("c/t.gltf"), gltf("b.bin", Some("t.png"))).unwrap();
    mkfifo(&d.join("c/t.png"));
    for (scene, file) in [
        ("a/m.obj", "m.mtl"),
        ("b/m.obj", "t.png"),
        ("c/t.gltf", "t.png"),
    ] {
        let run = render(d, scene);
        run.assert_ok();
        run.assert_says(&["warning:", file, FIFO]);
    }
}

#[test]
fn a_directory_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("d.toml")).unwrap();
    let before = names(dir.path());
    let run = render(dir.path(), "d.toml");
    assert_refused(
        dir.path(),
        &run,
        &before,
        &["d.toml", "not a regular file (a directory)"],
    );
}

/// `/dev/zero` (through a symlink with the extension each reader wants) fails at once, where
/// reading it used to run for 1.5 s into "out of memory".
#[test]
fn dev_zero_fails_fast_everywhere() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for link in ["z.toml", "z.obj", "z.gltf", "z.npy", "a/m.mtl", "b/t.png"] {
        if let Some(parent) = Path::new(link).parent() {
            std::fs::create_dir_all(d.join(parent)).unwrap();
        }
        std::os::unix::fs::symlink("/dev/zero", d.join(link)).unwrap();
    }
    let mesh = "[[mesh]]\nname = \"bunny\"\nfile = \"z.obj\"\nmaterial = \"m\"\n";
    std::fs::write(d.join("mesh.toml"), toml_scene(mesh)).unwrap();
    std::fs::write(d.join("s.toml"), toml_scene("")).unwrap();
    std::fs::write(d.join("a/m.obj"), OBJ).unwrap();
    std::fs::write(d.join("b/m.obj"), OBJ).unwrap();
    std::fs::write(d.join("b/m.mtl"), "newmtl m\nKd 1 1 1\nmap_Kd t.png\n").unwrap();
    let limit = Duration::from_secs(1);
    let runs = [
        (render(d, "z.toml"), vec!["z.toml"]),
        (render(d, "z.gltf"), vec!["z.gltf"]),
        (render(d, "mesh.toml"), vec!["mesh[0] \"bunny\"", "z.obj"]),
        (
            lumis(d, &["hits", "s.toml", "--rays", "z.npy", "--out", "h.npy"]),
            vec!["z.npy"],
        ),
        (lumis(d, &["info", "z.obj"]), vec!["z.obj"]),
    ];
    for (run, parts) in &runs {
        let mut parts = parts.clone();
        parts.push(CHAR_DEVICE);
        run.assert_error(&parts);
        assert!(
            run.elapsed < limit,
            "took {:?}: {}",
            run.elapsed,
            run.stderr
        );
    }
    // Where unreadable files are warnings: fast, warned about, rendered without them.
    for (scene, file) in [("a/m.obj", "m.mtl"), ("b/m.obj", "t.png")] {
        let run = render(d, scene);
        run.assert_ok();
        run.assert_says(&[file, CHAR_DEVICE]);
        assert!(run.elapsed < limit, "took {:?}", run.elapsed);
    }
    assert!(!d.join("h.npy").exists());
}

/// The reader still accepts a symlink to a regular file, and the rays format it reads.
#[test]
fn symlinks_to_regular_files_are_fine() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("real.toml"), toml_scene("")).unwrap();
    std::fs::write(d.join("real.npy"), rays_npy(&[0.0, 5.0])).unwrap();
    std::os::unix::fs::symlink("real.toml", d.join("s.toml")).unwrap();
    std::os::unix::fs::symlink("real.npy", d.join("r.npy")).unwrap();
    let run = lumis(d, &["hits", "s.toml", "--rays", "r.npy", "--out", "h.npy"]);
    run.assert_ok();
    assert!(d.join("h.npy").is_file());
}
