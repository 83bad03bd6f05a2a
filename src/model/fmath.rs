//! `exp`, `sin`, `cos`, `acos`, `atan`, `atan2`, `ln` and the normal quantile from
//! arithmetic alone, for the GPU's f64: the twin of
//! `shaders/model/fmath.wgsl` (same functions, same order, same operations in the same
//! order).
//!
//! # Why
//! WGSL's f64 has no safe transcendental functions: on Vulkan the builtins `exp`, `sin`,
//! `cos`, `acos`, `atan2`, `pow`, `log` compile for f64 and return garbage (the SPIR-V
//! instructions behind them are defined for 16- and 32-bit floats only). The resolutions
//! need some: the Alciatore ball–ball friction `exp(−c·|slip|)` (`src/resolve/ball_ball.rs`)
//! and the Stronge compliant cushion model's `sin`, `cos` of phases `ω·t` and `acos(x)`,
//! `x` in [−1, 1] (`src/resolve/stronge.rs`); a study's strike, drawn and resolved on the
//! device, needs `ln` and the normal quantile for its noise (`src/study/noise.rs`) and
//! `sin`, `cos` and the squirt's `atan2` for the cue (`src/resolve/stick_ball.rs`, which
//! the CPU resolves with these functions too, so that the two agree bit for bit). These functions use only what WGSL f64 has
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
//! - [`acos_poly`]: ≤ 1 ulp on [−1, 1];
//! - [`log_poly`]: ≤ 1 ulp on [2⁻¹⁰²², 2¹⁰²³];
//! - [`atan_poly`]: ≤ 1 ulp; [`atan2_poly`]: ≤ 2 ulp (the quotient's rounding first);
//! - [`normal_quantile`]: within 1e-15 relative on (0, 1) (against quantiles computed to
//!   40 digits).
//!
//! # Special values
//! NaN in gives NaN out; [`exp_poly`] overflows to +∞ above ~709.78 and is 0 below −746;
//! [`sin_poly`], [`cos_poly`] are NaN beyond ±[`TRIG_BOUND`] and for ±∞; [`acos_poly`] is
//! NaN outside [−1, 1]; [`log_poly`] and [`normal_quantile`] are specified only inside
//! their domains ((0, ∞) normal, (0, 1)). WGSL has no NaN or ∞ literals, so these come from arithmetic on the
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
//! - ln: fdlibm's minimax polynomial Lg1…Lg7 of log(1 + f) = 2·atanh(s) (`e_log.c`).
//! - atan, atan2: fdlibm's aT[0…10] and its atan(1/2), atan(1), atan(3/2) as
//!   double-doubles, and π's tail (`s_atan.c`, `e_atan2.c`).
//! - the normal quantile: the coefficients of M. J. Wichura's AS 241 (PPND16), Applied
//!   Statistics 37(3), 477–484, 1988.
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

// log: fdlibm e_log.c, log(1 + f) = f − s·(f − R(s²)), s = f/(2 + f).
/// 0x3FE55555_55555593
const LOG_LG1: f64 = 0.6666666666666735;
/// 0x3FD99999_9997FA04
const LOG_LG2: f64 = 0.3999999999940942;
/// 0x3FD24924_94229359
const LOG_LG3: f64 = 0.2857142874366239;
/// 0x3FCC71C5_1D8E78AF
const LOG_LG4: f64 = 0.22222198432149784;
/// 0x3FC74664_96CB03DE
const LOG_LG5: f64 = 0.1818357216161805;
/// 0x3FC39A09_D078C69F
const LOG_LG6: f64 = 0.15313837699209373;
/// 0x3FC2F112_DF3E5244
const LOG_LG7: f64 = 0.14798198605116586;
/// √2 rounded (0x3FF6A09E_667F3BCD): the reduced argument m lies in (√2/2, √2].
const SQRT2: f64 = std::f64::consts::SQRT_2;

