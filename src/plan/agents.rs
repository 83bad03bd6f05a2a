//! The agents of self-play ([`super::play`]): each chooses a strike for a position.
//!
//! - [`Agent::Greedy`]: what a user writes first — the easiest-looking direct pot (the
//!   largest `cos(cut) · exp(−(cue travel + object travel) / 2 m)` with clear paths), a
//!   fixed speed, centre ball, no simulation;
//! - [`Agent::Sampler`]: what a user writes in an afternoon on kisstime's batch — every
//!   direct pot candidate ([`super::direct_pots`]: 4 speeds × 5 tip offsets) played
//!   [`SAMPLER_SAMPLES`] times under the noise in one call, the best immediate outcome
//!   (P(keep the table); among safeties, the fewest fouls) wins; no position, no
//!   refinement;
//! - [`Agent::Planner`]: [`super::plan`] with its budget (its own candidates: banks,
//!   combinations, safeties and kicks too).
//!
//! Without a playable direct pot, greedy's and the sampler's candidates are [`safeties`]
//! (full hits on the balls on in straight reach): greedy takes the nearest at 2 m/s, the
//! sampler chooses by simulation (the fewest fouls). With none of those either, they play
//! the fallback: a full hit on the nearest ball it may hit, at 2 m/s ([`fallback`]); the
//! planner plays it too where it finds nothing to try.

use super::candidates::{
    Candidate, Kind, THETA, direct_pots, ease, easiest_pot, safeties, targets,
};
use super::evaluate::{Estimate, evaluate};
use super::{Budget, PlanOptions, plan};
use crate::engine::ShotEngine;
use crate::error::Error;
use crate::resolve::stick_ball::CueStrike;
use crate::study::{Noise, StudyConfig};

/// Samples of each candidate the sampler plays.
pub const SAMPLER_SAMPLES: u64 = 200;
/// The greedy agent's cue speed, m/s.
pub const GREEDY_SPEED: f64 = 2.5;

/// A self-play agent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Agent {
    /// The easiest-looking pot, no simulation.
    Greedy,
    /// Every direct pot simulated a few hundred times, the best immediate outcome.
    Sampler,
    /// The planner.
    Planner,
}

impl Agent {
    /// Every agent with its name.
    pub const ALL: [(Agent, &'static str); 3] = [
        (Agent::Greedy, "greedy"),
        (Agent::Sampler, "sampler"),
        (Agent::Planner, "planner"),
    ];

    /// Its name.
    pub fn name(self) -> &'static str {
        Agent::ALL
            .iter()
            .find(|(a, _)| *a == self)
            .map_or("", |(_, n)| n)
    }

    /// The agent named `name`; the error lists the names.
    pub fn from_name(name: &str) -> Result<Agent, String> {
        Agent::ALL
            .iter()
            .find(|(_, n)| *n == name)
            .map(|(a, _)| *a)
            .ok_or_else(|| {
                format!("unknown agent {name:?}: the agents are greedy, sampler, planner")
            })
    }
}

/// What an agent chose: the strike and, for a pot, the call (ball and pocket indices).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Choice {
    /// The intended strike.
    pub strike: CueStrike,
    /// The ball and pocket it means (8-ball's call), if a pot.
    pub call: Option<(usize, usize)>,
}

