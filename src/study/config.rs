//! A shot study's configuration: one table, one layout, one intended shot, the cue noise
//! and, optionally, where the cue ball should end up, as a TOML file (the "scenario" of
//! `kisstime shots`).
//!
//! The frame is the simulator's, pooltool's: on the 9-ft table x runs **across** (0 to
//! w = 1.27 m) and y **along** (0 to l = 2.54 m), the origin at a corner of the playing
//! surface (the cushion noses), the head rail at y = 0; angles counter-clockwise from +x.
//! The format (every length in metres, angles in degrees; `examples/study.toml` is the
//! built-in study and a complete example):
//!
//! ```toml
//! [table]            # optional: "9ft" (the default), "7ft" (pooltool's default table),
//! kind = "9ft"       #   "rectangle", "snooker", "carom" (their game's balls without
//!                    #   [physics]), or a JSON table file (the format of
//!                    #   data/fullshots/table.json; relative paths are taken from the
//!                    #   study file's folder)
//! # l = 2.54         # optional, a built-in table only: the playing surface's length and
//! # w = 1.27         #   width in m (its pockets and cushions follow, as in pooltool's
//!                    #   PocketTableSpecs; the JSON scenario's `table.l`, `table.w`)
//!
//! [physics]          # optional, each key too: pooltool 0.6.0's BallParams names and
//! R = 0.028575       #   defaults, read by the one parser of every entry point
//! m = 0.170097       #   (`crate::io::physics`, whose docs list the keys and ranges)
//! u_s = 0.2          # sliding friction
//! u_r = 0.01         # rolling resistance
//! u_sp_proportionality = 0.4444444444444444   # spinning friction u_sp = this × R
//! e_b = 0.95         # ball–ball restitution
//! e_c = 0.85         # cushion restitution
//! f_c = 0.2          # cushion friction
//! g = 9.81
//!
//! [physics.cue]      # optional: pooltool's CueSpecs names
//! M = 0.567          # cue mass
//! end_mass = 0.0056699   # squirt (default 0.170097 / 30)
//!
//! [[balls]]          # two or more, in pooltool's ball order (it decides exact ties);
//! id = "cue"         # ids are names or integers
//! x = 1.18
//! y = 1.19
//!
//! [shot]             # pooltool's Cue.set_state conventions (see `CueStrike`)
//! cue_ball = "cue"   # the ball the cue strikes
//! object_ball = "7"  # the ball the player means to pot
//! pocket = "lb"      # optional: the pocket it is called in (a pocket id of the table)
//! v0 = 1.5           # cue speed, m/s
//! phi = 201.75       # stroke azimuth
//! theta = 5.0        # cue elevation
//! a = 0.0            # tip contact point sideways, fraction of R (+ = shooter's left)
//! b = 0.2            # tip contact point up, fraction of R (+ = follow, − = draw)
//!
//! [target]           # optional: position play, the circle the cue ball should stop in
//! x = 1.0
//! y = 1.3
//! radius = 0.2
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
//! the table, a strike off the ball, an unknown pocket … are [`Error::Input`] errors naming
//! the file, the key and, where it applies, the ball. A `[physics]` key under one of
//! kisstime's former names (`radius`, `mu_s`, `cue_mass`, …) is refused with the pooltool
//! name to use instead.

use serde::Deserialize;

use crate::error::{Error, InputError, SimError};
use crate::game::{Context, Rules};
use crate::io::physics::{PhysicsSource, PhysicsValue, physics_from_entries, toml_error};
use crate::io::table_json::{BUILTIN_TABLES, table_by_name};
use crate::model::ball_state::BallState;
use crate::model::sim_params::SimParams;
use crate::model::table::{PocketTableSpecs, Table};
use crate::resolve::stick_ball::CueStrike;
use crate::simulate::check::check_layout;

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

