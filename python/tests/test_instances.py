"""Instance ids: `inst_id` of the ray queries (nearest and all hits) and `id.instance` of a
render, on a glTF file whose one mesh is used by two nodes.

Loaders that flatten such a file (one world-space copy per node) make no instances: every
`inst_id` is -1 and a render has no `id.instance`. Loaders that keep the shared mesh as a
prototype make node k instance k: the instanced branches below then check the values.
Either way the columns exist with their dtype, agree with the objects hit, and are bit for bit
what `lumis hits --instance-ids` writes."""

from __future__ import annotations

import base64
import json
import struct

import numpy as np

import lumis
from conftest import bits, cli_hits

# Node k's quad spans x in [X[k] - 1, X[k] + 1], y in [-1, 1], z = 0.
X = (-2.0, 2.0)


def two_nodes(tmp_path):
    quad = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, -1, 0), (1, 1, 0), (-1, 1, 0)]
    data = b"".join(struct.pack("<3f", *v) for v in quad)
    doc = {
        "asset": {"version": "2.0"},
        "buffers": [{
            "byteLength": len(data),
            "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode(),
        }],
        "bufferViews": [{"buffer": 0, "byteLength": len(data)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "type": "VEC3", "count": 6,
                       "min": [-1, -1, 0], "max": [1, 1, 0]}],
        "meshes": [{"name": "quad", "primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0, "name": f"node{k}", "translation": [x, 0, 0]}
                  for k, x in enumerate(X)],
        "scenes": [{"nodes": [0, 1]}],
        "scene": 0,
    }
    path = tmp_path / "two_nodes.gltf"
    path.write_text(json.dumps(doc))
    return path


def rays():
    """Down -z onto each quad's centre and half way to its edge, then one miss."""
    o = np.array([[X[0], 0, 5], [X[1], 0, 5], [X[0] + 0.5, 0.5, 5], [X[1] - 0.5, -0.5, 5],
                  [0, 5, 5]], np.float32)
    d = np.tile(np.array([0, 0, -1], np.float32), (len(o), 1))
    return o, d


def instanced(scene) -> bool:
    """Whether the loader kept the shared mesh as instances."""
    o, d = rays()
    return bool((scene.intersect(o, d).inst_id >= 0).any())


def test_inst_id_of_nearest_and_all_hits(tmp_path):
    s = lumis.load(two_nodes(tmp_path))
    o, d = rays()
    h = s.intersect(o, d)
    assert h.inst_id.dtype == np.int64 and h.inst_id.shape == (5,)
    assert h.t.tolist() == [5.0, 5.0, 5.0, 5.0, np.inf]
    node = [0, 1, 0, 1]
    # Two objects, one per node, either way; the miss has no instance.
    assert len(set(h.obj_id[:4].tolist())) == 2
    assert h.obj_id[:4].tolist() == [h.obj_id[k] for k in node]
    assert h.inst_id[4] == -1
    if instanced(s):
        assert h.inst_id[:4].tolist() == node
        # Both nodes' hits name the prototype's primitives, the same pair for each node.
        assert h.prim_id[0] == h.prim_id[1] and h.prim_id[2] == h.prim_id[3]
    else:
        assert h.inst_id.tolist() == [-1] * 5
    # The all-hits columns carry the same instance per hit.
    a = s.intersect_all(o, d)
    assert a.inst_id.dtype == np.int64
    assert a.ray.tolist() == [0, 1, 2, 3]
    assert a.inst_id.tolist() == h.inst_id[:4].tolist()


def test_inst_id_is_the_cli_column(cli, tmp_path):
    scene = two_nodes(tmp_path)
    s = lumis.load(scene)
    o, d = rays()
    r = np.zeros((len(o), 8), np.float32)
    r[:, 0:3], r[:, 3:6], r[:, 7] = o, d, np.inf
    h = s.intersect(o, d)
    want = cli_hits(cli, tmp_path, scene, r, "--instance-ids")
    assert want.shape == (5, 10)
    assert np.array_equal(bits(h.rows(instance_ids=True)), bits(want))
    # Without the flag the file keeps its nine columns, the first nine of the wide rows.
    assert np.array_equal(bits(h.rows()), bits(cli_hits(cli, tmp_path, scene, r)))
    a = s.intersect_all(o, d)
    want_all = cli_hits(cli, tmp_path, scene, r, "--all", "--instance-ids")
    assert want_all.shape == (4, 12)
    assert np.array_equal(want_all[:, 11], a.inst_id.astype(np.float32))
    # The ray index first, then the nearest-hit columns: the object id is column 3.
    assert np.array_equal(want_all[:, 0], a.ray.astype(np.float32))
    assert np.array_equal(want_all[:, 3], a.obj_id.astype(np.float32))


def test_render_id_instance_follows_the_objects(tmp_path):
    s = lumis.load(two_nodes(tmp_path))
    img = s.render(width=24, height=12, spp=1)
    objects = img["id.object"]
    assert (objects >= 0).any()
    if not instanced(s):
        # A scene without instances: the channels of files written before instancing.
        assert "id.instance" not in img
        return
    inst = img["id.instance"]
    assert inst.dtype == np.float32 and inst.shape == objects.shape
    assert np.array_equal(inst < 0, objects < 0)
    # Each object is one node's, so one instance; both nodes are in view.
    for obj in np.unique(objects[objects >= 0]):
        assert len(np.unique(inst[objects == obj])) == 1
    assert set(np.unique(inst[inst >= 0]).tolist()) == {0.0, 1.0}
