//! Ball–pocket detection (spec §4.6; `evolution/event_based/solve.py:
//! ball_pocket_collision_coeffs`): the moment the ball's centre enters the pocket circle,
//! "the point of no return". The depth plays no part.

use crate::model::Vec2;
use crate::model::ball_state::BallState;
use crate::model::sim_params::BallParams;
use crate::model::table::Pocket;
use crate::motion::trajectory::trajectory;
use crate::query::ball_circle::circle_crossing;

/// τ until a translating ball's centre enters the circle of radius `r_p` (not `r_p ± R`)
/// about the pocket's centre (or, for a centre a kiss left inside it, leaves it: pooltool's
/// quartic does not ask which way), or `∞` (non-translating balls too). See
/// [`crate::query::ball_circle::circle_crossing`] for the method.
pub fn ball_pocket_time(b: &BallState, pocket: &Pocket, p: &BallParams) -> f64 {
    if !b.translating() {
        return f64::INFINITY;
    }
    let path = trajectory(b, p);
    let center = Vec2::new(pocket.center.x, pocket.center.y);
    circle_crossing(&path, center, pocket.radius)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::MotionState;
    use crate::model::table::Table;
    use crate::model::vec3::Vec3;

    #[test]
    fn centre_enters_the_pocket_circle() {
        let p = BallParams::default();
        let t = Table::nine_foot();
        let lc = &t.pockets[1];
        assert_eq!(t.pocket_ids[1], "lc");
        let b = BallState {
            v: Vec3::new(-3.0, 0.0, 0.0),
            s: MotionState::Sliding,
            ..BallState::at_rest(0.3, 1.27, p.r)
        };
        let tau = ball_pocket_time(&b, lc, &p);
        let k = 0.5 * 0.2 * 9.81;
        let gap = 0.3 - (lc.center.x + lc.radius);
        let expect = (3.0 - (9.0 - 4.0 * k * gap).sqrt()) / (2.0 * k);
        assert!((tau - expect).abs() < 1e-12, "{tau} {expect}");
        let still = BallState::at_rest(0.3, 1.27, p.r);
        assert_eq!(ball_pocket_time(&still, lc, &p), f64::INFINITY);
    }
}
