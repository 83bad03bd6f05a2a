//! `exp`, `sin`, `cos` and `acos` from arithmetic alone, for the GPU's f64: the twin of
//! `shaders/model/fmath.wgsl` (same functions, same order, same operations in the same
//! order).
//!
//! # Why
//! WGSL's f64 has no safe transcendental functions: on Vulkan the builtins `exp`, `sin`,
//! `cos`, `acos`, `atan2`, `pow`, `log` compile for f64 and return garbage (the SPIR-V
//! instructions behind them are defined for 16- and 32-bit floats only). The resolutions
//! need some: the Alciatore ball–ball friction `exp(−c·|slip|)` (`src/resolve/ball_ball.rs`)
//! and the Stronge compliant cushion model's `sin`, `cos` of phases `ω·t` and `acos(x)`,
//! `x` in [−1, 1] (`src/resolve/stronge.rs`). These functions use only what WGSL f64 has
//! safely: `+ − × ÷`, `sqrt`, `abs`, `select`, comparisons and int/float conversions.
//!
//! # The twins give the same bits
//! Here `if c { t } else { f }` is `select(f, t, c)`, `as i32` / `as f64` are `i32(…)` /
//! `real(…)`, and [`mad`]`(a, b, c)` is `a * b + c` on both sides: rounded twice, never a
//! fused multiply-add. The GPU runs the shader as SPIR-V whose every float operation is
//! marked `NoContraction` ([`crate::gpu::spirv`]), so its compiler may neither fuse a
//! product into a sum nor re-associate sums, and Rust never does either: on a device whose
//! f64 `+ − × ÷` and `sqrt` are IEEE's (round to nearest even, subnormals kept), as on
//! NVIDIA's and AMD's GPUs and on Mesa's lavapipe, the twins give the same bits.
//! `tests/gpu_fmath.rs` checks that on the adapter it finds.
//!
//! Before that decoration the twins were written with fused `fma`s wherever a product fed
//! a sum, so that contraction could not change a bit; but Vulkan promises no fused `fma`
//! (lavapipe's rounds twice), and the compensated sums (`(1 − w) − h`, TwoSum's errors,
//! `z − s²`) did not survive lavapipe's re-association. With the decoration, separately
//! rounded products cost nothing measurable in accuracy (the bounds below hold as
//! before) and make one twin right everywhere.
//!
//! # Accuracy
//! Measured against the standard library (glibc's, itself within 1 ulp) by
//! `tests/fmath.rs` over a few million points each, dense where it is hard:
//! - [`exp_poly`]: ≤ 1 ulp on [−745, 709.7] (subnormal results included, counted in
//!   subnormal ulps);
//! - [`sin_poly`], [`cos_poly`]: ≤ 1 ulp for |x| ≤ [`TRIG_BOUND`] (8·10⁵), near the zeros
//!   (multiples of π/2) included;
//! - [`acos_poly`]: ≤ 1 ulp on [−1, 1].
//!
//! # Special values
//! NaN in gives NaN out; [`exp_poly`] overflows to +∞ above ~709.78 and is 0 below −746;
//! [`sin_poly`], [`cos_poly`] are NaN beyond ±[`TRIG_BOUND`] and for ±∞; [`acos_poly`] is
//! NaN outside [−1, 1]. WGSL has no NaN or ∞ literals, so these come from arithmetic on the
//! argument (an overflowing product, the square root of a negative number); a GPU compiler
//! that assumes there are no NaNs or infinities (Vulkan without the float-controls
//! execution modes, which naga does not ask for) may not keep them. The physics never
//! passes such arguments.
//!
//! # Coefficients
//! - exp: the Taylor coefficients 1/n! for n ≤ 13, rounded to nearest; the ln 2 split
//!   (`LN2_HI` with 32 significant bits, `LN2_LO`) and 1/ln 2 are fdlibm's (Sun Microsystems,
//!   1993–2004; FreeBSD `lib/msun/src/e_exp.c`).
//! - sin, cos: fdlibm's minimax polynomials on [−π/4, π/4] (FreeBSD `lib/msun/src/k_sin.c`,
//!   `k_cos.c`: |sin(x)/x − s(x)| ≤ 2⁻⁵⁸, |cos(x) − c(x)| ≤ 2⁻⁵⁸) and its 33-bit pieces of
//!   π/2 (`e_rem_pio2.c`).
//! - acos: fdlibm's rational approximation of asin, asin(x) = x + x·R(x²), R = P/Q on
//!   x² ≤ 1/4, and its π/2, π (`e_asin.c`, `e_acos.c`).
//!
//! The hexadecimal comments are the intended bits; the decimals are the shortest that give
//! them (in WGSL also for the four that are `std::f64::consts` here).
//!
//! # f32
//! The WGSL text is written in the shaders' `real` type like its siblings, and every
//! constant fits f32, so it also compiles into the f32 shader; it is designed and tested for
//! f64 only (for f32 the native builtins are accurate enough).

