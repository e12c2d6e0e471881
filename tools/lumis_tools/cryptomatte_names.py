"""The object and material names a scene's Cryptomatte should carry, read from the scene files
themselves (TOML with tomllib, OBJ/MTL and glTF by hand), not from lumis: what the
`CryptoObject` and `CryptoMaterial` manifests of check_cryptomatte are compared with.

The naming rules are lumis's documented ones (docs/scene-format.md, obj-mtl.md, gltf.md): a
TOML element's `name`; an OBJ's `o`/`g` objects (`NAME/OBJECT` inside a TOML mesh, just `NAME`
when the file has one object) with their `newmtl` materials; a glTF node with a mesh by the node
name, its material by the glTF name. What these rules leave to lumis's choice (unnamed elements
and materials get generated names) is refused with UnsupportedScene rather than guessed."""

from __future__ import annotations

import json
import tomllib
from pathlib import Path


class UnsupportedScene(Exception):
    """The scene uses a case whose expected names this module does not derive."""


def obj_names(path: Path):
    """[(object name, usemtl name or None)] of the OBJ objects with faces, and the `newmtl`
    names of its MTL files."""
    objects, current, material, faces = [], "unnamed_object", None, 0

    def close():
        if faces:
            objects.append((current, material))

    defined = set()
    for line in path.read_text().splitlines():
        word, _, rest = line.strip().partition(" ")
        rest = rest.strip()
        if word in ("o", "g"):
            close()
            current, faces = rest, 0
        elif word == "usemtl":
            # A new material starts a new run of faces under the same name.
            close()
            material, faces = rest, 0
        elif word == "f":
            faces += 1
        elif word == "mtllib":
            mtl = path.parent / rest
            for m in mtl.read_text().splitlines():
                if m.strip().startswith("newmtl "):
                    defined.add(m.strip()[len("newmtl "):].strip())
    close()
    for name, m in objects:
        if m is None or m not in defined:
            raise UnsupportedScene(f"{path}: object {name!r} has no MTL material (lumis names "
                                   "its default material itself)")
    return objects, defined


def gltf_names(path: Path):
    """(object names, material names) of a .gltf whose default scene's nodes each carry a
    one-primitive mesh with a named material (children are not followed)."""
    doc = json.loads(path.read_text())
    scene = doc["scenes"][doc.get("scene", 0)]
    objects, materials = set(), set()
    for n in scene["nodes"]:
        node = doc["nodes"][n]
        if "children" in node or "mesh" not in node or "name" not in node:
            raise UnsupportedScene(f"{path}: node {n} is not a named leaf with a mesh")
        prims = doc["meshes"][node["mesh"]]["primitives"]
        if len(prims) != 1 or "name" not in doc["materials"][prims[0].get("material", -1)]:
            raise UnsupportedScene(f"{path}: node {n}: not one primitive with a named material")
        objects.add(node["name"])
        materials.add(doc["materials"][prims[0]["material"]]["name"])
    return objects, materials


def toml_names(path: Path):
    """(object names, material names) of a TOML scene whose elements are named and carry a
    `material`, or are meshes of an OBJ file without one."""
    doc = tomllib.loads(path.read_text())
    objects, materials = set(), set()
    for kind in ("sphere", "mesh"):
        for i, e in enumerate(doc.get(kind, [])):
            if "name" not in e:
                raise UnsupportedScene(f"{path}: {kind} {i} has no name")
            file = e.get("file")
            if "material" in e:
                objects.add(e["name"])
                materials.add(e["material"])
            elif file and file.endswith(".obj"):
                objs, _ = obj_names((path.parent / file).resolve())
                single = len({o for o, _ in objs}) == 1
                objects |= {e["name"] if single else f"{e['name']}/{o}" for o, _ in objs}
                materials |= {m for _, m in objs}
            else:
                raise UnsupportedScene(f"{path}: {kind} {e['name']!r} has no material")
    return objects, materials


def expected_names(path: Path):
    """{"CryptoObject": names, "CryptoMaterial": names} of the scene at `path`."""
    path = Path(path)
    if path.suffix == ".toml":
        objects, materials = toml_names(path)
    elif path.suffix == ".obj":
        objs, _ = obj_names(path)
        objects, materials = {o for o, _ in objs}, {m for _, m in objs}
    elif path.suffix == ".gltf":
        objects, materials = gltf_names(path)
    else:
        raise UnsupportedScene(f"{path}: no name rules for {path.suffix} files")
    return {"CryptoObject": objects, "CryptoMaterial": materials}
