//! Stronge's compliant frictional collinear impact, in closed form in the time domain
//! (spec §5.4; `physics/resolve/stronge_compliant.py:
//! resolve_collinear_compliant_frictional_inelastic_collision`).
//!
//! Given the contact point's initial tangential and normal velocities (v_t0 ≤ 0,
//! v_n0 < 0), the final ones. With ρ = β_t/β_n, r = v_t0/v_n0, ω_n = √(β_n k_n/m),
//! ω_t = ω_n √(ρ/η²), t_c = π/(2ω_n), t_f = (1+e) t_c, σ = (π/2)(1 − 1/e) and the
//! restitution phase φ_R(t) = ω_n t/e + σ, three regimes by the branch boundaries
//! L = μη², M = μρ, H = μ[(1+e)ρ − η²/e]: gross slip (r > H), stick–slip (r < L),
//! slip–stick–slip (L ≤ r ≤ H).
//!
//! sin, cos and acos are [`crate::model::fmath`]'s (≤ 1 ulp), the shader's, so that the
//! CPU and the GPU give the same bits.
//!
//! Method note: pooltool finds the slip-resumption time with scipy's `toms748`
//! (xtol 2e-12); here bisection runs to adjacent floats, which is at least as close to
//! the exact root ([`bracketed_root`]). Deviation (Q8): pooltool asserts the stick-onset
//! cosine lies in [−1, 1] (it fails at r = H exactly); here it is clamped.

use std::f64::consts::PI;

use crate::model::fmath::{acos_poly, cos_poly, sin_poly};

/// The constants of one Stronge solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrongeConsts {
    /// Friction coefficient μ (the cushion's f_c).
    pub mu: f64,
    /// Normal restitution e (the cushion's e_c).
    pub e: f64,
    /// η² = (β_t/β_n)/omega_ratio².
    pub eta2: f64,
    /// Tangential compliance factor β_t.
    pub beta_t: f64,
    /// Normal compliance factor β_n.
    pub beta_n: f64,
    /// Normal stiffness k_n (N/m).
    pub k_n: f64,
    /// Ball mass m (kg).
    pub m: f64,
}

/// numpy's `isclose(a, b)` with its defaults: `|a − b| ≤ 1e-8 + 1e-5 |b|`.
pub fn isclose(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-8 + 1e-5 * b.abs()
}

/// A root of `f` on `[lo, hi]` by bisection to adjacent floats (at most 200 halvings).
/// When `f(lo)` and `f(hi)` have the same sign (scipy would raise), the end with the
/// smaller |f|.
///
/// Bisection rather than a faster secant: the slip–stick–slip function touches zero
/// from below at the stick onset (a double root inside the bracket), where a
/// regula-falsi iteration creeps and can stop; bisection, like `toms748` (whose bracket
/// at least halves every iteration), converges to the sign change.
pub fn bracketed_root(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    let (mut a, mut b) = (lo, hi);
    let (fa, fb) = (f(a), f(b));
    if fa == 0.0 {
        return a;
    }
    if fb == 0.0 {
        return b;
    }
    if (fa > 0.0) == (fb > 0.0) {
        return if fa.abs() <= fb.abs() { a } else { b };
    }
    let a_positive = fa > 0.0;
    for _ in 0..200 {
        let c = 0.5 * (a + b);
        if c <= a || c >= b {
            break;
        }
        let fc = f(c);
        if fc == 0.0 {
            return c;
        }
        if (fc > 0.0) == a_positive {
            a = c;
        } else {
            b = c;
        }
    }
    0.5 * (a + b)
}

/// The times and frequencies shared by the regimes.
struct Clock {
    w_n: f64,
    w_t: f64,
    t_c: f64,
    t_f: f64,
    sigma: f64,
    rho: f64,
}

impl Clock {
    fn new(k: &StrongeConsts) -> Clock {
        let rho = k.beta_t / k.beta_n;
        let w_n = (k.beta_n * k.k_n / k.m).sqrt();
        let t_c = PI / (2.0 * w_n);
        Clock {
            w_n,
            w_t: w_n * (rho / k.eta2).sqrt(),
            t_c,
            t_f: (1.0 + k.e) * t_c,
            sigma: (PI / 2.0) * (1.0 - 1.0 / k.e),
            rho,
        }
    }

    /// The restitution phase φ_R(t) = ω_n t/e + σ.
    fn phase(&self, t: f64, e: f64) -> f64 {
        self.w_n * t / e + self.sigma
    }
}

/// (B) stick–slip, r < L: v_t,f after sticking resumes slip at t_s.
fn stick_slip(r: f64, v_t0: f64, v_n0: f64, k: &StrongeConsts, c: &Clock) -> f64 {
    let big_l = k.mu * k.eta2;
    let t_s = if isclose(r, 0.0) {
        c.t_f
    } else if isclose(r, big_l) {
        c.t_c
    } else {
        let f = |t: f64| {
            (r * sin_poly(c.w_t * t)).abs()
                - k.mu * k.eta2 * (c.w_t / c.w_n) * sin_poly(c.phase(t, k.e))
        };
        bracketed_root(f, c.t_c, c.t_f)
    };
    v_t0 * cos_poly(c.w_t * t_s) + k.mu * v_n0 * c.rho * k.e * (1.0 + cos_poly(c.phase(t_s, k.e)))
}

