// exp, sin, cos, acos, atan, atan2, ln and the normal quantile from arithmetic alone, for
// the GPU's f64. WGSL twin of
// src/model/fmath.rs (same functions, same order, same operations in the same order;
// the module documentation there has the why, the accuracy and the sources).
//
// WGSL's f64 has no safe transcendental builtins: on Vulkan exp, sin, cos, acos, atan2,
// pow, log compile for f64 and return garbage. These use only + - * /, sqrt, abs, select,
// comparisons and int/float conversions; mad(a, b, c) is a * b + c rounded twice. Built
// as SPIR-V whose float operations are marked NoContraction (src/gpu/spirv.rs), nothing
// is fused or re-associated, so where + - * / sqrt are IEEE the results are the Rust
// twin's bits.
//
// Special values come from arithmetic on the argument (WGSL has no NaN or infinity
// literals): a compiler that assumes there are none may not keep them. Written in `real`
// like the other twins, with constants that fit f32, so the file compiles in the f32
// shader too; it is designed and tested for f64.

// exp: fdlibm's ln 2 split and 1/ln 2.
// 1/ln 2 (0x3FF71547_652B82FE).
const INV_LN2: real = 1.4426950408889634;
// ln 2 to 32 significant bits (0x3FE62E42_FEE00000): k·LN2_HI is exact for |k| < 2²¹.
const LN2_HI: real = 0.6931471803691238;
// ln 2 − LN2_HI (0x3DEA39EF_35793C76).
const LN2_LO: real = 1.9082149292705877e-10;
// Arguments beyond ±EXP_CLAMP reduce as if they were ±EXP_CLAMP (the result is 0 or ∞
// there anyway): |k| ≤ 1097, and the conversion to i32 never sees NaN or ∞.
const EXP_CLAMP: real = 760.0;
// Below this exp is 0 (it underflows to 0 below −745.1332…).
const EXP_ZERO_BELOW: real = -746.0;
// exp: 1/n!, rounded to nearest (1/2, 1 and 1 are written out where they are used).
// 1/3! (0x3FC55555_55555555).
const EXP_C3: real = 0.16666666666666666;
// 1/4! (0x3FA55555_55555555).
const EXP_C4: real = 0.041666666666666664;
// 1/5! (0x3F811111_11111111).
const EXP_C5: real = 0.008333333333333333;
// 1/6! (0x3F56C16C_16C16C17).
const EXP_C6: real = 0.001388888888888889;
// 1/7! (0x3F2A01A0_1A01A01A).
const EXP_C7: real = 0.0001984126984126984;
// 1/8! (0x3EFA01A0_1A01A01A).
const EXP_C8: real = 2.48015873015873e-5;
// 1/9! (0x3EC71DE3_A556C734).
const EXP_C9: real = 2.7557319223985893e-6;
// 1/10! (0x3E927E4F_B7789F5C).
const EXP_C10: real = 2.755731922398589e-7;
// 1/11! (0x3E5AE645_67F544E4).
const EXP_C11: real = 2.505210838544172e-8;
// 1/12! (0x3E21EED8_EFF8D898).
const EXP_C12: real = 2.08767569878681e-9;
// 1/13! (0x3DE61246_13A86D09).
const EXP_C13: real = 1.6059043836821613e-10;

