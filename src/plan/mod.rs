//! Which shot to play: a shot planner under cue noise and a game's rules (8-ball and
//! 9-ball: direct pots, banks, combinations, kicks and safeties; the cue ball in hand).
//!
//! - [`aim`]: the ghost-ball aim, the cut angle, whether a path is clear;
//! - [`candidates`]: the shots tried (each target ball into each pocket, where the aim is
//!   playable, over a grid of speeds and spins; one-rail banks, two-ball combinations,
//!   one-rail kicks) and safeties (no pot meant);
//! - [`evaluate`](mod@evaluate): candidates under the same noise draws (common random
//!   numbers), in one engine call, judged by the game in each candidate's context, and
//!   each sample's value (the table kept, the position left, fouls, the game);
//! - [`plan`]: successive halving over the candidates (every survivor of a round gets as
//!   many new samples as it had, the lower half is dropped), then the best few refined in
//!   the continuous strike ([`refine`](mod@refine): the cross-entropy method on common random
//!   numbers), then the finalists estimated again on fresh draws, so that the figures
//!   reported are not the ones that chose them (a candidate chosen for a lucky run would
//!   otherwise report its luck).
//!
//! - [`in_hand`]: the cue ball's placement when it is in hand;
//! - [`breaks`]: the break, the cue ball's spot behind the head string and the strike;
//! - [`play`](mod@play): self-play, whole games between two [`agents`] (`greedy`,
//!   `sampler`, the planner) on kisstime's own simulator.
//!
//! The cheap position value of [`evaluate`](mod@evaluate) is checked against nested plans
//! from the tables a shot really leaves in `tests/plan_validation.rs` (docs/plan.md).

pub mod agents;
pub mod aim;
pub mod breaks;
pub mod candidates;
pub mod evaluate;
pub mod in_hand;
pub mod play;
pub mod refine;

use std::time::Instant;

pub use aim::{Aim, Rail, ghost_ball, path_clear, rails};
pub use candidates::{
    Candidate, Kind, balls_on, direct_pots, ease, easiest_pot, opponent_on, safeties, targets,
};
pub use evaluate::{Estimate, context_of, next_shot_ease, opponent_ease};

use crate::engine::ShotEngine;
use crate::error::{Error, InputError};
use crate::study::{Noise, StudyConfig};

/// Where the final estimates' noise draws start: far from the halving's, so that the
/// finalists meet fresh noise.
pub const FRESH_DRAWS: u64 = 1 << 40;

/// Where the refinement's noise draws start: apart from the halving's and the final
/// estimates', so that the strikes it keeps are not chosen on the draws that then judge
/// them.
pub const REFINE_DRAWS: u64 = 1 << 41;

/// The fewest samples a strike the refinement plays gets: with fewer, it is skipped.
pub const REFINE_SAMPLES: u64 = 32;

/// The fewest samples of a first round (over all candidates) by default
/// ([`PlanOptions::first_round`]).
pub const FIRST_ROUND: usize = 4096;

/// The most a planner may be given: an hour, or 10⁹ samples.
pub const MAX_BUDGET_SECONDS: f64 = 3600.0;
/// See [`MAX_BUDGET_SECONDS`].
pub const MAX_BUDGET_SAMPLES: usize = 1_000_000_000;

/// How much a plan may simulate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Budget {
    /// About this many seconds (the rate measured on the first round sizes the rest).
    Seconds(f64),
    /// This many samples at most (a plan then is the same at every run).
    Samples(usize),
}

/// How a plan is made.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanOptions {
    /// The cue noise the strikes are played under.
    pub noise: Noise,
    /// The noise draws' seed.
    pub seed: u64,
    /// What it may spend.
    pub budget: Budget,
    /// Samples of each candidate in the first round.
    pub first_samples: usize,
    /// The fewest samples of the first round over all candidates (with a time budget,
    /// its rate sizes the rest).
    pub first_round: usize,
    /// Candidates estimated again on fresh draws at the end, and reported.
    pub finalists: usize,
    /// Whether the best few are refined in the continuous strike ([`refine`]) when the
    /// budget allows it.
    pub refine: bool,
}

