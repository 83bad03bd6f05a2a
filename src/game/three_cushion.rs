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

use super::{Shot, Verdict};
use crate::error::SimError;
use crate::simulate::events::EventKind;

/// Whether `shot` scores a point (see the module's docs). The cue ball is the one the
/// strike (the first event) hit; a shot without a strike is an error.
pub fn is_point(shot: &Shot<'_>) -> Result<bool, SimError> {
    let strike = shot.events.first().map(|r| &r.event);
    let Some(cue) = strike
        .filter(|e| e.kind == EventKind::StickBall)
        .map(|e| e.ball)
    else {
        return Err(SimError::Table(
            "three-cushion: the shot has no strike (the first event must be the cue's)".to_owned(),
        ));
    };
    let mut first_ball = None;
    let mut second_at = None;
    for e in shot.events() {
        if e.kind != EventKind::BallBall || (e.ball != cue && e.other != cue) {
            continue;
        }
        let other = if e.ball == cue { e.other } else { e.ball };
        match first_ball {
            None => first_ball = Some(other),
            Some(first) if first != other => {
                second_at = Some(e.t);
                break;
            }
            Some(_) => {}
        }
    }
    let Some(t) = second_at else {
        return Ok(false);
    };
    let cushions = shot
        .events()
        .take_while(|e| e.t < t)
        .filter(|e| e.kind == EventKind::BallLinearCushion && e.ball == cue)
        .count();
    Ok(cushions >= 3)
}

/// The verdict on `shot` (see the module's docs): legal, the turn over unless it scored.
pub fn judge(shot: &Shot<'_>) -> Result<Verdict, SimError> {
    let point = is_point(shot)?;
    Ok(Verdict {
        legal: true,
        foul: None,
        turn_over: !point,
        game_over: false,
        won: false,
    })
}
