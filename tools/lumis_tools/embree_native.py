"""Embree 4 driven directly, without embreex's Cython loop: its packet query `rtcIntersect8`
beside `rtcIntersect1`, both looped over in native code (used by bench_embree_packets).

- The library is embreex's own copy (`embreex.libs/libembree4*.so*`, found relative to the
  installed package), so the kernels are the very ones bench_embree times through embreex.
  The scene is set up through ctypes as embreex sets it up: a default device, scene flags
  ROBUST (or none), default build quality, one triangle mesh with a FLOAT3 vertex buffer of
  stride 16 and a UINT3 index buffer.
- The loops over rays and packets are a small C file compiled at run time with the system's C
  compiler (`$CC`, else `cc`) into a temporary shared library. A Python loop would cost about a
  microsecond per ctypes call, as much as the query itself, and measure ctypes rather than
  Embree. The C file includes no Embree header and links against nothing: it receives the
  addresses of `rtcIntersect1` / `rtcIntersect8` from ctypes, and its structs repeat the
  layout of Embree 4.4's `include/embree4/rtcore_ray.h` for the release builds (which embreex
  ships): RTC_MAX_INSTANCE_LEVEL_COUNT 1, RTC_GEOMETRY_INSTANCE_ARRAY defined (so RTCHit8 has
  instPrimID). `layout()` reads the compiled sizes and offsets back and checks them against
  HEADER_LAYOUT before anything is traced.
- Each loop does per ray what embreex's loop and `lumis hits` do: fill the ray and the
  hit's invalid ids from the `(N, 8)` float32 rays, query, and write the hit record (t, primID,
  geomID, u, v, Ng) to an array, so that the three engines' times cover the same work.
"""

from __future__ import annotations

import ctypes
import importlib.util
import os
import shutil
import subprocess
import time
from pathlib import Path

import numpy as np

from .exitcodes import SetupError

# Enum values of Embree 4.4's headers (rtcore_common.h, rtcore_buffer.h, rtcore_geometry.h,
# rtcore_scene.h, rtcore_device.h).
SCENE_FLAG_ROBUST = 1 << 2
GEOMETRY_TYPE_TRIANGLE = 0
BUFFER_TYPE_INDEX, BUFFER_TYPE_VERTEX = 0, 1
FORMAT_UINT3, FORMAT_FLOAT3 = 0x5003, 0x9003
RAY_QUERY_FLAG_INCOHERENT, RAY_QUERY_FLAG_COHERENT = 0, 1 << 16
FEATURE_FLAG_ALL = 0xFFFFFFFF
DEVICE_PROPERTY_VERSION, DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED = 0, 33
ERRORS = ("NONE", "UNKNOWN", "INVALID_ARGUMENT", "INVALID_OPERATION", "OUT_OF_MEMORY",
          "UNSUPPORTED_CPU", "CANCELLED", "LEVEL_ZERO_RAYTRACING_SUPPORT_MISSING")

# Sizes and offsets in bytes, worked out from rtcore_ray.h (4-byte fields; RTCRay/RTCHit
# aligned to 16, RTCRay8/RTCHit8 to 32): RTCRay is 12 fields (48); RTCHit is Ng_x..geomID (7
# fields), instID[1], instPrimID[1] = 36, padded to 48. RTCRay8 is 12 x 8 lanes (384); RTCHit8
# is 7 x 32 + instID[1][8] + instPrimID[1][8] = 288.
HEADER_LAYOUT = {
    "sizeof RTCRayHit": 96, "RTCRayHit.ray.tfar": 32, "RTCRayHit.hit": 48,
    "RTCRayHit.hit.u": 60, "RTCRayHit.hit.primID": 68, "RTCRayHit.hit.geomID": 72,
    "RTCRayHit.hit.instID": 76, "RTCRayHit.hit.instPrimID": 80,
    "sizeof RTCRayHit8": 672, "RTCRayHit8.ray.dir_x": 128, "RTCRayHit8.ray.tfar": 256,
    "RTCRayHit8.ray.mask": 288, "RTCRayHit8.hit": 384, "RTCRayHit8.hit.u": 480,
    "RTCRayHit8.hit.primID": 544, "RTCRayHit8.hit.geomID": 576, "RTCRayHit8.hit.instID": 608,
    "RTCRayHit8.hit.instPrimID": 640,
    "sizeof record": 32,
}

