//! FNV-1a (64 bit): the stable hash behind fiducial ids and the paper set's deterministic
//! choice of instances (the same on every platform and Rust version, unlike `std`'s hasher).

pub fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| (h ^ b as u64).wrapping_mul(0x100_0000_01b3))
}
