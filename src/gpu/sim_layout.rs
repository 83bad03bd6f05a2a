//! How the GPU event loop's state lies in storage (the host's side of
//! `shaders/simulate/event_loop.wgsl`'s layout constants, the same names and values; a test
//! reads the shader's and compares), and the host's packing and unpacking of one table:
//! its start (after the strike, resolved here), its end, its recorded events and its watch.
//!
//! A batch's state is three regions, one after the other in the real buffer and in the
//! u32 buffer, each a block per table:
//! - **I/O** ([`IO_REALS`], [`IO_UINTS`]): the balls, their transitions, the clock, the
//!   counts and the status. The host writes it before the first dispatch and reads it back
//!   at the end; it is all that crosses the bus for a batch of final states.
//! - **caches** ([`CACHE_REALS`], [`CACHE_UINTS`]): pair and row entries, the device's
//!   own: the first dispatch starts them empty (as [`crate::simulate::EventLoop::reset`]
//!   does), and they are never read back.
//! - **watch** ([`WATCH_REALS`], [`WATCH_UINTS`]): what a study needs of a table's events
//!   (the cue ball's first contact, every pot), read back only by a study.

use crate::error::Error;
use crate::model::MotionState;
use crate::model::ball_state::{BallState, ball_energy};
use crate::model::sim_params::SimParams;
use crate::model::vec3::Vec3;
use crate::motion::evolve::{TransitionKind, next_transition};
use crate::resolve::stick_ball::{CueStrike, cue_strike};
use crate::simulate::Limits;
use crate::simulate::batch::EventRecord;
use crate::simulate::events::{Cut, Event, EventKind, NO_AGENT, Outcome};

use super::device::gpu_error;

/// The most balls of one table on the GPU (the shader's `GPU_MAX_BALLS`).
pub const GPU_MAX_BALLS: usize = 16;
/// Pair entries of one table (the shader's `GPU_MAX_PAIRS`).
pub(super) const GPU_MAX_PAIRS: usize = GPU_MAX_BALLS * (GPU_MAX_BALLS - 1) / 2;
/// Ball–table rows of one table: 3 categories of [`GPU_MAX_BALLS`] (`GPU_ROWS`).
pub(super) const GPU_ROWS: usize = 3 * GPU_MAX_BALLS;

/// I/O reals per table: every ball's r, v, w, t (10 each), its transition's time, the clock.
pub(super) const IO_REALS: usize = 177;
pub(super) const IO_R_TRANS: usize = 10 * GPU_MAX_BALLS;
pub(super) const IO_R_CLOCK: usize = IO_R_TRANS + GPU_MAX_BALLS;
/// I/O u32s per table: every ball's motion state, its transition's kind, then n_balls,
/// n_events and the status.
pub(super) const IO_UINTS: usize = 35;
pub(super) const IO_U_TRANS: usize = GPU_MAX_BALLS;
pub(super) const IO_U_N: usize = 2 * GPU_MAX_BALLS;
/// Cache reals per table: pair times, then row times.
pub(super) const CACHE_REALS: usize = GPU_MAX_PAIRS + GPU_ROWS;
pub(super) const CACHE_R_ROWS: usize = GPU_MAX_PAIRS;
/// Cache u32s per table: pair steps, row steps, row items.
pub(super) const CACHE_UINTS: usize = GPU_MAX_PAIRS + 2 * GPU_ROWS;
pub(super) const CACHE_U_ROWS: usize = GPU_MAX_PAIRS;
pub(super) const CACHE_U_ITEMS: usize = GPU_MAX_PAIRS + GPU_ROWS;
/// Watch reals per table: the first contact's time, the clock before it, the cue ball's
/// r, v, w, t before it, the cue ball's and the other ball's centres after it, each pot's
/// time.
pub(super) const WATCH_REALS: usize = 34;
pub(super) const WATCH_R_BEFORE: usize = 2;
pub(super) const WATCH_R_CUE: usize = 12;
pub(super) const WATCH_R_OTHER: usize = 15;
pub(super) const WATCH_R_POTS: usize = 18;
/// Watch u32s per table: the pots so far, the first contact's event number (0: none), its
/// kind, ball, other and the cue ball's motion state before it, then each pot's event
/// number, ball and pocket.
pub(super) const WATCH_UINTS: usize = 54;
pub(super) const WATCH_U_FIRST: usize = 1;
pub(super) const WATCH_U_POTS: usize = 6;
/// Per recorded event (`EVENT_REALS`, `EVENT_UINTS`).
pub(super) const EVENT_REALS: usize = 21;
pub(super) const EVENT_UINTS: usize = 5;

