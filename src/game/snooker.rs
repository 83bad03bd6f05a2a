//! Snooker as pooltool 0.6.0 judges it (`pooltool/ruleset/snooker/core.py`: `is_legal`,
//! `is_turn_over`, `is_game_over`, `_Snooker.get_score`, `decide_winner`; its helpers in
//! `snooker/utils.py`; the table is `--table snooker`).
//!
//! **The balls** have kisstime ids ([`id_of`], [`name`]): the white 0, pooltool's
//! `red_01` … `red_15` 1 to 15, then the colours yellow 16, green 17, brown 18, blue 19,
//! pink 20, black 21. Each is worth its [`value`]: a red 1, the colours 2 (yellow) to 7
//! (black), the white 4 (pooltool's `ball_info(…).points`, which the foul's penalty reads).
//!
//! **The balls on** (pooltool's `get_on_balls`), from the context's `hittable`
//! ([`Context::hittable`]): reds, or colours, never both (an error). When the player is on
//! more than one colour (after potting a red) they must name one, `ball_call`, and only it
//! is on; otherwise the hittable balls are on. An empty `hittable` is worked out from the
//! table (kisstime's default, where pooltool has the game's state): the reds, if any red is
//! on the table at the start, else the lowest-valued colour on it (the sequential phase,
//! as pooltool's `get_lowest_pottable` names it). A shot on colours is a called shot
//! (pooltool's `call_shot`): the called ball is `ball_call` or, on a single colour, that
//! colour.
//!
//! **The foul**, the first that applies in this order (`is_legal`):
//! 1. the white is pocketed ([`Foul::CuePocketed`]);
//! 2. no ball–ball event at all ([`Foul::NoHit`]);
//! 3. the white's first ball–ball contact is not with a ball on ([`Foul::WrongBallFirst`]);
//! 4. a ball not on is pocketed ([`Foul::OffBallPocketed`]).
//!
//! **The turn** is over after a foul or when nothing was pocketed (`is_turn_over`). **The
//! game** is over only on the final black (at the start exactly the white and the black on
//! the table): after a foul, or when the black is pocketed (`is_game_over`).
//!
//! **The points** (`get_score`): a legal shot that keeps the table scores the pocketed
//! balls' values for the player who shot ([`Verdict::points`]); a foul gives the opponent
//! ([`Verdict::foul_points`]) the largest value among the white, the balls pocketed, the
//! first ball hit and, on a called shot, the called ball — at least 4 (`get_foul_points`).
//! When the game is over the player with more points (the context's
//! [`Context::score`] plus this shot's) wins; equal scores are a tie (no winner, as
//! pooltool's `decide_winner`).
//!
//! Where pooltool departs from the snooker rules (kisstime follows pooltool; a verdict
//! cannot tell the rest): no free ball, no miss, no push or jump shot; a tie on the final
//! black ends the game (the rules re-spot the black); the re-spotting of colours and the
//! next shot's ball on are the game's next state, not this shot's verdict.

use super::{Context, Foul, Played, Verdict, bit};
use crate::error::SimError;

/// The white's id.
pub const WHITE: i64 = 0;
/// The black's id.
pub const BLACK: i64 = 21;
/// The ids of the reds, as a set ([`Context::hittable`]'s bits).
pub const REDS: u32 = 0xFFFF & !1;
/// The ids of the colours, as a set.
pub const COLOURS: u32 = 0b11_1111 << 16;

/// pooltool's ball ids, index = kisstime id.
const NAMES: [&str; 22] = [
    "white", "red_01", "red_02", "red_03", "red_04", "red_05", "red_06", "red_07", "red_08",
    "red_09", "red_10", "red_11", "red_12", "red_13", "red_14", "red_15", "yellow", "green",
    "brown", "blue", "pink", "black",
];

/// pooltool's name of ball `id` (`white`, `red_01` … `red_15`, `yellow` … `black`).
pub fn name(id: i64) -> Option<&'static str> {
    usize::try_from(id).ok().and_then(|i| NAMES.get(i)).copied()
}

/// The kisstime id of the ball pooltool names `name` (see the module's docs).
pub fn id_of(name: &str) -> Option<i64> {
    NAMES.iter().position(|&n| n == name).map(|i| i as i64)
}

