//! The physics: what a ball does between two events, and what two balls do relative to
//! each other.
//!
//! Between events every ball that moves follows a quadratic path
//! `r(t) = c + b t + a t²` until its next motion transition (the derivation is in
//! `shared/seed/quartic-derivation.txt`, read with its `ERRATA.md`):
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
//! For a pair the difference of the two paths, `C(t) = C + B t + A t²` (ball 2 minus
//! ball 1), is what the solver works on: the balls touch when `|C(t)| = 2R`, i.e. at a root
//! of the quartic `a t⁴ + b t³ + c t² + d t + e` whose coefficients [`RelPath::quartic`]
//! gives (erratum 1 restores the linear term `d`).
//!
//! The GPU twin of this file is `shaders/physics.wgsl` (in f32 and f64).

use std::fmt;
use std::ops::{Add, Mul, Neg, Sub};
use std::str::FromStr;

/// Default ball radius in metres: pooltool's `BallParams.R` (a 2¼-inch pool ball).
pub const DEFAULT_RADIUS: f64 = 0.028575;
/// Default sliding friction coefficient ball–cloth: pooltool's `BallParams.u_s`.
pub const DEFAULT_MU_S: f64 = 0.2;
/// Default rolling friction coefficient ball–cloth: pooltool's `BallParams.u_r`.
pub const DEFAULT_MU_R: f64 = 0.01;
/// Default spinning friction coefficient divided by the radius: pooltool's
/// `BallParams.u_sp_proportionality` (`u_sp = 10/9 · R · 0.4 = 0.444 R`).
pub const DEFAULT_MU_SP_PER_RADIUS: f64 = 0.444;
/// Default gravitational acceleration in m/s²: pooltool's `BallParams.g`.
pub const DEFAULT_G: f64 = 9.81;

/// The physical parameters of one batch, in SI units.
///
/// The defaults are pooltool's (`pooltool/objects/ball/params.py`, version 0.6):
/// `R = 0.028575 m`, `μs = 0.2`, `μr = 0.01`, `μsp = 0.444·R`, `g = 9.81 m/s²`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// Ball radius `R` in metres.
    pub radius: f64,
    /// Sliding friction coefficient `μs`.
    pub mu_s: f64,
    /// Rolling friction coefficient `μr`.
    pub mu_r: f64,
    /// Spinning friction coefficient `μsp` (in metres, as in pooltool). It decides how long a
    /// ball spins in place, which never changes where it is, so collision times do not
    /// depend on it; it is validated and carried for the event loop around this crate.
    pub mu_sp: f64,
    /// Gravitational acceleration `g` in m/s².
    pub g: f64,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            radius: DEFAULT_RADIUS,
            mu_s: DEFAULT_MU_S,
            mu_r: DEFAULT_MU_R,
            mu_sp: DEFAULT_MU_SP_PER_RADIUS * DEFAULT_RADIUS,
            g: DEFAULT_G,
        }
    }
}

impl Params {
    /// Checks that every parameter is finite and strictly positive, and so are the
    /// decelerations `μs g` and `μr g` (neither may underflow to 0 or a subnormal, nor
    /// overflow: [`ball_path`] divides by them).
    ///
    /// On failure the error names the first offending parameter (or product).
    pub fn validate(&self) -> Result<(), crate::Error> {
        for (name, value) in [
            ("radius", self.radius),
            ("mu_s", self.mu_s),
            ("mu_r", self.mu_r),
            ("mu_sp", self.mu_sp),
            ("g", self.g),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(crate::Error::Param { name, value });
            }
        }
        for (name, value) in [
            ("mu_s * g", self.mu_s * self.g),
            ("mu_r * g", self.mu_r * self.g),
        ] {
            if !(value.is_normal() && (7.0 * value).is_finite()) {
                return Err(crate::Error::Param { name, value });
            }
        }
        Ok(())
    }
}

/// A ball's motion state, with the names and meaning of pooltool's `const.py`
/// (numeric codes as there: stationary 0, spinning 1, sliding 2, rolling 3, pocketed 4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum MotionState {
    /// At rest, no spin.
    Stationary = 0,
    /// In place, spinning about the vertical axis only.
    Spinning = 1,
    /// Moving with the contact point slipping on the cloth.
    Sliding = 2,
    /// Moving with the contact point at rest on the cloth.
    Rolling = 3,
    /// Off the table; never collides.
    Pocketed = 4,
}

