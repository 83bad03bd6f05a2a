//! A translating ball's horizontal trajectory polynomial `p(τ) = a τ² + b τ + c`, valid
//! until its next transition (spec §4.1; `evolution/event_based/solve.py`).

use crate::model::ball_state::{BallState, rel_velocity};
use crate::model::sim_params::BallParams;
use crate::model::{MotionState, Vec2};
use crate::motion::evolve::{roll_time, slide_time};

/// A ball's trajectory polynomial and how long it holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Path {
    /// Half the acceleration, `a = −½ μ g d̂`.
    pub a: Vec2,
    /// Velocity, `b = v_xy`.
    pub b: Vec2,
    /// Position, `c = r_xy`.
    pub c: Vec2,
    /// The time the polynomial holds, slightly extended (see [`horizon_margin`]);
    /// `∞` for a ball that does not translate.
    pub horizon: f64,
}

impl Path {
    /// The path of a ball that does not translate, at `c`: `a = b = 0`, horizon `∞`.
    pub fn still(c: Vec2) -> Path {
        Path {
            a: Vec2::ZERO,
            b: Vec2::ZERO,
            c,
            horizon: f64::INFINITY,
        }
    }
}

/// A horizon `h` widened by a relative 1e-9 and an absolute 1e-12 s.
///
/// pooltool takes the smallest root of the whole polynomial, with no horizon; a root past
/// the ball's next transition never fires, because the transition comes first and
/// invalidates the entry. Searching a little past the horizon therefore changes nothing,
/// and it keeps a root that lies within rounding of the transition time where pooltool
/// has it (the horizon here is recomputed from the current state, pooltool's transition
/// time from the state at the ball's last event).
pub fn horizon_margin(h: f64) -> f64 {
    h * (1.0 + 1e-9) + 1e-12
}

/// The trajectory polynomial of §4.1: sliding `μ = μ_s`, `d̂ = unit(u_rel)` (`unit(v)` if
/// the slip is exactly 0); rolling `μ = μ_r`, `d̂ = unit(v)`; otherwise `a = b = 0`.
pub fn trajectory(s: &BallState, p: &BallParams) -> Path {
    let c = Vec2::new(s.r.x, s.r.y);
    let still = Path::still(c);
    let (mu, dir, h) = match s.s {
        MotionState::Sliding => {
            let u = rel_velocity(s.v, s.w, p.r).xy();
            let d = if u.norm() == 0.0 {
                s.v.xy().unit()
            } else {
                u.unit()
            };
            (p.u_s, d, slide_time(s, p))
        }
        MotionState::Rolling => (p.u_r, s.v.xy().unit(), roll_time(s, p)),
        _ => return still,
    };
    let k = -0.5 * mu * p.g;
    Path {
        a: Vec2::new(k * dir.x, k * dir.y),
        b: Vec2::new(s.v.x, s.v.y),
        c,
        horizon: horizon_margin(h),
    }
}

/// The path's position at τ, `c + τ (b + τ a)`.
pub fn position_at(path: &Path, tau: f64) -> Vec2 {
    let Path { a, b, c, .. } = *path;
    Vec2::new(c.x + tau * (b.x + tau * a.x), c.y + tau * (b.y + tau * a.y))
}
