//! The study's driver: every sample from the strike to what the cue ball meets first.
//!
//! Every sample is one table of a [`Batch`] (table id = sample index, ball ids = the
//! study's). Step after step, the still-running samples of a chunk go to the engine
//! together, which answers each table's next ball–ball contact within the cue ball's current
//! motion (the per-pair horizon ends there); per sample the earliest of that contact, the
//! cue ball reaching a cushion line, and the end of the motion decides: a contact or a
//! cushion ends the sample, the end of a motion advances the cue ball to its next state
//! (sliding → rolling → still) and the sample goes round again. Only the cue ball moves;
//! nothing is resolved after the first contact.

use super::config::{Noise, StudyConfig};
use super::cue_ball::end_of_motion;
use super::noise::noisy_strike;
use super::rectangle::{Cushion, cushion_time};
use super::strike::{Strike, cue_strike};
use crate::batch::Batch;
use crate::engine::Engine;
use crate::error::Error;
use crate::model::{Ball, Vec2, dot, norm};
use crate::motion::ball_path;
use crate::query::pair_contact;

/// Samples handed to the engine at a time (memory stays bounded whatever the sample count).
pub const CHUNK: usize = 65_536;

/// What ended a sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Outcome {
    /// The cue ball touched this ball first.
    Ball(i64),
    /// The cue ball reached this cushion before touching any ball.
    Cushion(Cushion),
    /// The cue ball stopped without touching anything.
    Stopped,
}

impl Outcome {
    /// `ball`, `cushion` or `stopped`.
    pub fn kind(self) -> &'static str {
        match self {
            Outcome::Ball(_) => "ball",
            Outcome::Cushion(_) => "cushion",
            Outcome::Stopped => "stopped",
        }
    }
}

/// The result of one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// What ended it.
    pub outcome: Outcome,
    /// When, in seconds after the strike.
    pub t: f64,
    /// The cue ball's centre then.
    pub cue: Vec2,
    /// The cue ball's speed then, m/s.
    pub speed: f64,
    /// The contact point: on the object ball (halfway between the centres) for a ball, on
    /// the cushion nose for a cushion; NaN when the cue ball stopped.
    pub contact: Vec2,
    /// For a ball: the cut angle in degrees, the signed angle from the cue ball's velocity
    /// at contact to the line of centres (cue ball to object ball): 0 is a full-ball hit,
    /// positive sends the object ball to the left of the cue ball's direction
    /// (counterclockwise seen from above), ±90 a graze. NaN otherwise.
    pub cut: f64,
}

/// The columns of a per-sample table (the CLI's `-o samples.csv`): the noisy strike, the
/// outcome, the ball or cushion, the time, the cue ball's centre and speed, the contact
/// point, and the cut angle.
pub const SAMPLE_COLUMNS: &str = "sample,v0,phi,theta,a,b,outcome,ball,cushion,t,cue_x,cue_y,speed,contact_x,contact_y,cut_angle";

/// What one step of a sample decided.
enum Step {
    Done(Sample),
    /// The cue ball's next motion, and the time it starts.
    Next(Ball, f64),
}

/// One step of a sample whose cue ball is `cue` at time `elapsed`, given the first ball
/// contact within its current motion (`(t, object id)`, times relative to the step).
fn step(config: &StudyConfig, cue: &Ball, elapsed: f64, hit: Option<(f64, i64)>) -> Step {
    let p = &config.params;
    let path = ball_path(cue, p);
    if !cue.state.translates() {
        let at = Vec2::new(cue.x, cue.y);
        return Step::Done(Sample {
            outcome: Outcome::Stopped,
            t: elapsed,
            cue: at,
            speed: 0.0,
            contact: Vec2::new(f64::NAN, f64::NAN),
            cut: f64::NAN,
        });
    }
    let cushion = cushion_time(&path, &config.table, p.radius, path.tmax);
    let at = |t: f64| path.at(t);
    // a ball contact wins a tie with a cushion
    if let Some((t, id)) = hit.filter(|&(t, _)| cushion.is_none_or(|(tc, _)| t <= tc)) {
        let spot = config
            .balls
            .iter()
            .find(|b| b.id == id)
            .expect("the engine answers with the config's ids");
        let centre = at(t);
        let object = Vec2::new(spot.x, spot.y);
        let v = path.velocity_at(t);
        let n = object - centre;
        let cut = (v.x * n.y - v.y * n.x).atan2(dot(v, n)).to_degrees();
        return Step::Done(Sample {
            outcome: Outcome::Ball(id),
            t: elapsed + t,
            cue: centre,
            speed: norm(v),
            contact: 0.5 * (centre + object),
            cut,
        });
    }
    if let Some((t, c)) = cushion {
        let centre = at(t);
        return Step::Done(Sample {
            outcome: Outcome::Cushion(c),
            t: elapsed + t,
            cue: centre,
            speed: norm(path.velocity_at(t)),
            contact: centre + p.radius * c.normal(),
            cut: f64::NAN,
        });
    }
    let (next, dt) = end_of_motion(cue, p);
    Step::Next(next, elapsed + dt)
}

