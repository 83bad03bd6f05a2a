//! The arithmetic-only `exp`, `sin`, `cos`, `acos`, `atan`, `atan2`, `ln` and normal quantile (`src/model/fmath.rs`, twins of
//! `shaders/model/fmath.wgsl`) against the standard library, over the ranges the physics
//! uses and beyond, dense where they are hard: the error bound each one documents, in ulps,
//! and the special values.
//!
//! The reference is Rust's `f64` methods (glibc's libm on Linux, itself within 1 ulp of
//! the correctly rounded value); the error is counted in ulps as the distance between the
//! two results' positions on the line of doubles (`f64::to_bits`), so a subnormal result
//! counts in subnormal ulps and +0 / −0 are the same point.

mod common;

use std::f64::consts::{FRAC_PI_2, PI};

use common::rng::TestRng;

use kisstime::model::fmath::{
    HalfPiRem, LOG_ULPS, TRIG_BOUND, acos_poly, atan_poly, atan2_poly, cos_poly, exp_poly,
    log_poly, normal_quantile, pow2i, reduce_half_pi, sin_poly,
};

/// The documented bounds (ulps against the standard library).
const EXP_ULPS: u64 = 1;
const SIN_COS_ULPS: u64 = 1;
const ACOS_ULPS: u64 = 1;

/// A double's position on the ordered line of doubles: adjacent doubles differ by 1, and
/// +0 and −0 are both 0.
fn ordinal(x: f64) -> i64 {
    let bits = x.to_bits() as i64;
    if bits < 0 { -(bits & i64::MAX) } else { bits }
}

/// How many ulps apart `a` and `b` are (0 when both are NaN; `u64::MAX` when one is).
fn ulps(a: f64, b: f64) -> u64 {
    match (a.is_nan(), b.is_nan()) {
        (true, true) => 0,
        (false, false) => (ordinal(a) - ordinal(b)).unsigned_abs(),
        _ => u64::MAX,
    }
}

/// `n` ulps away from `x` (negative `n`: downwards).
fn step(x: f64, n: i64) -> f64 {
    let o = ordinal(x) + n;
    if o < 0 {
        -f64::from_bits((-o) as u64)
    } else {
        f64::from_bits(o as u64)
    }
}

/// The worst error of `f` against `reference` over `xs`: (ulps, at x, f(x), reference(x)).
struct Worst {
    ulps: u64,
    x: f64,
    got: f64,
    want: f64,
    count: usize,
    /// How many differ from the reference at all.
    off: usize,
}

fn worst(
    xs: impl IntoIterator<Item = f64>,
    f: impl Fn(f64) -> f64,
    reference: impl Fn(f64) -> f64,
) -> Worst {
    let mut w = Worst {
        ulps: 0,
        x: f64::NAN,
        got: f64::NAN,
        want: f64::NAN,
        count: 0,
        off: 0,
    };
    for x in xs {
        let (got, want) = (f(x), reference(x));
        let u = ulps(got, want);
        w.count += 1;
        w.off += usize::from(u > 0);
        if u > w.ulps || w.x.is_nan() {
            w = Worst {
                ulps: u,
                x,
                got,
                want,
                ..w
            };
        }
    }
    w
}

fn check(name: &str, range: &str, w: &Worst, bound: u64) {
    println!(
        "{name} on {range}: {} points, {} differ from std, max {} ulp (x = {:e}: {:e} vs std {:e})",
        w.count, w.off, w.ulps, w.x, w.got, w.want
    );
    assert!(
        w.ulps <= bound,
        "{name} on {range}: {} ulp > {bound} at x = {:e} ({:?}): got {:e} ({:#018x}), std {:e} ({:#018x})",
        w.ulps,
        w.x,
        w.x,
        w.got,
        w.got.to_bits(),
        w.want,
        w.want.to_bits()
    );
}

