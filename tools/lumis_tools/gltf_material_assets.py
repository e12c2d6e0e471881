"""glTF material, texture and attribute test assets (assets/gltf/materials/), written by
gen_gltf_assets.py (`python3 tools/gen_gltf_assets.py`); tests/gltf_materials.rs asserts their pixels, so change both together.

Every file is one or more quads in the plane z = 0 spanning [-1, 1]^2 (facing +Z, TEXCOORD_0
(0, 0) at the top-left corner x = -1, y = 1), lit by one directional light of intensity 0 (so the
default light rig stays away) unless it says otherwise. The tests render with ambient 1, so a
pixel shows emission + base colour * occlusion wherever the material is a rough dielectric.

  emissive.gltf       black base, emissiveFactor (1, 0.5, 1) x KHR_materials_emissive_strength 2 x
                      a 2x2 NEAREST emissive texture (red, green / blue, white).
  normal_map.gltf     white quad with a 2x2 normal texture (quarters tipped 45 degrees to +x,
                      flat / +y, -y), no TANGENT (generated), lit by a directional light from
                      (1, 1, 1).
  normal_map_tangents.gltf  the same with TANGENT (1, 0, 0, 1) given.
  metal_rough.gltf    metallic 1 roughness 1 x a 2x1 texture: left rough dielectric, right
                      smooth metal (a mirror).
  occlusion.gltf      white quad, occlusionTexture strength 0.5: left R = 0, right R = 255.
  vertex_colors.gltf  four quads (quarters) with COLOR_0 as float VEC3, normalized u8 VEC4,
                      normalized u16 VEC3 and none, base colour factor (0.5, 1, 1).
  samplers.gltf       three quads (thirds) whose TEXCOORD_0 runs from -1 to 2 over a 2x2 NEAREST
                      texture with REPEAT, CLAMP_TO_EDGE and MIRRORED_REPEAT; a fourth material on
                      a quad below reads TEXCOORD_1, which is TEXCOORD_0 mirrored in u.
  transform.gltf      a 2x1 (black, white) NEAREST texture with KHR_texture_transform
                      scale (2, 1), offset (0.25, 0).
  specular.gltf       one scene per KHR_materials_specular variant, each a grey (0.5) quad of
                      roughness 0.5 lit head-on (irradiance 3): no extension; specularFactor 0;
                      factor 0.5 with specularColorFactor (1, 0.5, 0.25); factor 0.5, colour
                      (30, 1, 0.5) and KHR_materials_ior 1.75.
  clearcoat.gltf      a rough grey (0.5) quad whose quarters have KHR_materials_clearcoat: none;
                      factor 1; factor 0.5 roughness 0.25; factor 1 roughness 1.
  quantized.gltf      a unit cube with KHR_mesh_quantization: SHORT normalized positions (+-1,
                      node scale 0.5), BYTE normalized normals, UNSIGNED_BYTE normalized texcoords;
  quantized_float.gltf  the same cube in floats.
  alpha_mask.gltf     a MASK quad (cutoff 0.5, RGBA texture: left column alpha 0, right 255) in
                      front of a wall at z = -1, lit along -Z by a directional light.
  unsupported.gltf    an unknown extension in extensionsUsed and on the material
                      (KHR_materials_sheen), an unreferenced texture and a JOINTS_0 attribute.
"""

import os
import struct

from .gltf_doc import ARRAY, ELEMENT, F32, I8, I16, U8, U16, Doc, cube, png, write_json

NEAREST, LINEAR = 9728, 9729
REPEAT, CLAMP, MIRROR = 10497, 33071, 33648

