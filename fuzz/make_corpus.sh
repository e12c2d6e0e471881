#!/usr/bin/env bash
# Seed corpus for the fuzz targets, made from the repository's own scenes and assets (and the
# paper's scenes when ../shared or LUMIS_PAPER_SCENES has them), rewritten so each seed stands
# alone in the fuzz targets' scratch folder: mesh paths point at the file the target puts there,
# glTF buffers become data URIs, GLBs are packed from the glTF assets, .m meshes are converted
# from the OBJ assets and ray files are written from a seeded generator.
#   fuzz/make_corpus.sh [OUT]     (default: fuzz/corpus; each target's seeds in OUT/<target>)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(dirname "$here")"
out="${1:-$here/corpus}"
paper="${LUMIS_PAPER_SCENES:-$repo/../shared/paper-scenes}"
mkdir -p "$out"/{toml,obj,mtl,gltf,glb,scn,m,npy,queries,hdr,exr}

python3 - "$repo" "$out" "$paper" <<'PY'
import base64, json, os, random, re, struct, sys
from pathlib import Path

repo, out, paper = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
LIMIT = 16 * 1024  # seeds stay small: libFuzzer mutates small inputs faster


def put(target, name, data):
    if isinstance(data, str):
        data = data.encode()
    if len(data) <= LIMIT:
        (out / target / name).write_bytes(data)


# TOML scenes: mesh files point at the triangle the target writes beside the scene.
for f in sorted((repo / "scenes").glob("*.toml")):
    put("toml", f.name, re.sub(r'file = "[^"]*"', 'file = "tri.obj"', f.read_text()))

# OBJ and MTL assets as they are (the OBJ target writes m.mtl beside each model).
for f in sorted((repo / "assets").glob("*.obj")):
    put("obj", f.name, re.sub(r"(?m)^mtllib .*$", "mtllib m.mtl", f.read_text()))
for f in sorted((repo / "assets").glob("*.mtl")):
    put("mtl", f.name, re.sub(r"(?m)^(newmtl) .*$", r"\1 red", f.read_text(), count=1))


def embedded(gltf_path):
    """The glTF document with every relative buffer and image URI inlined as a data URI."""
    doc = json.loads(gltf_path.read_text())
    for item in doc.get("buffers", []) + doc.get("images", []):
        uri = item.get("uri")
        if uri and not uri.startswith("data:"):
            f = gltf_path.parent / uri
            if not f.is_file():
                return None
            mime = "image/png" if uri.endswith(".png") else "application/octet-stream"
            item["uri"] = f"data:{mime};base64," + base64.b64encode(f.read_bytes()).decode()
    return doc


