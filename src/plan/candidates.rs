//! The shots a planner tries: for each ball the player may hit first and each pocket, the
//! ghost-ball aim of a direct pot ([`super::aim`]) where the cut is playable and both
//! paths (the cue ball's to the ghost ball, the object ball's to the pocket) are clear,
//! over a grid of speeds and spins.
//!
//! Beside them:
//! - [`banks`]: one-rail banks (the object ball off a rail into a pocket, aimed by the
//!   mirror with a wide fan of aims around it, of which the planner keeps those that pot
//!   without noise), the [`MAX_BANKS`] easiest;
//! - [`combos`]: two-ball combinations (the cue ball hits a ball on, which pots another
//!   the player may pot), the [`MAX_COMBOS`] easiest;
//! - [`safeties`]: hits on each ball on that the cue ball reaches straight, full at
//!   three speeds, and (where no direct pot is easy: [`WEAK_POT`]) a fan of thinner hits
//!   and softer speeds, so that the simulation can choose the one that leaves the
//!   opponent least ([`super::evaluate`] scores a legal miss by the opponent's easiest
//!   next shot);
//! - [`kicks`]: where no ball on is in straight reach, the cue ball off one rail first
//!   (a fan of aims around the mirror's), the [`MAX_KICKS`] shortest.
//!
//! 8-ball, which calls every shot, calls a safety's or a kick's ball in the pocket nearest
//! it.

use super::aim::{Aim, Rail, ghost_ball, path_clear, rails};
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
    /// A one-rail bank: ball `ball` sent off rail `rail` (the cushion segment's index in
    /// the table's straight cushions) into pocket `pocket` ([`banks`]).
    Bank {
        /// The object ball.
        ball: usize,
        /// The pocket.
        pocket: usize,
        /// The rail it comes off.
        rail: usize,
    },
    /// A combination: the cue ball hits ball `first` (a ball on), which sends ball `ball`
    /// into pocket `pocket` ([`combos`]).
    Combo {
        /// The ball the cue ball hits.
        first: usize,
        /// The ball potted.
        ball: usize,
        /// The pocket.
        pocket: usize,
    },
    /// A kick: the cue ball off rail `rail` (the cushion segment's index in the table's
    /// straight cushions) first, then a hit on ball `ball`, meant as a
    /// legal contact where no ball on is in straight reach ([`kicks`]); 8-ball calls that
    /// ball in the pocket nearest it.
    Kick {
        /// The ball hit.
        ball: usize,
        /// The pocket nearest it (8-ball's call).
        nearest: usize,
        /// The rail the cue ball comes off.
        rail: usize,
    },
    /// The break: the cue ball at the head ball `ball` of the rack ([`break_shots`]); no
    /// call.
    Break {
        /// The head ball (the object ball nearest the cue ball).
        ball: usize,
    },
    /// A hit on ball `ball`, meant as a legal contact rather than a pot ([`safeties`]);
    /// where the game calls every shot (8-ball), it calls that ball in the pocket nearest
    /// it.
    Safety {
        /// The ball hit.
        ball: usize,
        /// The pocket nearest it (8-ball's call).
        nearest: usize,
    },
}

impl Kind {
    /// The ball it calls: the ball potted (a pot's, a bank's, a combination's second
    /// ball), or the ball a safety or a kick hits (an index in the position's balls).
    pub fn ball(&self) -> usize {
        match *self {
            Kind::Pot { ball, .. }
            | Kind::Bank { ball, .. }
            | Kind::Combo { ball, .. }
            | Kind::Kick { ball, .. }
            | Kind::Break { ball }
            | Kind::Safety { ball, .. } => ball,
        }
    }

    /// The ball the cue ball is meant to hit first.
    pub fn first(&self) -> usize {
        match *self {
            Kind::Combo { first, .. } => first,
            _ => self.ball(),
        }
    }

    /// The pocket it calls (an index in the table's pockets): a pot's, a safety's or a
    /// kick's nearest; a break calls none (0).
    pub fn pocket(&self) -> usize {
        match *self {
            Kind::Pot { pocket, .. } | Kind::Bank { pocket, .. } | Kind::Combo { pocket, .. } => {
                pocket
            }
            Kind::Kick { nearest, .. } | Kind::Safety { nearest, .. } => nearest,
            Kind::Break { .. } => 0,
        }
    }

