//! Ball–pocket resolution, pooltool's `canonical` model (spec §5.5;
//! `physics/resolve/ball_pocket/__init__.py`): the ball drops to the pocket's centre at
//! z = −depth, at rest, labelled pocketed. No rattle, no depth physics (Q15).

use crate::model::MotionState;
use crate::model::ball_state::BallState;
use crate::model::table::Pocket;
use crate::model::vec3::Vec3;

/// The ball after falling into `pocket`.
pub fn resolve_pocket(b: &BallState, pocket: &Pocket) -> BallState {
    BallState {
        r: Vec3::new(pocket.center.x, pocket.center.y, -pocket.depth),
        v: Vec3::ZERO,
        w: Vec3::ZERO,
        s: MotionState::Pocketed,
        ..*b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ball_rests_at_the_pocket_centre() {
        let pocket = Pocket {
            center: Vec3::new(-0.0685, 1.27, 0.0),
            radius: 0.0645,
            depth: 0.08,
        };
        let b = BallState {
            v: Vec3::new(-1.0, 0.0, 0.0),
            s: MotionState::Rolling,
            ..BallState::at_rest(-0.01, 1.27, 0.028575)
        };
        let out = resolve_pocket(&b, &pocket);
        assert_eq!(out.r, Vec3::new(-0.0685, 1.27, -0.08));
        assert_eq!(
            (out.v, out.w, out.s),
            (Vec3::ZERO, Vec3::ZERO, MotionState::Pocketed)
        );
    }
}