def glb(doc):
    """Packs a document with one data-URI buffer as GLB: JSON chunk, then the BIN chunk."""
    buffers = doc.get("buffers", [])
    bin_chunk = b""
    if len(buffers) == 1 and buffers[0].get("uri", "").startswith("data:"):
        bin_chunk = base64.b64decode(buffers[0].pop("uri").split(",", 1)[1])
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    bin_chunk += b"\0" * (-len(bin_chunk) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text
    if bin_chunk:
        body += struct.pack("<II", len(bin_chunk), 0x004E4942) + bin_chunk
    return b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body


for f in sorted((repo / "assets" / "gltf").rglob("*.gltf")):
    try:
        doc = embedded(f)
    except (ValueError, OSError):
        continue  # the deliberately broken assets (invalid JSON) are no use as seeds
    if doc is None:
        continue
    put("gltf", f.name, json.dumps(doc, indent=1))
    put("glb", f.stem + ".glb", glb(doc))
for f in sorted((repo / "assets" / "gltf").rglob("*.glb")):
    put("glb", f.name, f.read_bytes())

# .m meshes converted from the OBJ assets (positions and triangles only), plus the paper's.
for f in sorted((repo / "assets").glob("*.obj")):
    lines, nv = [], 0
    for raw in f.read_text().splitlines():
        w = raw.split()
        if w[:1] == ["v"]:
            nv += 1
            lines.append(f"Vertex {nv} {' '.join(w[1:4])}")
        elif w[:1] == ["f"] and len(w) >= 4:
            idx = [c.split("/")[0] for c in w[1:]]
            for k in range(1, len(idx) - 1):
                lines.append(f"Face {len(lines) + 1} {idx[0]} {idx[k]} {idx[k + 1]}")
    put("m", f.stem + ".m", "\n".join(lines) + "\n")
for f in sorted((paper / "models").glob("*.m")) if paper.is_dir() else []:
    put("m", f.name, f.read_bytes())

# .scn scenes: the paper's small ones with their models pointed at the target's tri.m, and one
# written here that uses every statement the reader knows.
put("scn", "every_statement.scn", """cameraPosition 0 0 10
cameraLookAt 0 0 0
cameraUp 0 1 0
cameraScreenWidth 12
dispersion -1
depthComplexity 2
maxReflections 3
light 5 5 5 0.9
sphere 0 0 0 1 FlatColor 0.6 0.2 0.9 null
sphere 2 0 0 1 ShinyColor 0.6 0.2 0.9 100 0.5 null
sphere -2 0 0 1 Glass 1.5 50 null
triangle 0 0 -1 1 0 -1 0 1 -1 FlatColor 1 1 1 null
model tri.m 1 0 0 -3 FlatColor 0.5 0.5 0.5 null
""")
for f in sorted((paper / "scenes").glob("*.scn")) if paper.is_dir() else []:
    put("scn", f.name, re.sub(r"(?m)^(\s*model\s+)\S+", r"\1tri.m", f.read_text()))

# Rays: (N, 8) float32 arrays in .npy versions 1 and 2, and an empty one.
rng = random.Random(14)


def npy(rows, version=1, cols=8):
    header = "{'descr': '<f4', 'fortran_order': False, 'shape': (%d, %d), }" % (len(rows), cols)
    prefix = 10 if version == 1 else 12
    header += " " * (-(prefix + len(header) + 1) % 64) + "\n"
    size = struct.pack("<H" if version == 1 else "<I", len(header))
    data = b"".join(struct.pack(f"<{cols}f", *r) for r in rows)
    return b"\x93NUMPY" + bytes([version, 0]) + size + header.encode() + data


rays = [[rng.uniform(-1, 1), rng.uniform(-1, 1), 5, rng.uniform(-1, 1), rng.uniform(-1, 1), -1,
         0, float("inf")] for _ in range(4)]
put("npy", "rays_v1.npy", npy(rays))
put("npy", "rays_v2.npy", npy(rays, version=2))
put("npy", "empty.npy", npy([]))

# Ray queries (fuzz/src/queries/decode.rs has the layout): the issue's examples and a few
# scenes with shared edges, far from the origin, tiny and huge.


def i8(*xs):
    return bytes(x & 0xFF for x in xs)


def f32(*xs):
    return struct.pack(f"<{len(xs)}f", *xs)


ZERO = bytes([0, 0])  # value: 0


def pow10(e, negative=False):
    return bytes([2 | (0x80 if negative else 0), e + 18])


def scene(prims, pool, centre=ZERO * 3, scale_exp=0):
    """prims: ("t", i, j, k) or ("s", centre index, 2-exponent of the radius / L)."""
    b = bytes([len(prims) - 1]) + centre + bytes([scale_exp + 30, len(pool) - 3])
    for v in pool:  # lattice points in quarters of L
        b += bytes([0]) + i8(*(round(4 * x) for x in v))
    for p in prims:
        b += bytes([0, *p[1:]]) if p[0] == "t" else bytes([1, p[1], p[2] + 64, 0])
    return b


def rays(*rs):
    return bytes([len(rs) - 1]) + b"".join(rs)


TMIN0_TMAXINF = bytes([0, 0])
AT_CENTRE = bytes([3, 255, 0, 0, 0, 0, 0])  # dir: aimed at C, no tilt, scale 1: d = C - o


def raw_origin(x, y, z):
    return bytes([0]) + f32(x, y, z)


def afar(prim, feature, e, f, u):
    return bytes([5, prim, feature, e, f]) + i8(*u)


def aimed(prim, feature, tilt=0, side=(0, 0, 0), scale=0):
    return bytes([3, prim, feature, tilt]) + i8(*side) + i8(scale)


octa_pool = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (-1, 0, 0), (0, -1, 0), (0, 0, -1)]
octa = [("t", a, b, c) for a in (0, 3) for b in (1, 4) for c in (2, 5)]
# The unit-sphere mesh from (x, x, x) with d = -o exactly: the front face near t = 1.
for x in (1e6, 1e19, 1e30, 3e38):
    put("queries", f"octahedron_from_{x:.0e}.bin",
        scene(octa, octa_pool) + rays(raw_origin(x, x, x) + AT_CENTRE + TMIN0_TMAXINF))
