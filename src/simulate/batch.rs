//! Many tables at once: [`simulate_batch`] runs the event loop on every table of a batch
//! with Rayon over tables, and hands the results to a caller's sink chunk by chunk, in
//! table order.
//!
//! - **Deterministic**: each table is simulated on its own by the same code, so the
//!   results are bit for bit the same whatever the number of threads, and they come to
//!   the sink in table order.
//! - **Bounded memory**: tables are simulated [`BatchOptions::chunk_tables`] at a time;
//!   a chunk's results are handed to the sink and dropped before the next chunk starts,
//!   so memory depends on the chunk size, not on the batch size.
//! - **No allocation per event**: each worker reuses one [`EventLoop`] (and one input
//!   buffer) for all the tables it handles; events are appended to the chunk's flat list.
//!
//! ```
//! use kisstime::simulate::{BallState, BatchOptions, CueStrike, SimParams, Table, simulate_batch};
//!
//! let table = Table::nine_foot();
//! let p = SimParams::default();
//! let r = p.ball.r;
//! // 10 tables: the cue ball at (0.635, 0.6) shot straight at a ball on the foot spot
//! let strike = CueStrike { v0: 2.0, phi: 90.0, theta: 0.0, a: 0.0, b: 0.1 };
//! let input = |_k: usize, balls: &mut Vec<BallState>| {
//!     balls.clear();
//!     balls.push(BallState::at_rest(0.635, 0.6, r));
//!     balls.push(BallState::at_rest(0.635, 1.905, r));
//!     Ok(Some((0, strike)))
//! };
//! let mut first_kinds = Vec::new();
//! let stats = simulate_batch(&table, p, &BatchOptions::default(), 10, input, |chunk| {
//!     for run in chunk.iter() {
//!         first_kinds.push((run.events[0].event.kind.name(), run.events[1].event.kind.name()));
//!         assert_eq!(run.balls.len(), 2);
//!         assert!(run.outcome.cut.is_none());
//!     }
//!     Ok::<(), std::convert::Infallible>(())
//! })?;
//! assert_eq!(stats.tables, 10);
//! assert_eq!(first_kinds[0], ("stick_ball", "sliding_rolling"));
//! # Ok::<(), kisstime::simulate::BatchError<std::convert::Infallible>>(())
//! ```

use std::fmt;
use std::ops::Range;
use std::time::Instant;

use rayon::prelude::*;

use crate::error::SimError;
use crate::model::MotionState;
use crate::model::ball_state::BallState;
use crate::model::sim_params::{Physics, SimParams};
use crate::model::table::Table;
use crate::resolve::stick_ball::CueStrike;
use crate::simulate::check::check_layout;
use crate::simulate::event_loop::{EventLoop, Limits, MAX_BALLS};
use crate::simulate::events::{Event, EventKind, Outcome};
use crate::simulate::watch::{
    ShotFacts, TableWatch, WatchOptions, WatchedContact, WatchedPot, Watcher,
};

/// Tables per chunk by default: enough to keep every core busy (128 tasks of 8 tables),
/// few enough that a chunk of breaks (~200 events each, ~200 bytes an event kept) holds
/// some 40 MB.
pub const DEFAULT_CHUNK_TABLES: usize = 1024;

/// Tables one Rayon task simulates in a row (with one event loop), at least: a chunk is cut
/// into some 32 tasks a thread, each of 8 to 64 tables ([`tables_per_task`]).
const TABLES_PER_TASK: usize = 8;

/// Tables per Rayon task for chunks of `per_chunk` tables: some 32 tasks a thread (enough
/// to balance uneven tables), each of [`TABLES_PER_TASK`] to 64 tables (fewer, larger
/// tasks cost less to gather).
fn tables_per_task(per_chunk: usize) -> usize {
    (per_chunk / (32 * rayon::current_num_threads())).clamp(TABLES_PER_TASK, 64)
}

/// How [`simulate_batch`] runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BatchOptions {
    /// The per-table event and simulated-time caps.
    pub limits: Limits,
    /// Keep every event with the states of its balls ([`TableRun::events`]); `false`
    /// keeps only the final states and outcomes (faster, less memory).
    pub record_events: bool,
    /// Tables per chunk handed to the sink (at least 1; see the module docs).
    pub chunk_tables: usize,
    /// Run [`check_layout`] on every table before simulating it.
    pub check_layout: bool,
    /// Watch one ball of every table ([`crate::simulate::watch`]: a study's view of the
    /// events): each [`TableRun`] then has its [`TableRun::watch`], its
    /// [`TableRun::balls`] hold the watched ball's final state alone, and no event is
    /// recorded (whatever `record_events` says).
    pub watch: Option<WatchOptions>,
    /// A hint that every table's balls are the same (one position struck many ways: a
    /// study's). The results do not depend on it; on the GPU a chunk whose tables all
    /// strike the same ball of the same position at rest then crosses the bus as the
    /// position once and each table's strike ([`crate::gpu::CheckedTables::one_position`]).
    pub one_position: bool,
    /// A study's noisy strikes, described for the device to draw them itself
    /// ([`DrawnStrikes`]): with [`BatchOptions::one_position`], shared physics and no
    /// events recorded, a GPU chunk then crosses the bus as the position and one header,
    /// and each table's strike is drawn and played on the device. `input` must give what
    /// it describes (the engine compares the first and last table of every chunk with it
    /// and packs a chunk that differs from `input` as usual), and every strike it draws
    /// must be one the simulator takes (the study sets it only then). The results do not
    /// depend on it; the CPU ignores it.
    pub drawn: Option<DrawnStrikes>,
}

