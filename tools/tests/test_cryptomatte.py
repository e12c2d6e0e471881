"""The Cryptomatte reader (lumis_tools.cryptomatte) against published answers and a synthetic
EXR whose every id and coverage is known; no lumis binary needed."""

from __future__ import annotations

import json

import numpy as np
import OpenImageIO as oiio
import pytest
from conftest import write_exr

from lumis_tools import cryptomatte as cm


@pytest.mark.parametrize("data, seed, want", [
    # The widely published MurmurHash3_x86_32 answers (SMHasher's algorithm), covering the
    # empty input, seeds, 1-3 byte tails and whole blocks.
    (b"", 0, 0),
    (b"", 1, 0x514E28B7),
    (b"", 0xFFFFFFFF, 0x81F16F39),
    (b"\0\0\0\0", 0, 0x2362F9DE),
    (b"aaaa", 0x9747B28C, 0x5A97808A),
    (b"aaa", 0x9747B28C, 0x283E0130),
    (b"aa", 0x9747B28C, 0x5D211726),
    (b"a", 0x9747B28C, 0x7FA09EA6),
    (b"abcd", 0x9747B28C, 0xF0478627),
    (b"abc", 0x9747B28C, 0xC84A62DD),
    (b"Hello, world!", 0x9747B28C, 0x24884CBA),
    (b"The quick brown fox jumps over the lazy dog", 0x9747B28C, 0x2FA826CD),
])
def test_murmur3_published_vectors(data, seed, want):
    assert cm.murmur3_32(data, seed) == want


@pytest.mark.parametrize("name, hexbits", [
    # The manifests printed in the Cryptomatte specification 1.1.0.
    ("bunny", "13851a76"),
    ("default", "42c9679f"),
    ("bunny_porcelain_mat", "b24b26d4"),
])
def test_ids_of_the_specifications_manifest(name, hexbits):
    assert f"{cm.name_id_bits(name):08x}" == hexbits
    assert cm.name_id(name).view(np.uint32) == int(hexbits, 16)


def test_strings_hash_as_utf8():
    assert cm.murmur3_32("é") == cm.murmur3_32("é".encode("utf-8"))


@pytest.mark.parametrize("h, want", [
    (0x00000000, 0x00800000),  # exponent 0 (zero) -> 1: the smallest normal
    (0x007FFFFF, 0x00FFFFFF),  # a denormal keeps its mantissa
    (0x7F800000, 0x7F000000),  # +inf -> exponent 254
    (0x7FFFFFFF, 0x7F7FFFFF),  # a NaN -> the largest finite
    (0xFF800001, 0xFF000001),  # a negative NaN keeps sign and mantissa
    (0x80000000, 0x80800000),  # -0 -> the smallest negative normal
    (0x3F800000, 0x3F800000),  # 1.0: exponents in range unchanged
])
def test_conversion_clamps_the_exponent(h, want):
    bits = cm.hash_to_id_bits(h)
    assert bits == want
    f = cm.bits_to_float(bits)
    assert np.isfinite(f) and f != 0 and abs(f) >= np.finfo(np.float32).tiny


def test_metadata_key_is_seven_hex_digits_of_the_type_hash():
    assert cm.metadata_key("CryptoObject") == f"{cm.murmur3_32('CryptoObject'):08x}"[:7]
    assert len(cm.metadata_key("x")) == 7


def synthetic(tmp, *, manifest=None, key=None, formats=None):
    """A 3x2 EXR with CryptoObject (4 levels) of names a, b, c:
    pixel (0,0) all a; (1,0) a 0.75 + b 0.25; (2,0) nothing; row 1: a/b/c thirds, c alone,
    b half (half the samples missed)."""
    a, b, c = (cm.name_id_bits(n) for n in "abc")
    third = np.float32(1 / 3)
    ranks = [  # per pixel: [(id bits, coverage), ...], best first
        [(a, 1.0)], [(a, 0.75), (b, 0.25)], [],
        [(a, third), (b, third), (c, third)], [(c, 1.0)], [(b, 0.5)],
    ]
    h, w, levels = 2, 3, 4
    chans = {}
    for layer in range(levels // 2):
        for ch in "RGBA":
            chans[f"CryptoObject{layer:02}.{ch}"] = np.zeros((h, w), np.float32)
    for p, rs in enumerate(ranks):
        y, x = divmod(p, w)
        for r, (bits, cov) in enumerate(rs):
            idc, covc = ("RG", "BA")[r % 2]
            chans[f"CryptoObject{r // 2:02}.{idc}"][y, x] = cm.bits_to_float(bits)
            chans[f"CryptoObject{r // 2:02}.{covc}"][y, x] = cov
    chans["A"] = np.array([[1, 1, 0], [1, 1, 0.5]], np.float32)
    key = key or cm.metadata_key("CryptoObject")
    man = manifest if manifest is not None else {n: f"{cm.name_id_bits(n):08x}" for n in "abc"}
    attrs = {f"cryptomatte/{key}/name": (oiio.TypeString, "CryptoObject"),
             f"cryptomatte/{key}/hash": (oiio.TypeString, "MurmurHash3_32"),
             f"cryptomatte/{key}/conversion": (oiio.TypeString, "uint32_to_float32"),
             f"cryptomatte/{key}/manifest": (oiio.TypeString, json.dumps(man))}
    return write_exr(tmp / "crypto.exr", chans, formats, attrs)


def test_decodes_a_synthetic_exr(tmp_path):
    f = cm.read(synthetic(tmp_path))
    t = f.type("CryptoObject")
    assert t.levels == 4 and t.problems() == []
    assert t.channels[1] == ("CryptoObject00.B", "CryptoObject00.A")
    assert t.channels[2] == ("CryptoObject01.R", "CryptoObject01.G")
    m = t.mattes()
    third = np.float32(1 / 3)
    np.testing.assert_array_equal(m["a"], [[1, 0.75, 0], [third, 0, 0]])
    np.testing.assert_array_equal(m["b"], [[0, 0.25, 0], [third, 0, 0.5]])
    np.testing.assert_array_equal(m["c"], [[0, 0, 0], [third, 1, 0]])
    total = sum(m.values())
    np.testing.assert_allclose(total, f.pixels["A"], atol=1e-6)
    # Empty ranks are id 0 (bits 0), never a name's id.
    assert (t.ids[0, 2] == 0).all()


def test_reports_a_wrong_manifest_and_key(tmp_path):
    bad = {"a": f"{cm.name_id_bits('b'):08x}", "b": "xyz", "c": f"{cm.name_id_bits('c'):08x}"}
    t = cm.read(synthetic(tmp_path, manifest=bad, key="0000000")).type("CryptoObject")
    text = "\n".join(t.problems())
    assert "'a'" in text and "not 8 hex digits" in text and "key '0000000'" in text
    assert "'c'" not in text


def test_refuses_half_ids(tmp_path):
    formats = {"CryptoObject00.R": "half"}
    with pytest.raises(cm.CryptomatteError, match="half"):
        cm.read(synthetic(tmp_path, formats=formats))


def test_layer_numbering_must_have_no_gaps():
    chans = {f"T{n}.{c}": None for n in ("00", "02") for c in "RGBA"}
    with pytest.raises(cm.CryptomatteError, match="not 00, 01"):
        cm.rank_channels("T", chans)
    # The preview channels (no number) and other types' channels are not ranks.
    chans = {f"T00.{c}": None for c in "RGBA"} | {"T.R": None, "TT00.R": None}
    assert cm.rank_channels("T", chans) == [("T00.R", "T00.G"), ("T00.B", "T00.A")]
