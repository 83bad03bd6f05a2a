//! The cue strike, pooltool's `instantaneous_point` model with squirt (spec §5.6;
//! `physics/resolve/stick_ball/instantaneous_point/__init__.py: cue_strike`,
//! `.../stick_ball/squirt.py: get_squirt_angle`).
//!
//! (a, b) is the contact point in the cue frame as a fraction of R (a: side, +1 leftmost;
//! b: +1 top); the tip radius is not used (Q11). The ball leaves sliding with
//! `v = 2V0/(1 + m/M + T/(I/m))` horizontally along φ (the vertical part `v sinθ` is
//! dropped), spin from the contact offset, and the velocity (not the spin) turned by the
//! squirt angle.
//!
//! The twin of `shaders/resolve/stick_ball.wgsl` (same functions, same order): the GPU
//! strikes a study's samples itself. The sines, cosines and the arctangent are
//! [`crate::model::fmath`]'s (within an ulp of the standard library's, and the shader's bit
//! for bit); the degrees become radians as `f64::to_radians` does (one product by π/180).

use crate::error::SimError;
use crate::model::MotionState;
use crate::model::ball_state::BallState;
use crate::model::fmath::{atan2_poly, cos_poly, sin_poly};
use crate::model::sim_params::{BallParams, CueParams};
use crate::model::vec3::Vec3;
use std::f64::consts::FRAC_PI_2;

/// π/180 rounded, `f64::to_radians`'s factor (0x3F91DF46_A2529D39).
const DEG_TO_RAD: f64 = std::f64::consts::PI / 180.0;
/// The largest |φ| in degrees a strike may have: its angle in radians stays within the
/// arithmetic sine's and cosine's range ([`crate::model::fmath::TRIG_BOUND`], 8·10⁵).
pub const MAX_PHI_DEGREES: f64 = 1.0e7;

/// A cue strike: pooltool's `Cue.set_state(V0, phi, theta, a, b)` arguments.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CueStrike {
    /// Cue speed in m/s.
    pub v0: f64,
    /// Aim direction in degrees, counter-clockwise from +x.
    pub phi: f64,
    /// Cue elevation in degrees.
    pub theta: f64,
    /// Side offset of the contact point, fraction of R.
    pub a: f64,
    /// Vertical offset of the contact point, fraction of R.
    pub b: f64,
}

impl CueStrike {
    /// Checks the strike: every number finite, V0 ≥ 0, |φ| ≤ [`MAX_PHI_DEGREES`],
    /// a² + b² ≤ 1 (pooltool gives NaN beyond, Q11).
    pub fn validate(&self) -> Result<(), SimError> {
        let s = self;
        if ![s.v0, s.phi, s.theta, s.a, s.b]
            .iter()
            .all(|x| x.is_finite())
        {
            return Err(SimError::Strike(format!("non-finite number in {s:?}")));
        }
        if s.v0 < 0.0 {
            return Err(SimError::Strike(format!("V0 = {} < 0", s.v0)));
        }
        if s.phi.abs() > MAX_PHI_DEGREES {
            return Err(SimError::Strike(format!(
                "|phi| = {} degrees > {MAX_PHI_DEGREES:e} (give the angle modulo 360)",
                s.phi.abs()
            )));
        }
        if s.a * s.a + s.b * s.b > 1.0 {
            return Err(SimError::Strike(format!(
                "a² + b² > 1 (a = {}, b = {})",
                s.a, s.b
            )));
        }
        Ok(())
    }
}

/// The squirt angle `α = −throttle·atan2(2.5 a √(1−a²), 1 + m/m_e + 2.5(1−a²))`.
pub fn squirt_angle(a: f64, p: &BallParams, cue: &CueParams) -> f64 {
    let ratio = p.m / cue.end_mass;
    let num = 2.5 * a * (1.0 - a * a).sqrt();
    let den = 1.0 + ratio + 2.5 * (1.0 - a * a);
    -cue.squirt_throttle * atan2_poly(num, den)
}

