//! Candidates evaluated under cue noise: every candidate of a round meets the same noise
//! draws (sample `i` of each is its intended strike plus the `i`th draw of
//! [`noisy_strike_of`]: common random numbers, so that the differences between candidates
//! are the strikes', not the noise's), all of them in one engine call, each sample judged
//! by the game's rules in the candidate's own context (its call).
//!
//! A sample's value, a rough stand-in for what the shot does to the shooter's chance of
//! winning: the game won, [`WIN_VALUE`]; the table kept (legal, turn not over),
//! `1 + POSITION_WEIGHT · ease`, where `ease` in [0, 1] scores the best next shot from
//! where the cue ball stopped ([`next_shot_ease`]); a legal miss (the turn passes),
//! `−OPPONENT_WEIGHT · ease'`, where `ease'` scores the opponent's best shot from there
//! ([`opponent_ease`]): a miss that leaves nothing is a good safety, one that leaves a
//! hanger is not; a foul, `−FOUL_COST` (the opponent's ball in hand: about the easiest
//! shot there is, and more); the game lost, [`LOSS_VALUE`].

use rayon::prelude::*;

use super::candidates::{Candidate, balls_on, easiest_pot, opponent_on};
use crate::engine::ShotEngine;
use crate::error::Error;
use crate::game::{Context, Rules, Verdict};
use crate::resolve::stick_ball::CueStrike;
use crate::study::{
    Collect, Noise, RunOptions, Sample, Samples, StudyConfig, noisy_strike_of, run_into, wilson,
};

/// What the position after a kept shot adds to its value at most (a sure next shot).
pub const POSITION_WEIGHT: f64 = 0.5;
/// What a foul costs (the opponent's ball in hand: more than a miss that leaves the
/// opponent the easiest shot, `OPPONENT_WEIGHT`).
pub const FOUL_COST: f64 = 0.7;
/// What the opponent's position after a legal miss takes off its value at most (a sure
/// shot left).
pub const OPPONENT_WEIGHT: f64 = 0.6;
/// The value of a sample that wins the game.
pub const WIN_VALUE: f64 = 2.0;
/// The value of a sample that loses it.
pub const LOSS_VALUE: f64 = -2.0;

/// A candidate's counts over its samples.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Estimate {
    /// Samples simulated.
    pub samples: usize,
    /// Samples that kept the table (legal, the turn not over) or won the game.
    pub kept: usize,
    /// Samples with a foul.
    pub fouls: usize,
    /// Samples where the cue ball was pocketed.
    pub scratches: usize,
    /// Samples that won the game.
    pub won: usize,
    /// Samples that lost it.
    pub lost: usize,
    /// The sum of the samples' values (module docs).
    pub value_sum: f64,
    /// The sum of the next shot's ease over the kept samples.
    pub ease_sum: f64,
    /// Samples that passed the turn on a legal shot (legal misses).
    pub passed: usize,
    /// The sum of the opponent's next shot's ease over the legal misses.
    pub opponent_sum: f64,
}

impl Estimate {
    /// The mean value of a sample: what the planner ranks by.
    pub fn value(&self) -> f64 {
        self.value_sum / self.samples.max(1) as f64
    }

    /// The probability of keeping the table, with its 95 % Wilson interval.
    pub fn p_keep(&self) -> (f64, f64, f64) {
        interval(self.kept, self.samples)
    }

    /// The probability of a foul, with its interval.
    pub fn p_foul(&self) -> (f64, f64, f64) {
        interval(self.fouls, self.samples)
    }

    /// The probability of a scratch, with its interval.
    pub fn p_scratch(&self) -> (f64, f64, f64) {
        interval(self.scratches, self.samples)
    }

    /// The mean ease of the next shot over the kept samples (0 with none).
    pub fn position(&self) -> f64 {
        if self.kept == 0 {
            0.0
        } else {
            self.ease_sum / self.kept as f64
        }
    }

    /// The mean ease of the opponent's next shot over the legal misses (0 with none).
    pub fn opponent(&self) -> f64 {
        if self.passed == 0 {
            0.0
        } else {
            self.opponent_sum / self.passed as f64
        }
    }

    /// Adds `other`'s samples and sums to these.
    pub fn add(&mut self, other: &Estimate) {
        self.samples += other.samples;
        self.kept += other.kept;
        self.fouls += other.fouls;
        self.scratches += other.scratches;
        self.won += other.won;
        self.lost += other.lost;
        self.value_sum += other.value_sum;
        self.ease_sum += other.ease_sum;
        self.passed += other.passed;
        self.opponent_sum += other.opponent_sum;
    }
}

fn interval(k: usize, n: usize) -> (f64, f64, f64) {
    let (lo, hi) = wilson(k, n);
    (k as f64 / n.max(1) as f64, lo, hi)
}

/// The context a candidate is judged in: the game's, with its call (8-ball calls every
/// shot but the break: a pot's ball and pocket, a safety's ball in the pocket nearest
/// it).
pub fn context_of(config: &StudyConfig, c: &Candidate) -> Context {
    let game = config
        .game
        .as_ref()
        .expect("the planner's position has a game");
    match game.rules {
        Rules::EightBall if c.kind.calls() => Context {
            ball_call: Some(game.ids[c.kind.ball()]),
            pocket_call: Some(c.kind.pocket()),
            ..game.context
        },
        _ => game.context,
    }
}

