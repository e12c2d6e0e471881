#!/usr/bin/env python3
"""Writes the glTF test assets in assets/gltf/ (plain Python 3; documents built by gltf_doc.py).

    python3 tools/gen_gltf_assets.py

Every file is small and deterministic; tests/gltf_loading.rs and tests/gltf_bad_input.rs assert
on their exact contents (triangle counts, bounds, materials, lights, cameras), so change both
together.

Good files:
  cube.gltf + cube.bin, cube_embedded.gltf (data URI), cube.glb: the same unit cube (24 vertices,
      normals, UVs, u16 indices, 12 triangles, one red material) in the three containers.
  sparse.gltf       a quad whose POSITION accessor has a sparse override lifting two corners to y=1.
  strip_fan.gltf    a triangle strip (u8 indices, 6 vertices = 4 triangles) and a fan (u32
                    indices, 5 vertices = 3 triangles), all facing +Z; plus a POINTS primitive.
  hierarchy.gltf    parent (translation + 90 degree rotation about Y) with two cube children:
                    non-uniform scale [2, 1, 0.5] and negative scale [-1, 1, 1] (matrix form).
  instancing.gltf   one cube mesh placed by three nodes at x = -3, 0, 3 (loaded as three
                    instances of one prototype).
  shared_meshes.gltf, gpu_instancing.gltf: instancing (see gltf_instancing_assets.py).
  no_normals.gltf   one triangle without NORMAL (flat shading).
  textured_quad.gltf + checker.png: a quad with TEXCOORD_0 and a base colour texture.
  lights_camera.gltf  a cube on a ground quad, a perspective camera (yfov 0.6, aspect 1.5) and
                    one point, one spot and one directional light (KHR_lights_punctual).
  materials.gltf    four cubes with gold metal, glass (transmission + ior), emissive (strength)
                    and alpha-blended materials.
Bad files (assets/gltf/bad/): each must fail to load with a message naming the element.
"""

import base64
import json
import os
import struct

from . import REPO
from .gltf_doc import ARRAY, ELEMENT, F32, U8, U16, U32, Doc, cube, png, write_json

OUT = os.path.join(REPO, "assets", "gltf")


def write(doc, name, container="bin"):
    """Writes NAME.gltf + NAME.bin, NAME.gltf with a data URI, or NAME.glb."""
    if container == "bin":
        with open(os.path.join(OUT, name + ".bin"), "wb") as f:
            f.write(doc.bin)
        write_json(os.path.join(OUT, name + ".gltf"), doc.finish(name + ".bin"))
    elif container == "data":
        uri = "data:application/octet-stream;base64," + base64.b64encode(doc.bin).decode()
        write_json(os.path.join(OUT, name + ".gltf"), doc.finish(uri))
    else:
        with open(os.path.join(OUT, name + ".glb"), "wb") as f:
            f.write(glb(doc))


def glb(doc):
    js = json.dumps(doc.finish(None), sort_keys=True).encode()
    js += b" " * (-len(js) % 4)
    bn = bytes(doc.bin) + b"\0" * (-len(doc.bin) % 4)
    body = struct.pack("<I4s", len(js), b"JSON") + js + struct.pack("<I4s", len(bn), b"BIN\0") + bn
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def cube_prim(doc, material=None, normals=True):
    """A unit cube centred on the origin: 24 vertices, 12 outward, counter-clockwise triangles."""
    pos, nor, uv, idx = cube()
    attrs = {"POSITION": doc.accessor(F32, "VEC3", pos, ARRAY, minmax=True),
             "TEXCOORD_0": doc.accessor(F32, "VEC2", uv, ARRAY)}
    if normals:
        attrs["NORMAL"] = doc.accessor(F32, "VEC3", nor, ARRAY)
    p = {"attributes": attrs, "indices": doc.accessor(U16, "SCALAR", idx, ELEMENT)}
    if material is not None:
        p["material"] = material
    return p


RED = {"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1.0],
                                               "metallicFactor": 0.0, "roughnessFactor": 0.5}}


def cube_doc():
    d = Doc()
    m = d.material(RED)
    d.node(mesh=d.mesh([cube_prim(d, m)], "cube"), name="cube")
    return d


