"""check_env_mitsuba's scene and measures: a perfect mirror sphere under an environment map,
written for lumis (TOML + flags) and for Mitsuba 3 (XML), a float64 reference of the same picture
from the convention's formula alone (lumis_tools.envmap), and the image comparison.

Nothing here imports Mitsuba or runs lumis, so the tests can check it all without either."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .envmap import direction_to_uv, lookup_bilinear, world_to_map

# The scene: a unit sphere at the origin, seen from slightly above so that its reflection shows
# the sky, the horizon and the ground; the camera looks along -Z (u = 0 of the map, its seam,
# straight ahead in the background), the sphere fills about 70% of the frame.
CAMERA_POSITION = (0.0, 0.6, 4.0)
CAMERA_LOOK_AT = (0.0, 0.0, 0.0)
CAMERA_UP = (0.0, 1.0, 0.0)
CAMERA_FOV_DEG = 40.0  # vertical, lumis's `fov`; Mitsuba gets fov_axis = "y"
SPHERE_CENTER = (0.0, 0.0, 0.0)
SPHERE_RADIUS = 1.0


@dataclass(frozen=True)
class Case:
    """One rendering of the scene: which map file, its rotation (degrees about +Y) and
    intensity, and how lumis is told: "toml" ([environment] in the scene), "define" (the
    scene's [environment] with `-D environment.rotation=...` on top) or "flags" (`--env`,
    `--env-rotation`, `--env-intensity` on a scene without [environment])."""

    name: str
    env: str  # file name in the work folder: sky.hdr or sky.exr
    rotation: float
    intensity: float = 1.0
    via: str = "toml"
    mirrored: bool = False  # Mitsuba only: the map flipped (x -> -x), for a negative control


# Every way of setting the environment, both file formats, a quarter turn, a turn that tells
# +theta from -theta, and an intensity.
CASES = (
    Case("rot 0", "sky.hdr", 0.0),
    Case("rot 90", "sky.hdr", 90.0),
    Case("rot -30 x2 exr flags", "sky.exr", -30.0, 2.0, "flags"),
    Case("rot 200 -D", "sky.hdr", 200.0, 1.0, "define"),
)
# Negative controls: lumis's image of the first case against Mitsuba's of the second. Each is
# a mistake the check must catch: a quarter turn, the sense of rotation, a mirrored map.
CONTROLS = (
    ("rot 0", Case("mitsuba rot 90", "sky.hdr", 90.0)),
    ("rot 90", Case("mitsuba rot -90", "sky.hdr", -90.0)),
    ("rot 0", Case("mitsuba mirrored", "sky.hdr", 0.0, mirrored=True)),
)


def _vec(v):
    return "[" + ", ".join(repr(float(x)) for x in v) + "]"


def _xyz(v):
    return ", ".join(repr(float(x)) for x in v)


def lumis_scene_toml(case: Case | None):
    """The TOML scene for lumis: the mirror (reflectivity 1, black diffuse, no specular), no
    lights, ambient 0; `[environment]` from `case` unless it is set by flags (or None)."""
    env = ""
    if case is not None and case.via in ("toml", "define"):
        # -D sets the rotation of a scene that has an [environment] already; start it at 0.
        rotation = 0.0 if case.via == "define" else case.rotation
        env = (f"\n[environment]\nfile = {json.dumps(case.env)}\n"
               f"rotation = {rotation!r}\nintensity = {case.intensity!r}\n")
    return f"""\
# check_env_mitsuba: a perfect mirror lit only by the environment.
[render]
ambient = [0.0, 0.0, 0.0]
max_depth = 2
{env}
[camera]
position = {_vec(CAMERA_POSITION)}
look_at = {_vec(CAMERA_LOOK_AT)}
up = {_vec(CAMERA_UP)}
fov = {CAMERA_FOV_DEG!r}

[materials.mirror]
diffuse = [0.0, 0.0, 0.0]
specular = [0.0, 0.0, 0.0]
reflectivity = 1.0

