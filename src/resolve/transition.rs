//! Transition resolution (spec §2.7 / §5.7; `physics/resolve/transition/__init__.py:
//! CanonicalTransition`).
//!
//! - sliding → rolling: only the label changes;
//! - rolling → spinning: v = 0 and ω_x = ω_y = 0, ω_z kept;
//! - rolling → stationary, spinning → stationary: v = ω = 0.
//!
//! Deviation (Q12): pooltool asserts that the zeroed components are already below 1e-12;
//! here they are zeroed whatever their size, so a rounding excess never stops a table.

use crate::model::MotionState;
use crate::model::ball_state::BallState;
use crate::model::vec3::Vec3;
use crate::motion::evolve::TransitionKind;

/// The ball after transition `kind` (module docs). Position and reference time are kept;
/// the caller stamps the time.
pub fn resolve_transition(b: &BallState, kind: TransitionKind) -> BallState {
    match kind {
        TransitionKind::SlidingRolling => BallState {
            s: MotionState::Rolling,
            ..*b
        },
        TransitionKind::RollingSpinning => BallState {
            v: Vec3::ZERO,
            w: Vec3::new(0.0, 0.0, b.w.z),
            s: MotionState::Spinning,
            ..*b
        },
        TransitionKind::RollingStationary | TransitionKind::SpinningStationary => BallState {
            v: Vec3::ZERO,
            w: Vec3::ZERO,
            s: MotionState::Stationary,
            ..*b
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transitions_set_labels_and_zero_components() {
        let b = BallState {
            v: Vec3::new(1e-17, 0.0, 0.0),
            w: Vec3::new(1e-16, 2e-16, 4.0),
            s: MotionState::Rolling,
            ..BallState::at_rest(0.1, 0.2, 0.028575)
        };
        let s = resolve_transition(&b, TransitionKind::RollingSpinning);
        assert_eq!(
            (s.s, s.v, s.w),
            (MotionState::Spinning, Vec3::ZERO, Vec3::new(0.0, 0.0, 4.0))
        );
        let r = resolve_transition(&b, TransitionKind::SlidingRolling);
        assert_eq!((r.s, r.v, r.w), (MotionState::Rolling, b.v, b.w));
        let st = resolve_transition(&s, TransitionKind::SpinningStationary);
        assert_eq!(
            (st.s, st.w, st.r),
            (MotionState::Stationary, Vec3::ZERO, b.r)
        );
    }
}