# From 1e30, at a quad's centroid and 1e-3 rad off it (the exact answer: a miss), with
# |d| = 1e30 and, scaled by 2^-100, about 1.
quad_pool = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
quad = [("t", 0, 1, 2), ("t", 0, 2, 3)]
put("queries", "quad_from_1e30.bin", scene(quad, quad_pool) + rays(
    afar(0, 6, 30, 0, (0, 0, 4)) + aimed(0, 6, 0, (0, 0, 0), -100) + TMIN0_TMAXINF,
    afar(0, 6, 30, 0, (0, 0, 4)) + aimed(0, 6, 6, (4, 4, 0), -100) + TMIN0_TMAXINF,
    afar(0, 6, 30, 0, (0, 0, 4)) + aimed(0, 6) + TMIN0_TMAXINF,
    afar(0, 6, 30, 0, (0, 0, 4)) + aimed(0, 6, 6, (4, 0, 0)) + TMIN0_TMAXINF,
    afar(1, 6, 30, 0, (1, 2, 4)) + aimed(1, 6, 6, (0, 4, 0)) + TMIN0_TMAXINF,
    afar(0, 4, 2, 0, (1, 2, 4)) + aimed(0, 4) + TMIN0_TMAXINF,  # the shared edge
))
# A unit sphere and a triangle below it, seen from 1e6 .. 3e38 (the sphere's front).
ball = [("s", 0, 0), ("t", 1, 2, 3)]
ball_pool = [(0, 0, 0), (-4, -4, -3), (4, -4, -3), (0, 4, -3)]
for e, f in ((6, 0), (10, 0), (19, 0), (30, 0), (38, 0), (38, 255)):
    put("queries", f"ball_from_1e{e}_{f}.bin", scene(ball, ball_pool) + rays(
        afar(0, 0, e, f, (0, 0, 4)) + aimed(0, 0) + TMIN0_TMAXINF,
        afar(0, 1, e, f, (1, 1, 4)) + aimed(0, 1) + TMIN0_TMAXINF,  # the tangent point
        afar(1, 6, e, f, (0, 1, 4)) + aimed(1, 6) + TMIN0_TMAXINF,
    ))
# A fan of four triangles around a shared vertex, near and far from the origin, at every
# scale, with rays at its edges and vertex.
fan_pool = [(0, 0, 0), (2, 0, 0), (0, 2, 0), (-2, 0, 0), (0, -2, 0)]
fan = [("t", 0, 1, 2), ("t", 0, 2, 3), ("t", 0, 3, 4), ("t", 0, 4, 1)]
fan_rays = rays(
    bytes([2]) + i8(1, 1, 8) + aimed(0, 0) + TMIN0_TMAXINF,
    bytes([2]) + i8(1, 3, 8) + aimed(0, 5) + TMIN0_TMAXINF,
    bytes([2]) + i8(-3, 1, 8) + aimed(1, 4) + TMIN0_TMAXINF,
    afar(2, 6, 20, 0, (1, 1, 4)) + aimed(0, 0) + TMIN0_TMAXINF,
)
for name, centre, exp in (("origin", ZERO * 3, 0), ("far", pow10(18) + pow10(17, True) + ZERO, 12),
                          ("tiny", ZERO * 3, -30), ("huge", ZERO * 3, 17)):
    put("queries", f"fan_{name}.bin", scene(fan, fan_pool, centre, exp) + fan_rays)