// the normal quantile: Wichura's AS 241 (PPND16), rational approximations in three regions.
/// |p − 1/2| ≤ PPND_SPLIT1: the central region.
const PPND_SPLIT1: f64 = 0.425;
/// 0.425²: r = PPND_CONST1 − q² there.
const PPND_CONST1: f64 = 0.180625;
/// The tails: r = √(−ln min(p, 1 − p)) ≤ PPND_SPLIT2 is the near tail, beyond it the far one.
const PPND_SPLIT2: f64 = 5.0;
/// The near tail's shift: its polynomials are in r − PPND_CONST2.
const PPND_CONST2: f64 = 1.6;
// central numerator
/// 0x400B18D9_1E9EEF75
const PPND_A0: f64 = 3.3871328727963665;
/// 0x4060A488_8B1A436E
const PPND_A1: f64 = 133.14166789178438;
/// 0x409ECE5D_2213C0CC
const PPND_A2: f64 = 1971.5909503065513;
/// 0x40CAD1D8_CD4EE71D
const PPND_A3: f64 = 13731.69376550946;
/// 0x40E66C3E_869B752A
const PPND_A4: f64 = 45921.95393154987;
/// 0x40F06C1C_55B78F20
const PPND_A5: f64 = 67265.7709270087;
/// 0x40E052D2_6B2E45E4
const PPND_A6: f64 = 33430.57558358813;
/// 0x40A39A29_6F7D925E
const PPND_A7: f64 = 2509.0809287301227;
// central denominator (B0 = 1)
/// 0x4045281B_386E1AB5
const PPND_B1: f64 = 42.31333070160091;
/// 0x4085797E_FDC8B3F7
const PPND_B2: f64 = 687.1870074920579;
/// 0x40B51232_2E75C89F
const PPND_B3: f64 = 5394.196021424751;
/// 0x40D4B772_D5D65266
const PPND_B4: f64 = 21213.794301586597;
/// 0x40E3317C_AA64F4BE
const PPND_B5: f64 = 39307.89580009271;
/// 0x40DC0E45_7CB1AE76
const PPND_B6: f64 = 28729.085735721943;
/// 0x40B46A7E_CA984B69
const PPND_B7: f64 = 5226.495278852854;
// near tail numerator
/// 0x3FF6C665_FDE9526A
const PPND_C0: f64 = 1.4234371107496835;
/// 0x40128577_48CAB19B
const PPND_C1: f64 = 4.630337846156546;
/// 0x401713F7_1462256A
const PPND_C2: f64 = 5.769497221460691;
/// 0x400D2ECB_1A3D02C4
const PPND_C3: f64 = 3.6478483247632045;
/// 0x3FF453CC_085375B2
const PPND_C4: f64 = 1.2704582524523684;
/// 0x3FCEF2AB_B9B85C37
const PPND_C5: f64 = 0.2417807251774506;
/// 0x3F9744EB_6C45EC67
const PPND_C6: f64 = 0.022723844989269184;
/// 0x3F49615A_C0B7ACE9
const PPND_C7: f64 = 0.0007745450142783414;
// near tail denominator (D0 = 1)
/// 0x40006CEF_BB46A449
const PPND_D1: f64 = 2.053191626637759;
/// 0x3FFAD278_E6526633
const PPND_D2: f64 = 1.6763848301838038;
/// 0x3FE61292_F23385C9
const PPND_D3: f64 = 0.6897673349851;
/// 0x3FC2F512_3394F040
const PPND_D4: f64 = 0.14810397642748008;
/// 0x3F8F207A_7EAB17BF
const PPND_D5: f64 = 0.015198666563616457;
/// 0x3F41F18C_BFDF2728
const PPND_D6: f64 = 0.0005475938084995345;
/// 0x3E120D3F_686439E4
const PPND_D7: f64 = 1.0507500716444169e-09;
// far tail numerator
/// 0x401AA1B1_C13EE526
const PPND_E0: f64 = 6.657904643501103;
/// 0x4015DAEA_6E875003
const PPND_E1: f64 = 5.463784911164114;
/// 0x3FFC8EA6_461FA445
const PPND_E2: f64 = 1.7848265399172913;
/// 0x3FD2FAD9_315255CF
const PPND_E3: f64 = 0.29656057182850487;
/// 0x3F9B2B41_193B4EE7
const PPND_E4: f64 = 0.026532189526576124;
/// 0x3F545C19_08425345
const PPND_E5: f64 = 0.0012426609473880784;
/// 0x3EFC6EC6_CC59E02A
const PPND_E6: f64 = 2.7115555687434876e-05;
/// 0x3E8AFB74_D693BF93
const PPND_E7: f64 = 2.0103343992922881e-07;
// far tail denominator (F0 = 1)
/// 0x3FE331D3_4FC7D77F
const PPND_F1: f64 = 0.599832206555888;
/// 0x3FC186EB_183443FB
const PPND_F2: f64 = 0.1369298809227358;
/// 0x3F8E76F9_3215462A
const PPND_F3: f64 = 0.014875361290850615;
/// 0x3F49C8BC_979DC5D7
const PPND_F4: f64 = 0.0007868691311456133;
/// 0x3EF35C2C_496374BF
const PPND_F5: f64 = 1.8463183175100548e-05;
/// 0x3E831446_F740B9E0
const PPND_F6: f64 = 1.421511758316446e-07;
/// 0x3CE269BF_F1F8C190
const PPND_F7: f64 = 2.0442631033899397e-15;

