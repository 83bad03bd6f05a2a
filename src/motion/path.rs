//! One ball's path between two events.
//!
//! Between events every ball that moves follows a quadratic path
//! `r(t) = c + b t + a t²` until its next motion transition (the derivation is in
//! `docs/reference/quartic-derivation.txt`, read with its `ERRATA.md`):
//!
//! | state                    | `a` (half the acceleration)          | `b`   | motion time `tmax`   |
//! |--------------------------|--------------------------------------|-------|----------------------|
//! | `sliding`                | `−½ μs g û`, `û = u/|u|`             | `v`   | `2|u| / (7 μs g)`     |
//! | `rolling`                | `−½ μr g v̂`, `v̂ = v/|v|`             | `v`   | `|v| / (μr g)`        |
//! | `stationary`, `spinning` | `0`                                  | `0`   | `∞`                  |
//! | `pocketed`               | never collides                       |       | `∞`                  |
//!
//! with `u = (vx − R wy, vy + R wx)` the velocity of the contact point with the cloth
//! (`u = v + R ẑ × ω`). The sliding and rolling rows are the worksheet's rotated-frame
//! coefficients rotated back to the table frame, so no trigonometry is needed (erratum 3).
//! A spinning ball's spin decays (with `μsp`) but it does not move, so for collisions its
//! motion time is infinite.
//!
//! The GPU twin of this file is `shaders/motion/path.wgsl` (in f32 and f64).

use crate::model::{Ball, MotionState, Params, Vec2, norm};

/// Path flag: the ball moves across the cloth on this path.
pub const PATH_MOVES: u32 = 1;
/// Path flag: the ball is pocketed and never collides.
pub const PATH_POCKETED: u32 = 2;

/// One ball's centre on its current motion, `r(t) = c + b t + a t²`, valid for
/// `t ∈ [0, tmax]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BallPath {
    /// Half the acceleration.
    pub a: Vec2,
    /// Velocity at `t = 0`.
    pub b: Vec2,
    /// Position at `t = 0`.
    pub c: Vec2,
    /// Remaining time of this motion state (`∞` for a ball that does not move).
    pub tmax: f64,
    /// [`PATH_MOVES`] and [`PATH_POCKETED`] bits.
    pub flags: u32,
}

impl BallPath {
    /// The centre at `t`, `c + t (b + t a)`: the one place a path is evaluated.
    pub fn at(&self, t: f64) -> Vec2 {
        self.c + t * (self.b + t * self.a)
    }

    /// The velocity at `t`, `b + 2 t a`.
    pub fn velocity_at(&self, t: f64) -> Vec2 {
        self.b + (2.0 * t) * self.a
    }
}

/// The unit vector of `v`, or zero for the zero vector.
fn unit_or_zero(v: Vec2) -> Vec2 {
    let len = norm(v);
    if len > 0.0 {
        (1.0 / len) * v
    } else {
        Vec2::ZERO
    }
}

/// A ball's path coefficients and motion time (the table at the top of this module).
///
/// Contract: for any ball with finite numbers and valid `params`, every field is finite
/// except `tmax`, which is `+∞` exactly for balls that do not translate. A sliding ball whose
/// contact point is at rest, or a rolling ball at rest, has `tmax = 0`: its state is already
/// over and it gets no acceleration.
pub fn ball_path(ball: &Ball, params: &Params) -> BallPath {
    let c = Vec2::new(ball.x, ball.y);
    let v = Vec2::new(ball.vx, ball.vy);
    match ball.state {
        MotionState::Sliding => {
            // contact-point velocity u = v + R ẑ × ω
            let u = Vec2::new(
                ball.vx - params.radius * ball.wy,
                ball.vy + params.radius * ball.wx,
            );
            let a = (-0.5 * params.mu_s * params.g) * unit_or_zero(u);
            let tmax = 2.0 * norm(u) / (7.0 * params.mu_s * params.g);
            BallPath {
                a,
                b: v,
                c,
                tmax,
                flags: PATH_MOVES,
            }
        }
        MotionState::Rolling => {
            let a = (-0.5 * params.mu_r * params.g) * unit_or_zero(v);
            let tmax = norm(v) / (params.mu_r * params.g);
            BallPath {
                a,
                b: v,
                c,
                tmax,
                flags: PATH_MOVES,
            }
        }
        MotionState::Stationary | MotionState::Spinning => BallPath {
            a: Vec2::ZERO,
            b: Vec2::ZERO,
            c,
            tmax: f64::INFINITY,
            flags: 0,
        },
        MotionState::Pocketed => BallPath {
            a: Vec2::ZERO,
            b: Vec2::ZERO,
            c,
            tmax: f64::INFINITY,
            flags: PATH_POCKETED,
        },
    }
}

/// The horizon of a pair: the time at which the first of the two balls' current motions
/// ends, `H = min(tmax₁, tmax₂)` (`∞` when neither ball moves).
pub fn pair_horizon(p1: &BallPath, p2: &BallPath) -> f64 {
    p1.tmax.min(p2.tmax)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rolling_path_decelerates_along_velocity_and_stops_at_tmax() {
        let p = Params::default();
        let ball = Ball::rolling(0.3, 0.4, 3.0, -4.0, p.radius);
        let path = ball_path(&ball, &p);
        assert!((path.tmax - 5.0 / (p.mu_r * p.g)).abs() < 1e-12);
        // velocity b + 2 a t vanishes at tmax
        let v_end = path.b + (2.0 * path.tmax) * path.a;
        assert!(norm(v_end) < 1e-12, "{v_end:?}");
    }

    #[test]
    fn sliding_contact_point_velocity_includes_spin() {
        let p = Params::default();
        // a stun shot: v along x, no spin; u = v
        let ball = Ball {
            state: MotionState::Sliding,
            vx: 2.0,
            ..Ball::at_rest(0.0, 0.0)
        };
        let path = ball_path(&ball, &p);
        assert!((path.a.x + 0.5 * p.mu_s * p.g).abs() < 1e-15);
        assert_eq!(path.a.y, 0.0);
        assert!((path.tmax - 2.0 * 2.0 / (7.0 * p.mu_s * p.g)).abs() < 1e-15);
        // natural roll spin makes u = 0: the sliding state is already over
        let rolling_spin = Ball {
            state: MotionState::Sliding,
            ..Ball::rolling(0.0, 0.0, 2.0, 0.0, p.radius)
        };
        let path = ball_path(&rolling_spin, &p);
        assert_eq!(path.tmax, 0.0);
        assert_eq!(path.a, Vec2::ZERO);
    }

    #[test]
    fn still_and_pocketed_balls_have_fixed_paths() {
        let p = Params::default();
        for state in [
            MotionState::Stationary,
            MotionState::Spinning,
            MotionState::Pocketed,
        ] {
            let ball = Ball {
                state,
                wz: 5.0,
                ..Ball::at_rest(1.0, 2.0)
            };
            let path = ball_path(&ball, &p);
            assert_eq!(path.a, Vec2::ZERO);
            assert_eq!(path.b, Vec2::ZERO);
            assert_eq!(path.tmax, f64::INFINITY);
            assert_eq!(path.flags & PATH_MOVES, 0);
        }
    }
}
