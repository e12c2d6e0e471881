"""A Cryptomatte reader written from the Cryptomatte specification 1.1.0 (Psyop et al.), shared
with nothing in lumis's Rust code, so that it can check what lumis writes.

What the specification defines, and this module implements:

- ids: the 32-bit MurmurHash3 (x86 variant, seed 0) of a name's UTF-8 bytes, turned into a
  float32 by copying its bits with the exponent clamped to 1..254 (`uint32_to_float32`), so
  that no id is a NaN, an infinity, zero or a denormal;
- layers: a type name `T` (`CryptoObject`) whose channels `T00.R/G/B/A`, `T01.R/G/B/A`, ...
  hold (id, coverage) of ranks 0 and 1, 2 and 3, ...; empty ranks are id 0, coverage 0;
- metadata: `cryptomatte/<key>/name` (the type name), `/hash` (`MurmurHash3_32`),
  `/conversion` (`uint32_to_float32`) and the optional `/manifest`, a JSON object of name to the
  8 hex digits of the id's float bits. The key is at most 7 characters; a hash of the type name
  is suggested (lumis uses the first 7 hex digits of its MurmurHash3).

The matte of a name is the sum over ranks of the coverage where the rank's id is the name's id.
Ids are compared as bits, never as floats."""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

MASK32 = 0xFFFFFFFF
HASH = "MurmurHash3_32"
CONVERSION = "uint32_to_float32"
_ATTR = re.compile(r"^cryptomatte/([^/]+)/(name|hash|conversion|manifest|manif_file)$")


def _rotl32(x: int, r: int) -> int:
    return ((x << r) | (x >> (32 - r))) & MASK32


def _mix_block(k: int) -> int:
    # The per-block scramble of MurmurHash3_x86_32: multiply, rotate 15, multiply.
    k = (k * 0xCC9E2D51) & MASK32
    k = _rotl32(k, 15)
    return (k * 0x1B873593) & MASK32


def murmur3_32(data: bytes | str, seed: int = 0) -> int:
    """MurmurHash3_x86_32 of `data` (a str is hashed as UTF-8), as an unsigned 32-bit int."""
    if isinstance(data, str):
        data = data.encode("utf-8")
    h = seed & MASK32
    whole = len(data) - len(data) % 4
    for i in range(0, whole, 4):
        h ^= _mix_block(int.from_bytes(data[i:i + 4], "little"))
        h = (_rotl32(h, 13) * 5 + 0xE6546B64) & MASK32
    if whole < len(data):
        # The 1-3 tail bytes are scrambled like a block, but the state is not rotated.
        h ^= _mix_block(int.from_bytes(data[whole:], "little"))
    h ^= len(data) & MASK32
    # fmix32: the final avalanche.
    h ^= h >> 16
    h = (h * 0x85EBCA6B) & MASK32
    h ^= h >> 13
    h = (h * 0xC2B2AE35) & MASK32
    return h ^ (h >> 16)


def hash_to_id_bits(h: int) -> int:
    """The bits of the float32 id of hash `h` (`uint32_to_float32`): sign and mantissa as they
    are, the exponent clamped to [1, 254] (0 would be zero/denormal, 255 inf/NaN)."""
    exponent = min(max((h >> 23) & 0xFF, 1), 254)
    return (h & 0x807FFFFF) | (exponent << 23)


def bits_to_float(bits: int) -> np.float32:
    """The float32 whose bits are `bits`."""
    return np.array([bits], np.uint32).view(np.float32)[0]


def name_id_bits(name: str) -> int:
    """The id of `name` as float bits (the manifest's hex, as an int)."""
    return hash_to_id_bits(murmur3_32(name))


def name_id(name: str) -> np.float32:
    """The id of `name` as the float32 a pixel holds."""
    return bits_to_float(name_id_bits(name))


def metadata_key(type_name: str) -> str:
    """lumis's metadata key of a type: the first 7 of the 8 hex digits of its MurmurHash3."""
    return f"{murmur3_32(type_name):08x}"[:7]


class CryptomatteError(Exception):
    """The file is not a Cryptomatte this reader understands; the message says why."""


@dataclass
class CryptoType:
    """One Cryptomatte type of a file: its metadata and the (id, coverage) channels of its
    ranks, `ids`/`coverage` shaped (H, W, levels), ids as uint32 float bits."""

    key: str
    name: str
    hash: str | None
    conversion: str | None
    manifest: dict | None  # name -> 8 hex digits, None when the file has none
    channels: list  # channel names, rank order: [(id, coverage), ...]
    ids: np.ndarray
    coverage: np.ndarray

    @property
    def levels(self) -> int:
        return self.ids.shape[-1]

    def matte(self, name_or_bits) -> np.ndarray:
        """The (H, W) matte of a name (str) or id (float bits as int)."""
        bits = name_id_bits(name_or_bits) if isinstance(name_or_bits, str) else name_or_bits
        return np.where(self.ids == np.uint32(bits), self.coverage, 0).sum(axis=-1)

    def mattes(self) -> dict:
        """{name: matte} for every manifest name."""
        return {n: self.matte(n) for n in (self.manifest or {})}

    def problems(self) -> list:
        """What is wrong with the metadata by the specification (and lumis's key choice)."""
        out = []
        if self.hash != HASH:
            out.append(f"{self.name}: hash {self.hash!r}, want {HASH!r}")
        if self.conversion != CONVERSION:
            out.append(f"{self.name}: conversion {self.conversion!r}, want {CONVERSION!r}")
        if len(self.key) > 7:
            out.append(f"{self.name}: key {self.key!r} is longer than 7 characters")
        if self.key != metadata_key(self.name):
            out.append(f"{self.name}: key {self.key!r}, lumis's rule gives "
                       f"{metadata_key(self.name)!r}")
        if self.manifest is None:
            out.append(f"{self.name}: no manifest")
        for n, hexbits in (self.manifest or {}).items():
            want = f"{name_id_bits(n):08x}"
            if not (isinstance(hexbits, str) and re.fullmatch(r"[0-9a-f]{8}", hexbits)):
                out.append(f"{self.name}: manifest {n!r}: {hexbits!r} is not 8 hex digits")
            elif hexbits != want:
                out.append(f"{self.name}: manifest {n!r}: {hexbits}, its hash gives {want}")
        return out


