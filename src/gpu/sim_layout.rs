//! How the GPU event loop's state lies in storage (the host's side of
//! `shaders/simulate/event_loop.wgsl`'s layout constants, the same names and values; a test
//! reads the shader's and compares), and the host's packing and unpacking of one table:
//! its start (after the strike, resolved here), its end, its recorded events and its watch.
//!
//! The layout depends on the most balls a table of the call may have ([`SimLayout`], one
//! per bucket of [`GPU_BALL_BUCKETS`]); the shader is built once per bucket, its
//! `GPU_MAX_BALLS` set to the bucket and every other constant derived from it.
//!
//! A batch's state is three regions, one after the other in the real buffer and in the
//! u32 buffer, each a block per table:
//! - **I/O** ([`SimLayout::io_reals`], [`SimLayout::io_uints`]): the balls, their transitions, the clock, the
//!   counts and the status. The host writes it before the first dispatch and reads it back
//!   at the end; it is all that crosses the bus for a batch of final states.
//! - **caches** ([`SimLayout::cache_reals`], [`SimLayout::cache_uints`]): pair and row entries, the device's
//!   own: the first dispatch starts them empty (as [`crate::simulate::EventLoop::reset`]
//!   does), and they are never read back.
//! - **watch** ([`SimLayout::watch_reals`], [`SimLayout::watch_uints`]): what a study needs of a table's events
//!   (the cue ball's first contact, every pot, the rules' facts) and of its end (the cue
//!   ball's final state, the counts and status): all that a study reads back.

use crate::error::Error;
use crate::model::MotionState;
use crate::model::ball_state::{BallState, ball_energy};
use crate::model::sim_params::SimParams;
use crate::model::vec3::Vec3;
use crate::motion::evolve::{TransitionKind, next_transition};
use crate::resolve::stick_ball::{CueStrike, cue_strike};
use crate::simulate::batch::EventRecord;
use crate::simulate::events::{Cut, Event, EventKind, NO_AGENT, Outcome};
use crate::simulate::watch::{ShotFacts, Watch, WatchedContact, WatchedPot};
use crate::simulate::{DrawnStrikes, Limits};

use super::device::gpu_error;

/// The ball counts the event loop is built for: a call runs on the smallest that holds its
/// largest table (one pipeline each, built when first needed). Each is the shader's
/// `GPU_MAX_BALLS` of its build; the workgroup keeps the table's state in workgroup memory,
/// which grows with the square of it (about 7 KB at 16 balls, 17 KB at 32, 29 KB at 48,
/// 43 KB at 64 in f64): an adapter whose workgroup memory is too small for a bucket
/// refuses it with [`Error::Unsupported`].
pub const GPU_BALL_BUCKETS: [usize; 4] = [16, 32, 48, 64];

/// The most balls of one table on the GPU: the largest bucket, the CPU loop's
/// [`crate::simulate::MAX_BALLS`] too.
pub const GPU_MAX_BALLS: usize = GPU_BALL_BUCKETS[GPU_BALL_BUCKETS.len() - 1];

/// Per recorded event (`EVENT_REALS`, `EVENT_UINTS`): t and the two agents' r, v, w, t;
/// kind, ball, other and the two agents' motion states.
pub(super) const EVENT_REALS: usize = 21;
pub(super) const EVENT_UINTS: usize = 5;
/// Reals of one parameter block (`SIM_REALS`): the ball's 10, the resolver's 8, max_time
/// (at `SIM_R_MAX_TIME`).
pub(super) const SIM_REALS: usize = 19;
pub(super) const SIM_R_MAX_TIME: usize = 18;