// exp: fdlibm's ln 2 split and 1/ln 2.
/// 1/ln 2 (0x3FF71547_652B82FE).
const INV_LN2: f64 = std::f64::consts::LOG2_E;
/// ln 2 to 32 significant bits (0x3FE62E42_FEE00000): k·LN2_HI is exact for |k| < 2²¹.
const LN2_HI: f64 = 0.6931471803691238;
/// ln 2 − LN2_HI (0x3DEA39EF_35793C76).
const LN2_LO: f64 = 1.9082149292705877e-10;
/// Arguments beyond ±EXP_CLAMP reduce as if they were ±EXP_CLAMP (the result is 0 or ∞
/// there anyway): |k| ≤ 1097, and the conversion to i32 never sees NaN or ∞.
const EXP_CLAMP: f64 = 760.0;
/// Below this exp is 0 (it underflows to 0 below −745.1332…).
const EXP_ZERO_BELOW: f64 = -746.0;
// exp: 1/n!, rounded to nearest (1/2, 1 and 1 are written out where they are used).
/// 1/3! (0x3FC55555_55555555).
const EXP_C3: f64 = 0.16666666666666666;
/// 1/4! (0x3FA55555_55555555).
const EXP_C4: f64 = 0.041666666666666664;
/// 1/5! (0x3F811111_11111111).
const EXP_C5: f64 = 0.008333333333333333;
/// 1/6! (0x3F56C16C_16C16C17).
const EXP_C6: f64 = 0.001388888888888889;
/// 1/7! (0x3F2A01A0_1A01A01A).
const EXP_C7: f64 = 0.0001984126984126984;
/// 1/8! (0x3EFA01A0_1A01A01A).
const EXP_C8: f64 = 2.48015873015873e-5;
/// 1/9! (0x3EC71DE3_A556C734).
const EXP_C9: f64 = 2.7557319223985893e-6;
/// 1/10! (0x3E927E4F_B7789F5C).
const EXP_C10: f64 = 2.755731922398589e-7;
/// 1/11! (0x3E5AE645_67F544E4).
const EXP_C11: f64 = 2.505210838544172e-8;
/// 1/12! (0x3E21EED8_EFF8D898).
const EXP_C12: f64 = 2.08767569878681e-9;
/// 1/13! (0x3DE61246_13A86D09).
const EXP_C13: f64 = 1.6059043836821613e-10;

