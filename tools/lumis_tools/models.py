"""OBJ and glTF/GLB models through trimesh (pinned 5.2): world-space triangles and the vertex
normals the file gives, every mesh under its scene-graph transform. Where trimesh contradicts
the format specs (OBJ negative indices, glTF sparse accessors and TRIANGLE_FAN), a corrected
temporary copy of the input is loaded instead; see tools/README.md."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .exitcodes import SetupError


class LoadError(SetupError):
    """The scene could not be read; the message names the file and the element. Nothing can be
    checked then: status 2."""


def load_model(path: Path):
    """World-space triangles `(M, 3, 3)` and vertex normals (NaN where the file has none) of an
    OBJ or glTF/GLB file, every mesh under its scene-graph transform."""
    import tempfile

    import trimesh

    with tempfile.TemporaryDirectory(prefix="lumis-tools-") as tmp:
        ext = path.suffix.lower()
        source = path
        if ext in (".gltf", ".glb"):
            source = _gltf_for_trimesh(path, Path(tmp))
        elif ext == ".obj":
            source = _obj_for_trimesh(path, Path(tmp))
        try:
            scene = trimesh.load(str(source), force="scene", process=False,
                                 maintain_order=True)
            file_normals = _file_normal_shapes(source)
        except Exception as e:  # trimesh raises many types; the message is what matters
            raise LoadError(f"{path}: trimesh cannot load it: {e}") from e
    all_tris, all_normals = [], []
    for node in scene.graph.nodes_geometry:
        transform, name = scene.graph[node]
        mesh = scene.geometry[name]
        if not hasattr(mesh, "faces"):  # points and lines: not surfaces
            continue
        faces = np.asarray(mesh.faces, np.int64)
        verts = np.asarray(mesh.vertices, np.float64)
        normals = None
        # Only normals the file gives count: for a mesh without, trimesh would compute its own,
        # which lumis does not do (it shades such meshes flat).
        if file_normals.get(name) == verts.shape:
            normals = np.asarray(mesh.vertex_normals, np.float64)
        tris, ns = transform_triangles(verts[faces], None if normals is None else normals[faces],
                                       np.asarray(transform, np.float64))
        all_tris.append(tris)
        all_normals.append(ns)
    if not all_tris:
        return np.zeros((0, 3, 3)), np.zeros((0, 3, 3))
    return np.concatenate(all_tris), np.concatenate(all_normals)


def _file_normal_shapes(source: Path):
    """{mesh name: shape of its vertex normals} for the meshes whose normals the file itself
    holds, named as trimesh.load names its scene's geometry.

    trimesh has no public way to tell normals read from a file from normals it computes. Its
    format readers (trimesh.exchange.obj.load_obj, trimesh.exchange.gltf.load_gltf / load_glb,
    public API) return what the file holds, before any mesh is built, keyed by the geometry
    names the scene then uses; called with the arguments trimesh.load passes them. A mesh keeps
    the file's normals when their shape is that of its vertices (Trimesh's vertex_normals
    setter drops them otherwise), which the caller checks."""
    import trimesh
    from trimesh.exchange import gltf, obj

    reader = {".obj": obj.load_obj, ".gltf": gltf.load_gltf, ".glb": gltf.load_glb}
    ext = source.suffix.lower()
    with open(source, "rb") as f:
        kwargs = reader[ext](file_obj=f, file_type=ext[1:],
                             resolver=trimesh.resolvers.FilePathResolver(str(source)),
                             metadata=None, process=False, maintain_order=True)
    return {name: np.shape(g["vertex_normals"])
            for name, g in kwargs.get("geometry", {}).items()
            if isinstance(g, dict) and g.get("vertex_normals") is not None}


def transform_triangles(tris, normals, m):
    """Applies the 4x4 matrix `m` to `(M, 3, 3)` triangles (and normals by the inverse
    transpose); a mirroring matrix reverses the winding so faces keep facing outward."""
    lin, t = m[:3, :3], m[:3, 3]
    tris = tris @ lin.T + t
    out_n = np.full(tris.shape, np.nan)
    if normals is not None:
        n = normals @ np.linalg.inv(lin)
        length = np.linalg.norm(n, axis=-1, keepdims=True)
        out_n = n / np.where(length > 0, length, 1)
    if np.linalg.det(lin) < 0:
        tris = tris[:, [0, 2, 1]]
        out_n = out_n[:, [0, 2, 1]]
    return tris, out_n


def _gltf_document(path: Path):
    """(JSON document, list of buffer bytes) of a .gltf or .glb file."""
    import base64

    raw = path.read_bytes()
    if path.suffix.lower() == ".glb":
        jlen = int.from_bytes(raw[12:16], "little")
        doc = json.loads(raw[20:20 + jlen])
        rest = raw[20 + jlen:]
        glb_bin = rest[8:8 + int.from_bytes(rest[0:4], "little")] if rest else b""
    else:
        doc, glb_bin = json.loads(raw), b""
    buffers = []
    for b in doc.get("buffers", []):
        uri = b.get("uri")
        if uri is None:
            buffers.append(glb_bin)
        elif uri.startswith("data:"):
            buffers.append(base64.b64decode(uri.split(",", 1)[1]))
        else:
            buffers.append((path.parent / uri).read_bytes())
    return doc, buffers


_COMPONENTS = {5121: np.uint8, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
_WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def _read_accessor(doc, buffers, i):
    """Accessor `i` as an (count, width) array, sparse substitution applied."""
    a = doc["accessors"][i]
    dt = np.dtype(_COMPONENTS[a["componentType"]])
    n = _WIDTHS[a["type"]]
    if "bufferView" in a:
        v = doc["bufferViews"][a["bufferView"]]
        start = v.get("byteOffset", 0) + a.get("byteOffset", 0)
        stride = v.get("byteStride", dt.itemsize * n)
        buf = buffers[v["buffer"]]
        out = np.array([np.frombuffer(buf, dt, n, start + k * stride) for k in range(a["count"])])
    else:
        out = np.zeros((a["count"], n), dt)
    out = out.reshape(a["count"], n)
    sparse = a.get("sparse")
    if sparse:
        def view(part, dtype, width):
            v = doc["bufferViews"][part["bufferView"]]
            off = v.get("byteOffset", 0) + part.get("byteOffset", 0)
            return np.frombuffer(buffers[v["buffer"]], dtype, sparse["count"] * width, off)
        idx = view(sparse["indices"], _COMPONENTS[sparse["indices"]["componentType"]], 1)
        out = out.copy()
        out[idx.astype(np.int64)] = view(sparse["values"], dt, n).reshape(-1, n)
    return out


def _gltf_for_trimesh(path: Path, tmp: Path):
    """trimesh (pinned 5.2) ignores sparse accessors and drops TRIANGLE_FAN primitives. When
    `path` uses either, writes a geometry-only copy to `tmp` with sparse accessors made dense
    and fans turned into triangle lists (per the glTF 2.0 spec), and returns its path;
    otherwise returns `path`."""
    import base64

    doc, buffers = _gltf_document(path)
    prims = [p for m in doc.get("meshes", []) for p in m["primitives"]]
    sparse = any("sparse" in a for a in doc.get("accessors", []))
    fans = any(p.get("mode", 4) == 6 for p in prims)
    if not (sparse or fans):
        return path
    blob = bytearray()
    new_buffer = len(doc.get("buffers", []))

    def add_accessor(arr, comp, kind):
        while len(blob) % 4:
            blob.append(0)
        doc["bufferViews"].append({"buffer": new_buffer, "byteOffset": len(blob),
                                   "byteLength": arr.nbytes})
        blob.extend(arr.tobytes())
        doc["accessors"].append({"bufferView": len(doc["bufferViews"]) - 1, "componentType":
                                 comp, "count": len(arr), "type": kind})
        return len(doc["accessors"]) - 1

    dense = {}
    for p in prims:
        for name, acc in list(p["attributes"].items()):
            if "sparse" in doc["accessors"][acc]:
                if acc not in dense:
                    a = doc["accessors"][acc]
                    arr = _read_accessor(doc, buffers, acc).astype(_COMPONENTS[a["componentType"]])
                    dense[acc] = add_accessor(arr, a["componentType"], a["type"])
                p["attributes"][name] = dense[acc]
        if p.get("mode", 4) == 6:
            count = doc["accessors"][p["attributes"]["POSITION"]]["count"]
            idx = (_read_accessor(doc, buffers, p["indices"])[:, 0].astype(np.int64)
                   if "indices" in p else np.arange(count))
            tris = np.array([(idx[0], idx[k + 1], idx[k + 2]) for k in range(len(idx) - 2)],
                            np.uint32).reshape(-1)
            p["indices"] = add_accessor(tris, 5125, "SCALAR")
            p["mode"] = 4
    # Geometry only: the copy lives elsewhere, so relative image URIs would not resolve.
    for key in ("materials", "textures", "images", "samplers"):
        doc.pop(key, None)
    for p in prims:
        p.pop("material", None)
    data_uri = "data:application/octet-stream;base64,"
    for b, data in zip(doc.get("buffers", []), buffers):
        b["uri"] = data_uri + base64.b64encode(data).decode()
    doc.setdefault("buffers", []).append(
        {"byteLength": len(blob), "uri": data_uri + base64.b64encode(bytes(blob)).decode()})
    out = tmp / (path.stem + ".gltf")
    out.write_text(json.dumps(doc))
    return out


def _obj_for_trimesh(path: Path, tmp: Path):
    """trimesh (pinned 5.2) resolves negative (relative) OBJ indices against the end of the
    file instead of the vertices read so far, as the OBJ spec says. When `path` has any,
    writes a copy with absolute indices to `tmp` (next to a symlink of the folder's files, so
    `mtllib` still resolves) and returns it; otherwise returns `path`."""
    lines = path.read_text().splitlines()
    counts = {"v": 0, "vt": 0, "vn": 0}
    changed = False
    out = []
    for line in lines:
        tok = line.split()
        if tok and tok[0] in counts:
            counts[tok[0]] += 1
        elif tok and tok[0] == "f" and "-" in line:
            corners = []
            for corner in tok[1:]:
                parts = corner.split("/")
                for k, kind in enumerate(("v", "vt", "vn")):
                    if k < len(parts) and parts[k].startswith("-"):
                        parts[k] = str(counts[kind] + 1 + int(parts[k]))
                        changed = True
                corners.append("/".join(parts))
            line = "f " + " ".join(corners)
        out.append(line)
    if not changed:
        return path
    copy = tmp / path.name
    copy.write_text("\n".join(out) + "\n")
    for other in path.parent.iterdir():
        if other.suffix.lower() != ".obj" and not (tmp / other.name).exists():
            (tmp / other.name).symlink_to(other.resolve())
    return copy


def node_matrix(node):
    """A glTF node's local 4x4 matrix (column-major `matrix`, or T * R * S)."""
    if "matrix" in node:
        return np.array(node["matrix"], np.float64).reshape(4, 4).T
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    r = np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])
    m = np.eye(4)
    m[:3, :3] = r * np.array(node.get("scale", [1, 1, 1]))
    m[:3, 3] = node.get("translation", [0, 0, 0])
    return m
