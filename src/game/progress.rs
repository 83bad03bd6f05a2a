//! A pool game in progress between shots: the balls on the table, whose turn it is, the
//! cue ball in hand, the break, 8-ball's groups — and what one judged shot does to them.
//! Self-play ([`crate::plan::play`]) and the learning environments ([`crate::env`]) both
//! keep their games here.
//!
//! A [`GameState`] holds its balls by id (0 the cue ball, object balls their numbers, at
//! most [`MAX_IDS`]) in fixed arrays: copying one, judging a shot and applying it allocate
//! nothing.
//!
//! After a shot ([`GameState::apply`]):
//! - the shot is judged by the game's rules ([`Rules::judge`], pooltool 0.6.0's);
//! - a ball that ended off the playing surface without being pocketed (seen in
//!   self-play) is off the table, as a jumped ball: an object ball stays off (the 9, or
//!   the 8, is spotted again), the cue ball off is a foul (ball in hand);
//! - 8-ball: the table is open until a legal shot pots a ball, whose group (1–7 or 9–15)
//!   the shooter then takes; with the group down, the 8;
//! - 9-ball: the 9 pocketed (or off) without ending the game is spotted again;
//! - the turn passes when the verdict says so; after a foul the next player has the cue
//!   ball in hand ([`GameState::place_cue`]);
//! - the game is over when the verdict says so;
//! - a shot cut by a limit (`--max-events`: balls frozen together can chatter through
//!   thousands of collisions) is judged on its events so far, and its moving balls stop
//!   where they were cut ([`ShotResult::cut`]).
//!
//! Simplified against the WPA's rules: the cue ball in hand anywhere (also after a
//! scratch on the break), no push-out, no three-foul rule, no safety called.

use super::{Context, Rules, Shot, Verdict};
use crate::error::{Error, InputError};
use crate::model::MotionState;
use crate::model::ball_state::BallState;
use crate::model::table::Table;
use crate::model::vec3::Vec3;
use crate::simulate::batch::EventRecord;
use crate::simulate::check::check_on_table;
use crate::simulate::events::EventKind;

/// The foot spot of the 9-ft table in the simulator's frame (x across the table, 0 to
/// 1.27 m; y along it, 0 to 2.54 m): the rack's apex.
pub const FOOT_SPOT: (f64, f64) = (0.635, 1.905);
/// The head string of the 9-ft table, y = 0.635 m: a break is played from behind it.
pub const HEAD_STRING_Y: f64 = 0.635;
/// The most ball ids a game holds (0 to 15: pool's cue ball and fifteen object balls).
pub const MAX_IDS: usize = 16;

/// Solids, 8-ball's low group.
pub const SOLIDS: u32 = 0b1111_1110;
/// Stripes, 8-ball's high group.
pub const STRIPES: u32 = 0b1111_1110_0000_0000;
const EIGHT: u32 = 1 << 8;

/// How an 8-ball shot is called.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Call {
    /// No call (9-ball, a break, or an 8-ball shot that then cannot keep the table).
    None,
    /// The ball (id) and the pocket (index in the table's pockets) named before the shot.
    Given {
        /// The called ball's id.
        ball: i64,
        /// The called pocket's index.
        pocket: usize,
    },
    /// The shot called as it went: the first ball the shooter may pot that went down, in
    /// the pocket it went into; with none, a ball of the shooter's in pocket 0 (a call that
    /// did not come true). A learning agent's shots are called so: potting its own ball
    /// keeps the table, the 8 when it is on wins in any pocket.
    AsPlayed,
}

/// What one shot did ([`GameState::apply`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShotResult {
    /// The player who shot.
    pub shooter: usize,
    /// The rules' verdict, with a cue ball off the table made a foul (`legal` false,
    /// `turn_over`; `foul` stays `None`: see [`ShotResult::cue_off`]).
    pub verdict: Verdict,
    /// The object balls the shot pocketed (a bit per id).
    pub potted: u32,
    /// The shooter's own balls among them on a legal shot: 8-ball, the shooter's group
    /// (the one the shot took, on an open table) and the 8 when it was on; 9-ball, any.
    pub own_potted: u32,
    /// The balls that ended off the playing surface unpocketed (a bit per id).
    pub off: u32,
    /// Whether the cue ball ended off the table (a foul).
    pub cue_off: bool,
    /// Whether the cue ball was pocketed.
    pub scratch: bool,
    /// Whether the shot was cut by a limit with balls still moving (they were stopped
    /// where they were).
    pub cut: bool,
}

impl ShotResult {
    /// Whether the shot was a foul (the rules', or the cue ball off the table).
    pub fn fouled(&self) -> bool {
        self.verdict.foul.is_some() || self.cue_off
    }
}

