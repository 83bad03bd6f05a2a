//! The shots a planner tries: for each ball the player may hit first and each pocket, the
//! ghost-ball aim of a direct pot ([`super::aim`]) where the cut is playable and both
//! paths (the cue ball's to the ghost ball, the object ball's to the pocket) are clear,
//! over a grid of speeds and spins.
//!
//! Not yet: banks, kicks, combinations, safeties and ball in hand (issue 29's later parts).

use super::aim::{Aim, ghost_ball, path_clear};
use crate::game::Rules;
use crate::resolve::stick_ball::CueStrike;
use crate::study::StudyConfig;

/// The cut angles past which a direct pot is not tried, degrees.
pub const MAX_CUT: f64 = 80.0;

/// The cue speeds tried, m/s: soft, medium, firm, hard.
pub const SPEEDS: [f64; 4] = [1.2, 2.0, 3.0, 4.5];

/// The tip offsets tried, `(a, b)` as fractions of R: centre, follow, draw, left and right
/// side.
pub const SPINS: [(f64, f64); 5] = [(0.0, 0.0), (0.0, 0.4), (0.0, -0.4), (0.3, 0.0), (-0.3, 0.0)];

/// The cue's elevation of every candidate, degrees (a level cue, as pooltool's default
/// strike).
pub const THETA: f64 = 5.0;

/// What a candidate tries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// A direct pot of ball `ball` (an index in the position's balls) into pocket `pocket`
    /// (an index in the table's pockets).
    Pot {
        /// The object ball.
        ball: usize,
        /// The pocket.
        pocket: usize,
    },
}

/// One shot to try.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Candidate {
    /// What it tries.
    pub kind: Kind,
    /// The intended strike.
    pub strike: CueStrike,
    /// Its aim.
    pub aim: Aim,
}

/// The balls the player may hit first in `config`'s game (indices in its balls): 9-ball
/// the lowest-numbered ball on the table; 8-ball the context's hittable balls on it.
/// Errors where the game is not one the planner plays or no such ball is on the table.
pub fn targets(config: &StudyConfig) -> Result<Vec<usize>, String> {
    let game = config
        .game
        .as_ref()
        .ok_or("the planner needs a game (8-ball or 9-ball)")?;
    let on_table = |k: &usize| *k != config.cue && game.ids[*k] > 0;
    let balls: Vec<usize> = (0..config.balls.len()).filter(on_table).collect();
    let out: Vec<usize> = match game.rules {
        Rules::NineBall => balls
            .iter()
            .copied()
            .min_by_key(|&k| game.ids[k])
            .into_iter()
            .collect(),
        Rules::EightBall => {
            if game.context.break_shot {
                return Err("the planner does not plan breaks yet".into());
            }
            let hittable = |k: &usize| {
                let id = game.ids[*k];
                (1..32).contains(&id) && game.context.hittable & (1 << id) != 0
            };
            balls.into_iter().filter(hittable).collect()
        }
        other => {
            return Err(format!(
                "the planner plays 8-ball and 9-ball for now, not {}",
                other.name()
            ));
        }
    };
    if out.is_empty() {
        return Err("no ball the player may hit first is on the table".into());
    }
    Ok(out)
}

/// Every direct-pot candidate of `config`'s position (module docs): for each target of
/// [`targets`] and each pocket, the ghost-ball aim at the pocket's centre where the cut is
/// under [`MAX_CUT`] and both paths are clear, times [`SPEEDS`] and [`SPINS`] at
/// [`THETA`].
pub fn direct_pots(config: &StudyConfig) -> Result<Vec<Candidate>, String> {
    let r = config.params.ball.r;
    let at = |k: usize| (config.balls[k].x, config.balls[k].y);
    let cue = at(config.cue);
    let mut out = Vec::new();
    for ball in targets(config)? {
        let others = |skip: usize| {
            (0..config.balls.len())
                .filter(move |&k| k != config.cue && k != skip)
                .map(at)
        };
        for (pocket, p) in config.table.pockets.iter().enumerate() {
            let target = (p.center.x, p.center.y);
            let Some(aim) = ghost_ball(cue, at(ball), target, r) else {
                continue;
            };
            let clear = aim.cut < MAX_CUT
                && path_clear(cue, aim.ghost, r, others(ball))
                && path_clear(at(ball), target, r, others(ball));
            if !clear {
                continue;
            }
            for v0 in SPEEDS {
                for (a, b) in SPINS {
                    out.push(Candidate {
                        kind: Kind::Pot { ball, pocket },
                        strike: CueStrike {
                            v0,
                            phi: aim.phi,
                            theta: THETA,
                            a,
                            b,
                        },
                        aim,
                    });
                }
            }
        }
    }
    Ok(out)
}