impl MotionState {
    /// Every state, in code order.
    pub const ALL: [MotionState; 5] = [
        MotionState::Stationary,
        MotionState::Spinning,
        MotionState::Sliding,
        MotionState::Rolling,
        MotionState::Pocketed,
    ];

    /// The state's name as written in files (`stationary`, `spinning`, …).
    pub fn name(self) -> &'static str {
        match self {
            MotionState::Stationary => "stationary",
            MotionState::Spinning => "spinning",
            MotionState::Sliding => "sliding",
            MotionState::Rolling => "rolling",
            MotionState::Pocketed => "pocketed",
        }
    }

    /// Whether a ball in this state moves across the cloth.
    pub fn translates(self) -> bool {
        matches!(self, MotionState::Sliding | MotionState::Rolling)
    }
}

impl fmt::Display for MotionState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The error of parsing an unknown motion-state name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownState(pub String);

impl fmt::Display for UnknownState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "unknown state {:?} (expected one of stationary, spinning, sliding, rolling, pocketed)",
            self.0
        )
    }
}

impl std::error::Error for UnknownState {}

impl FromStr for MotionState {
    type Err = UnknownState;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        MotionState::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| UnknownState(s.to_owned()))
    }
}

/// One ball's state at the current event: motion state, centre position `(x, y)` in metres,
/// velocity `(vx, vy)` in m/s and angular velocity `(wx, wy, wz)` in rad/s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball {
    /// Motion state.
    pub state: MotionState,
    /// Centre position, x.
    pub x: f64,
    /// Centre position, y.
    pub y: f64,
    /// Velocity, x.
    pub vx: f64,
    /// Velocity, y.
    pub vy: f64,
    /// Angular velocity, x.
    pub wx: f64,
    /// Angular velocity, y.
    pub wy: f64,
    /// Angular velocity, z (vertical).
    pub wz: f64,
}

impl Ball {
    /// A ball at rest at `(x, y)`.
    pub fn at_rest(x: f64, y: f64) -> Ball {
        Ball {
            state: MotionState::Stationary,
            x,
            y,
            vx: 0.0,
            vy: 0.0,
            wx: 0.0,
            wy: 0.0,
            wz: 0.0,
        }
    }

    /// A ball rolling from `(x, y)` with velocity `(vx, vy)` and the matching natural-roll
    /// spin `ω = ẑ × v / R`.
    pub fn rolling(x: f64, y: f64, vx: f64, vy: f64, radius: f64) -> Ball {
        Ball {
            state: MotionState::Rolling,
            x,
            y,
            vx,
            vy,
            wx: -vy / radius,
            wy: vx / radius,
            wz: 0.0,
        }
    }

    /// A ball from its state and its numbers in file order (`x, y, vx, vy, wx, wy, wz`).
    pub fn from_numbers(state: MotionState, v: [f64; 7]) -> Ball {
        let [x, y, vx, vy, wx, wy, wz] = v;
        Ball {
            state,
            x,
            y,
            vx,
            vy,
            wx,
            wy,
            wz,
        }
    }

    /// The ball's numbers, in file order (`x, y, vx, vy, wx, wy, wz`).
    pub fn numbers(&self) -> [f64; 7] {
        [self.x, self.y, self.vx, self.vy, self.wx, self.wy, self.wz]
    }
}

/// A 2-D vector of f64: just what the path algebra needs, the twin of WGSL's `vec2`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vec2 {
    /// x component.
    pub x: f64,
    /// y component.
    pub y: f64,
}

impl Vec2 {
    /// The zero vector.
    pub const ZERO: Vec2 = Vec2 { x: 0.0, y: 0.0 };

    /// A vector from its components.
    pub const fn new(x: f64, y: f64) -> Vec2 {
        Vec2 { x, y }
    }
}

/// Dot product (WGSL `dot`).
pub fn dot(a: Vec2, b: Vec2) -> f64 {
    a.x * b.x + a.y * b.y
}

/// Euclidean length, `sqrt(dot(a, a))` (WGSL: the same function, not the `length` builtin).
pub fn norm(a: Vec2) -> f64 {
    dot(a, a).sqrt()
}