def sparse():
    d = Doc()
    quad = [[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]]
    pos = d.accessor(F32, "VEC3", quad, ARRAY)
    iv = d.view(struct.pack("<2B", 2, 3))
    vv = d.view(struct.pack("<6f", 1, 1, 1, -1, 1, 1))
    d.j["accessors"][pos]["sparse"] = {
        "count": 2, "indices": {"bufferView": iv, "componentType": U8},
        "values": {"bufferView": vv}}
    d.j["accessors"][pos]["min"] = [-1, 0, -1]
    d.j["accessors"][pos]["max"] = [1, 1, 1]
    idx = d.accessor(U16, "SCALAR", [0, 2, 1, 0, 3, 2], ELEMENT)
    d.node(mesh=d.mesh([{"attributes": {"POSITION": pos}, "indices": idx}]), name="lifted")
    write(d, "sparse")


def strip_fan():
    d = Doc()
    strip = [[i // 2 * 1.0, 1.0 - i % 2, 0.0] for i in range(6)]  # zig-zag: top, bottom
    fan = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 1.0, 0.0]]
    fan = [[p[0] + 5.0, p[1], p[2]] for p in fan]
    sp = d.accessor(F32, "VEC3", strip, ARRAY, minmax=True)
    fp = d.accessor(F32, "VEC3", fan, ARRAY, minmax=True)
    si = d.accessor(U8, "SCALAR", list(range(6)), ELEMENT)
    fi = d.accessor(U32, "SCALAR", list(range(5)), ELEMENT)
    d.node(mesh=d.mesh([
        {"attributes": {"POSITION": sp}, "indices": si, "mode": 5},
        {"attributes": {"POSITION": fp}, "indices": fi, "mode": 6},
        {"attributes": {"POSITION": fp}, "mode": 0},
    ]), name="strip_fan")
    write(d, "strip_fan")


def hierarchy():
    d = Doc()
    cube = d.mesh([cube_prim(d)], "cube")
    a = d.node(root=False, mesh=cube, name="stretched", translation=[2, 0, 0], scale=[2, 1, 0.5])
    b = d.node(root=False, mesh=cube, name="mirrored",
               matrix=[-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 3, 0, 1])
    s = 0.5 ** 0.5
    d.node(name="parent", children=[a, b], translation=[0, 0, 10], rotation=[0, s, 0, s])
    write(d, "hierarchy")


def instancing():
    d = Doc()
    cube = d.mesh([cube_prim(d)], "cube")
    for x in (-3, 0, 3):
        d.node(mesh=cube, name="cube%+d" % x, translation=[x, 0, 0])
    write(d, "instancing")


def no_normals():
    d = Doc()
    p = d.accessor(F32, "VEC3", [[0, 0, 0], [1, 0, 0], [0, 1, 0]], ARRAY, minmax=True)
    d.node(mesh=d.mesh([{"attributes": {"POSITION": p}}]), name="tri")
    write(d, "no_normals", "data")


def textured_quad():
    d = Doc()
    p = d.accessor(F32, "VEC3", [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], ARRAY, minmax=True)
    t = d.accessor(F32, "VEC2", [[0, 1], [1, 1], [1, 0], [0, 0]], ARRAY)
    i = d.accessor(U16, "SCALAR", [0, 1, 2, 0, 2, 3], ELEMENT)
    d.j["images"] = [{"uri": "checker.png"}]
    d.j["textures"] = [{"source": 0}]
    m = d.material({"name": "checker", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}})
    d.node(mesh=d.mesh([{"attributes": {"POSITION": p, "TEXCOORD_0": t}, "indices": i,
                         "material": m}]), name="quad")
    w, b = (230, 230, 230), (20, 20, 20)
    with open(os.path.join(OUT, "checker.png"), "wb") as f:
        f.write(png(2, 2, [[w, b], [b, w]]))
    write(d, "textured_quad")


def lights_camera():
    d = cube_doc()
    g = d.accessor(F32, "VEC3", [[-5, -0.5, -5], [5, -0.5, -5], [5, -0.5, 5], [-5, -0.5, 5]],
                   ARRAY, minmax=True)
    gi = d.accessor(U16, "SCALAR", [0, 2, 1, 0, 3, 2], ELEMENT)
    d.node(mesh=d.mesh([{"attributes": {"POSITION": g}, "indices": gi}]), name="ground")
    d.j["cameras"] = [{"type": "perspective", "perspective": {
        "yfov": 0.6, "aspectRatio": 1.5, "znear": 0.1, "zfar": 100}}]
    d.node(camera=0, name="camera", translation=[0, 1, 6])
    d.j["extensionsUsed"] = ["KHR_lights_punctual"]
    d.j["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "point", "color": [1, 0.5, 0.25], "intensity": 40},
        {"type": "spot", "intensity": 100, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.4}},
        {"type": "directional", "color": [0.5, 0.5, 1], "intensity": 2}]}}
    s = 0.5 ** 0.5
    lights = d.node(name="lights", translation=[0, 4, 0], children=[])
    for k, kw in enumerate([dict(translation=[-2, 0, 2]),
                            dict(rotation=[-s, 0, 0, s]),  # -90 degrees about X: -Z becomes -Y
                            dict(rotation=[-s, 0, 0, s])]):
        n = d.node(root=False, name="light%d" % k, extensions={"KHR_lights_punctual": {"light": k}},
                   **kw)
        d.j["nodes"][lights]["children"].append(n)
    write(d, "lights_camera")


