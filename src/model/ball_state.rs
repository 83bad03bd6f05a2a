//! One ball's full state in the event loop (spec §0): position r, velocity v, angular
//! velocity ω (3-vectors), the motion label, and the reference time t_b of the last event
//! that changed the ball. Plus the two scalar functions of a state that the loop uses:
//! the cloth slip velocity and the ball's kinetic energy.

use crate::model::sim_params::BallParams;
use crate::model::vec3::Vec3;
use crate::model::{Ball, MotionState};

/// A ball's state, a plain `Copy` struct (the GPU twin will hold the same fields).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BallState {
    /// Centre position in m (z = R on the table, −depth once pocketed).
    pub r: Vec3,
    /// Velocity in m/s (v_z is always 0).
    pub v: Vec3,
    /// Angular velocity in rad/s.
    pub w: Vec3,
    /// Motion label (pooltool's codes: stationary 0, spinning 1, sliding 2, rolling 3,
    /// pocketed 4).
    pub s: MotionState,
    /// Reference time t_b in s: the time of the last event that changed this ball.
    pub t: f64,
}

impl BallState {
    /// A ball at rest on the cloth at `(x, y)` (centre at z = R), reference time 0.
    pub fn at_rest(x: f64, y: f64, radius: f64) -> BallState {
        BallState {
            r: Vec3::new(x, y, radius),
            v: Vec3::ZERO,
            w: Vec3::ZERO,
            s: MotionState::Stationary,
            t: 0.0,
        }
    }

    /// The 3-D state of a [`Ball`] of a [`crate::Batch`] (the 2-D input of every command):
    /// centre at z = `radius` on the cloth (whatever the motion state, pocketed included),
    /// v_z = 0, the spin as given, reference time 0.
    ///
    /// ```
    /// use kisstime::Ball;
    /// use kisstime::simulate::BallState;
    ///
    /// let b = BallState::from_ball(&Ball::rolling(0.5, 1.0, 0.0, 1.0, 0.028575), 0.028575);
    /// assert_eq!((b.r.x, b.r.y, b.r.z, b.v.y, b.v.z), (0.5, 1.0, 0.028575, 1.0, 0.0));
    /// ```
    pub fn from_ball(ball: &Ball, radius: f64) -> BallState {
        BallState {
            r: Vec3::new(ball.x, ball.y, radius),
            v: Vec3::new(ball.vx, ball.vy, 0.0),
            w: Vec3::new(ball.wx, ball.wy, ball.wz),
            s: ball.state,
            t: 0.0,
        }
    }

    /// The 2-D [`Ball`] of this state (z, v_z and the reference time dropped): the inverse
    /// of [`BallState::from_ball`].
    pub fn to_ball(&self) -> Ball {
        Ball {
            state: self.s,
            x: self.r.x,
            y: self.r.y,
            vx: self.v.x,
            vy: self.v.y,
            wx: self.w.x,
            wy: self.w.y,
            wz: self.w.z,
        }
    }

    /// Whether the ball moves across the cloth (sliding or rolling).
    pub fn translating(&self) -> bool {
        self.s.translates()
    }
}

/// The cloth slip velocity `u = v + ω × (−R ẑ) = (v_x − R ω_y, v_y + R ω_x, v_z)`
/// (pooltool's `ptmath.rel_velocity`, spec §0).
pub fn rel_velocity(v: Vec3, w: Vec3, radius: f64) -> Vec3 {
    Vec3::new(v.x - radius * w.y, v.y + radius * w.x, v.z)
}

/// The kinetic energy `½ m|v|² + ½ (2/5 m R²)|ω|²` (pooltool's `ptmath.get_ball_energy`,
/// spec §0), used for the stick check and the tie rule (§3).
pub fn ball_energy(b: &BallState, p: &BallParams) -> f64 {
    let inertia = 0.4 * p.m * p.r * p.r;
    0.5 * p.m * b.v.dot(b.v) + 0.5 * inertia * b.w.dot(b.w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slip_of_a_rolling_ball_is_zero() {
        let r = 0.028575;
        let v = Vec3::new(1.0, 2.0, 0.0);
        let w = Vec3::new(-2.0 / r, 1.0 / r, 3.0);
        assert!(rel_velocity(v, w, r).norm() < 1e-15);
    }

    #[test]
    fn energy_of_rest_is_zero() {
        let p = BallParams::default();
        let b = BallState::at_rest(0.5, 0.5, p.r);
        assert_eq!(ball_energy(&b, &p), 0.0);
        let moving = BallState {
            v: Vec3::new(1.0, 0.0, 0.0),
            ..b
        };
        assert!((ball_energy(&moving, &p) - 0.5 * p.m).abs() < 1e-15);
    }
}
