//! Games: the rules' verdict on one simulated shot — was it legal, which foul, is the turn
//! over, is the game over — judged from the shot's events and its balls at the start,
//! exactly as pooltool 0.6.0's rule sets judge them (`pooltool/ruleset/`), one module per
//! game:
//!
//! - [`nine_ball`]: 9-ball (`pooltool.ruleset.nine_ball`);
//! - [`eight_ball`]: 8-ball (`pooltool.ruleset.eight_ball`);
//! - [`snooker`]: snooker (`pooltool.ruleset.snooker`: the fouls, the points, the final
//!   black);
//! - [`three_cushion`]: three-cushion billiards (`pooltool.ruleset.three_cushion`: the
//!   point).
//!
//! A shot's context ([`Context`]) is what the player was allowed and asked to do: whether
//! it is a break, the balls they may hit first, their call, and the score before it.
//!
//! A judge reads a [`Shot`]: each ball's identity (`ids`, the input's ball ids: the cue
//! ball is 0, object balls their numbers; snooker's: [`snooker::id_of`]), each ball's state at the start (which balls
//! were already pocketed), and the events in order, the strike first (what
//! [`crate::simulate::simulate_batch`] records). It allocates nothing and loops over the
//! events a bounded number of times, so it can sit on the hot path of a batch or a study.
//!
//! Reference: `data/games/` holds pooltool's own verdicts on shots it simulated
//! (`tools/games/`, seeded), and `tests/games.rs` replays each shot through kisstime and
//! checks the judge against them.

use crate::error::SimError;
use crate::model::MotionState;
use crate::model::ball_state::BallState;
use crate::simulate::batch::EventRecord;
use crate::simulate::events::{Event, EventKind};
use crate::simulate::watch::{NO_POCKET, ShotFacts};

pub mod eight_ball;
pub mod nine_ball;
pub mod progress;
pub mod snooker;
pub mod three_cushion;

/// A game whose rules judge shots.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Rules {
    /// 9-ball ([`nine_ball`]).
    NineBall,
    /// 8-ball ([`eight_ball`]).
    EightBall,
    /// Snooker ([`snooker`]).
    Snooker,
    /// Three-cushion billiards ([`three_cushion`]).
    ThreeCushion,
}

impl Rules {
    /// Every game, with its name.
    pub const ALL: [(Rules, &'static str); 4] = [
        (Rules::NineBall, "9-ball"),
        (Rules::EightBall, "8-ball"),
        (Rules::Snooker, "snooker"),
        (Rules::ThreeCushion, "three-cushion"),
    ];

    /// Its name (`9-ball`, `8-ball`, `snooker`, `three-cushion`).
    pub fn name(self) -> &'static str {
        Rules::ALL
            .iter()
            .find(|(r, _)| *r == self)
            .map_or("", |(_, n)| n)
    }

    /// The game named `name` (`9-ball`, `8-ball`, `snooker`, `three-cushion`); the error
    /// lists the names.
    pub fn from_name(name: &str) -> Result<Rules, String> {
        Rules::ALL
            .iter()
            .find(|(_, n)| *n == name)
            .map(|(r, _)| *r)
            .ok_or_else(|| {
                let names: Vec<&str> = Rules::ALL.iter().map(|(_, n)| *n).collect();
                format!("unknown game {name:?}: the rules are {}", names.join(", "))
            })
    }

    /// The game's own part of a shot's context: 8-ball asks every shot but the break to be
    /// called (pooltool's `ShotConstraints.call_shot`); snooker, every shot on colours
    /// (`call_shot` then marks a called ball, as the judge works out: see [`snooker`]);
    /// 9-ball and three-cushion ask none.
    pub fn context(self, context: Context) -> Context {
        Context {
            call_shot: match self {
                Rules::EightBall => !context.break_shot,
                Rules::Snooker => context.hittable & snooker::COLOURS != 0,
                Rules::NineBall | Rules::ThreeCushion => false,
            },
            ..context
        }
    }

    /// Whether the game scores points per shot ([`Verdict::points`]): snooker and
    /// three-cushion.
    pub fn scores(self) -> bool {
        matches!(self, Rules::Snooker | Rules::ThreeCushion)
    }

    /// Checks `context` for what this game cannot judge (snooker: reds and colours on at
    /// once, several colours on and none called: [`snooker::check_context`]); the error
    /// says why.
    pub fn check_context(self, context: &Context) -> Result<(), String> {
        match self {
            Rules::Snooker => snooker::check_context(context),
            Rules::NineBall | Rules::EightBall | Rules::ThreeCushion => Ok(()),
        }
    }