# The hit record both loops write per ray (`struct record` below).
RECORD = np.dtype([("t", "<f4"), ("prim", "<i4"), ("geom", "<i4"), ("u", "<f4"), ("v", "<f4"),
                   ("ng", "<f4", (3,))])

HELPER_C = r"""
#include <stddef.h>

#define LEVELS 1              /* RTC_MAX_INSTANCE_LEVEL_COUNT of the release builds */
#define INVALID 0xffffffffu   /* RTC_INVALID_GEOMETRY_ID */

struct ray1 { float org_x, org_y, org_z, tnear, dir_x, dir_y, dir_z, time, tfar;
              unsigned mask, id, flags; } __attribute__((aligned(16)));
struct hit1 { float ng_x, ng_y, ng_z, u, v; unsigned prim, geom, inst[LEVELS],
              inst_prim[LEVELS]; } __attribute__((aligned(16)));
struct rayhit1 { struct ray1 ray; struct hit1 hit; };
struct ray8 { float org_x[8], org_y[8], org_z[8], tnear[8], dir_x[8], dir_y[8], dir_z[8],
              time[8], tfar[8]; unsigned mask[8], id[8], flags[8]; } __attribute__((aligned(32)));
struct hit8 { float ng_x[8], ng_y[8], ng_z[8], u[8], v[8]; unsigned prim[8], geom[8],
              inst[LEVELS][8], inst_prim[LEVELS][8]; } __attribute__((aligned(32)));
struct rayhit8 { struct ray8 ray; struct hit8 hit; };

/* Embree writes instID and instPrimID for each instance level it was built with: spare room
   after the struct keeps a build with more levels from writing past it. The fields read here
   come before those arrays, so their offsets do not depend on the level count. */
union slot1 { struct rayhit1 rh; char room[512]; };
union slot8 { struct rayhit8 rh; char room[2048]; };

struct record { float t; int prim, geom; float u, v, ng[3]; };

typedef void (*intersect1_fn)(void *scene, struct rayhit1 *rayhit, void *args);
typedef void (*intersect8_fn)(const int *valid, void *scene, struct rayhit8 *rayhit, void *args);

void layout(long *out)
{
    long v[] = {
        sizeof(struct rayhit1), offsetof(struct rayhit1, ray.tfar), offsetof(struct rayhit1, hit),
        offsetof(struct rayhit1, hit.u), offsetof(struct rayhit1, hit.prim),
        offsetof(struct rayhit1, hit.geom), offsetof(struct rayhit1, hit.inst),
        offsetof(struct rayhit1, hit.inst_prim),
        sizeof(struct rayhit8), offsetof(struct rayhit8, ray.dir_x),
        offsetof(struct rayhit8, ray.tfar), offsetof(struct rayhit8, ray.mask),
        offsetof(struct rayhit8, hit), offsetof(struct rayhit8, hit.u),
        offsetof(struct rayhit8, hit.prim), offsetof(struct rayhit8, hit.geom),
        offsetof(struct rayhit8, hit.inst), offsetof(struct rayhit8, hit.inst_prim),
        sizeof(struct record)};
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) out[i] = v[i];
}

static void put(struct record *r, float t, unsigned prim, unsigned geom, float u, float v,
                float x, float y, float z)
{
    r->t = t;
    r->prim = prim == INVALID ? -1 : (int)prim;
    r->geom = geom == INVALID ? -1 : (int)geom;
    r->u = u; r->v = v; r->ng[0] = x; r->ng[1] = y; r->ng[2] = z;
}

/* rays: (n, 8) float32 origin, direction, tnear, tfar. */
void trace1(intersect1_fn intersect, void *scene, void *args, const float *rays, long n,
            struct record *out)
{
    union slot1 s;
    struct ray1 *ray = &s.rh.ray;
    struct hit1 *hit = &s.rh.hit;
    for (long i = 0; i < n; i++) {
        const float *r = rays + 8 * i;
        ray->org_x = r[0]; ray->org_y = r[1]; ray->org_z = r[2]; ray->tnear = r[6];
        ray->dir_x = r[3]; ray->dir_y = r[4]; ray->dir_z = r[5]; ray->time = 0.0f;
        ray->tfar = r[7]; ray->mask = ~0u; ray->id = 0; ray->flags = 0;
        hit->prim = hit->geom = INVALID;
        for (int l = 0; l < LEVELS; l++) hit->inst[l] = hit->inst_prim[l] = INVALID;
        intersect(scene, &s.rh, args);
        put(out + i, ray->tfar, hit->prim, hit->geom, hit->u, hit->v, hit->ng_x, hit->ng_y,
            hit->ng_z);
    }
}

/* lanes: (packets, 8) ray indices, -1 for an empty lane; lane 0 of each packet is a ray (an
   empty lane repeats it, so that every lane holds finite numbers; Embree skips it by the
   valid mask). */
void trace8(intersect8_fn intersect, void *scene, void *args, const float *rays,
            const int *lanes, long packets, struct record *out)
{
    union slot8 s __attribute__((aligned(32)));
    int valid[8] __attribute__((aligned(32)));
    struct ray8 *ray = &s.rh.ray;
    struct hit8 *hit = &s.rh.hit;
    for (long p = 0; p < packets; p++) {
        const int *lane = lanes + 8 * p;
        for (int k = 0; k < 8; k++) {
            valid[k] = lane[k] >= 0 ? -1 : 0;
            const float *r = rays + 8 * (long)(lane[k] >= 0 ? lane[k] : lane[0]);
            ray->org_x[k] = r[0]; ray->org_y[k] = r[1]; ray->org_z[k] = r[2];
            ray->tnear[k] = r[6]; ray->dir_x[k] = r[3]; ray->dir_y[k] = r[4];
            ray->dir_z[k] = r[5]; ray->time[k] = 0.0f; ray->tfar[k] = r[7];
            ray->mask[k] = ~0u; ray->id[k] = 0; ray->flags[k] = 0;
            hit->prim[k] = hit->geom[k] = INVALID;
            for (int l = 0; l < LEVELS; l++) hit->inst[l][k] = hit->inst_prim[l][k] = INVALID;
        }
        intersect(valid, scene, &s.rh, args);
        for (int k = 0; k < 8; k++)
            if (valid[k])
                put(out + lane[k], ray->tfar[k], hit->prim[k], hit->geom[k], hit->u[k],
                    hit->v[k], hit->ng_x[k], hit->ng_y[k], hit->ng_z[k]);
    }
}
"""


