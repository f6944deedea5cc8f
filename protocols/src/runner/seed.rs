//! Stable hashes: episode seeds and shard membership that never change between runs,
//! machines or Rust versions (unlike `std`'s randomly keyed `DefaultHasher`).

use crate::spec::{EpisodeSpec, Protocol};

/// 64-bit FNV-1a of `bytes`.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// FNV-1a followed by the SplitMix64 finaliser, so that inputs differing in one character
/// give seeds differing in about half their bits (FNV alone mixes the last byte weakly).
pub fn stable_hash(text: &str) -> u64 {
    let mut z = fnv1a64(text.as_bytes()).wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The seed of one episode, from what identifies it: the cue instance id (or, for the
/// cue-free original protocol, the task key), the protocol, the initial state and the
/// repetition.
pub fn episode_seed(unit: &str, protocol: Protocol, init: usize, episode: usize) -> u64 {
    stable_hash(&format!("{unit}|{}|{init}|{episode}", protocol.name()))
}

/// [`episode_seed`] of a spec (its instance, else its task).
pub fn seed_for(spec: &EpisodeSpec) -> u64 {
    let unit = spec.instance.clone().unwrap_or_else(|| spec.task.to_string());
    episode_seed(&unit, spec.protocol, spec.init, spec.episode)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv_matches_the_reference_vectors() {
        assert_eq!(fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a64(b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn seeds_are_fixed_and_distinct() {
        let a = episode_seed("libero_goal/3/F2/straight_arrow_red", Protocol::Authorized, 0, 0);
        // Pinned (also computed independently in Python): a change here silently changes
        // every published episode.
        assert_eq!(a, 0x9849_658f_9903_114b);
        let mut seen = std::collections::BTreeSet::new();
        for protocol in Protocol::ALL {
            for init in 0..50 {
                for episode in 0..3 {
                    assert!(seen.insert(episode_seed("libero_goal/3/F2/straight_arrow_red", protocol, init, episode)));
                }
            }
        }
    }
}