/// Every layout constant the shader declares too, by its WGSL name, for the test that
/// compares them.
#[doc(hidden)]
pub const SHADER_LAYOUT: &[(&str, usize)] = &[
    ("GPU_MAX_BALLS", GPU_MAX_BALLS),
    ("GPU_MAX_PAIRS", GPU_MAX_PAIRS),
    ("GPU_ROWS", GPU_ROWS),
    ("IO_REALS", IO_REALS),
    ("IO_R_TRANS", IO_R_TRANS),
    ("IO_R_CLOCK", IO_R_CLOCK),
    ("IO_UINTS", IO_UINTS),
    ("IO_U_TRANS", IO_U_TRANS),
    ("IO_U_N", IO_U_N),
    ("CACHE_REALS", CACHE_REALS),
    ("CACHE_R_ROWS", CACHE_R_ROWS),
    ("CACHE_UINTS", CACHE_UINTS),
    ("CACHE_U_ROWS", CACHE_U_ROWS),
    ("CACHE_U_ITEMS", CACHE_U_ITEMS),
    ("WATCH_REALS", WATCH_REALS),
    ("WATCH_R_BEFORE", WATCH_R_BEFORE),
    ("WATCH_R_CUE", WATCH_R_CUE),
    ("WATCH_R_OTHER", WATCH_R_OTHER),
    ("WATCH_R_POTS", WATCH_R_POTS),
    ("WATCH_UINTS", WATCH_UINTS),
    ("WATCH_U_FIRST", WATCH_U_FIRST),
    ("WATCH_U_POTS", WATCH_U_POTS),
    ("EVENT_REALS", EVENT_REALS),
    ("EVENT_UINTS", EVENT_UINTS),
];

// The layout's blocks hold what they say.
const _: () = assert!(IO_REALS == IO_R_CLOCK + 1);
const _: () = assert!(IO_UINTS == IO_U_N + 3);
const _: () = assert!(WATCH_REALS == WATCH_R_POTS + GPU_MAX_BALLS);
const _: () = assert!(WATCH_UINTS == WATCH_U_POTS + 3 * GPU_MAX_BALLS);

/// The shader's "never" as the host writes it in f64 (f32 buffers get `NEVER_F32`).
pub(super) const NEVER_F64: f64 = 1.0e300;
pub(super) const NEVER_F32: f32 = 3.0e38;

/// A table's status (the shader's `STATUS_*`).
const STATUS_RUNNING: u32 = 0;
const STATUS_DONE: u32 = 1;
const STATUS_CUT_EVENTS: u32 = 2;
const STATUS_CUT_TIME: u32 = 3;

/// One table's shot: its balls (pooltool's order) and the strike, if any.
#[derive(Clone, Debug)]
pub struct GpuShot {
    /// The balls at t = 0.
    pub balls: Vec<BallState>,
    /// The cue ball's index and the strike.
    pub strike: Option<(usize, CueStrike)>,
}

/// One table's result: its events (if asked for) with the involved balls' states, the
/// final states, and how it ended.
#[derive(Clone, Debug, PartialEq)]
pub struct GpuRun {
    /// The events, the strike included (empty unless events were asked for).
    pub events: Vec<EventRecord>,
    /// The balls at the end.
    pub balls: Vec<BallState>,
    /// Events, end time, and whether a limit cut the run.
    pub outcome: Outcome,
}

/// The cue ball's first contact as the device's watch saw it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WatchedContact {
    /// Its event number (the strike is 1).
    pub number: usize,
    /// The event.
    pub event: Event,
    /// The cue ball's state before it, and the clock then.
    pub cue_before: BallState,
    /// The clock before the event.
    pub t0: f64,
    /// The cue ball's centre right after it.
    pub cue_after: Vec3,
    /// For a ball–ball contact, the other ball's centre right after it.
    pub other_after: Vec3,
}

