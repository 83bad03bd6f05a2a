//! A shot study's configuration: one table, one intended shot and the cue noise, as a
//! TOML file (the "scenario" file of `kisstime shots`).
//!
//! The format (every length in metres, angles in degrees; `examples/study.toml` is the
//! built-in study and a complete example):
//!
//! ```toml
//! [table]            # the playing area between the cushion noses: [0, length] × [0, width]
//! length = 2.54
//! width = 1.27
//!
//! [physics]          # optional, each key too: pooltool's defaults
//! radius = 0.028575
//! mu_s = 0.2
//! mu_r = 0.01
//! mu_sp = 0.0126873  # default 0.444 × radius
//! g = 9.81
//! ball_mass = 0.170097
//! cue_mass = 0.567
//!
//! [[balls]]          # two or more; centres within the table, no two overlapping
//! id = 0
//! x = 0.6
//! y = 0.4
//!
//! [shot]
//! cue_ball = 0       # the ball the cue strikes
//! object_ball = 1    # the ball the player means to hit first
//! v0 = 1.5           # cue speed, m/s
//! phi = 20.0         # aim: direction of travel, counterclockwise from +x
//! theta = 5.0        # cue elevation
//! a = 0.0            # tip offset sideways (fraction of R, + = shooter's left)
//! b = 0.2            # tip offset up (fraction of R, + = follow, − = draw)
//!
//! [noise]            # optional, each key too: the standard deviations, times `factor`
//! factor = 1.0
//! v0 = 0.075
//! phi = 0.125
//! theta = 0.1
//! a = 0.0005         # metres (0.5 mm) at the ball's surface
//! b = 0.0005
//! ```
//!
//! Unknown keys, missing keys, numbers that are not finite, balls that overlap or lie off
//! the table, a negative speed … are [`Error::Input`] errors naming the file, the key and,
//! where it applies, the ball.

use serde::Deserialize;

use super::rectangle::Rectangle;
use super::strike::{DEFAULT_BALL_MASS, DEFAULT_CUE_MASS, Masses, Strike};
use crate::error::{Error, InputError};
use crate::model::{
    Ball, DEFAULT_G, DEFAULT_MU_R, DEFAULT_MU_S, DEFAULT_MU_SP_PER_RADIUS, DEFAULT_RADIUS, Params,
};
use crate::query::ball_ball::CONTACT_TOL;

/// The built-in study, `examples/study.toml`, as text.
pub const BUILTIN_TOML: &str = include_str!("../../examples/study.toml");
/// The name under which errors in the built-in study are reported.
pub const BUILTIN_NAME: &str = "built-in study (examples/study.toml)";

/// Default standard deviation of the cue speed, m/s (the computational pool tournaments'
/// simulator).
pub const DEFAULT_SIGMA_V0: f64 = 0.075;
/// Default standard deviation of the aim azimuth, degrees.
pub const DEFAULT_SIGMA_PHI: f64 = 0.125;
/// Default standard deviation of the cue elevation, degrees.
pub const DEFAULT_SIGMA_THETA: f64 = 0.1;
/// Default standard deviation of each tip offset, metres.
pub const DEFAULT_SIGMA_OFFSET: f64 = 0.0005;

/// The cue noise: standard deviations of independent Gaussians on the strike.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Noise {
    /// Cue speed, m/s.
    pub v0: f64,
    /// Aim azimuth, degrees.
    pub phi: f64,
    /// Cue elevation, degrees.
    pub theta: f64,
    /// Sideways tip offset, metres.
    pub a: f64,
    /// Vertical tip offset, metres.
    pub b: f64,
}

impl Default for Noise {
    fn default() -> Self {
        Noise {
            v0: DEFAULT_SIGMA_V0,
            phi: DEFAULT_SIGMA_PHI,
            theta: DEFAULT_SIGMA_THETA,
            a: DEFAULT_SIGMA_OFFSET,
            b: DEFAULT_SIGMA_OFFSET,
        }
    }
}

impl Noise {
    /// Every standard deviation times `factor`.
    pub fn scaled(&self, factor: f64) -> Noise {
        Noise {
            v0: factor * self.v0,
            phi: factor * self.phi,
            theta: factor * self.theta,
            a: factor * self.a,
            b: factor * self.b,
        }
    }

    /// The names and values, in draw order.
    pub fn named(&self) -> [(&'static str, f64); 5] {
        [
            ("v0", self.v0),
            ("phi", self.phi),
            ("theta", self.theta),
            ("a", self.a),
            ("b", self.b),
        ]
    }
}

/// A ball of the layout.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spot {
    /// Ball id.
    pub id: i64,
    /// Centre, x (m).
    pub x: f64,
    /// Centre, y (m).
    pub y: f64,
}

