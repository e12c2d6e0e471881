"""The point-lit bunny scene tools/bench_mitsuba.py renders, written for both engines: a
binary PLY pair and a Mitsuba 3 scene dictionary for Mitsuba, a TOML scene for lumis."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .geometry import read_m

# The scene, in the bunny's own units (it is about 0.16 across, standing on y = 0.033), all of
# it then scaled by --scene-scale (the docstring says why the default is 10).
CAMERA_POSITION = (0.0, 0.16, 0.42)
CAMERA_LOOK_AT = (-0.015, 0.1, 0.0)
CAMERA_UP = (0.0, 1.0, 0.0)
CAMERA_FOV_DEG = 40.0  # vertical
LIGHT_POSITION = (0.25, 0.45, 0.35)
LIGHT_INTENSITY = 1.2  # W/sr: about 0.5 radiance on the lit side of the bunny
ALBEDO = 0.5
FLOOR_HALF_SIZE = 2.0
DEFAULT_SCALE = 10.0



def scaled(v, k):
    return tuple(k * x for x in v)




def write_ply(path: Path, vertices: np.ndarray, faces: np.ndarray):
    """Binary little-endian PLY with float32 positions and int32 triangle indices."""
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(vertices)}\n"
        "property float x\nproperty float y\nproperty float z\n"
        f"element face {len(faces)}\n"
        "property list uchar int vertex_indices\nend_header\n"
    )
    # Each face record is a count byte followed by three indices, unaligned: a packed dtype.
    records = np.empty(len(faces), np.dtype([("n", "u1"), ("idx", "<i4", (3,))]))
    records["n"] = 3
    records["idx"] = faces
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(np.ascontiguousarray(vertices, "<f4").tobytes())
        f.write(records.tobytes())


def floor_quad(y, k):
    """Two triangles spanning k * FLOOR_HALF_SIZE around the origin at height y."""
    s = k * FLOOR_HALF_SIZE
    vertices = np.array([[-s, y, -s], [s, y, -s], [s, y, s], [-s, y, s]], np.float32)
    faces = np.array([[0, 2, 1], [0, 3, 2]], np.int32)
    return vertices, faces


def prepare_scene(model: Path, folder: Path, k: float):
    """Writes bunny.ply and floor.ply (for Mitsuba) and scene.toml (for lumis, which reads the
    .m itself and scales it by `k`) into `folder`, everything scaled by `k`; returns the
    triangle count."""
    tris, _ = read_m(model)
    tris = tris * k
    # read_m gives a triangle soup; PLY wants shared vertices. Welding equal positions changes
    # nothing visible under flat shading.
    vertices, faces = np.unique(tris.reshape(-1, 3).astype(np.float32), axis=0,
                                return_inverse=True)
    write_ply(folder / "bunny.ply", vertices, faces.reshape(-1, 3).astype(np.int32))
    floor_y = float(vertices[:, 1].min())  # the bunny stands on the floor
    fv, ff = floor_quad(floor_y, k)
    write_ply(folder / "floor.ply", fv, ff)

    def vec(v):
        return "[" + ", ".join(repr(float(x)) for x in v) + "]"

    # Ambient 0: lumis's default ambient term (0.05 * kd) has no counterpart in Mitsuba's
    # direct lighting. Size and samples come from the command line.
    (folder / "scene.toml").write_text(f"""\
[render]
ambient = [0.0, 0.0, 0.0]
background = [0.0, 0.0, 0.0]

[camera]
position = {vec(scaled(CAMERA_POSITION, k))}
look_at = {vec(scaled(CAMERA_LOOK_AT, k))}
up = {vec(CAMERA_UP)}
fov = {CAMERA_FOV_DEG!r}

[materials.grey]
diffuse = {vec([ALBEDO] * 3)}

[[light]]
type = "point"
position = {vec(scaled(LIGHT_POSITION, k))}
color = [1.0, 1.0, 1.0]
intensity = {LIGHT_INTENSITY * k * k!r}

[[mesh]]
name = "bunny"
file = {json.dumps(str(model.resolve()))}
material = "grey"
scale = {float(k)!r}

[[mesh]]
name = "floor"
material = "grey"
positions = [{", ".join(vec(v) for v in fv)}]
indices = [{", ".join(str(f.tolist()) for f in ff)}]
smooth = false
""")
    return len(tris)


def mitsuba_scene_dict(mi, folder: Path, width, height, spp_axis, k):
    """The Mitsuba description of the scene prepare_scene wrote for lumis."""
    grey = {"type": "twosided",
            "material": {"type": "diffuse", "reflectance": {"type": "rgb", "value": ALBEDO}}}
    return {
        "type": "scene",
        # Whitted direct lighting: one shadow ray per sample towards the (delta) point light,
        # no BSDF-sampled rays (they cannot find a point light).
        "integrator": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0},
        "sensor": {
            "type": "perspective",
            "fov": CAMERA_FOV_DEG,
            "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(
                origin=scaled(CAMERA_POSITION, k), target=scaled(CAMERA_LOOK_AT, k),
                up=CAMERA_UP),
            "sampler": {"type": "stratified", "sample_count": spp_axis * spp_axis},
            "film": {"type": "hdrfilm", "width": width, "height": height,
                     "pixel_format": "rgb", "rfilter": {"type": "box"}},
        },
        "light": {"type": "point", "position": scaled(LIGHT_POSITION, k),
                  "intensity": {"type": "rgb", "value": LIGHT_INTENSITY * k * k}},
        "bunny": {"type": "ply", "filename": str(folder / "bunny.ply"), "face_normals": True,
                  "bsdf": grey},
        "floor": {"type": "ply", "filename": str(folder / "floor.ply"), "face_normals": True,
                  "bsdf": grey},
    }