impl Default for PlanOptions {
    fn default() -> Self {
        PlanOptions {
            noise: Noise::default(),
            seed: 1,
            budget: Budget::Seconds(1.0),
            first_samples: 64,
            first_round: FIRST_ROUND,
            finalists: 5,
            refine: true,
        }
    }
}

/// One of the finalists.
#[derive(Clone, Debug, PartialEq)]
pub struct Ranked {
    /// The candidate.
    pub candidate: Candidate,
    /// Its estimate on fresh draws.
    pub estimate: Estimate,
}

/// A plan: the finalists, best first (the first is the shot to play).
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// The finalists, by their fresh estimate's value, best first.
    pub ranked: Vec<Ranked>,
    /// Candidates generated (the refinement's strikes included).
    pub candidates: usize,
    /// Of them, the strikes the refinement drew ([`refine`]).
    pub refined: usize,
    /// Samples simulated in all.
    pub samples: usize,
    /// Rounds of halving.
    pub rounds: usize,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// With the cue ball in hand ([`in_hand::plan_in_hand`]): where it is placed.
    pub placement: Option<(f64, f64)>,
}

/// The shot to play from `config`'s position (its balls, table, physics and game with its
/// context; its `[shot]` is not used) under `options`, simulated on `engine` (module docs).
///
/// On a break, the break's strikes from where the cue ball is ([`breaks::plan_break`]
/// chooses the spot too).
///
/// Errors: a game the planner does not play, no ball the player may hit on the
/// table, no playable direct pot nor a ball on in straight reach, a budget that is not positive and finite or past
/// [`MAX_BUDGET_SECONDS`] / [`MAX_BUDGET_SAMPLES`] or smaller than a sample of every
/// candidate and the finalists
/// ([`Error::Input`]); what the engine refuses.
pub fn plan(
    engine: &mut ShotEngine,
    config: &StudyConfig,
    options: &PlanOptions,
) -> Result<Plan, Error> {
    let started = Instant::now();
    let mut candidates = candidates_of(config).map_err(InputError::new)?;
    if candidates.is_empty() {
        return Err(InputError::new(
            "no shot to try from this position: no direct pot, bank or combination is \
             playable (every cut too thin or every path blocked), no ball on is in the cue \
             ball's straight reach and no one-rail kick reaches one",
        )
        .into());
    }
    let screened = screen(engine, config, &mut candidates, options.seed)?;
    if candidates.is_empty() {
        return Err(InputError::new(
            "no shot to try from this position: no bank or combination pots without noise, \
             and nothing else is playable",
        )
        .into());
    }
    let n = candidates.len();
    // a first round of at least FIRST_ROUND samples: a time budget is sized by its rate
    let mut first = options
        .first_samples
        .max(options.first_round.div_ceil(n))
        .max(1);
    let finalists = options.finalists.max(1);
    let budget = match options.budget {
        Budget::Seconds(s) if s.is_finite() && s > 0.0 && s <= MAX_BUDGET_SECONDS => None,
        Budget::Samples(k) if (1..=MAX_BUDGET_SAMPLES).contains(&k) => {
            // a sample budget needs no rate: the first round may be as small as it allows
            let fits = k.saturating_sub(finalists) / n;
            if fits == 0 {
                return Err(InputError::new(format!(
                    "a budget of {k} samples is too small: {n} candidates and {finalists} \
                     finalists need {} at least",
                    n + finalists
                ))
                .into());
            }
            first = first.min(fits);
            Some(k)
        }
        b => {
            let named = match b {
                Budget::Seconds(s) => format!("{s} s"),
                Budget::Samples(k) => format!("{k} samples"),
            };
            return Err(InputError::new(format!(
                "a budget of {named}: give more than nothing, at most an hour or 10⁹ samples"
            ))
            .into());
        }
    };
    let draws = |ids: std::ops::Range<u64>| (&options.noise, options.seed, ids);
    let mut estimates = vec![Estimate::default(); n];
    let mut alive: Vec<usize> = (0..n).collect();
    let (mut per, mut done, mut used, mut rounds) = (first as u64, 0u64, screened, 0usize);
    loop {
        evaluate::evaluate(
            engine,
            config,
            &candidates,
            &alive,
            draws(done..done + per),
            &mut estimates,
        )?;
        used += alive.len() * per as usize;
        done += per;
        rounds += 1;
        let total = budget.unwrap_or_else(|| samples_in_time(options.budget, used, &started));
        if alive.len() <= finalists {
            break;
        }
        rank(&mut alive, &estimates);
        alive.truncate(alive.len().div_ceil(2).max(finalists));
        per = done;
        // the halving may spend half the budget; the refinement and the final estimates
        // the rest
        if used + alive.len() * per as usize > total / 2 {
            break;
        }
    }
    rank(&mut alive, &estimates);
    // the refinement, where it fits in three quarters of the budget with 32 samples a
    // strike at least (at most as many as the halving gave each survivor)
    let mut refined = 0;
    let total = budget.unwrap_or_else(|| samples_in_time(options.budget, used, &started));
    let leaders: Vec<usize> = alive.iter().take(refine::LEADERS).copied().collect();
    let room = (total * 3 / 4).saturating_sub(used) / refine::cost(leaders.len(), 1).max(1);
    let per_strike = (room as u64).min(done);
    alive.truncate(finalists);
    if options.refine && per_strike >= REFINE_SAMPLES {
        let before = candidates.len();
        let mut better = refine::refine(
            engine,
            config,
            &mut candidates,
            &leaders,
            draws(REFINE_DRAWS..REFINE_DRAWS + per_strike),
        )?;
        used += refine::cost(leaders.len(), per_strike);
        refined = candidates.len() - before;
        // each better child takes the place of the last original finalist (the best
        // original stays)
        let keep = finalists.saturating_sub(better.len()).max(1);
        better.truncate(finalists.saturating_sub(keep));
        alive.truncate(keep);
        alive.extend(better);
    }
    let total = budget.unwrap_or_else(|| samples_in_time(options.budget, used, &started));
    let fresh = (total.saturating_sub(used) / alive.len()).max(first) as u64;
    let mut finals = vec![Estimate::default(); candidates.len()];
    evaluate::evaluate(
        engine,
        config,
        &candidates,
        &alive,
        draws(FRESH_DRAWS..FRESH_DRAWS + fresh),
        &mut finals,
    )?;
    used += alive.len() * fresh as usize;
    rank(&mut alive, &finals);
    Ok(Plan {
        ranked: alive
            .iter()
            .map(|&c| Ranked {
                candidate: candidates[c],
                estimate: finals[c],
            })
            .collect(),
        candidates: candidates.len(),
        refined,
        samples: used,
        rounds,
        seconds: started.elapsed().as_secs_f64(),
        placement: None,
    })
}