// atan: fdlibm s_atan.c, atan(t) ≈ t − t·(s1 + s2) on |t| < 7/16 after the reduction.
/// 0x3FD55555_5555550D
const ATAN_T0: f64 = 0.3333333333333293;
/// 0xBFC99999_9998EBC4
const ATAN_T1: f64 = -0.19999999999876483;
/// 0x3FC24924_920083FF
const ATAN_T2: f64 = 0.14285714272503466;
/// 0xBFBC71C6_FE231671
const ATAN_T3: f64 = -0.11111110405462356;
/// 0x3FB745CD_C54C206E
const ATAN_T4: f64 = 0.09090887133436507;
/// 0xBFB3B0F2_AF749A6D
const ATAN_T5: f64 = -0.0769187620504483;
/// 0x3FB10D66_A0D03D51
const ATAN_T6: f64 = 0.06661073137387531;
/// 0xBFADDE2D_52DEFD9A
const ATAN_T7: f64 = -0.058335701337905735;
/// 0x3FA97B4B_24760DEB
const ATAN_T8: f64 = 0.049768779946159324;
/// 0xBFA2B444_2C6A6C2F
const ATAN_T9: f64 = -0.036531572744216916;
/// 0x3F90AD3A_E322DA11
const ATAN_T10: f64 = 0.016285820115365782;
/// atan(1/2) rounded (0x3FDDAC67_0561BB4F).
const ATAN_HI0: f64 = 0.4636476090008061;
/// atan(1) rounded (0x3FE921FB_54442D18).
const ATAN_HI1: f64 = std::f64::consts::FRAC_PI_4;
/// atan(3/2) rounded (0x3FEF730B_D281F69B).
const ATAN_HI2: f64 = 0.982793723247329;
/// atan(1/2) − ATAN_HI0 (0x3C7A2B7F_222F65E2).
const ATAN_LO0: f64 = 2.2698777452961687e-17;
/// atan(1) − ATAN_HI1 (0x3C81A626_33145C07).
const ATAN_LO1: f64 = 3.061616997868383e-17;
/// atan(3/2) − ATAN_HI2 (0x3C700788_7AF0CBBD).
const ATAN_LO2: f64 = 1.3903311031230998e-17;
/// Below this |x|, atan x is x to the last bit (2⁻²⁷).
const ATAN_TINY: f64 = 7.450580596923828e-9;
/// From this |x| on, atan x is ±π/2 rounded (2⁶⁶).
const ATAN_HUGE: f64 = 7.378697629483821e19;
/// π − PI_HI (0x3CA1A626_33145C07): atan2's tail of π.
const PI_LO: f64 = 1.2246467991473532e-16;

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

/// ln x.
///
/// Contract: for finite x ≥ 2⁻¹⁰²² (positive and normal), within [`LOG_ULPS`] ulp of the
/// correctly rounded value (tests/fmath.rs); ln 1 = +0. Zero, subnormal, negative,
/// infinite and NaN arguments are outside the contract (what they give is unspecified).
///
/// Method (fdlibm e_log.c): x = 2ᵏ·m with m in (√2/2, √2] — k and m found without the
/// bits of x (WGSL cannot take an f64 apart), by ten steps that divide or multiply by
/// 2^512, 2^256, …, 2, all exact — then with f = m − 1 (exact) and s = f/(2 + f),
/// ln m = f − s·(f − R(s²)), R fdlibm's minimax polynomial (|2s·atanh-series error| <
/// 2⁻⁵⁸·⁴⁵), and ln x = k·LN2_HI − ((s·(f − R) − k·LN2_LO) − f) with the ln 2 split of
/// [`exp_poly`] (k·LN2_HI exact). fdlibm also has a second arrangement for f near √2 − 1,
/// worth a fraction of an ulp there; it is left out, one formula on both twins.
pub fn log_poly(x: f64) -> f64 {
    let mut m = x;
    let mut k = 0i32;
    let mut p = pow2i(512);
    let mut e = 512i32;
    for _ in 0..10 {
        // before this step 2^(1 − 2e) ≤ m < 2^(2e); after it 2^(1 − e) ≤ m < 2^e
        if m >= p {
            m /= p;
            k += e;
        }
        if m < 2.0 / p {
            m *= p;
            k -= e;
        }
        p = p.sqrt();
        e >>= 1;
    }
    let big = m > SQRT2;
    let mr = if big { m * 0.5 } else { m };
    let kr = if big { k + 1 } else { k };
    let f = mr - 1.0;
    let s = f / (2.0 + f);
    let z = s * s;
    let w = z * z;
    let t1 = w * mad(w, mad(w, LOG_LG6, LOG_LG4), LOG_LG2);
    let t2 = z * mad(w, mad(w, mad(w, LOG_LG7, LOG_LG5), LOG_LG3), LOG_LG1);
    let r = t2 + t1;
    let dk = kr as f64;
    mad(dk, LN2_HI, -(mad(s, f - r, -(dk * LN2_LO)) - f))
}

