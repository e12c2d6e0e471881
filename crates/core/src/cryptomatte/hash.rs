//! The ids of Cryptomatte: the 32-bit MurmurHash3 (x86 variant, seed 0) of a name, turned into a
//! float that is neither NaN, infinite nor denormal, as the Cryptomatte specification defines.

/// MurmurHash3_x86_32 of `bytes` with seed 0, written from Austin Appleby's description of the
/// algorithm: 4-byte little-endian blocks mixed into the state, the 1-3 tail bytes mixed in
/// without the state rotation, then the length and the final avalanche (`fmix32`).
pub fn murmur3_32(bytes: &[u8]) -> u32 {
    const C1: u32 = 0xcc9e_2d51;
    const C2: u32 = 0x1b87_3593;
    let mix = |k: u32| k.wrapping_mul(C1).rotate_left(15).wrapping_mul(C2);
    let mut h: u32 = 0;
    let mut blocks = bytes.chunks_exact(4);
    for b in &mut blocks {
        h ^= mix(u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        h = h.rotate_left(13).wrapping_mul(5).wrapping_add(0xe654_6b64);
    }
    let tail = blocks.remainder();
    if !tail.is_empty() {
        let k = tail
            .iter()
            .rev()
            .fold(0u32, |k, &byte| (k << 8) | u32::from(byte));
        h ^= mix(k);
    }
    // The length enters modulo 2^32, as the reference's `int len` does.
    h ^= bytes.len() as u32;
    h ^= h >> 16;
    h = h.wrapping_mul(0x85eb_ca6b);
    h ^= h >> 13;
    h = h.wrapping_mul(0xc2b2_ae35);
    h ^ (h >> 16)
}

/// The bits of the float32 id the specification's `uint32_to_float32` conversion makes of
/// `hash`: sign and mantissa kept, the exponent clamped to 1..=254, so that no id reads as NaN,
/// infinity, zero or a denormal (which some compositors flush to zero).
pub fn id_bits(hash: u32) -> u32 {
    let exponent = ((hash >> 23) & 0xff).clamp(1, 254);
    (hash & 0x807f_ffff) | (exponent << 23)
}

/// The float32 pixel value of the id of `name` ([`murmur3_32`] then [`id_bits`]).
pub fn name_id(name: &str) -> f32 {
    f32::from_bits(id_bits(murmur3_32(name.as_bytes())))
}

/// The metadata key of a Cryptomatte layer: the first 7 hex digits of the MurmurHash3 of its
/// name, as the specification suggests, so that the key stays the same from shot to shot.
pub fn metadata_key(layer_name: &str) -> String {
    format!("{:08x}", murmur3_32(layer_name.as_bytes()))[..7].to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn murmur3_matches_the_reference_vectors() {
        // SMHasher's known answers for seed 0 (empty input, tails of 1-3 bytes, blocks).
        assert_eq!(murmur3_32(b""), 0);
        assert_eq!(murmur3_32(b"hello"), 0x248b_fa47);
        assert_eq!(murmur3_32(b"Hello, world!"), 0xc036_3e43);
        assert_eq!(
            murmur3_32(b"The quick brown fox jumps over the lazy dog"),
            0x2e4f_f723
        );
        assert_eq!(murmur3_32(&[0xff, 0xff, 0xff, 0xff]), 0x7629_3b50);
        assert_eq!(murmur3_32(&[0x21, 0x43, 0x65, 0x87]), 0xf55b_516b);
        assert_eq!(murmur3_32(&[0x21, 0x43, 0x65]), 0x7e4a_8634);
        assert_eq!(murmur3_32(&[0x21, 0x43]), 0xa0f7_b07a);
        assert_eq!(murmur3_32(&[0x21]), 0x7266_1cf4);
    }

    #[test]
    fn ids_match_the_specifications_manifest_example() {
        // The manifests and keys printed in the Cryptomatte specification 1.1.0.
        for (name, hex) in [
            ("bunny", "13851a76"),
            ("default", "42c9679f"),
            ("bunny_porcelain_mat", "b24b26d4"),
        ] {
            assert_eq!(format!("{:08x}", name_id(name).to_bits()), hex, "{name}");
        }
        // The specification's example keys (adb0a84, ...) are arbitrary; the key is only the
        // first 7 hex digits of the raw hash.
        assert_eq!(metadata_key("hello"), "248bfa4");
    }

    #[test]
    fn the_conversion_never_makes_nan_inf_or_denormals() {
        for hash in [
            0u32,
            1,
            0x007f_ffff,
            0x7f80_0000,
            0x7fff_ffff,
            0xff80_0001,
            u32::MAX,
        ] {
            let f = f32::from_bits(id_bits(hash));
            assert!(f.is_normal(), "{hash:#x} -> {f}");
            assert_eq!(id_bits(hash) & 0x807f_ffff, hash & 0x807f_ffff);
        }
        // Exponents already in range are kept bit for bit.
        assert_eq!(id_bits(0x3f80_0000), 0x3f80_0000);
    }
}
