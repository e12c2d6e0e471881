"""Loads a scene's geometry independently of lumis.

OBJ and glTF go through trimesh (with its scene graph transforms); lumis TOML scenes are read
with tomllib; the paper's `.scn`/`.m` files are parsed here. Nothing is shared with the Rust
loaders, so a loader bug on either side shows up as unmatched triangles.

Every coordinate is rounded to float32 after transforms, as lumis (and Embree) store them; the
oracle then works in float64 on those exact values.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

# LoadError is raised here too, and imported from here by the tools.
from .models import LoadError, load_model, transform_triangles  # noqa: F401


@dataclass
class Camera:
    """A look-at pinhole camera; `fov` is the vertical field of view in degrees (None when the
    scene describes its image plane another way, as `.scn` does)."""

    position: np.ndarray
    look_at: np.ndarray
    up: np.ndarray
    fov: float | None


@dataclass
class Geometry:
    """Triangles `(M, 3, 3)` and spheres `(S, 4)` (centre xyz, radius) in world space, float64
    holding float32 values. `vertex_normals` is `(M, 3, 3)`, NaN for flat-shaded triangles."""

    triangles: np.ndarray = field(default_factory=lambda: np.zeros((0, 3, 3)))
    vertex_normals: np.ndarray = field(default_factory=lambda: np.zeros((0, 3, 3)))
    spheres: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))
    # Primitives whose shading normal is perturbed (the paper's NormalMap): N is not comparable.
    sphere_normal_mapped: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))
    triangle_normal_mapped: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))
    camera: Camera | None = None

    def add_triangles(self, tris, normals=None, normal_mapped=False):
        tris = np.asarray(tris, np.float64).reshape(-1, 3, 3)
        if normals is None:
            normals = np.full(tris.shape, np.nan)
        self.triangles = np.concatenate([self.triangles, f32(tris)])
        self.vertex_normals = np.concatenate([self.vertex_normals, normals])
        flags = np.full(len(tris), normal_mapped)
        self.triangle_normal_mapped = np.concatenate([self.triangle_normal_mapped, flags])

    def add_sphere(self, center, radius, normal_mapped=False):
        row = f32(np.array([[*center, radius]], np.float64))
        self.spheres = np.concatenate([self.spheres, row])
        self.sphere_normal_mapped = np.append(self.sphere_normal_mapped, normal_mapped)

    def bounds(self):
        """(lo, hi) of everything; spheres by their boxes."""
        pts = [self.triangles.reshape(-1, 3)]
        if len(self.spheres):
            c, r = self.spheres[:, :3], self.spheres[:, 3:]
            pts += [c - r, c + r]
        pts = np.concatenate(pts)
        if not len(pts):
            return np.zeros(3), np.zeros(3)
        return pts.min(0), pts.max(0)


def f32(a):
    """Rounds to the nearest float32 and back to float64."""
    return np.asarray(a, np.float64).astype(np.float32).astype(np.float64)


def load_geometry(path) -> Geometry:
    """Loads `.toml`, `.scn`, `.obj`, `.gltf`, `.glb` or `.m` (chosen by extension)."""
    path = Path(path)
    ext = path.suffix.lower()
    g = Geometry()
    if ext == ".toml":
        _load_toml(path, g)
    elif ext == ".scn":
        _load_scn(path, g)
    elif ext in (".obj", ".gltf", ".glb"):
        tris, normals = load_model(path)
        g.add_triangles(tris, normals)
    elif ext == ".m":
        tris, _ = read_m(path)
        g.add_triangles(tris)
    else:
        raise LoadError(f"{path}: unknown scene type {ext!r}")
    return g


# ---------------------------------------------------------------------------------------------
# The paper's .m meshes


def read_m(path: Path):
    """Triangles `(M, 3, 3)` and the raw vertex array of a `.m` file (`Vertex i x y z ...`,
    `Face j a b c` with vertex numbers as given by the Vertex lines)."""
    verts, faces = {}, []
    with open(path) as f:
        for line_no, line in enumerate(f, 1):
            tok = line.split()
            if not tok or tok[0].startswith("#"):
                continue
            try:
                if tok[0] == "Vertex":
                    verts[int(tok[1])] = [float(t) for t in tok[2:5]]
                elif tok[0] == "Face":
                    faces.append([int(t) for t in tok[2:5]])
            except (ValueError, IndexError) as e:
                raise LoadError(f"{path}: line {line_no}: {e}") from e
    try:
        tris = np.array([[verts[i] for i in face] for face in faces], np.float64)
    except KeyError as e:
        raise LoadError(f"{path}: a Face uses undefined vertex {e}") from e
    return tris.reshape(-1, 3, 3), np.array(list(verts.values()), np.float64)


# ---------------------------------------------------------------------------------------------
# lumis TOML scenes


def _load_toml(path: Path, g: Geometry):
    try:
        doc = tomllib.loads(path.read_text())
    except (OSError, tomllib.TOMLDecodeError) as e:
        raise LoadError(f"{path}: {e}") from e
    cam = doc.get("camera")
    if cam:
        g.camera = Camera(np.array(cam["position"], float), np.array(cam["look_at"], float),
                          np.array(cam.get("up", [0, 1, 0]), float), float(cam.get("fov", 40)))
    for s in doc.get("sphere", []):
        g.add_sphere(s["center"], s["radius"])
    for i, mesh in enumerate(doc.get("mesh", [])):
        if "file" in mesh:
            file = path.parent / mesh["file"]
            if file.suffix.lower() == ".m":
                tris, _ = read_m(file)
                normals = np.full(tris.shape, np.nan)
            else:
                tris, normals = load_model(file)
        else:
            pos = np.array(mesh["positions"], np.float64)
            idx = np.array(mesh["indices"], np.int64).reshape(-1, 3)
            tris = pos[idx]
            normals = (np.array(mesh["normals"], np.float64)[idx] if "normals" in mesh
                       else np.full(tris.shape, np.nan))
        smooth = mesh.get("smooth")
        if smooth is False:
            normals = np.full(tris.shape, np.nan)
        elif smooth is True and np.isnan(normals).all():
            normals = area_weighted_normals(tris)
        tris, normals = transform_triangles(tris, normals, mesh_matrix(mesh))
        g.add_triangles(tris, normals)


def mesh_matrix(mesh):
    """translate * Rz * Ry * Rx * scale, as docs/scene-format.md defines it."""
    scale = mesh.get("scale", 1.0)
    scale = [scale] * 3 if isinstance(scale, (int, float)) else scale
    rx, ry, rz = (math.radians(a) for a in mesh.get("rotate", [0, 0, 0]))

    def rot(axis, a):
        c, s = math.cos(a), math.sin(a)
        i, j = [(1, 2), (2, 0), (0, 1)][axis]
        r = np.eye(3)
        r[i, i], r[i, j], r[j, i], r[j, j] = c, -s, s, c
        return r

    m = np.eye(4)
    m[:3, :3] = rot(2, rz) @ rot(1, ry) @ rot(0, rx) @ np.diag(scale)
    m[:3, 3] = mesh.get("translate", [0, 0, 0])
    return m


def area_weighted_normals(tris):
    """Per-corner normals of a mesh given as a triangle soup: corners at the same position share
    the area-weighted sum of their faces' normals."""
    face_n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    corners = tris.reshape(-1, 3)
    keys, inverse = np.unique(corners, axis=0, return_inverse=True)
    acc = np.zeros((len(keys), 3))
    np.add.at(acc, inverse.ravel(), np.repeat(face_n, 3, axis=0))
    acc /= np.maximum(np.linalg.norm(acc, axis=1, keepdims=True), 1e-300)
    return acc[inverse.ravel()].reshape(tris.shape)


