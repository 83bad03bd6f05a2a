//! A ball's state between events: its motion state and its numbers.
//!
//! The GPU twin of this file is `shaders/model/ball.wgsl` (the motion-state codes).

use std::fmt;
use std::str::FromStr;

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
    /// The names of the ball's numbers, in the order of [`Ball::numbers`] (and of the
    /// input files' columns).
    pub const NUMBER_NAMES: [&'static str; 7] = ["x", "y", "vx", "vy", "wx", "wy", "wz"];

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

    /// A ball sliding from `(x, y)` with velocity `(vx, vy)` and angular velocity
    /// `spin = [wx, wy, wz]` (a stun shot has no spin; its contact point slips at `v`).
    pub fn sliding(x: f64, y: f64, vx: f64, vy: f64, spin: [f64; 3]) -> Ball {
        let [wx, wy, wz] = spin;
        Ball {
            state: MotionState::Sliding,
            x,
            y,
            vx,
            vy,
            wx,
            wy,
            wz,
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

    /// The largest position coordinate accepted, in m (a table 10 km from the origin).
    pub const MAX_POSITION: f64 = 1e4;
    /// The largest velocity component accepted, in m/s (the hardest break is about 12 m/s).
    pub const MAX_SPEED: f64 = 1e3;
    /// The largest angular-velocity component accepted, in rad/s (a hard massé spins a few
    /// hundred).
    pub const MAX_SPIN: f64 = 1e5;

    /// Checks the ball's numbers: every one finite and within the physical range the crate
    /// answers for ([`Ball::MAX_POSITION`], [`Ball::MAX_SPEED`], [`Ball::MAX_SPIN`]; far
    /// beyond any real shot, and far below where squares of them overflow). On failure, the
    /// index of the first offending number (in [`Ball::NUMBER_NAMES`] order) and why.
    pub fn check_numbers(&self) -> Result<(), (usize, String)> {
        let numbers = self.numbers();
        for (k, &v) in numbers.iter().enumerate() {
            let name = Ball::NUMBER_NAMES[k];
            if !v.is_finite() {
                return Err((k, format!("{name} is {v}, numbers must be finite")));
            }
            let (limit, what, unit) = match k {
                0 | 1 => (Ball::MAX_POSITION, "position", "m"),
                2 | 3 => (Ball::MAX_SPEED, "velocity", "m/s"),
                _ => (Ball::MAX_SPIN, "angular velocity", "rad/s"),
            };
            if v.abs() > limit {
                return Err((
                    k,
                    format!(
                        "{name} is {v:e}: beyond the physical range answered for \
                         (|{what}| at most {limit:e} {unit})"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The ball's numbers, in file order (`x, y, vx, vy, wx, wy, wz`).
    pub fn numbers(&self) -> [f64; 7] {
        [self.x, self.y, self.vx, self.vy, self.wx, self.wy, self.wz]
    }
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
    fn sliding_and_rolling_constructors() {
        let r = 0.028575;
        let roll = Ball::rolling(0.1, 0.2, 2.0, 0.0, r);
        assert_eq!((roll.wx, roll.wy), (0.0, 2.0 / r), "wy = vx / R");
        let stun = Ball::sliding(0.1, 0.2, 2.0, 0.0, [0.0; 3]);
        assert_eq!(stun.state, MotionState::Sliding);
        assert_eq!(stun.numbers(), [0.1, 0.2, 2.0, 0.0, 0.0, 0.0, 0.0]);
        assert!(stun.check_numbers().is_ok());
        let wild = Ball::sliding(0.1, 0.2, 2.0, 0.0, [0.0, 0.0, 1e6]);
        assert_eq!(wild.check_numbers().unwrap_err().0, 6);
    }
}
