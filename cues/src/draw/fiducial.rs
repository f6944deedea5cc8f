//! VIFO-36: a small fiducial tag family of our own.
//!
//! No pure-Rust AprilTag/ArUco generator exists, and copying their tables would need
//! attribution and care, so the family is generated here by a documented deterministic search:
//!
//! * a tag is 6×6 data bits (bit *i*, row-major from the top-left, is `(code >> (35 - i)) & 1`)
//!   inside a one-cell black border and a one-cell white quiet ring: 10×10 cells in all;
//! * candidates come from a xorshift64* generator seeded with [`SEED`], masked to 36 bits;
//! * a candidate is kept if it has 12..=24 dark bits (no near-blank tags), differs from its own
//!   90°/180°/270° rotations in at least [`MIN_DISTANCE`] bits (orientation is unambiguous) and
//!   differs from every rotation of every kept code in at least [`MIN_DISTANCE`] bits;
//! * the search stops at [`CODEBOOK_SIZE`] codes.
//!
//! With a minimum distance of 9 a reader corrects up to 4 wrong bits in any orientation.

use super::geom::ID;
use std::sync::OnceLock;

use tiny_skia::{PathBuilder, Pixmap, Rect};

/// Data bits per side.
pub const BITS: usize = 6;
/// Cells per side including border and quiet ring.
pub const CELLS: usize = BITS + 4;
/// Minimum Hamming distance between any two codes under rotation (and a code and its own
/// rotations).
pub const MIN_DISTANCE: u32 = 9;
/// Number of codes in the family.
pub const CODEBOOK_SIZE: usize = 64;
/// Seed of the candidate generator.
pub const SEED: u64 = 0x5649_464F_5441_4753; // "VIFOTAGS"

const MASK: u64 = (1 << (BITS * BITS)) - 1;

/// The code rotated 90° clockwise (as seen in the image).
pub fn rotate(code: u64) -> u64 {
    let mut out = 0;
    for r in 0..BITS {
        for c in 0..BITS {
            // Cell (r, c) of the rotated tag shows cell (BITS-1-c, r) of the original.
            let src = (BITS - 1 - c) * BITS + r;
            let bit = (code >> (BITS * BITS - 1 - src)) & 1;
            out |= bit << (BITS * BITS - 1 - (r * BITS + c));
        }
    }
    out
}

fn rotations(code: u64) -> [u64; 4] {
    let r1 = rotate(code);
    let r2 = rotate(r1);
    [code, r1, r2, rotate(r2)]
}

fn distance(a: u64, b: u64) -> u32 {
    (a ^ b).count_ones()
}

/// The codebook: [`CODEBOOK_SIZE`] codes found by the search described in the module docs.
pub fn codebook() -> &'static [u64] {
    static BOOK: OnceLock<Vec<u64>> = OnceLock::new();
    BOOK.get_or_init(|| {
        let mut state = SEED;
        let mut book: Vec<u64> = Vec::with_capacity(CODEBOOK_SIZE);
        while book.len() < CODEBOOK_SIZE {
            // xorshift64*
            state ^= state >> 12;
            state ^= state << 25;
            state ^= state >> 27;
            let candidate = (state.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 28) & MASK;
            let dark = candidate.count_ones();
            if !(12..=24).contains(&dark) {
                continue;
            }
            let rots = rotations(candidate);
            if rots[1..].iter().any(|&r| distance(candidate, r) < MIN_DISTANCE) {
                continue;
            }
            if book.iter().all(|&c| rotations(c).iter().all(|&r| distance(candidate, r) >= MIN_DISTANCE)) {
                book.push(candidate);
            }
        }
        book
    })
}

/// Bit (row, col) of a code.
pub fn bit(code: u64, row: usize, col: usize) -> bool {
    (code >> (BITS * BITS - 1 - (row * BITS + col))) & 1 == 1
}

/// A decoded tag: its id, how many quarter turns clockwise it was seen rotated, and how many
/// bits were wrong.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Detection {
    pub id: usize,
    pub rotation: u8,
    pub errors: u32,
}

/// Finds the code nearest to `observed` under rotation; `None` when more bits are wrong than
/// the family can correct.
pub fn decode(observed: u64) -> Option<Detection> {
    let mut best: Option<Detection> = None;
    for (id, &code) in codebook().iter().enumerate() {
        for (rotation, r) in rotations(code).into_iter().enumerate() {
            let errors = distance(observed & MASK, r);
            if best.is_none_or(|b| errors < b.errors) {
                best = Some(Detection { id, rotation: rotation as u8, errors });
            }
        }
    }
    best.filter(|b| b.errors <= (MIN_DISTANCE - 1) / 2)
}