/// Every candidate the planner tries from `config`'s position ([`candidates`]): the direct
/// pots, the banks and the combinations; the safeties beside them (a poor pot may be worth
/// less than a safety), with the fuller fan of thinner and softer hits where no direct pot
/// is easy ([`candidates::WEAK_POT`]); and, where no ball on is in straight reach, the
/// kicks. On a break, the break's shots ([`candidates::break_shots`]). Errors: as
/// [`targets`].
pub fn candidates_of(config: &StudyConfig) -> Result<Vec<Candidate>, String> {
    if config.game.as_ref().is_some_and(|g| g.context.break_shot) {
        return candidates::break_shots(config);
    }
    let mut out = direct_pots(config)?;
    let easiest = out.iter().map(|c| ease(&c.aim)).fold(0.0, f64::max);
    out.extend(candidates::banks(config)?);
    out.extend(candidates::combos(config)?);
    let safe = if easiest < candidates::WEAK_POT {
        candidates::safety_fan(config)?
    } else {
        safeties(config)?
    };
    if safe.is_empty() {
        out.extend(candidates::kicks(config)?);
    }
    out.extend(safe);
    Ok(out)
}

/// Drops the banks and combinations of `candidates` that do not pot what they call when
/// played once without noise (their aims are the mirror's and the ghost ball's, which a
/// real rebound or throw departs from: of a bank's wide fan, only the aims that work
/// stay). Returns the samples it played (one a bank or combination).
pub fn screen(
    engine: &mut ShotEngine,
    config: &StudyConfig,
    candidates: &mut Vec<Candidate>,
    seed: u64,
) -> Result<usize, Error> {
    let which: Vec<usize> = (0..candidates.len())
        .filter(|&k| matches!(candidates[k].kind, Kind::Bank { .. } | Kind::Combo { .. }))
        .collect();
    if which.is_empty() {
        return Ok(0);
    }
    let mut e = vec![Estimate::default(); candidates.len()];
    let none = Noise::default().scaled(0.0);
    evaluate::evaluate(
        engine,
        config,
        candidates,
        &which,
        (&none, seed, 0..1),
        &mut e,
    )?;
    let mut k = 0;
    candidates.retain(|c| {
        let keep = !matches!(c.kind, Kind::Bank { .. } | Kind::Combo { .. }) || e[k].kept > 0;
        k += 1;
        keep
    });
    Ok(which.len())
}

