"""trimesh 5.2.0's ray tests run with lumis's engine (a package, so that its conftest does not
shadow the package tests' own `conftest` module)."""
