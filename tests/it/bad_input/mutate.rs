//! The damage done to a seed: truncations, byte flips, numbers replaced by NaN, infinities,
//! huge finite values and huge counts, and referenced files removed.

use super::Rng;

/// One way of damaging a file, with a label that reproduces it.
pub struct Mutation {
    pub label: String,
    /// The damaged bytes, or `None` to delete the file.
    pub bytes: Option<Vec<u8>>,
}

/// What replaces a number: non-finite spellings, finite values too large for the renderer's
/// squares or for half floats, negatives, and counts beyond any allocation.
const REPLACEMENTS: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "1e38",
    "-3e38",
    "1e30",
    "1e19",
    "65505",
    "-5",
    "5",
    "0",
    "4294967295",
    "2147483648",
    "1e-45",
];

/// Byte ranges of the numbers in `text` (digits with an optional sign, point and exponent).
fn numbers(text: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < text.len() {
        let starts = text[i].is_ascii_digit()
            || (matches!(text[i], b'-' | b'.') && text.get(i + 1).is_some_and(u8::is_ascii_digit));
        // Not the middle of a word (`v1`, `f32`): the previous byte is no letter or digit.
        let fresh = i == 0 || !(text[i - 1].is_ascii_alphanumeric() || text[i - 1] == b'_');
        if starts && fresh {
            let mut j = i + 1;
            while j < text.len()
                && (text[j].is_ascii_digit()
                    || matches!(text[j], b'.' | b'e' | b'E')
                    || (matches!(text[j], b'-' | b'+') && matches!(text[j - 1], b'e' | b'E')))
            {
                j += 1;
            }
            out.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

/// Mutations of `bytes`: `cuts` truncations, `flips` byte flips and, for text, `subs` number
/// substitutions, all chosen by `rng`.
pub fn mutations(
    bytes: &[u8],
    text: bool,
    rng: &mut Rng,
    (cuts, flips, subs): (usize, usize, usize),
) -> Vec<Mutation> {
    let mut out = Vec::new();
    let n = bytes.len();
    for k in 0..cuts {
        // Evenly spread, including the empty file, plus a random jitter.
        let at = (n * k / cuts + rng.below(n / cuts + 1)).min(n.saturating_sub(1));
        out.push(Mutation {
            label: format!("truncated to {at} of {n} bytes"),
            bytes: Some(bytes[..at].to_vec()),
        });
    }
    for _ in 0..flips {
        let mut b = bytes.to_vec();
        let at = rng.below(n);
        let x = 1 + rng.below(255) as u8;
        b[at] ^= x;
        out.push(Mutation {
            label: format!("byte {at} xor {x:#04x}"),
            bytes: Some(b),
        });
    }
    if text {
        let nums = numbers(bytes);
        for _ in 0..subs.min(nums.len()) {
            let (s, e) = nums[rng.below(nums.len())];
            let r = REPLACEMENTS[rng.below(REPLACEMENTS.len())];
            let mut b = bytes[..s].to_vec();
            b.extend(r.as_bytes());
            b.extend(&bytes[e..]);
            out.push(Mutation {
                label: format!(
                    "number {:?} at byte {s} replaced by {r}",
                    String::from_utf8_lossy(&bytes[s..e])
                ),
                bytes: Some(b),
            });
        }
    }
    out
}

/// The seed removed: a missing referenced file.
pub fn missing() -> Mutation {
    Mutation {
        label: "file missing".into(),
        bytes: None,
    }
}

#[test]
fn numbers_are_found_whole_and_not_inside_words() {
    let t = b"v1 2.5 -3e-2 x.7 f32 [1,-0.5]";
    let found: Vec<&[u8]> = numbers(t).iter().map(|&(s, e)| &t[s..e]).collect();
    assert_eq!(
        found,
        [&b"2.5"[..], b"-3e-2", b"7", b"1", b"-0.5"],
        "{:?}",
        found
            .iter()
            .map(|f| String::from_utf8_lossy(f))
            .collect::<Vec<_>>()
    );
}
