//! The watch: what a shot study takes from a table's events without keeping them — the
//! watched (cue) ball's first contact, with the state it had and the clock just before it
//! and the centres just after it, and every pot in order; and, where asked, the games'
//! rules' facts ([`ShotFacts`]).
//!
//! Both backends keep it as the events go by: the CPU's batch ([`super::batch`], with
//! [`BatchOptions::watch`](super::BatchOptions::watch)) through [`Watcher`], the GPU's event
//! loop through its twin in `shaders/simulate/event_loop.wgsl` (`first_contact_of`,
//! `watch_event`), which writes the same record into each table's watch block. So a study
//! reads the same [`TableWatch`] from either backend and turns it into its samples
//! (`study::run`), and no event crosses the bus or fills memory.
//!
//! With [`WatchOptions::stop_at_first_contact`] a table stops at that first contact (its
//! outcome and final state are then those at the contact): the cheaper study of what the
//! cue ball meets first.

use super::events::{Event, EventKind};
use crate::model::ball_state::BallState;
use crate::model::vec3::Vec3;

/// What a batch watches: one ball (the same in every table), and whether a table stops at
/// its first contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WatchOptions {
    /// The watched ball's index in every table (the cue ball).
    pub cue: usize,
    /// End each table at the watched ball's first contact.
    pub stop_at_first_contact: bool,
    /// The games' rules' facts are wanted ([`TableWatch::facts`]): both backends keep them
    /// as the events go by (the GPU's `observe_facts`, the twin of
    /// [`ShotFacts::observe`]).
    pub facts: bool,
}

/// The watched ball's first contact, as the watch saw it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WatchedContact {
    /// Its event number (the strike is 1).
    pub number: usize,
    /// The event.
    pub event: Event,
    /// The watched ball's state before it (it holds at time `t0`, whatever its own time
    /// stamp).
    pub cue_before: BallState,
    /// The clock before the event.
    pub t0: f64,
    /// The watched ball's centre right after it.
    pub cue_after: Vec3,
    /// The centre right after it of the other ball of a ball–ball contact (for any other
    /// kind, of ball `min(other, n − 1)`: meaningless, as on the GPU).
    pub other_after: Vec3,
}

/// A pot the watch saw: its event number and the `ball_pocket` event.
pub type WatchedPot = (usize, Event);

/// One table's watch, borrowed from its chunk.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TableWatch<'a> {
    /// The watched ball's first contact, if there was one.
    pub first: Option<WatchedContact>,
    /// Every pot, in order.
    pub pots: &'a [WatchedPot],
    /// What the games' rules need of the table's events ([`ShotFacts`], following the
    /// watched ball), where [`WatchOptions::facts`] asked for them.
    pub facts: Option<&'a ShotFacts>,
}

/// One table's watch, owned (what the GPU's readback makes of a watch block).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Watch {
    /// The watched ball's first contact, if there was one.
    pub first: Option<WatchedContact>,
    /// Every pot, in order.
    pub pots: Vec<WatchedPot>,
    /// The rules' facts, where they were asked for ([`WatchOptions::facts`]).
    pub facts: Option<ShotFacts>,
}

impl Watch {
    /// Borrowed, as a chunk hands it out.
    pub fn as_table_watch(&self) -> TableWatch<'_> {
        TableWatch {
            first: self.first,
            pots: &self.pots,
            facts: self.facts.as_ref(),
        }
    }
}

/// Whether event (kind, ball, other) is ball `cue`'s first contact, if none came before
/// (WGSL: `first_contact_of`): ball–ball with the cue ball, a cushion or jaw, a pocket, or
/// the cue ball stopping; not the strike, nor the cue ball's own sliding → rolling.
pub fn first_contact_of(kind: EventKind, ball: u32, other: u32, cue: u32) -> bool {
    let involves = ball == cue || (kind == EventKind::BallBall && other == cue);
    involves && kind != EventKind::StickBall && kind != EventKind::SlidingRolling
}

/// No pocket: [`ShotFacts::pocket_of`]'s mark for a ball that was not pocketed.
pub const NO_POCKET: u16 = u16::MAX;