#[test]
fn the_ulp_helper_counts_doubles() {
    assert_eq!(ulps(1.0, 1.0), 0);
    assert_eq!(ulps(1.0, 1.0 + f64::EPSILON), 1);
    assert_eq!(ulps(0.0, -0.0), 0);
    assert_eq!(ulps(f64::from_bits(1), -f64::from_bits(1)), 2);
    assert_eq!(ulps(f64::MAX, f64::INFINITY), 1);
    assert_eq!(ulps(f64::NAN, f64::NAN), 0);
    assert_eq!(ulps(f64::NAN, 1.0), u64::MAX);
    assert_eq!(step(1.0, 1), 1.0 + f64::EPSILON);
    assert_eq!(step(f64::from_bits(1), -2), -f64::from_bits(1));
}

#[test]
fn pow2i_is_exact_over_its_range() {
    for n in -1023..=1023 {
        let want = if n >= -1022 {
            f64::from_bits(((n + 1023) as u64) << 52)
        } else {
            f64::from_bits(1u64 << (n + 1074))
        };
        assert_eq!(pow2i(n).to_bits(), want.to_bits(), "2^{n}");
    }
}

#[test]
fn exp_within_its_bound() {
    let mut rng = TestRng::new(0x0E49);
    let cases: [(&str, Vec<f64>); 6] = [
        (
            "[-745, 0] (the physics: -c·|slip|)",
            (0..1_000_000).map(|_| rng.range(-745.0, 0.0)).collect(),
        ),
        (
            "[-1, 1]",
            (0..200_000).map(|_| rng.range(-1.0, 1.0)).collect(),
        ),
        (
            "(0, 709.7]",
            (0..200_000).map(|_| rng.range(0.0, 709.7)).collect(),
        ),
        (
            "|x| in [1e-300, 1e-3]",
            (0..100_000).map(|_| rng.log_signed(-300.0, -3.0)).collect(),
        ),
        (
            "[-745.13, -708] (subnormal results)",
            (0..100_000).map(|_| rng.range(-745.13, -708.0)).collect(),
        ),
        (
            "(k + 1/2)·ln 2 ± 4 ulp (where k's rounding flips)",
            (-1075..1024)
                .flat_map(|k| {
                    let x = (k as f64 + 0.5) * std::f64::consts::LN_2;
                    (-4..=4).map(move |d| step(x, d))
                })
                .filter(|x| (-745.13..709.7).contains(x))
                .collect(),
        ),
    ];
    for (range, xs) in cases {
        check("exp", range, &worst(xs, exp_poly, f64::exp), EXP_ULPS);
    }
}

#[test]
fn exp_special_values() {
    assert_eq!(exp_poly(0.0).to_bits(), 1f64.to_bits());
    assert_eq!(exp_poly(-0.0).to_bits(), 1f64.to_bits());
    assert!(exp_poly(f64::NAN).is_nan());
    assert_eq!(exp_poly(f64::INFINITY), f64::INFINITY);
    assert_eq!(exp_poly(f64::NEG_INFINITY).to_bits(), 0);
    for x in [710.0, 709.79, 750.0, 760.5, 1e4, 1e300, f64::MAX] {
        assert_eq!(exp_poly(x), f64::INFINITY, "exp({x}) overflows");
    }
    assert!(exp_poly(709.78).is_finite());
    for x in [-745.2, -746.0, -746.5, -760.5, -1e4, -1e300, f64::MIN] {
        assert_eq!(exp_poly(x).to_bits(), 0, "exp({x}) underflows to +0");
    }
    // the smallest subnormal, and the edge of the normal range
    assert_eq!(exp_poly(-745.0), (-745f64).exp());
    assert_eq!(exp_poly(-708.4), (-708.4f64).exp());
    assert!(ulps(exp_poly(1.0), std::f64::consts::E) <= EXP_ULPS);
    assert!(ulps(exp_poly(-1.0), 1.0 / std::f64::consts::E) <= EXP_ULPS);
    // tiny arguments: 1 + x
    assert_eq!(exp_poly(1e-20), 1.0);
    assert_eq!(exp_poly(-1e-20), 1.0);
    assert_eq!(exp_poly(f64::from_bits(1)), 1.0);
}