/// A study's noisy strikes as a rule instead of a list ([`BatchOptions::drawn`]): table
/// `k`'s strike is `draw(self, r, first + k)` on balls of radius `r`, the intended strike
/// `shot` plus the five σ times normals drawn from Philox keyed by `seed` at counter
/// `first + k` (the study's `noisy_strike_of`; its twin in `shaders/study/noise.wgsl` is
/// what the device runs).
#[derive(Clone, Copy, Debug)]
pub struct DrawnStrikes {
    /// The intended strike.
    pub shot: CueStrike,
    /// The noise's σ, in the order V0 (m/s), φ, θ (degrees), a, b (metres).
    pub sigma: [f64; 5],
    /// The study's seed.
    pub seed: u64,
    /// Table 0's sample id.
    pub first: u64,
    /// The host's twin of the device's draw: `draw(self, r, i)` is sample `i`'s strike.
    pub draw: fn(&DrawnStrikes, f64, u64) -> CueStrike,
}

impl DrawnStrikes {
    /// Table `k`'s strike on balls of radius `r`.
    pub fn strike(&self, r: f64, k: usize) -> CueStrike {
        (self.draw)(self, r, self.first + k as u64)
    }

    /// The same draws from table `k` on: table 0 of the result is table `k` of these.
    pub fn from(&self, k: usize) -> DrawnStrikes {
        DrawnStrikes {
            first: self.first + k as u64,
            ..*self
        }
    }
}

impl PartialEq for DrawnStrikes {
    fn eq(&self, other: &Self) -> bool {
        (self.shot, self.sigma, self.seed, self.first)
            == (other.shot, other.sigma, other.seed, other.first)
            && std::ptr::fn_addr_eq(self.draw, other.draw)
    }
}

impl Default for BatchOptions {
    fn default() -> Self {
        BatchOptions {
            limits: Limits::default(),
            record_events: true,
            chunk_tables: DEFAULT_CHUNK_TABLES,
            check_layout: true,
            watch: None,
            one_position: false,
            drawn: None,
        }
    }
}

/// One event and the states, right after it, of the balls it involved: `states[0]` is
/// ball `event.ball`'s; for a ball–ball event `states[1]` is ball `event.other`'s (for
/// every other kind it repeats `states[0]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EventRecord {
    /// The event.
    pub event: Event,
    /// The involved balls' states after it.
    pub states: [BallState; 2],
}

impl EventRecord {
    /// The record of `event` given every ball's state right after it.
    pub fn new(event: Event, balls: &[BallState]) -> EventRecord {
        let first = balls[event.ball as usize];
        let second = if event.kind == EventKind::BallBall {
            balls[event.other as usize]
        } else {
            first
        };
        EventRecord {
            event,
            states: [first, second],
        }
    }

    /// The involved balls, as (index in the table, state after the event): one, or two for
    /// a ball–ball event (in the event's agent order).
    pub fn balls(&self) -> impl Iterator<Item = (usize, &BallState)> {
        let two = self.event.kind == EventKind::BallBall;
        let ids = [self.event.ball, self.event.other];
        ids.into_iter()
            .zip(&self.states)
            .take(if two { 2 } else { 1 })
            .map(|(i, s)| (i as usize, s))
    }
}

/// One table's results, borrowed from its [`Chunk`].
#[derive(Clone, Copy, Debug)]
pub struct TableRun<'a> {
    /// The table's position in the batch (0-based).
    pub table: usize,
    /// Its events in order (empty unless [`BatchOptions::record_events`]).
    pub events: &'a [EventRecord],
    /// Every ball's state at the end, in the input's ball order; with
    /// [`BatchOptions::watch`], the watched ball's alone.
    pub balls: &'a [BallState],
    /// How the simulation ended (events, end time, cut or not).
    pub outcome: Outcome,
    /// What the watch saw, with [`BatchOptions::watch`].
    pub watch: Option<TableWatch<'a>>,
}

