"""glTF test assets for the loader's leniency, cameras and lights (assets/gltf/), written by
gen_gltf_assets.py; tests/gltf_views.rs and tests/cli_models.rs assert on them.

Valid files the gltf crate alone refuses, an orthographic view, photometric lights and a file
camera looking from -Z. Written to assets/gltf/ beside gen_gltf_assets.py's own files.
  custom_attribute.gltf  the cube with an application-specific _BARYCENTRIC VEC3 attribute.
  empty_scene.gltf       a scene without "nodes" (optional in the specification).
  no_minmax.gltf         the cube whose POSITION accessor has no min/max.
  ortho_cubes.gltf       two unit cubes, at z = 0 (x = -1.5) and z = -6 (x = +1.5), seen by an
                         orthographic camera at z = 5 (xmag 4, ymag 2) looking down -Z.
  sun.gltf               the cube on a ground quad under a 68,300 lux directional sun, with
                         a perspective camera.
  back_camera.gltf       the cube (no lights) seen by a camera at z = -4 looking +Z.
  no_view_uv.gltf        textured_quad.gltf whose TEXCOORD_0 accessor has no bufferView: all
                         zeros by the specification, so the whole quad shows texel (0, 0).
  no_source.gltf         textured_quad.gltf whose texture has no `source`, only an
                         EXT_texture_webp image (valid: `source` is optional).
  spot_defaults.gltf     lights_camera.gltf whose spot light has no `spot` object (its cone
                         angles all have defaults: inner 0, outer pi/4).
"""

import json
import os

# Imported when gen_gltf_assets runs generate(), so that module is complete by then.
from .gen_gltf_assets import (
    ARRAY, ELEMENT, F32, OUT, U16, Doc, cube_doc, cube_prim, write, write_json,
)


def custom_attribute():
    d = cube_doc()
    prim = d.j["meshes"][0]["primitives"][0]
    prim["attributes"]["_BARYCENTRIC"] = d.accessor(F32, "VEC3", [[1, 0, 0]] * 24, ARRAY)
    write(d, "custom_attribute", "data")


def empty_scene():
    d = Doc()
    d.j["scenes"] = [{"name": "nothing here"}]
    del d.j["nodes"], d.j["meshes"], d.j["accessors"], d.j["bufferViews"]
    write_json(os.path.join(OUT, "empty_scene.gltf"), d.j)


def no_minmax():
    d = cube_doc()
    a = d.j["accessors"][d.j["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
    del a["min"], a["max"]
    write(d, "no_minmax", "data")


def ortho_cubes():
    d = Doc()
    m = d.material({"name": "white", "pbrMetallicRoughness": {
        "baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0.0, "roughnessFactor": 1.0}})
    mesh = d.mesh([cube_prim(d, m)], "cube")
    d.node(mesh=mesh, name="near", translation=[-1.5, 0, 0])
    d.node(mesh=mesh, name="far", translation=[1.5, 0, -6])
    d.j["cameras"] = [{"type": "orthographic", "orthographic": {
        "xmag": 4, "ymag": 2, "znear": 0.1, "zfar": 100}}]
    d.node(camera=0, name="camera", translation=[0, 0, 5])
    write(d, "ortho_cubes", "data")


def sun():
    d = cube_doc()
    g = d.accessor(F32, "VEC3", [[-5, -0.5, -5], [5, -0.5, -5], [5, -0.5, 5], [-5, -0.5, 5]],
                   ARRAY, minmax=True)
    gi = d.accessor(U16, "SCALAR", [0, 2, 1, 0, 3, 2], ELEMENT)
    d.node(mesh=d.mesh([{"attributes": {"POSITION": g}, "indices": gi}]), name="ground")
    d.j["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}]
    d.node(camera=0, name="camera", translation=[0, 1, 4])
    d.j["extensionsUsed"] = ["KHR_lights_punctual"]
    d.j["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "directional", "color": [1, 0.95, 0.9], "intensity": 68300}]}}
    # -60 degrees about X: the sun shines down and away from the camera, lighting the top.
    d.node(name="sun", rotation=[-0.5, 0, 0, 0.75 ** 0.5],
           extensions={"KHR_lights_punctual": {"light": 0}})
    write(d, "sun", "data")


def back_camera():
    d = cube_doc()
    d.j["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1}}]
    # 180 degrees about Y: the node's -Z looks along +Z.
    d.node(camera=0, name="camera", translation=[0, 0, -4], rotation=[0, 1, 0, 0])
    write(d, "back_camera", "data")


def no_view_uv():
    # From the file gen_gltf_assets.py has just written, sharing its buffer and image.
    with open(os.path.join(OUT, "textured_quad.gltf")) as f:
        j = json.load(f)
    uv = j["accessors"][j["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"]]
    del uv["bufferView"]
    uv.pop("byteOffset", None)
    write_json(os.path.join(OUT, "no_view_uv.gltf"), j)


def no_source():
    with open(os.path.join(OUT, "textured_quad.gltf")) as f:
        j = json.load(f)
    texture = j["textures"][0]
    texture["extensions"] = {"EXT_texture_webp": {"source": texture.pop("source")}}
    j["extensionsUsed"] = ["EXT_texture_webp"]
    write_json(os.path.join(OUT, "no_source.gltf"), j)


def spot_defaults():
    with open(os.path.join(OUT, "lights_camera.gltf")) as f:
        j = json.load(f)
    for light in j["extensions"]["KHR_lights_punctual"]["lights"]:
        if light["type"] == "spot":
            del light["spot"]
    write_json(os.path.join(OUT, "spot_defaults.gltf"), j)


def generate():
    """Writes every file listed above."""
    custom_attribute()
    empty_scene()
    no_minmax()
    ortho_cubes()
    sun()
    back_camera()
    no_view_uv()
    no_source()
    spot_defaults()