#[test]
fn sin_and_cos_within_their_bound() {
    let mut rng = TestRng::new(0x51C0);
    // the doubles nearest to multiples of π/2, where sin or cos is tiny, and their
    // neighbours: all of them up to 2·10⁴ quadrants, then a random sample up to the bound
    let near_zeros = |j: f64| {
        let x = j * FRAC_PI_2;
        (-3..=3).map(move |d| step(x, d))
    };
    let max_j = (TRIG_BOUND / FRAC_PI_2).floor();
    let cases: [(&str, Vec<f64>); 6] = [
        (
            "[-1e4, 1e4]",
            (0..1_000_000).map(|_| rng.range(-1e4, 1e4)).collect(),
        ),
        (
            "[-2π, 2π] (the physics: Stronge's phases)",
            (0..300_000)
                .map(|_| rng.range(-2.0 * PI, 2.0 * PI))
                .collect(),
        ),
        (
            "|x| in [1e-300, 1]",
            (0..100_000).map(|_| rng.log_signed(-300.0, 0.0)).collect(),
        ),
        (
            "j·π/2 ± 3 ulp, |j| ≤ 20000",
            (-20_000..=20_000)
                .flat_map(|j| near_zeros(j as f64))
                .collect(),
        ),
        (
            "j·π/2 ± 3 ulp, random |j| up to the bound",
            (0..20_000)
                .flat_map(|_| {
                    let j = (rng.unit() * max_j).floor();
                    near_zeros(if rng.coin() { j } else { -j })
                })
                .filter(|x| x.abs() <= TRIG_BOUND)
                .collect(),
        ),
        (
            "1e4 ≤ |x| ≤ TRIG_BOUND",
            (0..200_000)
                .map(|_| {
                    let x = rng.range(1e4, TRIG_BOUND);
                    if rng.coin() { x } else { -x }
                })
                .collect(),
        ),
    ];
    for (range, xs) in cases {
        check(
            "sin",
            range,
            &worst(xs.iter().copied(), sin_poly, f64::sin),
            SIN_COS_ULPS,
        );
        check(
            "cos",
            range,
            &worst(xs.iter().copied(), cos_poly, f64::cos),
            SIN_COS_ULPS,
        );
    }
}

#[test]
fn the_reduction_is_a_double_double() {
    // x = 1 is in quadrant 1, remainder 1 − π/2 (hi rounded, lo its tail)
    let HalfPiRem { n, hi, lo } = reduce_half_pi(1.0);
    assert_eq!(n, 1);
    assert!(ulps(hi, 1.0 - FRAC_PI_2) <= 1, "{hi}");
    assert!(lo.abs() <= 0.5 * ulps_size(hi), "{lo}");
    // a double next to a multiple of π/2: the remainder is tiny and keeps its bits
    let x = 1000.0 * FRAC_PI_2;
    let q = reduce_half_pi(x);
    assert_eq!(q.n, 1000);
    assert!(q.hi.abs() < 1e-12 && q.hi != 0.0, "{q:?}");
    assert!(q.lo.abs() <= 0.5 * ulps_size(q.hi));
    // |hi| stays within π/4 (and a little) however n was rounded
    for x in [
        FRAC_PI_2 / 2.0,
        step(FRAC_PI_2 / 2.0, 1),
        3.0 * FRAC_PI_2 / 2.0,
        -5.0 * FRAC_PI_2 / 2.0,
    ] {
        let q = reduce_half_pi(x);
        assert!(q.hi.abs() <= FRAC_PI_2 / 2.0 + 1e-15, "{x}: {q:?}");
    }
}

/// The size of one ulp at `x`.
fn ulps_size(x: f64) -> f64 {
    (step(x.abs(), 1) - x.abs()).abs()
}

