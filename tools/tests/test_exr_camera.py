"""Rebuilding the camera rays from an EXR header (lumis_tools.exr_camera): matrices written in
the OpenEXR/Imath convention give the right rays and pass the convention checks; a header with
NDC y pointing up (bottom-left origin) is caught."""

from __future__ import annotations

import numpy as np

from lumis_tools.exr_camera import camera_rays
from lumis_tools.exr_file import Checks

EYE = np.array([1.0, 2.0, -5.0])
TAN = np.tan(np.radians(45))  # a 90 degree field of view both ways


def matrices(flip_y=False):
    """Row-vector (p' = p M) worldToCamera for a camera at EYE looking along +z with y up,
    and worldToNDC = worldToCamera x projection with NDC (0, 0) top-left."""
    w2c = np.eye(4)
    w2c[3, :3] = -EYE
    proj = np.zeros((4, 4))
    sy = 0.5 / TAN if flip_y else -0.5 / TAN
    proj[:, 0] = [0.5 / TAN, 0, 0.5, 0]   # x_ndc w = x / (2 tan) + w / 2, w = z_cam
    proj[:, 1] = [0, sy, 0.5, 0]           # y_ndc grows downwards
    proj[:, 2] = [0, 0, 1, 0]
    proj[:, 3] = [0, 0, 1, 0]
    return w2c, w2c @ proj


def failed(checks):
    return {c["check"] for c in checks.items if not c["ok"]}


def test_rays_from_imath_matrices():
    w2c, w2ndc = matrices()
    checks = Checks()
    cam = camera_rays(w2c, w2ndc, 4, 2, checks)
    assert failed(checks) == set()
    np.testing.assert_allclose(cam.eye, EYE)
    np.testing.assert_allclose(cam.forward, [0, 0, 1])
    d = cam.rays[:, 3:6].astype(np.float64)
    np.testing.assert_allclose(cam.rays[:, 0:3], np.broadcast_to(EYE, (8, 3)), rtol=1e-7)
    # Pixel (0, 0), centre at NDC (1/8, 1/4): x = (2 * 0.125 - 1) tan, y = (1 - 2 * 0.25) tan.
    np.testing.assert_allclose(d[0], np.array([-0.75, 0.5, 1]) / np.linalg.norm([-0.75, 0.5, 1]),
                               rtol=1e-6)
    # Last pixel (3, 1): bottom right.
    np.testing.assert_allclose(d[7], np.array([0.75, -0.5, 1]) / np.linalg.norm([0.75, -0.5, 1]),
                               rtol=1e-6)


def test_bottom_left_ndc_origin_is_caught():
    w2c, w2ndc = matrices(flip_y=True)
    checks = Checks()
    camera_rays(w2c, w2ndc, 4, 2, checks)
    assert failed(checks) == {"worldToNDC: (0,0) is the top-left corner"}


def test_column_vector_matrix_is_caught():
    # The same camera written transposed (column-vector form, as a bug might): the eye and the
    # view direction no longer come out of it.
    w2c, w2ndc = matrices()
    checks = Checks()
    camera_rays(w2c.T, w2ndc.T, 4, 2, checks)
    assert "every pixel ray passes through the worldToCamera eye" in failed(checks)
