//! The Monte Carlo shot study: re-play one intended shot under cue noise many times and
//! record what the cue ball touches first.
//!
//! Every sample is one table of a [`Batch`] (table id = sample index, ball ids = the
//! scenario's). Step after step, the still-running samples of a chunk go to the engine
//! together, which answers each table's next ball–ball contact within the cue ball's current
//! motion (the per-pair horizon ends there); per sample the earliest of that contact, the
//! cue ball reaching a cushion line, and the end of the motion decides: a contact or a
//! cushion ends the sample, the end of a motion advances the cue ball to its next state
//! (sliding → rolling → still) and the sample goes round again. Only the cue ball moves;
//! nothing is resolved after the first contact.
//!
//! Noise: sample `i` draws five standard normals, in the order `v0, phi, theta, a, b`, from
//! a PCG generator seeded by `(seed, i)` only, so results do not depend on the backend, the
//! thread count or the chunking.

use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rand_pcg::Pcg64Mcg;

use crate::batch::Batch;
use crate::engine::Engine;
use crate::error::Error;
use crate::physics::{Ball, Vec2, ball_path, dot, norm};
use crate::scenario::{Noise, Scenario};
use crate::shot::{Cushion, Strike, cue_strike, cushion_time, end_of_motion};
use crate::solver::pair_contact;

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

/// The noisy strike of sample `i` (module docs): the intended strike plus `sigma` times
/// five standard normals, with the offsets' σ (metres) divided by R, then clamped into the
/// physical range ([`Strike::clamped`]).
pub fn noisy_strike(scenario: &Scenario, sigma: &Noise, seed: u64, i: u64) -> Strike {
    let mut rng = Pcg64Mcg::seed_from_u64(mix(seed, i));
    let mut z = [0.0f64; 5];
    for v in &mut z {
        *v = StandardNormal.sample(&mut rng);
    }
    let s = scenario.shot;
    let r = scenario.params.radius;
    Strike {
        v0: s.v0 + sigma.v0 * z[0],
        phi: s.phi + sigma.phi * z[1],
        theta: s.theta + sigma.theta * z[2],
        a: s.a + sigma.a / r * z[3],
        b: s.b + sigma.b / r * z[4],
    }
    .clamped()
}

/// SplitMix64's finaliser.
fn splitmix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// One 64-bit seed from the study's seed and the sample index.
fn mix(seed: u64, i: u64) -> u64 {
    splitmix(splitmix(seed).wrapping_add(i.wrapping_mul(0x9e37_79b9_7f4a_7c15)))
}

/// What one step of a sample decided.
enum Step {
    Done(Sample),
    /// The cue ball's next motion, and the time it starts.
    Next(Ball, f64),
}