#[test]
fn sin_and_cos_special_values() {
    assert_eq!(sin_poly(0.0).to_bits(), 0f64.to_bits());
    assert_eq!(sin_poly(-0.0).to_bits(), (-0f64).to_bits());
    assert_eq!(cos_poly(0.0), 1.0);
    assert_eq!(cos_poly(-0.0), 1.0);
    for x in [1e-10, -1e-10, f64::from_bits(1), -f64::MIN_POSITIVE] {
        assert_eq!(sin_poly(x), x, "sin x = x for tiny x");
        assert_eq!(cos_poly(x), 1.0, "cos x = 1 for tiny x");
    }
    for x in [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        step(TRIG_BOUND, 1),
        -step(TRIG_BOUND, 1),
        1e6,
        1e300,
    ] {
        assert!(sin_poly(x).is_nan(), "sin({x}) is NaN");
        assert!(cos_poly(x).is_nan(), "cos({x}) is NaN");
    }
    assert!(sin_poly(TRIG_BOUND).is_finite() && cos_poly(TRIG_BOUND).is_finite());
    // the quadrant signs
    for (x, s, c) in [
        (FRAC_PI_2, 1.0, 0.0),
        (PI, 0.0, -1.0),
        (3.0 * FRAC_PI_2, -1.0, 0.0),
        (2.0 * PI, 0.0, 1.0),
        (-FRAC_PI_2, -1.0, 0.0),
        (-PI, 0.0, -1.0),
    ] {
        assert!((sin_poly(x) - s).abs() < 1e-15, "sin({x})");
        assert!((cos_poly(x) - c).abs() < 1e-15, "cos({x})");
        assert!(ulps(sin_poly(x), x.sin()) <= SIN_COS_ULPS);
        assert!(ulps(cos_poly(x), x.cos()) <= SIN_COS_ULPS);
    }
}

#[test]
fn acos_within_its_bound() {
    let mut rng = TestRng::new(0xAC05);
    let near = |to: f64, rng: &mut TestRng| {
        // to − sign(to)·10^u: distances from 1e-16 to 0.5
        let d = 10f64.powf(rng.range(-16.5, -0.3));
        to - to.signum() * d
    };
    let cases: [(&str, Vec<f64>); 5] = [
        (
            "[-1, 1]",
            (0..1_000_000).map(|_| rng.range(-1.0, 1.0)).collect(),
        ),
        (
            "near ±1 (1e-16 .. 0.5 from it)",
            (0..200_000)
                .map(|i| near(if i % 2 == 0 { 1.0 } else { -1.0 }, &mut rng))
                .collect(),
        ),
        (
            "the last 64 doubles below 1 and above -1",
            (1..=64)
                .flat_map(|d| [step(1.0, -d), step(-1.0, d)])
                .collect(),
        ),
        (
            "±1/2 ± 1e-6 (where the method changes)",
            (0..100_000)
                .map(|i| {
                    let c = if i % 2 == 0 { 0.5 } else { -0.5 };
                    c + rng.range(-1e-6, 1e-6)
                })
                .collect(),
        ),
        (
            "|x| in [1e-300, 1e-3]",
            (0..50_000).map(|_| rng.log_signed(-300.0, -3.0)).collect(),
        ),
    ];
    for (range, xs) in cases {
        check("acos", range, &worst(xs, acos_poly, f64::acos), ACOS_ULPS);
    }
}

#[test]
fn acos_special_values() {
    assert_eq!(acos_poly(1.0).to_bits(), 0f64.to_bits());
    assert_eq!(acos_poly(-1.0), PI);
    assert_eq!(acos_poly(0.0), FRAC_PI_2);
    assert_eq!(acos_poly(-0.0), FRAC_PI_2);
    assert!(ulps(acos_poly(0.5), PI / 3.0) <= ACOS_ULPS);
    assert!(ulps(acos_poly(-0.5), 2.0 * PI / 3.0) <= ACOS_ULPS);
    for x in [
        step(1.0, 1),
        step(-1.0, -1),
        2.0,
        -2.0,
        1e300,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
    ] {
        assert!(acos_poly(x).is_nan(), "acos({x}) is NaN");
    }
}