// sin, cos: the reduction modulo π/2 (fdlibm e_rem_pio2.c).
// sin and cos reduce arguments up to this size exactly enough (|n| < 2¹⁹, so n times a
// 33-bit piece of π/2 is exact); beyond it they are NaN. fdlibm's medium range goes to
// 2¹⁹·π/2 ≈ 8.2·10⁵.
const TRIG_BOUND: real = 8.0e5;
// 2/π (0x3FE45F30_6DC9C883).
const INV_PIO2: real = 0.6366197723675814;
// The first 33 bits of π/2 (0x3FF921FB_54400000).
const PIO2_1: real = 1.5707963267341256;
// The second 33 bits of π/2 (0x3DD0B461_1A600000).
const PIO2_2: real = 6.077100506303966e-11;
// The third 33 bits of π/2 (0x3BA3198A_2E000000).
const PIO2_3: real = 2.0222662487111665e-21;
// π/2 − (PIO2_1 + PIO2_2 + PIO2_3) (0x397B839A_252049C1).
const PIO2_3T: real = 8.4784276603689e-32;
// Below this |x|, sin x is x to the last bit (2⁻²⁷, 0x3E400000_00000000).
const SIN_TINY: real = 7.450580596923828e-9;
// sin: fdlibm k_sin.c, sin(x) ≈ x + SIN_S1·x³ + … + SIN_S6·x¹³ on [−π/4, π/4].
// 0xBFC55555_55555549
const SIN_S1: real = -0.16666666666666632;
// 0x3F811111_1110F8A6
const SIN_S2: real = 0.00833333333332249;
// 0xBF2A01A0_19C161D5
const SIN_S3: real = -0.0001984126982985795;
// 0x3EC71DE3_57B1FE7D
const SIN_S4: real = 2.7557313707070068e-6;
// 0xBE5AE5E6_8A2B9CEB
const SIN_S5: real = -2.5050760253406863e-8;
// 0x3DE5D93A_5ACFD57C
const SIN_S6: real = 1.58969099521155e-10;
// cos: fdlibm k_cos.c, cos(x) ≈ 1 − x²/2 + COS_C1·x⁴ + … + COS_C6·x¹⁴ on [−π/4, π/4].
// 0x3FA55555_5555554C
const COS_C1: real = 0.0416666666666666;
// 0xBF56C16C_16C15177
const COS_C2: real = -0.001388888888887411;
// 0x3EFA01A0_19CB1590
const COS_C3: real = 2.480158728947673e-5;
// 0xBE927E4F_809C52AD
const COS_C4: real = -2.7557314351390663e-7;
// 0x3E21EE9E_BDB4B1C4
const COS_C5: real = 2.087572321298175e-9;
// 0xBDA8FAE9_BE8838D4
const COS_C6: real = -1.1359647557788195e-11;

// acos: fdlibm e_asin.c / e_acos.c.
// π rounded (0x400921FB_54442D18).
const PI_HI: real = 3.141592653589793;
// π/2 rounded (0x3FF921FB_54442D18).
const PIO2_HI: real = 1.5707963267948966;
// π/2 − PIO2_HI (0x3C91A626_33145C07).
const PIO2_LO: real = 6.123233995736766e-17;
// R(z) = P(z)/Q(z): asin(x) ≈ x + x·P(x²)/Q(x²) on |x| ≤ 1/2 (P has a factor z).
// 0x3FC55555_55555555
const ASIN_P0: real = 0.16666666666666666;
// 0xBFD4D612_03EB6F7D
const ASIN_P1: real = -0.3255658186224009;
// 0x3FC9C155_0E884455
const ASIN_P2: real = 0.20121253213486293;
// 0xBFA48228_B5688F3B
const ASIN_P3: real = -0.04005553450067941;
// 0x3F49EFE0_7501B288
const ASIN_P4: real = 0.0007915349942898145;
// 0x3F023DE1_0DFDF709
const ASIN_P5: real = 3.479331075960212e-5;
// 0xC0033A27_1C8A2D4B
const ASIN_Q1: real = -2.403394911734414;
// 0x40002AE5_9C598AC8
const ASIN_Q2: real = 2.0209457602335057;
// 0xBFE6066C_1B8D0159
const ASIN_Q3: real = -0.6882839716054533;
// 0x3FB3B8C5_B12E9282
const ASIN_Q4: real = 0.07703815055590194;

// log: fdlibm e_log.c, log(1 + f) = f − s·(f − R(s²)), s = f/(2 + f).
// 0x3FE55555_55555593
const LOG_LG1: real = 0.6666666666666735;
// 0x3FD99999_9997FA04
const LOG_LG2: real = 0.3999999999940942;
// 0x3FD24924_94229359
const LOG_LG3: real = 0.2857142874366239;
// 0x3FCC71C5_1D8E78AF
const LOG_LG4: real = 0.22222198432149784;
// 0x3FC74664_96CB03DE
const LOG_LG5: real = 0.1818357216161805;
// 0x3FC39A09_D078C69F
const LOG_LG6: real = 0.15313837699209373;
// 0x3FC2F112_DF3E5244
const LOG_LG7: real = 0.14798198605116586;
// √2 rounded (0x3FF6A09E_667F3BCD): the reduced argument m lies in (√2/2, √2].
const SQRT2: real = 1.4142135623730951;

