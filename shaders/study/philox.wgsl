// Philox4x32-10, the counter-based generator behind the cue noise. WGSL twin of
// src/study/philox.rs (same functions, same order; the module documentation there has
// the why and the source). Integer arithmetic is exact, so the bits are the Rust twin's.

// Philox4x32's two round multipliers (Salmon et al., table 2).
const PHILOX_M0: u32 = 0xD2511F53u;
// The second multiplier.
const PHILOX_M1: u32 = 0xCD9E8D57u;
// The key's Weyl increments per round: the golden ratio's and √3 − 1's first 32 bits.
const PHILOX_W0: u32 = 0x9E3779B9u;
// The second increment.
const PHILOX_W1: u32 = 0xBB67AE85u;
// Philox4x32's round count: ten, the published default (seven already pass BigCrush).
const PHILOX_ROUNDS: u32 = 10u;

// The high (x) and low (y) 32 bits of the 64-bit product a·b. WGSL has no 64-bit
// integers: the sum of four 16-bit partial products gives the Rust twin's bits.
fn mul_hi_lo(a: u32, b: u32) -> vec2<u32> {
    let a0 = a & 0xffffu;
    let a1 = a >> 16u;
    let b0 = b & 0xffffu;
    let b1 = b >> 16u;
    let p00 = a0 * b0;
    let p01 = a0 * b1;
    let p10 = a1 * b0;
    let p11 = a1 * b1;
    // the middle column with the carry out of the low half (below 3·2¹⁶)
    let mid = (p00 >> 16u) + (p01 & 0xffffu) + (p10 & 0xffffu);
    let hi = p11 + (p01 >> 16u) + (p10 >> 16u) + (mid >> 16u);
    return vec2<u32>(hi, a * b);
}

// Philox4x32-10: the four 32-bit words that `counter` encrypts to under `key`.
fn philox4x32(counter: vec4<u32>, key: vec2<u32>) -> vec4<u32> {
    var c = counter;
    var k = key;
    for (var r = 0u; r < PHILOX_ROUNDS; r++) {
        let p0 = mul_hi_lo(PHILOX_M0, c.x);
        let p1 = mul_hi_lo(PHILOX_M1, c.z);
        c = vec4<u32>(p1.x ^ c.y ^ k.x, p1.y, p0.x ^ c.w ^ k.y, p0.y);
        k = vec2<u32>(k.x + PHILOX_W0, k.y + PHILOX_W1);
    }
    return c;
}

// A uniform number in the open interval (0, 1) from two words: with k the 52-bit integer
// of hi's top 20 bits and all of lo, (2k + 1)·2⁻⁵³ (every step exact in f64).
fn open_unit(lo: u32, hi: u32) -> real {
    let k = real(hi >> 12u) * 4294967296.0 + real(lo);
    return (2.0 * k + 1.0) * (1.0 / 9007199254740992.0);
}