    /// The ball id pooltool's game names `name` (snooker: `white`, `red_01`, …,
    /// `black`: [`snooker::id_of`]), for the games whose balls have names; pool balls and
    /// three-cushion's take numbers.
    pub fn ball_named(self, name: &str) -> Option<i64> {
        match self {
            Rules::Snooker => snooker::id_of(name),
            Rules::NineBall | Rules::EightBall | Rules::ThreeCushion => None,
        }
    }

    /// The verdict on `shot` in `context` (see [`nine_ball::judge`], [`eight_ball::judge`],
    /// [`snooker::judge`], [`three_cushion::judge`]): the shot's facts ([`ShotFacts`])
    /// following the game's cue ball (pool and snooker: the ball with id 0; three-cushion:
    /// the ball struck), then
    /// [`Rules::judge_played`].
    pub fn judge(self, shot: &Shot<'_>, context: &Context) -> Result<Verdict, SimError> {
        let cue = match self {
            Rules::ThreeCushion => shot.struck()?,
            Rules::NineBall | Rules::EightBall => shot.pool_cue()?,
            Rules::Snooker => snooker::snooker_cue(shot.ids, shot.start.len())?,
        };
        let facts = ShotFacts::of(shot.events(), cue as u32);
        self.judge_played(
            &Played {
                ids: shot.ids,
                start: shot.start,
                cue,
                facts: &facts,
            },
            context,
        )
    }

    /// The verdict on a shot known by its facts (what a watched study keeps of each
    /// sample), in `context`.
    ///
    /// Errors (never panics) on a shot that does not hold together, whatever the game:
    /// ids and start states of different lengths, facts that follow a ball that is not in
    /// the shot, or that name one (a first contact, a pocketed ball, a ball at a cushion)
    /// that is not (what events for balls out of range would give: the `rules_judge` fuzz
    /// target's finding 9, FUZZING.md).
    pub fn judge_played(self, played: &Played<'_>, context: &Context) -> Result<Verdict, SimError> {
        played.check()?;
        match self {
            Rules::NineBall => nine_ball::judge(played, context.break_shot, context.wpa),
            Rules::EightBall => eight_ball::judge(played, context),
            Rules::Snooker => snooker::judge(played, context),
            Rules::ThreeCushion => three_cushion::judge(played, context),
        }
    }
}

/// A foul, named as in kisstime's outputs ([`Foul::code`]) and as pooltool 0.6.0's rule
/// sets word its reason ([`nine_ball::pooltool_reason`], [`eight_ball::pooltool_reason`],
/// [`snooker::pooltool_reason`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Foul {
    /// The cue ball was pocketed.
    CuePocketed,
    /// The cue ball hit no ball (pooltool: no ball–ball event at all).
    NoHit,
    /// The first ball the cue ball hit was not one the player may hit first.
    WrongBallFirst,
    /// No ball reached a cushion after the first contact and none was pocketed.
    NoRail,
    /// A break with no ball pocketed and fewer than four object balls at a cushion.
    BreakRails,
    /// A shot that had to be called was not (8-ball).
    NotCalled,
    /// The 8 pocketed out of turn or in another pocket than the one called (8-ball: the
    /// game is lost).
    EightIllegal,
    /// A ball that was not on was pocketed (snooker).
    OffBallPocketed,
}

impl Foul {
    /// Every foul.
    pub const ALL: [Foul; 8] = [
        Foul::CuePocketed,
        Foul::NoHit,
        Foul::WrongBallFirst,
        Foul::NoRail,
        Foul::BreakRails,
        Foul::NotCalled,
        Foul::EightIllegal,
        Foul::OffBallPocketed,
    ];

    /// Its code in kisstime's outputs: `cue_pocketed`, `no_hit`, `wrong_ball_first`,
    /// `no_rail`, `break_rails`, `not_called`, `eight_illegal`, `off_ball_pocketed`.
    pub fn code(self) -> &'static str {
        match self {
            Foul::CuePocketed => "cue_pocketed",
            Foul::NoHit => "no_hit",
            Foul::WrongBallFirst => "wrong_ball_first",
            Foul::NoRail => "no_rail",
            Foul::BreakRails => "break_rails",
            Foul::NotCalled => "not_called",
            Foul::EightIllegal => "eight_illegal",
            Foul::OffBallPocketed => "off_ball_pocketed",
        }
    }

    /// The reason pooltool 0.6.0's rule sets give for it (the rules that know it; the
    /// wrong ball first is worded per game: [`nine_ball::pooltool_reason`],
    /// [`eight_ball::pooltool_reason`]).
    fn pooltool_reason(self) -> &'static str {
        match self {
            Foul::CuePocketed => "Cue ball in pocket!",
            Foul::NoHit => "No ball contacted",
            Foul::WrongBallFirst => "Lowest ball not hit first",
            Foul::NoRail => "Cushion not contacted after first contact",
            Foul::BreakRails => "4 rails must be contacted, or 1 ball potted",
            Foul::NotCalled => "Shot not called, but it was required!",
            Foul::EightIllegal => "8-ball sunk illegally (out of turn or wrong pocket)!",
            Foul::OffBallPocketed => "Pocketed a ball that's not on!",
        }
    }
}