/// One table of a watched batch: its cue ball at the end, how it ended, and the watch.
#[derive(Clone, Debug, PartialEq)]
pub struct WatchedRun {
    /// The watched cue ball's final state.
    pub cue: BallState,
    /// Events, end time, and whether a limit cut the run.
    pub outcome: Outcome,
    /// What the watch saw.
    pub watch: GpuWatch,
}

/// What the device's watch of a table saw: what a study takes from its events.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GpuWatch {
    /// The cue ball's first contact, if there was one.
    pub first: Option<WatchedContact>,
    /// Every pot in order: its event number and the `ball_pocket` event.
    pub pots: Vec<(usize, Event)>,
}

/// The shader's "never" as the CPU's ∞.
pub(super) fn from_never(t: f64) -> f64 {
    if t >= f64::from(NEVER_F32) {
        f64::INFINITY
    } else {
        t
    }
}

/// Lays out one table's I/O block at its start (after the strike, which is resolved
/// here, under the CPU loop's rule) in `sr` and `su`; returns the strike's event record if
/// there was a strike and `record` asks for it. Allocates nothing.
pub(super) fn start_table(
    shot_balls: &[BallState],
    shot_strike: Option<(usize, CueStrike)>,
    params: &SimParams,
    limits: Limits,
    record: bool,
    sr: &mut [f64; IO_REALS],
    su: &mut [u32; IO_UINTS],
) -> Option<EventRecord> {
    let n = shot_balls.len().min(GPU_MAX_BALLS);
    let mut balls = [BallState::at_rest(0.0, 0.0, params.ball.r); GPU_MAX_BALLS];
    for (b, s) in balls.iter_mut().zip(shot_balls) {
        *b = BallState { t: 0.0, ..*s };
    }
    let balls = &mut balls[..n];
    let mut strike = None;
    let mut n_events = 0u32;
    // the stick candidate of the CPU loop: at t = 0, every ball at rest, V0 > 0
    if let Some((cue, s)) = shot_strike {
        let at_rest = balls.iter().all(|b| ball_energy(b, &params.ball) == 0.0);
        if at_rest && s.v0 > 0.0 && limits.max_events > 0 {
            let struck = cue_strike(&balls[cue], &s, &params.ball, &params.cue);
            balls[cue] = BallState { t: 0.0, ..struck };
            n_events = 1;
            let event = Event {
                kind: EventKind::StickBall,
                t: 0.0,
                ball: cue as u32,
                other: NO_AGENT,
            };
            strike = record.then(|| EventRecord::new(event, balls));
        }
    }
    sr.fill(0.0);
    su.fill(0);
    for (i, b) in balls.iter().enumerate() {
        let at = 10 * i;
        sr[at..at + 10].copy_from_slice(&[
            b.r.x, b.r.y, b.r.z, b.v.x, b.v.y, b.v.z, b.w.x, b.w.y, b.w.z, b.t,
        ]);
        su[i] = b.s as u32;
        let (t, kind) = next_transition(b, &params.ball).map_or((f64::INFINITY, 0), |(tau, k)| {
            (b.t + tau, transition_code(k))
        });
        sr[IO_R_TRANS + i] = if t.is_finite() { t } else { NEVER_F64 };
        su[IO_U_TRANS + i] = kind;
    }
    sr[IO_R_CLOCK] = 0.0;
    su[IO_U_N] = n as u32;
    su[IO_U_N + 1] = n_events;
    // a table without balls, or one cut before its first event, is done already
    su[IO_U_N + 2] = if limits.max_events == 0 {
        STATUS_CUT_EVENTS
    } else if n == 0 {
        STATUS_DONE
    } else {
        STATUS_RUNNING
    };
    strike
}

/// The shader's code of a transition kind (`TRANSITION_*` of `motion/evolve.wgsl`).
fn transition_code(k: TransitionKind) -> u32 {
    match k {
        TransitionKind::SlidingRolling => 0,
        TransitionKind::RollingSpinning => 1,
        TransitionKind::RollingStationary => 2,
        TransitionKind::SpinningStationary => 3,
    }
}

fn event_kind(code: u32) -> Result<EventKind, Error> {
    Ok(match code {
        0 => EventKind::StickBall,
        1 => EventKind::BallBall,
        2 => EventKind::BallLinearCushion,
        3 => EventKind::BallCircularCushion,
        4 => EventKind::BallPocket,
        5 => EventKind::SlidingRolling,
        6 => EventKind::RollingSpinning,
        7 => EventKind::RollingStationary,
        8 => EventKind::SpinningStationary,
        _ => return Err(gpu_error(format!("the GPU reported event kind {code}"))),
    })
}

