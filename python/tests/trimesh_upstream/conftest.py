"""trimesh's own ray tests (tests/test_ray.py of trimesh 5.2.0, vendored unchanged beside its
`generic.py` helpers and the models they load; see README.md) with lumis in place of Embree:
for every test here, `trimesh.ray.ray_pyembree` is a module whose `RayMeshIntersector` is
`lumis.trimesh.RayMeshIntersector`, so `use_embree=True` meshes and tests that import the
Embree engine get lumis's. `generic.py` finds `../models` beside itself, as in trimesh's
repository. Outside this folder trimesh is left as it was."""

from __future__ import annotations

import sys
import types

import pytest

try:
    import trimesh
except ImportError:  # the package's tests without trimesh (CI installs it: python[test])
    trimesh = None
    collect_ignore_glob = ["tests/*"]
else:
    import lumis.trimesh


@pytest.fixture(autouse=True)
def lumis_instead_of_embree(monkeypatch):
    engine = types.ModuleType("trimesh.ray.ray_pyembree")
    engine.RayMeshIntersector = lumis.trimesh.RayMeshIntersector
    monkeypatch.setitem(sys.modules, "trimesh.ray.ray_pyembree", engine)
    monkeypatch.setattr(trimesh.ray, "ray_pyembree", engine)
    monkeypatch.setattr(trimesh.ray, "has_embree", True)
    # The swap reaches what the tests build: a default mesh gets lumis's engine.
    assert isinstance(trimesh.creation.box().ray, lumis.trimesh.RayMeshIntersector)
    yield