[[sphere]]
name = "mirror"
center = {_vec(SPHERE_CENTER)}
radius = {SPHERE_RADIUS!r}
material = "mirror"
"""


def lumis_flags(case: Case, folder: Path):
    """The `lumis render` flags that set `case`'s environment beyond the scene file."""
    if case.via == "flags":
        # `=` so that a negative angle is never taken for a flag.
        return ["--env", str(folder / case.env), f"--env-rotation={case.rotation!r}",
                f"--env-intensity={case.intensity!r}"]
    if case.via == "define":
        return ["-D", f"environment.rotation={case.rotation!r}"]
    return []


def mitsuba_scene_xml(case: Case, folder: Path, width, height, spp_axis, seed=0):
    """Mitsuba 3's description of the same picture: `path` with max_depth 3 (camera ray, the
    one mirror bounce, the environment; a convex mirror never sees itself), a `conductor` with
    material "none" (reflectance 1 at every angle), the `envmap` emitter with the same file,
    `scale` = intensity and the rotation as its to_world; stratified N*N samples, box filter."""
    mirror = '<scale x="-1"/>' if case.mirrored else ""
    return f"""\
<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="3"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="{CAMERA_FOV_DEG!r}"/>
        <string name="fov_axis" value="y"/>
        <transform name="to_world">
            <lookat origin="{_xyz(CAMERA_POSITION)}" target="{_xyz(CAMERA_LOOK_AT)}"
                    up="{_xyz(CAMERA_UP)}"/>
        </transform>
        <sampler type="stratified">
            <integer name="sample_count" value="{spp_axis * spp_axis}"/>
            <integer name="seed" value="{seed}"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="{width}"/>
            <integer name="height" value="{height}"/>
            <string name="pixel_format" value="rgb"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <shape type="sphere">
        <point name="center" value="{_xyz(SPHERE_CENTER)}"/>
        <float name="radius" value="{SPHERE_RADIUS!r}"/>
        <bsdf type="conductor"><string name="material" value="none"/></bsdf>
    </shape>
    <emitter type="envmap">
        <string name="filename" value="{folder / case.env}"/>
        <float name="scale" value="{case.intensity!r}"/>
        <transform name="to_world">{mirror}<rotate y="1" angle="{case.rotation!r}"/></transform>
    </emitter>
</scene>
"""


# --- The reference from the formula ---------------------------------------------------------


def camera_rays(width, height, spp_axis, jitter=None):
    """Unit directions (H, W, S, 3) of a pinhole camera's rays through each pixel's S = N^2
    strata: at the strata centres, or offset by `jitter` ((H, W, S, 2) in [0, 1)). Pixel (0, 0)
    is the top left; the image plane's +x is right = forward x up."""
    eye, target, up = (np.asarray(v, np.float64) for v in
                       (CAMERA_POSITION, CAMERA_LOOK_AT, CAMERA_UP))
    fwd = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(fwd, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, fwd)
    n = spp_axis
    sy, sx = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    offs = np.stack([sx.ravel(), sy.ravel()], axis=-1)  # (S, 2) stratum indices
    j = 0.5 if jitter is None else jitter
    sub = (offs + j) / n  # (.., S, 2) in [0, 1)
    py, px = np.meshgrid(np.arange(height), np.arange(width), indexing="ij")
    x = (px[..., None] + sub[..., 0]) / width  # (H, W, S)
    y = (py[..., None] + sub[..., 1]) / height
    half = np.tan(np.radians(CAMERA_FOV_DEG) / 2.0)
    sx_ = (2.0 * x - 1.0) * half * width / height
    sy_ = (1.0 - 2.0 * y) * half
    d = fwd + sx_[..., None] * right + sy_[..., None] * true_up
    return eye, d / np.linalg.norm(d, axis=-1, keepdims=True)