/// A game of 8-ball or 9-ball between shots (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GameState {
    /// The game.
    pub rules: Rules,
    /// Each ball's state by id, at rest; meaningful where [`GameState::on_table`] has its
    /// bit.
    pub balls: [BallState; MAX_IDS],
    /// The balls on the table (a bit per id; the cue ball's is clear while in hand).
    pub on_table: u32,
    /// The player to shoot (0 or 1).
    pub shooter: usize,
    /// Whether the shooter has the cue ball in hand.
    pub in_hand: bool,
    /// Whether the next shot is the break.
    pub break_shot: bool,
    /// 8-ball: each player's group, once taken.
    pub groups: Option<[u32; 2]>,
    /// Whether the game is over.
    pub over: bool,
    /// The winner, once over.
    pub winner: Option<usize>,
    /// Shots played.
    pub shots: u32,
    /// The balls' radius, m.
    pub radius: f64,
}

impl GameState {
    /// The rack on the 9-ft table with balls of radius `r`, `breaker` to break: 9-ball a
    /// diamond (the 1 at the foot spot, the 9 in the middle), 8-ball a triangle (the 8 in
    /// the middle), neighbours 2R + 1 µm apart; the cue ball on the head string's centre, a
    /// little behind it. Errors: a game other than 8-ball and 9-ball.
    pub fn rack(rules: Rules, r: f64, breaker: usize) -> Result<GameState, Error> {
        let order: &[&[i64]] = match rules {
            Rules::NineBall => &[&[1], &[2, 3], &[4, 9, 5], &[6, 7], &[8]],
            Rules::EightBall => &[
                &[1],
                &[9, 2],
                &[10, 8, 3],
                &[11, 4, 12, 5],
                &[6, 13, 7, 14, 15],
            ],
            Rules::Snooker | Rules::ThreeCushion => {
                return Err(InputError::new(format!(
                    "a rack is 8-ball's or 9-ball's, not {}'s",
                    rules.name()
                ))
                .into());
            }
        };
        let d = 2.0 * r + 1e-6;
        let mut game = GameState::empty(rules, r, breaker);
        game.put(0, 0.635, HEAD_STRING_Y - 0.1, r);
        for (row, ids) in order.iter().enumerate() {
            let y = FOOT_SPOT.1 + row as f64 * d * 3f64.sqrt() / 2.0;
            for (i, &id) in ids.iter().enumerate() {
                let x = FOOT_SPOT.0 + (i as f64 - (ids.len() - 1) as f64 / 2.0) * d;
                game.put(id, x, y, r);
            }
        }
        game.break_shot = true;
        Ok(game)
    }

    /// A game of `rules` on the balls `(id, state)` (ids 0 to 15, the cue ball 0), not a
    /// break, `shooter` to shoot. Errors: a game other than 8-ball and 9-ball, an id out of
    /// range or twice, no cue ball.
    pub fn from_balls(
        rules: Rules,
        balls: &[(i64, BallState)],
        shooter: usize,
    ) -> Result<GameState, Error> {
        let r = balls.first().map_or(0.0, |(_, b)| b.r.z);
        if !(r > 0.0 && r.is_finite()) {
            return Err(InputError::new(format!("a ball's radius of {r} m")).into());
        }
        let mut game = GameState::rack(rules, r, shooter)?;
        game.on_table = 0;
        game.break_shot = false;
        for &(id, b) in balls {
            if !(0..MAX_IDS as i64).contains(&id) || game.on_table & (1 << id) != 0 {
                return Err(InputError::new(format!(
                    "ball id {id}: a game's balls are 0 (the cue ball) to 15, each once"
                ))
                .into());
            }
            game.balls[id as usize] = BallState { t: 0.0, ..b };
            game.on_table |= 1 << id;
        }
        if game.on_table & 1 == 0 {
            return Err(InputError::new("no cue ball (id 0)").into());
        }
        Ok(game)
    }

    fn empty(rules: Rules, r: f64, shooter: usize) -> GameState {
        GameState {
            rules,
            balls: [BallState::at_rest(0.0, 0.0, r); MAX_IDS],
            on_table: 0,
            shooter,
            in_hand: false,
            break_shot: false,
            groups: None,
            over: false,
            winner: None,
            shots: 0,
            radius: r,
        }
    }

    /// Ball `id` at rest at `(x, y)`.
    fn put(&mut self, id: i64, x: f64, y: f64, r: f64) {
        self.balls[id as usize] = BallState::at_rest(x, y, r);
        self.on_table |= 1 << id;
    }

