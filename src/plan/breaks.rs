//! The break: where to put the cue ball behind the head string and how to strike the rack,
//! so that the break is legal, pots a ball and leaves the cue ball on the table — and,
//! the value of a kept table weighing the next shot ([`super::evaluate`]), leaves a shot.
//!
//! Method: the cue ball is placed at each of [`BREAK_SPOTS`] (across the table, a little
//! behind the head string, as a rack's cue ball), and from each the break's candidates
//! ([`super::candidates::break_shots`]: at the head ball, full and a little to either
//! side, three speeds, centre ball and a little draw) are planned in full as any
//! position ([`super::plan`]: common random numbers, halving, the refinement, fresh final
//! estimates), the budget shared between the spots ([`super::in_hand::plan_at`]); the
//! spot whose best break has the highest value on its fresh draws wins. The verdicts are
//! the game's on a break (pooltool's rules: [`crate::game`]).

use super::in_hand::{cue_fits, plan_at};
use super::{Plan, PlanOptions};
use crate::engine::ShotEngine;
use crate::error::{Error, InputError};
use crate::game::progress::HEAD_STRING_Y;
use crate::study::StudyConfig;

/// The cue ball's spots tried: x across the 9-ft table's width (its middle, 0.635 m, and
/// 0.2 m and 0.4 m to either side), y [`BREAK_Y`].
pub const BREAK_SPOTS: [f64; 5] = [0.235, 0.435, 0.635, 0.835, 1.035];
/// The spots' y: 0.1 m behind the head string (where a rack's cue ball waits).
pub const BREAK_Y: f64 = HEAD_STRING_Y - 0.1;

/// A break's first round: samples of each candidate at most.
pub const BREAK_FIRST_SAMPLES: usize = 16;
/// A break's first round at each spot: samples over all candidates at most.
pub const BREAK_FIRST_ROUND: usize = 256;

/// The break from `config`'s rack (module docs): its cue ball (wherever it is) placed by
/// the planner, [`Plan::placement`] the spot. `config`'s game must be on its break.
/// Errors: not a break, no spot free on the table, and as [`super::plan`]'s.
pub fn plan_break(
    engine: &mut ShotEngine,
    config: &StudyConfig,
    options: &PlanOptions,
) -> Result<Plan, Error> {
    if !config.game.as_ref().is_some_and(|g| g.context.break_shot) {
        return Err(InputError::new("not a break: the game's context is not on its break").into());
    }
    let spots: Vec<(f64, f64)> = BREAK_SPOTS
        .iter()
        .map(|&x| (x, BREAK_Y))
        .filter(|&(x, y)| cue_fits(config, x, y))
        .collect();
    if spots.is_empty() {
        return Err(InputError::new("no free spot behind the head string for the break").into());
    }
    // a break simulates a rack: a smaller first round, so that a time budget is kept
    let options = PlanOptions {
        first_samples: options.first_samples.min(BREAK_FIRST_SAMPLES),
        first_round: options.first_round.min(BREAK_FIRST_ROUND),
        ..options.clone()
    };
    plan_at(engine, config, &options, &spots)
}