def packet_lanes(width, height, tile=(4, 2)):
    """`(P, 8)` int32 ray indices of a row-major `width` x `height` pixel grid: one packet per
    4 x 2 tile (4 pixels wide, 2 tall), tiles in row-major order, lanes row by row within the
    tile; -1 marks a lane past the right or bottom edge (partly filled packets at ragged
    edges). A tile's top-left pixel is always in the grid, so lane 0 is always a ray."""
    tw, th = tile
    assert tw * th == 8
    ty, tx = -(-height // th), -(-width // tw)
    ys = (np.arange(ty)[:, None, None, None] * th + np.arange(th)[None, None, :, None])
    xs = (np.arange(tx)[None, :, None, None] * tw + np.arange(tw)[None, None, None, :])
    ys, xs = np.broadcast_arrays(ys, xs)
    inside = (ys < height) & (xs < width)
    return np.where(inside, ys * width + xs, -1).astype(np.int32).reshape(-1, 8)


def compiler():
    """The C compiler to build the helper with: $CC, else cc, gcc or clang on PATH."""
    for name in filter(None, (os.environ.get("CC"), "cc", "gcc", "clang")):
        path = shutil.which(name)
        if path:
            return path
    raise SetupError("no C compiler found ($CC, cc, gcc, clang): the native loops around "
                     "rtcIntersect1/rtcIntersect8 are compiled at run time")


class Helper:
    """The C loops above, compiled into `folder` and loaded; checks their struct layout."""

    def __init__(self, folder: Path):
        src, so = Path(folder) / "embree_loops.c", Path(folder) / "embree_loops.so"
        src.write_text(HELPER_C)
        # -O2 without -march: the loops only copy; the time is spent inside Embree.
        cmd = [compiler(), "-O2", "-shared", "-fPIC", "-o", str(so), str(src)]
        done = subprocess.run(cmd, capture_output=True, text=True)
        if done.returncode != 0:
            raise SetupError(f"compiling the native loops failed: {' '.join(cmd)}\n"
                             + done.stderr[-2000:])
        self.lib = ctypes.CDLL(str(so))
        ptr = ctypes.c_void_p
        self.lib.trace1.argtypes = [ptr, ptr, ptr, ptr, ctypes.c_long, ptr]
        self.lib.trace8.argtypes = [ptr, ptr, ptr, ptr, ptr, ctypes.c_long, ptr]
        got = self.layout()
        if got != HEADER_LAYOUT:
            wrong = {k: (got[k], v) for k, v in HEADER_LAYOUT.items() if got[k] != v}
            raise SetupError(f"the compiled structs differ from rtcore_ray.h (got, want): {wrong}")

    def layout(self):
        out = (ctypes.c_long * len(HEADER_LAYOUT))()
        self.lib.layout(out)
        return dict(zip(HEADER_LAYOUT, out, strict=True))


def library_path() -> Path:
    """embreex's libembree4 (the wheel's `embreex.libs/`, or beside the package)."""
    spec = importlib.util.find_spec("embreex")
    if spec is None or not spec.submodule_search_locations:
        raise SetupError("embreex is not installed (pip install -r tools/requirements.txt)")
    pkg = Path(next(iter(spec.submodule_search_locations)))
    for folder in (pkg.parent / "embreex.libs", pkg, pkg / "lib"):
        found = sorted(folder.glob("libembree4*.so*"))
        if found:
            return found[0]
    raise SetupError(f"no libembree4*.so* in or beside {pkg}")


class IntersectArguments(ctypes.Structure):
    """RTCIntersectArguments (rtcore_scene.h); the trailing float is minWidthDistanceFactor,
    present only in builds with RTC_MIN_WIDTH and harmless otherwise."""

    _fields_ = [("flags", ctypes.c_uint), ("feature_mask", ctypes.c_uint),
                ("context", ctypes.c_void_p), ("filter", ctypes.c_void_p),
                ("intersect", ctypes.c_void_p), ("min_width_distance_factor", ctypes.c_float)]


class NativeEmbree:
    """One Embree device and scene of float32 `(M, 3, 3)` triangles (primitive i = triangle i),
    traced by the helper's loops. A query with `coherent` passes RTC_RAY_QUERY_FLAG_COHERENT;
    otherwise no arguments (NULL: Embree's defaults, incoherent), as embreex calls
    rtcIntersect1."""

    def __init__(self, triangles, helper: Helper, robust=True):
        self.helper = helper
        lib = self.lib = ctypes.CDLL(str(library_path()))
        vp, u = ctypes.c_void_p, ctypes.c_uint
        for name, res, args in [
            ("rtcNewDevice", vp, [ctypes.c_char_p]), ("rtcReleaseDevice", None, [vp]),
            ("rtcGetDeviceError", ctypes.c_int, [vp]),
            ("rtcGetDeviceProperty", ctypes.c_ssize_t, [vp, ctypes.c_int]),
            ("rtcNewScene", vp, [vp]), ("rtcReleaseScene", None, [vp]),
            ("rtcSetSceneFlags", None, [vp, ctypes.c_int]), ("rtcCommitScene", None, [vp]),
            ("rtcNewGeometry", vp, [vp, ctypes.c_int]), ("rtcReleaseGeometry", None, [vp]),
            ("rtcSetNewGeometryBuffer", vp, [vp, ctypes.c_int, u, ctypes.c_int,
                                             ctypes.c_size_t, ctypes.c_size_t]),
            ("rtcCommitGeometry", None, [vp]), ("rtcAttachGeometry", u, [vp, vp]),
        ]:
            getattr(lib, name).restype, getattr(lib, name).argtypes = res, args
        self.device = lib.rtcNewDevice(None)  # embreex's device: the default configuration
        if not self.device:
            raise SetupError("rtcNewDevice failed")
        self.scene = lib.rtcNewScene(self.device)
        lib.rtcSetSceneFlags(self.scene, SCENE_FLAG_ROBUST if robust else 0)
        # As lumis_tools/embree.py hands the mesh to embreex: 3 vertices per triangle, stride 16.
        tris = np.asarray(triangles, np.float32).reshape(-1, 3, 3)
        verts = np.zeros((3 * len(tris), 4), np.float32)
        verts[:, :3] = tris.reshape(-1, 3)
        geom = lib.rtcNewGeometry(self.device, GEOMETRY_TYPE_TRIANGLE)
        vbuf = lib.rtcSetNewGeometryBuffer(geom, BUFFER_TYPE_VERTEX, 0, FORMAT_FLOAT3, 16,
                                           len(verts))
        ibuf = lib.rtcSetNewGeometryBuffer(geom, BUFFER_TYPE_INDEX, 0, FORMAT_UINT3, 12,
                                           len(tris))
        self.check("creating the mesh")
        ctypes.memmove(vbuf, verts.ctypes.data, verts.nbytes)
        index = np.arange(3 * len(tris), dtype=np.uint32)
        ctypes.memmove(ibuf, index.ctypes.data, index.nbytes)
        lib.rtcCommitGeometry(geom)
        lib.rtcAttachGeometry(self.scene, geom)
        lib.rtcReleaseGeometry(geom)  # the scene holds it now
        self.check("attaching the mesh")
        self.coherent = IntersectArguments(RAY_QUERY_FLAG_COHERENT, FEATURE_FLAG_ALL)
        self.intersect1 = ctypes.cast(lib.rtcIntersect1, vp).value
        self.intersect8 = ctypes.cast(lib.rtcIntersect8, vp).value

    def check(self, what):
        code = self.lib.rtcGetDeviceError(self.device)
        if code:
            name = ERRORS[code] if code < len(ERRORS) else str(code)
            raise SetupError(f"Embree error RTC_ERROR_{name} while {what}")

    def property(self, prop):
        return self.lib.rtcGetDeviceProperty(self.device, prop)

    def version(self):
        v = self.property(DEVICE_PROPERTY_VERSION)
        return f"{v // 10000}.{v // 100 % 100}.{v % 100}"

    def commit(self):
        """Builds the BVH; returns its (wall, cpu) seconds."""
        wall, cpu = time.perf_counter(), time.process_time()
        self.lib.rtcCommitScene(self.scene)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        self.check("committing the scene")
        return wall, cpu

    def _args(self, coherent):
        return ctypes.addressof(self.coherent) if coherent else None

    def trace1(self, rays, coherent=False):
        """(wall seconds, this thread's CPU seconds, RECORD array) of rtcIntersect1 on every
        `(N, 8)` ray in turn."""
        rays = np.ascontiguousarray(rays, np.float32)
        out = np.empty(len(rays), RECORD)
        wall, cpu = time.perf_counter(), time.thread_time()
        self.helper.lib.trace1(self.intersect1, self.scene, self._args(coherent),
                               rays.ctypes.data, len(rays), out.ctypes.data)
        return time.perf_counter() - wall, time.thread_time() - cpu, out

    def trace8(self, rays, lanes, coherent=False):
        """(wall seconds, CPU seconds, RECORD array) of rtcIntersect8 on the packets `lanes`
        (see packet_lanes) of `rays`; each ray must be in one lane, so that every record is
        written."""
        rays = np.ascontiguousarray(rays, np.float32)
        lanes = np.ascontiguousarray(lanes, np.int32)
        assert lanes.ndim == 2 and lanes.shape[1] == 8 and (lanes[:, 0] >= 0).all()
        out = np.empty(len(rays), RECORD)
        wall, cpu = time.perf_counter(), time.thread_time()
        self.helper.lib.trace8(self.intersect8, self.scene, self._args(coherent),
                               rays.ctypes.data, lanes.ctypes.data, len(lanes), out.ctypes.data)
        return time.perf_counter() - wall, time.thread_time() - cpu, out

    def close(self):
        if self.scene:
            self.lib.rtcReleaseScene(self.scene)
            self.lib.rtcReleaseDevice(self.device)
            self.scene = self.device = None