/// The documented bound of [`log_poly`], in ulps.
pub const LOG_ULPS: u64 = 1;

/// The standard normal quantile Φ⁻¹(p): the x with P(Z ≤ x) = p.
///
/// Contract: for p in (0, 1), within 1e-15 relative of Φ⁻¹(p) (AS 241's approximations
/// are good to about 1e-16, the rounding of their evaluation adds a few ulps;
/// tests/fmath.rs checks known quantiles to 1e-15); antisymmetric,
/// Φ⁻¹(1 − p) = −Φ⁻¹(p) where 1 − p is exact; Φ⁻¹(1/2) = 0. p = 0, 1 and arguments
/// outside (0, 1) are outside the contract.
///
/// Method: M. J. Wichura, "Algorithm AS 241: The percentage points of the normal
/// distribution", Applied Statistics 37(3), 1988 (its PPND16): with q = p − 1/2, for
/// |q| ≤ 0.425 a rational function of r = 0.425² − q² (degree 7 over 7) times q; beyond it,
/// with r = √(−ln min(p, 1 − p)), a rational function of r − 1.6 for r ≤ 5 and of r − 5
/// beyond, signed as q. Polynomials in Horner form with [`mad`]; ln by [`log_poly`]. The
/// central region returns early (85 % of uniform p: no logarithm); of the tails both are
/// computed and one is selected, as on the GPU.
pub fn normal_quantile(p: f64) -> f64 {
    let q = p - 0.5;
    let r = PPND_CONST1 - q * q;
    let a = mad(r, PPND_A7, PPND_A6);
    let a = mad(r, a, PPND_A5);
    let a = mad(r, a, PPND_A4);
    let a = mad(r, a, PPND_A3);
    let a = mad(r, a, PPND_A2);
    let a = mad(r, a, PPND_A1);
    let a = mad(r, a, PPND_A0);
    let b = mad(r, PPND_B7, PPND_B6);
    let b = mad(r, b, PPND_B5);
    let b = mad(r, b, PPND_B4);
    let b = mad(r, b, PPND_B3);
    let b = mad(r, b, PPND_B2);
    let b = mad(r, b, PPND_B1);
    let b = mad(r, b, 1.0);
    if q.abs() <= PPND_SPLIT1 {
        return q * (a / b);
    }
    // the smaller tail, exact: p itself below 1/2, 1 − p (Sterbenz) above
    let small = if q < 0.0 { p } else { 1.0 - p };
    let t = (-log_poly(small)).sqrt();
    let u = t - PPND_CONST2;
    let c = mad(u, PPND_C7, PPND_C6);
    let c = mad(u, c, PPND_C5);
    let c = mad(u, c, PPND_C4);
    let c = mad(u, c, PPND_C3);
    let c = mad(u, c, PPND_C2);
    let c = mad(u, c, PPND_C1);
    let c = mad(u, c, PPND_C0);
    let d = mad(u, PPND_D7, PPND_D6);
    let d = mad(u, d, PPND_D5);
    let d = mad(u, d, PPND_D4);
    let d = mad(u, d, PPND_D3);
    let d = mad(u, d, PPND_D2);
    let d = mad(u, d, PPND_D1);
    let d = mad(u, d, 1.0);
    let v = t - PPND_SPLIT2;
    let e = mad(v, PPND_E7, PPND_E6);
    let e = mad(v, e, PPND_E5);
    let e = mad(v, e, PPND_E4);
    let e = mad(v, e, PPND_E3);
    let e = mad(v, e, PPND_E2);
    let e = mad(v, e, PPND_E1);
    let e = mad(v, e, PPND_E0);
    let f = mad(v, PPND_F7, PPND_F6);
    let f = mad(v, f, PPND_F5);
    let f = mad(v, f, PPND_F4);
    let f = mad(v, f, PPND_F3);
    let f = mad(v, f, PPND_F2);
    let f = mad(v, f, PPND_F1);
    let f = mad(v, f, 1.0);
    let size = if t <= PPND_SPLIT2 { c / d } else { e / f };
    if q < 0.0 { -size } else { size }
}