/// A planner's position as a study's configuration: the balls on the table at rest
/// (`ids[k]`, `balls[k]`: the game's ids, 0 the cue ball; pocketed balls are left out), the
/// table (`table_name` for messages) and physics, the game and its context (the rules'
/// own part added: 8-ball's call; with none of the group on the table, the 8 is the ball
/// on). The study's shot is a placeholder (the planner chooses it).
///
/// Errors ([`Error::Input`], naming the ball): no cue ball (id 0), a ball moving, two
/// balls with one id, a ball off the table or overlapping another, a context the game
/// cannot judge.
pub fn position(
    table: &crate::model::table::Table,
    table_name: &str,
    params: crate::model::sim_params::SimParams,
    (ids, balls): (&[i64], &[crate::model::ball_state::BallState]),
    rules: crate::game::Rules,
    context: crate::game::Context,
) -> Result<StudyConfig, Error> {
    use crate::model::MotionState;
    let mut spots = Vec::new();
    let mut on = Vec::new();
    let mut kept_ids = Vec::new();
    for (k, (&id, b)) in ids.iter().zip(balls).enumerate() {
        if ids[..k].contains(&id) {
            return Err(InputError::new(format!("ball {id} is given twice")).into());
        }
        match b.s {
            MotionState::Pocketed => continue,
            MotionState::Stationary => {}
            s => {
                return Err(InputError::new(format!(
                    "ball {id} is {} : the planner plays from a position at rest",
                    s.name()
                ))
                .into());
            }
        }
        if b.v.norm() != 0.0 || b.w.norm() != 0.0 {
            return Err(InputError::new(format!(
                "ball {id} moves or spins: the planner plays from a position at rest"
            ))
            .into());
        }
        spots.push(crate::study::Spot {
            id: id.to_string(),
            x: b.r.x,
            y: b.r.y,
        });
        on.push(*b);
        kept_ids.push(id);
    }
    let Some(cue) = kept_ids.iter().position(|&id| id == 0) else {
        return Err(InputError::new("no cue ball (id 0) on the table").into());
    };
    crate::simulate::check::check_layout(table, params.ball.r, &on).map_err(|e| {
        use crate::error::SimError;
        InputError::new(match e {
            SimError::Ball { index, reason } => format!("ball {}: {reason}", kept_ids[index]),
            SimError::Overlap {
                first,
                second,
                depth,
            } => format!(
                "balls {} and {} overlap by {depth:.3e} m",
                kept_ids[first], kept_ids[second]
            ),
            other => other.to_string(),
        })
    })?;
    let mut context = context;
    // 8-ball: with the group down, the 8 is the ball on
    let on_table = |id: i64| (1..32).contains(&id) && context.hittable & (1 << id) != 0;
    if rules == crate::game::Rules::EightBall && !kept_ids.iter().any(|&id| on_table(id)) {
        context.hittable = crate::game::Context::balls([8]);
    }
    let context = rules.context(context);
    rules.check_context(&context).map_err(InputError::new)?;
    let intended = (0..spots.len()).find(|&k| k != cue).unwrap_or(cue);
    Ok(StudyConfig {
        source: "the planner's position".into(),
        table_name: table_name.into(),
        table: table.clone(),
        params,
        balls: spots,
        cue,
        intended,
        pocket: None,
        shot: crate::resolve::stick_ball::CueStrike {
            v0: 0.0,
            phi: 0.0,
            theta: 0.0,
            a: 0.0,
            b: 0.0,
        },
        target: None,
        noise_factor: 1.0,
        noise: Noise::default(),
        game: Some(crate::study::StudyGame {
            rules,
            context,
            ids: kept_ids,
        }),
    })
}

