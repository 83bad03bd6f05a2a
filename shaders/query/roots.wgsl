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