// the normal quantile: Wichura's AS 241 (PPND16), rational approximations in three regions.
// |p − 1/2| ≤ PPND_SPLIT1: the central region.
const PPND_SPLIT1: real = 0.425;
// 0.425²: r = PPND_CONST1 − q² there.
const PPND_CONST1: real = 0.180625;
// The tails: r = √(−ln min(p, 1 − p)) ≤ PPND_SPLIT2 is the near tail, beyond it the far one.
const PPND_SPLIT2: real = 5.0;
// The near tail's shift: its polynomials are in r − PPND_CONST2.
const PPND_CONST2: real = 1.6;
// central numerator
// 0x400B18D9_1E9EEF75
const PPND_A0: real = 3.3871328727963665;
// 0x4060A488_8B1A436E
const PPND_A1: real = 133.14166789178438;
// 0x409ECE5D_2213C0CC
const PPND_A2: real = 1971.5909503065513;
// 0x40CAD1D8_CD4EE71D
const PPND_A3: real = 13731.69376550946;
// 0x40E66C3E_869B752A
const PPND_A4: real = 45921.95393154987;
// 0x40F06C1C_55B78F20
const PPND_A5: real = 67265.7709270087;
// 0x40E052D2_6B2E45E4
const PPND_A6: real = 33430.57558358813;
// 0x40A39A29_6F7D925E
const PPND_A7: real = 2509.0809287301227;
// central denominator (B0 = 1)
// 0x4045281B_386E1AB5
const PPND_B1: real = 42.31333070160091;
// 0x4085797E_FDC8B3F7
const PPND_B2: real = 687.1870074920579;
// 0x40B51232_2E75C89F
const PPND_B3: real = 5394.196021424751;
// 0x40D4B772_D5D65266
const PPND_B4: real = 21213.794301586597;
// 0x40E3317C_AA64F4BE
const PPND_B5: real = 39307.89580009271;
// 0x40DC0E45_7CB1AE76
const PPND_B6: real = 28729.085735721943;
// 0x40B46A7E_CA984B69
const PPND_B7: real = 5226.495278852854;
// near tail numerator
// 0x3FF6C665_FDE9526A
const PPND_C0: real = 1.4234371107496835;
// 0x40128577_48CAB19B
const PPND_C1: real = 4.630337846156546;
// 0x401713F7_1462256A
const PPND_C2: real = 5.769497221460691;
// 0x400D2ECB_1A3D02C4
const PPND_C3: real = 3.6478483247632045;
// 0x3FF453CC_085375B2
const PPND_C4: real = 1.2704582524523684;
// 0x3FCEF2AB_B9B85C37
const PPND_C5: real = 0.2417807251774506;
// 0x3F9744EB_6C45EC67
const PPND_C6: real = 0.022723844989269184;
// 0x3F49615A_C0B7ACE9
const PPND_C7: real = 0.0007745450142783414;
// near tail denominator (D0 = 1)
// 0x40006CEF_BB46A449
const PPND_D1: real = 2.053191626637759;
// 0x3FFAD278_E6526633
const PPND_D2: real = 1.6763848301838038;
// 0x3FE61292_F23385C9
const PPND_D3: real = 0.6897673349851;
// 0x3FC2F512_3394F040
const PPND_D4: real = 0.14810397642748008;
// 0x3F8F207A_7EAB17BF
const PPND_D5: real = 0.015198666563616457;
// 0x3F41F18C_BFDF2728
const PPND_D6: real = 0.0005475938084995345;
// 0x3E120D3F_686439E4
const PPND_D7: real = 1.0507500716444169e-09;
// far tail numerator
// 0x401AA1B1_C13EE526
const PPND_E0: real = 6.657904643501103;
// 0x4015DAEA_6E875003
const PPND_E1: real = 5.463784911164114;
// 0x3FFC8EA6_461FA445
const PPND_E2: real = 1.7848265399172913;
// 0x3FD2FAD9_315255CF
const PPND_E3: real = 0.29656057182850487;
// 0x3F9B2B41_193B4EE7
const PPND_E4: real = 0.026532189526576124;
// 0x3F545C19_08425345
const PPND_E5: real = 0.0012426609473880784;
// 0x3EFC6EC6_CC59E02A
const PPND_E6: real = 2.7115555687434876e-05;
// 0x3E8AFB74_D693BF93
const PPND_E7: real = 2.0103343992922881e-07;
// far tail denominator (F0 = 1)
// 0x3FE331D3_4FC7D77F
const PPND_F1: real = 0.599832206555888;
// 0x3FC186EB_183443FB
const PPND_F2: real = 0.1369298809227358;
// 0x3F8E76F9_3215462A
const PPND_F3: real = 0.014875361290850615;
// 0x3F49C8BC_979DC5D7
const PPND_F4: real = 0.0007868691311456133;
// 0x3EF35C2C_496374BF
const PPND_F5: real = 1.8463183175100548e-05;
// 0x3E831446_F740B9E0
const PPND_F6: real = 1.421511758316446e-07;
// 0x3CE269BF_F1F8C190
const PPND_F7: real = 2.0442631033899397e-15;

