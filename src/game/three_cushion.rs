//! Three-cushion billiards (carom), as pooltool 0.6.0 judges a shot
//! (`pooltool/ruleset/three_cushion.py`: `is_point`, `is_turn_over`; the table is
//! `--table carom`, the balls white, yellow and red).
//!
//! **The point** (`is_point`): the cue ball — the ball the strike hit, pooltool's
//! `cue.cue_ball_id` — must meet both other balls, and before it first meets the second
//! one it must have made at least three cushion contacts. Method, as pooltool's: the cue
//! ball's ball–ball events in order give the first and the second object ball hit (the
//! second is the first event with a ball other than the first); the cue ball's
//! straight-cushion events (`ball_linear_cushion`) strictly before that event's time are
//! counted (pooltool's `by_time(t, after=False)` is strict). Jaws and pockets do not
//! count; the carom table has none.
//!
//! **The verdict**: every three-cushion shot is legal (pooltool has no fouls there); a
//! point keeps the turn, no point ends it. Whether the game is over depends on the running
//! score, which one shot does not carry (pooltool's `is_game_over(score, …)`), so
//! `game_over` and `won` are false here; count the points (`!turn_over`) to keep score.
//!
//! Reference: `data/carom`'s `shots.csv` has pooltool's own `is_point` on each of its 40
//! shots; `tests/sim_tables.rs` checks this judge on kisstime's replays of them.

use super::{Played, Verdict};
use crate::error::SimError;

/// Whether the shot scores a point (see the module's docs), from its facts following the
/// ball struck (`played.cue`).
pub fn is_point(played: &Played<'_>) -> bool {
    let f = played.facts;
    f.first_ball.is_some() && f.second_ball_t.is_some() && f.cue_cushions >= 3
}

/// The verdict on `played` (see the module's docs): legal, the turn over unless it
/// scored. (It cannot fail; the `Result` is the judges' common form.)
pub fn judge(played: &Played<'_>) -> Result<Verdict, SimError> {
    let point = is_point(played);
    Ok(Verdict {
        legal: true,
        foul: None,
        turn_over: !point,
        game_over: false,
        won: false,
    })
}