    /// The shooter's context: the break; 9-ball's (worked out from the table); 8-ball's
    /// group, the open table before one is taken (any ball but the 8), the 8 with the
    /// group down. No call: [`GameState::apply`] adds it.
    pub fn context(&self) -> Context {
        let mut hittable = Context::balls((1..=15).filter(|&n| n != 8));
        if self.rules == Rules::EightBall
            && let Some(groups) = self.groups
        {
            let group = groups[self.shooter];
            hittable = if group & self.on_table == 0 {
                EIGHT
            } else {
                group
            };
        }
        Context {
            break_shot: self.break_shot,
            hittable,
            ..Context::default()
        }
    }

    /// The balls the shooter may hit first (a bit per id): 8-ball the context's, 9-ball
    /// the lowest ball on the table.
    pub fn hittable(&self) -> u32 {
        match self.rules {
            Rules::NineBall => {
                let objects = self.on_table & !1;
                objects & objects.wrapping_neg()
            }
            _ => self.context().hittable & self.on_table,
        }
    }

    /// The balls on the table in id order (pooltool's): their ids and states into `ids`
    /// and `balls`; returns how many.
    pub fn layout(&self, ids: &mut [i64; MAX_IDS], balls: &mut [BallState; MAX_IDS]) -> usize {
        let mut n = 0;
        for id in 0..MAX_IDS {
            if self.on_table & (1 << id) != 0 {
                ids[n] = id as i64;
                balls[n] = self.balls[id];
                n += 1;
            }
        }
        n
    }

    /// The cue ball placed at `(x, y)` (ball in hand), taken out of the hand. The caller
    /// chooses a free spot on the playing surface ([`GameState::free_spot`]).
    pub fn place_cue(&mut self, x: f64, y: f64) {
        let r = self.radius;
        self.put(0, x, y, r);
        self.in_hand = false;
    }

    /// Whether a ball of radius `r` at `(x, y)` is on the playing surface of `table` and
    /// clear of every other ball on the table by `gap`.
    pub fn is_free(&self, table: &Table, x: f64, y: f64, gap: f64) -> bool {
        let r = self.radius;
        check_on_table(table, r, Vec3::new(x, y, r)).is_ok()
            && (1..MAX_IDS).all(|id| {
                self.on_table & (1 << id) == 0 || {
                    let b = self.balls[id].r;
                    (b.x - x).hypot(b.y - y) > 2.0 * r + gap
                }
            })
    }

    /// The free spot nearest `(x, y)` for the cue ball: `(x, y)` itself if free
    /// ([`GameState::is_free`] with a 1 mm gap), else the first free point on squares of
    /// growing size around it, 5 mm apart (at most 2.6 m out, the table's length); `None`
    /// if the table has no room.
    pub fn free_spot(&self, table: &Table, x: f64, y: f64) -> Option<(f64, f64)> {
        const STEP: f64 = 0.005;
        const GAP: f64 = 1e-3;
        if self.is_free(table, x, y, GAP) {
            return Some((x, y));
        }
        for ring in 1..=520i32 {
            let mut best: Option<((f64, f64), f64)> = None;
            for i in -ring..=ring {
                for (dx, dy) in [(i, -ring), (i, ring), (-ring, i), (ring, i)] {
                    let p = (x + f64::from(dx) * STEP, y + f64::from(dy) * STEP);
                    let d = f64::from(dx).hypot(f64::from(dy));
                    if best.is_none_or(|(_, bd)| d < bd) && self.is_free(table, p.0, p.1, GAP) {
                        best = Some((p, d));
                    }
                }
            }
            if let Some((p, _)) = best {
                return Some(p);
            }
        }
        None
    }

