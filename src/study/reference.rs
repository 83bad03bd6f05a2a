//! The shot-study reference format (`data/studies/README.md`): a scenario as JSON in
//! pooltool's frame and vocabulary, and one outcome row per sample with pooltool's columns
//! ([`REFERENCE_COLUMNS`]), so that a study can be checked against pooltool sample by
//! sample (`examples/replay_study.rs`, `tests/study_reference.rs`).
//!
//! The scenario:
//!
//! ```json
//! {
//!   "table": {"type": "pocket", "l": 2.54, "w": 1.27},
//!   "balls": [{"id": "cue", "x": 1.1829, "y": 1.1908}, {"id": "7", "x": 0.55, "y": 0.9}],
//!   "intended": "7",
//!   "target_pocket": "lb",
//!   "nominal_shot": {"V0": 1.5, "phi": 201.75, "theta": 5.0, "a": 0.0, "b": 0.2}
//! }
//! ```
//!
//! `table.type` is `pocket` (pooltool's `PocketTableSpecs` with that `l` and `w`, every
//! other spec at its default) or `rectangle` (that playing surface with four rails and no
//! pockets). The cue ball is the ball with id `cue`. An optional `ball_params` object sets
//! the balls' physics with pooltool's `BallParams` names, as a pooltool table JSON's
//! `ball_params` does ([`crate::io::physics::ball_params_from_json`]; pooltool's defaults
//! without it). Other keys (`comment`, …) are ignored. The cue and the noise are
//! pooltool's defaults and the reference's sigmas, which are this crate's defaults.

use serde::Deserialize;

use super::config::{Keys, Noise, Parts, Spot, StudyConfig};
use super::run::{FirstContact, Sample};
use crate::error::{Error, InputError};
use crate::io::csv::format_finite;
use crate::io::physics::ball_params_from_json;
use crate::model::sim_params::SimParams;
use crate::model::table::{PocketTableSpecs, Table};
use crate::resolve::stick_ball::CueStrike;

/// The reference's outcome columns, in order.
pub const REFERENCE_COLUMNS: &str = "sample,first_contact,first_t,intended_potted,intended_pocket,cue_potted,potted,cue_x,cue_y,n_events,duration";

#[derive(Deserialize)]
struct RawScenario {
    table: RawTable,
    balls: Vec<RawBall>,
    intended: String,
    target_pocket: Option<String>,
    nominal_shot: RawShot,
    ball_params: Option<serde_json::Value>,
}

#[derive(Deserialize)]
struct RawTable {
    #[serde(rename = "type")]
    kind: String,
    l: Option<f64>,
    w: Option<f64>,
}

#[derive(Deserialize)]
struct RawBall {
    id: String,
    x: f64,
    y: f64,
}

#[derive(Deserialize)]
#[allow(non_snake_case)]
struct RawShot {
    V0: f64,
    phi: f64,
    theta: f64,
    a: f64,
    b: f64,
}