/// What the games' rules take from a shot's events (pooltool 0.6.0's rule sets: 9-ball,
/// 8-ball, three-cushion), kept as the events go by ([`ShotFacts::observe`]), so that a
/// shot can be judged without its events: from a recorded shot (`game::Shot`) and from a
/// watched one alike. Balls are indices (below 64); `cue` is the ball the facts follow
/// (the struck one). Copy, no allocation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShotFacts {
    /// Whether any two balls touched (a ball–ball event of any balls).
    pub any_ball_ball: bool,
    /// The cue ball's first ball–ball contact: its time and the other ball.
    pub first_ball: Option<(f64, u32)>,
    /// Whether some ball reached a cushion or a jaw strictly after `first_ball`'s time.
    pub cushion_after_first: bool,
    /// The balls that reached a cushion or a jaw at any time (bit `i` for ball `i`).
    pub at_cushion: u64,
    /// The balls pocketed (bit `i` for ball `i`).
    pub pocketed: u64,
    /// The pocket (index in the table's pockets) each ball first fell into, or
    /// [`NO_POCKET`].
    pub pocket_of: [u16; 64],
    /// The time the cue ball first met a second, other ball (three-cushion).
    pub second_ball_t: Option<f64>,
    /// The cue ball's straight-cushion contacts strictly before `second_ball_t` (before
    /// it is known: so far).
    pub cue_cushions: u32,
    /// The time of the cue ball's last counted straight-cushion contact, and how many of
    /// the counted ones came at that very time (so that those at `second_ball_t` itself
    /// can be taken back: pooltool counts strictly before).
    pub(crate) last_cushion: (f64, u32),
}

impl Default for ShotFacts {
    fn default() -> Self {
        ShotFacts {
            any_ball_ball: false,
            first_ball: None,
            cushion_after_first: false,
            at_cushion: 0,
            pocketed: 0,
            pocket_of: [NO_POCKET; 64],
            second_ball_t: None,
            cue_cushions: 0,
            last_cushion: (f64::NEG_INFINITY, 0),
        }
    }
}

impl ShotFacts {
    /// The facts of a whole event sequence (in order), following ball `cue`.
    pub fn of<'e>(events: impl IntoIterator<Item = &'e Event>, cue: u32) -> ShotFacts {
        let mut facts = ShotFacts::default();
        for e in events {
            facts.observe(e, cue);
        }
        facts
    }

    /// Takes in the next event `e` of the shot (events come in time order), following
    /// ball `cue`.
    pub fn observe(&mut self, e: &Event, cue: u32) {
        let bit = |i: u32| 1u64.checked_shl(i).unwrap_or(0);
        match e.kind {
            EventKind::BallBall => {
                self.any_ball_ball = true;
                if e.ball != cue && e.other != cue {
                    return;
                }
                let other = if e.ball == cue { e.other } else { e.ball };
                match self.first_ball {
                    None => self.first_ball = Some((e.t, other)),
                    Some((_, first)) if first != other && self.second_ball_t.is_none() => {
                        self.second_ball_t = Some(e.t);
                        if self.last_cushion.0 == e.t {
                            self.cue_cushions -= self.last_cushion.1;
                        }
                    }
                    Some(_) => {}
                }
            }
            EventKind::BallLinearCushion | EventKind::BallCircularCushion => {
                self.at_cushion |= bit(e.ball);
                if let Some((t, _)) = self.first_ball
                    && e.t > t
                {
                    self.cushion_after_first = true;
                }
                if e.kind == EventKind::BallLinearCushion
                    && e.ball == cue
                    && self.second_ball_t.is_none()
                {
                    self.cue_cushions += 1;
                    self.last_cushion = match self.last_cushion {
                        (t, k) if t == e.t => (t, k + 1),
                        _ => (e.t, 1),
                    };
                }
            }
            EventKind::BallPocket => {
                self.pocketed |= bit(e.ball);
                if let Some(p) = self.pocket_of.get_mut(e.ball as usize)
                    && *p == NO_POCKET
                {
                    *p = u16::try_from(e.other).unwrap_or(NO_POCKET - 1);
                }
            }
            _ => {}
        }
    }
}

/// The CPU's watch of one table at a time (WGSL: `watch_event` and its workgroup state),
/// reused across tables: [`Watcher::start`], then [`Watcher::before`] and
/// [`Watcher::watch_event`] around each step, then [`Watcher::first`]. Pots go to the
/// caller's list. Allocates nothing.
#[derive(Clone, Copy, Debug)]
pub struct Watcher {
    options: WatchOptions,
    /// The watched ball's state and the clock before this step's event.
    before: (BallState, f64),
    first: Option<WatchedContact>,
    facts: ShotFacts,
}