fn motion_state(code: u32) -> Result<MotionState, Error> {
    Ok(match code {
        0 => MotionState::Stationary,
        1 => MotionState::Spinning,
        2 => MotionState::Sliding,
        3 => MotionState::Rolling,
        4 => MotionState::Pocketed,
        _ => return Err(gpu_error(format!("the GPU reported motion state {code}"))),
    })
}

/// A ball state from its 10 reals (r, v, w, t) and its motion state.
fn ball_state(r: &[f64], s: u32) -> Result<BallState, Error> {
    Ok(BallState {
        r: Vec3::new(r[0], r[1], r[2]),
        v: Vec3::new(r[3], r[4], r[5]),
        w: Vec3::new(r[6], r[7], r[8]),
        s: motion_state(s)?,
        t: r[9],
    })
}

/// One recorded event from its u32s (kind, ball, other, two states) and reals.
pub(super) fn event_record(u: &[u32], r: &[f64]) -> Result<EventRecord, Error> {
    let event = Event {
        kind: event_kind(u[0])?,
        t: r[0],
        ball: u[1],
        other: u[2],
    };
    Ok(EventRecord {
        event,
        states: [ball_state(&r[1..11], u[3])?, ball_state(&r[11..21], u[4])?],
    })
}

/// A finished table's outcome, from its I/O block.
pub(super) fn table_outcome(sr: &[f64], su: &[u32]) -> Outcome {
    Outcome {
        n_events: su[IO_U_N + 1] as usize,
        t_end: from_never(sr[IO_R_CLOCK]),
        cut: match su[IO_U_N + 2] {
            STATUS_CUT_EVENTS => Some(Cut::MaxEvents),
            STATUS_CUT_TIME => Some(Cut::MaxTime),
            _ => None,
        },
    }
}

/// Ball `i`'s final state, from a table's I/O block.
pub(super) fn final_ball(sr: &[f64], su: &[u32], i: usize) -> Result<BallState, Error> {
    ball_state(&sr[10 * i..10 * i + 10], su[i])
}

/// A finished table's final states and outcome, from its I/O block, into its run.
pub(super) fn finish_table(run: &mut GpuRun, sr: &[f64], su: &[u32]) -> Result<(), Error> {
    let n = (su[IO_U_N] as usize).min(GPU_MAX_BALLS);
    run.balls.clear();
    for i in 0..n {
        run.balls.push(final_ball(sr, su, i)?);
    }
    run.outcome = table_outcome(sr, su);
    Ok(())
}

/// Reads a table's watch block.
pub(super) fn read_watch(sr: &[f64], su: &[u32], n_balls: usize) -> Result<GpuWatch, Error> {
    let v3 = |at: usize| Vec3::new(sr[at], sr[at + 1], sr[at + 2]);
    let first = match su[WATCH_U_FIRST] {
        0 => None,
        number => Some(WatchedContact {
            number: number as usize,
            event: Event {
                kind: event_kind(su[WATCH_U_FIRST + 1])?,
                t: sr[0],
                ball: su[WATCH_U_FIRST + 2],
                other: su[WATCH_U_FIRST + 3],
            },
            cue_before: ball_state(
                &sr[WATCH_R_BEFORE..WATCH_R_BEFORE + 10],
                su[WATCH_U_FIRST + 4],
            )?,
            t0: sr[1],
            cue_after: v3(WATCH_R_CUE),
            other_after: v3(WATCH_R_OTHER),
        }),
    };
    let n_pots = su[0] as usize;
    if n_pots > n_balls {
        return Err(gpu_error(format!("the GPU reported {n_pots} pots")));
    }
    let pots = (0..n_pots)
        .map(|k| {
            let at = WATCH_U_POTS + k;
            (
                su[at] as usize,
                Event {
                    kind: EventKind::BallPocket,
                    t: sr[WATCH_R_POTS + k],
                    ball: su[at + GPU_MAX_BALLS],
                    other: su[at + 2 * GPU_MAX_BALLS],
                },
            )
        })
        .collect();
    Ok(GpuWatch { first, pots })
}