#[test]
fn the_std_constants_are_the_wgsl_literals() {
    // src/model/fmath.rs uses std::f64::consts where shaders/model/fmath.wgsl writes
    // the literal: the same bits
    let wgsl = include_str!("../shaders/model/fmath.wgsl");
    for (name, value) in [
        ("INV_LN2", std::f64::consts::LOG2_E),
        ("INV_PIO2", std::f64::consts::FRAC_2_PI),
        ("PI_HI", PI),
        ("PIO2_HI", FRAC_PI_2),
        ("SQRT2", std::f64::consts::SQRT_2),
        ("ATAN_HI1", std::f64::consts::FRAC_PI_4),
    ] {
        let decl = format!("const {name}: real = ");
        let line = wgsl
            .lines()
            .find_map(|l| l.strip_prefix(&decl))
            .unwrap_or_else(|| panic!("{name} in the WGSL twin"));
        let literal: f64 = line.trim_end_matches(';').parse().unwrap();
        assert_eq!(literal.to_bits(), value.to_bits(), "{name}");
    }
}

#[test]
fn log_within_its_bound() {
    let mut rng = TestRng::new(0x106);
    let cases: [(&str, Vec<f64>); 5] = [
        (
            "[2^-53, 1/2] (the normal quantile's tails)",
            (0..1_000_000)
                .map(|_| 2f64.powf(rng.range(-53.0, -1.0)))
                .collect(),
        ),
        (
            "[1/2, 2]",
            (0..300_000).map(|_| rng.range(0.5, 2.0)).collect(),
        ),
        (
            "[2^-1022, 2^1023] by exponent",
            (0..300_000)
                .map(|_| 2f64.powf(rng.range(-1022.0, 1023.0)))
                .collect(),
        ),
        (
            "1 ± 2^-20 (ln near 0)",
            (0..100_000)
                .map(|_| 1.0 + rng.range(-1.0, 1.0) * 2f64.powi(-20))
                .collect(),
        ),
        (
            "√2·2^k ± 4 ulp (where the reduction flips)",
            (-1020..1020)
                .flat_map(|k| {
                    let x = std::f64::consts::SQRT_2 * 2f64.powi(k);
                    (-4..=4).map(move |d| step(x, d))
                })
                .collect(),
        ),
    ];
    for (range, xs) in cases {
        check("ln", range, &worst(xs, log_poly, f64::ln), LOG_ULPS);
    }
    // powers of two and the extremes exactly where the reference is exact
    assert_eq!(log_poly(1.0).to_bits(), 0f64.to_bits());
    for k in [-1022, -53, -1, 1, 2, 1023] {
        let x = 2f64.powi(k);
        assert!(ulps(log_poly(x), f64::ln(x)) <= LOG_ULPS, "ln 2^{k}");
    }
    assert!(ulps(log_poly(f64::MAX), f64::MAX.ln()) <= LOG_ULPS);
    assert!(ulps(log_poly(f64::MIN_POSITIVE), f64::MIN_POSITIVE.ln()) <= LOG_ULPS);
}

#[test]
fn the_normal_quantile_gives_known_quantiles() {
    // Φ⁻¹(p) to 16+ digits (mpmath, 40 digits: √2·erfinv(2p − 1))
    let known = [
        (0.5, 0.0f64),
        (0.975, 1.9599639845400538),
        (0.999, 3.090232306167813),
        (0.9, 1.2815515655446006),
        (0.6, 0.2533471031357997),
        (0.3, -0.5244005127080408),
        (0.075, -1.439531470938456),
        (0.02, -2.053748910631823),
        (1e-5, -4.264890793922825),
        (1e-10, -6.361340902404057),
        (1e-20, -9.262340089798407),
        (2f64.powi(-53), -8.209536151601387),
    ];
    for (p, want) in known {
        let got = normal_quantile(p);
        let tol = 1e-15 * want.abs().max(1.0);
        assert!(
            (got - want).abs() <= tol,
            "Φ⁻¹({p:e}) = {got:e}, want {want:e} (off {:e})",
            got - want
        );
    }
    // antisymmetric where 1 − p is exact, and increasing over a fine grid across the
    // three regions' boundaries
    let mut rng = TestRng::new(0x9A55);
    for _ in 0..100_000 {
        let p = rng.range(0.5, 1.0);
        let lo = 1.0 - p;
        assert_eq!(
            normal_quantile(lo).to_bits(),
            (-normal_quantile(p)).to_bits(),
            "p = {p:e}"
        );
    }
    let mut last = f64::NEG_INFINITY;
    for i in 1..200_000u32 {
        let p = f64::from(i) / 200_000.0;
        let x = normal_quantile(p);
        assert!(x > last, "Φ⁻¹ increases at p = {p}: {x} after {last}");
        last = x;
    }
    // across the regions' boundaries (|p − 1/2| = 0.425; r = 5 at p = e⁻²⁵) the
    // quantile's step between neighbouring p is the true step within four ulps (AS 241's
    // rational functions are accurate to a few ulps, and its regions meet within that)
    for split in [0.075, 0.925, (-25f64).exp()] {
        for d in -50..=50 {
            let (p, q) = (step(split, d), step(split, d + 1));
            let (x, y) = (normal_quantile(p), normal_quantile(q));
            // the true step: (q − p)/φ(x)
            let phi = (-0.5 * x * x).exp() / (2.0 * PI).sqrt();
            let off = (y - x) - (q - p) / phi;
            assert!(
                off.abs() <= 4.0 * f64::EPSILON * x.abs(),
                "at {p:e}: {x:e} then {y:e}"
            );
        }
    }
}

