//! Motion between events: pooltool's closed forms (spec §2; `physics/evolve/__init__.py`:
//! `evolve_ball_motion`, `_evolve_slide_state`, `_evolve_roll_state`,
//! `_evolve_perpendicular_spin_*`; `ptmath/utils.py`: `get_slide_time`, `get_roll_time`,
//! `get_spin_time`).
//!
//! τ is the time since the state given. z and v_z never change. The label is never
//! changed here: only transition events change labels (§2.5), so [`evolve`] chains the
//! states internally only to absorb rounding at a transition time.

use crate::model::MotionState;
use crate::model::ball_state::{BallState, rel_velocity};
use crate::model::sim_params::{BallParams, EPS};
use crate::model::vec3::Vec3;

/// The z-spin after τ (§2): it decays at α_sp towards 0 and never passes it; unchanged
/// for τ = 0 or |ω_z| < EPS.
pub fn decay_spin_z(wz: f64, tau: f64, p: &BallParams) -> f64 {
    if tau == 0.0 || wz.abs() < EPS {
        return wz;
    }
    let alpha = p.spin_decel();
    let sign = if wz > 0.0 { 1.0 } else { -1.0 };
    wz - sign * alpha * tau.min(wz.abs() / alpha)
}

/// τ_slide = 2|u_rel|/(7 μ_s g) (§2.1): when the cloth slip of a sliding ball vanishes.
pub fn slide_time(b: &BallState, p: &BallParams) -> f64 {
    let u = rel_velocity(b.v, b.w, p.r);
    2.0 * u.norm() / (7.0 * p.u_s * p.g)
}

/// τ_roll = |v|/(μ_r g) (§2.2): when a rolling ball stops.
pub fn roll_time(b: &BallState, p: &BallParams) -> f64 {
    b.v.norm() / (p.u_r * p.g)
}

/// τ_spin = |ω_z|/α_sp = 2R|ω_z|/(5 μ_sp g) (§2.3): when a spinning ball stops spinning.
pub fn spin_time(b: &BallState, p: &BallParams) -> f64 {
    b.w.z.abs() * 2.0 * p.r / (5.0 * p.u_sp * p.g)
}

/// A sliding ball after τ (§2.1): constant deceleration μ_s g against the slip direction
/// û, spin changed by the friction torque, z-spin decaying. Valid for τ ≤ τ_slide.
pub fn evolve_slide(b: &BallState, tau: f64, p: &BallParams) -> BallState {
    let u_hat = rel_velocity(b.v, b.w, p.r).xy().unit();
    let k = p.u_s * p.g;
    let r = b.r + tau * b.v - (0.5 * k * tau * tau) * u_hat;
    let v = b.v - (k * tau) * u_hat;
    // û × ẑ = (û_y, −û_x, 0)
    let dw = (5.0 * k * tau / (2.0 * p.r)) * Vec3::new(u_hat.y, -u_hat.x, 0.0);
    let w = Vec3::new(b.w.x - dw.x, b.w.y - dw.y, decay_spin_z(b.w.z, tau, p));
    BallState {
        r: Vec3::new(r.x, r.y, b.r.z),
        v: Vec3::new(v.x, v.y, b.v.z),
        w,
        ..*b
    }
}

/// A rolling ball after τ (§2.2): deceleration μ_r g along v̂, ω_xy recomputed from v
/// (Q13), z-spin decaying. τ = 0 returns the state untouched. Valid for τ ≤ τ_roll.
pub fn evolve_roll(b: &BallState, tau: f64, p: &BallParams) -> BallState {
    if tau == 0.0 {
        return *b;
    }
    let v_hat = b.v.xy().unit();
    let k = p.u_r * p.g;
    let r = b.r + tau * b.v - (0.5 * k * tau * tau) * v_hat;
    let v = b.v - (k * tau) * v_hat;
    let w = Vec3::new(-v.y / p.r, v.x / p.r, decay_spin_z(b.w.z, tau, p));
    BallState {
        r: Vec3::new(r.x, r.y, b.r.z),
        v: Vec3::new(v.x, v.y, b.v.z),
        w,
        ..*b
    }
}

/// A spinning ball after τ (§2.3): only ω_z changes (decays).
pub fn evolve_spin(b: &BallState, tau: f64, p: &BallParams) -> BallState {
    let w = Vec3::new(b.w.x, b.w.y, decay_spin_z(b.w.z, tau, p));
    BallState { w, ..*b }
}

/// Rolling, then spinning, then at rest, for τ (the tail of §2.5's chain).
fn evolve_from_roll(b: &BallState, tau: f64, p: &BallParams) -> BallState {
    let t_roll = roll_time(b, p);
    if tau < t_roll {
        return evolve_roll(b, tau, p);
    }
    let rolled = evolve_roll(b, t_roll, p);
    evolve_from_spin(&rolled, tau - t_roll, p)
}

/// Spinning, then at rest, for τ.
fn evolve_from_spin(b: &BallState, tau: f64, p: &BallParams) -> BallState {
    let t_spin = spin_time(b, p);
    evolve_spin(b, tau.min(t_spin), p)
}

/// `evolve_ball_motion` (§2.5): the state after τ, chaining slide → roll → spin → rest
/// through the states reached (each duration recomputed from the intermediate state).
/// The label of `b` is kept. Stationary and pocketed balls do not change.
pub fn evolve(b: &BallState, tau: f64, p: &BallParams) -> BallState {
    match b.s {
        MotionState::Sliding => {
            let t_slide = slide_time(b, p);
            if tau < t_slide {
                return evolve_slide(b, tau, p);
            }
            let slid = evolve_slide(b, t_slide, p);
            evolve_from_roll(&slid, tau - t_slide, p)
        }
        MotionState::Rolling => evolve_from_roll(b, tau, p),
        MotionState::Spinning => evolve_from_spin(b, tau, p),
        MotionState::Stationary | MotionState::Pocketed => *b,
    }
}