/// Speed and ball-frame spin of the strike (§5.6 steps 1–3): `(v, ω_B)`.
fn strike_ball_frame(s: &CueStrike, p: &BallParams, cue: &CueParams) -> (f64, Vec3) {
    let theta = s.theta * DEG_TO_RAD;
    let (st, ct) = (sin_poly(theta), cos_poly(theta));
    // clamped: for a tip on the ball's rim (a² + b² = 1, which validation accepts) the
    // difference can round below 0, and its root was NaN (pooltool's too): a NaN strike
    // and NaN event times (the `event_loop` fuzz target's finding 15, FUZZING.md)
    let c_cue = (1.0 - s.a * s.a - s.b * s.b).max(0.0).sqrt();
    let (a_b, c_b, b_b) = (s.a, ct * c_cue - st * s.b, st * c_cue + ct * s.b);
    let (qa, qc, qb) = (p.r * a_b, p.r * c_b, p.r * b_b);
    let i_m = 0.4 * p.r * p.r;
    let (qbc, qcs) = (qb * ct, qc * st);
    let t = qa * qa + qbc * qbc + qcs * qcs - 2.0 * qb * qc * ct * st;
    let v = 2.0 * s.v0 / (1.0 + p.m / cue.mass + t / i_m);
    let w = (v / i_m) * Vec3::new(-qc * st + qb * ct, qa * st, -qa * ct);
    (v, w)
}

/// The cue ball right after the strike (§5.6): position kept, labelled sliding.
pub fn cue_strike(ball: &BallState, s: &CueStrike, p: &BallParams, cue: &CueParams) -> BallState {
    let (v, w_b) = strike_ball_frame(s, p, cue);
    let theta = s.theta * DEG_TO_RAD;
    let rot = s.phi * DEG_TO_RAD + FRAC_PI_2;
    let v_b = Vec3::new(0.0, -v * cos_poly(theta), 0.0);
    let v_t = v_b.rotate_z(rot).rotate_z(squirt_angle(s.a, p, cue));
    let w_t = cue.english_throttle * w_b.rotate_z(rot);
    BallState {
        v: v_t,
        w: w_t,
        s: MotionState::Sliding,
        ..*ball
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(got: f64, want: f64) -> bool {
        (got - want).abs() <= 1e-12 * want.abs().max(1.0)
    }

    fn strike(v0: f64, phi: f64, theta: f64, a: f64, b: f64) -> BallState {
        let p = BallParams::default();
        let s = CueStrike {
            v0,
            phi,
            theta,
            a,
            b,
        };
        cue_strike(
            &BallState::at_rest(0.5, 0.5, p.r),
            &s,
            &p,
            &CueParams::default(),
        )
    }

    /// Spec §8, test vector A.
    #[test]
    fn vector_a() {
        let out = strike(2.0, 90.0, 0.0, 0.2, 0.3);
        for (got, want) in [
            (out.v.x, 0.036101103935539),
            (out.v.y, 2.461281732245495),
            (out.w.x, -64.60751906408932),
            (out.w.z, -43.07167937605954),
        ] {
            assert!(close(got, want), "{got} vs {want}");
        }
        assert!(out.w.y.abs() < 1e-13 && out.v.z == 0.0);
        assert_eq!(out.s, MotionState::Sliding);
    }

    /// Spec §8, test vector B.
    #[test]
    fn vector_b() {
        let out = strike(3.0, 30.0, 15.0, -0.3, -0.2);
        for (got, want) in [
            (out.v.x, 3.049638595493054),
            (out.v.y, 1.849236710711011),
            (out.w.x, 54.02582837347929),
            (out.w.y, -43.4105104920309),
            (out.w.z, 93.6091068547008),
        ] {
            assert!(close(got, want), "{got} vs {want}");
        }
    }

    #[test]
    fn bad_strikes_are_refused() {
        let ok = CueStrike {
            v0: 1.0,
            phi: 0.0,
            theta: 0.0,
            a: 0.0,
            b: 0.0,
        };
        assert!(ok.validate().is_ok());
        assert!(
            CueStrike {
                a: 0.8,
                b: 0.8,
                ..ok
            }
            .validate()
            .is_err()
        );
        assert!(CueStrike { v0: f64::NAN, ..ok }.validate().is_err());
    }
}
