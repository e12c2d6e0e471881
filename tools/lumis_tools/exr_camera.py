"""The camera rays of an EXR, rebuilt from its header alone (worldToCamera, worldToNDC), and
the checks that the matrices follow the OpenEXR/Imath conventions."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

@dataclass
class CameraRays:
    eye: np.ndarray  # (3,)
    forward: np.ndarray  # (3,) unit, camera +z in world space
    rays: np.ndarray  # (H*W, 8) float32 as traced


def camera_rays(w2c, w2ndc, width, height, checks):
    """The ray through every pixel centre, from the Imath (row-vector) matrices: a pinhole's,
    or an orthographic camera's when worldToNDC is affine.

    The eye is the camera-space origin mapped back to world space. A pixel's ray is the line of
    world points whose NDC x and y (after the homogeneous divide) are the pixel centre's: with
    p_h = (p, 1), x = (p_h . M[:, 0]) / (p_h . M[:, 3]), so p lies on the two planes
    p_h . (M[:, 0] - x M[:, 3]) = 0 and p_h . (M[:, 1] - y M[:, 3]) = 0, and the ray runs along
    their intersection. Only the x and y columns of worldToNDC are used, whatever its z."""
    c2w = np.linalg.inv(w2c)  # row-vector form: p_world = p_cam * c2w
    eye = c2w[3, :3] / c2w[3, 3]
    forward = c2w[2, :3] / np.linalg.norm(c2w[2, :3])
    right = c2w[0, :3] / np.linalg.norm(c2w[0, :3])
    up = c2w[1, :3] / np.linalg.norm(c2w[1, :3])
    xs = (np.arange(width) + 0.5) / width
    ys = (np.arange(height) + 0.5) / height
    nx, ny = np.meshgrid(xs, ys)  # (H, W)
    plane_x = w2ndc[None, None, :, 0] - nx[..., None] * w2ndc[None, None, :, 3]
    plane_y = w2ndc[None, None, :, 1] - ny[..., None] * w2ndc[None, None, :, 3]
    d = np.cross(plane_x[..., :3], plane_y[..., :3])
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    d *= np.sign(d @ forward)[..., None]
    # An orthographic worldToNDC is affine: no position changes the homogeneous w. Its pixel
    # rays are parallel and start on the camera plane through the eye, not at the eye.
    orthographic = bool(np.abs(w2ndc[:3, 3]).max() <= 1e-9 * np.abs(w2ndc).max())
    if orthographic:
        # Per pixel: the point on both pixel planes and on the camera plane.
        a = np.stack([plane_x[..., :3], plane_y[..., :3],
                      np.broadcast_to(forward, plane_x[..., :3].shape)], axis=-2)
        b = np.stack([-plane_x[..., 3], -plane_y[..., 3],
                      np.broadcast_to(forward @ eye, nx.shape)], axis=-1)
        origins = np.linalg.solve(a, b[..., None])[..., 0]
    else:
        origins = np.broadcast_to(eye, d.shape)

    # Conventions, checked on the numbers written.
    scale = np.abs(w2ndc).max() * max(1.0, np.abs(eye).max())
    o_h = np.concatenate([origins, np.ones(origins.shape[:2] + (1,))], axis=-1)
    resid = max(np.abs(np.sum(plane_x * o_h, -1)).max(),
                np.abs(np.sum(plane_y * o_h, -1)).max()) / scale
    if orthographic:
        spread = float(np.abs(d - forward).max())
        checks.add("orthographic: every pixel ray runs along the view direction",
                   spread < 1e-5, f"max deviation {spread:.2e}")
        checks.add("orthographic: every pixel ray starts on the camera plane", resid < 1e-5,
                   f"max relative residual {resid:.2e}")
    else:
        checks.add("every pixel ray passes through the worldToCamera eye", resid < 1e-5,
                   f"max relative residual {resid:.2e}")
    ahead = np.append(eye + forward, 1.0) @ w2c
    checks.add("worldToCamera: +z is the view direction", abs(ahead[2] - 1) < 1e-4
               and abs(ahead[0]) < 1e-4 and abs(ahead[1]) < 1e-4, f"{ahead[:3]}")
    # Camera-space directions (pinhole) or offsets on the camera plane (orthographic).
    cam = ((origins - eye) if orthographic else d) @ np.stack([right, up, forward]).T
    tl, br = cam[0, 0], cam[-1, -1]
    checks.add("worldToNDC: (0,0) is the top-left corner",
               tl[0] < 0 < tl[1] and br[1] < 0 < br[0],
               f"top-left camera dir {tl.round(4)}, bottom-right {br.round(4)}")
    # Round trip: a point along each ray projects back onto its pixel centre.
    p = origins + max(3.0, float(np.abs(eye).max())) * d
    q = np.concatenate([p, np.ones(p.shape[:2] + (1,))], axis=-1) @ w2ndc
    err = max(np.abs(q[..., 0] / q[..., 3] * width - (nx * width)).max(),
              np.abs(q[..., 1] / q[..., 3] * height - (ny * height)).max())
    checks.add("worldToNDC round trip to pixel centres", err < 1e-3, f"max {err:.2e} px")

    rays = np.zeros((height * width, 8), np.float32)
    rays[:, 0:3] = origins.reshape(-1, 3)
    rays[:, 3:6] = d.reshape(-1, 3)
    rays[:, 7] = np.inf
    return CameraRays(eye, forward, rays)