// atan: fdlibm s_atan.c, atan(t) ≈ t − t·(s1 + s2) on |t| < 7/16 after the reduction.
// 0x3FD55555_5555550D
const ATAN_T0: real = 0.3333333333333293;
// 0xBFC99999_9998EBC4
const ATAN_T1: real = -0.19999999999876483;
// 0x3FC24924_920083FF
const ATAN_T2: real = 0.14285714272503466;
// 0xBFBC71C6_FE231671
const ATAN_T3: real = -0.11111110405462356;
// 0x3FB745CD_C54C206E
const ATAN_T4: real = 0.09090887133436507;
// 0xBFB3B0F2_AF749A6D
const ATAN_T5: real = -0.0769187620504483;
// 0x3FB10D66_A0D03D51
const ATAN_T6: real = 0.06661073137387531;
// 0xBFADDE2D_52DEFD9A
const ATAN_T7: real = -0.058335701337905735;
// 0x3FA97B4B_24760DEB
const ATAN_T8: real = 0.049768779946159324;
// 0xBFA2B444_2C6A6C2F
const ATAN_T9: real = -0.036531572744216916;
// 0x3F90AD3A_E322DA11
const ATAN_T10: real = 0.016285820115365782;
// atan(1/2) rounded (0x3FDDAC67_0561BB4F).
const ATAN_HI0: real = 0.4636476090008061;
// atan(1) rounded (0x3FE921FB_54442D18).
const ATAN_HI1: real = 0.7853981633974483;
// atan(3/2) rounded (0x3FEF730B_D281F69B).
const ATAN_HI2: real = 0.982793723247329;
// atan(1/2) − ATAN_HI0 (0x3C7A2B7F_222F65E2).
const ATAN_LO0: real = 2.2698777452961687e-17;
// atan(1) − ATAN_HI1 (0x3C81A626_33145C07).
const ATAN_LO1: real = 3.061616997868383e-17;
// atan(3/2) − ATAN_HI2 (0x3C700788_7AF0CBBD).
const ATAN_LO2: real = 1.3903311031230998e-17;
// Below this |x|, atan x is x to the last bit (2⁻²⁷).
const ATAN_TINY: real = 7.450580596923828e-9;
// From this |x| on, atan x is ±π/2 rounded (2⁶⁶).
const ATAN_HUGE: real = 7.378697629483821e19;
// π − PI_HI (0x3CA1A626_33145C07): atan2's tail of π.
const PI_LO: real = 1.2246467991473532e-16;


// a·b + c rounded twice, the product then the sum, never fused (Rust: mad).
fn mad(a: real, b: real, c: real) -> real {
    return a * b + c;
}