/// What ball `id` is worth: a red 1, yellow 2 … black 7, the white 4; 0 for no snooker
/// ball.
pub fn value(id: i64) -> u32 {
    match id {
        WHITE => 4,
        1..=15 => 1,
        16..=BLACK => (id - 14) as u32,
        _ => 0,
    }
}

/// The bit of ball id `id` in a set of ids (none outside 0..=21).
fn id_bit(id: i64) -> u32 {
    if (0..=BLACK).contains(&id) {
        1 << id
    } else {
        0
    }
}

/// Checks a snooker context for what no shot can judge: `hittable` holding both reds and
/// colours (or balls that are neither), or several colours on and no colour called.
pub fn check_context(context: &Context) -> Result<(), String> {
    let h = context.hittable;
    if h & !(REDS | COLOURS) != 0 {
        return Err("hittable: snooker's balls on are reds (1 to 15) or colours (16 to 21)".into());
    }
    if h & REDS != 0 && h & COLOURS != 0 {
        return Err("hittable: snooker's balls on are reds or colours, not both".to_owned());
    }
    if (h & COLOURS).count_ones() > 1 && context.ball_call.is_none_or(|b| id_bit(b) & COLOURS == 0)
    {
        return Err(
            "ball_call: on several colours (after a red) the player must call one".to_owned(),
        );
    }
    Ok(())
}

/// The balls on in `context` for `shot` (a set of ids) and the called ball (on colours),
/// as the module's docs say.
fn on_balls(shot: &Played<'_>, context: &Context) -> Result<(u32, Option<i64>), SimError> {
    check_context(context).map_err(SimError::Table)?;
    let mut hittable = context.hittable;
    if hittable == 0 {
        let at_start = |i: usize| shot.on_table_at_start(i);
        let reds = (0..shot.ids.len())
            .filter(|&i| at_start(i))
            .fold(0, |set, i| set | (id_bit(shot.ids[i]) & REDS));
        hittable = if reds != 0 {
            REDS
        } else {
            (0..shot.ids.len())
                .filter(|&i| at_start(i) && id_bit(shot.ids[i]) & COLOURS != 0)
                .map(|i| shot.ids[i])
                .min()
                .map_or(0, id_bit)
        };
    }
    if hittable & COLOURS == 0 {
        return Ok((hittable, None));
    }
    if hittable.count_ones() > 1 {
        // checked above: a colour is called
        let call = context.ball_call.unwrap_or(BLACK);
        return Ok((id_bit(call), Some(call)));
    }
    let single = hittable.trailing_zeros() as i64;
    Ok((hittable, Some(context.ball_call.unwrap_or(single))))
}

/// Checks the balls of a snooker game: one id per ball, each 0 to 21 and none twice, the
/// white (0) among them. Returns the white's index.
pub fn snooker_cue(ids: &[i64], start_len: usize) -> Result<usize, SimError> {
    if ids.len() != start_len {
        return Err(SimError::Table(format!(
            "{} ball ids for {start_len} balls",
            ids.len()
        )));
    }
    let mut seen = 0u32;
    for (index, &id) in ids.iter().enumerate() {
        let b = id_bit(id);
        if b == 0 {
            return Err(SimError::Ball {
                index,
                reason: format!(
                    "id {id}: snooker's balls are the white (0), the reds (1 to 15) and the \
                     colours (16 yellow to 21 black)"
                ),
            });
        }
        if seen & b != 0 {
            return Err(SimError::Ball {
                index,
                reason: format!("a second ball with id {id}"),
            });
        }
        seen |= b;
    }
    ids.iter()
        .position(|&id| id == WHITE)
        .ok_or_else(|| SimError::Table("no white (id 0) on the table".to_owned()))
}