/// A shot's context: what the player was allowed and asked to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Context {
    /// Whether the shot is a game's break.
    pub break_shot: bool,
    /// The balls the player may hit first, as a set of ball ids (bit `n` for ball `n`;
    /// 8-ball: the group, e.g. solids `0b1111_1110`; snooker: the reds or the colours
    /// that are on, empty to work them out from the table: see [`snooker`]). 9-ball
    /// works it out from the table (the lowest ball) and ignores it.
    pub hittable: u32,
    /// Whether the shot must be called (8-ball after the break).
    pub call_shot: bool,
    /// The called ball's id, if any.
    pub ball_call: Option<i64>,
    /// The called pocket's index in the table's pockets, if any.
    pub pocket_call: Option<usize>,
    /// Judge by the WPA rules where pooltool departs from them and the verdict can tell
    /// (9-ball: the break must hit the 1 first; 8-ball: the 8 pocketed on the break ends
    /// no game, and a legal such break keeps the table). `false`: pooltool's reading, the
    /// default.
    pub wpa: bool,
    /// The score before the shot: the player who shoots, then the opponent (snooker and
    /// three-cushion; it decides who has won when the game ends).
    pub score: [u32; 2],
}

impl Context {
    /// The set of ball ids `numbers` as [`Context::hittable`] takes it (ids outside
    /// 1..=21 are left out).
    pub fn balls(numbers: impl IntoIterator<Item = i64>) -> u32 {
        numbers
            .into_iter()
            .filter(|n| (1..=21).contains(n))
            .fold(0, |set, n| set | (1 << n))
    }
}

/// The rules' verdict on one shot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Verdict {
    /// Whether the shot was legal.
    pub legal: bool,
    /// The foul, where it was not (`None` exactly when `legal`).
    pub foul: Option<Foul>,
    /// Whether the player's turn is over.
    pub turn_over: bool,
    /// Whether the game is over.
    pub game_over: bool,
    /// Whether the player who shot won the game (it is over, and theirs).
    pub won: bool,
    /// The points the player who shot scored (snooker: the balls pocketed on a legal
    /// shot; three-cushion: 1 for a point; 0 in 8-ball and 9-ball).
    pub points: u32,
    /// The points a foul gave the opponent (snooker's penalty; 0 elsewhere).
    pub foul_points: u32,
}

/// One simulated shot as the rules see it.
#[derive(Clone, Copy, Debug)]
pub struct Shot<'a> {
    /// Each ball's identity, index for index: 0 the cue ball, object balls their numbers.
    pub ids: &'a [i64],
    /// Each ball's state at the start of the shot (pocketed ones are off the table).
    pub start: &'a [BallState],
    /// The shot's events in order, the strike first.
    pub events: &'a [EventRecord],
}

impl Shot<'_> {
    /// Checks the shot for a pool game (8-ball, 9-ball): see [`pool_cue`]. Returns the cue
    /// ball's index.
    pub fn pool_cue(&self) -> Result<usize, SimError> {
        pool_cue(self.ids, self.start)
    }

    /// The ball the strike (the first event) hit; a shot without a strike is an error.
    pub fn struck(&self) -> Result<usize, SimError> {
        self.events
            .first()
            .map(|r| &r.event)
            .filter(|e| e.kind == EventKind::StickBall)
            .map(|e| e.ball as usize)
            .ok_or_else(|| {
                SimError::Table(
                    "the shot has no strike (its first event must be the cue's)".to_owned(),
                )
            })
    }

    /// The events, in order.
    fn events(&self) -> impl Iterator<Item = &Event> + '_ {
        self.events.iter().map(|r| &r.event)
    }
}