/// A validated shot study (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct StudyConfig {
    /// Where errors are reported from: the file name or [`BUILTIN_NAME`].
    pub source: String,
    /// The playing area.
    pub table: Rectangle,
    /// Ball radius and friction.
    pub params: Params,
    /// Ball and cue mass.
    pub masses: Masses,
    /// The balls, in file order.
    pub balls: Vec<Spot>,
    /// The cue ball's id.
    pub cue_ball: i64,
    /// The intended object ball's id.
    pub object_ball: i64,
    /// The intended strike.
    pub shot: Strike,
    /// The file's noise scale factor.
    pub noise_factor: f64,
    /// The file's standard deviations (before `noise_factor`).
    pub noise: Noise,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    table: RawTable,
    #[serde(default)]
    physics: RawPhysics,
    balls: Vec<RawBall>,
    shot: RawShot,
    #[serde(default)]
    noise: RawNoise,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTable {
    length: f64,
    width: f64,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawPhysics {
    radius: Option<f64>,
    mu_s: Option<f64>,
    mu_r: Option<f64>,
    mu_sp: Option<f64>,
    g: Option<f64>,
    ball_mass: Option<f64>,
    cue_mass: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBall {
    id: i64,
    x: f64,
    y: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawShot {
    cue_ball: i64,
    object_ball: i64,
    v0: f64,
    phi: f64,
    theta: f64,
    a: f64,
    b: f64,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawNoise {
    factor: Option<f64>,
    v0: Option<f64>,
    phi: Option<f64>,
    theta: Option<f64>,
    a: Option<f64>,
    b: Option<f64>,
}

impl StudyConfig {
    /// The built-in study (`examples/study.toml`, compiled in).
    pub fn builtin() -> StudyConfig {
        StudyConfig::parse(BUILTIN_TOML, BUILTIN_NAME).expect("the built-in study is valid")
    }

    /// Reads and validates a scenario file.
    pub fn read(path: &std::path::Path) -> Result<StudyConfig, Error> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: path.display().to_string(),
            source,
        })?;
        StudyConfig::parse(&text, &path.display().to_string())
    }

    /// Parses and validates scenario text; errors name `source` as the file.
    pub fn parse(text: &str, source: &str) -> Result<StudyConfig, Error> {
        let raw: RawFile = toml::from_str(text).map_err(|e| {
            let mut message = e.message().trim().to_owned();
            let mut line = None;
            if let Some(span) = e.span() {
                let start = span.start.min(text.len());
                line = Some(text[..start].matches('\n').count() as u64 + 1);
                // name the offending text when the message does not (e.g. "duplicate key")
                let at = text
                    .get(start..span.end.min(text.len()))
                    .and_then(|t| t.lines().next())
                    .unwrap_or("")
                    .trim();
                if !at.is_empty() && at.len() <= 60 && !message.contains(at) {
                    message = format!("{message} (at `{at}`)");
                }
            }
            let mut ie = InputError::new(message).in_file(source);
            if let Some(line) = line {
                ie = ie.at_line(line);
            }
            Error::from(ie)
        })?;
        let err = |msg: String| Error::from(InputError::new(msg).in_file(source));
        let ball_err =
            |id: i64, msg: String| Error::from(InputError::new(msg).in_file(source).at_ball(id));

        let finite = |key: &str, v: f64| -> Result<f64, Error> {
            if v.is_finite() {
                Ok(v)
            } else {
                Err(err(format!(
                    "key `{key}` is {v}, it must be a finite number"
                )))
            }
        };
        let positive = |key: &str, v: f64| -> Result<f64, Error> {
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(err(format!(
                    "key `{key}` is {v}, it must be finite and greater than 0"
                )))
            }
        };
        let non_negative = |key: &str, v: f64| -> Result<f64, Error> {
            if v.is_finite() && v >= 0.0 {
                Ok(v)
            } else {
                Err(err(format!(
                    "key `{key}` is {v}, it must be finite and not negative"
                )))
            }
        };

        let ph = &raw.physics;
        let radius = positive("physics.radius", ph.radius.unwrap_or(DEFAULT_RADIUS))?;
        let params = Params {
            radius,
            mu_s: positive("physics.mu_s", ph.mu_s.unwrap_or(DEFAULT_MU_S))?,
            mu_r: positive("physics.mu_r", ph.mu_r.unwrap_or(DEFAULT_MU_R))?,
            mu_sp: positive(
                "physics.mu_sp",
                ph.mu_sp.unwrap_or(DEFAULT_MU_SP_PER_RADIUS * radius),
            )?,
            g: positive("physics.g", ph.g.unwrap_or(DEFAULT_G))?,
        };
        // each key is fine; their products (the decelerations) must be too
        params
            .validate()
            .map_err(|e| err(format!("keys of `physics`: {e}")))?;
        let masses = Masses {
            ball: positive(
                "physics.ball_mass",
                ph.ball_mass.unwrap_or(DEFAULT_BALL_MASS),
            )?,
            cue: positive("physics.cue_mass", ph.cue_mass.unwrap_or(DEFAULT_CUE_MASS))?,
        };

        let table = Rectangle {
            length: positive("table.length", raw.table.length)?,
            width: positive("table.width", raw.table.width)?,
        };
        for (key, extent) in [("table.length", table.length), ("table.width", table.width)] {
            if extent <= 2.0 * radius {
                return Err(err(format!(
                    "key `{key}` is {extent}, the table must be wider than a ball (2R = {})",
                    2.0 * radius
                )));
            }
        }

        if raw.balls.len() < 2 {
            return Err(err(format!(
                "key `balls`: a study needs at least 2 balls, this one has {}",
                raw.balls.len()
            )));
        }
        let mut balls: Vec<Spot> = Vec::with_capacity(raw.balls.len());
        for (k, b) in raw.balls.iter().enumerate() {
            for (name, v, hi) in [("x", b.x, table.length), ("y", b.y, table.width)] {
                let key = format!("balls[{k}].{name}");
                if !v.is_finite() {
                    return Err(ball_err(
                        b.id,
                        format!("key `{key}` is {v}, it must be a finite number"),
                    ));
                }
                if v < radius || v > hi - radius {
                    return Err(ball_err(
                        b.id,
                        format!(
                            "key `{key}` is {v}: the ball is off the table (its centre must be \
                             within [{radius}, {}])",
                            hi - radius
                        ),
                    ));
                }
            }
            if let Some(prev) = balls.iter().position(|p| p.id == b.id) {
                return Err(ball_err(
                    b.id,
                    format!("key `balls[{k}].id`: the id {} is also balls[{prev}]", b.id),
                ));
            }
            for (j, p) in balls.iter().enumerate() {
                let d = ((b.x - p.x).powi(2) + (b.y - p.y).powi(2)).sqrt();
                if d < 2.0 * radius - CONTACT_TOL {
                    return Err(ball_err(
                        b.id,
                        format!(
                            "key `balls[{k}]`: the ball overlaps ball {} (balls[{j}]): their \
                             centres are {d} m apart, less than 2R = {}",
                            p.id,
                            2.0 * radius
                        ),
                    ));
                }
            }
            balls.push(Spot {
                id: b.id,
                x: b.x,
                y: b.y,
            });
        }

        let s = &raw.shot;
        for (key, id) in [
            ("shot.cue_ball", s.cue_ball),
            ("shot.object_ball", s.object_ball),
        ] {
            if !balls.iter().any(|b| b.id == id) {
                return Err(err(format!(
                    "key `{key}` is {id}, which is not the id of any of the balls"
                )));
            }
        }
        if s.cue_ball == s.object_ball {
            return Err(err(format!(
                "key `shot.object_ball` is {}, the cue ball itself",
                s.object_ball
            )));
        }
        let shot = Strike {
            v0: positive("shot.v0", s.v0)?,
            phi: finite("shot.phi", s.phi)?,
            theta: finite("shot.theta", s.theta)?,
            a: finite("shot.a", s.a)?,
            b: finite("shot.b", s.b)?,
        };
        if !(0.0..90.0).contains(&shot.theta) {
            return Err(err(format!(
                "key `shot.theta` is {}, the cue elevation must be in [0, 90) degrees",
                shot.theta
            )));
        }
        if shot.a * shot.a + shot.b * shot.b > 1.0 {
            return Err(err(format!(
                "keys `shot.a` = {} and `shot.b` = {}: the tip must hit the ball \
                 (a² + b² ≤ 1)",
                shot.a, shot.b
            )));
        }

        let n = &raw.noise;
        let d = Noise::default();
        let noise = Noise {
            v0: non_negative("noise.v0", n.v0.unwrap_or(d.v0))?,
            phi: non_negative("noise.phi", n.phi.unwrap_or(d.phi))?,
            theta: non_negative("noise.theta", n.theta.unwrap_or(d.theta))?,
            a: non_negative("noise.a", n.a.unwrap_or(d.a))?,
            b: non_negative("noise.b", n.b.unwrap_or(d.b))?,
        };
        let noise_factor = non_negative("noise.factor", n.factor.unwrap_or(1.0))?;

        Ok(StudyConfig {
            source: source.to_owned(),
            table,
            params,
            masses,
            balls,
            cue_ball: s.cue_ball,
            object_ball: s.object_ball,
            shot,
            noise_factor,
            noise,
        })
    }

    /// The cue ball's position.
    pub fn cue_spot(&self) -> Spot {
        *self
            .balls
            .iter()
            .find(|b| b.id == self.cue_ball)
            .expect("validated")
    }

    /// The object balls (every ball but the cue ball) at rest, with their ids.
    pub fn object_balls(&self) -> Vec<(i64, Ball)> {
        self.balls
            .iter()
            .filter(|b| b.id != self.cue_ball)
            .map(|b| (b.id, Ball::at_rest(b.x, b.y)))
            .collect()
    }

    /// The standard deviations in effect: the file's, times its factor.
    pub fn sigma(&self) -> Noise {
        self.noise.scaled(self.noise_factor)
    }
}