impl StudyConfig {
    /// Reads a scenario in the reference format (module docs).
    pub fn read_reference(path: &std::path::Path) -> Result<StudyConfig, Error> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: path.display().to_string(),
            source,
        })?;
        StudyConfig::parse_reference(&text, &path.display().to_string())
    }

    /// Parses a scenario in the reference format; errors name `source`, the line and key.
    pub fn parse_reference(text: &str, source: &str) -> Result<StudyConfig, Error> {
        let raw: RawScenario = serde_json::from_str(text).map_err(|e| {
            Error::from(
                InputError::new(format!("not a study scenario: {e}"))
                    .in_file(source)
                    .at_line(e.line() as u64),
            )
        })?;
        let err = |msg: String| Error::from(InputError::new(msg).in_file(source));
        let specs = PocketTableSpecs::default();
        let extent = |key: &str, v: Option<f64>, default: f64| match v {
            Some(x) if x.is_finite() && x > 0.0 => Ok(x),
            None => Ok(default),
            Some(x) => Err(err(format!(
                "key `table.{key}` is {x}, it must be finite and greater than 0"
            ))),
        };
        let l = extent("l", raw.table.l, specs.l)?;
        let w = extent("w", raw.table.w, specs.w)?;
        let table = match raw.table.kind.as_str() {
            "pocket" => Table::pocket_table(&PocketTableSpecs { l, w, ..specs }),
            "rectangle" => Table::rectangle(w, l, specs.cushion_height)?,
            other => {
                return Err(err(format!(
                    "key `table.type` is \"{other}\"; expected \"pocket\" or \"rectangle\""
                )));
            }
        };
        let s = &raw.nominal_shot;
        let shot = CueStrike {
            v0: s.V0,
            phi: s.phi,
            theta: s.theta,
            a: s.a,
            b: s.b,
        };
        for (key, v) in [
            ("V0", shot.v0),
            ("phi", shot.phi),
            ("theta", shot.theta),
            ("a", shot.a),
            ("b", shot.b),
        ] {
            if !v.is_finite() {
                return Err(err(format!(
                    "key `nominal_shot.{key}` is {v}, it must be a finite number"
                )));
            }
        }
        let params = match &raw.ball_params {
            Some(v) => SimParams {
                ball: ball_params_from_json(v, source, "ball_params.")?,
                ..SimParams::default()
            },
            None => SimParams::default(),
        };
        StudyConfig::assemble(Parts {
            source: source.to_owned(),
            table_name: format!("{} l={l} w={w}", raw.table.kind),
            table,
            params,
            balls: raw
                .balls
                .into_iter()
                .map(|b| Spot {
                    id: b.id,
                    x: b.x,
                    y: b.y,
                })
                .collect(),
            cue: "cue".to_owned(),
            intended: raw.intended,
            pocket: raw.target_pocket,
            shot,
            target: None,
            noise_factor: 1.0,
            noise: Noise::default(),
            keys: Keys {
                cue: "balls (the id \"cue\")",
                intended: "intended",
                pocket: "target_pocket",
                balls: "balls",
                shot: "nominal_shot",
            },
        })
    }
}

/// The reference's `first_contact` word: the ball's id, `cushion`, `pocket`, `stopped`
/// (empty when nothing involved the cue ball).
pub fn first_contact_word<'a>(config: &'a StudyConfig, f: &FirstContact) -> &'a str {
    match f {
        FirstContact::Ball(k) => &config.balls[*k as usize].id,
        FirstContact::Cushion { .. } => "cushion",
        FirstContact::Pocket(_) => "pocket",
        FirstContact::Stopped => "stopped",
        FirstContact::Nothing => "",
    }
}

/// The `potted` field: `ball@pocket` in pocketing order, joined by `;`.
pub fn potted_field(config: &StudyConfig, sample: &Sample) -> String {
    let mut s = String::new();
    for (k, pot) in sample.potted.iter().enumerate() {
        if k > 0 {
            s.push(';');
        }
        s.push_str(&config.balls[pot.ball as usize].id);
        s.push('@');
        s.push_str(&config.table.pocket_ids[pot.pocket as usize]);
    }
    s
}

/// Writes `samples` as rows of [`REFERENCE_COLUMNS`] (header first), `ids[k]` being the
/// `sample` of `samples[k]`. Floats are the shortest text that reads back as the same f64.
pub fn write_reference_csv(
    out: &mut dyn std::io::Write,
    config: &StudyConfig,
    ids: &[i64],
    samples: &[Sample],
) -> std::io::Result<()> {
    writeln!(out, "{REFERENCE_COLUMNS}")?;
    let mut buf = ryu::Buffer::new();
    let mut num = |v: f64| -> String { format_finite(v, &mut buf).to_owned() };
    for (id, s) in ids.iter().zip(samples) {
        let intended = s.pocket_of(config.intended);
        writeln!(
            out,
            "{id},{},{},{},{},{},{},{},{},{},{}",
            first_contact_word(config, &s.first),
            num(s.first_t),
            u8::from(intended.is_some()),
            intended.map_or("", |p| config.table.pocket_ids[p].as_str()),
            u8::from(s.pocket_of(config.cue).is_some()),
            potted_field(config, s),
            num(s.cue_final.0),
            num(s.cue_final.1),
            s.n_events,
            num(s.duration),
        )?;
    }
    Ok(())
}
