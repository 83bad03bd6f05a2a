//! The watch: what a shot study takes from a table's events without keeping them — the
//! watched (cue) ball's first contact, with the state it had and the clock just before it
//! and the centres just after it, and every pot in order.
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
}

/// One table's watch, owned (what the GPU's readback makes of a watch block).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Watch {
    /// The watched ball's first contact, if there was one.
    pub first: Option<WatchedContact>,
    /// Every pot, in order.
    pub pots: Vec<WatchedPot>,
}

impl Watch {
    /// Borrowed, as a chunk hands it out.
    pub fn as_table_watch(&self) -> TableWatch<'_> {
        TableWatch {
            first: self.first,
            pots: &self.pots,
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
}

impl Watcher {
    /// A watcher for `options`.
    pub fn new(options: WatchOptions) -> Watcher {
        Watcher {
            options,
            before: (BallState::at_rest(0.0, 0.0, 0.0), 0.0),
            first: None,
        }
    }

    /// Starts a table (its watch blank).
    pub fn start(&mut self) {
        self.first = None;
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
}
