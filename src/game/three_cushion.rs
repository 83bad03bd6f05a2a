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
//! point scores 1 ([`Verdict::points`]) and keeps the turn, no point ends it. The game is
//! over, and won by the player who shot, when the point brings their score (the context's
//! [`Context::score`](super::Context::score) before the shot, plus 1) to [`WIN_POINTS`]
//! (pooltool's `is_game_over` with its `win_condition` default, 10).
//!
//! Reference: `data/carom`'s `shots.csv` has pooltool's own `is_point` on each of its 40
//! shots; `tests/sim_tables.rs` checks this judge on kisstime's replays of them.

use super::{Context, Played, Verdict};
use crate::error::SimError;

/// The points that win a game (pooltool's `_ThreeCushion(win_condition=10)`).
pub const WIN_POINTS: u32 = 10;

/// Whether the shot scores a point (see the module's docs), from its facts following the
/// ball struck (`played.cue`).
pub fn is_point(played: &Played<'_>) -> bool {
    let f = played.facts;
    f.first_ball.is_some() && f.second_ball_t.is_some() && f.cue_cushions >= 3
}

/// The verdict on `played` with the score before it in `context` (see the module's docs):
/// legal, a point or the turn over, the game over at [`WIN_POINTS`]. (It cannot fail; the
/// `Result` is the judges' common form.)
pub fn judge(played: &Played<'_>, context: &Context) -> Result<Verdict, SimError> {
    let point = is_point(played);
    let game_over = point && context.score[0].saturating_add(1) == WIN_POINTS;
    Ok(Verdict {
        legal: true,
        foul: None,
        turn_over: !point,
        game_over,
        won: game_over,
        points: u32::from(point),
        foul_points: 0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::ball_state::BallState;
    use crate::simulate::watch::ShotFacts;

    #[test]
    fn a_point_scores_one_and_the_tenth_wins() {
        let start = [BallState::at_rest(0.3, 0.3, 0.0305); 3];
        let point = ShotFacts {
            first_ball: Some((0.5, 1)),
            second_ball_t: Some(1.5),
            cue_cushions: 3,
            ..ShotFacts::default()
        };
        let miss = ShotFacts {
            cue_cushions: 2,
            ..point
        };
        let judge = |facts: &ShotFacts, score: [u32; 2]| {
            let played = Played {
                ids: &[0, 1, 2],
                start: &start,
                cue: 0,
                facts,
            };
            let context = Context {
                score,
                ..Context::default()
            };
            judge(&played, &context).unwrap()
        };
        let v = judge(&point, [3, 9]);
        assert_eq!((v.points, v.turn_over, v.game_over), (1, false, false));
        let v = judge(&point, [WIN_POINTS - 1, 9]);
        assert_eq!((v.points, v.game_over, v.won), (1, true, true));
        let v = judge(&miss, [WIN_POINTS - 1, 0]);
        assert_eq!((v.points, v.turn_over, v.game_over), (0, true, false));
    }
}