    /// Whether it calls a ball and a pocket (every kind but the break).
    pub fn calls(&self) -> bool {
        !matches!(self, Kind::Break { .. })
    }

    /// Whether it means to pot the ball it calls.
    pub fn pots(&self) -> bool {
        matches!(
            self,
            Kind::Pot { .. } | Kind::Bank { .. } | Kind::Combo { .. }
        )
    }

    /// `pot`, `bank`, `combo`, `kick`, `break` or `safety`.
    pub fn name(&self) -> &'static str {
        match self {
            Kind::Pot { .. } => "pot",
            Kind::Bank { .. } => "bank",
            Kind::Combo { .. } => "combo",
            Kind::Kick { .. } => "kick",
            Kind::Break { .. } => "break",
            Kind::Safety { .. } => "safety",
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

/// A candidate of `kind` on `aim`: the stroke along the aim's φ at speed `v0`, the tip at
/// `(a, b)`, the cue at [`THETA`].
pub fn candidate(kind: Kind, aim: Aim, v0: f64, (a, b): (f64, f64)) -> Candidate {
    Candidate {
        kind,
        strike: CueStrike {
            v0,
            phi: aim.phi,
            theta: THETA,
            a,
            b,
        },
        aim,
    }
}

/// The balls the player may hit first in `config`'s game (indices in its balls): 9-ball
/// the lowest-numbered ball on the table; 8-ball the context's hittable balls on it; on a
/// break, the head ball ([`head_ball`]). Errors where the game is not one the planner
/// plays, or where no such ball is on the table.
pub fn targets(config: &StudyConfig) -> Result<Vec<usize>, String> {
    let game = config
        .game
        .as_ref()
        .ok_or("the planner needs a game (8-ball or 9-ball)")?;
    match game.rules {
        Rules::NineBall | Rules::EightBall if game.context.break_shot => {
            return head_ball(config)
                .map(|k| vec![k])
                .ok_or_else(|| "no object ball to break".into());
        }
        Rules::NineBall | Rules::EightBall => {}
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

/// The head ball of a rack: the object ball nearest the cue ball (an index in `config`'s
/// balls), if any.
pub fn head_ball(config: &StudyConfig) -> Option<usize> {
    let cue = &config.balls[config.cue];
    let far = |k: &usize| (config.balls[*k].x - cue.x).hypot(config.balls[*k].y - cue.y);
    (0..config.balls.len())
        .filter(|&k| k != config.cue)
        .min_by(|a, b| far(a).total_cmp(&far(b)))
}

/// The aims of a break: the cue ball's line moved sideways from the head ball's centre by
/// these fractions of R (a full hit, and a little to either side).
pub const BREAK_OFFSETS: [f64; 3] = [-0.3, 0.0, 0.3];
/// A break's speeds, m/s.
pub const BREAK_SPEEDS: [f64; 3] = [6.0, 7.5, 9.0];
/// A break's tip offsets: centre, and a little draw (which keeps the cue ball near the
/// middle after a full hit).
pub const BREAK_SPINS: [(f64, f64); 2] = [(0.0, 0.0), (0.0, -0.3)];

/// The break's candidates from where the cue ball is: at the head ball ([`head_ball`]),
/// each of [`BREAK_OFFSETS`] × [`BREAK_SPEEDS`] × [`BREAK_SPINS`], a level cue.
pub fn break_shots(config: &StudyConfig) -> Result<Vec<Candidate>, String> {
    let r = config.params.ball.r;
    let ball = head_ball(config).ok_or("no object ball to break")?;
    let cue = (config.balls[config.cue].x, config.balls[config.cue].y);
    let o = (config.balls[ball].x, config.balls[ball].y);
    let (dx, dy) = (o.0 - cue.0, o.1 - cue.1);
    let d = dx.hypot(dy);
    if d <= 2.0 * r {
        return Err("the cue ball touches the head ball".into());
    }
    let n = (-dy / d, dx / d);
    let mut out = Vec::new();
    for s in BREAK_OFFSETS {
        let p = (o.0 + s * r * n.0, o.1 + s * r * n.1);
        let (px, py) = (p.0 - cue.0, p.1 - cue.1);
        let aim = Aim {
            phi: py.atan2(px).to_degrees().rem_euclid(360.0),
            cut: (s.abs() / 2.0).asin().to_degrees(),
            ghost: p,
            cue_travel: d - 2.0 * r,
            object_travel: 0.0,
        };
        for v0 in BREAK_SPEEDS {
            for (a, b) in BREAK_SPINS {
                // a level cue
                let mut c = candidate(Kind::Break { ball }, aim, v0, (a, b));
                c.strike.theta = 0.0;
                out.push(c);
            }
        }
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
                    out.push(candidate(Kind::Pot { ball, pocket }, aim, v0, (a, b)));
                }
            }
        }
    }
    Ok(out)
}

/// The speeds of a safety's full hit, m/s.
pub const SAFETY_SPEEDS: [f64; 3] = [1.0, 2.0, 3.0];

/// The ease ([`ease`]) under which the best direct pot is weak, so that the planner tries
/// the fuller fan of safeties ([`safety_fan`]).
pub const WEAK_POT: f64 = 0.25;

/// The fan of safeties tried where no direct pot is easy: the cue ball's aim moved
/// sideways from the full hit by these fractions of the ball's radius (a hit of half the
/// ball at 1, thinner past it), each at [`FAN_SPEEDS`].
pub const FAN_OFFSETS: [f64; 4] = [-1.5, -0.75, 0.75, 1.5];

/// The speeds of the fan's safeties, m/s (softer than a full hit's).
pub const FAN_SPEEDS: [f64; 3] = [0.7, 1.3, 2.2];

/// A full hit, centre ball, at each of [`SAFETY_SPEEDS`], on every target of [`targets`]
/// that the cue ball reaches on a straight path clear of the other balls.
pub fn safeties(config: &StudyConfig) -> Result<Vec<Candidate>, String> {
    safeties_with(config, false)
}

/// [`safeties`], and with them, on the same balls, the cue ball aimed [`FAN_OFFSETS`]
/// radii beside the full hit at [`FAN_SPEEDS`] (where that aim's path is clear too).
pub fn safety_fan(config: &StudyConfig) -> Result<Vec<Candidate>, String> {
    safeties_with(config, true)
}

fn safeties_with(config: &StudyConfig, fan: bool) -> Result<Vec<Candidate>, String> {
    let r = config.params.ball.r;
    let at = |k: usize| (config.balls[k].x, config.balls[k].y);
    let cue = at(config.cue);
    let mut out = Vec::new();
    for ball in targets(config)? {
        let o = at(ball);
        let (dx, dy) = (o.0 - cue.0, o.1 - cue.1);
        let d = dx.hypot(dy);
        let others = || {
            (0..config.balls.len())
                .filter(move |&k| k != config.cue && k != ball)
                .map(at)
        };
        if d <= 2.0 * r || !path_clear(cue, o, r, others()) {
            continue;
        }
        let nearest = nearest_pocket(config, o);
        let kind = Kind::Safety { ball, nearest };
        let mut push = |aim: Aim, v0: f64| out.push(candidate(kind, aim, v0, (0.0, 0.0)));
        let full = Aim {
            phi: dy.atan2(dx).to_degrees().rem_euclid(360.0),
            cut: 0.0,
            ghost: (o.0 - 2.0 * r * dx / d, o.1 - 2.0 * r * dy / d),
            cue_travel: d - 2.0 * r,
            object_travel: 0.0,
        };
        for v0 in SAFETY_SPEEDS {
            push(full, v0);
        }
        if !fan {
            continue;
        }
        // the aim moved sideways: the cue ball's centre to o + s·n (n across the line)
        let n = (-dy / d, dx / d);
        for s in FAN_OFFSETS {
            let p = (o.0 + s * r * n.0, o.1 + s * r * n.1);
            if !path_clear(cue, p, r, others()) {
                continue;
            }
            let (px, py) = (p.0 - cue.0, p.1 - cue.1);
            let aim = Aim {
                phi: py.atan2(px).to_degrees().rem_euclid(360.0),
                // the cut of a hit whose line passes `s·r` beside the object ball's centre
                cut: (s.abs() / 2.0).min(1.0).asin().to_degrees(),
                ghost: p,
                cue_travel: px.hypot(py),
                object_travel: 0.0,
            };
            for v0 in FAN_SPEEDS {
                push(aim, v0);
            }
        }
    }
    Ok(out)
}

/// The index of the pocket nearest `p` among `config`'s table's.
pub fn nearest_pocket(config: &StudyConfig, p: (f64, f64)) -> usize {
    let far = |k: &usize| {
        let c = config.table.pockets[*k].center;
        (c.x - p.0).hypot(c.y - p.1)
    };
    (0..config.table.pockets.len())
        .min_by(|a, b| far(a).total_cmp(&far(b)))
        .unwrap_or(0)
}

/// The most banks tried (the easiest by [`ease`]).
pub const MAX_BANKS: usize = 4;
/// The most combinations tried (the easiest).
pub const MAX_COMBOS: usize = 4;
/// The most kicks tried (the shortest).
pub const MAX_KICKS: usize = 6;
/// The cut angle past which a bank or a combination's cut is not tried, degrees.
pub const MAX_BANK_CUT: f64 = 60.0;
/// The turns of the object ball's line tried around a bank's mirror aim, degrees: wide,
/// as a real rebound leaves the mirror's line by several degrees (the planner keeps those
/// that pot without noise: [`super::screen`]).
pub const BANK_FAN: [f64; 13] = [
    -6.0, -5.0, -4.0, -3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0,
];
/// A bank's speeds, m/s.
pub const BANK_SPEEDS: [f64; 2] = [2.5, 4.0];
/// The turns of the cue ball's line tried around a kick's mirror aim, degrees.
pub const KICK_FAN: [f64; 5] = [-1.5, -0.75, 0.0, 0.75, 1.5];
/// A kick's speeds, m/s.
pub const KICK_SPEEDS: [f64; 3] = [1.5, 2.5, 4.0];
/// A combination's speeds, m/s.
pub const COMBO_SPEEDS: [f64; 2] = [2.5, 4.0];
/// A combination's tip offsets: centre, follow, draw.
pub const COMBO_SPINS: [(f64, f64); 3] = [(0.0, 0.0), (0.0, 0.4), (0.0, -0.4)];

/// `p` turned by `deg` degrees about `o`.
fn turned(o: (f64, f64), p: (f64, f64), deg: f64) -> (f64, f64) {
    let (s, c) = deg.to_radians().sin_cos();
    let (x, y) = (p.0 - o.0, p.1 - o.1);
    (o.0 + c * x - s * y, o.1 + s * x + c * y)
}

/// One-rail banks (module docs): for each target and pocket and rail, the object ball
/// aimed at the pocket mirrored in the rail ([`Rail::mirror`]), where the rebound is on
/// the rail's stretch, the cut under [`MAX_BANK_CUT`] and every path (the cue ball's to
/// the ghost ball, the object ball's to the rail and on to the pocket) clear; the
/// [`MAX_BANKS`] easiest, each over [`BANK_FAN`] × [`BANK_SPEEDS`], centre ball.
pub fn banks(config: &StudyConfig) -> Result<Vec<Candidate>, String> {
    let r = config.params.ball.r;
    let at = |k: usize| (config.balls[k].x, config.balls[k].y);
    let cue = at(config.cue);
    let rails = rails(&config.table, r);
    let mut found: Vec<(f64, Kind, (f64, f64))> = Vec::new();
    for ball in targets(config)? {
        let o = at(ball);
        let others = || {
            (0..config.balls.len())
                .filter(move |&k| k != config.cue && k != ball)
                .map(at)
        };
        for (pocket, p) in config.table.pockets.iter().enumerate() {
            let target = (p.center.x, p.center.y);
            for rail in &rails {
                let mirrored = rail.mirror(target);
                let Some(bounce) = rail.bounce(o, mirrored, r) else {
                    continue;
                };
                let Some(mut aim) = ghost_ball(cue, o, mirrored, r) else {
                    continue;
                };
                let clear = aim.cut < MAX_BANK_CUT
                    && path_clear(cue, aim.ghost, r, others())
                    && path_clear(o, bounce, r, others())
                    && path_clear(bounce, target, r, others());
                if !clear {
                    continue;
                }
                aim.object_travel = (bounce.0 - o.0).hypot(bounce.1 - o.1)
                    + (target.0 - bounce.0).hypot(target.1 - bounce.1);
                let kind = Kind::Bank {
                    ball,
                    pocket,
                    rail: rail.segment,
                };
                found.push((ease(&aim), kind, mirrored));
            }
        }
    }
    found.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut out = Vec::new();
    for &(_, kind, mirrored) in found.iter().take(MAX_BANKS) {
        let o = at(kind.ball());
        for turn in BANK_FAN {
            let Some(mut aim) = ghost_ball(cue, o, turned(o, mirrored, turn), r) else {
                continue;
            };
            aim.object_travel = (mirrored.0 - o.0).hypot(mirrored.1 - o.1);
            for v0 in BANK_SPEEDS {
                out.push(candidate(kind, aim, v0, (0.0, 0.0)));
            }
        }
    }
    Ok(out)
}

/// Two-ball combinations (module docs): the cue ball sends a target `first` to the ghost
/// ball of another ball `ball` the player may pot (9-ball: any; 8-ball: another of the
/// balls on) for a pocket, each cut under [`MAX_BANK_CUT`] and every path clear; the
/// [`MAX_COMBOS`] easiest (the product of the two cuts' cosines and the travel's
/// `exp(−travel / EASE_LENGTH)`), each over [`COMBO_SPEEDS`] × [`COMBO_SPINS`].
pub fn combos(config: &StudyConfig) -> Result<Vec<Candidate>, String> {
    let r = config.params.ball.r;
    let at = |k: usize| (config.balls[k].x, config.balls[k].y);
    let cue = at(config.cue);
    let game = config.game.as_ref().ok_or("the planner needs a game")?;
    let firsts = targets(config)?;
    let pottable: Vec<usize> = if game.rules == Rules::NineBall {
        (0..config.balls.len())
            .filter(|&k| k != config.cue && game.ids[k] > 0)
            .collect()
    } else {
        firsts.clone()
    };
    let mut found: Vec<(f64, Candidate)> = Vec::new();
    for &first in &firsts {
        for &ball in &pottable {
            if ball == first {
                continue;
            }
            let (a, b) = (at(first), at(ball));
            let others = || {
                (0..config.balls.len())
                    .filter(move |&k| k != config.cue && k != first && k != ball)
                    .map(at)
            };
            for (pocket, p) in config.table.pockets.iter().enumerate() {
                let target = (p.center.x, p.center.y);
                let Some(second) = ghost_ball(a, b, target, r) else {
                    continue;
                };
                let Some(aim) = ghost_ball(cue, a, second.ghost, r) else {
                    continue;
                };
                let clear = second.cut < MAX_BANK_CUT
                    && aim.cut < MAX_BANK_CUT
                    && path_clear(cue, aim.ghost, r, others().chain([b]))
                    && path_clear(a, second.ghost, r, others())
                    && path_clear(b, target, r, others().chain([a]));
                if !clear {
                    continue;
                }
                let travel = aim.cue_travel + second.cue_travel + second.object_travel;
                let score = aim.cut.to_radians().cos()
                    * second.cut.to_radians().cos()
                    * (-travel / EASE_LENGTH).exp();
                let aim = Aim {
                    object_travel: second.cue_travel + second.object_travel,
                    ..aim
                };
                let kind = Kind::Combo {
                    first,
                    ball,
                    pocket,
                };
                found.push((
                    score,
                    Candidate {
                        kind,
                        strike: CueStrike {
                            v0: 0.0,
                            phi: aim.phi,
                            theta: THETA,
                            a: 0.0,
                            b: 0.0,
                        },
                        aim,
                    },
                ));
            }
        }
    }
    found.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut out = Vec::new();
    for (_, c) in found.into_iter().take(MAX_COMBOS) {
        for v0 in COMBO_SPEEDS {
            for (a, b) in COMBO_SPINS {
                out.push(Candidate {
                    strike: CueStrike {
                        v0,
                        a,
                        b,
                        ..c.strike
                    },
                    ..c
                });
            }
        }
    }
    Ok(out)
}

/// One-rail kicks (module docs): for each target and rail, the cue ball aimed at the
/// target mirrored in the rail (a full hit after an ideal rebound), where the rebound is
/// on the rail's stretch and both legs clear of the other balls; the [`MAX_KICKS`]
/// shortest, each over [`KICK_FAN`] × [`KICK_SPEEDS`], centre ball.
pub fn kicks(config: &StudyConfig) -> Result<Vec<Candidate>, String> {
    let r = config.params.ball.r;
    let at = |k: usize| (config.balls[k].x, config.balls[k].y);
    let cue = at(config.cue);
    let rails: Vec<Rail> = rails(&config.table, r);
    let mut found: Vec<(f64, Kind, (f64, f64))> = Vec::new();
    for ball in targets(config)? {
        let o = at(ball);
        let others = || {
            (0..config.balls.len())
                .filter(move |&k| k != config.cue && k != ball)
                .map(at)
        };
        for rail in &rails {
            let mirrored = rail.mirror(o);
            let Some(bounce) = rail.bounce(cue, mirrored, r) else {
                continue;
            };
            if !(path_clear(cue, bounce, r, others()) && path_clear(bounce, o, r, others())) {
                continue;
            }
            let travel =
                (bounce.0 - cue.0).hypot(bounce.1 - cue.1) + (o.0 - bounce.0).hypot(o.1 - bounce.1);
            let kind = Kind::Kick {
                ball,
                nearest: nearest_pocket(config, o),
                rail: rail.segment,
            };
            found.push((travel, kind, mirrored));
        }
    }
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out = Vec::new();
    for &(travel, kind, mirrored) in found.iter().take(MAX_KICKS) {
        for turn in KICK_FAN {
            let m = turned(cue, mirrored, turn);
            let (dx, dy) = (m.0 - cue.0, m.1 - cue.1);
            let aim = Aim {
                phi: dy.atan2(dx).to_degrees().rem_euclid(360.0),
                cut: 0.0,
                ghost: m,
                cue_travel: travel - 2.0 * r,
                object_travel: 0.0,
            };
            for v0 in KICK_SPEEDS {
                out.push(candidate(kind, aim, v0, (0.0, 0.0)));
            }
        }
    }
    Ok(out)
}

/// The balls the opponent may hit first after a shot that passes the turn, among those
/// that `left` keeps (indices in `config`'s balls): 9-ball the lowest-numbered; 8-ball the
/// other group (the player's group down: every object ball but the 8; an open table:
/// the same balls as the player's), else the 8.
pub fn opponent_on(config: &StudyConfig, left: impl Fn(usize) -> bool) -> Vec<usize> {
    let game = config
        .game
        .as_ref()
        .expect("the planner's position has a game");
    if game.rules == Rules::NineBall {
        return balls_on(config, left);
    }
    let (solids, stripes) = (0b1111_1110u32, 0b1111_1110u32 << 8);
    let mine = game.context.hittable;
    let theirs = if mine & solids != 0 && mine & stripes != 0 {
        mine
    } else if mine & solids != 0 {
        stripes
    } else if mine & stripes != 0 {
        solids
    } else {
        solids | stripes
    };
    let balls: Vec<usize> = (0..config.balls.len())
        .filter(|&k| k != config.cue && game.ids[k] > 0 && left(k))
        .collect();
    let group: Vec<usize> = balls
        .iter()
        .copied()
        .filter(|&k| (1..32).contains(&game.ids[k]) && theirs & (1 << game.ids[k]) != 0)
        .collect();
    if group.is_empty() {
        balls.into_iter().filter(|&k| game.ids[k] == 8).collect()
    } else {
        group
    }
}