/// The verdict on `shot` in `context` (see the module's docs). Errors: the balls are not
/// snooker's ([`snooker_cue`]), the facts do not follow the white, or the context cannot
/// be judged ([`check_context`]).
pub fn judge(shot: &Played<'_>, context: &Context) -> Result<Verdict, SimError> {
    shot.check_cue(snooker_cue(shot.ids, shot.start.len())?, "the white")?;
    let (on, call) = on_balls(shot, context)?;
    // the pocketed balls, as a set of ids
    let pocketed = (0..shot.ids.len())
        .filter(|&i| shot.pocketed() & bit(i as u32) != 0)
        .fold(0u32, |set, i| set | id_bit(shot.ids[i]));
    let first = shot.first_contact().map(|(_, i)| shot.ids[i]);
    let foul = if pocketed & id_bit(WHITE) != 0 {
        Some(Foul::CuePocketed)
    } else if !shot.facts.any_ball_ball {
        Some(Foul::NoHit)
    } else if first.is_none_or(|id| on & id_bit(id) == 0) {
        Some(Foul::WrongBallFirst)
    } else if pocketed & !on != 0 {
        Some(Foul::OffBallPocketed)
    } else {
        None
    };
    let legal = foul.is_none();
    let turn_over = !legal || pocketed == 0;
    let values = |set: u32| {
        (0..=BLACK)
            .filter(move |&id| set & id_bit(id) != 0)
            .map(value)
    };
    let points = if legal { values(pocketed).sum() } else { 0 };
    let foul_points = if legal {
        0
    } else {
        let offending = pocketed | id_bit(WHITE) | first.map_or(0, id_bit) | call.map_or(0, id_bit);
        values(offending).max().unwrap_or(0).max(4)
    };
    // the final black: the white and the black alone on the table at the start
    let on_at_start = (0..shot.ids.len())
        .filter(|&i| shot.on_table_at_start(i))
        .fold(0u32, |set, i| set | id_bit(shot.ids[i]));
    let final_black = on_at_start == id_bit(WHITE) | id_bit(BLACK);
    let game_over = final_black && (!legal || pocketed & id_bit(BLACK) != 0);
    let [mine, theirs] = context.score;
    // in u64: a score read from a context file may be any u32 (the `rules_judge` fuzz
    // target's finding 10: `u32::MAX` overflowed the sum)
    let won = game_over
        && u64::from(mine) + u64::from(points) > u64::from(theirs) + u64::from(foul_points);
    Ok(Verdict {
        legal,
        foul,
        turn_over,
        game_over,
        won,
        points,
        foul_points,
    })
}

/// The reason pooltool 0.6.0's snooker gives for `foul` (`snooker.utils.Reason`).
pub fn pooltool_reason(foul: Foul) -> &'static str {
    match foul {
        Foul::NoHit => "No ball contacted!",
        Foul::WrongBallFirst => "First contact made with a ball that's not on!",
        Foul::OffBallPocketed => "Pocketed a ball that's not on!",
        other => other.pooltool_reason(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_ids_and_values_agree_with_pooltool() {
        assert_eq!(id_of("white"), Some(0));
        assert_eq!(id_of("red_07"), Some(7));
        assert_eq!(id_of("yellow"), Some(16));
        assert_eq!(id_of("black"), Some(BLACK));
        assert_eq!(id_of("red"), None);
        assert_eq!(name(15), Some("red_15"));
        assert_eq!(name(22), None);
        assert_eq!(name(-1), None);
        let v: Vec<u32> = (16..=21).map(value).collect();
        assert_eq!(v, [2, 3, 4, 5, 6, 7]);
        assert_eq!((value(0), value(3), value(22)), (4, 1, 0));
        assert_eq!(REDS.count_ones(), 15);
        assert_eq!(COLOURS, (16..=21).fold(0, |s, i| s | (1 << i)));
    }

    #[test]
    fn contexts_that_cannot_be_judged_are_refused() {
        let c = |hittable, ball_call| Context {
            hittable,
            ball_call,
            ..Context::default()
        };
        assert!(check_context(&c(REDS, None)).is_ok());
        assert!(check_context(&c(1 << 19, None)).is_ok());
        assert!(check_context(&c(COLOURS, Some(19))).is_ok());
        let e = check_context(&c(COLOURS, None)).unwrap_err();
        assert!(e.contains("call one"), "{e}");
        let e = check_context(&c(COLOURS, Some(3))).unwrap_err();
        assert!(e.contains("call one"), "{e}");
        let e = check_context(&c(REDS | (1 << 16), None)).unwrap_err();
        assert!(e.contains("not both"), "{e}");
        let e = check_context(&c(1 << 22, None)).unwrap_err();
        assert!(e.contains("16 to 21"), "{e}");
    }
}
