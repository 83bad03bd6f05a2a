//! 9-ball as pooltool 0.6.0 judges it (`pooltool/ruleset/nine_ball.py`: `is_legal`,
//! `is_turn_over`, `is_game_over`, with `pooltool/ruleset/utils.py`'s helpers).
//!
//! **A break** (the first shot of a game) is legal unless the cue ball is pocketed
//! ([`Foul::CuePocketed`]), and then only if a ball is pocketed or at least four object
//! balls reach a cushion (straight or jaw; [`Foul::BreakRails`]).
//!
//! **Any other shot**, the first foul that applies in this order:
//! 1. no ball–ball event at all ([`Foul::NoHit`]);
//! 2. the cue ball's first ball–ball contact is not with the lowest-numbered ball on the
//!    table at the start ([`Foul::WrongBallFirst`]);
//! 3. the cue ball is pocketed ([`Foul::CuePocketed`]);
//! 4. no ball (the cue ball included) touches a cushion strictly after the time of that
//!    first contact, and no object ball is pocketed ([`Foul::NoRail`]).
//!
//! The turn is over after a foul or when no object ball was pocketed; the game is over
//! after a legal shot that pocketed the highest-numbered ball on the table at the start
//! (the 9), the break included, and won by the player who shot.
//!
//! Where pooltool departs from the WPA rules (kisstime follows pooltool by default): the
//! break need not hit the 1 first — with [`Context::wpa`](super::Context::wpa) it must
//! (WPA 9-ball rule 3.2: the cue ball's first contact on the break is the 1, else
//! [`Foul::WrongBallFirst`], checked after the cue ball's pocket); a ball driven off the
//! table is no foul (pooltool's tables have no such event); a 9 pocketed on a foul stays
//! down (WPA re-spots it; pooltool's game loop re-spots a ball only when none is left,
//! which is not part of the verdict: the game is not over either way); there is no
//! push-out after the break (a choice of the next shot, not part of this one's verdict).

use super::{Foul, Played, Verdict, bit};
use crate::error::SimError;

/// The verdict on `shot`, a break where `break_shot`, with the WPA's break where `wpa`
/// (the 1 first). Errors: the shot's balls are not a pool game's ([`super::pool_cue`]), or
/// no object ball was on the table at the start.
pub fn judge(shot: &Played<'_>, break_shot: bool, wpa: bool) -> Result<Verdict, SimError> {
    let cue = shot.pool_cue()?;
    let on_table = |i: usize| i != cue && shot.on_table_at_start(i);
    let numbers = || (0..shot.ids.len()).filter(|&i| on_table(i));
    let lowest = numbers().min_by_key(|&i| shot.ids[i]);
    let highest = numbers().max_by_key(|&i| shot.ids[i]);
    let (Some(lowest), Some(highest)) = (lowest, highest) else {
        return Err(SimError::Table(
            "no numbered ball on the table at the start".to_owned(),
        ));
    };
    let pocketed = shot.pocketed();
    let cue_pocketed = pocketed & bit(cue as u32) != 0;
    let object_pocketed = pocketed & !bit(cue as u32) != 0;
    let foul = if break_shot {
        break_foul(shot, cue, cue_pocketed, pocketed != 0).or_else(|| {
            (wpa && shot.first_contact().map(|(_, b)| b) != Some(lowest))
                .then_some(Foul::WrongBallFirst)
        })
    } else {
        shot_foul(shot, lowest, cue_pocketed, object_pocketed)
    };
    let legal = foul.is_none();
    let game_over = legal && pocketed & bit(highest as u32) != 0;
    Ok(Verdict {
        legal,
        foul,
        turn_over: !legal || !object_pocketed,
        game_over,
        won: game_over,
        points: 0,
        foul_points: 0,
    })
}

/// The reason pooltool 0.6.0's 9-ball gives for `foul` (`is_legal`'s text).
pub fn pooltool_reason(foul: Foul) -> &'static str {
    foul.pooltool_reason()
}

/// A break's foul (pooltool's `_is_legal_break`, the same in 8-ball), if any.
pub(super) fn break_foul(
    shot: &Played<'_>,
    cue: usize,
    cue_pocketed: bool,
    any_pocketed: bool,
) -> Option<Foul> {
    if cue_pocketed {
        return Some(Foul::CuePocketed);
    }
    let at_cushion = shot.facts.at_cushion & !bit(cue as u32);
    (!any_pocketed && at_cushion.count_ones() < 4).then_some(Foul::BreakRails)
}

/// A shot's foul other than a break's (pooltool's `is_legal`), if any.
fn shot_foul(
    shot: &Played<'_>,
    lowest: usize,
    cue_pocketed: bool,
    object_pocketed: bool,
) -> Option<Foul> {
    let any_contact = shot.facts.any_ball_ball;
    let first = shot.first_contact();
    if !any_contact {
        return Some(Foul::NoHit);
    }
    if first.map(|(_, ball)| ball) != Some(lowest) {
        return Some(Foul::WrongBallFirst);
    }
    if cue_pocketed {
        return Some(Foul::CuePocketed);
    }
    let cushion_after = first.is_some() && shot.facts.cushion_after_first;
    (!cushion_after && !object_pocketed).then_some(Foul::NoRail)
}