impl Watcher {
    /// A watcher for `options`.
    pub fn new(options: WatchOptions) -> Watcher {
        Watcher {
            options,
            before: (BallState::at_rest(0.0, 0.0, 0.0), 0.0),
            first: None,
            facts: ShotFacts::default(),
        }
    }

    /// Starts a table (its watch blank).
    pub fn start(&mut self) {
        self.first = None;
        self.facts = ShotFacts::default();
    }

    /// Keeps the watched ball's state `balls[cue]` and the clock `t` before a step.
    pub fn before(&mut self, balls: &[BallState], t: f64) {
        if self.first.is_none()
            && let Some(b) = balls.get(self.options.cue)
        {
            self.before = (*b, t);
        }
    }

    /// The watch's record of `ev`, the table's `number`th event (the strike is 1), given
    /// every ball's state right after it: a pot goes to `pots`, the first contact is kept.
    /// Returns whether the table ends here (its first contact, with
    /// [`WatchOptions::stop_at_first_contact`]).
    pub fn watch_event(
        &mut self,
        number: usize,
        ev: &Event,
        balls: &[BallState],
        pots: &mut Vec<WatchedPot>,
    ) -> bool {
        if ev.kind == EventKind::BallPocket {
            pots.push((number, *ev));
        }
        let cue = self.options.cue;
        if self.options.facts {
            self.facts.observe(ev, cue as u32);
        }
        if self.first.is_some() || !first_contact_of(ev.kind, ev.ball, ev.other, cue as u32) {
            return false;
        }
        let other = if ev.ball as usize == cue {
            ev.other
        } else {
            ev.ball
        };
        let n = balls.len();
        let (cue_before, t0) = self.before;
        self.first = Some(WatchedContact {
            number,
            event: *ev,
            cue_before,
            t0,
            cue_after: balls[cue].r,
            other_after: balls[(other as usize).min(n - 1)].r,
        });
        self.options.stop_at_first_contact
    }

    /// The first contact seen since [`Watcher::start`].
    pub fn first(&self) -> Option<WatchedContact> {
        self.first
    }

    /// The rules' facts of the events seen since [`Watcher::start`], where
    /// [`WatchOptions::facts`] asks for them.
    pub fn facts(&self) -> Option<&ShotFacts> {
        self.options.facts.then_some(&self.facts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(kind: EventKind, t: f64, ball: u32, other: u32) -> Event {
        Event {
            kind,
            t,
            ball,
            other,
        }
    }

    #[test]
    fn facts_count_strictly_before_and_after_as_pooltool() {
        use EventKind::*;
        let events = [
            ev(StickBall, 0.0, 0, u32::MAX),
            ev(BallLinearCushion, 0.5, 0, 3),
            ev(BallLinearCushion, 0.7, 0, 9),
            // the first contact at 1.0, and a cushion at the very same time: not after it
            ev(BallBall, 1.0, 0, 1),
            ev(BallLinearCushion, 1.0, 2, 6),
            ev(BallLinearCushion, 1.5, 0, 12),
            // a cushion of the cue ball at the second contact's very time: not before it
            ev(BallLinearCushion, 2.0, 0, 15),
            ev(BallBall, 2.0, 2, 0),
            ev(BallLinearCushion, 2.5, 0, 3),
            ev(BallPocket, 3.0, 1, 4),
            ev(BallPocket, 3.5, 2, 0),
        ];
        let f = ShotFacts::of(events.iter().take(5), 0);
        assert_eq!(f.first_ball, Some((1.0, 1)));
        assert!(
            !f.cushion_after_first,
            "a cushion at the contact's time is not after it"
        );
        assert_eq!(f.at_cushion, 0b101);
        let f = ShotFacts::of(&events, 0);
        assert!(f.any_ball_ball && f.cushion_after_first);
        assert_eq!(f.second_ball_t, Some(2.0));
        assert_eq!(
            f.cue_cushions, 3,
            "0.5, 0.7 and 1.5: not the one at 2.0, nor 2.5"
        );
        assert_eq!(f.pocketed, 0b110);
        assert_eq!(
            (f.pocket_of[1], f.pocket_of[2], f.pocket_of[0]),
            (4, 0, NO_POCKET)
        );
        // another ball's contacts are no first contact of the cue ball
        let f = ShotFacts::of(&[ev(BallBall, 1.0, 1, 2)], 0);
        assert!(f.any_ball_ball && f.first_ball.is_none());
    }
}