    /// Applies one simulated shot: `events` (the strike first) and `end` (the balls at
    /// rest, in [`GameState::layout`]'s order) of the shot played from this state on
    /// `table`, called by `call` (module docs). Returns what the shot did. Errors: the
    /// shot's balls are not a pool game's, a shot after the game is over.
    pub fn apply(
        &mut self,
        table: &Table,
        events: &[EventRecord],
        end: &[BallState],
        call: Call,
    ) -> Result<ShotResult, Error> {
        if self.over {
            return Err(InputError::new("the game is over").into());
        }
        let mut ids = [0i64; MAX_IDS];
        let mut start = [self.balls[0]; MAX_IDS];
        let n = self.layout(&mut ids, &mut start);
        if end.len() != n {
            return Err(InputError::new(format!(
                "{} balls at the end of a shot of {n}",
                end.len()
            ))
            .into());
        }
        let mut context = self.rules.context(self.context());
        if self.rules == Rules::EightBall && !self.break_shot {
            match call {
                Call::None => {}
                Call::Given { ball, pocket } => {
                    context.ball_call = Some(ball);
                    context.pocket_call = Some(pocket);
                }
                Call::AsPlayed => {
                    let may = context.hittable & self.on_table;
                    let first = events.iter().find(|e| {
                        e.event.kind == EventKind::BallPocket
                            && may & (1 << ids[e.event.ball as usize]) != 0
                    });
                    let (ball, pocket) = match first {
                        Some(e) => (ids[e.event.ball as usize], e.event.other as usize),
                        None => (i64::from(may.trailing_zeros().min(15)), 0),
                    };
                    context.ball_call = Some(ball);
                    context.pocket_call = Some(pocket);
                }
            }
        }
        let shot = Shot {
            ids: &ids[..n],
            start: &start[..n],
            events,
        };
        let mut verdict = self.rules.judge(&shot, &context)?;
        let r = self.radius;
        let (mut potted, mut off) = (0u32, 0u32);
        for (k, b) in end.iter().enumerate() {
            let bit = 1u32 << ids[k];
            if b.s == MotionState::Pocketed {
                potted |= bit;
            } else if check_on_table(table, r, b.r).is_err() {
                off |= bit;
            }
        }
        let scratch = potted & 1 != 0;
        let cut = end
            .iter()
            .any(|b| !matches!(b.s, MotionState::Stationary | MotionState::Pocketed));
        let cue_off = off & 1 != 0 && verdict.foul.is_none();
        if cue_off {
            verdict.legal = false;
            verdict.turn_over = true;
            verdict.won = false;
        }
        let s = self.shooter;
        let potted_objects = potted & !1;
        // 8-ball: the first legal pot after the break takes its group
        if self.rules == Rules::EightBall
            && self.groups.is_none()
            && !self.break_shot
            && verdict.legal
            && !verdict.turn_over
        {
            let first = events.iter().find(|e| {
                e.event.kind == EventKind::BallPocket && {
                    let id = ids[e.event.ball as usize];
                    id > 0 && id != 8
                }
            });
            if let Some(e) = first {
                let (mine, theirs) = if ids[e.event.ball as usize] < 8 {
                    (SOLIDS, STRIPES)
                } else {
                    (STRIPES, SOLIDS)
                };
                let mut groups = [0; 2];
                groups[s] = mine;
                groups[1 - s] = theirs;
                self.groups = Some(groups);
            }
        }
        let own_potted = if !verdict.legal {
            0
        } else if self.rules == Rules::EightBall {
            let own = match self.groups {
                Some(g) => g[s] | (context.hittable & EIGHT),
                None => 0,
            };
            potted_objects & own
        } else {
            potted_objects
        };
        // the balls after it: the pocketed and those off the table leave; a ball still
        // moving (the shot cut by a limit) stops where it was cut
        for (k, b) in end.iter().enumerate() {
            let id = ids[k] as usize;
            self.balls[id] = if matches!(b.s, MotionState::Stationary | MotionState::Pocketed) {
                BallState { t: 0.0, ..*b }
            } else {
                BallState::at_rest(b.r.x, b.r.y, r)
            };
        }
        self.on_table &= !(potted | off);
        self.shots += 1;
        let result = ShotResult {
            shooter: s,
            verdict,
            potted: potted_objects,
            own_potted,
            off,
            cue_off,
            scratch,
            cut,
        };
        if verdict.game_over {
            self.over = true;
            self.winner = Some(if verdict.won { s } else { 1 - s });
            return Ok(result);
        }
        // a 9 (or 8) pocketed or off the table without ending the game comes back
        let spotted = if self.rules == Rules::NineBall { 9 } else { 8 };
        if (potted | off) & (1 << spotted) != 0 {
            self.respot(spotted, r);
        }
        self.break_shot = false;
        self.in_hand = result.fouled() || self.on_table & 1 == 0;
        if self.in_hand {
            self.on_table &= !1;
        }
        if verdict.turn_over {
            self.shooter = 1 - s;
        }
        Ok(result)
    }

    /// Ball `id` back on the table: on the foot spot, or the first free point behind it.
    fn respot(&mut self, id: i64, r: f64) {
        let mut y = FOOT_SPOT.1;
        let taken = |g: &GameState, y: f64| {
            (0..MAX_IDS).any(|k| {
                g.on_table & (1 << k) != 0
                    && (g.balls[k].r.x - FOOT_SPOT.0).hypot(g.balls[k].r.y - y) <= 2.0 * r + 1e-3
            })
        };
        while taken(self, y) {
            y += 0.01;
        }
        self.put(id, FOOT_SPOT.0, y, r);
    }
}
