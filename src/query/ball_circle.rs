//! When does a ball's path enter a fixed circle? The quartic of spec §4.5–4.6, shared by
//! the circular cushions (jaws) and the pockets.

use crate::model::Vec2;
use crate::motion::trajectory::Path;
use crate::query::ball_ball::{RelPath, first_entry};

/// The first τ in `(0, horizon]` at which the path enters the circle of radius `rho`
/// about `center` (`|p(τ) − q|²` goes from `> ρ²` to `≤ ρ²`), or `∞`.
///
/// This is the smallest positive root of pooltool's quartic (§4.5, §4.6) for a ball that
/// starts outside the circle, found by the crate's exact bracketing root finder
/// ([`crate::query::ball_ball::first_entry`]) instead of pooltool's Algorithm 1010 plus its root
/// filter (§4.2). They differ only for grazes within ~1e-17 m (pooltool's filter takes a
/// complex pair with |Im| < 1e-9 as a touch) and for a ball that starts inside the
/// circle (pooltool would report its exit; a table never starts a ball there).
pub fn circle_entry(path: &Path, center: Vec2, rho: f64) -> f64 {
    if !path.horizon.is_finite() {
        return f64::INFINITY;
    }
    let rel = RelPath {
        a: path.a,
        b: path.b,
        c: path.c - center,
    };
    let t = first_entry(&rel, rho * rho, path.horizon, false);
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
    fn rolling_path_and_circle_entry() {
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
        let t = circle_entry(&path, Vec2::new(0.6, 0.0), 0.1);
        let x = position_at(&path, t).x;
        assert!((x - 0.5).abs() < 1e-12, "{x}");
        // a circle off to the side is never entered
        assert_eq!(circle_entry(&path, Vec2::new(0.6, 0.5), 0.1), f64::INFINITY);
        // still balls have no path
        let still = trajectory(&BallState::at_rest(0.0, 0.0, p.r), &p);
        assert_eq!(
            circle_entry(&still, Vec2::new(0.0, 0.0), 1.0),
            f64::INFINITY
        );
    }
}
