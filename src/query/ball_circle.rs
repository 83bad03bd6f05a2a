//! When does a ball's path cross a fixed circle? The quartic of spec §4.5–4.6, shared by
//! the circular cushions (jaws) and the pockets.

use crate::model::Vec2;
use crate::motion::trajectory::Path;
use crate::query::ball_ball::{RelPath, contact_fn, first_entry, first_exit};

/// The first τ in `(0, horizon]` at which the path crosses the circle of radius `rho`
/// about `center`, or `∞`: where it starts outside (`|p(0) − q|² ≥ ρ²`), the first entry
/// (`|p(τ) − q|²` goes from `> ρ²` to `≤ ρ²`); where it starts inside, the first exit.
///
/// This is the smallest positive root of pooltool's quartic (§4.5, §4.6), whose detection
/// does not ask which way the path crosses, found by the crate's exact bracketing root
/// finders ([`crate::query::ball_ball::first_entry`], [`crate::query::ball_ball::first_exit`])
/// instead of pooltool's Algorithm 1010 plus its root filter (§4.2). They differ only for
/// grazes within ~1e-17 m (pooltool's filter takes a complex pair with |Im| < 1e-9 as a
/// touch). A table never starts a ball inside a pocket's circle, but a shot can leave one
/// there: a cushion's kiss (Q1) that ends a rounding error inside the circle. pooltool then
/// pockets the ball where its path leaves the circle, and so does this (FUZZING.md,
/// finding 32).
pub fn circle_crossing(path: &Path, center: Vec2, rho: f64) -> f64 {
    if !path.horizon.is_finite() {
        return f64::INFINITY;
    }
    let rel = RelPath {
        a: path.a,
        b: path.b,
        c: path.c - center,
    };
    let rho2 = rho * rho;
    let (f0, _, _) = contact_fn(&rel, rho2, 0.0, 0);
    let t = if f0 < 0.0 {
        first_exit(&rel, rho2, path.horizon)
    } else {
        first_entry(&rel, rho2, path.horizon, false)
    };
    if t >= 0.0 { t } else { f64::INFINITY }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::MotionState;
    use crate::model::ball_state::BallState;
    use crate::model::sim_params::BallParams;
    use crate::model::vec3::Vec3;
    use crate::motion::trajectory::{position_at, trajectory};

    #[test]
    fn rolling_path_and_circle_crossing() {
        let p = BallParams::default();
        let b = BallState {
            v: Vec3::new(1.0, 0.0, 0.0),
            w: Vec3::new(0.0, 1.0 / p.r, 0.0),
            s: MotionState::Rolling,
            ..BallState::at_rest(0.0, 0.0, p.r)
        };
        let path = trajectory(&b, &p);
        assert!((path.a.x + 0.5 * 0.01 * 9.81).abs() < 1e-16);
        // a circle of radius 0.1 centred 0.6 m ahead: entered after 0.5 m of travel
        let t = circle_crossing(&path, Vec2::new(0.6, 0.0), 0.1);
        let x = position_at(&path, t).x;
        assert!((x - 0.5).abs() < 1e-12, "{x}");
        // a circle off to the side is never entered
        assert_eq!(
            circle_crossing(&path, Vec2::new(0.6, 0.5), 0.1),
            f64::INFINITY
        );
        // still balls have no path
        let still = trajectory(&BallState::at_rest(0.0, 0.0, p.r), &p);
        assert_eq!(
            circle_crossing(&still, Vec2::new(0.0, 0.0), 1.0),
            f64::INFINITY
        );
    }
}
