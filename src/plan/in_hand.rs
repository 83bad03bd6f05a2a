//! The cue ball in hand: where to place it, and the shot from there.
//!
//! Method: every point of a 5 cm grid over the region the rules allow (anywhere, or
//! behind the head string) where the cue ball fits — on the playing surface, 1 mm clear of
//! every ball — is scored by its easiest direct pot ([`super::agents::best_ease`]: the cut
//! and the distances, no simulation); the [`IN_HAND_SPOTS`] best, each at least
//! [`SPOT_SPACING`] from a better one, are planned in full ([`super::plan`], the budget
//! shared between them), and the spot whose best shot's fresh estimate has the highest
//! value wins. The cheap score only shortlists: the simulation chooses.

use std::time::Instant;

use super::agents::best_ease;
use super::{Budget, Plan, PlanOptions, plan};
use crate::engine::ShotEngine;
use crate::error::{Error, InputError};
use crate::game::progress::HEAD_STRING_Y;
use crate::model::vec3::Vec3;
use crate::simulate::check::check_on_table;
use crate::study::StudyConfig;

/// Spots planned in full.
pub const IN_HAND_SPOTS: usize = 4;
/// The least distance between two spots planned, m.
pub const SPOT_SPACING: f64 = 0.15;
/// The grid's step, m.
pub const GRID: f64 = 0.05;

/// Where the cue ball in hand may be placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InHand {
    /// Anywhere on the table (after a foul, WPA rules).
    Anywhere,
    /// Behind the head string (y below 0.635 m on the 9-ft table; after a scratch on the
    /// break under some rules).
    Kitchen,
}

impl InHand {
    /// `anywhere` or `kitchen`.
    pub fn from_name(name: &str) -> Result<InHand, String> {
        match name {
            "anywhere" => Ok(InHand::Anywhere),
            "kitchen" => Ok(InHand::Kitchen),
            other => Err(format!(
                "ball in hand {other:?}: \"anywhere\" or \"kitchen\" (behind the head string)"
            )),
        }
    }
}

/// The cue ball's placement in `region` and the shot from there (module docs): the plan of
/// the winning spot, with [`Plan::placement`] set and its counts (candidates, samples,
/// seconds) those of every spot planned. `config`'s cue ball is where the placement starts
/// from (its spot is replaced). Errors: as [`plan`]'s; no spot in the region; no spot from
/// which a shot can be planned.
pub fn plan_in_hand(
    engine: &mut ShotEngine,
    config: &StudyConfig,
    options: &PlanOptions,
    region: InHand,
) -> Result<Plan, Error> {
    let started = Instant::now();
    let spots = shortlist(config, region);
    if spots.is_empty() {
        return Err(InputError::new("no free spot for the cue ball in hand").into());
    }
    let mut planned = plan_at(engine, config, options, &spots)?;
    planned.seconds = started.elapsed().as_secs_f64();
    Ok(planned)
}

/// The best of the plans from each of `spots` (the cue ball put there; the budget shared
/// between them): the plan whose best shot's fresh estimate has the highest value, with
/// [`Plan::placement`] its spot and its counts (candidates, samples) those of every spot
/// planned. Errors: as [`plan`]'s (a spot from which nothing can be planned is skipped;
/// with none left, the last such error); no spots.
pub fn plan_at(
    engine: &mut ShotEngine,
    config: &StudyConfig,
    options: &PlanOptions,
    spots: &[(f64, f64)],
) -> Result<Plan, Error> {
    let started = Instant::now();
    if spots.is_empty() {
        return Err(InputError::new("no free spot for the cue ball").into());
    }
    let k = spots.len();
    let budget = match options.budget {
        Budget::Seconds(s) => Budget::Seconds(s / k as f64),
        Budget::Samples(n) => Budget::Samples(n / k),
    };
    let mut best: Option<(Plan, (f64, f64))> = None;
    let (mut candidates, mut refined, mut samples, mut rounds) = (0, 0, 0, 0);
    let mut last_error = None;
    for (i, &spot) in spots.iter().enumerate() {
        let placed = at(config, spot);
        let opts = PlanOptions {
            budget,
            seed: options.seed.wrapping_add(i as u64),
            ..options.clone()
        };
        let planned = match plan(engine, &placed, &opts) {
            Ok(p) => p,
            Err(e @ Error::Input(_)) => {
                last_error = Some(e);
                continue;
            }
            Err(e) => return Err(e),
        };
        candidates += planned.candidates;
        refined += planned.refined;
        samples += planned.samples;
        rounds = rounds.max(planned.rounds);
        let value = planned.ranked[0].estimate.value();
        if best
            .as_ref()
            .is_none_or(|(b, _)| value > b.ranked[0].estimate.value())
        {
            best = Some((planned, spot));
        }
    }
    let Some((mut planned, spot)) = best else {
        return Err(
            last_error.unwrap_or_else(|| InputError::new("no shot from any spot in hand").into())
        );
    };
    planned.placement = Some(spot);
    planned.candidates = candidates;
    planned.refined = refined;
    planned.samples = samples;
    planned.rounds = rounds;
    planned.seconds = started.elapsed().as_secs_f64();
    Ok(planned)
}

