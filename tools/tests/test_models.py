"""The independent loader keeps exactly the normals a file gives (lumis_tools.models): trimesh
would compute normals for meshes without, which lumis does not (it shades those flat)."""

from __future__ import annotations

import base64
import json
import struct

import numpy as np

from lumis_tools import REPO
from lumis_tools.geometry import load_geometry

QUAD = """v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
"""


def test_obj_with_and_without_normals(tmp_path):
    flat = tmp_path / "flat.obj"
    flat.write_text(QUAD + "f 1 2 3\nf 1 3 4\n")
    smooth = tmp_path / "smooth.obj"
    # Tilted normals, unlike any trimesh would compute for a flat quad.
    smooth.write_text(QUAD + "vn 0 0.6 0.8\nf 1//1 2//1 3//1\nf 1//1 3//1 4//1\n")
    g = load_geometry(flat)
    assert g.triangles.shape == (2, 3, 3) and np.isnan(g.vertex_normals).all()
    g = load_geometry(smooth)
    np.testing.assert_allclose(g.vertex_normals.reshape(-1, 3), [[0, 0.6, 0.8]] * 6, atol=1e-7)


def gltf_triangle(tmp_path, normals):
    """A one-triangle glTF with (or without) a NORMAL attribute, buffer embedded."""
    pos = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    nrm = struct.pack("<9f", *([0.0, 0.6, 0.8] * 3))
    data = pos + (nrm if normals else b"")
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 36}]
    accessors = [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                  "min": [0, 0, 0], "max": [1, 1, 0]}]
    attributes = {"POSITION": 0}
    if normals:
        views.append({"buffer": 0, "byteOffset": 36, "byteLength": 36})
        accessors.append({"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"})
        attributes["NORMAL"] = 1
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
           "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": attributes}]}],
           "accessors": accessors, "bufferViews": views,
           "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64,"
                        + base64.b64encode(data).decode()}]}
    path = tmp_path / f"tri_{normals}.gltf"
    path.write_text(json.dumps(doc))
    return path


def test_gltf_with_and_without_normals(tmp_path):
    assert np.isnan(load_geometry(gltf_triangle(tmp_path, False)).vertex_normals).all()
    g = load_geometry(gltf_triangle(tmp_path, True))
    np.testing.assert_allclose(g.vertex_normals[0], [[0, 0.6, 0.8]] * 3, atol=1e-7)


def test_repository_assets_with_and_without_normals():
    assert np.isnan(load_geometry(REPO / "assets" / "no_normals.obj").vertex_normals).all()
    assert np.isnan(load_geometry(REPO / "assets" / "gltf" / "no_normals.gltf")
                    .vertex_normals).all()
    cube = load_geometry(REPO / "assets" / "gltf" / "cube.gltf")
    assert not np.isnan(cube.vertex_normals).any()
    np.testing.assert_allclose(np.linalg.norm(cube.vertex_normals, axis=-1), 1, atol=1e-6)