/// The results of consecutive tables, flat: what the sink of [`simulate_batch`] receives.
#[derive(Clone, Debug, Default)]
pub struct Chunk {
    first: usize,
    events: Vec<EventRecord>,
    event_start: Vec<usize>,
    balls: Vec<BallState>,
    ball_start: Vec<usize>,
    outcomes: Vec<Outcome>,
    /// Whether its tables were watched ([`BatchOptions::watch`]): then one first contact
    /// per table, and the pots flat.
    watched: bool,
    firsts: Vec<Option<WatchedContact>>,
    facts: Vec<Option<ShotFacts>>,
    pots: Vec<WatchedPot>,
    pot_start: Vec<usize>,
}

impl Chunk {
    /// A chunk of no tables whose first table will be `first`.
    pub(crate) fn empty(first: usize) -> Chunk {
        Chunk {
            first,
            event_start: vec![0],
            ball_start: vec![0],
            pot_start: vec![0],
            ..Chunk::default()
        }
    }

    /// A chunk of no watched tables whose first table will be `first`.
    pub(crate) fn empty_watched(first: usize) -> Chunk {
        Chunk {
            watched: true,
            ..Chunk::empty(first)
        }
    }

    /// The tables it holds (positions in the batch).
    pub fn tables(&self) -> Range<usize> {
        self.first..self.first + self.outcomes.len()
    }

    /// The number of tables.
    pub fn len(&self) -> usize {
        self.outcomes.len()
    }

    /// Whether it holds no table.
    pub fn is_empty(&self) -> bool {
        self.outcomes.is_empty()
    }

    /// Events simulated over its tables (whether recorded or not).
    pub fn n_events(&self) -> usize {
        self.outcomes.iter().map(|o| o.n_events).sum()
    }

    /// Table `i` of the chunk (0-based within the chunk; `None` past the end).
    pub fn get(&self, i: usize) -> Option<TableRun<'_>> {
        let outcome = *self.outcomes.get(i)?;
        Some(TableRun {
            table: self.first + i,
            events: &self.events[self.event_start[i]..self.event_start[i + 1]],
            balls: &self.balls[self.ball_start[i]..self.ball_start[i + 1]],
            outcome,
            watch: self.watched.then(|| TableWatch {
                first: self.firsts[i],
                pots: &self.pots[self.pot_start[i]..self.pot_start[i + 1]],
                facts: self.facts[i].as_ref(),
            }),
        })
    }

    /// Its tables in order.
    pub fn iter(&self) -> impl Iterator<Item = TableRun<'_>> {
        (0..self.len()).filter_map(|i| self.get(i))
    }

    /// Appends the next table's results (a backend that does not simulate into chunks).
    pub(crate) fn push(&mut self, events: &[EventRecord], balls: &[BallState], outcome: Outcome) {
        self.events.extend_from_slice(events);
        self.balls.extend_from_slice(balls);
        self.outcomes.push(outcome);
        self.end_table();
    }

    /// Appends the next watched table's results: the watched ball's final state, the
    /// outcome and the watch (a chunk made by [`Chunk::empty_watched`]).
    pub(crate) fn push_watched(&mut self, cue: BallState, outcome: Outcome, watch: TableWatch) {
        self.balls.push(cue);
        self.outcomes.push(outcome);
        self.firsts.push(watch.first);
        self.facts.push(watch.facts.copied());
        self.pots.extend_from_slice(watch.pots);
        self.end_table();
    }

    /// The same tables numbered from `first` (a chunk simulated on its own).
    pub(crate) fn renumbered(&self, first: usize) -> Chunk {
        Chunk {
            first,
            ..self.clone()
        }
    }

    /// Closes the table just appended (its events, balls and pots end here).
    fn end_table(&mut self) {
        self.event_start.push(self.events.len());
        self.ball_start.push(self.balls.len());
        self.pot_start.push(self.pots.len());
    }

    /// Makes this chunk the consecutive `parts` (each holding the tables right after the
    /// one before), the first of them table `first`: emptied (its memory kept) and grown
    /// once to its final size.
    fn refill(&mut self, first: usize, watched: bool, parts: Vec<Chunk>) {
        self.first = first;
        self.watched = watched;
        self.events.clear();
        self.balls.clear();
        self.outcomes.clear();
        self.firsts.clear();
        self.facts.clear();
        self.pots.clear();
        for v in [
            &mut self.event_start,
            &mut self.ball_start,
            &mut self.pot_start,
        ] {
            v.clear();
            v.push(0);
        }
        let total = |f: fn(&Chunk) -> usize| parts.iter().map(f).sum::<usize>();
        self.events.reserve(total(|c| c.events.len()));
        self.balls.reserve(total(|c| c.balls.len()));
        self.pots.reserve(total(|c| c.pots.len()));
        let n = total(|c| c.outcomes.len());
        self.outcomes.reserve(n);
        self.firsts.reserve(total(|c| c.firsts.len()));
        self.facts.reserve(total(|c| c.facts.len()));
        for v in [
            &mut self.event_start,
            &mut self.ball_start,
            &mut self.pot_start,
        ] {
            v.reserve(n);
        }
        for part in parts {
            self.append(part);
        }
    }

    /// Appends `other`, which holds the tables right after this chunk's.
    fn append(&mut self, other: Chunk) {
        let (e0, b0, p0) = (self.events.len(), self.balls.len(), self.pots.len());
        self.events.extend(other.events);
        self.balls.extend(other.balls);
        self.outcomes.extend(other.outcomes);
        self.firsts.extend(other.firsts);
        self.facts.extend(other.facts);
        self.pots.extend(other.pots);
        self.event_start
            .extend(other.event_start[1..].iter().map(|s| s + e0));
        self.ball_start
            .extend(other.ball_start[1..].iter().map(|s| s + b0));
        self.pot_start
            .extend(other.pot_start[1..].iter().map(|s| s + p0));
    }
}