QUAD = [[-1, 1, 0], [1, 1, 0], [1, -1, 0], [-1, -1, 0]]
QUAD_UV = [[0, 0], [1, 0], [1, 1], [0, 1]]
QUAD_IDX = [0, 3, 2, 0, 2, 1]  # counter-clockwise seen from +Z
# The quad's four quarters (top-left, top-right, bottom-left, bottom-right), as QUAD is laid out.
QUARTERS = [[[x0 + a, y0 + b, 0] for a, b in ((0, 0), (1, 0), (1, -1), (0, -1))]
            for x0, y0 in ((-1, 1), (0, 1), (-1, 0), (0, 0))]


def accessor(doc, comp, kind, values, normalized=False, minmax=False):
    fmt = {F32: "f", I8: "b", U8: "B", I16: "h", U16: "H"}[comp]
    width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[kind]
    size = struct.calcsize(fmt)
    # Elements padded to 4 bytes, as the specification asks of vertex attributes.
    stride = (width * size + 3) // 4 * 4
    data = b""
    for v in values:
        v = v if width > 1 else [v]
        e = struct.pack("<%d%s" % (width, fmt), *v)
        data += e + b"\0" * (stride - len(e))
    view = doc.view(data, ARRAY)
    if stride != width * size:
        doc.j["bufferViews"][view]["byteStride"] = stride
    a = {"bufferView": view, "componentType": comp, "count": len(values), "type": kind}
    if normalized:
        a["normalized"] = True
    if minmax:
        a["min"] = [min(v[i] for v in values) for i in range(width)]
        a["max"] = [max(v[i] for v in values) for i in range(width)]
    doc.j["accessors"].append(a)
    return len(doc.j["accessors"]) - 1


def quad(doc, material, pos=QUAD, uv=QUAD_UV, extra=None):
    attrs = {"POSITION": accessor(doc, F32, "VEC3", pos, minmax=True),
             "NORMAL": accessor(doc, F32, "VEC3", [[0, 0, 1]] * 4),
             "TEXCOORD_0": accessor(doc, F32, "VEC2", uv)}
    attrs.update(extra or {})
    idx = doc.accessor(U16, "SCALAR", QUAD_IDX, ELEMENT)
    return {"attributes": attrs, "indices": idx, "material": material}


def image(doc, name, png_bytes):
    """An image in its own PNG file beside the assets, and a texture of it."""
    doc.j.setdefault("images", []).append({"uri": name})
    return len(doc.j["images"]) - 1


def texture(doc, img, mag=LINEAR, wrap=(REPEAT, REPEAT)):
    doc.j.setdefault("samplers", []).append({"magFilter": mag, "wrapS": wrap[0], "wrapT": wrap[1]})
    doc.j.setdefault("textures", []).append({"source": img, "sampler": len(doc.j["samplers"]) - 1})
    return len(doc.j["textures"]) - 1


