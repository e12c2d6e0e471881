//! The valid inputs every malformed case starts from: small files of each format lumis reads,
//! generated here or taken from the repository's own assets, which render cleanly together.

use std::path::Path;

/// One seed file: its name in the case directory and its bytes.
pub struct Seed {
    pub name: &'static str,
    pub bytes: Vec<u8>,
    /// Text formats get numeric substitutions as well as byte damage.
    pub text: bool,
}

const SCENE_TOML: &str = r#"[render]
width = 16
height = 12
spp = 1
background = [0.1, 0.2, 0.3]
ambient = [0.05, 0.05, 0.05]
exposure = 0.5

[camera]
position = [0.0, 1.0, 8.0]
look_at = [0.0, 0.0, 0.0]
fov = 45.0

[materials.red]
diffuse = [0.7, 0.2, 0.1]
specular = [0.3, 0.3, 0.3]
shininess = 40.0
reflectivity = 0.2

[materials.lamp]
emission = [2.0, 1.5, 1.0]

[[light]]
type = "point"
position = [3.0, 5.0, 4.0]
intensity = 120.0

[[light]]
type = "directional"
direction = [-1.0, -1.0, -0.5]
intensity = 0.8

[[sphere]]
name = "ball"
center = [-1.5, 0.0, 0.0]
radius = 0.8
material = "red"

[[sphere]]
center = [1.5, 1.0, -1.0]
radius = 0.3
material = "lamp"

[[mesh]]
name = "quad"
file = "model.obj"
translate = [0.0, -1.0, 0.0]
rotate = [-90.0, 0.0, 0.0]
scale = 3.0

[[mesh]]
file = "cube.gltf"
translate = [1.5, 0.0, 0.0]
scale = [0.7, 0.7, 0.7]

[[mesh]]
file = "cube.glb"
translate = [0.0, 1.5, -2.0]

[[mesh]]
file = "tetra.m"
material = "red"
translate = [0.0, 0.0, 2.0]
scale = 0.5

[[mesh]]
positions = [[-3.0, -1.0, -3.0], [3.0, -1.0, -3.0], [0.0, 3.0, -3.0]]
indices = [[0, 1, 2]]

# Rendered at frame 0 (the keys' values are damaged like any other number).
[animation]
frames = 4
fps = [24000, 1001]

[[animation.camera]]
frame = 0
position = [0.0, 1.0, 8.0]
fov = 45.0

[[animation.camera]]
frame = 3
position = [2.0, 1.0, 8.0]
interpolation = "step"

[[animation.sphere]]
name = "ball"
frame = 2
center = [-1.5, 0.5, 0.0]

[[animation.mesh]]
name = "quad"
frame = 1
rotate = [-90.0, 10.0, 0.0]
"#;

const MODEL_OBJ: &str = "mtllib model.mtl
o quad
v -1 -1 0
v 1 -1 0
v 1 1 0
v -1 1 0
v 0 1.5 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vt 0.5 1
vn 0 0 1
usemtl texels
f 1/1/1 2/2/1 3/3/1 5/5/1 4/4/1
o tri
v 0 0 0.5
v 0.5 0 0.5
v 0 0.5 0.5
usemtl shiny
f 6 7 8
";

const MODEL_MTL: &str = "newmtl texels
Kd 1 1 1
Ks 0 0 0
illum 1
map_Kd tex.png
newmtl shiny
Kd 0.2 0.4 0.6
Ks 0.5 0.5 0.5
Ns 30
Ke 0.1 0.1 0.1
illum 2
";

const SCENE_SCN: &str = "cameraPosition 0 20 300
cameraLookAt 0 0 0
cameraUp 0 1 0
cameraScreenWidth 400
maxReflections 3
light 100 200 300 0.8
material chrome ShinyColor 0.8 0.8 0.8 80 0.9 null
sphere 0 -100040 0 100000 Checkerboard 0.3 0.2 0.1  0.9 0.9 0.9  20  -1 -1 null
sphere -20 0 0 15 chrome
sphere 20 0 0 15 Glass 1.5 50 null
triangle -80 -40 -50  80 -40 -50  0 80 -60 ShinyColor 0.2 0.4 0.6 10 0.3 null
model tetra.m
      30
      0 40 20
      FlatColor 0.9 0.5 0.1 null
";

/// An `(n, 8)` float32 C-order `.npy` of rays from the camera's side towards the scene.
fn rays_npy(n: usize) -> Vec<u8> {
    let header = format!("{{'descr': '<f4', 'fortran_order': False, 'shape': ({n}, 8), }}");
    // Magic, version 1.0, header length; the header is padded with spaces to a multiple of 64.
    let unpadded = 10 + header.len() + 1;
    let pad = unpadded.div_ceil(64) * 64 - unpadded;
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend(((header.len() + pad + 1) as u16).to_le_bytes());
    out.extend(header.as_bytes());
    out.extend(std::iter::repeat_n(b' ', pad));
    out.push(b'\n');
    for i in 0..n {
        let x = i as f32 * 0.4 - 1.0;
        for v in [x, 0.2, 8.0, 0.0, 0.0, -1.0, 0.0, f32::INFINITY] {
            out.extend(v.to_le_bytes());
        }
    }
    out
}

fn asset(repo: &Path, rel: &str) -> Vec<u8> {
    std::fs::read(repo.join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// Every seed, in the order cases are generated.
pub fn seeds(repo: &Path) -> Vec<Seed> {
    let text = |name, s: &str| Seed {
        name,
        bytes: s.as_bytes().to_vec(),
        text: true,
    };
    let binary = |name, bytes| Seed {
        name,
        bytes,
        text: false,
    };
    vec![
        text("scene.toml", SCENE_TOML),
        text("model.obj", MODEL_OBJ),
        text("model.mtl", MODEL_MTL),
        binary("tex.png", asset(repo, "assets/quad_texture.png")),
        Seed {
            name: "cube.gltf",
            bytes: asset(repo, "assets/gltf/cube.gltf"),
            text: true,
        },
        binary("cube.bin", asset(repo, "assets/gltf/cube.bin")),
        binary("cube.glb", asset(repo, "assets/gltf/cube.glb")),
        Seed {
            name: "tetra.m",
            bytes: asset(repo, "tests/fixtures/scn/tetra.m"),
            text: true,
        },
        text("scene.scn", SCENE_SCN),
        binary("rays.npy", rays_npy(6)),
    ]
}