/// Totals of a batch run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BatchStats {
    /// Tables simulated.
    pub tables: usize,
    /// Events in all.
    pub events: usize,
    /// Tables cut by a limit.
    pub cut: usize,
    /// Wall-clock seconds spent simulating (the sink's time excluded).
    pub sim_seconds: f64,
}

/// Why [`simulate_batch`] stopped.
#[derive(Debug)]
pub enum BatchError<E> {
    /// A table could not be simulated: its position in the batch and the error (a ball's
    /// index in [`SimError::Ball`] is its index in the table's input). Of several bad
    /// tables the first in table order is reported.
    Table {
        /// The table's position in the batch.
        table: usize,
        /// What is wrong.
        error: SimError,
    },
    /// The sink failed.
    Sink(E),
}

impl<E: fmt::Display> fmt::Display for BatchError<E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BatchError::Table { table, error } => write!(f, "table #{table}: {error}"),
            BatchError::Sink(e) => write!(f, "{e}"),
        }
    }
}

impl<E: fmt::Debug + fmt::Display> std::error::Error for BatchError<E> {}

/// Simulates `n_tables` tables on `table` from the strike to rest (or to a limit), with
/// Rayon over tables, handing the results to `sink` one [`Chunk`] at a time in table
/// order (see the module docs).
///
/// `input(k, balls)` fills `balls` (cleared by the callee) with table `k`'s balls (in the
/// order that decides exact ties, pooltool's ball order) and returns its cue strike
/// (ball index and strike, applied at t = 0) if any; it is called from worker threads.
/// Each table is checked ([`check_layout`], if asked, and [`EventLoop::reset`]: at most
/// [`MAX_BALLS`] balls, finite numbers, a valid strike on an existing ball); the first bad
/// table stops the run with [`BatchError::Table`] before its chunk reaches the sink.
pub fn simulate_batch<'p, E>(
    table: &Table,
    physics: impl Into<Physics<'p>>,
    options: &BatchOptions,
    n_tables: usize,
    input: impl Fn(usize, &mut Vec<BallState>) -> Result<Option<(usize, CueStrike)>, SimError> + Sync,
    mut sink: impl FnMut(&Chunk) -> Result<(), E>,
) -> Result<BatchStats, BatchError<E>> {
    let physics = physics.into();
    // the parameters, checked once (every table's, with per-table physics)
    physics
        .check(n_tables)
        .map_err(|(table, error)| BatchError::Table { table, error })?;
    let params = physics.first();
    EventLoop::new(table, params, options.limits, 0)
        .map_err(|error| BatchError::Table { table: 0, error })?;
    let per_chunk = options.chunk_tables.max(1);
    let mut stats = BatchStats::default();
    // one chunk, refilled: its memory is reused from chunk to chunk
    let mut chunk = Chunk::empty(0);
    let per_task = tables_per_task(per_chunk);
    let mut first = 0;
    while first < n_tables {
        let end = n_tables.min(first.saturating_add(per_chunk));
        let started = Instant::now();
        let tasks: Vec<Range<usize>> = (first..end)
            .step_by(per_task)
            .map(|s| s..end.min(s + per_task))
            .collect();
        let parts: Vec<Result<Chunk, (usize, SimError)>> = tasks
            .into_par_iter()
            .map_init(
                // cannot fail: the parameters were checked above and 16 ≤ MAX_BALLS
                || {
                    (
                        EventLoop::new(table, params, options.limits, 16).ok(),
                        Vec::new(),
                    )
                },
                |(lp, buf), tables| match lp {
                    Some(lp) => run_tables(lp, buf, table, physics, options, &input, tables),
                    None => Err((tables.start, SimError::Table("no event loop".to_owned()))),
                },
            )
            .collect();
        let parts: Vec<Chunk> = parts
            .into_iter()
            .collect::<Result<_, _>>()
            .map_err(|(table, error)| BatchError::Table { table, error })?;
        chunk.refill(first, options.watch.is_some(), parts);
        stats.sim_seconds += started.elapsed().as_secs_f64();
        stats.tables += chunk.len();
        stats.events += chunk.n_events();
        stats.cut += chunk.outcomes.iter().filter(|o| o.cut.is_some()).count();
        sink(&chunk).map_err(BatchError::Sink)?;
        first = end;
    }
    Ok(stats)
}