// sin, cos: the reduction modulo π/2 (fdlibm e_rem_pio2.c).
/// sin and cos reduce arguments up to this size exactly enough (|n| < 2¹⁹, so n times a
/// 33-bit piece of π/2 is exact); beyond it they are NaN. fdlibm's medium range goes to
/// 2¹⁹·π/2 ≈ 8.2·10⁵.
pub const TRIG_BOUND: f64 = 8.0e5;
/// 2/π (0x3FE45F30_6DC9C883).
const INV_PIO2: f64 = std::f64::consts::FRAC_2_PI;
/// The first 33 bits of π/2 (0x3FF921FB_54400000).
const PIO2_1: f64 = 1.5707963267341256;
/// The second 33 bits of π/2 (0x3DD0B461_1A600000).
const PIO2_2: f64 = 6.077100506303966e-11;
/// The third 33 bits of π/2 (0x3BA3198A_2E000000).
const PIO2_3: f64 = 2.0222662487111665e-21;
/// π/2 − (PIO2_1 + PIO2_2 + PIO2_3) (0x397B839A_252049C1).
const PIO2_3T: f64 = 8.4784276603689e-32;
/// Below this |x|, sin x is x to the last bit (2⁻²⁷, 0x3E400000_00000000).
const SIN_TINY: f64 = 7.450580596923828e-9;
// sin: fdlibm k_sin.c, sin(x) ≈ x + SIN_S1·x³ + … + SIN_S6·x¹³ on [−π/4, π/4].
/// 0xBFC55555_55555549
const SIN_S1: f64 = -0.16666666666666632;
/// 0x3F811111_1110F8A6
const SIN_S2: f64 = 0.00833333333332249;
/// 0xBF2A01A0_19C161D5
const SIN_S3: f64 = -0.0001984126982985795;
/// 0x3EC71DE3_57B1FE7D
const SIN_S4: f64 = 2.7557313707070068e-6;
/// 0xBE5AE5E6_8A2B9CEB
const SIN_S5: f64 = -2.5050760253406863e-8;
/// 0x3DE5D93A_5ACFD57C
const SIN_S6: f64 = 1.58969099521155e-10;
// cos: fdlibm k_cos.c, cos(x) ≈ 1 − x²/2 + COS_C1·x⁴ + … + COS_C6·x¹⁴ on [−π/4, π/4].
/// 0x3FA55555_5555554C
const COS_C1: f64 = 0.0416666666666666;
/// 0xBF56C16C_16C15177
const COS_C2: f64 = -0.001388888888887411;
/// 0x3EFA01A0_19CB1590
const COS_C3: f64 = 2.480158728947673e-5;
/// 0xBE927E4F_809C52AD
const COS_C4: f64 = -2.7557314351390663e-7;
/// 0x3E21EE9E_BDB4B1C4
const COS_C5: f64 = 2.087572321298175e-9;
/// 0xBDA8FAE9_BE8838D4
const COS_C6: f64 = -1.1359647557788195e-11;

// acos: fdlibm e_asin.c / e_acos.c.
/// π rounded (0x400921FB_54442D18).
const PI_HI: f64 = std::f64::consts::PI;
/// π/2 rounded (0x3FF921FB_54442D18).
const PIO2_HI: f64 = std::f64::consts::FRAC_PI_2;
/// π/2 − PIO2_HI (0x3C91A626_33145C07).
const PIO2_LO: f64 = 6.123233995736766e-17;
// R(z) = P(z)/Q(z): asin(x) ≈ x + x·P(x²)/Q(x²) on |x| ≤ 1/2 (P has a factor z).
/// 0x3FC55555_55555555
const ASIN_P0: f64 = 0.16666666666666666;
/// 0xBFD4D612_03EB6F7D
const ASIN_P1: f64 = -0.3255658186224009;
/// 0x3FC9C155_0E884455
const ASIN_P2: f64 = 0.20121253213486293;
/// 0xBFA48228_B5688F3B
const ASIN_P3: f64 = -0.04005553450067941;
/// 0x3F49EFE0_7501B288
const ASIN_P4: f64 = 0.0007915349942898145;
/// 0x3F023DE1_0DFDF709
const ASIN_P5: f64 = 3.479331075960212e-5;
/// 0xC0033A27_1C8A2D4B
const ASIN_Q1: f64 = -2.403394911734414;
/// 0x40002AE5_9C598AC8
const ASIN_Q2: f64 = 2.0209457602335057;
/// 0xBFE6066C_1B8D0159
const ASIN_Q3: f64 = -0.6882839716054533;
/// 0x3FB3B8C5_B12E9282
const ASIN_Q4: f64 = 0.07703815055590194;