/// The transitions a ball's motion can end in (§2.6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TransitionKind {
    /// sliding → rolling.
    SlidingRolling,
    /// rolling → spinning.
    RollingSpinning,
    /// rolling → stationary.
    RollingStationary,
    /// spinning → stationary.
    SpinningStationary,
}

/// The ball's next transition as `(τ, kind)` from its current state (§2.6,
/// `evolution/event_based/cache.py: _next_transition`), or `None` for stationary and
/// pocketed balls. A rolling ball spins next only if τ_spin > τ_roll (strictly).
pub fn next_transition(b: &BallState, p: &BallParams) -> Option<(f64, TransitionKind)> {
    match b.s {
        MotionState::Sliding => Some((slide_time(b, p), TransitionKind::SlidingRolling)),
        MotionState::Rolling => {
            let (t_roll, t_spin) = (roll_time(b, p), spin_time(b, p));
            let kind = if t_spin > t_roll {
                TransitionKind::RollingSpinning
            } else {
                TransitionKind::RollingStationary
            };
            Some((t_roll, kind))
        }
        MotionState::Spinning => Some((spin_time(b, p), TransitionKind::SpinningStationary)),
        MotionState::Stationary | MotionState::Pocketed => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> BallParams {
        BallParams::default()
    }

    fn sliding(v: Vec3, w: Vec3) -> BallState {
        BallState {
            v,
            w,
            s: MotionState::Sliding,
            ..BallState::at_rest(0.5, 0.5, p().r)
        }
    }

    #[test]
    fn slide_ends_with_zero_slip() {
        let b = sliding(Vec3::new(1.0, 0.5, 0.0), Vec3::new(3.0, -20.0, 7.0));
        let t = slide_time(&b, &p());
        let end = evolve_slide(&b, t, &p());
        assert!(rel_velocity(end.v, end.w, p().r).norm() < 1e-14);
        assert_eq!(end.r.z, b.r.z);
    }

    #[test]
    fn stun_slide_matches_the_closed_form() {
        let b = sliding(Vec3::new(2.0, 0.0, 0.0), Vec3::ZERO);
        let tau = 0.1;
        let e = evolve_slide(&b, tau, &p());
        let k = 0.2 * 9.81;
        assert!((e.v.x - (2.0 - k * tau)).abs() < 1e-15);
        assert!((e.r.x - (0.5 + 2.0 * tau - 0.5 * k * tau * tau)).abs() < 1e-15);
        // friction rolls the ball forward: ω_y grows positive
        assert!((e.w.y - 5.0 * k * tau / (2.0 * p().r)).abs() < 1e-12);
    }

    #[test]
    fn roll_stops_and_spin_decays_without_crossing_zero() {
        let r = p().r;
        let b = BallState {
            v: Vec3::new(0.0, 1.0, 0.0),
            w: Vec3::new(-1.0 / r, 0.0, 50.0),
            s: MotionState::Rolling,
            ..BallState::at_rest(0.5, 0.5, r)
        };
        let t = roll_time(&b, &p());
        assert!((t - 1.0 / (0.01 * 9.81)).abs() < 1e-12);
        let end = evolve_roll(&b, t, &p());
        assert!(end.v.norm() < 1e-15 && end.w.x.abs() < 1e-13);
        // ω_z: 50 rad/s at 10.9 rad/s² lasts 4.59 s < t_roll
        let alpha = p().spin_decel();
        assert_eq!(end.w.z, 50.0 - alpha * (50.0 / alpha));
        assert_eq!(
            next_transition(&b, &p()).unwrap().1,
            TransitionKind::RollingStationary
        );
        assert_eq!(evolve_roll(&b, 0.0, &p()), b);
    }

    #[test]
    fn chaining_passes_through_every_state() {
        let b = sliding(Vec3::new(0.3, 0.0, 0.0), Vec3::new(0.0, 0.0, 60.0));
        let end = evolve(&b, 100.0, &p());
        assert_eq!(end.s, MotionState::Sliding, "the label is kept");
        assert!(end.v.norm() < 1e-15 && end.w.z.abs() < 1e-12);
        let kinds = next_transition(&evolve(&b, slide_time(&b, &p()), &p()), &p());
        assert!(kinds.is_some());
    }

    #[test]
    fn next_transitions_by_state() {
        let r = p().r;
        let spin = BallState {
            w: Vec3::new(0.0, 0.0, -21.8),
            s: MotionState::Spinning,
            ..BallState::at_rest(0.5, 0.5, r)
        };
        let (t, k) = next_transition(&spin, &p()).unwrap();
        assert!((t - 2.0).abs() < 1e-14);
        assert_eq!(k, TransitionKind::SpinningStationary);
        let fast_spin = BallState {
            v: Vec3::new(0.01, 0.0, 0.0),
            w: Vec3::new(0.0, 0.01 / r, 30.0),
            s: MotionState::Rolling,
            ..spin
        };
        assert_eq!(
            next_transition(&fast_spin, &p()).unwrap().1,
            TransitionKind::RollingSpinning
        );
        assert!(next_transition(&BallState::at_rest(0.0, 0.0, r), &p()).is_none());
    }
}