/// Adds samples `ids` of every candidate of `which` (indices in `candidates`) to their
/// estimates, all in one call on `engine`.
pub fn evaluate(
    engine: &mut ShotEngine,
    config: &StudyConfig,
    candidates: &[Candidate],
    which: &[usize],
    (noise, seed, ids): (&Noise, u64, std::ops::Range<u64>),
    estimates: &mut [Estimate],
) -> Result<(), Error> {
    let per = ids.end.saturating_sub(ids.start) as usize;
    if per == 0 || which.is_empty() {
        return Ok(());
    }
    let r = config.params.ball.r;
    let mut strikes: Vec<CueStrike> = Vec::with_capacity(which.len() * per);
    let mut contexts: Vec<Context> = Vec::with_capacity(which.len() * per);
    for &c in which {
        let context = context_of(config, &candidates[c]);
        for i in ids.clone() {
            strikes.push(noisy_strike_of(candidates[c].strike, r, noise, seed, i));
            contexts.push(context);
        }
    }
    let samples = Samples::Judged {
        strikes: &strikes,
        contexts: &contexts,
    };
    // each chunk's samples judged as they come (while the device runs the next chunk)
    let mut judging = Judging {
        config,
        per,
        partial: vec![Estimate::default(); which.len()],
        taken: 0,
        judged: Vec::new(),
    };
    run_into(
        engine,
        config,
        samples,
        &RunOptions::default(),
        &mut judging,
        &mut |_, _| {},
    )?;
    for (&c, e) in which.iter().zip(&judging.partial) {
        estimates[c].add(e);
    }
    Ok(())
}

/// The samples of a round's candidates (`per` each, one candidate after another) judged
/// chunk by chunk into each candidate's estimate: judged in parallel (Rayon over the
/// chunk), added in order, so each estimate's sums are the samples' in their order.
struct Judging<'c> {
    config: &'c StudyConfig,
    per: usize,
    /// The round's estimate of each candidate so far.
    partial: Vec<Estimate>,
    /// Samples taken so far.
    taken: usize,
    /// The chunk's samples judged (kept across chunks).
    judged: Vec<Estimate>,
}

impl Collect for Judging<'_> {
    fn take(&mut self, chunk: &mut Vec<Sample>) {
        let config = self.config;
        self.judged.clear();
        self.judged.par_extend(
            chunk
                .par_iter()
                .with_min_len(64)
                .map(|s| judge_sample(config, s)),
        );
        for (k, e) in self.judged.iter().enumerate() {
            self.partial[(self.taken + k) / self.per].add(e);
        }
        self.taken += chunk.len();
        chunk.clear();
    }

    fn restart(&mut self) {
        self.partial.fill(Estimate::default());
        self.taken = 0;
    }

    fn taken(&self) -> usize {
        self.taken
    }
}

/// One sample as an [`Estimate`] of one sample: its counts and its value (module docs).
pub fn judge_sample(config: &StudyConfig, s: &Sample) -> Estimate {
    let v: Verdict = s.verdict.unwrap_or(Verdict {
        legal: false,
        foul: None,
        turn_over: true,
        game_over: false,
        won: false,
        points: 0,
        foul_points: 0,
    });
    let scratch = s.pocket_of(config.cue).is_some();
    let mut e = Estimate {
        samples: 1,
        scratches: usize::from(scratch),
        fouls: usize::from(v.foul.is_some()),
        ..Estimate::default()
    };
    if v.game_over {
        if v.won {
            e.won = 1;
            e.kept = 1;
            e.ease_sum = 1.0;
            e.value_sum = WIN_VALUE;
        } else {
            e.lost = 1;
            e.value_sum = LOSS_VALUE;
        }
    } else if v.legal && !v.turn_over {
        let ease = next_shot_ease(config, s);
        e.kept = 1;
        e.ease_sum = ease;
        e.value_sum = 1.0 + POSITION_WEIGHT * ease;
    } else if v.foul.is_some() {
        e.value_sum = -FOUL_COST;
    } else {
        let ease = opponent_ease(config, s);
        e.passed = 1;
        e.opponent_sum = ease;
        e.value_sum = -OPPONENT_WEIGHT * ease;
    }
    e
}

/// How easy the best next shot is from where sample `s` left the cue ball, in [0, 1]:
/// [`easiest_pot`] among the balls on next ([`balls_on`]: 9-ball the lowest left; 8-ball
/// the group's left, else the 8). A cheap estimate: the other balls are taken where they
/// were before the shot (less the pocketed ones), which the shot may have moved.
pub fn next_shot_ease(config: &StudyConfig, s: &Sample) -> f64 {
    let left = |k: usize| k != config.cue && s.pocket_of(k).is_none();
    let others: Vec<usize> = (0..config.balls.len()).filter(|&k| left(k)).collect();
    easiest_pot(config, s.cue_final, &balls_on(config, left), &others)
}

/// How easy the opponent's best shot is from where sample `s` left the cue ball, in
/// [0, 1]: [`easiest_pot`] among the balls the opponent may hit ([`opponent_on`]: 9-ball
/// the lowest left; 8-ball the other group left, else the 8). The same cheap estimate as
/// [`next_shot_ease`].
pub fn opponent_ease(config: &StudyConfig, s: &Sample) -> f64 {
    let left = |k: usize| k != config.cue && s.pocket_of(k).is_none();
    let others: Vec<usize> = (0..config.balls.len()).filter(|&k| left(k)).collect();
    easiest_pot(config, s.cue_final, &opponent_on(config, left), &others)
}