def materials():
    d = Doc()
    d.j["extensionsUsed"] = ["KHR_materials_transmission", "KHR_materials_ior",
                             "KHR_materials_emissive_strength"]
    mats = [
        {"name": "gold", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.8, 0.3, 1.0],
                                                  "metallicFactor": 1.0, "roughnessFactor": 0.0}},
        {"name": "glass", "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.0},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                        "KHR_materials_ior": {"ior": 1.45}}},
        {"name": "lamp", "emissiveFactor": [1.0, 0.5, 0.25],
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2.0}}},
        {"name": "ghost", "alphaMode": "BLEND", "doubleSided": True,
         "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 0.25],
                                  "metallicFactor": 0.0, "roughnessFactor": 1.0}},
    ]
    for k, m in enumerate(mats):
        mi = d.material(m)
        d.node(mesh=d.mesh([cube_prim(d, mi)]), name=m["name"], translation=[2 * k, 0, 0])
    write(d, "materials")


def bad():
    """Broken files; each test names the element its error must mention."""
    out = os.path.join(OUT, "bad")
    with open(os.path.join(OUT, "cube.glb"), "rb") as f:
        whole = f.read()
    with open(os.path.join(out, "truncated.glb"), "wb") as f:
        f.write(whole[: len(whole) // 2])
    with open(os.path.join(out, "invalid_json.gltf"), "w") as f:
        f.write('{"asset": {"version": "2.0"}, "nodes": [\n')

    def variant(name, edit, container="data"):
        d = cube_doc()
        edit(d)
        if container == "bin":
            write_json(os.path.join(out, name + ".gltf"), d.finish("does_not_exist.bin"))
        else:
            uri = "data:application/octet-stream;base64," + base64.b64encode(d.bin).decode()
            write_json(os.path.join(out, name + ".gltf"), d.finish(uri))

    variant("accessor_out_of_bounds", lambda d: d.j["accessors"][0].update(count=2400))

    def index_out_of_range(d):
        # Rewrite the first u16 index to 99 (the cube has 24 vertices).
        idx_view = d.j["bufferViews"][d.j["accessors"][3]["bufferView"]]
        struct.pack_into("<H", d.bin, idx_view["byteOffset"], 99)
    variant("index_out_of_range", index_out_of_range)

    def nan_position(d):
        pos_view = d.j["bufferViews"][d.j["accessors"][0]["bufferView"]]
        struct.pack_into("<f", d.bin, pos_view["byteOffset"] + 4 * 3 * 5 + 4, float("nan"))
    variant("nan_position", nan_position)
    variant("missing_buffer", lambda d: None, "bin")
    variant("draco", lambda d: d.j.update(
        extensionsUsed=["KHR_draco_mesh_compression"],
        extensionsRequired=["KHR_draco_mesh_compression"]))
    variant("empty_mesh", lambda d: d.j["meshes"][0].update(primitives=[]))




def main():
    os.makedirs(os.path.join(OUT, "bad"), exist_ok=True)
    d = cube_doc()
    write(d, "cube", "bin")
    write(d, "cube_embedded", "data")
    write(d, "cube", "glb")
    sparse()
    strip_fan()
    hierarchy()
    instancing()
    no_normals()
    textured_quad()
    lights_camera()
    materials()
    bad()
    # Shared meshes and EXT_mesh_gpu_instancing: gltf_instancing_assets.py.
    from . import gltf_instancing_assets
    gltf_instancing_assets.generate(write)
    # Loader robustness, cameras and lights: gltf_view_assets.py.
    from . import gltf_view_assets
    gltf_view_assets.generate()
    # Materials, textures and attributes: gltf_material_assets.py.
    from . import gltf_material_assets
    gltf_material_assets.generate(os.path.join(OUT, "materials"))


def cli():
    main()


if __name__ == "__main__":
    cli()