/// `agent`'s choice from `config`'s position (its game and context), the noise being
/// `noise`; `budget` is the planner's, `seed` the simulating agents' noise draws.
pub fn choose(
    agent: Agent,
    engine: &mut ShotEngine,
    config: &StudyConfig,
    noise: &Noise,
    budget: Budget,
    seed: u64,
) -> Result<Choice, Error> {
    let greedy = match agent {
        Agent::Greedy => true,
        Agent::Sampler => false,
        Agent::Planner => return planner_choice(engine, config, noise, budget, seed),
    };
    let mut candidates = direct_pots(config).unwrap_or_default();
    if candidates.is_empty() {
        candidates = safeties(config).unwrap_or_default();
    }
    if candidates.is_empty() {
        return Ok(fallback(config));
    }
    let pick = choice_of;
    if greedy {
        // no pot: the nearest ball in reach, at the middle speed
        if matches!(candidates[0].kind, Kind::Safety { .. }) {
            let best = candidates
                .iter()
                .filter(|c| c.strike.v0 == 2.0)
                .min_by(|x, y| x.aim.cue_travel.total_cmp(&y.aim.cue_travel))
                .expect("every safety at 2 m/s");
            return Ok(pick(best));
        }
        let best = candidates
            .iter()
            .filter(|c| c.strike.a == 0.0 && c.strike.b == 0.0)
            .max_by(|x, y| ease(&x.aim).total_cmp(&ease(&y.aim)))
            .expect("every pot has a centre-ball candidate");
        return Ok(Choice {
            strike: CueStrike {
                v0: GREEDY_SPEED,
                ..best.strike
            },
            ..pick(best)
        });
    }
    // the sampler
    let all: Vec<usize> = (0..candidates.len()).collect();
    let mut estimates = vec![Estimate::default(); candidates.len()];
    evaluate(
        engine,
        config,
        &candidates,
        &all,
        (noise, seed, 0..SAMPLER_SAMPLES),
        &mut estimates,
    )?;
    let best = (0..candidates.len())
        .max_by(|&x, &y| {
            // the table kept, then (a safety keeps none) the fewest fouls
            let (ex, ey) = (&estimates[x], &estimates[y]);
            ex.kept
                .cmp(&ey.kept)
                .then(ey.fouls.cmp(&ex.fouls))
                .then(y.cmp(&x))
        })
        .expect("candidates");
    Ok(pick(&candidates[best]))
}

/// The planner's choice: [`plan`] with `budget`, keeping 3 finalists; where it finds
/// nothing to try, the [`fallback`] as the other agents.
fn planner_choice(
    engine: &mut ShotEngine,
    config: &StudyConfig,
    noise: &Noise,
    budget: Budget,
    seed: u64,
) -> Result<Choice, Error> {
    let options = PlanOptions {
        noise: *noise,
        seed,
        budget,
        finalists: 3,
        ..PlanOptions::default()
    };
    match plan(engine, config, &options) {
        Ok(planned) => Ok(choice_of(&planned.ranked[0].candidate)),
        // nothing to try: the fallback, as the other agents
        Err(Error::Input(_)) => Ok(fallback(config)),
        Err(e) => Err(e),
    }
}

/// A candidate as a choice: its strike, its ball and pocket as the call (a break: none).
pub fn choice_of(c: &Candidate) -> Choice {
    Choice {
        strike: c.strike,
        call: c.kind.calls().then(|| (c.kind.ball(), c.kind.pocket())),
    }
}

/// No direct pot: a full hit on the nearest ball the player may hit, at 2 m/s, with no
/// call (or, with no such ball, a 2 m/s stroke along +y).
pub fn fallback(config: &StudyConfig) -> Choice {
    let at = |k: usize| (config.balls[k].x, config.balls[k].y);
    let cue = at(config.cue);
    let dist = |k: &usize| {
        let (x, y) = at(*k);
        (x - cue.0).hypot(y - cue.1)
    };
    let nearest = targets(config)
        .unwrap_or_default()
        .into_iter()
        .min_by(|a, b| dist(a).total_cmp(&dist(b)));
    let phi = nearest.map_or(90.0, |k| {
        let (x, y) = at(k);
        (y - cue.1).atan2(x - cue.0).to_degrees().rem_euclid(360.0)
    });
    Choice {
        strike: CueStrike {
            v0: 2.0,
            phi,
            theta: THETA,
            a: 0.0,
            b: 0.0,
        },
        call: None,
    }
}

/// How easy the easiest direct pot of `config`'s position is, 0 to 1 ([`easiest_pot`]
/// over its balls on): what ball-in-hand placement maximises.
pub fn best_ease(config: &StudyConfig) -> f64 {
    let cue = (config.balls[config.cue].x, config.balls[config.cue].y);
    let all: Vec<usize> = (0..config.balls.len()).collect();
    easiest_pot(config, cue, &targets(config).unwrap_or_default(), &all)
}