// 2ⁿ exactly, for |n| ≤ 1023 (below 2⁻¹⁰²² the result is subnormal, still exact).
//
// Method: the product of the powers 2^(±2ⁱ) for the bits i of |n|, each power the square
// of the one before: WGSL cannot build an f64 from its bits without 64-bit integers
// (`bitcast` keeps the width), and `ldexp` is not on the list of safe f64 builtins.
fn pow2i(n: i32) -> real {
    var b = select(real(2.0), real(0.5), n < 0);
    var m = abs(n);
    var p: real = 1.0;
    for (var i = 0; i < 10; i++) {
        p = select(p, p * b, (m & 1) == 1);
        m = m >> 1u;
        b = b * b;
    }
    return p;
}

// eˣ.
//
// Contract: ≤ 1 ulp from the correctly rounded value on [−745, 709.7] (tests/fmath.rs),
// results below 2⁻¹⁰²² subnormal; 0 for x < −746 (and −∞); +∞ above ~709.78 (and for +∞);
// NaN for NaN. exp(±0) = 1 exactly.
//
// Method: k = round(x/ln 2) (halves away from zero) and r = x − k·ln 2 with a two-constant
// Cody–Waite split of ln 2 (k·LN2_HI and x − k·LN2_HI are exact), so |r| ≤ ln 2/2 +
// rounding; eʳ by its Taylor polynomial to r¹³ (truncation < 2⁻⁵⁸ relative) in Horner form
// with mad; then 2ᵏ as 2^(k − 2h)·2ʰ·2ʰ with h = k/2, so each factor is a normal power of
// two, the first two products are exact and only the last one rounds (into the subnormals,
// or overflowing to +∞).
fn exp_poly(x: real) -> real {
    let xc = select(select(-EXP_CLAMP, EXP_CLAMP, x > 0.0), x, abs(x) <= EXP_CLAMP);
    let half = select(real(0.5), real(-0.5), xc < 0.0);
    let k = i32(mad(xc, INV_LN2, half));
    let kf = real(k);
    let hi = mad(-kf, LN2_HI, x);
    let r = mad(-kf, LN2_LO, hi);
    var p = mad(r, EXP_C13, EXP_C12);
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
    return select(y, 0.0, x < EXP_ZERO_BELOW);
}

// x reduced modulo π/2: x = n·π/2 + hi + lo (what reduce_half_pi returns).
struct HalfPiRem {
    // The quadrant: n = round(x·2/π); only n mod 4 matters to sin and cos.
    n: i32,
    // The remainder, |hi| ≤ π/4 + a few ulps.
    hi: real,
    // Its tail: |lo| ≤ ulp(hi)/2.
    lo: real,
}

// x − n·π/2 as a double-double hi + lo, n = round(x·2/π), for |x| ≤ TRIG_BOUND.
//
// Contract: hi + lo is the true remainder to far more than 53 bits (about 2⁻¹⁰⁰
// relative by the construction below), however close x is to a multiple of π/2. Beyond the bound, and for ±∞ and NaN, n = 0 and hi is NaN.
//
// Method: Cody–Waite with fdlibm's three 33-bit pieces of π/2 and the tail PIO2_3T:
// n·PIO2_1, n·PIO2_2, n·PIO2_3 are exact (|n| < 2¹⁹) and so is x − n·PIO2_1 (Sterbenz); the
// next two subtractions are error-free (TwoSum), their errors and −n·PIO2_3T (a mad) are
// summed into the tail, and a last TwoSum normalises hi + lo. Branch-free (fdlibm decides
// how many pieces it needs from the exponents; TwoSum needs no such decision).
fn reduce_half_pi(x: real) -> HalfPiRem {
    let inside = abs(x) <= TRIG_BOUND;
    let xr = select(0.0, x, inside);
    let half = select(real(0.5), real(-0.5), xr < 0.0);
    let n = i32(mad(xr, INV_PIO2, half));
    let f = real(n);
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
    let bad = sqrt(-1.0 - abs(x));
    return HalfPiRem(n, select(bad, hi, inside), lo);
}