/// The storage layout of the event loop built for `max_balls` balls a table: every
/// constant the shader declares with the same name in upper case (a test evaluates the
/// shader's declarations and compares them for every bucket).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SimLayout {
    /// The most balls of a table (`GPU_MAX_BALLS`).
    pub gpu_max_balls: usize,
    /// Pair entries of one table (`GPU_MAX_PAIRS`).
    pub gpu_max_pairs: usize,
    /// Ball–table rows of one table: 3 categories of `gpu_max_balls` (`GPU_ROWS`).
    pub gpu_rows: usize,
    /// I/O reals per table: every ball's r, v, w, t (10 each), its transition's time, the
    /// clock (`IO_REALS`; `IO_R_TRANS`, `IO_R_CLOCK` where they start).
    pub io_reals: usize,
    /// Where the transitions' times start in the I/O reals.
    pub io_r_trans: usize,
    /// Where the clock is in the I/O reals.
    pub io_r_clock: usize,
    /// I/O u32s per table: every ball's motion state, its transition's kind, then n_balls,
    /// n_events and the status (`IO_UINTS`).
    pub io_uints: usize,
    /// Where the transitions' kinds start in the I/O u32s.
    pub io_u_trans: usize,
    /// Where n_balls, n_events and the status are in the I/O u32s.
    pub io_u_n: usize,
    /// Cache reals per table: pair times, then row times (`CACHE_REALS`).
    pub cache_reals: usize,
    /// Where the row times start in the cache reals.
    pub cache_r_rows: usize,
    /// Cache u32s per table: pair steps, row steps, row items (`CACHE_UINTS`).
    pub cache_uints: usize,
    /// Where the row steps start in the cache u32s.
    pub cache_u_rows: usize,
    /// Where the row items start in the cache u32s.
    pub cache_u_items: usize,
    /// Watch reals per table: the first contact's time, the clock before it, the cue
    /// ball's r, v, w, t before it, the cue ball's and the other ball's centres after it,
    /// each pot's time, the rules' facts, the table's end (`WATCH_REALS`).
    pub watch_reals: usize,
    /// Where the cue ball's state before the first contact starts in the watch reals.
    pub watch_r_before: usize,
    /// Where the cue ball's centre after it starts.
    pub watch_r_cue: usize,
    /// Where the other ball's centre after it starts.
    pub watch_r_other: usize,
    /// Where the pots' times start.
    pub watch_r_pots: usize,
    /// Watch u32s per table: the pots so far, the first contact's event number (0: none),
    /// its kind, ball, other and the cue ball's motion state before it, then each pot's
    /// event number, ball and pocket, the rules' facts, the table's end (`WATCH_UINTS`).
    pub watch_uints: usize,
    /// Where the first contact starts in the watch u32s.
    pub watch_u_first: usize,
    /// Where the pots start in the watch u32s.
    pub watch_u_pots: usize,
    /// Where the rules' facts start in the watch reals: the first and second ball
    /// contacts' times and the cue ball's last counted cushion's (`WATCH_R_FACTS`).
    pub watch_r_facts: usize,
    /// Where the rules' facts start in the watch u32s: any ball–ball contact, the first
    /// ball contact's other ball + 1 (0: none), a cushion after it, the balls at a cushion
    /// (two words), the second contact seen, the cue ball's cushions before it, and how
    /// many of them came at the last one's time (`WATCH_U_FACTS`).
    pub watch_u_facts: usize,
    /// Where the table's end starts in the watch reals: the cue ball's r, v, w, t at the
    /// end and the clock (`WATCH_R_END`, `WATCH_END_REALS` of them). A study reads back
    /// the watch blocks alone.
    pub watch_r_end: usize,
    /// Where the table's end starts in the watch u32s: the cue ball's motion state,
    /// n_balls, n_events, the status (`WATCH_U_END`, `WATCH_END_UINTS` of them).
    pub watch_u_end: usize,
}

impl SimLayout {
    /// The layout for tables of up to `max_balls` balls.
    pub const fn for_balls(max_balls: usize) -> SimLayout {
        let n = max_balls;
        let pairs = n * n.saturating_sub(1) / 2;
        let rows = 3 * n;
        let io_r_trans = 10 * n;
        let io_r_clock = io_r_trans + n;
        let io_u_n = 2 * n;
        let watch_r_pots = 18;
        let watch_u_pots = 6;
        SimLayout {
            gpu_max_balls: n,
            gpu_max_pairs: pairs,
            gpu_rows: rows,
            io_reals: io_r_clock + 1,
            io_r_trans,
            io_r_clock,
            io_uints: io_u_n + 3,
            io_u_trans: n,
            io_u_n,
            cache_reals: pairs + rows,
            cache_r_rows: pairs,
            cache_uints: pairs + 2 * rows,
            cache_u_rows: pairs,
            cache_u_items: pairs + rows,
            watch_reals: watch_r_pots + n + WATCH_FACT_REALS + WATCH_END_REALS,
            watch_r_before: 2,
            watch_r_cue: 12,
            watch_r_other: 15,
            watch_r_pots,
            watch_uints: watch_u_pots + 3 * n + WATCH_FACT_UINTS + WATCH_END_UINTS,
            watch_u_first: 1,
            watch_u_pots,
            watch_r_facts: watch_r_pots + n,
            watch_u_facts: watch_u_pots + 3 * n,
            watch_r_end: watch_r_pots + n + WATCH_FACT_REALS,
            watch_u_end: watch_u_pots + 3 * n + WATCH_FACT_UINTS,
        }
    }

