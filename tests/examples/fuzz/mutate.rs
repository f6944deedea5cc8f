//! Byte-level mutation of real inputs, as coverage-free fuzzers do it: a few stacked edits
//! (bit flips, byte swaps, inserted and deleted runs, splices from another input, tokens of
//! the format) turn a valid file into the slightly wrong ones parsers most often mishandle.

use rand::{Rng, RngExt};

/// Numbers and bytes that sit on edges: overflow, sign, NaN spellings, msgpack and pickle
/// type bytes, UTF-8 fragments.
const EDGES: &[&[u8]] = &[
    b"0",
    b"-0",
    b"-1",
    b"1e309",
    b"-1e309",
    b"NaN",
    b"nan",
    b"inf",
    b"18446744073709551616",
    b"9223372036854775807",
    b"4294967296",
    b"0.000000000000000000000000000000001",
    b"\x00",
    b"\xff",
    b"\xc1",
    b"\xdd\xff\xff\xff\xff",
    b"\xdf\xff\xff\xff\xff",
    b"\xc6\xff\xff\xff\xff",
    b"\xcb\x7f\xf8\x00\x00\x00\x00\x00\x00",
    b"\xe2\x82",
    b"\xf0\x9f\x98\x80",
    b"\r\n",
];

/// Applies 1 to 8 random edits to `input`; `dictionary` holds tokens of the input's format and
/// `other` is spliced from.
pub fn mutate(rng: &mut impl Rng, input: &[u8], other: &[u8], dictionary: &[&[u8]]) -> Vec<u8> {
    let mut out = input.to_vec();
    for _ in 0..rng.random_range(1..=8) {
        edit(rng, &mut out, other, dictionary);
    }
    out
}

fn edit(rng: &mut impl Rng, out: &mut Vec<u8>, other: &[u8], dictionary: &[&[u8]]) {
    let len = out.len();
    let mut pick = |n: usize| rng.random_range(0..n.max(1));
    match pick(10) {
        // Flip one bit.
        0 if len > 0 => {
            let i = pick(len);
            out[i] ^= 1 << pick(8);
        }
        // Replace one byte.
        1 if len > 0 => {
            let i = pick(len);
            out[i] = pick(256) as u8;
        }
        // Delete a run.
        2 if len > 0 => {
            let i = pick(len);
            let n = 1 + pick((len - i).min(64));
            out.drain(i..i + n);
        }
        // Duplicate a run in place.
        3 if len > 0 => {
            let i = pick(len);
            let n = 1 + pick((len - i).min(256));
            let run = out[i..i + n].to_vec();
            let j = pick(len + 1);
            out.splice(j..j, run);
        }
        // Insert random bytes.
        4 => {
            let n = 1 + pick(16);
            let bytes: Vec<u8> = (0..n).map(|_| pick(256) as u8).collect();
            let j = pick(len + 1);
            out.splice(j..j, bytes);
        }
        // Splice a run of another input.
        5 if !other.is_empty() => {
            let i = pick(other.len());
            let n = 1 + pick((other.len() - i).min(512));
            let j = pick(len + 1);
            out.splice(j..j, other[i..i + n].iter().copied());
        }
        // Overwrite with an edge value or a token of the format.
        6 | 7 => {
            let token = if pick(2) == 0 || dictionary.is_empty() { EDGES[pick(EDGES.len())] } else { dictionary[pick(dictionary.len())] };
            let j = pick(len + 1);
            let end = (j + token.len()).min(len);
            if pick(2) == 0 {
                out.splice(j..end, token.iter().copied());
            } else {
                out.splice(j..j, token.iter().copied());
            }
        }
        // Cut the end off (a truncated file).
        8 if len > 0 => out.truncate(pick(len)),
        // Swap two bytes.
        _ if len > 1 => {
            let (i, j) = (pick(len), pick(len));
            out.swap(i, j);
        }
        _ => out.push(pick(256) as u8),
    }
}