/// The plan as JSON: `rules`, `candidates`, `refined` (of them, the refinement's),
/// `samples`, `rounds`, `seconds`, `strike` (the
/// chosen one: `V0`, `phi`, `theta`, `a`, `b` in pooltool's `Cue` conventions) and
/// `ranked`, the finalists best first, each with `kind` (`pot`, `bank`, `combo`, `kick` or
/// `safety`: [`Kind`]; a kick and a safety are meant as a legal contact, 8-ball calling the
/// pocket nearest the ball), `first` (the ball the cue ball is to hit first), `ball` (the
/// ball called) and `pocket` (the position's and the table's ids), `rail` (a bank's or a
/// kick's cushion, its id in the table), `cut` (degrees),
/// `strike`, `samples`, `p_keep`, `p_foul`, `p_scratch` (each `[p, low, high]`, the 95 %
/// Wilson interval), `p_won`, `p_lost`, `position` (the mean ease of the next shot over
/// the samples that kept the table), `opponent` (the mean ease of the opponent's shot over
/// the legal misses) and `value`.
pub fn json(config: &StudyConfig, planned: &Plan) -> serde_json::Value {
    let strike = |s: crate::resolve::stick_ball::CueStrike| serde_json::json!({"V0": s.v0, "phi": s.phi, "theta": s.theta, "a": s.a, "b": s.b});
    let ranked: Vec<serde_json::Value> = planned
        .ranked
        .iter()
        .map(|r| {
            let (ball, pocket) = (r.candidate.kind.ball(), r.candidate.kind.pocket());
            let e = &r.estimate;
            let p = |(v, lo, hi): (f64, f64, f64)| serde_json::json!([v, lo, hi]);
            let share = |k: usize| k as f64 / e.samples.max(1) as f64;
            serde_json::json!({
                "kind": r.candidate.kind.name(),
                "first": config.balls[r.candidate.kind.first()].id,
                "ball": config.balls[ball].id,
                "pocket": r.candidate.kind.calls().then(|| &config.table.pocket_ids[pocket]),
                "cut": r.candidate.aim.cut,
                "rail": match r.candidate.kind {
                    Kind::Bank { rail, .. } | Kind::Kick { rail, .. } => {
                        Some(&config.table.linear_ids[rail])
                    }
                    _ => None,
                },
                "strike": strike(r.candidate.strike),
                "samples": e.samples,
                "p_keep": p(e.p_keep()),
                "p_foul": p(e.p_foul()),
                "p_scratch": p(e.p_scratch()),
                "p_won": share(e.won),
                "p_lost": share(e.lost),
                "position": e.position(),
                "opponent": e.opponent(),
                "value": e.value(),
            })
        })
        .collect();
    serde_json::json!({
        "rules": config.game.as_ref().map_or("", |g| g.rules.name()),
        "candidates": planned.candidates,
        "refined": planned.refined,
        "samples": planned.samples,
        "rounds": planned.rounds,
        "seconds": planned.seconds,
        "strike": planned.ranked.first().map(|r| strike(r.candidate.strike)),
        "placement": planned.placement.map(|(x, y)| serde_json::json!({"x": x, "y": y})),
        "ranked": ranked,
    })
}

/// A time budget as samples: `used` samples so far took the time since `started`, and
/// the rest go at that rate.
fn samples_in_time(budget: Budget, used: usize, started: &Instant) -> usize {
    match budget {
        Budget::Seconds(s) => {
            let rate = used as f64 / started.elapsed().as_secs_f64().max(1e-6);
            (rate * s) as usize
        }
        Budget::Samples(k) => k,
    }
}

/// `which` by their estimates' value, best first (ties: the earlier candidate).
fn rank(which: &mut [usize], estimates: &[Estimate]) {
    which.sort_by(|&a, &b| {
        estimates[b]
            .value()
            .total_cmp(&estimates[a].value())
            .then(a.cmp(&b))
    });
}
