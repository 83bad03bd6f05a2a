//! Philox4x32-10, the counter-based generator behind the cue noise: the twin of
//! `shaders/study/philox.wgsl` (same functions, same order).
//!
//! # Why counter-based
//! Sample `i`'s random numbers are a pure function of the study's seed (the key) and of
//! `i` (the counter): no generator state is carried from one draw to the next, so the CPU
//! draws sample `i` on whichever thread runs it and the GPU draws it in whichever
//! invocation runs its table, and both get the same bits. Philox is made for that: a
//! ten-round integer block cipher of the 128-bit counter under a 64-bit key, which passes
//! TestU01's BigCrush for every key (Salmon, Moraes, Dror and Shaw, "Parallel random
//! numbers: as easy as 1, 2, 3", SC '11, 2011; the Random123 library's known-answer
//! vectors are in this module's tests and in `tests/gpu_noise.rs`).
//!
//! # The twins give the same bits
//! Integer arithmetic is exact on both sides: a product of two `u32`s is the same 64 bits
//! whether Rust forms it in a `u64` or WGSL (which has no 64-bit integers) from four
//! 16-bit partial products ([`mul_hi_lo`]). The uniform [`open_unit`] is built from 52 of
//! the bits by exact `f64` operations.

/// Philox4x32's two round multipliers (Salmon et al., table 2).
const PHILOX_M0: u32 = 0xD251_1F53;
/// The second multiplier.
const PHILOX_M1: u32 = 0xCD9E_8D57;
/// The key's Weyl increments per round: the golden ratio's and √3 − 1's first 32 bits.
const PHILOX_W0: u32 = 0x9E37_79B9;
/// The second increment.
const PHILOX_W1: u32 = 0xBB67_AE85;
/// Philox4x32's round count: ten, the published default (seven already pass BigCrush).
const PHILOX_ROUNDS: u32 = 10;

/// The high and low 32 bits of the 64-bit product `a·b`.
///
/// WGSL has no 64-bit integers: its twin sums four 16-bit partial products; the bits are
/// the same.
#[inline]
pub fn mul_hi_lo(a: u32, b: u32) -> (u32, u32) {
    let p = u64::from(a) * u64::from(b);
    ((p >> 32) as u32, p as u32)
}

/// Philox4x32-10: the four 32-bit words that `counter` encrypts to under `key`.
///
/// Contract: a bijection of the counter for each key; equal to Random123's
/// `philox4x32(counter, key)` with ten rounds (its known-answer vectors: the tests).
///
/// Method: ten rounds, each two multiplications whose high halves are mixed with the other
/// two words and the key (an S-box-free Feistel network), the key bumped by the Weyl
/// increments between rounds.
pub fn philox4x32(counter: [u32; 4], key: [u32; 2]) -> [u32; 4] {
    let mut c = counter;
    let mut k = key;
    for _ in 0..PHILOX_ROUNDS {
        let (hi0, lo0) = mul_hi_lo(PHILOX_M0, c[0]);
        let (hi1, lo1) = mul_hi_lo(PHILOX_M1, c[2]);
        c = [hi1 ^ c[1] ^ k[0], lo1, hi0 ^ c[3] ^ k[1], lo0];
        k = [k[0].wrapping_add(PHILOX_W0), k[1].wrapping_add(PHILOX_W1)];
    }
    c
}

/// A uniform number in the open interval (0, 1) from two words: with k the 52-bit integer
/// of `hi`'s top 20 bits and all of `lo`, (2k + 1)·2⁻⁵³.
///
/// Contract: one of the 2⁵² odd multiples of 2⁻⁵³ in (0, 1), each equally likely for
/// uniform words; never 0 or 1, and 1 − u is exact and of the same set (so a quantile
/// function's two tails are drawn alike).
///
/// Method: every step is exact in f64 (k < 2⁵², 2k + 1 < 2⁵³, a power of two), so the
/// twins agree bit for bit.
pub fn open_unit(lo: u32, hi: u32) -> f64 {
    let k = f64::from(hi >> 12) * 4_294_967_296.0 + f64::from(lo);
    (2.0 * k + 1.0) * (1.0 / 9_007_199_254_740_992.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn philox_gives_random123s_known_answers() {
        // Random123's kat_vectors, philox4x32 with 10 rounds: counter, key, output
        let cases = [
            (
                [0, 0, 0, 0],
                [0, 0],
                [0x6627_e8d5, 0xe169_c58d, 0xbc57_ac4c, 0x9b00_dbd8],
            ),
            (
                [u32::MAX; 4],
                [u32::MAX; 2],
                [0x408f_276d, 0x41c8_3b0e, 0xa20b_c7c6, 0x6d54_51fd],
            ),
            (
                [0x243f_6a88, 0x85a3_08d3, 0x1319_8a2e, 0x0370_7344],
                [0xa409_3822, 0x299f_31d0],
                [0xd16c_fe09, 0x94fd_cceb, 0x5001_e420, 0x2412_6ea1],
            ),
        ];
        for (counter, key, want) in cases {
            assert_eq!(philox4x32(counter, key), want, "{counter:x?} {key:x?}");
        }
    }

    #[test]
    fn the_open_unit_stays_inside_and_is_symmetric() {
        let lowest = open_unit(0, 0);
        let highest = open_unit(u32::MAX, u32::MAX);
        assert_eq!(lowest, 2f64.powi(-53));
        assert_eq!(highest, 1.0 - 2f64.powi(-53));
        assert_eq!(1.0 - highest, lowest);
        // the 52 bits: the top 20 of hi, all of lo; the low 12 of hi are dropped
        assert_eq!(open_unit(0, 0x0000_0fff), lowest);
        assert_eq!(open_unit(0, 0x8000_0000), 0.5 + 2f64.powi(-53));
        for (lo, hi) in [(1, 0), (0xdead_beef, 0x1234_5678), (7, 0xffff_f000)] {
            let u = open_unit(lo, hi);
            assert!(0.0 < u && u < 1.0);
            let k = (u64::from(hi >> 12) << 32) | u64::from(lo);
            assert_eq!(u, (2 * k + 1) as f64 / 2f64.powi(53));
        }
    }
}
