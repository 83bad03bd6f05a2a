// Stronge's compliant frictional collinear impact, in closed form in the time domain
// (spec §5.4; `physics/resolve/stronge_compliant.py:
// resolve_collinear_compliant_frictional_inelastic_collision`). WGSL twin of
// src/resolve/stronge.rs: the same functions in the same order with the same comments.
// Differences, all forced by WGSL: no closures (the functions whose roots are found are
// named functions, stick_slip_f and slip_stick_slip_g, and bracketed_root takes a RootFn:
// which of them, and what they capture in Rust), methods as functions (`Clock::new` is
// `clock_new`), a real2 instead of a tuple, sin/cos/acos from the precision prelude
// (real_sin, real_cos, real_acos).
//
// Given the contact point's initial tangential and normal velocities (v_t0 ≤ 0,
// v_n0 < 0), the final ones. With ρ = β_t/β_n, r = v_t0/v_n0, ω_n = √(β_n k_n/m),
// ω_t = ω_n √(ρ/η²), t_c = π/(2ω_n), t_f = (1+e) t_c, σ = (π/2)(1 − 1/e) and the
// restitution phase φ_R(t) = ω_n t/e + σ, three regimes by the branch boundaries
// L = μη², M = μρ, H = μ[(1+e)ρ − η²/e]: gross slip (r > H), stick–slip (r < L),
// slip–stick–slip (L ≤ r ≤ H).
//
// Method note: pooltool finds the slip-resumption time with scipy's `toms748`
// (xtol 2e-12); here bisection runs to adjacent floats, which is at least as close to
// the exact root (bracketed_root). Deviation (Q8): pooltool asserts the stick-onset
// cosine lies in [−1, 1] (it fails at r = H exactly); here it is clamped.
//
// Needs (before it): the precision prelude (and, for f64, model/fmath.wgsl).

// π (Rust: std::f64::consts::PI; named for this file, as WGSL has one namespace).
const STRONGE_PI: real = 3.141592653589793;

// The constants of one Stronge solve.
struct StrongeConsts {
    // Friction coefficient μ (the cushion's f_c).
    mu: real,
    // Normal restitution e (the cushion's e_c).
    e: real,
    // η² = (β_t/β_n)/omega_ratio².
    eta2: real,
    // Tangential compliance factor β_t.
    beta_t: real,
    // Normal compliance factor β_n.
    beta_n: real,
    // Normal stiffness k_n (N/m).
    k_n: real,
    // Ball mass m (kg).
    m: real,
}

// numpy's `isclose(a, b)` with its defaults: `|a − b| ≤ 1e-8 + 1e-5 |b|`.
fn isclose(a: real, b: real) -> bool {
    return abs(a - b) <= 1e-8 + 1e-5 * abs(b);
}

// Which function bracketed_root finds a root of (Rust: the closure it is given).
// stick_slip's f.
const ROOT_STICK_SLIP: u32 = 0u;
// slip_stick_slip's g.
const ROOT_SLIP_STICK_SLIP: u32 = 1u;

// A function of t for bracketed_root: its code (ROOT_*) and what the Rust closure
// captures (r for f; v_n0 and the stick-onset state t_st, u_st, v_st for g).
struct RootFn {
    code: u32,
    k: StrongeConsts,
    c: Clock,
    r: real,
    v_n0: real,
    t_st: real,
    u_st: real,
    v_st: real,
}

// WGSL only: the value at t of the function `f` stands for (Rust: calling the closure).
fn root_fn_at(f: RootFn, t: real) -> real {
    if f.code == ROOT_STICK_SLIP {
        return stick_slip_f(f.r, f.k, f.c, t);
    }
    return slip_stick_slip_g(f.v_n0, f.t_st, f.u_st, f.v_st, f.k, f.c, t);
}

// A root of `f` on `[lo, hi]` by bisection to adjacent floats (at most 200 halvings).
// When `f(lo)` and `f(hi)` have the same sign (scipy would raise), the end with the
// smaller |f|.
//
// Bisection rather than a faster secant: the slip–stick–slip function touches zero
// from below at the stick onset (a double root inside the bracket), where a
// regula-falsi iteration creeps and can stop; bisection, like `toms748` (whose bracket
// at least halves every iteration), converges to the sign change.
fn bracketed_root(f: RootFn, lo: real, hi: real) -> real {
    var a = lo;
    var b = hi;
    let fa = root_fn_at(f, a);
    let fb = root_fn_at(f, b);
    if fa == 0.0 {
        return a;
    }
    if fb == 0.0 {
        return b;
    }
    if (fa > 0.0) == (fb > 0.0) {
        return select(b, a, abs(fa) <= abs(fb));
    }
    let a_positive = fa > 0.0;
    for (var i = 0u; i < 200u; i++) {
        let c = 0.5 * (a + b);
        if c <= a || c >= b {
            break;
        }
        let fc = root_fn_at(f, c);
        if fc == 0.0 {
            return c;
        }
        if (fc > 0.0) == a_positive {
            a = c;
        } else {
            b = c;
        }
    }
    return 0.5 * (a + b);
}

// The times and frequencies shared by the regimes.
struct Clock {
    w_n: real,
    w_t: real,
    t_c: real,
    t_f: real,
    sigma: real,
    rho: real,
}

