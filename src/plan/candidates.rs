//! The shots a planner tries: for each ball the player may hit first and each pocket, the
//! ghost-ball aim of a direct pot ([`super::aim`]) where the cut is playable and both
//! paths (the cue ball's to the ghost ball, the object ball's to the pocket) are clear,
//! over a grid of speeds and spins.
//!
//! Beside them, [`safeties`]: a full hit on each ball on that the cue ball reaches
//! straight, at three speeds (meant as a legal contact; not yet chosen for the position
//! left to the opponent); 8-ball, which calls every shot, calls that ball in the pocket
//! nearest it.
//!
//! Not yet: banks, kicks, combinations, safeties chosen for the position they leave, and
//! ball in hand (issue 29's later parts).

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
    /// A full hit on ball `ball`, meant as a legal contact rather than a pot
    /// ([`safeties`]); where the game calls every shot (8-ball), it calls that ball in the
    /// pocket nearest it.
    Safety {
        /// The ball hit.
        ball: usize,
        /// The pocket nearest it (8-ball's call).
        nearest: usize,
    },
}

impl Kind {
    /// The ball it aims at (an index in the position's balls).
    pub fn ball(&self) -> usize {
        match *self {
            Kind::Pot { ball, .. } | Kind::Safety { ball, .. } => ball,
        }
    }

    /// The pocket it calls (an index in the table's pockets): a pot's, a safety's nearest.
    pub fn pocket(&self) -> usize {
        match *self {
            Kind::Pot { pocket, .. } => pocket,
            Kind::Safety { nearest, .. } => nearest,
        }
    }
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
/// Errors where the game is not one the planner plays, on a break, or where no such ball
/// is on the table.
pub fn targets(config: &StudyConfig) -> Result<Vec<usize>, String> {
    let game = config
        .game
        .as_ref()
        .ok_or("the planner needs a game (8-ball or 9-ball)")?;
    match game.rules {
        Rules::NineBall => {}
        Rules::EightBall if game.context.break_shot => {
            return Err("the planner does not plan breaks yet".into());
        }
        Rules::EightBall => {}
        other => {
            return Err(format!(
                "the planner plays 8-ball and 9-ball for now, not {}",
                other.name()
            ));
        }
    }
    let out = balls_on(config, |_| true);
    if out.is_empty() {
        return Err("no ball the player may hit first is on the table".into());
    }
    Ok(out)
}

/// The balls on (indices in `config`'s balls) among those that `left` keeps of the
/// object balls: 9-ball the lowest-numbered; 8-ball the context's hittable ones, else (the
/// group down) the 8.
pub fn balls_on(config: &StudyConfig, left: impl Fn(usize) -> bool) -> Vec<usize> {
    let game = config
        .game
        .as_ref()
        .expect("the planner's position has a game");
    let balls: Vec<usize> = (0..config.balls.len())
        .filter(|&k| k != config.cue && game.ids[k] > 0 && left(k))
        .collect();
    if game.rules == Rules::NineBall {
        return balls
            .iter()
            .copied()
            .min_by_key(|&k| game.ids[k])
            .into_iter()
            .collect();
    }
    let hittable = |k: &usize| {
        let id = game.ids[*k];
        (1..32).contains(&id) && game.context.hittable & (1 << id) != 0
    };
    let group: Vec<usize> = balls.iter().copied().filter(hittable).collect();
    if group.is_empty() {
        balls.into_iter().filter(|&k| game.ids[k] == 8).collect()
    } else {
        group
    }
}

/// How easy the easiest direct pot is for the cue ball at `cue`, 0 to 1: over the balls
/// `on` and the table's pockets, the largest `cos(cut) · exp(−(cue travel + object
/// travel) / EASE_LENGTH)` of a ghost-ball aim whose cut is under [`MAX_CUT`] with both
/// paths clear of the balls `others` (indices, the cue ball left out); 0 where there is
/// none. Positions are `config`'s.
pub fn easiest_pot(config: &StudyConfig, cue: (f64, f64), on: &[usize], others: &[usize]) -> f64 {
    let r = config.params.ball.r;
    let at = |k: usize| (config.balls[k].x, config.balls[k].y);
    let mut best = 0.0f64;
    for &b in on {
        let rest = || {
            others
                .iter()
                .copied()
                .filter(|&k| k != b && k != config.cue)
                .map(at)
        };
        for p in &config.table.pockets {
            let target = (p.center.x, p.center.y);
            let Some(aim) = ghost_ball(cue, at(b), target, r) else {
                continue;
            };
            if aim.cut < MAX_CUT
                && path_clear(cue, aim.ghost, r, rest())
                && path_clear(at(b), target, r, rest())
            {
                best = best.max(ease(&aim));
            }
        }
    }
    best
}

/// A direct pot's ease: `cos(cut) · exp(−(cue travel + object travel) / EASE_LENGTH)`.
pub fn ease(aim: &Aim) -> f64 {
    aim.cut.to_radians().cos() * (-(aim.cue_travel + aim.object_travel) / EASE_LENGTH).exp()
}

/// The length scale of a pot's ease, m ([`ease`]).
pub const EASE_LENGTH: f64 = 2.0;

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

/// The speeds of a safety, m/s.
pub const SAFETY_SPEEDS: [f64; 3] = [1.0, 2.0, 3.0];

/// A full hit, centre ball, at each of [`SAFETY_SPEEDS`], on every target of [`targets`]
/// that the cue ball reaches on a straight path clear of the other balls.
pub fn safeties(config: &StudyConfig) -> Result<Vec<Candidate>, String> {
    let r = config.params.ball.r;
    let at = |k: usize| (config.balls[k].x, config.balls[k].y);
    let cue = at(config.cue);
    let mut out = Vec::new();
    for ball in targets(config)? {
        let o = at(ball);
        let (dx, dy) = (o.0 - cue.0, o.1 - cue.1);
        let d = dx.hypot(dy);
        let others = (0..config.balls.len())
            .filter(|&k| k != config.cue && k != ball)
            .map(at);
        if d <= 2.0 * r || !path_clear(cue, o, r, others) {
            continue;
        }
        let aim = Aim {
            phi: dy.atan2(dx).to_degrees().rem_euclid(360.0),
            cut: 0.0,
            ghost: (o.0 - 2.0 * r * dx / d, o.1 - 2.0 * r * dy / d),
            cue_travel: d - 2.0 * r,
            object_travel: 0.0,
        };
        let far = |p: &crate::model::table::Pocket| (p.center.x - o.0).hypot(p.center.y - o.1);
        let nearest = (0..config.table.pockets.len())
            .min_by(|&a, &b| {
                far(&config.table.pockets[a]).total_cmp(&far(&config.table.pockets[b]))
            })
            .unwrap_or(0);
        for v0 in SAFETY_SPEEDS {
            out.push(Candidate {
                kind: Kind::Safety { ball, nearest },
                strike: CueStrike {
                    v0,
                    phi: aim.phi,
                    theta: THETA,
                    a: 0.0,
                    b: 0.0,
                },
                aim,
            });
        }
    }
    Ok(out)
}