// sin(x + y) for |x| ≤ π/4 + a little and a tail |y| ≤ ulp(x)/2 (fdlibm's
// __kernel_sin(x, y, 1)).
//
// Method: x + x³·(SIN_S1 + x²·r(x²)) with fdlibm's minimax coefficients, arranged so that
// the tail enters as sin(x + y) ≈ sin(x) + y·(1 − x²/2); products that feed sums are mads.
fn sin_kernel(x: real, y: real) -> real {
    let z = x * x;
    let w = z * z;
    let r = mad(z * w, mad(z, SIN_S6, SIN_S5), mad(z, mad(z, SIN_S4, SIN_S3), SIN_S2));
    let v = z * x;
    let t = mad(-v, r, 0.5 * y);
    let u = mad(z, t, -y);
    return x - mad(-v, SIN_S1, u);
}

// cos(x + y) for |x| ≤ π/4 + a little and a tail |y| ≤ ulp(x)/2 (fdlibm's
// __kernel_cos(x, y), the FreeBSD form).
//
// Method: 1 − x²/2 + x⁴·r(x²) with fdlibm's minimax coefficients; w = 1 − x²/2 is
// rounded and its rounding error (1 − w) − x²/2 (exact) added back with the tail's
// −x·y; products that feed sums are mads.
fn cos_kernel(x: real, y: real) -> real {
    let z = x * x;
    let w = z * z;
    let r = mad(
        z,
        mad(z, mad(z, COS_C3, COS_C2), COS_C1),
        (w * w) * mad(z, mad(z, COS_C6, COS_C5), COS_C4),
    );
    let hz = 0.5 * z;
    let one_minus = 1.0 - hz;
    return one_minus + (((1.0 - one_minus) - hz) + mad(z, r, -(x * y)));
}

// sin x.
//
// Contract: ≤ 1 ulp from the correctly rounded value for |x| ≤ TRIG_BOUND
// (tests/fmath.rs), near the multiples of π/2 included; sin(±0) = ±0 and sin x = x for
// |x| < 2⁻²⁷; NaN beyond the bound, for ±∞ and for NaN.
//
// Method: reduce_half_pi, then by n mod 4: sin r, cos r, −sin r, −cos r (sin_kernel,
// cos_kernel; both are computed and one is selected).
fn sin_poly(x: real) -> real {
    let q = reduce_half_pi(x);
    let s = sin_kernel(q.hi, q.lo);
    let c = cos_kernel(q.hi, q.lo);
    let v = select(c, s, (q.n & 1) == 0);
    let signed = select(-v, v, (q.n & 2) == 0);
    return select(signed, x, abs(x) < SIN_TINY);
}

// cos x.
//
// Contract: ≤ 1 ulp from the correctly rounded value for |x| ≤ TRIG_BOUND
// (tests/fmath.rs), near the multiples of π/2 included; cos(±0) = 1; NaN beyond the
// bound, for ±∞ and for NaN.
//
// Method: reduce_half_pi, then by n mod 4: cos r, −sin r, −cos r, sin r.
fn cos_poly(x: real) -> real {
    let q = reduce_half_pi(x);
    let s = sin_kernel(q.hi, q.lo);
    let c = cos_kernel(q.hi, q.lo);
    let v = select(s, c, (q.n & 1) == 0);
    return select(-v, v, ((q.n + 1) & 2) == 0);
}

