"""The glTF document building the asset generators share (gen_gltf_assets.py,
gltf_view_assets.py, gltf_material_assets.py): a document with one binary buffer, its JSON
writer, the unit cube's geometry and an 8-bit PNG encoder (standard library only).

Every generated file must come out byte for byte the same on every run, so nothing here
depends on dictionary order of input, time or platform."""

import json
import struct
import zlib

F32, I8, U8, I16, U16, U32 = 5126, 5120, 5121, 5122, 5123, 5125
ARRAY, ELEMENT = 34962, 34963


class Doc:
    """A glTF document with one binary buffer built up view by view."""

    def __init__(self):
        self.bin = bytearray()
        self.j = {"asset": {"version": "2.0", "generator": "lumis tools/gen_gltf_assets.py"},
                  "bufferViews": [], "accessors": [], "meshes": [], "nodes": [],
                  "scenes": [{"nodes": []}], "scene": 0}

    def view(self, data, target=None):
        while len(self.bin) % 4:
            self.bin.append(0)
        v = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if target:
            v["target"] = target
        self.bin += data
        self.j["bufferViews"].append(v)
        return len(self.j["bufferViews"]) - 1

    def accessor(self, comp, kind, values, target=None, minmax=False, normalized=False):
        fmt = {F32: "f", I8: "b", U8: "B", I16: "h", U16: "H", U32: "I"}[comp]
        width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[kind]
        flat = [x for v in values for x in (v if width > 1 else [v])]
        data = struct.pack("<%d%s" % (len(flat), fmt), *flat)
        a = {"bufferView": self.view(data, target), "componentType": comp,
             "count": len(values), "type": kind}
        if normalized:
            a["normalized"] = True
        if minmax:
            a["min"] = [min(v[i] for v in values) for i in range(width)]
            a["max"] = [max(v[i] for v in values) for i in range(width)]
        self.j["accessors"].append(a)
        return len(self.j["accessors"]) - 1

    def mesh(self, prims, name=None):
        m = {"primitives": prims}
        if name:
            m["name"] = name
        self.j["meshes"].append(m)
        return len(self.j["meshes"]) - 1

    def node(self, root=True, **kw):
        self.j["nodes"].append(kw)
        i = len(self.j["nodes"]) - 1
        if root:
            self.j["scenes"][0]["nodes"].append(i)
        return i

    def material(self, m):
        self.j.setdefault("materials", []).append(m)
        return len(self.j["materials"]) - 1

    def finish(self, uri):
        """The JSON with the buffer named by `uri` (None: the GLB chunk)."""
        j = json.loads(json.dumps(self.j))
        b = {"byteLength": len(self.bin)}
        if uri is not None:
            b["uri"] = uri
        j["buffers"] = [b]
        return j


def write_json(path, j):
    with open(path, "w") as f:
        json.dump(j, f, indent=1, sort_keys=True)
        f.write("\n")


def cube():
    """A unit cube centred on the origin: 24 vertices (positions, normals, uvs) and the
    indices of 12 outward, counter-clockwise triangles."""
    pos, nor, uv, idx = [], [], [], []
    for axis in range(3):
        for sign in (1.0, -1.0):
            n = [0.0, 0.0, 0.0]
            n[axis] = sign
            u = [0.0, 0.0, 0.0]
            v = [0.0, 0.0, 0.0]
            u[(axis + 1) % 3] = 1.0
            v[(axis + 2) % 3] = 1.0
            if sign < 0:
                u, v = v, u  # keep u x v = n so the winding faces outwards
            base = len(pos)
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                pos.append([0.5 * (n[i] + a * u[i] + b * v[i]) for i in range(3)])
                nor.append(n)
                uv.append([(a + 1) / 2, (b + 1) / 2])
            idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return pos, nor, uv, idx


def png(width, height, rows, alpha=False):
    """An 8-bit RGB (or RGBA) PNG of `rows` of pixel tuples."""
    raw = b"".join(b"\0" + bytes(c for px in row for c in px) for row in rows)

    def chunk(tag, data):
        return (struct.pack(">I", len(data)) + tag + data
                + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF))
    kind = 6 if alpha else 2
    return (b"\x89PNG\r\n\x1a\n"
            + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, kind, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
