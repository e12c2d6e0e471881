//! The `.scn` / `.m` importer on the project's own fixtures: every keyword and material kind,
//! the model placement rule, and clear errors (file and line) for bad input.

use lumis_core::camera::Lens;
use lumis_core::film::DisplayTransform;
use lumis_core::light::Light;
use lumis_core::material::Texture;
use lumis_core::math::Vec3;
use lumis_io::formats::load;
use lumis_io::formats::scn::parse_scn;
use std::path::Path;

fn fixture(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/scn")
        .join(name)
}

#[test]
fn every_keyword_and_material_kind_loads() {
    let scene = load(&fixture("every_keyword.scn")).expect("fixture loads");
    // 8 spheres + 1 triangle + 1 model.
    assert_eq!(scene.objects().len(), 10);
    assert_eq!(scene.geometry().spheres().len(), 8);
    assert_eq!(scene.geometry().meshes().len(), 2);
    assert_eq!(scene.geometry().meshes()[1].triangle_count(), 4);
    let st = scene.settings();
    assert_eq!(
        (st.max_depth, st.lens_samples, st.ambient),
        (4, 3, Vec3::splat(0.2))
    );
    assert_eq!(st.medium_ior, 1.0);
    assert_eq!(scene.camera().lens(), Lens::Square(2.0));
    assert_eq!(scene.lights().len(), 2);
    assert!(
        matches!(scene.lights()[0], Light::Unattenuated { irradiance, .. } if (irradiance.x - 0.8 * std::f32::consts::PI).abs() < 1e-5)
    );
    let kinds: Vec<&'static str> = scene
        .objects()
        .iter()
        .map(|o| match scene.materials()[o.material as usize].diffuse {
            Texture::Solid(_) => "solid",
            Texture::Checkerboard { .. } => "checker",
            Texture::Turbulence { .. } => "turbulence",
            Texture::Marble { .. } => "marble",
            Texture::Wood { .. } => "wood",
            Texture::CrissCross { .. } => "crisscross",
            Texture::Image { .. } => "image",
        })
        .collect();
    for k in [
        "solid",
        "checker",
        "turbulence",
        "marble",
        "wood",
        "crisscross",
    ] {
        assert!(kinds.contains(&k), "{k} missing from {kinds:?}");
    }
    let glass = &scene.materials()[scene.objects()[3].material as usize];
    assert_eq!((glass.transmission, glass.ior), (1.0, 1.5));
    let chrome = &scene.materials()[scene.objects()[2].material as usize];
    assert_eq!((chrome.reflectivity, chrome.shininess), (0.9, 80.0));
    let veins = &scene.materials()[scene.objects()[5].material as usize];
    assert!(
        veins.normal_map.is_some(),
        "named material keeps its normal map"
    );
}

#[test]
fn model_is_centred_scaled_to_its_diagonal_and_translated() {
    let scene = load(&fixture("every_keyword.scn")).unwrap();
    let b = scene.geometry().meshes()[1].bounds();
    assert!(
        (b.extent().length() - 30.0).abs() < 1e-3,
        "diagonal {}",
        b.extent().length()
    );
    assert!(
        (b.center() - Vec3::new(0.0, 70.0, 20.0)).length() < 1e-3,
        "centre {}",
        b.center()
    );
}

#[test]
fn scn_renders_through_the_cli() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("k.png");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_lumis"))
        .args(["render", "-q", "--width", "48", "--height", "27"])
        .arg(fixture("every_keyword.scn"))
        .arg("-o")
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    assert!(out.is_file());
}

#[test]
fn missing_statements_take_the_originals_defaults() {
    let scene = parse_scn(
        "sphere 0 0 -10 1 FlatColor 1 1 1 null\n",
        Path::new("d.scn"),
    )
    .unwrap();
    let st = scene.settings();
    // The original's main: maxReflections 10; its constructor: dispersion 5 (depth of field on,
    // with the paper's 5 lens rays); its TGA: colour x 255, clamped.
    assert_eq!((st.max_depth, st.lens_samples), (10, 5));
    assert_eq!((st.width, st.height, st.spp), (1920, 1080, 1));
    assert_eq!(st.display, DisplayTransform::Clamp);
    assert_eq!(st.cutoff, 0.0);
    assert_eq!(scene.camera().lens(), Lens::Square(5.0));
    assert!(scene.camera().has_depth_of_field());
    // A negative dispersion is a pinhole; 0 (N identical rays in the original) is one too.
    for text in [
        "dispersion -1\n",
        "dispersion 0\n",
        "dispersion 3\ndispersion -0.5\n",
    ] {
        let scene = parse_scn(text, Path::new("d.scn")).unwrap();
        assert_eq!(scene.camera().lens(), Lens::Pinhole, "{text:?}");
    }
    let scene = parse_scn("maxReflections 2\ndispersion 0.5\n", Path::new("d.scn")).unwrap();
    assert_eq!(scene.settings().max_depth, 2);
    assert_eq!(scene.camera().lens(), Lens::Square(0.5));
}