/// `a·b + c` rounded twice, the product then the sum, never fused (WGSL: `mad`, the same
/// function). Where fdlibm and the earlier twins used a fused multiply-add, these use
/// this: a fused `fma` is what a GPU has and a CPU may emulate slowly, and Mesa's lavapipe
/// rounds its "fused" f64 `fma` twice anyway; written as a product and a sum, in SPIR-V
/// marked `NoContraction` ([`crate::gpu::spirv`]), every device rounds it the same.
#[inline]
pub fn mad(a: f64, b: f64, c: f64) -> f64 {
    a * b + c
}

/// 2ⁿ exactly, for |n| ≤ 1023 (below 2⁻¹⁰²² the result is subnormal, still exact).
///
/// Method: the product of the powers 2^(±2ⁱ) for the bits i of |n|, each power the square
/// of the one before: WGSL cannot build an f64 from its bits without 64-bit integers
/// (`bitcast` keeps the width), and `ldexp` is not on the list of safe f64 builtins.
pub fn pow2i(n: i32) -> f64 {
    let mut b = if n < 0 { 0.5 } else { 2.0 };
    let mut m = n.abs();
    let mut p = 1.0;
    for _ in 0..10 {
        p = if m & 1 == 1 { p * b } else { p };
        m >>= 1;
        b *= b;
    }
    p
}

/// eˣ.
///
/// Contract: ≤ 1 ulp from the correctly rounded value on [−745, 709.7] (tests/fmath.rs),
/// results below 2⁻¹⁰²² subnormal; 0 for x < −746 (and −∞); +∞ above ~709.78 (and for +∞);
/// NaN for NaN. exp(±0) = 1 exactly.
///
/// Method: k = round(x/ln 2) (halves away from zero) and r = x − k·ln 2 with a two-constant
/// Cody–Waite split of ln 2 (k·LN2_HI and x − k·LN2_HI are exact), so |r| ≤ ln 2/2 +
/// rounding; eʳ by its Taylor polynomial to r¹³ (truncation < 2⁻⁵⁸ relative) in Horner form
/// with mad; then 2ᵏ as 2^(k − 2h)·2ʰ·2ʰ with h = k/2, so each factor is a normal power of
/// two, the first two products are exact and only the last one rounds (into the subnormals,
/// or overflowing to +∞).
pub fn exp_poly(x: f64) -> f64 {
    let xc = if x.abs() <= EXP_CLAMP {
        x
    } else if x > 0.0 {
        EXP_CLAMP
    } else {
        -EXP_CLAMP
    };
    let half = if xc < 0.0 { -0.5 } else { 0.5 };
    let k = mad(xc, INV_LN2, half) as i32;
    let kf = k as f64;
    let hi = mad(-kf, LN2_HI, x);
    let r = mad(-kf, LN2_LO, hi);
    let mut p = mad(r, EXP_C13, EXP_C12);
    p = mad(r, p, EXP_C11);
    p = mad(r, p, EXP_C10);
    p = mad(r, p, EXP_C9);
    p = mad(r, p, EXP_C8);
    p = mad(r, p, EXP_C7);
    p = mad(r, p, EXP_C6);
    p = mad(r, p, EXP_C5);
    p = mad(r, p, EXP_C4);
    p = mad(r, p, EXP_C3);
    p = mad(r, p, 0.5);
    p = mad(r, p, 1.0);
    p = mad(r, p, 1.0);
    let h = k / 2;
    let s = pow2i(h);
    let y = p * pow2i(k - 2 * h) * s * s;
    if x < EXP_ZERO_BELOW { 0.0 } else { y }
}

/// x reduced modulo π/2: `x = n·π/2 + hi + lo` (what [`reduce_half_pi`] returns).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfPiRem {
    /// The quadrant: n = round(x·2/π); only n mod 4 matters to sin and cos.
    pub n: i32,
    /// The remainder, |hi| ≤ π/4 + a few ulps.
    pub hi: f64,
    /// Its tail: |lo| ≤ ulp(hi)/2.
    pub lo: f64,
}