/// How the physics varies from sample to sample (`[noise.physics]`): for each of
/// pooltool's ball parameters ([`crate::io::physics::BALL_KEYS`], in that order; never
/// `R`, which would move the layout) either nothing or a range of relative offsets
/// `(lo, hi)`: sample `i` has the parameter times `1 + lo + (hi − lo)·u`, `u` uniform in
/// [0, 1) from its own stream ([`crate::study::noise::sample_physics`]).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct PhysicsSpread {
    /// The relative range of each parameter, by its index in `BALL_KEYS`.
    pub ranges: [Option<(f64, f64)>; 10],
}

impl PhysicsSpread {
    /// Whether no parameter varies.
    pub fn is_empty(&self) -> bool {
        self.ranges
            .iter()
            .all(|r| r.is_none_or(|(lo, hi)| lo == 0.0 && hi == 0.0))
    }

    /// Every range times `factor` (the noise's scale factor).
    pub fn scaled(&self, factor: f64) -> PhysicsSpread {
        PhysicsSpread {
            ranges: self
                .ranges
                .map(|r| r.map(|(lo, hi)| (factor * lo, factor * hi))),
        }
    }

    /// The varying parameters by pooltool's name, with their relative ranges.
    pub fn named(&self) -> Vec<(&'static str, f64, f64)> {
        crate::io::physics::BALL_KEYS
            .iter()
            .zip(&self.ranges)
            .filter_map(|(k, r)| r.map(|(lo, hi)| (*k, lo, hi)))
            .collect()
    }
}

/// The noise of a study: standard deviations of independent Gaussians on the strike, and
/// the spread of the physics across samples.
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
    /// The physics' spread across samples (none by default).
    pub physics: PhysicsSpread,
}

impl Default for Noise {
    fn default() -> Self {
        Noise {
            v0: DEFAULT_SIGMA_V0,
            phi: DEFAULT_SIGMA_PHI,
            theta: DEFAULT_SIGMA_THETA,
            a: DEFAULT_SIGMA_OFFSET,
            b: DEFAULT_SIGMA_OFFSET,
            physics: PhysicsSpread::default(),
        }
    }
}

/// The cue-noise presets ([`Noise::preset`]): a name, its factor on the `fastfiz`
/// deviations, and what it models.
pub const NOISE_PRESETS: [(&str, f64, &str); 4] = [
    (
        "fastfiz",
        1.0,
        "the computational-pool tournaments' model (FastFiz): σ V0 0.075 m/s, φ 0.125°, \
         θ 0.1°, a and b 0.5 mm",
    ),
    (
        "club",
        2.0,
        "a good club player: twice fastfiz's deviations",
    ),
    (
        "casual",
        4.0,
        "a casual player: four times fastfiz's deviations",
    ),
    ("none", 0.0, "no noise: every sample is the intended strike"),
];

impl Noise {
    /// The preset `name` of [`NOISE_PRESETS`] (fastfiz's deviations, the study's
    /// defaults, times the preset's factor; no physics spread), or `None`.
    pub fn preset(name: &str) -> Option<Noise> {
        NOISE_PRESETS
            .iter()
            .find(|(n, _, _)| *n == name)
            .map(|(_, factor, _)| Noise::default().scaled(*factor))
    }

