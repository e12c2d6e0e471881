"""Scenes that travel: a scene from arrays pickles as its float32 arrays, a scene from a file
as its path, defines, options and the SHA-256 of every file it read (a changed or missing file
is refused by name on unpickling); a `multiprocessing` pool (spawn) answers as the parent
does, bit for bit; queries release the GIL."""

from __future__ import annotations

import multiprocessing
import pickle
import sys
import threading
import time

import numpy as np
import pytest

import lumis
from conftest import ASSETS, SCENES, bits
from mesh_cases import aimed_rays, split_box, write_obj

COLUMNS = ("t", "prim_id", "obj_id", "u", "v", "normal", "kind", "inst_id")


def builder_scene():
    v, f = split_box(2)
    b = lumis.SceneBuilder()
    b.add_mesh(v * 0.3 + 0.1, f, name="box")
    b.add_sphere([4, 0.5, 0.25], 0.75)
    proto = b.add_prototype(v, f)
    m = np.eye(4)
    m[:3, :3] = [[0, -0.5, 0], [0.5, 0, 0], [0, 0, 0.5]]
    m[:3, 3] = [-3, 1, 0.1]
    b.add_instance(proto, m, name="turned")
    b.add_instance(proto, m[:3] + np.array([[0, 0, 0, 0], [0, 0, 0, 3], [0, 0, 0, 0]]))
    return b.build()


def rays(n=1500, seed=11):
    v, f = split_box(2)
    o, d = aimed_rays(v * 3 - 3, f, n, seed=seed)
    return o, d


def answers(scene, o, d):
    """Every column of the nearest, any and all hits: what must survive the trip."""
    h = scene.intersect(o, d)
    a = scene.intersect_all(o, d)
    out = {c: getattr(h, c) for c in COLUMNS}
    out["occluded"] = scene.occluded(o, d)
    out.update({"all_" + c: getattr(a, c) for c in COLUMNS + ("ray", "graze")})
    return out


def assert_same(x, y):
    assert x.keys() == y.keys()
    for k in x:
        a, b = x[k], y[k]
        if a.dtype == np.float32:
            a, b = bits(a), bits(b)
        assert np.array_equal(a, b), k


def test_a_scene_from_arrays_pickles_exactly():
    s = builder_scene()
    t = pickle.loads(pickle.dumps(s))
    assert t.path is None
    assert (t.num_primitives, t.num_objects) == (s.num_primitives, s.num_objects)
    assert np.array_equal(bits(t.triangles()), bits(s.triangles()))
    assert np.array_equal(bits(t.spheres()), bits(s.spheres()))
    assert np.array_equal(t.first_prim, s.first_prim)
    o, d = rays()
    ref = answers(s, o, d)
    assert (ref["inst_id"] >= 0).sum() > 20 and (ref["kind"] == 0).sum() > 5
    assert_same(answers(t, o, d), ref)
    # Twice over, and from float64 vertices rounded once: the same bits.
    assert_same(answers(pickle.loads(pickle.dumps(t)), o, d), ref)


def test_from_arrays_pickles_its_float32_rounding():
    rng = np.random.default_rng(12)
    v = rng.normal(size=(40, 3))
    f = rng.integers(0, 40, size=(60, 3))
    s = lumis.Scene.from_arrays(v, f)
    t = pickle.loads(pickle.dumps(s))
    assert np.array_equal(bits(t.triangles()), bits(s.triangles()))


def test_a_file_scene_pickles_by_path_and_reloads(tmp_path):
    v, f = split_box(2)
    path = write_obj(tmp_path / "box.obj", v, f)
    s = lumis.load(path, **{"render.spp": 3}, up="z")
    t = pickle.loads(pickle.dumps(s))
    assert t.path == str(path) and t.settings == s.settings and t.settings["spp"] == 3
    assert np.array_equal(bits(t.triangles()), bits(s.triangles()))  # turned to Y-up alike
    o, d = rays()
    assert_same(answers(t, o, d), answers(s, o, d))
    state = s._s.pickle_state()
    assert state["kind"] == "file" and state["up"] == "z"
    assert state["expect_files"] == [(str(path), sha256(path))]


def sha256(path):
    import hashlib
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_a_relative_path_reloads_from_another_directory(tmp_path, monkeypatch):
    v, f = split_box(2)
    write_obj(tmp_path / "box.obj", v, f)
    monkeypatch.chdir(tmp_path)
    s = lumis.load("box.obj")
    assert s.path == "box.obj"
    data = pickle.dumps(s)
    monkeypatch.chdir(SCENES)
    t = pickle.loads(data)
    assert t.path == str(tmp_path / "box.obj") and t.num_primitives == s.num_primitives