/// Simulates the tables `tables` with one loop, into a chunk; the first bad table's
/// position and error otherwise.
fn run_tables(
    lp: &mut EventLoop,
    buf: &mut Vec<BallState>,
    table: &Table,
    physics: Physics<'_>,
    options: &BatchOptions,
    input: &(impl Fn(usize, &mut Vec<BallState>) -> Result<Option<(usize, CueStrike)>, SimError> + Sync),
    tables: Range<usize>,
) -> Result<Chunk, (usize, SimError)> {
    let mut out = Chunk::empty(tables.start);
    out.watched = options.watch.is_some();
    // room for the tables (their balls, at a guess), so that the chunk seldom grows
    let n = tables.len();
    out.outcomes.reserve(n);
    out.ball_start.reserve(n);
    out.event_start.reserve(n);
    out.pot_start.reserve(n);
    if out.watched {
        out.balls.reserve(n);
        out.firsts.reserve(n);
        out.facts.reserve(n);
    } else {
        out.balls.reserve(n * 16);
    }
    let mut watcher = options.watch.map(Watcher::new);
    for k in tables {
        let fail = |e| (k, e);
        let strike = input(k, buf).map_err(fail)?;
        if !physics.is_shared() {
            lp.set_params(physics.of(k)).map_err(fail)?;
        }
        let radius = lp.params().ball.r;
        check_table(lp, table, radius, options, buf, strike).map_err(fail)?;
        let Some(watcher) = watcher.as_mut() else {
            while let Some(ev) = lp.step() {
                if options.record_events {
                    out.events.push(EventRecord::new(ev, lp.balls()));
                }
            }
            out.balls.extend_from_slice(lp.balls());
            out.outcomes.push(lp.outcome());
            out.end_table();
            continue;
        };
        watcher.start();
        loop {
            watcher.before(lp.balls(), lp.time());
            let Some(ev) = lp.step() else { break };
            let number = lp.outcome().n_events;
            if watcher.watch_event(number, &ev, lp.balls(), &mut out.pots) {
                break;
            }
        }
        let cue = options.watch.map_or(0, |w| w.cue);
        out.balls.push(lp.balls()[cue]);
        out.outcomes.push(lp.outcome());
        out.firsts.push(watcher.first());
        out.facts.push(watcher.facts().copied());
        out.end_table();
    }
    Ok(out)
}

/// Checks one table's input as every backend checks it before simulating it, and leaves
/// `lp` reset to it: [`check_input`]'s checks, then [`EventLoop::reset`]'s.
pub(crate) fn check_table(
    lp: &mut EventLoop,
    table: &Table,
    radius: f64,
    options: &BatchOptions,
    balls: &[BallState],
    strike: Option<(usize, CueStrike)>,
) -> Result<(), SimError> {
    check_input(table, radius, options, balls, strike)?;
    lp.reset(balls, strike)
}

/// Checks one table's input as every backend checks it before simulating it: at most
/// [`MAX_BALLS`] balls, the watched ball on the table (with [`BatchOptions::watch`]),
/// [`check_layout`] (when `options.check_layout`), a strike on a ball that is on the table,
/// and [`EventLoop::check_input`] (finite numbers, a valid strike): what
/// [`EventLoop::reset`] would refuse, and more.
pub(crate) fn check_input(
    table: &Table,
    radius: f64,
    options: &BatchOptions,
    balls: &[BallState],
    strike: Option<(usize, CueStrike)>,
) -> Result<(), SimError> {
    if balls.len() > MAX_BALLS {
        return Err(SimError::Ball {
            index: MAX_BALLS,
            reason: format!(
                "the table has {} balls; the simulator takes at most {MAX_BALLS}",
                balls.len()
            ),
        });
    }
    if let Some(w) = options.watch
        && w.cue >= balls.len()
    {
        return Err(SimError::Table(format!(
            "the watched ball {} is not on the table: it has {} balls",
            w.cue,
            balls.len()
        )));
    }
    if options.check_layout {
        check_layout(table, radius, balls)?;
    }
    if let Some((cue, _)) = strike
        && balls.get(cue).is_some_and(|b| b.s == MotionState::Pocketed)
    {
        return Err(SimError::Ball {
            index: cue,
            reason: "the strike's ball is pocketed".to_owned(),
        });
    }
    EventLoop::check_input(balls, strike)
}