    /// Every standard deviation, and the physics' every range, times `factor`.
    pub fn scaled(&self, factor: f64) -> Noise {
        Noise {
            v0: factor * self.v0,
            phi: factor * self.phi,
            theta: factor * self.theta,
            a: factor * self.a,
            b: factor * self.b,
            physics: self.physics.scaled(factor),
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
#[derive(Clone, Debug, PartialEq)]
pub struct Spot {
    /// Ball id (a name, or an integer written as text).
    pub id: String,
    /// Centre, x (m).
    pub x: f64,
    /// Centre, y (m).
    pub y: f64,
}

/// Position play: the circle the cue ball should come to rest in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Target {
    /// Centre, x (m).
    pub x: f64,
    /// Centre, y (m).
    pub y: f64,
    /// Radius (m).
    pub radius: f64,
}

impl Target {
    /// Whether `(x, y)` lies in the circle (its edge included).
    pub fn contains(&self, x: f64, y: f64) -> bool {
        (x - self.x).powi(2) + (y - self.y).powi(2) <= self.radius * self.radius
    }
}

/// A validated shot study (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct StudyConfig {
    /// Where errors are reported from: the file name or [`BUILTIN_NAME`].
    pub source: String,
    /// The table's name as the file gives it (`9ft`, `rectangle`, a file).
    pub table_name: String,
    /// The table.
    pub table: Table,
    /// The balls', cue's and resolver's constants.
    pub params: SimParams,
    /// The balls, in file order (pooltool's ball order).
    pub balls: Vec<Spot>,
    /// The cue ball's index in `balls`.
    pub cue: usize,
    /// The intended object ball's index in `balls`.
    pub intended: usize,
    /// The pocket it is called in: an index into `table.pockets`.
    pub pocket: Option<usize>,
    /// The intended strike.
    pub shot: CueStrike,
    /// Where the cue ball should stop, if the study says.
    pub target: Option<Target>,
    /// The file's noise scale factor.
    pub noise_factor: f64,
    /// The file's standard deviations (before `noise_factor`).
    pub noise: Noise,
    /// The game every sample is judged by (`[game]`), if any.
    pub game: Option<StudyGame>,
}

/// A study's game (`[game]`): the rules that judge every sample, as `kisstime simulate
/// --rules` judges a shot, and the shot's context.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyGame {
    /// The rules.
    pub rules: Rules,
    /// The shot's context (with the rules' own part: 8-ball asks a call after the break).
    pub context: Context,
    /// Each ball's identity for the rules, in the study's ball order: pool games number
    /// the cue ball 0 and the object balls by their ids (1 to 15); snooker's are its ids
    /// 0 to 21 ([`crate::game::snooker::id_of`]); three-cushion needs none (the balls'
    /// indices).
    pub ids: Vec<i64>,
}

/// A ball id in TOML: a name or an integer.
#[derive(Deserialize)]
#[serde(untagged)]
enum RawId {
    Int(i64),
    Name(String),
}