/// x − n·π/2 as a double-double `hi + lo`, n = round(x·2/π), for |x| ≤ [`TRIG_BOUND`].
///
/// Contract: `hi + lo` is the true remainder to far more than 53 bits (about 2⁻¹⁰⁰
/// relative by the construction below), however close x is to a multiple of π/2. Beyond the bound, and for ±∞ and NaN, n = 0 and hi is NaN.
///
/// Method: Cody–Waite with fdlibm's three 33-bit pieces of π/2 and the tail PIO2_3T:
/// n·PIO2_1, n·PIO2_2, n·PIO2_3 are exact (|n| < 2¹⁹) and so is x − n·PIO2_1 (Sterbenz); the
/// next two subtractions are error-free (TwoSum), their errors and −n·PIO2_3T (a mad) are
/// summed into the tail, and a last TwoSum normalises hi + lo. Branch-free (fdlibm decides
/// how many pieces it needs from the exponents; TwoSum needs no such decision).
pub fn reduce_half_pi(x: f64) -> HalfPiRem {
    let inside = x.abs() <= TRIG_BOUND;
    let xr = if inside { x } else { 0.0 };
    let half = if xr < 0.0 { -0.5 } else { 0.5 };
    let n = mad(xr, INV_PIO2, half) as i32;
    let f = n as f64;
    let a = mad(-f, PIO2_1, xr);
    let b = f * PIO2_2;
    let s1 = a - b;
    let z1 = s1 - a;
    let e1 = (a - (s1 - z1)) + (-b - z1);
    let c = f * PIO2_3;
    let s2 = s1 - c;
    let z2 = s2 - s1;
    let e2 = (s1 - (s2 - z2)) + (-c - z2);
    let low = mad(-f, PIO2_3T, e1 + e2);
    let hi = s2 + low;
    let z3 = hi - s2;
    let lo = (s2 - (hi - z3)) + (low - z3);
    // NaN from arithmetic: WGSL has no NaN literal
    let bad = (-1.0 - x.abs()).sqrt();
    HalfPiRem {
        n,
        hi: if inside { hi } else { bad },
        lo,
    }
}

/// sin(x + y) for |x| ≤ π/4 + a little and a tail |y| ≤ ulp(x)/2 (fdlibm's
/// `__kernel_sin(x, y, 1)`).
///
/// Method: x + x³·(SIN_S1 + x²·r(x²)) with fdlibm's minimax coefficients, arranged so that the
/// tail enters as sin(x + y) ≈ sin(x) + y·(1 − x²/2); products that feed sums are mads.
pub fn sin_kernel(x: f64, y: f64) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = mad(
        z * w,
        mad(z, SIN_S6, SIN_S5),
        mad(z, mad(z, SIN_S4, SIN_S3), SIN_S2),
    );
    let v = z * x;
    let t = mad(-v, r, 0.5 * y);
    let u = mad(z, t, -y);
    x - mad(-v, SIN_S1, u)
}

/// cos(x + y) for |x| ≤ π/4 + a little and a tail |y| ≤ ulp(x)/2 (fdlibm's
/// `__kernel_cos(x, y)`, the FreeBSD form).
///
/// Method: 1 − x²/2 + x⁴·r(x²) with fdlibm's minimax coefficients; `w = 1 − x²/2` is
/// rounded and its rounding error `(1 − w) − x²/2` (exact) added back with the tail's
/// −x·y; products that feed sums are mads.
pub fn cos_kernel(x: f64, y: f64) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = mad(
        z,
        mad(z, mad(z, COS_C3, COS_C2), COS_C1),
        (w * w) * mad(z, mad(z, COS_C6, COS_C5), COS_C4),
    );
    let hz = 0.5 * z;
    let one_minus = 1.0 - hz;
    one_minus + (((1.0 - one_minus) - hz) + mad(z, r, -(x * y)))
}