/// (C) slip–stick–slip, L ≤ r ≤ H: stick onset t_st, the state there, slip again at t_s.
fn slip_stick_slip(r: f64, v_t0: f64, v_n0: f64, k: &StrongeConsts, c: &Clock) -> f64 {
    let (mu, e, eta2, rho) = (k.mu, k.e, k.eta2, c.rho);
    let tau_star = if r <= mu * rho {
        let x = ((r / mu - rho) / (eta2 - rho)).clamp(-1.0, 1.0);
        (2.0 / PI) * acos_poly(x)
    } else {
        let x = ((r / mu - rho) / (eta2 / e - e * rho)).clamp(-1.0, 1.0);
        (2.0 / PI) * (acos_poly(x) - c.sigma) * e
    };
    let t_st = c.t_c * tau_star;
    let (u_st, v_st) = if t_st <= c.t_c {
        (
            -mu * v_n0 * eta2 / c.w_n * sin_poly(c.w_n * t_st),
            v_t0 - mu * rho * v_n0 * (1.0 - cos_poly(c.w_n * t_st)),
        )
    } else {
        (
            -mu * v_n0 * eta2 / c.w_n * sin_poly(c.phase(t_st, e)),
            v_t0 - mu * rho * v_n0 * (1.0 - e * cos_poly(c.phase(t_st, e))),
        )
    };
    let big_h = mu * ((1.0 + e) * rho - eta2 / e);
    let t_s = if isclose(r, mu * eta2) {
        c.t_c
    } else if isclose(r, big_h) {
        c.t_f
    } else {
        let g = |t: f64| {
            let d = c.w_t * (t - t_st);
            let inner = u_st * cos_poly(d) - (v_st / c.w_t) * sin_poly(d);
            ((c.w_n / (mu * v_n0)) * inner).abs() - eta2 * sin_poly(c.phase(t, e))
        };
        bracketed_root(g, c.t_c, c.t_f)
    };
    let d = c.w_t * (t_s - t_st);
    c.w_t * u_st * sin_poly(d)
        + v_st * cos_poly(d)
        + rho * mu * v_n0 * e * (1.0 + cos_poly(c.phase(t_s, e)))
}

/// The final contact-point velocities `(v_t,f, v_n,f)` from `(v_t0, v_n0)` (module
/// docs). `v_n0` must be negative (approaching); the caller checks.
pub fn stronge_compliant(v_t0: f64, v_n0: f64, k: &StrongeConsts) -> (f64, f64) {
    let c = Clock::new(k);
    let r = v_t0 / v_n0;
    let big_l = k.mu * k.eta2;
    let big_h = k.mu * ((1.0 + k.e) * c.rho - k.eta2 / k.e);
    let v_tf = if r > big_h {
        v_t0 - k.mu * v_n0 * c.rho * (1.0 + k.e)
    } else if r < big_l {
        stick_slip(r, v_t0, v_n0, k, &c)
    } else {
        slip_stick_slip(r, v_t0, v_n0, k, &c)
    };
    let v_nf = k.e * v_n0 * cos_poly(c.phase(c.t_f, k.e));
    (v_tf, v_nf)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn consts() -> StrongeConsts {
        StrongeConsts {
            mu: 0.2,
            e: 0.85,
            eta2: 3.5 / (1.8 * 1.8),
            beta_t: 3.5,
            beta_n: 1.0,
            k_n: 1000.0,
            m: 0.170097,
        }
    }

    #[test]
    fn normal_restitution_and_gross_slip() {
        let (vt, vn) = stronge_compliant(-2.0, -1.0, &consts());
        assert!((vn - 0.85).abs() < 1e-15);
        assert!((vt - (-2.0 + 0.2 * 3.5 * 1.85)).abs() < 1e-15);
    }

    #[test]
    fn continuous_across_the_middle_branches() {
        // away from pooltool's isclose bands the tangential result is continuous in r
        let k = consts();
        let mut last: Option<f64> = None;
        for i in 1..=1300 {
            let r = i as f64 * 1e-3;
            let (vt, _) = stronge_compliant(-r, -1.0, &k);
            assert!(vt.is_finite());
            if let Some(prev) = last {
                let near_band = (r - 0.216049).abs() < 3e-3
                    || (r - 0.7).abs() < 3e-3
                    || (r - 1.0408).abs() < 3e-3;
                if !near_band {
                    assert!((vt - prev).abs() < 0.02, "r = {r}: {prev} → {vt}");
                }
            }
            last = Some(vt);
        }
    }

    #[test]
    fn root_finder_hits_the_root() {
        let t = bracketed_root(|t| t * t - 2.0, 0.0, 2.0);
        assert!((t - 2f64.sqrt()).abs() < 1e-15);
        assert_eq!(bracketed_root(|t| t + 1.0, 0.0, 1.0), 0.0);
    }
}