impl RawId {
    fn text(&self) -> String {
        match self {
            RawId::Int(i) => i.to_string(),
            RawId::Name(s) => s.clone(),
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    #[serde(default)]
    table: RawTable,
    physics: Option<toml::Table>,
    balls: Vec<RawBall>,
    shot: RawShot,
    target: Option<RawTarget>,
    #[serde(default)]
    noise: RawNoise,
    game: Option<RawGame>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawGame {
    rules: String,
    #[serde(default, rename = "break")]
    break_shot: bool,
    #[serde(default)]
    hittable: Vec<RawId>,
    ball_call: Option<RawId>,
    pocket_call: Option<String>,
    #[serde(default)]
    wpa: bool,
    #[serde(default)]
    score: u32,
    #[serde(default)]
    opponent_score: u32,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawTable {
    kind: Option<String>,
    /// A size of its own for a built-in table: the playing surface's length and width.
    l: Option<f64>,
    w: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBall {
    id: RawId,
    x: f64,
    y: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawShot {
    cue_ball: RawId,
    object_ball: RawId,
    pocket: Option<String>,
    v0: f64,
    phi: f64,
    theta: f64,
    a: f64,
    b: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTarget {
    x: f64,
    y: f64,
    radius: f64,
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
    physics: Option<toml::Table>,
}

/// What [`StudyConfig::assemble`] builds a study from: the parts every scenario format
/// gives, with the keys to name in errors.
pub(crate) struct Parts {
    pub source: String,
    pub table_name: String,
    pub table: Table,
    pub params: SimParams,
    pub balls: Vec<Spot>,
    pub cue: String,
    pub intended: String,
    pub pocket: Option<String>,
    pub shot: CueStrike,
    pub target: Option<Target>,
    pub noise_factor: f64,
    pub noise: Noise,
    /// The keys of the cue ball, the object ball and the pocket, and the balls' list.
    pub keys: Keys,
}

/// The names a format gives its keys, for error messages.
pub(crate) struct Keys {
    pub cue: &'static str,
    pub intended: &'static str,
    pub pocket: &'static str,
    pub balls: &'static str,
    pub shot: &'static str,
}

impl StudyConfig {
    /// The built-in study (`examples/study.toml`, compiled in).
    pub fn builtin() -> StudyConfig {
        StudyConfig::parse(BUILTIN_TOML, BUILTIN_NAME, None).expect("the built-in study is valid")
    }

    /// Reads and validates a scenario file (a table file it names is taken relative to
    /// the scenario's folder).
    pub fn read(path: &std::path::Path) -> Result<StudyConfig, Error> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: path.display().to_string(),
            source,
        })?;
        StudyConfig::parse(&text, &path.display().to_string(), path.parent())
    }

    /// Parses and validates scenario text; errors name `source` as the file. A table file
    /// is looked for relative to `dir` (the working directory when `None`).
    pub fn parse(
        text: &str,
        source: &str,
        dir: Option<&std::path::Path>,
    ) -> Result<StudyConfig, Error> {
        let raw: RawFile = toml::from_str(text).map_err(|e| toml_error(&e, text, source))?;
        let err = |msg: String| Error::from(InputError::new(msg).in_file(source));
        let finite = |key: &str, v: f64| -> Result<f64, Error> {
            if v.is_finite() {
                Ok(v)
            } else {
                Err(err(format!(
                    "key `{key}` is {v}, it must be a finite number"
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

        let table_name = raw.table.kind.clone().unwrap_or_else(|| "9ft".to_owned());
        // a size of its own (`l`, `w`), for a built-in table
        let extent = |key: &str, v: Option<f64>| match v {
            Some(x) if !(x.is_finite() && x > 0.0) => Err(err(format!(
                "key `table.{key}` is {x}, it must be finite and greater than 0"
            ))),
            _ => Ok(v),
        };
        let (l, w) = (extent("l", raw.table.l)?, extent("w", raw.table.w)?);
        let sized = l.is_some() || w.is_some();
        let table = match table_name.as_str() {
            "9ft" | "7ft" | "rectangle" if sized => {
                let specs = if table_name == "7ft" {
                    PocketTableSpecs::seven_foot()
                } else {
                    PocketTableSpecs::default()
                };
                let specs = PocketTableSpecs {
                    l: l.unwrap_or(specs.l),
                    w: w.unwrap_or(specs.w),
                    ..specs
                };
                if table_name == "rectangle" {
                    Table::rectangle(specs.w, specs.l, specs.cushion_height)?
                } else {
                    Table::pocket_table(&specs)
                }
            }
            builtin if BUILTIN_TABLES.contains(&builtin) => table_by_name(builtin)?,
            _ if sized => {
                return Err(err(format!(
                    "keys `table.l`, `table.w`: the table {table_name} has its own size (they \
                     size the pocket tables 9ft and 7ft and the rectangle)"
                )));
            }
            file => {
                let path = match dir {
                    Some(d) if !std::path::Path::new(file).is_absolute() => d.join(file),
                    _ => std::path::PathBuf::from(file),
                };
                table_by_name(&path.display().to_string()).map_err(|e| match e {
                    Error::Io { path, source } => err(format!(
                        "key `table.kind`: cannot read the table file {path}: {source} (the \
                         kind is a built-in table, {}, or a JSON table file)",
                        BUILTIN_TABLES.join(", ")
                    )),
                    other => other,
                })?
            }
        };

        let params = match &raw.physics {
            Some(t) => {
                let PhysicsValue::Table(entries) = PhysicsValue::from_toml_table(t) else {
                    unreachable!("a table converts to a table")
                };
                let src = PhysicsSource {
                    file: source,
                    prefix: "physics.",
                    toml_text: Some(text),
                };
                physics_from_entries(&entries, &src, true)?
            }
            // the balls of the table's game (snooker, carom), as pooltool's defaults
            None => SimParams {
                ball: crate::io::table_json::default_ball_params(&table_name),
                ..SimParams::default()
            },
        };

        let balls = raw
            .balls
            .iter()
            .map(|b| Spot {
                id: b.id.text(),
                x: b.x,
                y: b.y,
            })
            .collect();
        let s = &raw.shot;
        let shot = CueStrike {
            v0: finite("shot.v0", s.v0)?,
            phi: finite("shot.phi", s.phi)?,
            theta: finite("shot.theta", s.theta)?,
            a: finite("shot.a", s.a)?,
            b: finite("shot.b", s.b)?,
        };
        let target = match &raw.target {
            Some(t) => Some(Target {
                x: finite("target.x", t.x)?,
                y: finite("target.y", t.y)?,
                radius: non_negative("target.radius", t.radius)?,
            }),
            None => None,
        };
        let n = &raw.noise;
        let d = Noise::default();
        let noise = Noise {
            v0: non_negative("noise.v0", n.v0.unwrap_or(d.v0))?,
            phi: non_negative("noise.phi", n.phi.unwrap_or(d.phi))?,
            theta: non_negative("noise.theta", n.theta.unwrap_or(d.theta))?,
            a: non_negative("noise.a", n.a.unwrap_or(d.a))?,
            b: non_negative("noise.b", n.b.unwrap_or(d.b))?,
            physics: match &n.physics {
                Some(t) => physics_spread(t, &params, text, source)?,
                None => PhysicsSpread::default(),
            },
        };
        let noise_factor = non_negative("noise.factor", n.factor.unwrap_or(1.0))?;
        let config = StudyConfig::assemble(Parts {
            source: source.to_owned(),
            table_name,
            table,
            params,
            balls,
            cue: s.cue_ball.text(),
            intended: s.object_ball.text(),
            pocket: s.pocket.clone(),
            shot,
            target,
            noise_factor,
            noise,
            keys: Keys {
                cue: "shot.cue_ball",
                intended: "shot.object_ball",
                pocket: "shot.pocket",
                balls: "balls",
                shot: "shot",
            },
        })?;
        match &raw.game {
            Some(g) => {
                let game = study_game(g, &config)
                    .map_err(|m| Error::from(InputError::new(m).in_file(source)))?;
                Ok(StudyConfig {
                    game: Some(game),
                    ..config
                })
            }
            None => Ok(config),
        }
    }

    /// Checks the parts every format shares and builds the study: at least two balls with
    /// distinct ids, each on the table and none overlapping another, the cue and object
    /// balls among them and distinct, the pocket one of the table's, the strike on the
    /// ball (`a² + b² ≤ 1`), `0 ≤ θ < 90°`, `V0 > 0`.
    pub(crate) fn assemble(p: Parts) -> Result<StudyConfig, Error> {
        let source = p.source.as_str();
        let err = |msg: String| Error::from(InputError::new(msg).in_file(source));
        let k = &p.keys;
        if p.balls.len() < 2 {
            return Err(err(format!(
                "key `{}`: a study needs at least 2 balls, this one has {}",
                k.balls,
                p.balls.len()
            )));
        }
        for (i, b) in p.balls.iter().enumerate() {
            if let Some(prev) = p.balls[..i].iter().position(|q| q.id == b.id) {
                return Err(err(format!(
                    "key `{}[{i}].id`: ball \"{}\" is also {}[{prev}]",
                    k.balls, b.id, k.balls
                )));
            }
            for (name, v) in [("x", b.x), ("y", b.y)] {
                if !v.is_finite() {
                    return Err(err(format!(
                        "key `{}[{i}].{name}` (ball \"{}\") is {v}, it must be a finite number",
                        k.balls, b.id
                    )));
                }
            }
        }
        let r = p.params.ball.r;
        let states: Vec<BallState> = p
            .balls
            .iter()
            .map(|b| BallState::at_rest(b.x, b.y, r))
            .collect();
        check_layout(&p.table, r, &states).map_err(|e| match e {
            SimError::Ball { index, reason } => err(format!(
                "key `{}[{index}]` (ball \"{}\"): {reason}",
                k.balls, p.balls[index].id
            )),
            SimError::Overlap {
                first,
                second,
                depth,
            } => err(format!(
                "key `{}[{second}]` (ball \"{}\"): it overlaps ball \"{}\" ({}[{first}]) by \
                 {depth:.3e} m: their centres are less than 2R = {} apart",
                k.balls,
                p.balls[second].id,
                p.balls[first].id,
                k.balls,
                2.0 * r
            )),
            other => err(other.to_string()),
        })?;
        let find = |key: &str, id: &str| {
            p.balls.iter().position(|b| b.id == id).ok_or_else(|| {
                err(format!(
                    "key `{key}` is \"{id}\", which is not the id of any of the balls"
                ))
            })
        };
        let cue = find(k.cue, &p.cue)?;
        let intended = find(k.intended, &p.intended)?;
        if cue == intended {
            return Err(err(format!(
                "key `{}` is \"{}\", the cue ball itself",
                k.intended, p.intended
            )));
        }
        let pocket =
            match &p.pocket {
                Some(id) => Some(p.table.pocket_ids.iter().position(|q| q == id).ok_or_else(
                    || {
                        err(format!(
                            "key `{}` is \"{id}\", which is not a pocket of the table \
                             (its pockets: {})",
                            k.pocket,
                            if p.table.pocket_ids.is_empty() {
                                "none".to_owned()
                            } else {
                                p.table.pocket_ids.join(", ")
                            }
                        ))
                    },
                )?),
                None => None,
            };
        let s = p.shot;
        if s.v0 <= 0.0 || s.v0.is_nan() {
            return Err(err(format!(
                "key `{}.v0` is {}, the cue speed must be greater than 0",
                k.shot, s.v0
            )));
        }
        if !(0.0..90.0).contains(&s.theta) {
            return Err(err(format!(
                "key `{}.theta` is {}, the cue elevation must be in [0, 90) degrees",
                k.shot, s.theta
            )));
        }
        if s.a * s.a + s.b * s.b > 1.0 {
            return Err(err(format!(
                "keys `{0}.a` = {1} and `{0}.b` = {2}: the tip must hit the ball (a² + b² ≤ 1)",
                k.shot, s.a, s.b
            )));
        }
        Ok(StudyConfig {
            source: p.source,
            table_name: p.table_name,
            table: p.table,
            params: p.params,
            balls: p.balls,
            cue,
            intended,
            pocket,
            shot: s,
            target: p.target,
            noise_factor: p.noise_factor,
            noise: p.noise,
            game: None,
        })
    }

    /// The study with another physics spread (`kisstime shots --physics-noise`, Python's
    /// `shot_study(physics_noise=...)`), replacing the scenario's `[noise.physics]`: `text`
    /// is that table's body as TOML (`u_r = 0.1`, `e_c = [0.8, 0.9]`), checked as the file's
    /// is, errors naming `source`.
    pub fn with_physics_noise(mut self, text: &str, source: &str) -> Result<StudyConfig, Error> {
        let t: toml::Table = toml::from_str(text).map_err(|e| toml_error(&e, text, source))?;
        self.noise.physics = physics_spread(&t, &self.params, text, source)?;
        Ok(self)
    }

    /// The study with other physical parameters (`kisstime shots --physics`, Python's
    /// `shot_study(physics=...)`), which replace the scenario's `[physics]` as a whole.
    /// The layout is checked again with the new radius R: a ball that now overlaps
    /// another or a cushion is an [`Error::Input`] naming the scenario's key and ball and
    /// `physics_source`, where R came from.
    pub fn with_physics(
        self,
        params: SimParams,
        physics_source: &str,
    ) -> Result<StudyConfig, Error> {
        let r = params.ball.r;
        let states: Vec<BallState> = self
            .balls
            .iter()
            .map(|b| BallState::at_rest(b.x, b.y, r))
            .collect();
        check_layout(&self.table, r, &states).map_err(|e| {
            let (index, what) = match e {
                SimError::Ball { index, reason } => (index, reason),
                SimError::Overlap {
                    first,
                    second,
                    depth,
                } => (
                    second,
                    format!(
                        "it overlaps ball \"{}\" by {depth:.3e} m: their centres are less than \
                         2R = {} apart",
                        self.balls[first].id,
                        2.0 * r
                    ),
                ),
                other => (0, other.to_string()),
            };
            Error::from(
                InputError::new(format!(
                    "key `balls[{index}]` (ball \"{}\"), with R = {r} from {physics_source}: \
                     {what}",
                    self.balls[index.min(self.balls.len() - 1)].id
                ))
                .in_file(&self.source),
            )
        })?;
        Ok(StudyConfig { params, ..self })
    }

    /// The balls at rest, in order (the simulator's input).
    pub fn initial(&self) -> Vec<BallState> {
        let r = self.params.ball.r;
        self.balls
            .iter()
            .map(|b| BallState::at_rest(b.x, b.y, r))
            .collect()
    }

    /// The cue ball's id.
    pub fn cue_id(&self) -> &str {
        &self.balls[self.cue].id
    }

    /// The intended object ball's id.
    pub fn intended_id(&self) -> &str {
        &self.balls[self.intended].id
    }

    /// The called pocket's id, if any.
    pub fn pocket_id(&self) -> Option<&str> {
        self.pocket.map(|k| self.table.pocket_ids[k].as_str())
    }

    /// The standard deviations in effect: the file's, times its factor.
    pub fn sigma(&self) -> Noise {
        self.noise.scaled(self.noise_factor)
    }
}

/// A study's `[noise.physics]`: per pooltool ball parameter, a number `x ≥ 0` (the value
/// varies by ±x relative: `u_r = 0.1` is ±10 %) or an array `[lo, hi]` of absolute values
/// around the study's own. Every value a sample can draw must be in range
/// ([`SimParams::validate`]); `R` cannot vary (it would move the layout). Errors name the
/// key and its line.
fn physics_spread(
    t: &toml::Table,
    base: &SimParams,
    text: &str,
    source: &str,
) -> Result<PhysicsSpread, Error> {
    use crate::io::physics::BALL_KEYS;
    let err = |key: &str, msg: String| {
        let mut e = InputError::new(format!("key `noise.physics.{key}`: {msg}")).in_file(source);
        let needle = format!("{key} =");
        if let Some(at) = text
            .lines()
            .position(|l| l.trim_start().starts_with(&needle))
        {
            e = e.at_line(at as u64 + 1);
        }
        Error::from(e)
    };
    let mut spread = PhysicsSpread::default();
    for (key, value) in t {
        let Some(k) = BALL_KEYS.iter().position(|b| b == key) else {
            return Err(err(
                key,
                format!(
                    "not one of pooltool's ball parameters that may vary ({})",
                    BALL_KEYS
                        .iter()
                        .filter(|k| **k != "R")
                        .copied()
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        };
        if key == "R" {
            return Err(err(
                key,
                "the ball size cannot vary per sample (it would move the layout)".to_owned(),
            ));
        }
        let v = base_value(base, k);
        let number = |x: &toml::Value| match x {
            toml::Value::Float(f) => Some(*f),
            toml::Value::Integer(i) => Some(*i as f64),
            _ => None,
        };
        let (lo, hi) = match value {
            toml::Value::Array(a) if a.len() == 2 => match (number(&a[0]), number(&a[1])) {
                (Some(lo), Some(hi)) if lo.is_finite() && hi.is_finite() && lo <= hi && v > 0.0 => {
                    (lo / v - 1.0, hi / v - 1.0)
                }
                _ => {
                    return Err(err(
                        key,
                        "an array must be [lo, hi], two finite numbers with lo ≤ hi".to_owned(),
                    ));
                }
            },
            other => match number(other) {
                Some(x) if x.is_finite() && x >= 0.0 => (-x, x),
                _ => {
                    return Err(err(
                        key,
                        "give a relative spread (a number ≥ 0: 0.1 is ±10 %) or [lo, hi]"
                            .to_owned(),
                    ));
                }
            },
        };
        // both ends must be valid parameters
        for rel in [lo, hi] {
            let mut p = *base;
            *ball_field(&mut p, k) *= 1.0 + rel;
            if let Err(e) = p.validate() {
                return Err(err(
                    key,
                    format!("{} is out of range: {e}", v * (1.0 + rel)),
                ));
            }
        }
        spread.ranges[k] = Some((lo, hi));
    }
    Ok(spread)
}

/// The study's value of ball parameter `k` (`BALL_KEYS` order; `u_sp_proportionality` as
/// `u_sp / R`).
fn base_value(p: &SimParams, k: usize) -> f64 {
    let mut q = *p;
    let v = *ball_field(&mut q, k);
    if k == 4 { v / p.ball.r } else { v }
}

/// The field of `p` that ball parameter `k` (`BALL_KEYS` order) scales: `u_sp` for
/// `u_sp_proportionality` (R is fixed, so scaling the proportionality scales `u_sp`).
pub(crate) fn ball_field(p: &mut SimParams, k: usize) -> &mut f64 {
    let b = &mut p.ball;
    match k {
        0 => &mut b.m,
        1 => &mut b.r,
        2 => &mut b.u_s,
        3 => &mut b.u_r,
        4 => &mut b.u_sp,
        5 => &mut b.u_b,
        6 => &mut b.e_b,
        7 => &mut b.e_c,
        8 => &mut b.f_c,
        _ => &mut b.g,
    }
}

/// A study's `[game]` checked against its balls and table: the rules by name, pool games'
/// ball numbers (the cue ball 0, the others their ids, 1 to 15; snooker's 1 to 21 or
/// pooltool's names, `red_01` … `black`), the hittable balls and the call among the balls,
/// the called pocket among the table's, the score. Errors name the key.
fn study_game(g: &RawGame, config: &StudyConfig) -> Result<StudyGame, String> {
    let rules = Rules::from_name(&g.rules).map_err(|e| format!("key `game.rules`: {e}"))?;
    let (numbered, words) = match rules {
        Rules::ThreeCushion => (None, ""),
        Rules::Snooker => (
            Some(1..=21),
            "numbers its object balls 1 to 21 (or names them red_01 … red_15, yellow, \
             green, brown, blue, pink, black)",
        ),
        Rules::NineBall | Rules::EightBall => (Some(1..=15), "numbers its object balls 1 to 15"),
    };
    let mut ids = Vec::with_capacity(config.balls.len());
    for (i, b) in config.balls.iter().enumerate() {
        let id = match &numbered {
            _ if i == config.cue => 0,
            None => i as i64,
            Some(range) => match b.id.parse::<i64>().ok().or_else(|| rules.ball_named(&b.id)) {
                Some(n) if range.contains(&n) => n,
                _ => {
                    return Err(format!(
                        "key `balls[{i}].id` is \"{}\": {} {words} (the cue ball, \"{}\", is \
                         its 0)",
                        b.id, g.rules, config.balls[config.cue].id
                    ));
                }
            },
        };
        ids.push(id);
    }
    let number = |key: &str, id: &RawId| {
        let text = id.text();
        config
            .balls
            .iter()
            .position(|b| b.id == text)
            .map(|i| ids[i])
            .ok_or_else(|| {
                format!("key `{key}` is \"{text}\", which is not the id of any of the balls")
            })
    };
    let mut hittable = Vec::with_capacity(g.hittable.len());
    for (k, h) in g.hittable.iter().enumerate() {
        hittable.push(number(&format!("game.hittable[{k}]"), h)?);
    }
    let ball_call = match &g.ball_call {
        Some(b) => Some(number("game.ball_call", b)?),
        None => None,
    };
    let pocket_call = match &g.pocket_call {
        Some(p) => Some(
            config
                .table
                .pocket_ids
                .iter()
                .position(|q| q == p)
                .ok_or_else(|| {
                    format!(
                        "key `game.pocket_call` is \"{p}\", which is not a pocket of the table \
                         (its pockets: {})",
                        config.table.pocket_ids.join(", ")
                    )
                })?,
        ),
        None => None,
    };
    let context = rules.context(Context {
        wpa: g.wpa,
        break_shot: g.break_shot,
        hittable: Context::balls(hittable),
        call_shot: false,
        ball_call,
        pocket_call,
        score: [g.score, g.opponent_score],
    });
    rules
        .check_context(&context)
        .map_err(|e| format!("table `game`: {e}"))?;
    Ok(StudyGame {
        rules,
        context,
        ids,
    })
}