def mirror_directions(eye, d):
    """Where each camera ray goes after the mirror sphere (its reflection, or itself where it
    misses), and whether it hit."""
    c = np.asarray(SPHERE_CENTER, np.float64)
    oc = eye - c
    b = d @ oc
    disc = b * b - (oc @ oc - SPHERE_RADIUS ** 2)
    hit = disc > 0.0
    t = -b - np.sqrt(np.where(hit, disc, 0.0))
    n = (eye + t[..., None] * d - c) / SPHERE_RADIUS
    refl = d - 2.0 * np.sum(d * n, axis=-1, keepdims=True) * n
    return np.where(hit[..., None], refl, d), hit


def reference_image(env, case: Case, width, height, spp_axis=8):
    """The picture from the convention alone (float64): each stratum centre's ray, mirrored by
    the sphere, looked up in `env` (H, W, 3) with Mitsuba's bilinear rule; also the fraction
    of each pixel's rays that hit the sphere (1 on it, 0 in the background, between at its rim)."""
    eye, d = camera_rays(width, height, spp_axis)
    out, hit = mirror_directions(eye, d)
    local = world_to_map(out, case.rotation)
    if case.mirrored:
        local[..., 0] *= -1.0
    u, v = direction_to_uv(local)
    rgb = case.intensity * lookup_bilinear(env, u, v)
    return rgb.mean(axis=2), hit.mean(axis=2)


# --- Comparison -----------------------------------------------------------------------------


def rmse(a, b):
    """Root mean square difference over every pixel and channel."""
    diff = np.asarray(a, np.float64) - np.asarray(b, np.float64)
    return float(np.sqrt(np.mean(diff * diff))) if diff.size else 0.0


def exposure_scale(img, ref):
    """The factor that gives `img` the mean of `ref` (the ratio of the means)."""
    m = float(np.mean(np.asarray(img, np.float64)))
    return float(np.mean(np.asarray(ref, np.float64))) / m if m > 0.0 else float("inf")


@dataclass
class Agreement:
    scale: float  # lumis's exposure scale onto Mitsuba (ratio of means): 1 when units agree
    rmse: float  # after the scale
    rel_rmse: float  # rmse / RMS of the reference
    rel_rmse_unscaled: float
    regions: dict = field(default_factory=dict)  # region -> rel_rmse after the scale


def compare(img, ref, coverage=None):
    """`img` (lumis) against `ref` (Mitsuba) after the exposure match; with the reference's
    sphere `coverage` (H, W), also per region: "sphere" (every ray hit it: reflections),
    "background" (none did: the camera's own lookups), "rim" (the rest)."""
    img, ref = np.asarray(img, np.float64), np.asarray(ref, np.float64)
    s = exposure_scale(img, ref)
    rms = float(np.sqrt(np.mean(ref * ref))) or 1.0
    e = rmse(s * img, ref)
    regions = {}
    if coverage is not None:
        for name, mask in (("sphere", coverage >= 1.0), ("background", coverage <= 0.0),
                           ("rim", (coverage > 0.0) & (coverage < 1.0))):
            if mask.any():
                regions[name] = rmse(s * img[mask], ref[mask]) / rms
    return Agreement(s, e, e / rms, rmse(img, ref) / rms, regions)


def best_rotation(img, env, case: Case, width, height, step=5.0):
    """For a failed case: the rotation (every `step` degrees, the map plain and mirrored) whose
    picture from the formula (at `case`'s intensity) is closest to `img`, to say what kind of
    mistake it is (a sign, a quarter turn, a mirror, or none of these)."""
    best = None
    for mirrored in (False, True):
        for rot in np.arange(0.0, 360.0, step):
            trial = Case("trial", case.env, float(rot), case.intensity, mirrored=mirrored)
            ref, _ = reference_image(env, trial, width, height, 2)
            e = compare(img, ref).rel_rmse
            if best is None or e < best["rel_rmse"]:
                best = {"rotation": float(rot), "mirrored": mirrored, "rel_rmse": e}
    return best