// acos x, in [0, π].
//
// Contract: ≤ 1 ulp from the correctly rounded value on [−1, 1] (tests/fmath.rs);
// acos 1 = +0, acos(−1) = π rounded, acos 0 = π/2 rounded; NaN outside [−1, 1] and for
// NaN.
//
// Method (fdlibm e_acos.c, with a mad where fdlibm splits a square root by its bits):
// - |x| < 1/2: acos x = π/2 − (x + x·R(x²)), π/2 as PIO2_HI + PIO2_LO;
// - x ≥ 1/2: acos x = 2·asin √z with z = (1 − x)/2 (exact): 2·(s + s·R(z) + c) with
//   s = √z rounded and c = (z − s²)/(2s) (z − s² by mad, to about an ulp of z), so s + c ≈ √z to about an ulp;
// - x ≤ −1/2: acos x = π − 2·asin √z with z = (1 + x)/2: π − 2·(s + s·R(z)).
//
// All three are computed and one is selected.
fn acos_poly(x: real) -> real {
    let ax = abs(x);
    let outer = ax >= 0.5;
    let z = select(x * x, (1.0 - ax) * 0.5, outer);
    let p = z * mad(
        z,
        mad(z, mad(z, mad(z, mad(z, ASIN_P5, ASIN_P4), ASIN_P3), ASIN_P2), ASIN_P1),
        ASIN_P0,
    );
    let q = mad(z, mad(z, mad(z, mad(z, ASIN_Q4, ASIN_Q3), ASIN_Q2), ASIN_Q1), 1.0);
    let r = p / q;
    let s = sqrt(z);
    let mid = PIO2_HI - (x - mad(-x, r, PIO2_LO));
    let c = mad(-s, s, z) / select(1.0, s + s, s > 0.0);
    let right = 2.0 * (s + mad(r, s, c));
    let left = PI_HI - 2.0 * (s + mad(r, s, -PIO2_LO));
    return select(select(left, right, x > 0.0), mid, !outer);
}

// ln x, for finite x ≥ 2⁻¹⁰²²: x = 2ᵏ·m with m in (√2/2, √2] by ten exact steps of
// 2^512 … 2, then fdlibm's ln m = f − s·(f − R(s²)), f = m − 1, s = f/(2 + f).
fn log_poly(x: real) -> real {
    var m = x;
    var k = 0;
    var p = pow2i(512);
    var e = 512;
    for (var i = 0; i < 10; i++) {
        // before this step 2^(1 − 2e) ≤ m < 2^(2e); after it 2^(1 − e) ≤ m < 2^e
        if m >= p {
            m = m / p;
            k = k + e;
        }
        if m < 2.0 / p {
            m = m * p;
            k = k - e;
        }
        p = sqrt(p);
        e = e >> 1u;
    }
    let big = m > SQRT2;
    let mr = select(m, m * 0.5, big);
    let kr = select(k, k + 1, big);
    let f = mr - 1.0;
    let s = f / (2.0 + f);
    let z = s * s;
    let w = z * z;
    let t1 = w * mad(w, mad(w, LOG_LG6, LOG_LG4), LOG_LG2);
    let t2 = z * mad(w, mad(w, mad(w, LOG_LG7, LOG_LG5), LOG_LG3), LOG_LG1);
    let r = t2 + t1;
    let dk = real(kr);
    return mad(dk, LN2_HI, -(mad(s, f - r, -(dk * LN2_LO)) - f));
}

// Φ⁻¹(p) for p in (0, 1): Wichura's AS 241 (PPND16). The central region returns early;
// of the tails both are computed and one is selected.
fn normal_quantile(p: real) -> real {
    let q = p - 0.5;
    let r = PPND_CONST1 - q * q;
    var a = mad(r, PPND_A7, PPND_A6);
    a = mad(r, a, PPND_A5);
    a = mad(r, a, PPND_A4);
    a = mad(r, a, PPND_A3);
    a = mad(r, a, PPND_A2);
    a = mad(r, a, PPND_A1);
    a = mad(r, a, PPND_A0);
    var b = mad(r, PPND_B7, PPND_B6);
    b = mad(r, b, PPND_B5);
    b = mad(r, b, PPND_B4);
    b = mad(r, b, PPND_B3);
    b = mad(r, b, PPND_B2);
    b = mad(r, b, PPND_B1);
    b = mad(r, b, 1.0);
    if abs(q) <= PPND_SPLIT1 {
        return q * (a / b);
    }
    // the smaller tail, exact: p itself below 1/2, 1 − p (Sterbenz) above
    let small = select(1.0 - p, p, q < 0.0);
    let t = sqrt(-log_poly(small));
    let u = t - PPND_CONST2;
    var c = mad(u, PPND_C7, PPND_C6);
    c = mad(u, c, PPND_C5);
    c = mad(u, c, PPND_C4);
    c = mad(u, c, PPND_C3);
    c = mad(u, c, PPND_C2);
    c = mad(u, c, PPND_C1);
    c = mad(u, c, PPND_C0);
    var d = mad(u, PPND_D7, PPND_D6);
    d = mad(u, d, PPND_D5);
    d = mad(u, d, PPND_D4);
    d = mad(u, d, PPND_D3);
    d = mad(u, d, PPND_D2);
    d = mad(u, d, PPND_D1);
    d = mad(u, d, 1.0);
    let v = t - PPND_SPLIT2;
    var e = mad(v, PPND_E7, PPND_E6);
    e = mad(v, e, PPND_E5);
    e = mad(v, e, PPND_E4);
    e = mad(v, e, PPND_E3);
    e = mad(v, e, PPND_E2);
    e = mad(v, e, PPND_E1);
    e = mad(v, e, PPND_E0);
    var f = mad(v, PPND_F7, PPND_F6);
    f = mad(v, f, PPND_F5);
    f = mad(v, f, PPND_F4);
    f = mad(v, f, PPND_F3);
    f = mad(v, f, PPND_F2);
    f = mad(v, f, PPND_F1);
    f = mad(v, f, 1.0);
    let size = select(e / f, c / d, t <= PPND_SPLIT2);
    return select(size, -size, q < 0.0);
}

