"""The instancing assets of assets/gltf/ (written by gen_gltf_assets.py), which
tests/it/gltf_instancing.rs checks pixel by pixel, so change both together.

Both files look through an orthographic camera at (0, 0, 10) down -Z spanning x in [-8, 8] and
y in [-4, 4] (xmag 8, ymag 4), lit by one directional light shining down -Z, so a pixel's
world x, y follow from its column and row alone and nothing depends on the automatic framing.

The shared mesh "nosed" is a unit cube (primitive 0, red) with a blue "nose" box on its +X side
(primitive 1: x in [0.5, 1], y and z in [-0.25, 0.25]): which way the nose points shows the
transform, mirrors included.

shared_meshes.gltf: "nosed" placed by four nodes:
    plain      at (-6, 2, 0)
    mirrored   at (-2, 2, 0), scale (-1, 1, 1): the nose at x in [-3, -2.5]
    stretched  at (2, 2, 0), scale (2, 0.5, 1): the cube x in [1, 3], y in [1.75, 2.25], the
               nose x in [3, 4]
    child      at (1, 0, 0) under "turned" at (4, -2, 0), rotated +90 degrees about Z and
               scaled 1.5: the cube centred at (4, -0.5), the nose up, y in [0.25, 1]
  and a green cube "single" (its own mesh, placed once) at (-5, -2, 0).
gpu_instancing.gltf: "swarm", EXT_mesh_gpu_instancing with 50 instances of "nosed":
    instance i: column c = i % 10, row r = i // 10, translation (-6.75 + 1.5 c, 3.2 - 0.8 r, 0),
    rotation (i % 8) x 45 degrees about Z as normalized SHORT quaternions, uniform float scale
    0.3 + 0.05 (i % 3);
  and "flock" at (0, -2.5, 0): 8 instances, translation (-7 + 2 k, 0, 0), float rotations
    k x 45 degrees about Z, float scale 0.6.
  The extension is in extensionsUsed and extensionsRequired.
"""

import math

from .gltf_doc import ARRAY, ELEMENT, F32, I16, U16, Doc, cube

NAME = "EXT_mesh_gpu_instancing"
RED = {"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1.0],
                                               "metallicFactor": 0.0, "roughnessFactor": 1.0}}
BLUE = {"name": "blue", "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.2, 0.8, 1.0],
                                                 "metallicFactor": 0.0, "roughnessFactor": 1.0}}
GREEN = {"name": "green", "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.7, 0.2, 1.0],
                                                   "metallicFactor": 0.0, "roughnessFactor": 1.0}}


def box(doc, material, scale=1.0, offset=(0.0, 0.0, 0.0)):
    """A cube primitive (normals, u16 indices) scaled by `scale` about the origin, then moved."""
    pos, nor, _, idx = cube()
    pos = [[p[i] * scale + offset[i] for i in range(3)] for p in pos]
    return {"attributes": {"POSITION": doc.accessor(F32, "VEC3", pos, ARRAY, minmax=True),
                           "NORMAL": doc.accessor(F32, "VEC3", nor, ARRAY)},
            "indices": doc.accessor(U16, "SCALAR", idx, ELEMENT), "material": material}


def staged():
    """A document with the camera, the light and the "nosed" mesh (index 0)."""
    d = Doc()
    red, blue = d.material(RED), d.material(BLUE)
    d.mesh([box(d, red), box(d, blue, 0.5, (0.75, 0.0, 0.0))], "nosed")
    d.j["cameras"] = [{"type": "orthographic",
                       "orthographic": {"xmag": 8, "ymag": 4, "znear": 0.1, "zfar": 100}}]
    d.node(camera=0, name="camera", translation=[0, 0, 10])
    d.j["extensionsUsed"] = ["KHR_lights_punctual"]
    d.j["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "directional", "color": [1, 1, 1], "intensity": 3}]}}
    d.node(name="sun", extensions={"KHR_lights_punctual": {"light": 0}})
    return d


def about_z(degrees):
    h = math.radians(degrees) / 2
    return [0.0, 0.0, math.sin(h), math.cos(h)]


def shared_meshes(write):
    d = staged()
    d.node(mesh=0, name="plain", translation=[-6, 2, 0])
    d.node(mesh=0, name="mirrored", translation=[-2, 2, 0], scale=[-1, 1, 1])
    d.node(mesh=0, name="stretched", translation=[2, 2, 0], scale=[2, 0.5, 1])
    child = d.node(root=False, mesh=0, name="child", translation=[1, 0, 0])
    d.node(name="turned", children=[child], translation=[4, -2, 0], rotation=about_z(90),
           scale=[1.5, 1.5, 1.5])
    green = d.mesh([box(d, d.material(GREEN))], "single")
    d.node(mesh=green, name="single", translation=[-5, -2, 0])
    write(d, "shared_meshes")


def quantised(q):
    """A quaternion as normalized SHORTs: round(c x 32767), the inverse of max(c / 32767, -1)."""
    return [max(-32767, min(32767, round(c * 32767))) for c in q]


def gpu_instancing(write):
    d = staged()
    swarm = range(50)
    t = d.accessor(F32, "VEC3", [[-6.75 + 1.5 * (i % 10), 3.2 - 0.8 * (i // 10), 0.0]
                                 for i in swarm])
    r = d.accessor(I16, "VEC4", [quantised(about_z(45 * (i % 8))) for i in swarm],
                   normalized=True)
    s = d.accessor(F32, "VEC3", [[0.3 + 0.05 * (i % 3)] * 3 for i in swarm])
    d.node(mesh=0, name="swarm", extensions={NAME: {"attributes": {
        "TRANSLATION": t, "ROTATION": r, "SCALE": s}}})
    flock = range(8)
    t = d.accessor(F32, "VEC3", [[-7.0 + 2 * k, 0.0, 0.0] for k in flock])
    r = d.accessor(F32, "VEC4", [about_z(45 * k) for k in flock])
    s = d.accessor(F32, "VEC3", [[0.6] * 3 for _ in flock])
    d.node(mesh=0, name="flock", translation=[0, -2.5, 0], extensions={NAME: {"attributes": {
        "TRANSLATION": t, "ROTATION": r, "SCALE": s}}})
    d.j["extensionsUsed"].append(NAME)
    d.j["extensionsRequired"] = [NAME]
    write(d, "gpu_instancing")


def generate(write):
    """Writes both files through `write(doc, name)` (NAME.gltf + NAME.bin)."""
    shared_meshes(write)
    gpu_instancing(write)