@dataclass
class CryptoFile:
    """An EXR's Cryptomatte types by type name, with the pixels of its other channels."""

    path: Path
    width: int
    height: int
    types: dict  # type name -> CryptoType
    pixels: dict = field(default_factory=dict)  # every channel: name -> (H, W) float32
    formats: dict = field(default_factory=dict)  # channel name -> "float" / "half"

    def type(self, name: str) -> CryptoType:
        if name not in self.types:
            raise CryptomatteError(f"{self.path}: no Cryptomatte {name!r} "
                                   f"(has {sorted(self.types)})")
        return self.types[name]


def metadata(attributes: dict) -> dict:
    """{key: {field: value}} of the `cryptomatte/<key>/<field>` entries of a header."""
    out: dict = {}
    for attr, value in attributes.items():
        m = _ATTR.match(attr)
        if m:
            out.setdefault(m.group(1), {})[m.group(2)] = value
    return out


def rank_channels(type_name: str, channel_names) -> list:
    """[(id channel, coverage channel), ...] in rank order for `type_name`: layers `T00`,
    `T01`, ... each R/G (even rank) and B/A (odd rank); numbering must start at 00 without
    gaps. A type's preview channels (`T.R`, no number) are not ranks."""
    pattern = re.compile(re.escape(type_name) + r"(\d+)\.([RGBArgba])$")
    layers: dict = {}
    for c in channel_names:
        m = pattern.match(c)
        if m:
            layers.setdefault(int(m.group(1)), {})[m.group(2).upper()] = c
    if not layers:
        raise CryptomatteError(f"{type_name}: no {type_name}00.R/G/B/A channels")
    if sorted(layers) != list(range(len(layers))):
        raise CryptomatteError(f"{type_name}: layer numbers {sorted(layers)} are not 00, 01, ...")
    out = []
    for n in range(len(layers)):
        got = layers[n]
        if set(got) != set("RGBA"):
            raise CryptomatteError(f"{type_name}{n:02}: channels {sorted(got)}, want R, G, B, A")
        out += [(got["R"], got["G"]), (got["B"], got["A"])]
    return out


def decode(path, attributes: dict, pixels: dict, formats: dict, width: int, height: int):
    """A CryptoFile from a header (`attributes`: name -> value) and channels already read."""
    types = {}
    for key, meta in metadata(attributes).items():
        if "name" not in meta:
            raise CryptomatteError(f"{path}: cryptomatte/{key}/ has no name")
        name = meta["name"]
        pairs = rank_channels(name, pixels)
        for c in (c for pair in pairs for c in pair):
            # A HALF id is another id: the hash bits would be rounded.
            if formats.get(c, "float") != "float":
                raise CryptomatteError(f"{path}: {c} is {formats[c]}, the specification's ids "
                                       "need 32-bit float")
        manifest = None
        if "manifest" in meta:
            try:
                manifest = json.loads(meta["manifest"])
            except json.JSONDecodeError as e:
                raise CryptomatteError(f"{path}: {name}: manifest is not JSON: {e}") from e
            if not isinstance(manifest, dict):
                raise CryptomatteError(f"{path}: {name}: manifest is not a JSON object")
        ids = np.stack([np.ascontiguousarray(pixels[i], np.float32).view(np.uint32)
                        for i, _ in pairs], axis=-1)
        cov = np.stack([np.asarray(pixels[c], np.float32) for _, c in pairs], axis=-1)
        types[name] = CryptoType(key, name, meta.get("hash"), meta.get("conversion"),
                                 manifest, pairs, ids, cov)
    return CryptoFile(Path(path), width, height, types, pixels, formats)


def read(path) -> CryptoFile:
    """The Cryptomatte types of the EXR at `path`, read with OpenImageIO (data window)."""
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        raise CryptomatteError(f"cannot open {path}: {oiio.geterror()}")
    try:
        spec = inp.spec()
        data = inp.read_image(0, 0, 0, spec.nchannels, oiio.FLOAT)
        if data is None:
            raise CryptomatteError(f"cannot read the pixels of {path}: {inp.geterror()}")
    finally:
        inp.close()
    data = np.asarray(data, np.float32).reshape(spec.height, spec.width, spec.nchannels)
    names = list(spec.channelnames)
    pixels = {n: data[:, :, i] for i, n in enumerate(names)}
    formats = {n: str(spec.channelformat(i)) for i, n in enumerate(names)}
    attributes = {a.name: a.value for a in spec.extra_attribs}
    return decode(path, attributes, pixels, formats, spec.width, spec.height)