/// sin x.
///
/// Contract: ≤ 1 ulp from the correctly rounded value for |x| ≤ [`TRIG_BOUND`]
/// (tests/fmath.rs), near the multiples of π/2 included; sin(±0) = ±0 and sin x = x for
/// |x| < 2⁻²⁷; NaN beyond the bound, for ±∞ and for NaN.
///
/// Method: [`reduce_half_pi`], then by n mod 4: sin r, cos r, −sin r, −cos r
/// ([`sin_kernel`], [`cos_kernel`]; both are computed and one is selected, as on the GPU).
pub fn sin_poly(x: f64) -> f64 {
    let q = reduce_half_pi(x);
    let s = sin_kernel(q.hi, q.lo);
    let c = cos_kernel(q.hi, q.lo);
    let v = if q.n & 1 == 0 { s } else { c };
    let signed = if q.n & 2 == 0 { v } else { -v };
    if x.abs() < SIN_TINY { x } else { signed }
}

/// cos x.
///
/// Contract: ≤ 1 ulp from the correctly rounded value for |x| ≤ [`TRIG_BOUND`]
/// (tests/fmath.rs), near the multiples of π/2 included; cos(±0) = 1; NaN beyond the
/// bound, for ±∞ and for NaN.
///
/// Method: [`reduce_half_pi`], then by n mod 4: cos r, −sin r, −cos r, sin r.
pub fn cos_poly(x: f64) -> f64 {
    let q = reduce_half_pi(x);
    let s = sin_kernel(q.hi, q.lo);
    let c = cos_kernel(q.hi, q.lo);
    let v = if q.n & 1 == 0 { c } else { s };
    if (q.n + 1) & 2 == 0 { v } else { -v }
}

/// acos x, in [0, π].
///
/// Contract: ≤ 1 ulp from the correctly rounded value on [−1, 1] (tests/fmath.rs);
/// acos 1 = +0, acos(−1) = π rounded, acos 0 = π/2 rounded; NaN outside [−1, 1] and for
/// NaN.
///
/// Method (fdlibm e_acos.c, with a mad where fdlibm splits a square root by its bits):
/// - |x| < 1/2: acos x = π/2 − (x + x·R(x²)), π/2 as PIO2_HI + PIO2_LO;
/// - x ≥ 1/2: acos x = 2·asin √z with z = (1 − x)/2 (exact): 2·(s + s·R(z) + c) with
///   s = √z rounded and c = (z − s²)/(2s) (z − s² by mad, to about an ulp of z), so s + c ≈ √z to about an ulp;
/// - x ≤ −1/2: acos x = π − 2·asin √z with z = (1 + x)/2: π − 2·(s + s·R(z)).
///
/// All three are computed and one is selected, as on the GPU.
pub fn acos_poly(x: f64) -> f64 {
    let ax = x.abs();
    let outer = ax >= 0.5;
    let z = if outer { (1.0 - ax) * 0.5 } else { x * x };
    let p = z * mad(
        z,
        mad(
            z,
            mad(z, mad(z, mad(z, ASIN_P5, ASIN_P4), ASIN_P3), ASIN_P2),
            ASIN_P1,
        ),
        ASIN_P0,
    );
    let q = mad(
        z,
        mad(z, mad(z, mad(z, ASIN_Q4, ASIN_Q3), ASIN_Q2), ASIN_Q1),
        1.0,
    );
    let r = p / q;
    let s = z.sqrt();
    let mid = PIO2_HI - (x - mad(-x, r, PIO2_LO));
    let c = mad(-s, s, z) / if s > 0.0 { s + s } else { 1.0 };
    let right = 2.0 * (s + mad(r, s, c));
    let left = PI_HI - 2.0 * (s + mad(r, s, -PIO2_LO));
    if !outer {
        mid
    } else if x > 0.0 {
        right
    } else {
        left
    }
}