#[test]
fn atan_and_atan2_within_their_bounds() {
    let mut rng = TestRng::new(0xA7A2);
    let cases: [(&str, Vec<f64>); 4] = [
        (
            "[-3, 3]",
            (0..500_000).map(|_| rng.range(-3.0, 3.0)).collect(),
        ),
        (
            "|x| in [1e-12, 1e22]",
            (0..300_000).map(|_| rng.log_signed(-12.0, 22.0)).collect(),
        ),
        (
            "the reduction's edges 7/16, 11/16, 19/16, 39/16 ± 4 ulp",
            [
                0.4375,
                0.6875,
                1.1875,
                2.4375,
                2f64.powi(-27),
                2f64.powi(66),
            ]
            .iter()
            .flat_map(|&x| (-4..=4).flat_map(move |d| [step(x, d), -step(x, d)]))
            .collect(),
        ),
        (
            "the squirt's quotients (|a| < 1)",
            (0..200_000)
                .map(|_| {
                    let a: f64 = rng.range(-1.0, 1.0);
                    2.5 * a * (1.0 - a * a).sqrt() / (1.0 + 0.1 + 2.5 * (1.0 - a * a))
                })
                .collect(),
        ),
    ];
    for (range, xs) in cases {
        check("atan", range, &worst(xs, atan_poly, f64::atan), 1);
    }
    for x in [0.0, -0.0, 1e-300, -1e-300] {
        assert_eq!(atan_poly(x).to_bits(), x.to_bits(), "atan({x:e})");
    }
    assert_eq!(atan_poly(f64::INFINITY), FRAC_PI_2);
    assert_eq!(atan_poly(f64::NEG_INFINITY), -FRAC_PI_2);
    assert!(atan_poly(f64::NAN).is_nan());

    // atan2 over the four quadrants: the quotient's rounding, then atan
    let mut pairs = Vec::new();
    for _ in 0..400_000 {
        pairs.push((rng.log_signed(-6.0, 6.0), rng.log_signed(-6.0, 6.0)));
    }
    let (mut bad, mut most) = (None, 0);
    for &(y, x) in &pairs {
        let u = ulps(atan2_poly(y, x), y.atan2(x));
        if u > most {
            most = u;
            bad = Some((y, x));
        }
    }
    println!("atan2: {} points, max {most} ulp at {bad:?}", pairs.len());
    assert!(most <= 2, "atan2 {most} ulp at {bad:?}");
    for (y, x, want) in [
        (0.0, 1.0, 0.0),
        (-0.0, 1.0, 0.0),
        (1.0, 0.0, FRAC_PI_2),
        (-1.0, 0.0, -FRAC_PI_2),
        (0.0, 0.0, 0.0),
        (0.0, -1.0, PI),
        (1.0, -1.0, 0.75 * PI),
        (-1.0, -1.0, -0.75 * PI),
    ] {
        assert_eq!(
            atan2_poly(y, x).to_bits(),
            want.to_bits(),
            "atan2({y}, {x})"
        );
    }
}