/// A free spot for a ball of radius `r` among `balls` on `table`: the first point of a
/// 5 cm grid (from the table's corner) on the playing surface, 1 mm clear of every ball.
pub fn free_spot(
    table: &crate::model::table::Table,
    r: f64,
    balls: &[crate::model::ball_state::BallState],
) -> Option<(f64, f64)> {
    (0..200)
        .flat_map(|j| (0..100).map(move |i| (i as f64 * GRID, j as f64 * GRID)))
        .find(|&(x, y)| {
            check_on_table(table, r, Vec3::new(x, y, r)).is_ok()
                && balls
                    .iter()
                    .all(|b| (b.r.x - x).hypot(b.r.y - y) > 2.0 * r + 1e-3)
        })
}

/// A position's balls (`ids[k]`, `balls[k]`) with the cue ball (id 0) in hand: taken off
/// where it was (if it was on the table) and put first at a [`free_spot`], for
/// [`plan_in_hand`] to place. Errors: no room for it.
pub fn cue_in_hand(
    table: &crate::model::table::Table,
    r: f64,
    ids: &[i64],
    balls: &[crate::model::ball_state::BallState],
) -> Result<(Vec<i64>, Vec<crate::model::ball_state::BallState>), Error> {
    let (mut ids, mut balls): (Vec<i64>, Vec<_>) = ids
        .iter()
        .zip(balls)
        .filter(|(id, _)| **id != 0)
        .map(|(id, b)| (*id, *b))
        .unzip();
    let spot = free_spot(table, r, &balls)
        .ok_or_else(|| InputError::new("no room for the cue ball in hand"))?;
    ids.insert(0, 0);
    balls.insert(
        0,
        crate::model::ball_state::BallState::at_rest(spot.0, spot.1, r),
    );
    Ok((ids, balls))
}

/// `config` with its cue ball at `spot`.
pub fn at(config: &StudyConfig, spot: (f64, f64)) -> StudyConfig {
    let mut placed = config.clone();
    placed.balls[config.cue].x = spot.0;
    placed.balls[config.cue].y = spot.1;
    placed
}

/// Whether `config`'s cue ball fits at `(x, y)`: on the playing surface, 1 mm clear of
/// every other ball.
pub fn cue_fits(config: &StudyConfig, x: f64, y: f64) -> bool {
    let r = config.params.ball.r;
    check_on_table(&config.table, r, Vec3::new(x, y, r)).is_ok()
        && config
            .balls
            .iter()
            .enumerate()
            .all(|(k, b)| k == config.cue || (b.x - x).hypot(b.y - y) > 2.0 * r + 1e-3)
}

/// The spots planned in full: the grid's best by the easiest pot, spaced (module docs).
fn shortlist(config: &StudyConfig, region: InHand) -> Vec<(f64, f64)> {
    let free = |x: f64, y: f64| cue_fits(config, x, y);
    let (mut lo, mut hi) = ((f64::MAX, f64::MAX), (f64::MIN, f64::MIN));
    for s in &config.table.linear {
        for p in [s.p1, s.p2] {
            lo = (lo.0.min(p.x), lo.1.min(p.y));
            hi = (hi.0.max(p.x), hi.1.max(p.y));
        }
    }
    if region == InHand::Kitchen {
        hi.1 = hi.1.min(HEAD_STRING_Y);
    }
    let mut scored = Vec::new();
    let (nx, ny) = (
        ((hi.0 - lo.0) / GRID).max(0.0) as usize,
        ((hi.1 - lo.1) / GRID).max(0.0) as usize,
    );
    for i in 0..=nx.min(400) {
        for j in 0..=ny.min(400) {
            let (x, y) = (lo.0 + i as f64 * GRID, lo.1 + j as f64 * GRID);
            if (region == InHand::Kitchen && y >= HEAD_STRING_Y) || !free(x, y) {
                continue;
            }
            scored.push(((x, y), best_ease(&at(config, (x, y)))));
        }
    }
    scored.sort_by(|a, b| b.1.total_cmp(&a.1));
    let mut spots: Vec<(f64, f64)> = Vec::new();
    for (p, _) in scored {
        if spots
            .iter()
            .all(|q| (q.0 - p.0).hypot(q.1 - p.1) >= SPOT_SPACING)
        {
            spots.push(p);
            if spots.len() == IN_HAND_SPOTS {
                break;
            }
        }
    }
    spots
}