/// atan x, in [−π/2, π/2].
///
/// Contract: ≤ 1 ulp from the correctly rounded value for finite x (tests/fmath.rs);
/// atan(±0) = ±0, atan x = x for |x| < 2⁻²⁷, ±π/2 rounded for |x| ≥ 2⁶⁶; NaN for NaN.
///
/// Method (fdlibm s_atan.c): with t = |x|, below 7/16 atan t = t − t·(s1 + s2) (fdlibm's
/// odd minimax polynomial, split in even and odd powers of t⁴); above, t is reduced by
/// atan t = atan c + atan((t − c)/(1 + c·t)) with c = 1/2, 1, 3/2 or ∞ by where t lies
/// (7/16, 11/16, 19/16, 39/16), atan c as a double-double; the sign of x last.
pub fn atan_poly(x: f64) -> f64 {
    let ax = x.abs();
    let id = if ax < 0.4375 {
        -1
    } else if ax < 0.6875 {
        0
    } else if ax < 1.1875 {
        1
    } else if ax < 2.4375 {
        2
    } else {
        3
    };
    let t = match id {
        -1 => ax,
        0 => mad(2.0, ax, -1.0) / (2.0 + ax),
        1 => (ax - 1.0) / (ax + 1.0),
        2 => (ax - 1.5) / mad(1.5, ax, 1.0),
        _ => -1.0 / ax,
    };
    let (hi, lo) = match id {
        0 => (ATAN_HI0, ATAN_LO0),
        1 => (ATAN_HI1, ATAN_LO1),
        2 => (ATAN_HI2, ATAN_LO2),
        _ => (PIO2_HI, PIO2_LO),
    };
    let z = t * t;
    let w = z * z;
    let s1 = z * mad(
        w,
        mad(
            w,
            mad(w, mad(w, mad(w, ATAN_T10, ATAN_T8), ATAN_T6), ATAN_T4),
            ATAN_T2,
        ),
        ATAN_T0,
    );
    let s2 = w * mad(
        w,
        mad(w, mad(w, mad(w, ATAN_T9, ATAN_T7), ATAN_T5), ATAN_T3),
        ATAN_T1,
    );
    let small = mad(-t, s1 + s2, t);
    let reduced = hi - (mad(t, s1 + s2, -lo) - t);
    let a = if id < 0 { small } else { reduced };
    let a = if ax >= ATAN_HUGE {
        PIO2_HI + PIO2_LO
    } else {
        a
    };
    let signed = if x < 0.0 { -a } else { a };
    if ax < ATAN_TINY { x } else { signed }
}

/// atan2(y, x): the angle of the point (x, y) from the +x axis, in [−π, π].
///
/// Contract: for finite arguments whose quotient y/x neither overflows nor underflows,
/// ≤ 2 ulp from the correctly rounded value (tests/fmath.rs: the rounding of y/x, then
/// [`atan_poly`]); atan2(y, 0) = ±π/2 for y ≠ 0; atan2(±0, x > 0) = +0, atan2(±0, 0) = +0
/// and atan2(±0, x < 0) = π (glibc keeps the sign of −0 there: the physics never asks);
/// NaN for NaN.
///
/// Method (fdlibm e_atan2.c): z = atan|y/x|, then by the signs: z, −z, π − (z − π_lo),
/// (z − π_lo) − π, with π as the double-double PI_HI + PI_LO.
pub fn atan2_poly(y: f64, x: f64) -> f64 {
    let z = atan_poly((y / x).abs());
    let right = if y < 0.0 { -z } else { z };
    let left = if y < 0.0 {
        (z - PI_LO) - PI_HI
    } else {
        PI_HI - (z - PI_LO)
    };
    let up = if y < 0.0 { -PIO2_HI } else { PIO2_HI };
    let on_axis = if y == 0.0 { 0.0 } else { up };
    if x > 0.0 {
        right
    } else if x < 0.0 {
        left
    } else {
        on_axis
    }
}