    /// The layout of the smallest bucket ([`GPU_BALL_BUCKETS`]) that holds tables of
    /// `n_balls` balls, or `None` past [`GPU_MAX_BALLS`].
    pub fn bucket(n_balls: usize) -> Option<SimLayout> {
        GPU_BALL_BUCKETS
            .iter()
            .find(|&&b| b >= n_balls)
            .map(|&b| SimLayout::for_balls(b))
    }

    /// Every constant by its WGSL name (`EVENT_*` and `SIM_*` too), for the test
    /// that compares them with the shader's.
    pub fn named(&self) -> Vec<(&'static str, usize)> {
        vec![
            ("GPU_MAX_BALLS", self.gpu_max_balls),
            ("GPU_MAX_PAIRS", self.gpu_max_pairs),
            ("GPU_ROWS", self.gpu_rows),
            ("IO_REALS", self.io_reals),
            ("IO_R_TRANS", self.io_r_trans),
            ("IO_R_CLOCK", self.io_r_clock),
            ("IO_UINTS", self.io_uints),
            ("IO_U_TRANS", self.io_u_trans),
            ("IO_U_N", self.io_u_n),
            ("CACHE_REALS", self.cache_reals),
            ("CACHE_R_ROWS", self.cache_r_rows),
            ("CACHE_UINTS", self.cache_uints),
            ("CACHE_U_ROWS", self.cache_u_rows),
            ("CACHE_U_ITEMS", self.cache_u_items),
            ("WATCH_REALS", self.watch_reals),
            ("WATCH_R_BEFORE", self.watch_r_before),
            ("WATCH_R_CUE", self.watch_r_cue),
            ("WATCH_R_OTHER", self.watch_r_other),
            ("WATCH_R_POTS", self.watch_r_pots),
            ("WATCH_UINTS", self.watch_uints),
            ("WATCH_U_FIRST", self.watch_u_first),
            ("WATCH_U_POTS", self.watch_u_pots),
            ("WATCH_R_FACTS", self.watch_r_facts),
            ("WATCH_U_FACTS", self.watch_u_facts),
            ("WATCH_FACT_REALS", WATCH_FACT_REALS),
            ("WATCH_FACT_UINTS", WATCH_FACT_UINTS),
            ("WATCH_R_END", self.watch_r_end),
            ("WATCH_U_END", self.watch_u_end),
            ("WATCH_END_REALS", WATCH_END_REALS),
            ("WATCH_END_UINTS", WATCH_END_UINTS),
            ("STRUCK_REALS", STRUCK_REALS),
            ("STRUCK_UINTS", STRUCK_UINTS),
            ("DRAWN_REALS", DRAWN_REALS),
            ("DRAWN_UINTS", DRAWN_UINTS),
            ("EVENT_REALS", EVENT_REALS),
            ("EVENT_UINTS", EVENT_UINTS),
            ("SIM_REALS", SIM_REALS),
            ("SIM_R_MAX_TIME", SIM_R_MAX_TIME),
        ]
    }
}