def dark_light(doc, direction_light=None):
    """One directional light: intensity 0 unless `direction_light` gives a quaternion."""
    doc.j.setdefault("extensionsUsed", []).append("KHR_lights_punctual")
    # 2049 lux: irradiance 3 after lumis's 683 lm/W.
    intensity = 0 if direction_light is None else 2049
    doc.j["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "directional", "intensity": intensity}]}}
    kw = {} if direction_light is None else {"rotation": direction_light}
    doc.node(name="light", extensions={"KHR_lights_punctual": {"light": 0}}, **kw)


def rough(base=(1, 1, 1, 1), **kw):
    m = {"pbrMetallicRoughness": {"baseColorFactor": list(base), "metallicFactor": 0.0,
                                  "roughnessFactor": 1.0}}
    m.update(kw)
    return m


def generate(out):
    """Writes every asset into `out`."""
    os.makedirs(out, exist_ok=True)

    def save_png(name, w, h, rows, alpha=False):
        with open(os.path.join(out, name), "wb") as f:
            f.write(png(w, h, rows, alpha))

    def written(d, name):
        with open(os.path.join(out, name + ".bin"), "wb") as f:
            f.write(d.bin)
        write_json(os.path.join(out, name + ".gltf"), d.finish(name + ".bin"))

    # Emission.
    save_png("emissive.png", 2, 2, [[(255, 0, 0), (0, 255, 0)], [(0, 0, 255), (255, 255, 255)]])
    d = Doc()
    d.j["extensionsUsed"] = ["KHR_materials_emissive_strength"]
    t = texture(d, image(d, "emissive.png", None), NEAREST)
    m = d.material(rough((0, 0, 0, 1), emissiveFactor=[1, 0.5, 1], emissiveTexture={"index": t},
                         extensions={"KHR_materials_emissive_strength": {"emissiveStrength": 2}}))
    d.node(mesh=d.mesh([quad(d, m)]), name="quad")
    dark_light(d)
    written(d, "emissive")

    # Normal maps, texels tipped 45 degrees: (+x, flat / +y, -y); +y is up the image.
    save_png("normal.png", 2, 2, [[(218, 128, 218), (128, 128, 255)],
                                  [(128, 218, 218), (128, 37, 218)]])
    for name, tangents in (("normal_map", False), ("normal_map_tangents", True)):
        d = Doc()
        t = texture(d, image(d, "normal.png", None), NEAREST)
        m = d.material(rough(normalTexture={"index": t, "scale": 1.0}))
        extra = {"TANGENT": accessor(d, F32, "VEC4", [[1, 0, 0, 1]] * 4)} if tangents else {}
        d.node(mesh=d.mesh([quad(d, m, extra=extra)]), name="quad")
        # Light travelling along -(1, 1, 1): the rotation taking -Z there.
        dark_light(d, rotation_between([0, 0, -1], [-3 ** -0.5] * 3))
        written(d, name)

    # Metal / roughness: left (G 255 rough, B 0 dielectric), right (G 0 smooth, B 255 metal).
    save_png("metal_rough.png", 2, 1, [[(0, 255, 0), (0, 0, 255)]])
    d = Doc()
    t = texture(d, image(d, "metal_rough.png", None), NEAREST)
    m = d.material({"pbrMetallicRoughness": {
        "metallicFactor": 1.0, "roughnessFactor": 1.0, "metallicRoughnessTexture": {"index": t}}})
    d.node(mesh=d.mesh([quad(d, m)]), name="quad")
    dark_light(d)
    written(d, "metal_rough")

    # Occlusion.
    save_png("occlusion.png", 2, 1, [[(0, 0, 0), (255, 255, 255)]])
    d = Doc()
    t = texture(d, image(d, "occlusion.png", None), NEAREST)
    m = d.material(rough(occlusionTexture={"index": t, "strength": 0.5}))
    d.node(mesh=d.mesh([quad(d, m)]), name="quad")
    dark_light(d)
    written(d, "occlusion")

    # Vertex colours, one quarter each.
    d = Doc()
    m = d.material(rough((0.5, 1, 1, 1)))
    colours = [lambda: accessor(d, F32, "VEC3", [[1, 0.5, 0.25]] * 4),
               lambda: accessor(d, U8, "VEC4", [[51, 102, 153, 255]] * 4, normalized=True),
               lambda: accessor(d, U16, "VEC3", [[65535, 13107, 0]] * 4, normalized=True),
               None]
    prims = []
    for pos, colour in zip(QUARTERS, colours):
        extra = {"COLOR_0": colour()} if colour else {}
        prims.append(quad(d, m, pos=pos, extra=extra))
    d.node(mesh=d.mesh(prims), name="quarters")
    dark_light(d)
    written(d, "vertex_colors")

    # Samplers: thirds of the top half, TEXCOORD_0 from -1 to 2 across each.
    save_png("grid.png", 2, 2, [[(255, 0, 0), (0, 255, 0)], [(0, 0, 255), (255, 255, 255)]])
    d = Doc()
    img = image(d, "grid.png", None)
    prims = []
    for k, wrap in enumerate((REPEAT, CLAMP, MIRROR)):
        t = texture(d, img, NEAREST, (wrap, wrap))
        m = d.material(rough(pbrMetallicRoughness={"baseColorTexture": {"index": t},
                                                   "metallicFactor": 0.0, "roughnessFactor": 1.0}))
        x0, x1 = -1 + 2 * k / 3, -1 + 2 * (k + 1) / 3
        pos = [[x0, 1, 0], [x1, 1, 0], [x1, 0, 0], [x0, 0, 0]]
        prims.append(quad(d, m, pos=pos, uv=[[-1, -1], [2, -1], [2, 2], [-1, 2]]))
    # Bottom half: TEXCOORD_1 (u mirrored) chosen by texCoord 1.
    t = texture(d, img, NEAREST, (CLAMP, CLAMP))
    m = d.material(rough(pbrMetallicRoughness={"baseColorTexture": {"index": t, "texCoord": 1},
                                               "metallicFactor": 0.0, "roughnessFactor": 1.0}))
    pos = [[-1, 0, 0], [1, 0, 0], [1, -1, 0], [-1, -1, 0]]
    uv1 = accessor(d, F32, "VEC2", [[1, 0], [0, 0], [0, 1], [1, 1]])
    prims.append(quad(d, m, pos=pos, extra={"TEXCOORD_1": uv1}))
    d.node(mesh=d.mesh(prims), name="samplers")
    dark_light(d)
    written(d, "samplers")

    # Texture transform.
    save_png("stripe.png", 2, 1, [[(0, 0, 0), (255, 255, 255)]])
    d = Doc()
    d.j["extensionsUsed"] = ["KHR_texture_transform"]
    t = texture(d, image(d, "stripe.png", None), NEAREST)
    m = d.material(rough(pbrMetallicRoughness={
        "baseColorTexture": {"index": t, "extensions": {"KHR_texture_transform": {
            "scale": [2, 1], "offset": [0.25, 0]}}},
        "metallicFactor": 0.0, "roughnessFactor": 1.0}))
    d.node(mesh=d.mesh([quad(d, m)]), name="quad")
    dark_light(d)
    written(d, "transform")

    # KHR_materials_specular: one grey roughness-0.5 quad per scene, lit head-on (along -Z),
    # so that every scene's pixel sees the same view ray and the same Phong lobe.
    d = Doc()
    d.j["extensionsUsed"] = ["KHR_lights_punctual", "KHR_materials_specular",
                             "KHR_materials_ior"]
    d.j["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "directional", "intensity": 2049}]}}
    light = d.node(root=False, name="light", extensions={"KHR_lights_punctual": {"light": 0}})
    variants = [("plain", {}),
                ("none", {"KHR_materials_specular": {"specularFactor": 0.0}}),
                ("tinted", {"KHR_materials_specular": {"specularFactor": 0.5,
                                                       "specularColorFactor": [1, 0.5, 0.25]}}),
                ("ior", {"KHR_materials_specular": {"specularFactor": 0.5,
                                                    "specularColorFactor": [30, 1, 0.5]},
                         "KHR_materials_ior": {"ior": 1.75}})]
    d.j["scenes"] = []
    for name, extensions in variants:
        m = d.material({"name": name, "pbrMetallicRoughness": {
            "baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0.0, "roughnessFactor": 0.5},
            **({"extensions": extensions} if extensions else {})})
        q = d.node(root=False, mesh=d.mesh([quad(d, m)]), name=name)
        d.j["scenes"].append({"name": name, "nodes": [q, light]})
    written(d, "specular")

    # KHR_materials_clearcoat on a rough grey quad, one coat per quarter, no light.
    d = Doc()
    d.j["extensionsUsed"] = ["KHR_materials_clearcoat"]
    coats = [None, {"clearcoatFactor": 1.0}, {"clearcoatFactor": 0.5, "clearcoatRoughness": 0.25},
             {"clearcoatFactor": 1.0, "clearcoatRoughness": 1.0}]
    prims = []
    for pos, coat in zip(QUARTERS, coats):
        extensions = {"extensions": {"KHR_materials_clearcoat": coat}} if coat else {}
        m = d.material(rough((0.5, 0.5, 0.5, 1), **extensions))
        prims.append(quad(d, m, pos=pos))
    d.node(mesh=d.mesh(prims), name="coats")
    dark_light(d)
    written(d, "clearcoat")

    # Quantized and float cubes.
    pos, nor, uv, idx = cube()
    for name, quantized in (("quantized", True), ("quantized_float", False)):
        d = Doc()
        m = d.material(rough((0.8, 0.3, 0.2, 1)))
        if quantized:
            d.j["extensionsUsed"] = ["KHR_mesh_quantization"]
            d.j["extensionsRequired"] = ["KHR_mesh_quantization"]
            attrs = {"POSITION": accessor(d, I16, "VEC3", [[int(c * 2 * 32767) for c in p]
                                                           for p in pos], True, True),
                     "NORMAL": accessor(d, I8, "VEC3", [[int(c * 127) for c in n] for n in nor],
                                        True),
                     "TEXCOORD_0": accessor(d, U8, "VEC2", [[int(c * 255) for c in t] for t in uv],
                                            True)}
            kw = {"scale": [0.5, 0.5, 0.5]}
        else:
            attrs = {"POSITION": accessor(d, F32, "VEC3", pos, minmax=True),
                     "NORMAL": accessor(d, F32, "VEC3", nor),
                     "TEXCOORD_0": accessor(d, F32, "VEC2", uv)}
            kw = {}
        prim = {"attributes": attrs, "indices": d.accessor(U16, "SCALAR", idx, ELEMENT),
                "material": m}
        d.node(mesh=d.mesh([prim]), name="cube", **kw)
        written(d, name)

    # Alpha mask: left column cut out.
    save_png("mask.png", 2, 2, [[(255, 255, 255, 0), (255, 255, 255, 255)]] * 2, alpha=True)
    d = Doc()
    t = texture(d, image(d, "mask.png", None), NEAREST)
    m = d.material(rough((1, 0.2, 0.2, 1), alphaMode="MASK", alphaCutoff=0.5,
                         pbrMetallicRoughness={"baseColorTexture": {"index": t},
                                               "baseColorFactor": [1, 0.2, 0.2, 1],
                                               "metallicFactor": 0.0, "roughnessFactor": 1.0}))
    wall = d.material(rough((0.2, 0.2, 1, 1)))
    wall_pos = [[-3, 3, -1], [3, 3, -1], [3, -3, -1], [-3, -3, -1]]
    d.node(mesh=d.mesh([quad(d, m), quad(d, wall, pos=wall_pos)]), name="masked")
    d.j["extensionsUsed"] = ["KHR_lights_punctual"]
    d.j["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "directional", "intensity": 2049}]}}
    d.node(name="light", extensions={"KHR_lights_punctual": {"light": 0}})
    written(d, "alpha_mask")

    # Things lumis does not use.
    d = Doc()
    d.j["extensionsUsed"] = ["KHR_materials_sheen", "EXT_lumis_unknown"]
    t = texture(d, image(d, "grid.png", None))
    texture(d, 0)
    m = d.material(rough(extensions={"KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1]}},
                         name="velvet"))
    d.j["materials"][m]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": t}
    joints = accessor(d, U8, "VEC4", [[0, 0, 0, 0]] * 4)
    d.node(mesh=d.mesh([quad(d, m, extra={"JOINTS_0": joints})]), name="quad")
    dark_light(d)
    written(d, "unsupported")


def rotation_between(a, b):
    """The unit quaternion [x, y, z, w] turning unit vector a onto unit vector b (not opposite)."""
    cross = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    w = 1 + sum(x * y for x, y in zip(a, b))
    n = (sum(c * c for c in cross) + w * w) ** 0.5
    return [c / n for c in cross] + [w / n]