# ---------------------------------------------------------------------------------------------
# The paper's .scn scenes


_MATERIAL_PARAMS = {"FlatColor": 3, "ShinyColor": 5, "Checkerboard": 9, "Glass": 2,
                    "Turbulence": 9, "Marble": 9, "Wood": 9, "CrissCross": 12}


def _load_scn(path: Path, g: Geometry):
    tokens = []  # (token, line)
    for line_no, line in enumerate(path.read_text().splitlines(), 1):
        for tok in line.split():
            if tok.startswith("#"):
                break
            tokens.append((tok, line_no))
    named = {}  # material name -> normal-mapped?
    pos = 0
    cam = {}

    def take(n):
        nonlocal pos
        if pos + n > len(tokens):
            raise LoadError(f"{path}: line {tokens[-1][1]}: statement cut short")
        out = tokens[pos:pos + n]
        pos += n
        return out

    def numbers(n):
        out = []
        for tok, line in take(n):
            try:
                out.append(float(tok))
            except ValueError:
                raise LoadError(f"{path}: line {line}: expected a number, found {tok!r}") from None
        return out

    def material():
        """Skips a MATERIAL; returns whether it carries a NormalMap."""
        (kind, line), = take(1)
        if kind in named:
            return named[kind]
        if kind not in _MATERIAL_PARAMS:
            raise LoadError(f"{path}: line {line}: unknown material {kind!r}")
        numbers(_MATERIAL_PARAMS[kind])
        (nm, line), = take(1)
        if nm == "null":
            return False
        if nm == "NormalMap":
            numbers(2)
            return True
        raise LoadError(f"{path}: line {line}: expected null or NormalMap, found {nm!r}")

    while pos < len(tokens):
        (kw, line), = take(1)
        if kw in ("cameraPosition", "cameraLookAt", "cameraUp"):
            cam[kw] = np.array(numbers(3))
        elif kw in ("cameraScreenWidth", "dispersion", "maxReflections", "depthComplexity"):
            numbers(1)
        elif kw == "light":
            numbers(4)
        elif kw == "sphere":
            c = numbers(4)
            g.add_sphere(c[:3], c[3], material())
        elif kw == "triangle":
            t = numbers(9)
            g.add_triangles([t], normal_mapped=material())
        elif kw == "model":
            (file, _), = take(1)
            size, tx, ty, tz = numbers(4)
            mapped = material()
            tris, verts = read_m(path.parent / file)
            lo, hi = verts.min(0), verts.max(0)
            diag = np.linalg.norm(hi - lo)
            tris = (tris - (lo + hi) / 2) * (size / diag) + np.array([tx, ty, tz])
            g.add_triangles(tris, normal_mapped=mapped)
        elif kw == "material":
            (name, _), = take(1)
            named[name] = material()
        elif kw == "startingMaterial":
            material()
        else:
            raise LoadError(f"{path}: line {line}: unknown keyword {kw!r}")
    if {"cameraPosition", "cameraLookAt"} <= cam.keys():
        g.camera = Camera(cam["cameraPosition"], cam["cameraLookAt"],
                          cam.get("cameraUp", np.array([0.0, 1.0, 0.0])), None)
