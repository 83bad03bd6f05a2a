//! The shot study's cue strike (its first-contact model; the simulator's strike, with
//! squirt and pooltool's cue frame, is [`crate::resolve::stick_ball`]).
//!
//! Leckie & Greenspan's instantaneous point-contact model ("An event-based pool physics
//! simulator", Advances in Computer Games 2005), as pooltool implements it
//! (`pooltool/physics/resolve/stick_ball/instantaneous_point`, with `english_throttle = 1`
//! and without squirt). The cue of mass `M` moving at `V0`, aimed at azimuth `φ` and
//! elevated by `θ`, hits the ball (mass `m`, radius `R`) at the point `(a R, c, b R)` of
//! the ball frame: `a` sideways (positive to the shooter's left), `b` up,
//! `c = √(R² − a²R² − b²R²)` behind the centre. The ball leaves with
//!
//! `v = 2 V0 / (1 + m/M + 5/(2R²) · (a² + b² cos²θ + c² sin²θ − 2 b c cosθ sinθ))`
//!
//! (a, b in metres here) along the horizontal direction `φ` (the vertical part `v sinθ` is
//! dropped: the ball stays on the cloth), and spin
//! `ω = 5 v / (2 R²) · (−c sinθ + b cosθ, a sinθ, −a cosθ)` in the ball frame (`x`: the
//! shooter's left, `y`: backwards, `z`: up), rotated into the table frame.

use super::cue_ball::contact_velocity;
use crate::model::{Ball, MotionState, Vec2, norm};

/// pooltool's default ball mass in kg (`BallParams.m`).
pub const DEFAULT_BALL_MASS: f64 = 0.170097;
/// pooltool's default cue mass in kg (`CueSpecs.M`, a 20-oz cue).
pub const DEFAULT_CUE_MASS: f64 = 0.567;

/// How the cue strikes the cue ball (pooltool's `Cue` state, and the parameters that the
/// computational pool tournaments' noise model perturbs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Strike {
    /// Cue speed at impact, m/s.
    pub v0: f64,
    /// Azimuth of the cue in degrees: the direction the ball is sent, counterclockwise
    /// from the table's +x axis.
    pub phi: f64,
    /// Elevation of the cue above the cloth in degrees.
    pub theta: f64,
    /// Horizontal offset of the contact point from the ball's centre, as a fraction of R,
    /// positive to the shooter's left.
    pub a: f64,
    /// Vertical offset of the contact point from the ball's centre, as a fraction of R,
    /// positive up (follow), negative down (draw).
    pub b: f64,
}

/// The masses that the strike depends on, in kg.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Masses {
    /// Ball mass `m`.
    pub ball: f64,
    /// Cue mass `M`.
    pub cue: f64,
}

impl Default for Masses {
    fn default() -> Self {
        Masses {
            ball: DEFAULT_BALL_MASS,
            cue: DEFAULT_CUE_MASS,
        }
    }
}

/// The cue ball at `(x, y)` right after the strike (module docs): `Sliding`, or `Rolling`
/// when its contact point happens to be at rest, or `Stationary` for `v0 = 0`.
///
/// The strike is assumed valid: `a² + b² ≤ 1` (see [`Strike::clamped`]).
pub fn cue_strike(x: f64, y: f64, s: &Strike, radius: f64, masses: &Masses) -> Ball {
    let r = radius;
    let (phi, theta) = (s.phi.to_radians(), s.theta.to_radians());
    let (a, b) = (s.a * r, s.b * r);
    let c = (r * r - a * a - b * b).max(0.0).sqrt();
    let (st, ct) = theta.sin_cos();
    let temp = a * a + (b * ct).powi(2) + (c * st).powi(2) - 2.0 * b * c * ct * st;
    let k = 5.0 / (2.0 * r * r);
    let v = 2.0 * s.v0 / (1.0 + masses.ball / masses.cue + k * temp);
    // spin in the ball frame: x the shooter's left, y backwards, z up
    let wb = [
        k * v * (-c * st + b * ct),
        k * v * (a * st),
        k * v * (-a * ct),
    ];
    let speed = v * ct;
    let (sp, cp) = phi.sin_cos();
    let left = Vec2::new(-sp, cp);
    let back = Vec2::new(-cp, -sp);
    let w = wb[0] * left + wb[1] * back;
    let mut ball = Ball {
        state: MotionState::Sliding,
        x,
        y,
        vx: speed * cp,
        vy: speed * sp,
        wx: w.x,
        wy: w.y,
        wz: wb[2],
    };
    if speed == 0.0 {
        ball.state = MotionState::Stationary;
        ball.vx = 0.0;
        ball.vy = 0.0;
        ball.wx = 0.0;
        ball.wy = 0.0;
        if ball.wz != 0.0 {
            ball.state = MotionState::Spinning;
        }
    } else if norm(contact_velocity(&ball, radius)) == 0.0 {
        ball.state = MotionState::Rolling;
    }
    ball
}

impl Strike {
    /// The strike moved into its physical range: `v0 ≥ 0`, `0 ≤ θ ≤ 90°`, and the contact
    /// point on the ball (`a² + b² ≤ 1`, scaled onto the rim when outside). Noisy draws
    /// can leave the range when the intended shot sits at its edge.
    pub fn clamped(self) -> Strike {
        let mut s = self;
        s.v0 = s.v0.max(0.0);
        s.theta = s.theta.clamp(0.0, 90.0);
        let rho = (s.a * s.a + s.b * s.b).sqrt();
        if rho > 1.0 {
            s.a /= rho;
            s.b /= rho;
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Params;

    #[test]
    fn centre_hit_gives_no_spin_and_velocity_along_phi() {
        let p = Params::default();
        let s = Strike {
            v0: 2.0,
            phi: 30.0,
            theta: 0.0,
            a: 0.0,
            b: 0.0,
        };
        let ball = cue_strike(0.5, 0.5, &s, p.radius, &Masses::default());
        let m = Masses::default();
        let v = 2.0 * 2.0 / (1.0 + m.ball / m.cue);
        assert!((ball.vx - v * 30f64.to_radians().cos()).abs() < 1e-12);
        assert!((ball.vy - v * 30f64.to_radians().sin()).abs() < 1e-12);
        assert!(ball.wx.abs() < 1e-9 && ball.wy.abs() < 1e-9 && ball.wz == 0.0);
        assert_eq!(ball.state, MotionState::Sliding);
    }
}