/// Reals of the rules' facts in a watch block (`WATCH_FACT_REALS`).
pub const WATCH_FACT_REALS: usize = 3;
/// u32s of the rules' facts in a watch block (`WATCH_FACT_UINTS`).
pub const WATCH_FACT_UINTS: usize = 8;
/// Reals of a table's end in a watch block (`WATCH_END_REALS`).
pub const WATCH_END_REALS: usize = 11;
/// u32s of a table's end in a watch block (`WATCH_END_UINTS`).
pub const WATCH_END_UINTS: usize = 4;
/// Reals of one table's strike block when a chunk is expanded from one position
/// (`STRUCK_REALS`, the shader's `expand_tables`): the struck ball's r, v, w, t and its
/// transition's time.
pub const STRUCK_REALS: usize = 11;
/// u32s of one strike block (`STRUCK_UINTS`): the struck ball's motion state, its
/// transition's kind, n_events and the status.
pub const STRUCK_UINTS: usize = 4;
/// Reals of a drawn chunk's header (`DRAWN_REALS`, the shader's `expand_drawn`): the
/// intended strike (V0, φ, θ, a, b), the noise's five σ in the same order, and the cue's
/// mass, end mass, english and squirt throttles.
pub const DRAWN_REALS: usize = 14;
/// u32s of a drawn chunk's header (`DRAWN_UINTS`): the seed and the chunk's first sample
/// id (low word, high word each), and 1 where the strike is played at all.
pub const DRAWN_UINTS: usize = 5;

/// The largest bucket's layout: the sizes of the host's scratch blocks.
pub(super) const MAX_LAYOUT: SimLayout = SimLayout::for_balls(GPU_MAX_BALLS);

// The layout's blocks hold what they say (checked for the largest bucket).
const _: () = {
    let l = SimLayout::for_balls(GPU_MAX_BALLS);
    assert!(l.watch_r_pots == l.watch_r_other + 3);
    assert!(l.watch_r_other == l.watch_r_cue + 3);
    assert!(l.watch_r_cue == l.watch_r_before + 10);
    assert!(l.watch_u_pots == l.watch_u_first + 5);
    assert!(GPU_MAX_BALLS == crate::simulate::MAX_BALLS);
};

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