/// Checks every table of a batch as [`simulate_batch`] (and every backend of
/// [`crate::engine::ShotEngine::simulate_with`]) checks it before simulating it, without
/// simulating: one verdict per table, in table order, `Ok` or what is wrong (the
/// parameters of a table with per-table physics, [`check_layout`] when
/// `options.check_layout`, the strike, [`EventLoop::reset`]'s checks). Rayon over tables.
///
/// For callers that report bad tables instead of stopping at the first: simulate the good
/// ones afterwards through an index map (their input is then known to pass). The error is
/// that of the whole batch: shared parameters that are invalid, or a table (cushions,
/// pockets) the event loop refuses.
pub fn check_tables<'p>(
    table: &Table,
    physics: impl Into<Physics<'p>>,
    options: &BatchOptions,
    n_tables: usize,
    input: impl Fn(usize, &mut Vec<BallState>) -> Result<Option<(usize, CueStrike)>, SimError> + Sync,
) -> Result<Vec<Result<(), SimError>>, SimError> {
    let physics = physics.into();
    if let Physics::PerTable(all) = physics
        && all.len() < n_tables
    {
        return Err(SimError::Table(format!(
            "no physics for table {}: {} parameter sets for {n_tables} tables",
            all.len(),
            all.len()
        )));
    }
    // the shared parameters and the table, once
    let first = if physics.is_shared() {
        physics.first()
    } else {
        SimParams::default()
    };
    EventLoop::new(table, first, options.limits, 0)?;
    Ok((0..n_tables)
        .into_par_iter()
        .map_init(
            || (EventLoop::new(table, first, options.limits, 16), Vec::new()),
            |(lp, buf), k| {
                // cannot fail: the parameters were checked above and 16 <= MAX_BALLS
                let lp = lp
                    .as_mut()
                    .map_err(|_| SimError::Table("no event loop".to_owned()))?;
                let strike = input(k, buf)?;
                lp.set_params(physics.of(k))?;
                let radius = lp.params().ball.r;
                check_table(lp, table, radius, options, buf, strike)
            },
        )
        .collect())
}

