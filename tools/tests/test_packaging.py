"""The package's own promises: its dependencies are requirements.txt's pins, every script in
tools/ is an entry point of a module with a cli(), nothing edits sys.path, and importing the
package and its exit-status helper loads no third-party module."""

from __future__ import annotations

import ast
import importlib
import subprocess
import sys
import tomllib

from lumis_tools import TOOLS


def pins(path):
    return sorted(line.split("#")[0].strip() for line in path.read_text().splitlines()
                  if line.split("#")[0].strip())


def test_dependencies_are_the_pinned_requirements():
    project = tomllib.loads((TOOLS / "pyproject.toml").read_text())["project"]
    assert sorted(project["dependencies"]) == pins(TOOLS / "requirements.txt")
    assert sorted(project["optional-dependencies"]["mitsuba"]) == \
        pins(TOOLS / "requirements-mitsuba.txt")


def test_scripts_are_entry_points_of_modules_with_cli():
    scripts = sorted(p for p in TOOLS.glob("*.py"))
    assert len(scripts) == 21
    for script in scripts:
        tree = ast.parse(script.read_text())
        imports = [n for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
        assert [(n.module, [a.name for a in n.names]) for n in imports] == \
            [(f"lumis_tools.{script.stem}", ["cli"])], script.name
        assert callable(getattr(importlib.import_module(f"lumis_tools.{script.stem}"), "cli"))
    project = tomllib.loads((TOOLS / "pyproject.toml").read_text())["project"]
    for target in project["scripts"].values():
        module, func = target.split(":")
        assert callable(getattr(importlib.import_module(module), func)), target


def test_nothing_edits_sys_path():
    for path in [*TOOLS.glob("*.py"), *(TOOLS / "lumis_tools").glob("*.py")]:
        assert "sys.path.insert" not in path.read_text(), path.name


def test_package_import_is_light():
    # So that a tool can still say which requirement is missing, with status 2.
    code = ("import sys, lumis_tools, lumis_tools.exitcodes; "
            "print(sorted(m for m in ('numpy', 'trimesh', 'embreex', 'OpenImageIO') "
            "if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], cwd=TOOLS, capture_output=True,
                         text=True, check=True).stdout
    assert out.strip() == "[]"