/// One table of a watched batch: its cue ball at the end, how it ended, and the watch.
#[derive(Clone, Debug, PartialEq)]
pub struct WatchedRun {
    /// The watched cue ball's final state.
    pub cue: BallState,
    /// Events, end time, and whether a limit cut the run.
    pub outcome: Outcome,
    /// What the watch saw.
    pub watch: Watch,
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
#[allow(clippy::too_many_arguments)]
pub(super) fn start_table(
    shot_balls: &[BallState],
    shot_strike: Option<(usize, CueStrike)>,
    params: &SimParams,
    limits: Limits,
    record: bool,
    layout: &SimLayout,
    sr: &mut [f64],
    su: &mut [u32],
) -> Option<EventRecord> {
    let n = shot_balls.len().min(layout.gpu_max_balls);
    let mut balls = [BallState::at_rest(0.0, 0.0, params.ball.r); GPU_MAX_BALLS];
    for (b, s) in balls.iter_mut().zip(shot_balls) {
        *b = BallState { t: 0.0, ..*s };
    }
    let balls = &mut balls[..n];
    let mut strike = None;
    let struck = struck_ball(balls, shot_strike, params, limits);
    if let Some((cue, b)) = struck {
        balls[cue] = b;
        let event = Event {
            kind: EventKind::StickBall,
            t: 0.0,
            ball: cue as u32,
            other: NO_AGENT,
        };
        strike = record.then(|| EventRecord::new(event, balls));
    }
    sr.fill(0.0);
    su.fill(0);
    for (i, b) in balls.iter().enumerate() {
        let (t, kind) = ball_io(b, params, &mut sr[10 * i..10 * i + 10]);
        su[i] = b.s as u32;
        sr[layout.io_r_trans + i] = t;
        su[layout.io_u_trans + i] = kind;
    }
    sr[layout.io_r_clock] = 0.0;
    su[layout.io_u_n] = n as u32;
    su[layout.io_u_n + 1] = u32::from(struck.is_some());
    su[layout.io_u_n + 2] = start_status(n, limits);
    strike
}

/// One table's strike block ([`STRUCK_REALS`], [`STRUCK_UINTS`]) for a chunk expanded from
/// one position on the device (the shader's `expand_tables`): what [`start_table`] writes
/// for ball `cue` of `position` struck by `strike` — the ball's r, v, w, t and its
/// transition (the strike played under the CPU loop's rule, or the ball as it is), the
/// event count and the status — so that the expanded block is [`start_table`]'s, bit for
/// bit. `position`'s balls must be at t = 0.
pub(super) fn strike_block(
    position: &[BallState],
    (cue, strike): (usize, CueStrike),
    params: &SimParams,
    limits: Limits,
    sr: &mut [f64; STRUCK_REALS],
    su: &mut [u32; STRUCK_UINTS],
) {
    let struck = struck_ball(position, Some((cue, strike)), params, limits);
    let b = struck.map_or(position[cue], |(_, b)| b);
    let (t, kind) = ball_io(&b, params, &mut sr[..10]);
    sr[10] = t;
    *su = [
        b.s as u32,
        kind,
        u32::from(struck.is_some()),
        start_status(position.len(), limits),
    ];
}

/// A drawn chunk's header ([`DRAWN_REALS`], [`DRAWN_UINTS`]) for the shader's
/// `expand_drawn`: table `k` of the chunk is `position` with its ball `cue` struck by
/// `drawn`'s strike of sample `first + k` (drawn on the device) under the CPU loop's rule,
/// so that the block the device lays out is [`start_table`]'s for that strike, bit for
/// bit. `position`'s balls must be at t = 0.
pub(super) fn drawn_block(
    position: &[BallState],
    drawn: &DrawnStrikes,
    params: &SimParams,
    limits: Limits,
    sr: &mut [f64; DRAWN_REALS],
    su: &mut [u32; DRAWN_UINTS],
) {
    let (s, c) = (drawn.shot, &params.cue);
    let sigma = drawn.sigma;
    *sr = [
        s.v0,
        s.phi,
        s.theta,
        s.a,
        s.b,
        sigma[0],
        sigma[1],
        sigma[2],
        sigma[3],
        sigma[4],
        c.mass,
        c.end_mass,
        c.english_throttle,
        c.squirt_throttle,
    ];
    // struck_ball's rule, less the strike's own V0 > 0 (the device's, per sample)
    let played =
        position.iter().all(|b| ball_energy(b, &params.ball) == 0.0) && limits.max_events > 0;
    *su = [
        drawn.seed as u32,
        (drawn.seed >> 32) as u32,
        drawn.first as u32,
        (drawn.first >> 32) as u32,
        u32::from(played),
    ];
}

/// The CPU loop's stick candidate: ball `cue` right after `strike` (at t = 0) where the
/// strike is played — every ball at rest, V0 > 0, an event allowed — else `None`.
fn struck_ball(
    balls: &[BallState],
    strike: Option<(usize, CueStrike)>,
    params: &SimParams,
    limits: Limits,
) -> Option<(usize, BallState)> {
    let (cue, s) = strike?;
    let at_rest = balls.iter().all(|b| ball_energy(b, &params.ball) == 0.0);
    (at_rest && s.v0 > 0.0 && limits.max_events > 0).then(|| {
        let struck = cue_strike(&balls[cue], &s, &params.ball, &params.cue);
        (cue, BallState { t: 0.0, ..struck })
    })
}

/// A ball's r, v, w, t into `r` (10 reals); its next transition's absolute time (the
/// shader's never where there is none) and kind.
fn ball_io(b: &BallState, params: &SimParams, r: &mut [f64]) -> (f64, u32) {
    r.copy_from_slice(&[
        b.r.x, b.r.y, b.r.z, b.v.x, b.v.y, b.v.z, b.w.x, b.w.y, b.w.z, b.t,
    ]);
    let (t, kind) = next_transition(b, &params.ball).map_or((f64::INFINITY, 0), |(tau, k)| {
        (b.t + tau, transition_code(k))
    });
    (if t.is_finite() { t } else { NEVER_F64 }, kind)
}

/// A table's status before its first dispatch: a table without balls, or one cut before
/// its first event, is done already.
fn start_status(n_balls: usize, limits: Limits) -> u32 {
    if limits.max_events == 0 {
        STATUS_CUT_EVENTS
    } else if n_balls == 0 {
        STATUS_DONE
    } else {
        STATUS_RUNNING
    }
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
fn table_outcome(layout: &SimLayout, sr: &[f64], su: &[u32]) -> Outcome {
    Outcome {
        n_events: su[layout.io_u_n + 1] as usize,
        t_end: from_never(sr[layout.io_r_clock]),
        cut: cut_of(su[layout.io_u_n + 2]),
    }
}

/// The cut of a table's status, if it was cut.
fn cut_of(status: u32) -> Option<Cut> {
    match status {
        STATUS_CUT_EVENTS => Some(Cut::MaxEvents),
        STATUS_CUT_TIME => Some(Cut::MaxTime),
        _ => None,
    }
}

/// Ball `i`'s final state, from a table's I/O block.
fn final_ball(sr: &[f64], su: &[u32], i: usize) -> Result<BallState, Error> {
    ball_state(&sr[10 * i..10 * i + 10], su[i])
}

/// A finished table's final states and outcome, from its I/O block, into its run.
pub(super) fn finish_table(
    layout: &SimLayout,
    run: &mut GpuRun,
    sr: &[f64],
    su: &[u32],
) -> Result<(), Error> {
    let n = (su[layout.io_u_n] as usize).min(layout.gpu_max_balls);
    run.balls.clear();
    for i in 0..n {
        run.balls.push(final_ball(sr, su, i)?);
    }
    run.outcome = table_outcome(layout, sr, su);
    Ok(())
}

/// A watched table's end from its watch block (the shader's `watch_end`): the watched
/// ball's final state, the outcome and the table's ball count.
pub(super) fn watched_end(
    layout: &SimLayout,
    sr: &[f64],
    su: &[u32],
) -> Result<(BallState, Outcome, usize), Error> {
    let (r, u) = (layout.watch_r_end, layout.watch_u_end);
    let cue = ball_state(&sr[r..r + 10], su[u])?;
    let outcome = Outcome {
        n_events: su[u + 2] as usize,
        t_end: from_never(sr[r + 10]),
        cut: cut_of(su[u + 3]),
    };
    Ok((cue, outcome, su[u + 1] as usize))
}

/// Reads a table's watch block.
pub(super) fn read_watch(
    layout: &SimLayout,
    sr: &[f64],
    su: &[u32],
    n_balls: usize,
    with_facts: bool,
) -> Result<Watch, Error> {
    let l = layout;
    let v3 = |at: usize| Vec3::new(sr[at], sr[at + 1], sr[at + 2]);
    let first = match su[l.watch_u_first] {
        0 => None,
        number => Some(WatchedContact {
            number: number as usize,
            event: Event {
                kind: event_kind(su[l.watch_u_first + 1])?,
                t: sr[0],
                ball: su[l.watch_u_first + 2],
                other: su[l.watch_u_first + 3],
            },
            cue_before: ball_state(
                &sr[l.watch_r_before..l.watch_r_before + 10],
                su[l.watch_u_first + 4],
            )?,
            t0: sr[1],
            cue_after: v3(l.watch_r_cue),
            other_after: v3(l.watch_r_other),
        }),
    };
    let n_pots = su[0] as usize;
    if n_pots > n_balls {
        return Err(gpu_error(format!("the GPU reported {n_pots} pots")));
    }
    let pots = (0..n_pots)
        .map(|k| {
            let at = l.watch_u_pots + k;
            (
                su[at] as usize,
                Event {
                    kind: EventKind::BallPocket,
                    t: sr[l.watch_r_pots + k],
                    ball: su[at + l.gpu_max_balls],
                    other: su[at + 2 * l.gpu_max_balls],
                },
            )
        })
        .collect::<Vec<_>>();
    let facts = with_facts.then(|| read_facts(l, sr, su, &pots));
    Ok(Watch { first, pots, facts })
}

/// The rules' facts of a watch block (the shader's `observe_facts`); the pockets from the
/// pots.
fn read_facts(l: &SimLayout, sr: &[f64], su: &[u32], pots: &[WatchedPot]) -> ShotFacts {
    let (r, u) = (l.watch_r_facts, l.watch_u_facts);
    let mut facts = ShotFacts {
        any_ball_ball: su[u] != 0,
        first_ball: (su[u + 1] != 0).then(|| (sr[r], su[u + 1] - 1)),
        cushion_after_first: su[u + 2] != 0,
        at_cushion: u64::from(su[u + 3]) | u64::from(su[u + 4]) << 32,
        second_ball_t: (su[u + 5] != 0).then_some(sr[r + 1]),
        cue_cushions: su[u + 6],
        last_cushion: match su[u + 7] {
            0 => (f64::NEG_INFINITY, 0),
            k => (sr[r + 2], k),
        },
        ..ShotFacts::default()
    };
    for (_, e) in pots {
        facts.observe(e, u32::MAX);
    }
    facts
}