/// The 2-D cross product `a.x b.y − a.y b.x`: `|a|` times the signed distance of `b` from
/// the line along `a` (WGSL: the same function).
pub fn perp_dot(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// The 1-norm `|a.x| + |a.y|`, an upper bound of [`norm`] without a square root (WGSL: the
/// same function).
pub fn norm1(a: Vec2) -> f64 {
    a.x.abs() + a.y.abs()
}

impl Add for Vec2 {
    type Output = Vec2;
    fn add(self, o: Vec2) -> Vec2 {
        Vec2::new(self.x + o.x, self.y + o.y)
    }
}

impl Sub for Vec2 {
    type Output = Vec2;
    fn sub(self, o: Vec2) -> Vec2 {
        Vec2::new(self.x - o.x, self.y - o.y)
    }
}

impl Neg for Vec2 {
    type Output = Vec2;
    fn neg(self) -> Vec2 {
        Vec2::new(-self.x, -self.y)
    }
}

impl Mul<Vec2> for f64 {
    type Output = Vec2;
    fn mul(self, v: Vec2) -> Vec2 {
        Vec2::new(self * v.x, self * v.y)
    }
}

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

/// The centre difference of a pair, ball 2 minus ball 1: `C(t) = C + B t + A t²`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RelPath {
    /// Relative half-acceleration `A = a₂ − a₁`.
    pub a: Vec2,
    /// Relative velocity at `t = 0`, `B = b₂ − b₁`.
    pub b: Vec2,
    /// Centre difference at `t = 0`, `C = c₂ − c₁`.
    pub c: Vec2,
}

impl RelPath {
    /// The relative path of ball 2 seen from ball 1.
    pub fn between(p1: &BallPath, p2: &BallPath) -> RelPath {
        RelPath {
            a: p2.a - p1.a,
            b: p2.b - p1.b,
            c: p2.c - p1.c,
        }
    }

    /// `C(t)`, evaluated from the vectors (never from the expanded quartic).
    pub fn at(&self, t: f64) -> Vec2 {
        self.c + t * (self.b + t * self.a)
    }

    /// `C'(t) = B + 2 t A`, the relative velocity.
    pub fn velocity_at(&self, t: f64) -> Vec2 {
        self.b + (2.0 * t) * self.a
    }

    /// The coefficients `[a, b, c, d, e]` of `|C(t)|² − (2R)²` expanded in powers of `t`,
    /// highest first (erratum 1):
    /// `a = |A|²`, `b = 2 A·B`, `c = |B|² + 2 A·C`, `d = 2 B·C`, `e = |C|² − 4R²`.
    ///
    /// The solver never evaluates this form (cancellation in `e` costs accuracy, see
    /// `shared/notes/numerics.md`); it is here for inspection and tests.
    pub fn quartic(&self, radius: f64) -> [f64; 5] {
        let (a, b, c) = (self.a, self.b, self.c);
        [
            dot(a, a),
            2.0 * dot(a, b),
            dot(b, b) + 2.0 * dot(a, c),
            2.0 * dot(b, c),
            dot(c, c) - 4.0 * radius * radius,
        ]
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
    fn state_names_round_trip() {
        for s in MotionState::ALL {
            assert_eq!(s.name().parse::<MotionState>().unwrap(), s);
        }
        assert!("Rolling".parse::<MotionState>().is_err());
        assert!("".parse::<MotionState>().is_err());
    }

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

    #[test]
    fn quartic_matches_vector_form() {
        let rel = RelPath {
            a: Vec2::new(0.3, -0.2),
            b: Vec2::new(-1.5, 0.7),
            c: Vec2::new(0.4, 0.1),
        };
        let r = 0.028575;
        let q = rel.quartic(r);
        for t in [0.0, 0.1, 0.7, 2.5] {
            let poly = (((q[0] * t + q[1]) * t + q[2]) * t + q[3]) * t + q[4];
            let ct = rel.at(t);
            let direct = dot(ct, ct) - 4.0 * r * r;
            assert!(
                (poly - direct).abs() < 1e-12 * (1.0 + direct.abs()),
                "t={t}"
            );
        }
    }

    #[test]
    fn params_validation_names_the_parameter() {
        let bad = Params {
            mu_r: 0.0,
            ..Params::default()
        };
        let err = bad.validate().unwrap_err().to_string();
        assert!(err.contains("mu_r"), "{err}");
        let nan = Params {
            g: f64::NAN,
            ..Params::default()
        };
        assert!(nan.validate().unwrap_err().to_string().contains('g'));
        assert!(Params::default().validate().is_ok());
    }
}