/// One step of a sample whose cue ball is `cue` at time `elapsed`, given the first ball
/// contact within its current motion (`(t, object id)`, times relative to the step).
fn step(scenario: &Scenario, cue: &Ball, elapsed: f64, hit: Option<(f64, i64)>) -> Step {
    let p = &scenario.params;
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
    let cushion = cushion_time(&path, &scenario.table, p.radius, path.tmax);
    let at = |t: f64| path.c + t * (path.b + t * path.a);
    // a ball contact wins a tie with a cushion
    if let Some((t, id)) = hit.filter(|&(t, _)| cushion.is_none_or(|(tc, _)| t <= tc)) {
        let spot = scenario
            .balls
            .iter()
            .find(|b| b.id == id)
            .expect("the engine answers with the scenario's ids");
        let centre = at(t);
        let object = Vec2::new(spot.x, spot.y);
        let v = path.b + (2.0 * t) * path.a;
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
            speed: norm(path.b + (2.0 * t) * path.a),
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
    scenario: &Scenario,
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
    let objects = scenario.object_balls();
    let start = scenario.cue_spot();
    let cue_id = scenario.cue_ball;
    let mut first = 0;
    while first < samples {
        let n = CHUNK.min(samples - first);
        let mut cue: Vec<Ball> = (0..n)
            .map(|k| {
                let s = noisy_strike(scenario, sigma, seed, (first + k) as u64);
                cue_strike(
                    start.x,
                    start.y,
                    &s,
                    scenario.params.radius,
                    &scenario.masses,
                )
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
                } else if let Step::Done(s) = step(scenario, &cue[k], elapsed[k], None) {
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
            let next = engine.next_collisions(&batch, &scenario.params)?;
            let mut still = Vec::new();
            for (nc, &k) in next.iter().zip(&moving) {
                let hit = match (nc.status.is_contact(), nc.pair) {
                    (true, Some((i, j))) => Some((nc.t, if i == cue_id { j } else { i })),
                    _ => None,
                };
                match step(scenario, &cue[k], elapsed[k], hit) {
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
pub fn simulate_one(scenario: &Scenario, strike: &Strike, contact_distance: f64) -> Sample {
    let p = &scenario.params;
    let start = scenario.cue_spot();
    let mut cue = cue_strike(start.x, start.y, strike, p.radius, &scenario.masses);
    let mut elapsed = 0.0;
    let objects = scenario.object_balls();
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
        match step(scenario, &cue, elapsed, hit) {
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
pub fn grazes(scenario: &Scenario, strike: &Strike, delta: f64) -> bool {
    let d = 2.0 * scenario.params.radius;
    simulate_one(scenario, strike, d - 0.5 * delta).outcome
        != simulate_one(scenario, strike, d + 0.5 * delta).outcome
}

/// Summary statistics of a set of values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stats {
    /// How many values.
    pub n: usize,
    /// Mean.
    pub mean: f64,
    /// Sample standard deviation (0 for one value).
    pub std: f64,
    /// 5th percentile (linear interpolation between order statistics).
    pub p5: f64,
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
}

impl Stats {
    /// The statistics of `values`, `None` when empty.
    pub fn of(values: &[f64]) -> Option<Stats> {
        if values.is_empty() {
            return None;
        }
        let n = values.len();
        let mean = values.iter().sum::<f64>() / n as f64;
        let var = if n > 1 {
            values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64
        } else {
            0.0
        };
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let q = |p: f64| {
            let x = p * (n - 1) as f64;
            let lo = x.floor() as usize;
            let hi = (lo + 1).min(n - 1);
            sorted[lo] + (x - lo as f64) * (sorted[hi] - sorted[lo])
        };
        Some(Stats {
            n,
            mean,
            std: var.sqrt(),
            p5: q(0.05),
            p50: q(0.5),
            p95: q(0.95),
        })
    }
}

/// The 95 % Wilson score interval of a proportion `k / n`.
pub fn wilson(k: usize, n: usize) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let z = 1.959_963_984_540_054;
    let (k, n) = (k as f64, n as f64);
    let p = k / n;
    let denom = 1.0 + z * z / n;
    let centre = (p + z * z / (2.0 * n)) / denom;
    let half = z / denom * (p * (1.0 - p) / n + z * z / (4.0 * n * n)).sqrt();
    // exactly 0 and 1 at the ends (the formula leaves rounding there)
    let lo = if k == 0.0 {
        0.0
    } else {
        (centre - half).max(0.0)
    };
    let hi = if k == n {
        1.0
    } else {
        (centre + half).min(1.0)
    };
    (lo, hi)
}

/// A fraction as a percentage: two decimals, or three significant digits below 1 %.
fn percent(x: f64) -> String {
    let p = 100.0 * x;
    if p == 0.0 || p >= 1.0 {
        format!("{p:.2}")
    } else {
        let digits = (2 - p.log10().floor() as i32).max(0) as usize;
        format!("{p:.digits$}")
    }
}

/// An outcome class of the summary: a ball, any cushion, or stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Class {
    /// The cue ball touched this ball first.
    Ball(i64),
    /// The cue ball reached a cushion first.
    Cushion,
    /// The cue ball stopped without touching anything.
    Stopped,
}

impl Class {
    /// The class of an outcome.
    pub fn of(o: Outcome) -> Class {
        match o {
            Outcome::Ball(id) => Class::Ball(id),
            Outcome::Cushion(_) => Class::Cushion,
            Outcome::Stopped => Class::Stopped,
        }
    }
}

/// What a study found.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// Samples.
    pub samples: usize,
    /// The intended object ball.
    pub intended: i64,
    /// Count per class: every object ball (in id order), then cushion, then stopped.
    pub counts: Vec<(Class, usize)>,
    /// Time to contact with the intended ball, over the samples that hit it first.
    pub time: Option<Stats>,
    /// Cut angle on the intended ball, degrees.
    pub cut: Option<Stats>,
}

impl Summary {
    /// Counts and statistics of `samples`.
    pub fn of(scenario: &Scenario, samples: &[Sample]) -> Summary {
        let mut ids: Vec<i64> = scenario
            .balls
            .iter()
            .map(|b| b.id)
            .filter(|&id| id != scenario.cue_ball)
            .collect();
        ids.sort_unstable();
        let mut counts: Vec<(Class, usize)> = ids
            .into_iter()
            .map(Class::Ball)
            .chain([Class::Cushion, Class::Stopped])
            .map(|c| (c, 0))
            .collect();
        let mut times = Vec::new();
        let mut cuts = Vec::new();
        for s in samples {
            let class = Class::of(s.outcome);
            if let Some(c) = counts.iter_mut().find(|(k, _)| *k == class) {
                c.1 += 1;
            }
            if s.outcome == Outcome::Ball(scenario.object_ball) {
                times.push(s.t);
                cuts.push(s.cut);
            }
        }
        Summary {
            samples: samples.len(),
            intended: scenario.object_ball,
            counts,
            time: Stats::of(&times),
            cut: Stats::of(&cuts),
        }
    }

    /// The count of a class.
    pub fn count(&self, class: Class) -> usize {
        self.counts
            .iter()
            .find(|(c, _)| *c == class)
            .map_or(0, |c| c.1)
    }

    /// The summary as text: one line per outcome (balls that are never hit first are
    /// left out, except the intended one), then the intended ball's statistics.
    pub fn to_text(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "{:<24} {:>9} {:>9}   95% confidence interval",
            "first contact", "count", "fraction"
        );
        for &(class, k) in &self.counts {
            let label = match class {
                Class::Ball(id) if id == self.intended => format!("ball {id} (intended)"),
                Class::Ball(id) if k == 0 => {
                    let _ = id;
                    continue;
                }
                Class::Ball(id) => format!("ball {id}"),
                Class::Cushion => "cushion".to_owned(),
                Class::Stopped => "stopped".to_owned(),
            };
            let (lo, hi) = wilson(k, self.samples);
            let frac = if self.samples > 0 {
                k as f64 / self.samples as f64
            } else {
                0.0
            };
            let _ = writeln!(
                s,
                "  {label:<22} {k:>9} {:>8.2}%   [{}%, {}%]",
                100.0 * frac,
                percent(lo),
                percent(hi)
            );
        }
        let _ = writeln!(s);
        match (&self.time, &self.cut) {
            (Some(t), Some(c)) => {
                let _ = writeln!(
                    s,
                    "ball {} hit first ({} samples):{:>9} {:>9} {:>9} {:>9} {:>9}",
                    self.intended, t.n, "mean", "std", "p5", "p50", "p95"
                );
                let _ = writeln!(
                    s,
                    "  {:<30}{:>9.4} {:>9.4} {:>9.4} {:>9.4} {:>9.4}",
                    "time to contact (s)", t.mean, t.std, t.p5, t.p50, t.p95
                );
                let _ = writeln!(
                    s,
                    "  {:<30}{:>9.2} {:>9.2} {:>9.2} {:>9.2} {:>9.2}",
                    "cut angle (deg)", c.mean, c.std, c.p5, c.p50, c.p95
                );
            }
            _ => {
                let _ = writeln!(s, "ball {} is never hit first", self.intended);
            }
        }
        s
    }
}

/// The columns of the per-sample CSV.
pub const SAMPLE_COLUMNS: &str = "sample,v0,phi,theta,a,b,outcome,ball,cushion,t,cue_x,cue_y,speed,contact_x,contact_y,cut_angle";

/// Writes one CSV row per sample (header [`SAMPLE_COLUMNS`]): the noisy strike (recomputed
/// from `seed`), the outcome, the ball or cushion, the time, the cue ball's centre and speed,
/// the contact point, and the cut angle; empty fields where they do not apply. Numbers are the
/// shortest decimals that read back as the same f64.
pub fn write_samples_csv(
    out: &mut dyn std::io::Write,
    scenario: &Scenario,
    sigma: &Noise,
    seed: u64,
    samples: &[Sample],
) -> std::io::Result<()> {
    writeln!(out, "{SAMPLE_COLUMNS}")?;
    let mut buf = ryu::Buffer::new();
    let mut num = |v: f64| -> String {
        if v.is_finite() {
            buf.format(v).to_owned()
        } else {
            String::new()
        }
    };
    for (i, s) in samples.iter().enumerate() {
        let k = noisy_strike(scenario, sigma, seed, i as u64);
        let (ball, cushion) = match s.outcome {
            Outcome::Ball(id) => (id.to_string(), String::new()),
            Outcome::Cushion(c) => (String::new(), c.name().to_owned()),
            Outcome::Stopped => (String::new(), String::new()),
        };
        writeln!(
            out,
            "{i},{},{},{},{},{},{},{ball},{cushion},{},{},{},{},{},{},{}",
            num(k.v0),
            num(k.phi),
            num(k.theta),
            num(k.a),
            num(k.b),
            s.outcome.kind(),
            num(s.t),
            num(s.cue.x),
            num(s.cue.y),
            num(s.speed),
            num(s.contact.x),
            num(s.contact.y),
            num(s.cut)
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wilson_interval_brackets_the_proportion() {
        let (lo, hi) = wilson(50, 100);
        assert!(lo < 0.5 && hi > 0.5 && (0.5 - lo - (hi - 0.5)).abs() < 1e-12);
        assert_eq!(wilson(0, 100).0, 0.0);
        assert!(wilson(0, 100).1 > 0.0);
        assert_eq!(wilson(100, 100).1, 1.0);
    }

    #[test]
    fn percentages_keep_three_digits_when_small() {
        assert_eq!(percent(0.5), "50.00");
        assert_eq!(percent(0.0), "0.00");
        assert_eq!(percent(3.8e-5), "0.00380");
        assert_eq!(percent(0.0042), "0.420");
    }

    #[test]
    fn stats_percentiles_interpolate() {
        let v: Vec<f64> = (0..=100).map(f64::from).collect();
        let s = Stats::of(&v).unwrap();
        assert_eq!((s.p5, s.p50, s.p95), (5.0, 50.0, 95.0));
        assert_eq!(s.mean, 50.0);
    }
}
