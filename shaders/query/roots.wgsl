// Roots of quadratics: the building block of every "when does X happen" query. WGSL twin
// of src/query/roots.rs (same names, same order). No NaN or ∞: a missing root is −1.

// What a missing root or time is reported as inside the algorithms.
const NO_ROOT: real = -1.0;

struct Roots2 {
    n: u32,
    r0: real,
    r1: real,
}

// Stable formula; a = 0 falls back to the linear root; a double root is reported twice;
// 0 x² + 0 x + c has no roots.
fn quadratic_roots(a: real, b: real, c: real) -> Roots2 {
    if a == 0.0 {
        if b == 0.0 {
            return Roots2(0u, NO_ROOT, NO_ROOT);
        }
        return Roots2(1u, -c / b, NO_ROOT);
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return Roots2(0u, NO_ROOT, NO_ROOT);
    }
    var sign_b: real = 1.0;
    if b < 0.0 {
        sign_b = -1.0;
    }
    let q = -0.5 * (b + sign_b * sqrt(disc));
    if q == 0.0 {
        // b = 0 and disc = 0, so c = 0: a double root at 0
        return Roots2(2u, 0.0, 0.0);
    }
    let r0 = q / a;
    let r1 = c / q;
    if r0 <= r1 {
        return Roots2(2u, r0, r1);
    }
    return Roots2(2u, r1, r0);
}

// The smallest strictly positive root of a x² + b x + c, or −1 if it has none.
fn smallest_positive_root(a: real, b: real, c: real) -> real {
    let r = quadratic_roots(a, b, c);
    if r.n >= 1u && r.r0 > 0.0 {
        return r.r0;
    }
    if r.n == 2u && r.r1 > 0.0 {
        return r.r1;
    }
    return NO_ROOT;
}

// A make_kiss root (Rust: Option<f64>): `found`, and τ when found.
struct KissRoot {
    found: bool,
    tau: real,
}

// The make_kiss root choice shared by the ball–ball and circular-cushion spacers (spec
// §5.1, §5.3): of the roots of `A τ² + B τ + C = 0` whose imaginary part is below 1e-3 of
// their real part, the one with the smallest |τ|.
//
// That is: the root of `A τ² + B τ + C` with the smallest |τ| among the "real" ones (a
// complex pair counts, by its real part, when `|Im|/|Re| < 1e-3`), or none (`A = 0`, or no
// root passes). Real roots use the stable formula `q = −½(B + sign(B)√Δ)`, `q/A`, `C/q`.
// (The Rust twin also refuses non-finite coefficients; WGSL has no NaN or ∞ to test for,
// and the resolutions' inputs are finite.)
fn smallest_kiss_root(a: real, b: real, c: real) -> KissRoot {
    if a == 0.0 {
        return KissRoot(false, 0.0);
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        let re = -b / (2.0 * a);
        let im = sqrt(-disc) / (2.0 * a);
        if re != 0.0 && abs(im / re) < 1e-3 {
            return KissRoot(true, re);
        }
        return KissRoot(false, 0.0);
    }
    var sign: real = 1.0;
    if b < 0.0 {
        sign = -1.0;
    }
    let q = -0.5 * (b + sign * sqrt(disc));
    if q == 0.0 {
        return KissRoot(true, 0.0);
    }
    let r1 = q / a;
    let r2 = c / q;
    return KissRoot(true, select(r2, r1, abs(r1) <= abs(r2)));
}