/// Renders `scn` text (written to a temporary folder) through the CLI at 8x6 and returns the
/// PNG's pixels.
fn render_scn_png(scn: &str, extra: &[&str]) -> Vec<[u8; 3]> {
    let dir = tempfile::tempdir().unwrap();
    let (path, out) = (dir.path().join("s.scn"), dir.path().join("s.png"));
    std::fs::write(&path, scn).unwrap();
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_lumis"))
        .args(["render", "-q", "--width", "8", "--height", "6"])
        .args(extra)
        .arg(&path)
        .arg("-o")
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let img = image::open(&out).unwrap().to_rgb8();
    img.pixels().map(|p| p.0).collect()
}

#[test]
fn scn_png_is_clamped_without_a_transfer_curve() {
    // A white FlatColor sphere fills the view and no light shines: every pixel is the
    // original's ambient 0.2 x colour = 0.2 linear, which the original writes as 0.2 x 255 = 51.
    let scn = "cameraPosition 0 0 100\ncameraLookAt 0 0 0\ncameraScreenWidth 4\n\
               sphere 0 0 0 50 FlatColor 1 1 1 null\n";
    assert!(render_scn_png(scn, &[]).iter().all(|p| *p == [51; 3]));
    // The flag overrides the format's default: sRGB encodes 0.2 as 124.
    let srgb = render_scn_png(scn, &["--display", "srgb"]);
    assert!(srgb.iter().all(|p| *p == [124; 3]), "{:?}", srgb[0]);
}

fn error_of(text: &str) -> String {
    match parse_scn(text, Path::new("dir/bad.scn")) {
        Ok(_) => panic!("accepted: {text}"),
        Err(e) => {
            let mut s = e.to_string();
            let mut src = std::error::Error::source(&e);
            while let Some(c) = src {
                s += &format!(": {c}");
                src = c.source();
            }
            s
        }
    }
}

#[test]
fn bad_input_names_file_and_line() {
    let cases = [
        (
            "cameraPosition 0 0 1\nfoo 1 2 3\n",
            "dir/bad.scn:2:",
            "unknown keyword",
        ),
        (
            "sphere 0 0 0 1 FlatColor 1 1\n",
            "dir/bad.scn:1:",
            "expected colour component, found end of file",
        ),
        (
            "sphere 0 0 0 1 FlatColor 1 x 1 null\n",
            "dir/bad.scn:1:",
            "finite number",
        ),
        (
            "\n\nsphere 0 0 0 1 Plaid 1 1 1 null\n",
            "dir/bad.scn:3:",
            "unknown material \"Plaid\"",
        ),
        (
            "sphere 0 0 0 -1 FlatColor 1 1 1 null\n",
            "dir/bad.scn:1:",
            "must be positive",
        ),
        (
            "sphere 0 0 0 1 FlatColor 1 1 1 bump\n",
            "dir/bad.scn:1:",
            "NormalMap",
        ),
        ("light 0 0 0\n", "dir/bad.scn:1:", "end of file"),
        (
            "model nothere.m 10 0 0 0 FlatColor 1 1 1 null\n",
            "dir/bad.scn:1:",
            "nothere.m",
        ),
        (
            "sphere 0 0 0 nan FlatColor 1 1 1 null\n",
            "dir/bad.scn:1:",
            "finite",
        ),
        ("maxReflections 2.5\n", "dir/bad.scn:1:", "whole number"),
        ("maxReflections 100000\n", "dir/bad.scn:1:", "0..=64"),
    ];
    for (text, location, what) in cases {
        let e = error_of(text);
        assert!(
            e.contains(location) && e.contains(what),
            "for {text:?} got: {e}"
        );
    }
}

#[test]
fn bad_m_file_names_its_own_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("broken.m"),
        "Vertex 1 0 0 0\nVertex 2 1 0 0\nFace 1 1 2 9\n",
    )
    .unwrap();
    let scn = dir.path().join("s.scn");
    std::fs::write(&scn, "\nmodel broken.m 10 0 0 0 FlatColor 1 1 1 null\n").unwrap();
    let e = match load(&scn) {
        Ok(_) => panic!("accepted a face with a missing vertex"),
        Err(e) => format!("{:#}", anyhow::Error::new(e)),
    };
    assert!(
        e.contains("s.scn:2") && e.contains("broken.m:3") && e.contains("vertex 9"),
        "{e}"
    );
}