/// Runs the study: `samples` noisy strikes from `seed`, every ball contact answered by
/// `engine`. `progress(done, total)` is called after each chunk. The samples come back in
/// index order. A study whose samples would not fit the available memory is refused
/// before it starts ([`Error::TooLarge`]).
pub fn run_study(
    config: &StudyConfig,
    sigma: &Noise,
    samples: usize,
    seed: u64,
    engine: &mut Engine,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<Sample>, Error> {
    crate::limits::check_memory(
        &format!("a study of {samples} samples"),
        (samples as u64).saturating_mul(std::mem::size_of::<Sample>() as u64),
    )?;
    let mut out = Vec::with_capacity(samples);
    let objects = config.object_balls();
    let start = config.cue_spot();
    let cue_id = config.cue_ball;
    let mut first = 0;
    while first < samples {
        let n = CHUNK.min(samples - first);
        let mut cue: Vec<Ball> = (0..n)
            .map(|k| {
                let s = noisy_strike(config, sigma, seed, (first + k) as u64);
                cue_strike(start.x, start.y, &s, config.params.radius, &config.masses)
            })
            .collect();
        let mut elapsed = vec![0.0; n];
        let mut done: Vec<Option<Sample>> = vec![None; n];
        let mut active: Vec<usize> = (0..n).collect();
        while !active.is_empty() {
            // samples whose cue ball no longer moves need no engine
            let mut moving = Vec::with_capacity(active.len());
            for &k in &active {
                if cue[k].state.translates() {
                    moving.push(k);
                } else if let Step::Done(s) = step(config, &cue[k], elapsed[k], None) {
                    done[k] = Some(s);
                }
            }
            if moving.is_empty() {
                break;
            }
            let mut batch = Batch::new();
            for &k in &moving {
                batch.push_table(
                    (first + k) as i64,
                    std::iter::once((cue_id, cue[k])).chain(objects.iter().copied()),
                )?;
            }
            let next = engine.next_collisions(&batch, &config.params)?;
            let mut still = Vec::new();
            for (nc, &k) in next.iter().zip(&moving) {
                let hit = match (nc.status.is_contact(), nc.pair) {
                    (true, Some((i, j))) => Some((nc.t, if i == cue_id { j } else { i })),
                    _ => None,
                };
                match step(config, &cue[k], elapsed[k], hit) {
                    Step::Done(s) => done[k] = Some(s),
                    Step::Next(ball, t) => {
                        cue[k] = ball;
                        elapsed[k] = t;
                        still.push(k);
                    }
                }
            }
            active = still;
        }
        out.extend(done.into_iter().map(|s| s.expect("every sample ends")));
        first += n;
        progress(first, samples);
    }
    Ok(out)
}

/// One sample on its own, on the CPU in f64, with the balls touching at the centre distance
/// `contact_distance` (normally `2R`): the reference for checks, and, with `2R ± δ`, the
/// test of whether a sample grazes a ball within `δ` ([`grazes`]).
pub fn simulate_one(config: &StudyConfig, strike: &Strike, contact_distance: f64) -> Sample {
    let p = &config.params;
    let start = config.cue_spot();
    let mut cue = cue_strike(start.x, start.y, strike, p.radius, &config.masses);
    let mut elapsed = 0.0;
    let objects = config.object_balls();
    loop {
        let mut hit: Option<(f64, i64)> = None;
        if cue.state.translates() {
            let cp = ball_path(&cue, p);
            for (id, ball) in &objects {
                let c = pair_contact(&cp, &ball_path(ball, p), 0.5 * contact_distance);
                if c.status.is_contact() && hit.is_none_or(|(t, _)| c.t < t) {
                    hit = Some((c.t, *id));
                }
            }
        }
        match step(config, &cue, elapsed, hit) {
            Step::Done(s) => return s,
            Step::Next(ball, t) => {
                cue = ball;
                elapsed = t;
            }
        }
    }
}

/// Whether the outcome of `strike` changes when the balls' contact distance moves from
/// `2R − δ/2` to `2R + δ/2`: the sample grazes a ball within `δ`, and a backend computing
/// within that margin may classify it either way.
pub fn grazes(config: &StudyConfig, strike: &Strike, delta: f64) -> bool {
    let d = 2.0 * config.params.radius;
    simulate_one(config, strike, d - 0.5 * delta).outcome
        != simulate_one(config, strike, d + 0.5 * delta).outcome
}
