//! 8-ball as pooltool 0.6.0 judges it (`pooltool/ruleset/eight_ball.py`: `is_legal`,
//! `is_turn_over`, `is_game_over`, `decide_winner`), given the shot's [`Context`] (its
//! `ShotConstraints`: the group the player may hit first, whether the shot must be called,
//! the call).
//!
//! **A break** is judged as 9-ball's ([`super::nine_ball`]): legal unless the cue ball is
//! pocketed, and then only if a ball is pocketed or four object balls reach a cushion.
//!
//! **Any other shot**, the first foul that applies in this order (the cue ball's pocket
//! comes first here, unlike 9-ball):
//! 1. the cue ball is pocketed ([`Foul::CuePocketed`]);
//! 2. no ball–ball event at all ([`Foul::NoHit`]);
//! 3. the cue ball's first ball–ball contact is not with a ball of the context's
//!    `hittable` ([`Foul::WrongBallFirst`]);
//! 4. no ball touches a cushion strictly after the time of that contact and no object
//!    ball is pocketed ([`Foul::NoRail`]);
//! 5. the shot had to be called and its ball or pocket is missing ([`Foul::NotCalled`]);
//!
//! and then, whatever came before, the 8 pocketed when it was not hittable or (its first
//! pocket) in another pocket than the one called ([`Foul::EightIllegal`]).
//!
//! The turn is over after a foul; after a legal shot, where no call was asked for, unless a
//! hittable ball was pocketed; where one was, unless the called ball went into the called
//! pocket. The game is over whenever the 8 is pocketed (the break included): won by the
//! player who shot if the shot was legal, lost otherwise.
//!
//! Where pooltool departs from the WPA rules (kisstime follows pooltool by default): the 8
//! pocketed on the break ends the game — with [`Context::wpa`](super::Context::wpa) it ends
//! none (WPA 8-ball rule 3.4: the 8 is re-spotted or the table re-racked, after a legal
//! break or a scratch alike), and a legal break with the 8 down keeps the table; the break needs no call, and a
//! legal break keeps the table only if a ball other than the 8 is pocketed; an open table
//! after the break takes any ball but the 8 first; no combination or safety call; the cue
//! ball's pocket outranks the other fouls in the reason given.

use super::nine_ball::break_foul;
use super::{Context, Foul, Played, Verdict, bit};
use crate::error::SimError;

/// The verdict on `shot` in `context`. Errors: the shot's balls are not a pool game's
/// ([`super::pool_cue`]). (A call of a ball or pocket the table lacks is the caller's to
/// refuse: here it is a call that cannot come true.)
pub fn judge(shot: &Played<'_>, context: &Context) -> Result<Verdict, SimError> {
    let cue = shot.pool_cue()?;
    let pocketed = shot.pocketed();
    let cue_pocketed = pocketed & bit(cue as u32) != 0;
    let object_pocketed = pocketed & !bit(cue as u32) != 0;
    let mut foul = if context.break_shot {
        break_foul(shot, cue, cue_pocketed, pocketed != 0)
    } else {
        shot_foul(shot, context, cue_pocketed, object_pocketed)
    };
    // the 8's first pocket, if it went down
    let eight = shot.index_of(8);
    let eight_pocket = eight.and_then(|i| shot.pocket_of(i));
    if !context.break_shot
        && let Some(pocket) = eight_pocket
        && (context.hittable & (1 << 8) == 0 || context.pocket_call != Some(pocket))
    {
        foul = Some(Foul::EightIllegal);
    }
    let legal = foul.is_none();
    // WPA 3.4: the 8 on the break ends no game (it is re-spotted, or the table re-racked),
    // and after a legal break with the 8 down the breaker shoots again
    let wpa_break = context.wpa && context.break_shot;
    let kept = keeps_table(shot, context, pocketed & !bit(cue as u32))
        || (wpa_break && eight_pocket.is_some());
    let turn_over = !legal || !kept;
    let game_over = eight_pocket.is_some() && !wpa_break;
    Ok(Verdict {
        legal,
        foul,
        turn_over,
        game_over,
        won: game_over && legal,
        points: 0,
        foul_points: 0,
    })
}

/// The reason pooltool 0.6.0's 8-ball gives for `foul` (`is_legal`'s text).
pub fn pooltool_reason(foul: Foul) -> &'static str {
    match foul {
        Foul::WrongBallFirst => "First contact wasn't made with target balls",
        other => other.pooltool_reason(),
    }
}

/// A shot's foul other than a break's (pooltool's `is_legal` before its 8-ball check), if
/// any.
fn shot_foul(
    shot: &Played<'_>,
    context: &Context,
    cue_pocketed: bool,
    object_pocketed: bool,
) -> Option<Foul> {
    if cue_pocketed {
        return Some(Foul::CuePocketed);
    }
    if !shot.facts.any_ball_ball {
        return Some(Foul::NoHit);
    }
    let first = shot.first_contact();
    let hittable = |i: usize| {
        let n = shot.ids[i];
        (1..=15).contains(&n) && context.hittable & (1 << n) != 0
    };
    if !first.is_some_and(|(_, ball)| hittable(ball)) {
        return Some(Foul::WrongBallFirst);
    }
    let cushion_after = first.is_some() && shot.facts.cushion_after_first;
    if !cushion_after && !object_pocketed {
        return Some(Foul::NoRail);
    }
    let called = context.ball_call.is_some() && context.pocket_call.is_some();
    (context.call_shot && !called).then_some(Foul::NotCalled)
}

/// Whether a legal shot keeps the player at the table (pooltool's `is_turn_over` after a
/// legal shot): without a call, a hittable ball pocketed; with one, the called ball in the
/// called pocket. `object_pocketed` is the set of balls pocketed (indices).
fn keeps_table(shot: &Played<'_>, context: &Context, object_pocketed: u64) -> bool {
    if !context.call_shot {
        return (0..shot.ids.len()).any(|i| {
            let n = shot.ids[i];
            object_pocketed & bit(i as u32) != 0
                && (1..=15).contains(&n)
                && context.hittable & (1 << n) != 0
        });
    }
    let (Some(ball), Some(pocket)) = (context.ball_call, context.pocket_call) else {
        return false;
    };
    let Some(i) = shot.index_of(ball) else {
        return false;
    };
    shot.pocket_of(i) == Some(pocket)
}
