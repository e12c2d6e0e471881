"""trimesh's tests folder, vendored (see ../README.md)."""