/// Checks the balls of a pool game (8-ball, 9-ball): one id per ball, exactly one cue ball
/// (id 0), the others numbered 1 to 15, at most [`u64::BITS`] balls. Returns the cue
/// ball's index.
pub fn pool_cue(ids: &[i64], start: &[BallState]) -> Result<usize, SimError> {
    if ids.len() != start.len() {
        return Err(SimError::Table(format!(
            "{} ball ids for {} balls",
            ids.len(),
            start.len()
        )));
    }
    if ids.len() > u64::BITS as usize {
        return Err(SimError::Table(format!(
            "{} balls: the rules take at most {}",
            ids.len(),
            u64::BITS
        )));
    }
    let mut cue = None;
    for (index, &id) in ids.iter().enumerate() {
        match id {
            0 if cue.is_some() => {
                return Err(SimError::Ball {
                    index,
                    reason: "a second cue ball (id 0)".to_owned(),
                });
            }
            0 => cue = Some(index),
            1..=15 => {}
            other => {
                return Err(SimError::Ball {
                    index,
                    reason: format!("id {other}: pool balls are the cue ball (0) and 1 to 15"),
                });
            }
        }
    }
    cue.ok_or_else(|| SimError::Table("no cue ball (id 0) on the table".to_owned()))
}

/// A shot as the judges read it: each ball's identity and state at the start, the ball
/// the facts follow (`cue`), and the facts of its events ([`ShotFacts`]: from recorded
/// events, [`Rules::judge`], or kept by a study's watch as the events went by).
#[derive(Clone, Copy, Debug)]
pub struct Played<'a> {
    /// Each ball's identity, index for index: 0 the cue ball, object balls their numbers.
    pub ids: &'a [i64],
    /// Each ball's state at the start of the shot (pocketed ones are off the table).
    pub start: &'a [BallState],
    /// The ball `facts` follow.
    pub cue: usize,
    /// The facts of the shot's events.
    pub facts: &'a ShotFacts,
}

impl Played<'_> {
    /// Checks that the facts and the balls hold together (see [`Rules::judge_played`]).
    fn check(&self) -> Result<(), SimError> {
        let n = self.ids.len();
        if self.start.len() != n {
            return Err(SimError::Table(format!(
                "{n} ball ids for {} balls",
                self.start.len()
            )));
        }
        if self.cue >= n {
            return Err(SimError::Ball {
                index: self.cue,
                reason: format!("the shot's facts follow ball {}, of {n}", self.cue),
            });
        }
        let mask = if n >= 64 { u64::MAX } else { (1u64 << n) - 1 };
        let beyond = |set: u64| set & !mask;
        let f = self.facts;
        let stray = f
            .first_ball
            .map(|(_, b)| b as usize)
            .filter(|&b| b >= n)
            .or_else(|| {
                [f.pocketed, f.at_cushion]
                    .into_iter()
                    .find(|&set| beyond(set) != 0)
                    .map(|set| beyond(set).trailing_zeros() as usize)
            });
        match stray {
            Some(index) => Err(SimError::Ball {
                index,
                reason: format!("an event of ball {index}, but the shot has {n} balls"),
            }),
            None => Ok(()),
        }
    }

    /// The cue ball of a pool game ([`pool_cue`]), which must be the ball the facts follow.
    fn pool_cue(&self) -> Result<usize, SimError> {
        self.check_cue(pool_cue(self.ids, self.start)?, "the cue ball")
    }

    /// Returns `cue` (the game's cue ball, `what` in the message) if the shot's facts follow
    /// it, an error naming both balls if they follow another.
    fn check_cue(&self, cue: usize, what: &str) -> Result<usize, SimError> {
        if cue != self.cue {
            return Err(SimError::Ball {
                index: self.cue,
                reason: format!(
                    "the shot's facts follow ball {}, but {what} (id 0) is ball {cue}",
                    self.cue
                ),
            });
        }
        Ok(cue)
    }

    /// Whether ball `i` was on the table at the start.
    fn on_table_at_start(&self, i: usize) -> bool {
        self.start[i].s != MotionState::Pocketed
    }

    /// The index of the ball numbered `n`, if it is in the shot.
    fn index_of(&self, n: i64) -> Option<usize> {
        self.ids.iter().position(|&id| id == n)
    }

    /// The balls pocketed during the shot, as a bit set of indices.
    fn pocketed(&self) -> u64 {
        self.facts.pocketed
    }

    /// The pocket ball `i` fell into, if it did.
    fn pocket_of(&self, i: usize) -> Option<usize> {
        self.facts
            .pocket_of
            .get(i)
            .filter(|&&p| p != NO_POCKET)
            .map(|&p| p as usize)
    }

    /// The cue ball's first ball–ball event: its time and the other ball's index.
    fn first_contact(&self) -> Option<(f64, usize)> {
        self.facts.first_ball.map(|(t, other)| (t, other as usize))
    }
}

/// The bit of ball index `i` in a set of balls.
fn bit(i: u32) -> u64 {
    1u64.checked_shl(i).unwrap_or(0)
}