def test_a_changed_file_is_refused_by_name(tmp_path):
    v, f = split_box(2)
    path = write_obj(tmp_path / "box.obj", v, f)
    data = pickle.dumps(lumis.load(path))
    write_obj(path, v * 2, f)
    with pytest.raises(lumis.SceneError, match=rf"{path}: changed since the scene was pickled"):
        pickle.loads(data)
    # A change that leaves the file unreadable as OBJ is still named as a change.
    path.write_text("v 1 2\nf 1 2 3\n")
    with pytest.raises(lumis.SceneError, match=rf"{path}: changed since the scene was pickled"):
        pickle.loads(data)
    path.unlink()
    with pytest.raises(lumis.SceneError, match=rf"{path}: cannot be read to unpickle"):
        pickle.loads(data)


def test_a_changed_referenced_file_is_refused_by_name(tmp_path):
    v, f = split_box(2)
    mesh = write_obj(tmp_path / "mesh.obj", v, f)
    scene = tmp_path / "scene.toml"
    scene.write_text(
        (SCENES / "default.toml").read_text().replace("../assets/knot.obj", "mesh.obj")
    )
    s = lumis.load(scene, **{"sphere.0.radius": 0.5})
    t = pickle.loads(pickle.dumps(s))
    assert np.array_equal(bits(t.spheres()), bits(s.spheres()))
    assert t.spheres()[0, 4] == 0.5
    data = pickle.dumps(s)
    write_obj(mesh, v + 1, f)
    with pytest.raises(lumis.SceneError, match=rf"{mesh}: changed since the scene was pickled"):
        pickle.loads(data)


def test_a_pickle_of_an_asset_reloads():
    # The repository's own files: a glTF (its buffer and images are hashed too).
    s = lumis.load(ASSETS / "gltf" / "cube.gltf")
    files = [p for p, _ in s._s.pickle_state()["expect_files"]]
    assert files[0] == str(ASSETS / "gltf" / "cube.gltf") and len(files) >= 2
    assert pickle.loads(pickle.dumps(s)).num_primitives == s.num_primitives


def query(scene, o, d):
    """Run in a worker process: the scene came by pickle."""
    return answers(scene, o, d)


def test_a_spawned_pool_answers_as_the_parent(tmp_path):
    v, f = split_box(3)
    file_scene = lumis.load(write_obj(tmp_path / "box.obj", v * 0.5 - 0.75, f))
    scenes = [builder_scene(), file_scene]
    o, d = rays(800, seed=13)
    chunks = np.array_split(np.arange(len(o)), 3)
    jobs = [(s, o[c], d[c]) for s in scenes for c in chunks]
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        # A worker that dies while unpickling a task leaves a pool waiting forever: bounded.
        results = pool.starmap_async(query, jobs).get(timeout=120)
    for (s, oc, dc), got in zip(jobs, results):
        assert_same(got, answers(s, oc, dc))


def big_batch(n=400_000):
    rng = np.random.default_rng(14)
    o = rng.normal(size=(n, 3)).astype(np.float32) * 5
    d = (rng.uniform(-1, 1, size=(n, 3)) - o / 5).astype(np.float32)
    return o, d


def test_two_threads_query_at_once():
    s = builder_scene()
    o, d = big_batch(50_000)
    ref = s.intersect(o, d)
    out = [None, None]

    def work(k):
        out[k] = s.intersect(o, d)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for h in out:
        assert np.array_equal(bits(h.t), bits(ref.t)) and np.array_equal(h.prim_id, ref.prim_id)


def test_a_query_releases_the_gil():
    """A Python thread runs while a query is inside Rust. The switch interval is made so long
    that the querying thread would never hand the GIL over by itself: the counter can only
    advance between the two reads if the query released it."""
    s = builder_scene()
    o, d = big_batch()
    s.intersect(o[:10], d[:10])  # the hierarchy is built before the measured call
    count = [0]
    stop = threading.Event()

    def spin():
        while not stop.is_set():
            count[0] += 1
            time.sleep(0)  # hands the GIL back at once

    old = sys.getswitchinterval()
    sys.setswitchinterval(1000.0)
    spinner = threading.Thread(target=spin)
    try:
        spinner.start()
        while count[0] == 0:
            time.sleep(0.001)
        before = count[0]
        for _ in range(3):
            s.intersect(o, d)
            s.intersect_all(o[:50_000], d[:50_000])
        during = count[0] - before
    finally:
        stop.set()
        sys.setswitchinterval(old)
        spinner.join()
    assert during > 0


def test_unknown_state_is_refused():
    with pytest.raises(lumis.SceneError, match="not a pickled lumis scene"):
        lumis._builder.scene_from_state({"kind": "other"})