# Axis-aligned rays with zero and negative-zero components (0 * inf in slab tests), and a
# duplicated triangle and a huge sphere.
put("queries", "axis_rays.bin", scene(quad + [("t", 0, 1, 2), ("s", 2, 30)], quad_pool) + rays(
    bytes([2]) + i8(2, 2, 8) + bytes([2, 2 | 8 | 16, 0, 12, 0]) + TMIN0_TMAXINF,
    bytes([2]) + i8(0, 0, 0) + bytes([2, 1 | 32, 0, 13, 0]) + bytes([4, 0]),
))

# Environment maps: flat RGBE (the form tools/make_sky.py writes), the old #?RGBE signature, a
# run-length encoded scanline, and uncompressed scanline EXRs (float RGB, half Y) by hand.
def rgbe_file(w, h, sig=b"#?RADIANCE"):
    px = bytes((i * 37 + j * 11) % 256 for j in range(h) for i in range(w * 4))
    return sig + b"\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w) + px
put("hdr", "flat_4x2.hdr", rgbe_file(4, 2))
put("hdr", "rgbe_sig_8x4.hdr", rgbe_file(8, 4, b"#?RGBE"))
rle = bytes([2, 2, 0, 16]) + b"".join(bytes([128 + 16, 100 + c]) for c in range(4))
put("hdr", "rle_16x1.hdr", b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 16\n" + rle)


def exr_file(w, h, channels):
    """A single-part scanline EXR, no compression; `channels`: [(name, pixel type)]."""
    def attr(name, kind, value):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(value)) + value
    chlist = b"".join(n.encode() + b"\0" + struct.pack("<iB3xii", t, 0, 1, 1)
                      for n, t in channels) + b"\0"
    box = struct.pack("<iiii", 0, 0, w - 1, h - 1)
    head = (struct.pack("<ii", 20000630, 2) + attr("channels", "chlist", chlist)
            + attr("compression", "compression", b"\0") + attr("dataWindow", "box2i", box)
            + attr("displayWindow", "box2i", box) + attr("lineOrder", "lineOrder", b"\0")
            + attr("pixelAspectRatio", "float", struct.pack("<f", 1.0))
            + attr("screenWindowCenter", "v2f", struct.pack("<ff", 0, 0))
            + attr("screenWindowWidth", "float", struct.pack("<f", 1.0)) + b"\0")
    lines = []
    for y in range(h):
        data = b""
        for n, t in channels:  # channels in name order, each a run of the line's samples
            for x in range(w):
                v = 0.25 + 0.5 * ((x + y + len(n)) % 3)
                data += struct.pack("<e", v) if t == 1 else struct.pack("<f", v)
        lines.append(struct.pack("<ii", y, len(data)) + data)
    offsets, at = [], len(head) + 8 * h
    for line in lines:
        offsets.append(at)
        at += len(line)
    return head + b"".join(struct.pack("<Q", o) for o in offsets) + b"".join(lines)
put("exr", "rgb_float_4x2.exr", exr_file(4, 2, [("B", 2), ("G", 2), ("R", 2)]))
put("exr", "y_half_2x2.exr", exr_file(2, 2, [("Y", 1)]))
PY
for t in toml obj mtl gltf glb scn m npy queries hdr exr; do
    printf '%s: %s seeds\n' "$t" "$(ls "$out/$t" | wc -l)"
done
