//! One cue ball's shot: the cue strike, the motion between events, and the cushions.
//!
//! - **Cue strike**: Leckie & Greenspan's instantaneous point-contact model ("An
//!   event-based pool physics simulator", Advances in Computer Games 2005), as pooltool
//!   implements it (`pooltool/physics/resolve/stick_ball/instantaneous_point`, with
//!   `english_throttle = 1` and without squirt). The cue of mass `M` moving at `V0`, aimed
//!   at azimuth `φ` and elevated by `θ`, hits the ball (mass `m`, radius `R`) at the point
//!   `(a R, c, b R)` of the ball frame: `a` sideways (positive to the shooter's left), `b`
//!   up, `c = √(R² − a²R² − b²R²)` behind the centre. The ball leaves with
//!
//!   `v = 2 V0 / (1 + m/M + 5/(2R²) · (a² + b² cos²θ + c² sin²θ − 2 b c cosθ sinθ))`
//!
//!   (a, b in metres here) along the horizontal direction `φ` (the vertical part
//!   `v sinθ` is dropped: the ball stays on the cloth), and spin
//!   `ω = 5 v / (2 R²) · (−c sinθ + b cosθ, a sinθ, −a cosθ)` in the ball frame (`x`: the
//!   shooter's left, `y`: backwards, `z`: up), rotated into the table frame.
//! - **Motion** between events is exactly what [`crate::ball_path`] (and so the batch
//!   kernel) assumes: sliding until the contact-point velocity `u = v + R ẑ × ω` vanishes,
//!   then rolling until the ball stops. At each transition the position and velocity are
//!   the path's `c + b t + a t²` and `b + 2 a t`, the spin follows pooltool's closed forms
//!   (`evolve_slide_state`, `evolve_roll_state`): while sliding `ω` changes by
//!   `−(5/(2R)) μs g t (û × ẑ)`; while rolling it is `ẑ × v / R`; the vertical spin decays
//!   at `5 μsp g / (2R)` towards 0 and never moves the ball.
//! - **Cushions**: the playing area is the rectangle `[0, length] × [0, width]` (the
//!   cushion noses); the cue ball's centre reaches a cushion when it reaches the rectangle
//!   inset by `R`. Per side that is a quadratic in `t` on the current path.

use crate::physics::{Ball, BallPath, MotionState, Params, Vec2, ball_path, norm};
use crate::solver::quadratic_roots;

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
            let p = path.c + t * (path.b + t * path.a);
            let v = path.b + (2.0 * t) * path.a;
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

/// The playing area: `[0, length] × [0, width]`, in metres, between the cushion noses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Table {
    /// Extent along x.
    pub length: f64,
    /// Extent along y.
    pub width: f64,
}

/// A cushion of the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Cushion {
    /// The cushion along `x = 0`.
    Left,
    /// The cushion along `x = length`.
    Right,
    /// The cushion along `y = 0`.
    Bottom,
    /// The cushion along `y = width`.
    Top,
}

impl Cushion {
    /// `left`, `right`, `bottom`, `top`.
    pub fn name(self) -> &'static str {
        match self {
            Cushion::Left => "left",
            Cushion::Right => "right",
            Cushion::Bottom => "bottom",
            Cushion::Top => "top",
        }
    }

    /// The outward unit normal.
    pub fn normal(self) -> Vec2 {
        match self {
            Cushion::Left => Vec2::new(-1.0, 0.0),
            Cushion::Right => Vec2::new(1.0, 0.0),
            Cushion::Bottom => Vec2::new(0.0, -1.0),
            Cushion::Top => Vec2::new(0.0, 1.0),
        }
    }
}

/// The first time in `[0, tend]` at which a ball on `path` reaches a cushion line (the
/// playing area inset by `radius`) moving outwards, and which cushion; `None` if it stays
/// inside. A ball already on a line and moving outwards reaches it at 0.
pub fn cushion_time(
    path: &BallPath,
    table: &Table,
    radius: f64,
    tend: f64,
) -> Option<(f64, Cushion)> {
    if path.flags & crate::physics::PATH_MOVES == 0 {
        return None;
    }
    let mut best: Option<(f64, Cushion)> = None;
    for cushion in [Cushion::Left, Cushion::Right, Cushion::Bottom, Cushion::Top] {
        let n = cushion.normal();
        // signed distance of the centre beyond the line: s(t) = n·r(t) − limit, with the
        // line at n·r = limit (x = R, x = length − R, …)
        let limit = match cushion {
            Cushion::Left | Cushion::Bottom => -radius,
            Cushion::Right => table.length - radius,
            Cushion::Top => table.width - radius,
        };
        let (qa, qb, qc) = (
            crate::physics::dot(n, path.a),
            crate::physics::dot(n, path.b),
            crate::physics::dot(n, path.c) - limit,
        );
        let t = if qc >= 0.0 {
            // on or beyond the line: reaches it now if moving outwards
            if qb > 0.0 || (qb == 0.0 && qa > 0.0) {
                Some(0.0)
            } else {
                first_upcrossing(qa, qb, qc)
            }
        } else {
            first_upcrossing(qa, qb, qc)
        };
        if let Some(t) = t.filter(|&t| t <= tend)
            && best.is_none_or(|(bt, _)| t < bt)
        {
            best = Some((t, cushion));
        }
    }
    best
}

/// The smallest `t > 0` at which `qa t² + qb t + qc` crosses zero upwards (or touches it).
fn first_upcrossing(qa: f64, qb: f64, qc: f64) -> Option<f64> {
    let (n, r0, r1) = quadratic_roots(qa, qb, qc);
    [r0, r1]
        .into_iter()
        .take(n as usize)
        .find(|&t| t > 0.0 && 2.0 * qa * t + qb >= 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn cushion_line_reached_by_a_rolling_ball() {
        let p = Params::default();
        let table = Table {
            length: 2.0,
            width: 1.0,
        };
        let ball = Ball::rolling(1.0, 0.5, 2.0, 0.0, p.radius);
        let path = ball_path(&ball, &p);
        let (t, c) = cushion_time(&path, &table, p.radius, path.tmax).unwrap();
        assert_eq!(c, Cushion::Right);
        let x = path.c.x + t * (path.b.x + t * path.a.x);
        assert!((x - (2.0 - p.radius)).abs() < 1e-12);
    }
}
