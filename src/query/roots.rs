//! Roots of quadratics: the building block of every "when does X happen" query.
//!
//! Both routines avoid NaN and ∞ (WGSL may assume neither exists): a missing root is
//! [`NO_ROOT`] (`−1`). The GPU twin of this file is `shaders/query/roots.wgsl`.

/// What a missing root or time is reported as inside the algorithms.
pub const NO_ROOT: f64 = -1.0;

/// Real roots of `a x² + b x + c`, ascending: `(count, r0, r1)`, missing roots `−1`.
///
/// The stable formula (`q = −½(b + sign(b)√disc)`, roots `q/a` and `c/q`) keeps both
/// roots accurate when `b² ≫ |ac|`, and `a = 0` falls back to the linear root, so a
/// vanishing leading coefficient needs no special case in the callers. A double root is
/// reported twice. `0 x² + 0 x + c` has no roots (also for `c = 0`).
pub fn quadratic_roots(a: f64, b: f64, c: f64) -> (u32, f64, f64) {
    if a == 0.0 {
        if b == 0.0 {
            return (0, NO_ROOT, NO_ROOT);
        }
        return (1, -c / b, NO_ROOT);
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return (0, NO_ROOT, NO_ROOT);
    }
    let sign_b = if b < 0.0 { -1.0 } else { 1.0 };
    let q = -0.5 * (b + sign_b * disc.sqrt());
    if q == 0.0 {
        // b = 0 and disc = 0, so c = 0: a double root at 0
        return (2, 0.0, 0.0);
    }
    let r0 = q / a;
    let r1 = c / q;
    if r0 <= r1 { (2, r0, r1) } else { (2, r1, r0) }
}

/// The smallest strictly positive root of `a x² + b x + c`, or `−1` if it has none.
pub fn smallest_positive_root(a: f64, b: f64, c: f64) -> f64 {
    let (n, r0, r1) = quadratic_roots(a, b, c);
    if n >= 1 && r0 > 0.0 {
        return r0;
    }
    if n == 2 && r1 > 0.0 {
        return r1;
    }
    NO_ROOT
}

/// The make_kiss root choice shared by the ball–ball and circular-cushion spacers (spec
/// §5.1, §5.3): of the roots of `A τ² + B τ + C = 0` whose imaginary part is below 1e-3 of
/// their real part, the one with the smallest |τ|.
///
/// That is: the root of `A τ² + B τ + C` with the smallest |τ| among the "real" ones (a complex
/// pair counts, by its real part, when `|Im|/|Re| < 1e-3`), or `None` (`A = 0`, or no
/// root passes). Real roots use the stable formula `q = −½(B + sign(B)√Δ)`, `q/A`, `C/q`.
pub fn smallest_kiss_root(a: f64, b: f64, c: f64) -> Option<f64> {
    if a == 0.0 || !(a.is_finite() && b.is_finite() && c.is_finite()) {
        return None;
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        let re = -b / (2.0 * a);
        let im = (-disc).sqrt() / (2.0 * a);
        return if re != 0.0 && (im / re).abs() < 1e-3 {
            Some(re)
        } else {
            None
        };
    }
    let sign = if b < 0.0 { -1.0 } else { 1.0 };
    let q = -0.5 * (b + sign * disc.sqrt());
    if q == 0.0 {
        return Some(0.0);
    }
    let (r1, r2) = (q / a, c / q);
    Some(if r1.abs() <= r2.abs() { r1 } else { r2 })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadratic_roots_edge_cases() {
        assert_eq!(quadratic_roots(1.0, -3.0, 2.0), (2, 1.0, 2.0));
        assert_eq!(quadratic_roots(0.0, 2.0, -4.0), (1, 2.0, NO_ROOT));
        assert_eq!(quadratic_roots(0.0, 0.0, 1.0).0, 0);
        assert_eq!(quadratic_roots(0.0, 0.0, 0.0).0, 0);
        assert_eq!(quadratic_roots(1.0, 0.0, 1.0).0, 0);
        assert_eq!(quadratic_roots(1.0, 0.0, 0.0), (2, 0.0, 0.0));
        // b² ≫ 4ac: the small root keeps full relative accuracy
        let (n, r0, r1) = quadratic_roots(1.0, -1e8, 1.0);
        assert_eq!(n, 2);
        assert!((r0 - 1e-8).abs() < 1e-22, "{r0}");
        assert!((r1 - 1e8).abs() < 1e-6);
        // a tiny leading coefficient: one root near −c/b, the other far away
        let (n, r0, r1) = quadratic_roots(1e-300, 2.0, -4.0);
        assert_eq!(n, 2);
        assert!(r0 < -1e299 && (r1 - 2.0).abs() < 1e-15);
    }

    #[test]
    fn smallest_positive_root_skips_negative_and_missing() {
        assert_eq!(smallest_positive_root(1.0, -3.0, 2.0), 1.0);
        assert_eq!(smallest_positive_root(1.0, 1.0, -2.0), 1.0);
        assert_eq!(smallest_positive_root(1.0, 3.0, 2.0), NO_ROOT);
        assert_eq!(smallest_positive_root(1.0, 0.0, 1.0), NO_ROOT);
    }

    #[test]
    fn picks_the_root_nearest_zero() {
        // (τ + 1e-6)(τ − 3) = τ² − (3 − 1e-6) τ − 3e-6
        let t = smallest_kiss_root(1.0, -(3.0 - 1e-6), -3e-6).unwrap();
        assert!((t + 1e-6).abs() < 1e-20, "{t}");
        assert_eq!(smallest_kiss_root(0.0, 1.0, 1.0), None);
        // a clearly complex pair is refused
        assert_eq!(smallest_kiss_root(1.0, 0.0, 1.0), None);
        // a nearly double complex pair counts by its real part
        let t = smallest_kiss_root(1.0, -2.0, 1.0 + 1e-10).unwrap();
        assert_eq!(t, 1.0);
    }
}