/// The index of the pocket a pocketed ball sits in (its centre is the pocket's, as the
/// pocket resolution leaves it), if any.
pub fn pocket_of(table: &Table, b: &BallState) -> Option<usize> {
    if b.s != MotionState::Pocketed {
        return None;
    }
    table
        .pockets
        .iter()
        .position(|p| p.center.x == b.r.x && p.center.y == b.r.y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::batch::Batch;
    use crate::model::Ball;
    use crate::model::sim_params::SimParams;
    use crate::simulate::events::Cut;

    fn rack_batch(n: usize) -> (Batch, Vec<Option<(usize, CueStrike)>>) {
        let mut batch = Batch::new();
        let mut strikes = Vec::new();
        for k in 0..n {
            let mut balls = vec![(0, Ball::at_rest(0.635, 0.6))];
            for i in 0..5 {
                let x = 0.4 + 0.1 * i as f64;
                balls.push((i + 1, Ball::at_rest(x, 1.9 + 0.01 * (k % 7) as f64)));
            }
            batch.push_table(k as i64, balls).unwrap();
            let phi = 80.0 + (k % 20) as f64;
            strikes.push(Some((
                0,
                CueStrike {
                    v0: 1.0 + 0.3 * (k % 9) as f64,
                    phi,
                    theta: 0.0,
                    a: 0.1,
                    b: -0.2,
                },
            )));
        }
        (batch, strikes)
    }

    fn run(
        batch: &Batch,
        strikes: &[Option<(usize, CueStrike)>],
        options: &BatchOptions,
    ) -> (Vec<EventRecord>, Vec<BallState>, Vec<Outcome>, usize) {
        let p = SimParams::default();
        let (mut ev, mut balls, mut outs, mut chunks) = (Vec::new(), Vec::new(), Vec::new(), 0);
        let input = batch.sim_input(strikes, p.ball.r);
        simulate_batch(
            &Table::nine_foot(),
            p,
            options,
            batch.num_tables(),
            input,
            |c: &Chunk| {
                chunks += 1;
                for (next, t) in (c.tables().start..).zip(c.iter()) {
                    assert_eq!(t.table, next);
                    ev.extend_from_slice(t.events);
                    balls.extend_from_slice(t.balls);
                    outs.push(t.outcome);
                }
                Ok::<(), ()>(())
            },
        )
        .unwrap();
        (ev, balls, outs, chunks)
    }

    #[test]
    fn chunking_and_threads_do_not_change_results() {
        let (batch, strikes) = rack_batch(45);
        let big = BatchOptions::default();
        let one = BatchOptions {
            chunk_tables: 1,
            ..big
        };
        let a = run(&batch, &strikes, &big);
        let b = run(&batch, &strikes, &one);
        assert_eq!((a.3, b.3), (1, 45));
        assert_eq!(a.0, b.0);
        assert_eq!(a.1, b.1);
        assert_eq!(a.2, b.2);
        let single = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let c = single.install(|| run(&batch, &strikes, &big));
        assert_eq!(a.0, c.0);
        assert_eq!(a.1, c.1);
        // the same as the one-table entry point
        let p = SimParams::default();
        let balls: Vec<BallState> = batch
            .balls(3)
            .iter()
            .map(|b| BallState::from_ball(b, p.ball.r))
            .collect();
        let mut events = Vec::new();
        let t = Table::nine_foot();
        let out =
            crate::simulate::simulate(&t, p, Limits::default(), &balls, strikes[3], |e, b| {
                events.push(EventRecord::new(*e, b))
            })
            .unwrap();
        let before: usize = a.2[..3].iter().map(|o| o.n_events).sum();
        assert_eq!(&a.0[before..before + out.n_events], &events[..]);
        // final states only
        let fin = BatchOptions {
            record_events: false,
            ..big
        };
        let d = run(&batch, &strikes, &fin);
        assert!(d.0.is_empty());
        assert_eq!(a.1, d.1);
        assert_eq!(a.2, d.2);
    }

    /// Every table's runs with and without the watch: (events, watch, watched final
    /// state, outcome) of each.
    type Watched = Vec<(Vec<EventRecord>, crate::simulate::Watch, BallState, Outcome)>;

    fn watched(stop: bool) -> (Watched, Vec<Outcome>) {
        let (batch, strikes) = rack_batch(40);
        let (events, balls, outcomes, _) = run(&batch, &strikes, &BatchOptions::default());
        let n_balls = 6;
        let options = BatchOptions {
            watch: Some(WatchOptions {
                cue: 0,
                stop_at_first_contact: stop,
                facts: false,
            }),
            chunk_tables: 7,
            ..BatchOptions::default()
        };
        let p = SimParams::default();
        let mut seen = Vec::new();
        let input = batch.sim_input(&strikes, p.ball.r);
        simulate_batch(&Table::nine_foot(), p, &options, 40, input, |c: &Chunk| {
            for t in c.iter() {
                assert!(t.events.is_empty(), "a watch records no event");
                assert_eq!(t.balls.len(), 1, "the watched ball alone");
                let w = t.watch.expect("watched");
                let watch = crate::simulate::Watch {
                    first: w.first,
                    pots: w.pots.to_vec(),
                    facts: w.facts.copied(),
                };
                seen.push((watch, t.balls[0], t.outcome));
            }
            Ok::<(), ()>(())
        })
        .unwrap();
        let mut out = Vec::new();
        let mut at = 0;
        for (k, (watch, cue, outcome)) in seen.into_iter().enumerate() {
            let n = outcomes[k].n_events;
            out.push((events[at..at + n].to_vec(), watch, cue, outcome));
            if !stop {
                assert_eq!(
                    cue,
                    balls[k * n_balls],
                    "table {k}: the cue ball's final state"
                );
            }
            at += n;
        }
        (out, outcomes)
    }

    #[test]
    fn the_watch_keeps_the_cue_balls_first_contact_and_every_pot() {
        let (runs, outcomes) = watched(false);
        let mut contacts = 0;
        for (k, (events, watch, _, outcome)) in runs.iter().enumerate() {
            assert_eq!(*outcome, outcomes[k], "table {k}: the same run");
            // the pots: every ball_pocket event, numbered from the strike (1)
            let pots: Vec<(usize, Event)> = (1..)
                .zip(events)
                .filter(|(_, r)| r.event.kind == EventKind::BallPocket)
                .map(|(n, r)| (n, r.event))
                .collect();
            assert_eq!(watch.pots, pots, "table {k}");
            // the first contact: the first event that involves the cue ball, other than
            // the strike and its sliding → rolling
            let first = (1..).zip(events).find(|(_, r)| {
                let e = r.event;
                (e.ball == 0 || (e.kind == EventKind::BallBall && e.other == 0))
                    && !matches!(e.kind, EventKind::StickBall | EventKind::SlidingRolling)
            });
            match (first, watch.first) {
                (None, None) => {}
                (Some((n, r)), Some(f)) => {
                    contacts += 1;
                    assert_eq!((f.number, f.event), (n, r.event), "table {k}");
                    let cue_after = r.balls().find(|(i, _)| *i == 0).unwrap().1.r;
                    assert_eq!(f.cue_after, cue_after, "table {k}");
                    // the cue ball's last recorded state before the contact, evolved to
                    // the contact, is where the watch's state before it goes
                    let (t_last, last) = events[..n - 1]
                        .iter()
                        .rev()
                        .find_map(|r| {
                            r.balls()
                                .find(|(i, _)| *i == 0)
                                .map(|(_, s)| (r.event.t, *s))
                        })
                        .unwrap();
                    assert!(f.t0 >= t_last && f.t0 <= f.event.t, "table {k}");
                    let ball = SimParams::default().ball;
                    let dt = f.event.t;
                    let a = crate::motion::evolve::evolve(&last, dt - t_last, &ball).r;
                    let b = crate::motion::evolve::evolve(&f.cue_before, dt - f.t0, &ball).r;
                    assert!((a.x - b.x).abs() + (a.y - b.y).abs() < 1e-9, "table {k}");
                }
                other => panic!("table {k}: {other:?}"),
            }
        }
        assert!(contacts > 30, "{contacts} first contacts");
        assert!(runs.iter().any(|r| !r.1.pots.is_empty()), "no pot at all");
    }

    #[test]
    fn a_watch_that_stops_at_the_first_contact_ends_the_table_there() {
        let (full, _) = watched(false);
        let (stopped, _) = watched(true);
        for (k, (a, b)) in full.iter().zip(&stopped).enumerate() {
            assert_eq!(a.1.first, b.1.first, "table {k}");
            match b.1.first {
                Some(f) => {
                    assert_eq!(b.3.n_events, f.number, "table {k}");
                    assert_eq!(b.3.t_end, f.event.t, "table {k}");
                    assert_eq!(b.2.r, f.cue_after, "table {k}");
                    assert!(b.1.pots.iter().all(|(n, _)| *n <= f.number), "table {k}");
                }
                None => assert_eq!(a.3, b.3, "table {k}"),
            }
        }
    }

    #[test]
    fn check_tables_flags_each_bad_table_as_simulate_batch_would() {
        let mut bad = Batch::new();
        for k in 0..6 {
            // table 2: a ball off the table; table 4: two balls overlapping
            let (x, y) = match k {
                2 => (3.0, 1.0),
                4 => (0.61, 0.6),
                _ => (0.5, 1.0),
            };
            bad.push_table(k, [(0, Ball::at_rest(0.6, 0.6)), (1, Ball::at_rest(x, y))])
                .unwrap();
        }
        let strike = CueStrike {
            v0: 1.0,
            phi: 90.0,
            theta: 0.0,
            a: 0.0,
            b: 0.0,
        };
        let mut strikes = vec![Some((0, strike)); 6];
        strikes[5] = Some((
            0,
            CueStrike {
                a: 0.9,
                b: 0.9,
                ..strike
            },
        ));
        let p = SimParams::default();
        let t = Table::nine_foot();
        let options = BatchOptions::default();
        let verdicts = check_tables(&t, p, &options, 6, bad.sim_input(&strikes, p.ball.r)).unwrap();
        let bad_ones: Vec<usize> = (0..6).filter(|&k| verdicts[k].is_err()).collect();
        assert_eq!(bad_ones, [2, 4, 5]);
        // the same errors simulate_batch stops at, table by table
        for k in bad_ones {
            let one = |j: usize, balls: &mut Vec<BallState>| {
                bad.sim_input(&strikes, p.ball.r)(k + j, balls)
            };
            let err = simulate_batch(&t, p, &options, 1, one, |_| Ok::<(), ()>(())).unwrap_err();
            match err {
                BatchError::Table { table: 0, error } => {
                    let flagged = verdicts[k].as_ref().unwrap_err().to_string();
                    assert_eq!(flagged, error.to_string(), "table {k}")
                }
                other => panic!("{other:?}"),
            }
        }
        // per-table physics: a bad set flags its table only
        let mut per = vec![p; 6];
        per[1].ball.u_s = -1.0;
        let verdicts =
            check_tables(&t, &per, &options, 6, bad.sim_input(&strikes, p.ball.r)).unwrap();
        assert!(verdicts[1].is_err() && verdicts[0].is_ok() && verdicts[3].is_ok());
        assert!(check_tables(&t, &per[..2], &options, 6, bad.sim_input(&strikes, 0.03)).is_err());
    }

    #[test]
    fn a_table_cut_by_the_event_cap_is_reported_and_bad_tables_are_named() {
        let (batch, strikes) = rack_batch(5);
        let options = BatchOptions {
            limits: Limits {
                max_events: 3,
                ..Limits::default()
            },
            ..BatchOptions::default()
        };
        let (ev, _, outs, _) = run(&batch, &strikes, &options);
        assert_eq!(ev.len(), 15);
        assert!(outs.iter().all(|o| o.cut == Some(Cut::MaxEvents)));
        // a ball off the table in table 2
        let mut bad = Batch::new();
        for k in 0..4 {
            let x = if k == 2 { 3.0 } else { 0.5 };
            bad.push_table(
                k,
                [(0, Ball::at_rest(0.6, 0.6)), (1, Ball::at_rest(x, 1.0))],
            )
            .unwrap();
        }
        let p = SimParams::default();
        let err = simulate_batch(
            &Table::nine_foot(),
            p,
            &BatchOptions::default(),
            4,
            bad.sim_input(&[], p.ball.r),
            |_| Ok::<(), ()>(()),
        )
        .unwrap_err();
        match err {
            BatchError::Table {
                table: 2,
                error: SimError::Ball { index: 1, reason },
            } => assert!(reason.contains("off the table"), "{reason}"),
            other => panic!("{other:?}"),
        }
    }
}
