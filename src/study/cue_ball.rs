//! The shot study's cue ball between events: its state after some time on its current
//! motion, and at the end of it (the first-contact model's 2-D ball; the simulator evolves
//! [`crate::model::BallState`] with [`mod@crate::motion::evolve`]).
//!
//! Motion between events is exactly what [`crate::ball_path`] (and so the batch kernel)
//! assumes: sliding until the contact-point velocity `u = v + R ẑ × ω` vanishes, then
//! rolling until the ball stops. At each transition the position and velocity are the
//! path's [`BallPath::at`](crate::BallPath::at) and
//! [`velocity_at`](crate::BallPath::velocity_at); the spin follows pooltool's closed forms
//! (`evolve_slide_state`, `evolve_roll_state`): while sliding `ω` changes by
//! `−(5/(2R)) μs g t (û × ẑ)`; while rolling it is `ẑ × v / R`; the vertical spin decays
//! at `5 μsp g / (2R)` towards 0 and never moves the ball.

use crate::model::{Ball, MotionState, Params, Vec2};
use crate::motion::path::ball_path;

/// The velocity of the ball's contact point with the cloth, `u = v + R ẑ × ω`.
pub fn contact_velocity(ball: &Ball, radius: f64) -> Vec2 {
    Vec2::new(ball.vx - radius * ball.wy, ball.vy + radius * ball.wx)
}

/// The vertical spin after spinning friction has acted for `t` seconds (pooltool's
/// `evolve_perpendicular_spin_component`): it decays at `5 μsp g / (2R)` towards 0.
fn decay_wz(wz: f64, params: &Params, t: f64) -> f64 {
    let alpha = 5.0 * params.mu_sp * params.g / (2.0 * params.radius);
    let d = (alpha * t).min(wz.abs());
    wz - wz.signum() * d
}

/// The ball `t` seconds into its current motion (`0 ≤ t ≤ ball_path(ball).tmax`), still in
/// the same state: position and velocity from its path, spin by pooltool's closed forms.
pub fn evolve(ball: &Ball, params: &Params, t: f64) -> Ball {
    let path = ball_path(ball, params);
    let mut out = *ball;
    match ball.state {
        MotionState::Sliding | MotionState::Rolling => {
            let p = path.at(t);
            let v = path.velocity_at(t);
            out.x = p.x;
            out.y = p.y;
            out.vx = v.x;
            out.vy = v.y;
            if ball.state == MotionState::Sliding {
                // ω(t) = ω0 − (5/(2R)) μs g t (û × ẑ), û × ẑ = (ûy, −ûx); the path's a is
                // −½ μs g û, so (5/(2R)) μs g t û = −(5/R) t a
                let k = -(5.0 / params.radius) * t;
                out.wx = ball.wx - k * path.a.y;
                out.wy = ball.wy + k * path.a.x;
            } else {
                out.wx = -v.y / params.radius;
                out.wy = v.x / params.radius;
            }
            out.wz = decay_wz(ball.wz, params, t);
        }
        MotionState::Spinning => out.wz = decay_wz(ball.wz, params, t),
        MotionState::Stationary | MotionState::Pocketed => {}
    }
    out
}

/// The ball at the end of its current motion, in its next state: sliding → rolling,
/// rolling → stationary (or spinning while vertical spin is left). Balls that do not
/// translate are returned unchanged. Also returns the duration of the motion.
pub fn end_of_motion(ball: &Ball, params: &Params) -> (Ball, f64) {
    if !ball.state.translates() {
        return (*ball, f64::INFINITY);
    }
    let tmax = ball_path(ball, params).tmax;
    let mut out = evolve(ball, params, tmax);
    match ball.state {
        MotionState::Sliding => {
            // the contact point is at rest now: roll (the spin is the rolling spin up to
            // rounding; make it exact)
            out.state = MotionState::Rolling;
            out.wx = -out.vy / params.radius;
            out.wy = out.vx / params.radius;
        }
        _ => {
            out.vx = 0.0;
            out.vy = 0.0;
            out.wx = 0.0;
            out.wy = 0.0;
            out.state = if out.wz == 0.0 {
                MotionState::Stationary
            } else {
                MotionState::Spinning
            };
        }
    }
    (out, tmax)
}