// atan x, in [−π/2, π/2] (fdlibm s_atan.c): below 7/16 the odd polynomial, above it
// atan t = atan c + atan((t − c)/(1 + c·t)) for c = 1/2, 1, 3/2 or ∞, the sign last.
fn atan_poly(x: real) -> real {
    let ax = abs(x);
    var id = 3;
    if ax < 0.4375 {
        id = -1;
    } else if ax < 0.6875 {
        id = 0;
    } else if ax < 1.1875 {
        id = 1;
    } else if ax < 2.4375 {
        id = 2;
    }
    var t = -1.0 / ax;
    var hi = PIO2_HI;
    var lo = PIO2_LO;
    if id == -1 {
        t = ax;
    } else if id == 0 {
        t = mad(2.0, ax, -1.0) / (2.0 + ax);
        hi = ATAN_HI0;
        lo = ATAN_LO0;
    } else if id == 1 {
        t = (ax - 1.0) / (ax + 1.0);
        hi = ATAN_HI1;
        lo = ATAN_LO1;
    } else if id == 2 {
        t = (ax - 1.5) / mad(1.5, ax, 1.0);
        hi = ATAN_HI2;
        lo = ATAN_LO2;
    }
    let z = t * t;
    let w = z * z;
    let s1 = z * mad(
        w,
        mad(w, mad(w, mad(w, mad(w, ATAN_T10, ATAN_T8), ATAN_T6), ATAN_T4), ATAN_T2),
        ATAN_T0,
    );
    let s2 = w * mad(w, mad(w, mad(w, mad(w, ATAN_T9, ATAN_T7), ATAN_T5), ATAN_T3), ATAN_T1);
    let small = mad(-t, s1 + s2, t);
    let reduced = hi - (mad(t, s1 + s2, -lo) - t);
    var a = select(reduced, small, id < 0);
    a = select(a, PIO2_HI + PIO2_LO, ax >= ATAN_HUGE);
    let signed = select(a, -a, x < 0.0);
    return select(signed, x, ax < ATAN_TINY);
}

// atan2(y, x) in [−π, π] (fdlibm e_atan2.c): z = atan|y/x|, then by the signs z, −z,
// π − (z − π_lo), (z − π_lo) − π; ±π/2 on the y axis, +0 at the origin.
fn atan2_poly(y: real, x: real) -> real {
    let z = atan_poly(abs(y / x));
    let right = select(z, -z, y < 0.0);
    let left = select(PI_HI - (z - PI_LO), (z - PI_LO) - PI_HI, y < 0.0);
    let up = select(PIO2_HI, -PIO2_HI, y < 0.0);
    let on_axis = select(up, 0.0, y == 0.0);
    return select(select(on_axis, left, x < 0.0), right, x > 0.0);
}