/// Renders tag `id` (modulo the codebook size) on a `side`-px square: white quiet ring, black
/// border, data cells. Cells are whole pixels when there is room.
pub fn render(id: usize, side: u32) -> Option<Pixmap> {
    let code = codebook()[id % CODEBOOK_SIZE];
    let mut pm = Pixmap::new(side.max(1), side.max(1))?;
    pm.fill(tiny_skia::Color::WHITE);
    let fit = side as f32 / CELLS as f32;
    let cell = if fit >= 1.0 { fit.floor() } else { fit };
    let offset = ((side as f32 - cell * CELLS as f32) / 2.0).floor();
    let mut pb = PathBuilder::new();
    for r in 0..BITS + 2 {
        for c in 0..BITS + 2 {
            let border = r == 0 || c == 0 || r == BITS + 1 || c == BITS + 1;
            if border || !bit(code, r - 1, c - 1) {
                // Border cells and 0-bits are dark; 1-bits are light.
                if let Some(rect) =
                    Rect::from_xywh(offset + (c + 1) as f32 * cell, offset + (r + 1) as f32 * cell, cell, cell)
                {
                    pb.push_rect(rect);
                }
            }
        }
    }
    if let Some(path) = pb.finish() {
        super::fill(&mut pm, &path, super::BLACK, ID);
    }
    Some(pm)
}

/// Reads the 36 data bits of a tag rendered by [`render`] at `side` px, sampling cell centres
/// of a `side`² RGBA buffer (dark = luminance below 128); `None` if the buffer is too small.
/// Used by tests and by consumers checking a frame.
pub fn read(rgba: &[u8], side: u32) -> Option<u64> {
    if rgba.len() < side as usize * side as usize * 4 || side < CELLS as u32 {
        return None;
    }
    let fit = side as f32 / CELLS as f32;
    let cell = if fit >= 1.0 { fit.floor() } else { fit };
    let offset = ((side as f32 - cell * CELLS as f32) / 2.0).floor();
    let mut code = 0;
    for r in 0..BITS {
        for c in 0..BITS {
            let x = (offset + (c as f32 + 2.5) * cell) as usize;
            let y = (offset + (r as f32 + 2.5) * cell) as usize;
            let i = (y * side as usize + x) * 4;
            let lum = (rgba[i] as u32 * 3 + rgba[i + 1] as u32 * 6 + rgba[i + 2] as u32) / 10;
            if lum >= 128 {
                code |= 1 << (BITS * BITS - 1 - (r * BITS + c));
            }
        }
    }
    Some(code)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codebook_has_the_documented_distance_under_rotation() {
        let book = codebook();
        assert_eq!(book.len(), CODEBOOK_SIZE);
        for (i, &a) in book.iter().enumerate() {
            for r in &rotations(a)[1..] {
                assert!(distance(a, *r) >= MIN_DISTANCE, "code {i} is too close to its own rotation");
            }
            for &b in &book[i + 1..] {
                for r in rotations(b) {
                    assert!(distance(a, r) >= MIN_DISTANCE);
                }
            }
        }
    }

    #[test]
    fn four_rotations_return_to_the_start() {
        let c = codebook()[5];
        assert_ne!(rotate(c), c);
        assert_eq!(rotate(rotate(rotate(rotate(c)))), c);
    }

    #[test]
    fn rendered_tags_read_back_with_rotation_and_bit_errors() {
        for id in [0, 17, 63] {
            let pm = render(id, 80).unwrap();
            let observed = read(pm.data(), 80).unwrap();
            assert_eq!(decode(observed), Some(Detection { id, rotation: 0, errors: 0 }));
            let turned = rotate(observed);
            assert_eq!(decode(turned).map(|d| (d.id, d.rotation)), Some((id, 1)));
            let damaged = observed ^ 0b1011 << 7;
            assert_eq!(decode(damaged).map(|d| (d.id, d.errors)), Some((id, 3)));
        }
        assert_eq!(decode(0), None, "an all-dark square is no tag");
        assert_eq!(read(&[0; 16], 80), None, "a short buffer is no tag");
    }
}