// (Rust: Clock::new.)
fn clock_new(k: StrongeConsts) -> Clock {
    let rho = k.beta_t / k.beta_n;
    let w_n = sqrt(k.beta_n * k.k_n / k.m);
    let t_c = STRONGE_PI / (2.0 * w_n);
    return Clock(
        w_n,
        w_n * sqrt(rho / k.eta2),
        t_c,
        (1.0 + k.e) * t_c,
        (STRONGE_PI / 2.0) * (1.0 - 1.0 / k.e),
        rho,
    );
}

// The restitution phase φ_R(t) = ω_n t/e + σ (Rust: Clock::phase).
fn clock_phase(c: Clock, t: real, e: real) -> real {
    return c.w_n * t / e + c.sigma;
}

// WGSL only: stick_slip's closure f, whose root on [t_c, t_f] is t_s.
fn stick_slip_f(r: real, k: StrongeConsts, c: Clock, t: real) -> real {
    return abs(r * real_sin(c.w_t * t)) - k.mu * k.eta2 * (c.w_t / c.w_n) * real_sin(clock_phase(c, t, k.e));
}

// (B) stick–slip, r < L: v_t,f after sticking resumes slip at t_s.
fn stick_slip(r: real, v_t0: real, v_n0: real, k: StrongeConsts, c: Clock) -> real {
    let big_l = k.mu * k.eta2;
    var t_s: real;
    if isclose(r, 0.0) {
        t_s = c.t_f;
    } else if isclose(r, big_l) {
        t_s = c.t_c;
    } else {
        let f = RootFn(ROOT_STICK_SLIP, k, c, r, 0.0, 0.0, 0.0, 0.0);
        t_s = bracketed_root(f, c.t_c, c.t_f);
    }
    return v_t0 * real_cos(c.w_t * t_s) + k.mu * v_n0 * c.rho * k.e * (1.0 + real_cos(clock_phase(c, t_s, k.e)));
}

// WGSL only: slip_stick_slip's closure g, whose root on [t_c, t_f] is t_s.
fn slip_stick_slip_g(
    v_n0: real,
    t_st: real,
    u_st: real,
    v_st: real,
    k: StrongeConsts,
    c: Clock,
    t: real,
) -> real {
    let d = c.w_t * (t - t_st);
    let inner = u_st * real_cos(d) - (v_st / c.w_t) * real_sin(d);
    return abs((c.w_n / (k.mu * v_n0)) * inner) - k.eta2 * real_sin(clock_phase(c, t, k.e));
}

// (C) slip–stick–slip, L ≤ r ≤ H: stick onset t_st, the state there, slip again at t_s.
fn slip_stick_slip(r: real, v_t0: real, v_n0: real, k: StrongeConsts, c: Clock) -> real {
    let mu = k.mu;
    let e = k.e;
    let eta2 = k.eta2;
    let rho = c.rho;
    var tau_star: real;
    if r <= mu * rho {
        let x = clamp((r / mu - rho) / (eta2 - rho), -1.0, 1.0);
        tau_star = (2.0 / STRONGE_PI) * real_acos(x);
    } else {
        let x = clamp((r / mu - rho) / (eta2 / e - e * rho), -1.0, 1.0);
        tau_star = (2.0 / STRONGE_PI) * (real_acos(x) - c.sigma) * e;
    }
    let t_st = c.t_c * tau_star;
    var u_st: real;
    var v_st: real;
    if t_st <= c.t_c {
        u_st = -mu * v_n0 * eta2 / c.w_n * real_sin(c.w_n * t_st);
        v_st = v_t0 - mu * rho * v_n0 * (1.0 - real_cos(c.w_n * t_st));
    } else {
        u_st = -mu * v_n0 * eta2 / c.w_n * real_sin(clock_phase(c, t_st, e));
        v_st = v_t0 - mu * rho * v_n0 * (1.0 - e * real_cos(clock_phase(c, t_st, e)));
    }
    let big_h = mu * ((1.0 + e) * rho - eta2 / e);
    var t_s: real;
    if isclose(r, mu * eta2) {
        t_s = c.t_c;
    } else if isclose(r, big_h) {
        t_s = c.t_f;
    } else {
        let g = RootFn(ROOT_SLIP_STICK_SLIP, k, c, r, v_n0, t_st, u_st, v_st);
        t_s = bracketed_root(g, c.t_c, c.t_f);
    }
    let d = c.w_t * (t_s - t_st);
    return c.w_t * u_st * real_sin(d) + v_st * real_cos(d) + rho * mu * v_n0 * e * (1.0 + real_cos(clock_phase(c, t_s, e)));
}

// The final contact-point velocities `(v_t,f, v_n,f)` from `(v_t0, v_n0)` (module
// docs), as real2(v_t,f, v_n,f). `v_n0` must be negative (approaching); the caller checks.
fn stronge_compliant(v_t0: real, v_n0: real, k: StrongeConsts) -> real2 {
    let c = clock_new(k);
    let r = v_t0 / v_n0;
    let big_l = k.mu * k.eta2;
    let big_h = k.mu * ((1.0 + k.e) * c.rho - k.eta2 / k.e);
    var v_tf: real;
    if r > big_h {
        v_tf = v_t0 - k.mu * v_n0 * c.rho * (1.0 + k.e);
    } else if r < big_l {
        v_tf = stick_slip(r, v_t0, v_n0, k, c);
    } else {
        v_tf = slip_stick_slip(r, v_t0, v_n0, k, c);
    }
    let v_nf = k.e * v_n0 * real_cos(clock_phase(c, c.t_f, k.e));
    return real2(v_tf, v_nf);
}
