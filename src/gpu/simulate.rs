//! The host of the GPU event loop (`shaders/simulate/event_loop.wgsl`, the WGSL twin of
//! [`crate::simulate::EventLoop`]): whole shots for many tables at once, one workgroup per
//! table.
//!
//! The host checks each table as [`EventLoop::reset`] does, resolves the strike (the stick
//! event, which has no shader twin) with `cue_strike` under the CPU's rule (at t = 0, if
//! every ball is at rest and V0 > 0), and writes each table's I/O block (balls, transitions,
//! counts: `sim_layout`) straight into the upload's staging memory, Rayon over tables. The
//! device starts the caches itself and keeps every table's state between dispatches; it
//! dispatches up to `events_per_dispatch` events per table at a time, reading back a 4-byte
//! "tables still running" count after each (and the recorded events only where the caller
//! asked for them), until every table is done; then only the I/O blocks (and, for a study,
//! the watch blocks) come back, unpacked Rayon over tables.
//!
//! The buffers and their bind group are made once and reused across chunks and calls while
//! they are large enough. A batch is cut into chunks of whole tables that fit the device's
//! largest binding, a large one into a few chunks ([`PIPELINE_CHUNKS`] of at least
//! [`PIPELINE_MIN_TABLES`]): while the device runs a chunk, a host thread unpacks the chunk
//! before it and packs the chunk after it (Rayon over tables, touching no device queue), so
//! that only the first chunk's packing and the last one's unpacking are not hidden behind
//! the device's work. A call runs on the pipeline built for the smallest ball-count bucket
//! that holds its largest table ([`SimLayout::bucket`]; up to [`GPU_MAX_BALLS`] balls);
//! each bucket's pipeline is built when first needed. There is no fall back to the CPU
//! here (the caller chooses: [`crate::engine::ShotEngine`] does).

use std::time::Instant;

use rayon::prelude::*;

use super::GpuTimings;
use super::device::{
    self, AdapterSummary, PassTimer, Scopes, copy_to_mapped, gpu_error, map_and_wait,
};
use super::shader::{simulate_source, workgroup_bytes};
use super::sim_layout::{
    DRAWN_REALS, DRAWN_UINTS, EVENT_REALS, EVENT_UINTS, GPU_MAX_BALLS, GpuRun, GpuShot, MAX_LAYOUT,
    NEVER_F32, NEVER_F64, SIM_R_MAX_TIME, SIM_REALS, STRUCK_REALS, STRUCK_UINTS, SimLayout,
    WatchedRun, drawn_block, event_record, finish_table, read_watch, start_table, strike_block,
    watched_end,
};
use crate::error::{Error, InputError, SimError};
use crate::model::ball_state::BallState;
use crate::model::sim_params::{Physics, SimParams};
use crate::model::table::Table;
use crate::model::{MotionState, Precision};
use crate::resolve::stick_ball::CueStrike;
use crate::simulate::batch::EventRecord;
use crate::simulate::check::check_layout;
use crate::simulate::events::Outcome;
use crate::simulate::watch::WatchOptions;
use crate::simulate::{DrawnStrikes, EventLoop, Limits};

mod buffers;
use buffers::LoopBuffers;

/// Events per table and dispatch, by default. Short dispatches keep a device responsive;
/// on lavapipe (Mesa 22.3) a 16-ball break's first 256-event dispatch stopped part-way
/// (after 172 events, with some threads' states not written back), while dispatches of
/// 32 or 64 events give the CPU's events.
pub const EVENTS_PER_DISPATCH: u32 = 32;

/// Threads of a table's workgroup, by default (the shader's `LOOP_THREADS`).
pub const EVENT_LOOP_THREADS: usize = 64;

/// A measuring knob of the GPU event loop: environment variable `name`, a whole number
/// that `allowed` accepts (`expected` says which), or `default` where it is unset. The
/// knobs change no answer, only the schedule (for measuring the alternatives on a device).
fn knob(
    name: &str,
    default: usize,
    allowed: impl Fn(usize) -> bool,
    expected: &str,
) -> Result<usize, Error> {
    let Ok(v) = std::env::var(name) else {
        return Ok(default);
    };
    match v.trim().parse::<usize>() {
        Ok(n) if allowed(n) => Ok(n),
        _ => Err(Error::Unsupported(format!(
            "{name}={v:?}: expected {expected}"
        ))),
    }
}

/// The workgroup's threads: `KISSTIME_EVENT_LOOP_THREADS` (16, 32 or 64; for measuring
/// occupancy on a device) or [`EVENT_LOOP_THREADS`].
fn event_loop_threads() -> Result<usize, Error> {
    knob(
        "KISSTIME_EVENT_LOOP_THREADS",
        EVENT_LOOP_THREADS,
        |t| matches!(t, 16 | 32 | 64),
        "16, 32 or 64",
    )
}

/// The most threads one missing row of a ball–table category is split over, by default
/// (the shader's `ROW_THREADS`): after an event only the one or two balls involved have
/// their rows to fill, each row a loop over the table's items (36 on a pool table); split
/// over the workgroup's threads, a step waits for a couple of items' times instead of a
/// whole row's.
pub const ROW_THREADS: usize = 64;

/// The threads a row is split over, at most: `KISSTIME_GPU_ROW_THREADS` (1 to 64; 1 fills
/// each row on one thread, item by item, as before: for measuring the two on a device) or
/// [`ROW_THREADS`].
fn row_threads() -> Result<usize, Error> {
    knob(
        "KISSTIME_GPU_ROW_THREADS",
        ROW_THREADS,
        |n| (1..=64).contains(&n),
        "a whole number from 1 to 64",
    )
}

/// Tables a workgroup of the event loop holds, at most, by default (the shader's
/// `TABLES_PER_GROUP`): one. More put several tables' threads side by side in one
/// workgroup (a 16-thread table fills half an NVIDIA warp; two tables fill it), each
/// table's work as before, for measuring occupancy on a device.
pub const TABLES_PER_GROUP: usize = 1;

/// Tables a workgroup holds, at most: `KISSTIME_GPU_TABLES_PER_GROUP` (1, 2, 4, 8 or 16)
/// or [`TABLES_PER_GROUP`].
fn tables_per_group() -> Result<usize, Error> {
    knob(
        "KISSTIME_GPU_TABLES_PER_GROUP",
        TABLES_PER_GROUP,
        valid_tables_per_group,
        "1, 2, 4, 8 or 16",
    )
}

/// Whether `n` tables a workgroup may be asked for.
fn valid_tables_per_group(n: usize) -> bool {
    matches!(n, 1 | 2 | 4 | 8 | 16)
}

/// The chunks a large batch is cut into: `KISSTIME_GPU_PIPELINE_CHUNKS` (1 to 64; 1 keeps
/// a batch in one chunk where the bindings allow, with no host work beside the device's:
/// for measuring what the overlap gains) or [`PIPELINE_CHUNKS`].
fn pipeline_chunks() -> Result<usize, Error> {
    knob(
        "KISSTIME_GPU_PIPELINE_CHUNKS",
        PIPELINE_CHUNKS,
        |n| (1..=64).contains(&n),
        "a whole number from 1 to 64",
    )
}

/// Whether the device draws a study's strikes itself where it can ([`CheckedTables::drawn`]):
/// `KISSTIME_GPU_DRAWS` (1, the default, or 0: the host packs each sample's struck cue
/// ball, as for a study with a physics spread — for measuring what the device's draws
/// gain on a device).
fn draws_wanted() -> Result<bool, Error> {
    knob("KISSTIME_GPU_DRAWS", 1, |n| n <= 1, "0 or 1").map(|n| n == 1)
}

/// Whether the event loop is built exact where the device allows: `KISSTIME_GPU_EXACT`
/// (1, the default, or 0: the WGSL as wgpu compiles it, which a driver may contract —
/// for measuring what exactness costs on a device).
fn exact_wanted() -> Result<bool, Error> {
    knob("KISSTIME_GPU_EXACT", 1, |n| n <= 1, "0 or 1").map(|n| n == 1)
}

/// Tables per chunk, at most, by default.
pub const MAX_TABLES_PER_CHUNK: usize = 1 << 20;

/// A batch of at least twice this many tables is cut into chunks of at least this many
/// (and at most [`PIPELINE_CHUNKS`] of them, where the bindings allow), so that the host's
/// packing and unpacking overlap the device's runs: enough tables a chunk to fill an H200
/// (10⁴ tables ran at the rate of 10⁶ there, 2,000 did not).
pub const PIPELINE_MIN_TABLES: usize = 1 << 15;

/// The chunks a large batch is cut into, at most (see [`PIPELINE_MIN_TABLES`]): the host
/// packs the first and unpacks the last alone, the rest while the device runs.
pub const PIPELINE_CHUNKS: usize = 4;

/// A dispatch that runs fewer than one table in this many of its chunk's counts in
/// [`GpuTimings::kernel_tail`].
const TAIL_FRACTION: usize = 16;

/// The event loop's pipeline constants for `layout`'s bucket: `LOOP_THREADS` (`threads`,
/// or the bucket's ball count if larger), `LOOP_ROUNDS` to match, `ROW_THREADS`
/// (`row_threads`), `GROUP_THREADS` (`tables` tables of `LOOP_THREADS`). What
/// [`GpuSimulator`] builds with, and `examples/pipeline_stats.rs`.
#[doc(hidden)]
pub fn event_loop_constants(
    layout: &SimLayout,
    threads: usize,
    row_threads: usize,
    tables: usize,
) -> [(&'static str, f64); 4] {
    let threads = threads.max(layout.gpu_max_balls.next_power_of_two());
    [
        ("LOOP_THREADS", threads as f64),
        ("LOOP_ROUNDS", layout.gpu_max_pairs.div_ceil(threads) as f64),
        ("ROW_THREADS", row_threads as f64),
        ("GROUP_THREADS", (tables * threads) as f64),
    ]
}

/// What [`GpuSimulator::simulate_with`] hands each event to: `(table, record)`.
pub type OnEvent<'a> = &'a mut dyn FnMut(usize, &EventRecord);

/// No agent (the shader's `NO_AGENT`): the watch is off.
const NO_WATCH: u32 = u32::MAX;

/// Fills table `k`'s balls (the callee clears the vector first) and returns its strike:
/// [`crate::simulate::simulate_batch`]'s input. Called from worker threads, more than once
/// a table.
pub type FillTable<'a> =
    &'a (dyn Fn(usize, &mut Vec<BallState>) -> Result<Option<(usize, CueStrike)>, SimError> + Sync);

/// Tables given by a [`FillTable`] that the caller has checked as
/// [`crate::simulate::simulate_batch`] checks them (layout, strike, parameters):
/// [`crate::engine::ShotEngine::simulate_with`]'s chunks. Nothing is held per table.
#[derive(Clone, Copy)]
pub struct CheckedTables<'a> {
    /// The tables' balls and strikes.
    pub fill: FillTable<'a>,
    /// Tables `0..n_tables` of `fill`.
    pub n_tables: usize,
    /// The most balls any of them has (it chooses the pipeline's bucket).
    pub max_balls: usize,
    /// A hint that every table's balls are the same (one position struck many ways: a
    /// study's): a chunk whose tables do have the same balls, all at rest (stationary or
    /// pocketed), and strike the same ball then uploads the position once and each table's
    /// strike, and the device lays the tables out; any other chunk is packed whole. The
    /// results are the same either way.
    pub one_position: bool,
    /// The tables' strikes as a rule the device draws by ([`DrawnStrikes`], table 0 being
    /// its `first`): with `one_position`, shared physics and no events recorded, a chunk
    /// then crosses the bus as the position and one header, and the device draws and plays
    /// each table's strike (the shader's `expand_drawn`). The caller has checked that
    /// `fill` gives what the rule says and that every strike it draws is valid (the
    /// engine's `check_drawn`, with the study's bound); the results are the same either way.
    pub drawn: Option<DrawnStrikes>,
}

/// A table's strike: the struck ball's index and the strike, if any.
type Strike = Option<(usize, CueStrike)>;

/// The tables of a call: shots of their own, or checked tables from a source.
#[derive(Clone, Copy)]
enum Input<'a> {
    Shots(&'a [GpuShot]),
    Checked {
        tables: CheckedTables<'a>,
        /// The first table's number in `fill`.
        offset: usize,
    },
}

impl<'a> Input<'a> {
    fn len(&self) -> usize {
        match self {
            Input::Shots(s) => s.len(),
            Input::Checked { tables, .. } => tables.n_tables,
        }
    }

    /// The most balls a table has.
    fn max_balls(&self) -> usize {
        match self {
            Input::Shots(s) => s.iter().map(|s| s.balls.len()).max().unwrap_or(0),
            Input::Checked { tables, .. } => tables.max_balls,
        }
    }

    /// Tables `range` of these.
    fn part(&self, range: std::ops::Range<usize>) -> Input<'a> {
        match *self {
            Input::Shots(s) => Input::Shots(&s[range]),
            Input::Checked { tables, offset } => Input::Checked {
                tables: CheckedTables {
                    n_tables: range.len(),
                    ..tables
                },
                offset: offset + range.start,
            },
        }
    }

    /// Table `k`'s balls (in `buf` for checked tables) and strike.
    fn shot<'b>(
        &'b self,
        k: usize,
        buf: &'b mut Vec<BallState>,
    ) -> Result<(&'b [BallState], Strike), SimError> {
        match *self {
            Input::Shots(s) => Ok((&s[k].balls, s[k].strike)),
            Input::Checked { tables, offset } => {
                let strike = (tables.fill)(offset + k, buf)?;
                Ok((&buf[..], strike))
            }
        }
    }
}

/// What a call reads back besides the final states.
pub enum GpuOutput<'a> {
    /// Final states only.
    Finals,
    /// Every event, handed to the callback after each dispatch.
    Events(OnEvent<'a>),
    /// The watch of one ball ([`crate::simulate::watch`]) instead of any event: the call
    /// returns [`WatchedRun`]s.
    Watch(WatchOptions),
}

/// What the phases of one chunk share.
struct ChunkCall<'c> {
    table: &'c Table,
    /// The chunk's tables' physics.
    physics: Physics<'c>,
    limits: Limits,
    layout: SimLayout,
    /// The chunk's tables.
    input: Input<'c>,
    /// The chunk's first table in the batch (for messages and callbacks).
    first: usize,
    /// Whether events are recorded and read back.
    record: bool,
    /// The watched cue ball ([`NO_WATCH`]: none), and whether a table stops at its first
    /// contact.
    watch_cue: u32,
    watch_stop: bool,
    /// Whether the rules' facts of the watch are read back.
    watch_facts: bool,
}

/// A packed chunk: the strikes' event records (with their tables' places in the chunk),
/// the runs so far, and how its host arrays become the tables' I/O blocks.
struct PackedChunk {
    strikes: Vec<(usize, EventRecord)>,
    runs: Vec<GpuRun>,
    expansion: Expansion,
}

/// How a packed chunk's host arrays become its tables' I/O blocks on the device.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Expansion {
    /// They are the I/O blocks, copied as they are.
    Whole,
    /// One position's block and each table's strike block of ball `cue`
    /// ([`pack_expanded`]), laid out by the shader's `expand_tables`.
    Strikes { cue: u32 },
    /// One position's block and a header ([`pack_drawn`]): the shader's `expand_drawn`
    /// draws each table's strike of ball `cue` and lays the tables out.
    Drawn { cue: u32 },
}

impl Expansion {
    /// The packed bytes of a chunk of `n_tables` tables: (reals, u32s).
    fn packed_len(self, l: &SimLayout, n_tables: usize, real: usize) -> (usize, usize) {
        match self {
            Expansion::Whole => (n_tables * l.io_reals * real, n_tables * l.io_uints * 4),
            Expansion::Strikes { .. } => (
                (l.io_reals + n_tables * STRUCK_REALS) * real,
                (l.io_uints + n_tables * STRUCK_UINTS) * 4,
            ),
            Expansion::Drawn { .. } => (
                (l.io_reals + DRAWN_REALS) * real,
                (l.io_uints + DRAWN_UINTS) * 4,
            ),
        }
    }
}

/// The host arrays a chunk's I/O blocks (or its position and strike blocks) are packed
/// in, kept across chunks and calls.
#[derive(Default)]
struct HostBlocks {
    r: Vec<u8>,
    u: Vec<u8>,
}

/// The event loop's pipelines of one bucket: the loop itself, and the expansions of one
/// position into a chunk's tables (from the host's strike blocks, or drawn on the device).
struct LoopPipelines {
    simulate: wgpu::ComputePipeline,
    expand: wgpu::ComputePipeline,
    drawn: wgpu::ComputePipeline,
    /// Tables a workgroup of `simulate` holds.
    tables: u32,
}

/// The GPU event loop: device, pipeline and buffers, reused across calls.
pub struct GpuSimulator {
    pub(super) device: wgpu::Device,
    queue: wgpu::Queue,
    adapter: AdapterSummary,
    precision: Precision,
    /// The event loop's pipelines for each ball-count bucket built so far.
    pipelines: Vec<(SimLayout, LoopPipelines)>,
    /// Threads a table's workgroup (at least the bucket's ball count).
    threads: usize,
    /// The most threads a missing row is split over (the shader's `ROW_THREADS`).
    row_threads: usize,
    /// Tables a workgroup holds, at most (fewer where a bucket's do not fit the device).
    tables_per_group: usize,
    /// The most threads a workgroup may have on the device.
    max_group_threads: u32,
    /// Whether the event loop is built as SPIR-V without contraction ([`super::spirv`]).
    exact: bool,
    /// Whether the device takes SPIR-V as it is (Vulkan, `PASSTHROUGH_SHADERS`).
    spirv: bool,
    /// The largest workgroup memory the device allows, in bytes.
    max_workgroup_bytes: u32,
    pub(super) max_groups_per_dim: u32,
    /// The largest storage binding the device allows, in bytes.
    max_binding: u64,
    watch: device::DeviceWatch,
    /// The event loop's passes timed on the device, where the adapter has timestamps.
    timer: Option<PassTimer>,
    bufs: Option<LoopBuffers>,
    /// A chunk's I/O blocks packed on the host, kept across calls.
    host: HostBlocks,
    /// A fault waiting for its dispatch: the fault, and how many dispatches run first.
    #[cfg(feature = "testing")]
    pub(super) pending_fault: Option<(super::Fault, u32)>,
    /// Test hook: make the buffers anew for every chunk instead of reusing them (to
    /// measure what the reuse saves).
    #[cfg(feature = "testing")]
    pub fresh_buffers: bool,
    /// The last call's timings, summed over chunks (see [`GpuTimings`]).
    timings: GpuTimings,
    /// Every call's timings since the simulator was opened.
    total: GpuTimings,
    /// Dispatches of the last call.
    dispatches: u64,
    /// Chunks of the last call laid out on the device from one position and the host's
    /// strike blocks.
    expanded: u64,
    /// Chunks of the last call whose strikes the device drew.
    drawn_chunks: u64,
    /// Events per table and dispatch.
    pub events_per_dispatch: u32,
    /// The most tables per chunk: a batch is cut into chunks of whole tables that fit the
    /// device's largest storage binding, and of at most this many tables (by default
    /// [`MAX_TABLES_PER_CHUNK`]), simulated one after the other.
    pub max_tables_per_chunk: usize,
    /// The chunks a large batch is cut into ([`PIPELINE_CHUNKS`] by default; 1: one chunk,
    /// no host work beside the device's), each of at least [`PIPELINE_MIN_TABLES`].
    pub pipeline_chunks: usize,
    /// Whether the device draws a study's strikes itself where the tables say how
    /// ([`CheckedTables::drawn`]; `true` by default, `KISSTIME_GPU_DRAWS=0` turns it off):
    /// the same runs either way.
    pub device_draws: bool,
}

impl GpuSimulator {
    /// Opens the GPU and builds the event loop's pipeline for `precision`.
    ///
    /// Errors: [`Error::GpuUnavailable`] without a usable adapter (or without
    /// `SHADER_F64` for f64); [`Error::Gpu`] when the device or the shader fails to build.
    pub fn new(precision: Precision) -> Result<GpuSimulator, Error> {
        let (threads, chunks, rows) = (event_loop_threads()?, pipeline_chunks()?, row_threads()?);
        let tables = tables_per_group()?;
        let draws = draws_wanted()?;
        let mut sim = GpuSimulator::with_loop_threads(precision, threads)?;
        sim.pipeline_chunks = chunks;
        sim.device_draws = draws;
        if rows != ROW_THREADS {
            sim.set_row_threads(rows)?;
        }
        if tables != TABLES_PER_GROUP {
            sim.set_tables_per_group(tables)?;
        }
        Ok(sim)
    }

    /// Puts up to `tables` tables in each workgroup of the event loop from now on (1, 2,
    /// 4, 8 or 16; [`TABLES_PER_GROUP`] by default): the same answers, another occupancy.
    /// A bucket whose workgroups of `tables` tables would not fit the device (its
    /// workgroup memory or threads) is built with as many as fit, halving. The pipelines
    /// are built again.
    ///
    /// Errors: [`Error::Unsupported`] for another count; [`Error::Gpu`] when the shader
    /// does not build.
    pub fn set_tables_per_group(&mut self, tables: usize) -> Result<(), Error> {
        if !valid_tables_per_group(tables) {
            return Err(Error::Unsupported(format!(
                "{tables} tables a workgroup: expected 1, 2, 4, 8 or 16"
            )));
        }
        self.tables_per_group = tables;
        self.rebuild()
    }

    /// Tables a workgroup of the event loop holds for tables of up to `max_balls` balls
    /// (the bucket's build; 1 by default).
    ///
    /// Errors: as [`GpuSimulator::set_tables_per_group`], when the bucket's pipelines are
    /// built now; [`Error::Unsupported`] past [`GPU_MAX_BALLS`].
    pub fn tables_per_group(&mut self, max_balls: usize) -> Result<usize, Error> {
        let layout = SimLayout::bucket(max_balls).ok_or_else(|| {
            Error::Unsupported(format!(
                "a table of {max_balls} balls: the GPU event loop takes at most {GPU_MAX_BALLS}"
            ))
        })?;
        Ok(self.pipeline(&layout)?.tables as usize)
    }

    /// Splits each missing row over at most `threads` threads from now on (1 to 64; 1:
    /// one thread a row; [`ROW_THREADS`] by default): the same answers, another schedule.
    /// The pipelines are built again.
    ///
    /// Errors: [`Error::Unsupported`] outside 1 to 64; [`Error::Gpu`] when the shader does
    /// not build.
    pub fn set_row_threads(&mut self, threads: usize) -> Result<(), Error> {
        if !(1..=64).contains(&threads) {
            return Err(Error::Unsupported(format!(
                "a row split over {threads} threads: expected 1 to 64"
            )));
        }
        self.row_threads = threads;
        self.rebuild()
    }

    /// Builds the event loop as exact SPIR-V (`true`, the default on Vulkan) or from the
    /// WGSL as wgpu compiles it (`false`) from now on; see [`GpuSimulator::exact`]. The
    /// pipelines are built again.
    ///
    /// Errors: [`Error::Unsupported`] asking for exact SPIR-V where the device takes none
    /// (not Vulkan); [`Error::Gpu`] when the shader does not build.
    pub fn set_exact(&mut self, exact: bool) -> Result<(), Error> {
        if exact && !self.spirv {
            return Err(Error::Unsupported(format!(
                "{} takes no SPIR-V (not Vulkan): the event loop runs as wgpu compiles it",
                self.adapter.name
            )));
        }
        self.exact = exact;
        self.rebuild()
    }

    /// The pipelines built anew for the settings now (the 16-ball bucket at once, so that
    /// a build that fails fails here), and the buffers made anew with them: their bind
    /// groups were made for the old pipelines' layouts.
    fn rebuild(&mut self) -> Result<(), Error> {
        self.pipelines.clear();
        self.bufs = None;
        self.pipeline(&SimLayout::for_balls(16))?;
        Ok(())
    }

    /// [`GpuSimulator::new`] with `threads` threads a table's workgroup (16, 32 or 64: the
    /// same answers, another occupancy; [`EVENT_LOOP_THREADS`] by default).
    pub fn with_loop_threads(precision: Precision, threads: usize) -> Result<GpuSimulator, Error> {
        if !matches!(threads, 16 | 32 | 64) {
            return Err(Error::Unsupported(format!(
                "{threads} threads a table: expected 16, 32 or 64"
            )));
        }
        let opened = device::open(precision)?;
        let device = opened.device;
        let timer = opened
            .timestamps
            .then(|| PassTimer::new(&device, &opened.queue));
        let mut sim = GpuSimulator {
            timer,
            max_groups_per_dim: opened.limits.max_compute_workgroups_per_dimension,
            max_binding: opened
                .limits
                .max_storage_buffer_binding_size
                .min(opened.limits.max_buffer_size),
            max_workgroup_bytes: opened.limits.max_compute_workgroup_storage_size,
            device,
            queue: opened.queue,
            adapter: opened.adapter,
            watch: opened.watch,
            bufs: None,
            host: HostBlocks::default(),
            #[cfg(feature = "testing")]
            pending_fault: None,
            #[cfg(feature = "testing")]
            fresh_buffers: false,
            precision,
            pipelines: Vec::new(),
            threads,
            row_threads: ROW_THREADS,
            tables_per_group: TABLES_PER_GROUP,
            max_group_threads: opened.limits.max_compute_invocations_per_workgroup,
            exact: opened.spirv && exact_wanted()?,
            spirv: opened.spirv,
            timings: GpuTimings::default(),
            total: GpuTimings::default(),
            dispatches: 0,
            expanded: 0,
            drawn_chunks: 0,
            events_per_dispatch: EVENTS_PER_DISPATCH,
            max_tables_per_chunk: MAX_TABLES_PER_CHUNK,
            pipeline_chunks: PIPELINE_CHUNKS,
            device_draws: true,
        };
        // the 16-ball bucket now: a shader that does not build fails here
        sim.pipeline(&SimLayout::for_balls(16))?;
        Ok(sim)
    }

    /// The event loop's pipelines for `layout`'s bucket, built the first time they are
    /// needed: the shader with its `GPU_MAX_BALLS` set to the bucket's, `LOOP_THREADS` the
    /// simulator's threads or the bucket's ball count if larger, `LOOP_ROUNDS` to match.
    fn pipeline(&mut self, layout: &SimLayout) -> Result<&LoopPipelines, Error> {
        if let Some(k) = self.pipelines.iter().position(|(l, _)| l == layout) {
            return Ok(&self.pipelines[k].1);
        }
        let n = layout.gpu_max_balls;
        let (tables, source) = self.group_build(layout)?;
        let constants = event_loop_constants(layout, self.threads, self.row_threads, tables);
        let device = &self.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("kisstime event loop"),
            source: wgpu::ShaderSource::Wgsl(source.as_str().into()),
        });
        let wgsl_entry = |name: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(name),
                layout: None,
                module: &module,
                entry_point: Some(name),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &constants,
                    ..Default::default()
                },
                cache: None,
            })
        };
        // every entry as exact SPIR-V where the device takes it (super::spirv): the loop,
        // and expand_drawn's draws and strike, must round as their Rust twins do
        let exact_entry = |name: &str| match self.exact {
            true => super::spirv::exact_pipeline(device, &source, name, &constants),
            false => Ok(wgsl_entry(name)),
        };
        let built = ["simulate_tables", "expand_tables", "expand_drawn"].map(exact_entry);
        let [simulate, expand, drawn] = match built {
            [Ok(simulate), Ok(expand), Ok(drawn)] => [simulate, expand, drawn],
            [Err(e), ..] | [_, Err(e), _] | [.., Err(e)] => {
                // the scope is the device's: closed before the error goes up
                let _ = pollster::block_on(scope.pop());
                return Err(gpu_error(format!("the event loop's SPIR-V: {e}")));
            }
        };
        let pipeline = LoopPipelines {
            simulate,
            expand,
            drawn,
            tables: tables as u32,
        };
        if let Some(e) = pollster::block_on(scope.pop()) {
            let text = e.to_string();
            if n > 16 && text.to_lowercase().contains("workgroup") {
                return Err(Error::Unsupported(format!(
                    "tables of up to {n} balls need more workgroup memory than the {} bytes \
                     of {}: {text}",
                    self.max_workgroup_bytes, self.adapter.name
                )));
            }
            return Err(gpu_error(format!(
                "the {} event-loop shader for {n} balls does not build on {}: {e}",
                self.precision.name(),
                self.adapter.name
            )));
        }
        self.pipelines.push((*layout, pipeline));
        Ok(&self.pipelines.last().expect("pushed").1)
    }
    /// The tables a workgroup of `layout`'s build holds, and its source: the simulator's
    /// count, halved until the workgroup's threads and memory fit the device (one table
    /// always: a bucket whose one table does not fit fails at the build, naming it).
    fn group_build(&self, layout: &SimLayout) -> Result<(usize, String), Error> {
        let threads = self.threads.max(layout.gpu_max_balls.next_power_of_two());
        let mut tables = self.tables_per_group;
        loop {
            let source = simulate_source(self.precision, layout.gpu_max_balls, tables);
            if tables == 1 {
                return Ok((1, source));
            }
            let bytes = workgroup_bytes(&source, "simulate_tables").map_err(gpu_error)?;
            if tables * threads <= self.max_group_threads as usize
                && bytes <= u64::from(self.max_workgroup_bytes)
            {
                return Ok((tables, source));
            }
            tables /= 2;
        }
    }

    /// The adapter in use.
    pub fn adapter(&self) -> &AdapterSummary {
        &self.adapter
    }

    /// Whether the event loop runs as SPIR-V whose float operations the driver may not
    /// contract or reorder ([`super::spirv`]): on Vulkan unless `KISSTIME_GPU_EXACT=0`.
    /// Then, on a device with IEEE f64 arithmetic, the f64 runs are the CPU's bit for bit.
    pub fn exact(&self) -> bool {
        self.exact
    }

    /// The precision the event loop computes in.
    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// The last call's split (see the field docs of [`GpuTimings`]: here "kernel" is every
    /// dispatch of the event loop, waited for, with the 4-byte count after each and the
    /// events where they are read back).
    pub fn timings(&self) -> GpuTimings {
        self.timings
    }

    /// The timings of every call since the simulator was opened (a study's batches
    /// together).
    pub fn total_timings(&self) -> GpuTimings {
        self.total
    }

    /// The dispatches of the last call (over all chunks).
    pub fn dispatches(&self) -> u64 {
        self.dispatches
    }

    /// The chunks of the last call that crossed the bus as one position and its tables'
    /// strikes ([`CheckedTables::one_position`]) and were laid out on the device.
    pub fn expanded_chunks(&self) -> u64 {
        self.expanded
    }

    /// The chunks of the last call that crossed the bus as one position and a header, the
    /// device drawing each table's strike ([`CheckedTables::drawn`]).
    pub fn drawn_chunks(&self) -> u64 {
        self.drawn_chunks
    }

    /// Simulates every shot on `table` to rest (or to a limit), in shot order; with
    /// `record_events` each run keeps its events (see [`GpuSimulator::simulate_with`] to
    /// stream them instead).
    ///
    /// Errors: a table with more than [`GPU_MAX_BALLS`] balls ([`Error::Unsupported`]); a
    /// table the CPU refuses too (`check_layout`: non-finite numbers, a ball off the
    /// table; a bad strike), as [`Error::Input`] naming the first such table and the
    /// reason; bad parameters; or a device failure ([`Error::Gpu`]: validation, out of
    /// memory, a lost device, a failed readback).
    pub fn simulate<'p>(
        &mut self,
        table: &Table,
        physics: impl Into<Physics<'p>>,
        limits: Limits,
        shots: &[GpuShot],
        record_events: bool,
    ) -> Result<Vec<GpuRun>, Error> {
        let params = physics.into();
        if !record_events {
            return self.simulate_with(table, params, limits, shots, None);
        }
        let mut events: Vec<Vec<EventRecord>> = vec![Vec::new(); shots.len()];
        let mut keep = |k: usize, e: &EventRecord| events[k].push(*e);
        let mut runs = self.simulate_with(table, params, limits, shots, Some(&mut keep))?;
        for (run, ev) in runs.iter_mut().zip(events) {
            run.events = ev;
        }
        Ok(runs)
    }

    /// [`GpuSimulator::simulate`] that hands each event, in order within each table, to
    /// `on_event(table, record)` as it is read back (after every dispatch) instead of
    /// keeping it. Without `on_event` no event is read back. The runs' `events` stay empty.
    pub fn simulate_with<'p>(
        &mut self,
        table: &Table,
        physics: impl Into<Physics<'p>>,
        limits: Limits,
        shots: &[GpuShot],
        on_event: Option<OnEvent<'_>>,
    ) -> Result<Vec<GpuRun>, Error> {
        let params = physics.into();
        let mode = match on_event {
            Some(f) => GpuOutput::Events(f),
            None => GpuOutput::Finals,
        };
        Ok(self
            .run(table, params, limits, Input::Shots(shots), mode)?
            .0)
    }

    /// Tables the caller has checked ([`CheckedTables`]: the engine's chunks), read back
    /// as `output` asks: the runs (final states, events through the callback), or with
    /// [`GpuOutput::Watch`] the watched runs (the watched ball's final state, the outcome,
    /// the watch), no event crossing the bus; a table then stops at its first contact where
    /// the watch asks for it. Errors as [`GpuSimulator::simulate`].
    pub fn simulate_checked(
        &mut self,
        table: &Table,
        physics: Physics<'_>,
        limits: Limits,
        tables: CheckedTables<'_>,
        output: GpuOutput<'_>,
    ) -> Result<(Vec<GpuRun>, Vec<WatchedRun>), Error> {
        if let GpuOutput::Watch(w) = output
            && w.cue >= tables.max_balls.max(1)
        {
            return Err(Error::from(InputError::new(format!(
                "the watched ball {} is not on the tables: they have at most {} balls",
                w.cue, tables.max_balls
            ))));
        }
        let tables = CheckedTables {
            drawn: tables.drawn.filter(|_| self.device_draws),
            ..tables
        };
        let input = Input::Checked { tables, offset: 0 };
        self.run(table, physics, limits, input, output)
    }

    /// The batch in chunks that fit the device's bindings.
    fn run(
        &mut self,
        table: &Table,
        physics: Physics<'_>,
        limits: Limits,
        input: Input<'_>,
        mut mode: GpuOutput<'_>,
    ) -> Result<(Vec<GpuRun>, Vec<WatchedRun>), Error> {
        self.timings = GpuTimings::default();
        self.dispatches = 0;
        self.expanded = 0;
        self.drawn_chunks = 0;
        // the parameters checked as the CPU loop checks them (each table's where per table)
        physics.check(input.len()).map_err(|(k, e)| {
            let which = if physics.is_shared() {
                "the simulation parameters".to_owned()
            } else {
                format!("table {k}'s parameters")
            };
            Error::from(InputError::new(format!("{which}: {e}")))
        })?;
        EventLoop::new(table, physics.first(), limits, GPU_MAX_BALLS)
            .map_err(|e| gpu_error(format!("the simulation parameters: {e}")))?;
        // the call's bucket: the smallest that holds its largest table
        let n = input.len();
        let most = input.max_balls();
        let Some(layout) = SimLayout::bucket(most) else {
            return Err(Error::Unsupported(format!(
                "a table of {most} balls: the GPU event loop takes at most {GPU_MAX_BALLS}"
            )));
        };
        self.pipeline(&layout)?;
        let l = &layout;
        let per = self.events_per_dispatch.max(1) as usize;
        let real = self.precision.real_size();
        // the largest per-table binding decides how many tables fit one binding
        let per_table = ((l.io_reals + l.cache_reals + l.watch_reals) * real)
            .max(per * EVENT_REALS * real)
            .max(4 * (1 + per * EVENT_UINTS));
        let fit = (self.max_binding / per_table as u64).max(1) as usize;
        let chunk = chunk_tables(n, self.max_tables_per_chunk.min(fit), self.pipeline_chunks);
        let (record, watch_cue, watch_stop, watch_facts) = match &mode {
            GpuOutput::Finals => (false, NO_WATCH, false, false),
            GpuOutput::Events(_) => (true, NO_WATCH, false, false),
            GpuOutput::Watch(w) => (false, w.cue as u32, w.stop_at_first_contact, w.facts),
        };
        let calls: Vec<ChunkCall<'_>> = (0..n)
            .step_by(chunk)
            .map(|start| {
                let end = n.min(start + chunk);
                ChunkCall {
                    table,
                    physics: physics.part(start..end),
                    limits,
                    layout,
                    input: input.part(start..end),
                    first: start,
                    record,
                    watch_cue,
                    watch_stop,
                    watch_facts,
                }
            })
            .collect();
        // the buffers fit the largest chunk of this call (they grow for a larger one)
        let capacity = chunk.min(n);
        // out of `self` while the chunks run: a host worker packs into it beside the device
        let mut host = std::mem::take(&mut self.host);
        let done = self.run_chunks(&calls, capacity, &mut host, &mut mode);
        self.host = host;
        self.total.add(&self.timings);
        done
    }

    /// The chunks one after the other on the device, each in its phases (the buffers and
    /// the shared data, the upload, the dispatches, the readback), while on the host a
    /// worker unpacks the chunk before and packs the chunk after (each phase timed in
    /// [`GpuTimings`]). The first chunk is packed, and the last unpacked, alone.
    fn run_chunks(
        &mut self,
        calls: &[ChunkCall<'_>],
        capacity: usize,
        host: &mut HostBlocks,
        mode: &mut GpuOutput<'_>,
    ) -> Result<(Vec<GpuRun>, Vec<WatchedRun>), Error> {
        let precision = self.precision;
        let mut runs = Vec::new();
        let mut watches = Vec::new();
        let clock = Instant::now();
        let mut next = match calls.first() {
            Some(call) => Some(pack_chunk(precision, call, host)?),
            None => None,
        };
        self.timings.pack += clock.elapsed().as_secs_f64();
        // the chunk read back and not yet unpacked: its runs so far and its readback
        let mut back: Option<(Vec<GpuRun>, ReadBack)> = None;
        for (k, call) in calls.iter().enumerate() {
            let PackedChunk {
                strikes,
                runs: chunk_runs,
                expansion,
            } = next.take().expect("each chunk is packed before its turn");
            let clock = Instant::now();
            self.prepare_chunk(call, capacity)?;
            self.timings.pack += clock.elapsed().as_secs_f64();
            match expansion {
                Expansion::Whole => {}
                Expansion::Strikes { .. } => self.expanded += 1,
                Expansion::Drawn { .. } => self.drawn_chunks += 1,
            }
            if let GpuOutput::Events(on_event) = mode {
                for (j, record) in &strikes {
                    on_event(call.first + j, record);
                }
            }
            let clock = Instant::now();
            self.upload_chunk(call, host, expansion)?;
            self.timings.upload += clock.elapsed().as_secs_f64();
            // while the device runs this chunk, the host unpacks the one before and packs
            // the one after (the upload has copied the host arrays)
            let before = back.take();
            let after = calls.get(k + 1);
            if before.is_none() && after.is_none() {
                // a call of one chunk: nothing for the host to do beside the device
                let clock = Instant::now();
                let dispatched = self.dispatch_chunk(call, mode);
                self.timings.kernel += clock.elapsed().as_secs_f64();
                dispatched?;
                back = Some((chunk_runs, self.read_back_chunk(call)?));
                continue;
            }
            let arrays = &mut *host;
            let (worker, (dispatched, kernel)) = std::thread::scope(|s| {
                let worker = s.spawn(move || {
                    let clock = Instant::now();
                    let unpacked = before.map(|(mut runs, readback)| {
                        unpack_chunk(precision, readback, &mut runs).map(|w| (runs, w))
                    });
                    let unpack = clock.elapsed().as_secs_f64();
                    let clock = Instant::now();
                    let packed = after.map(|c| pack_chunk(precision, c, arrays));
                    (unpacked, unpack, packed, clock.elapsed().as_secs_f64())
                });
                let clock = Instant::now();
                let dispatched = self.dispatch_chunk(call, mode);
                let kernel = clock.elapsed().as_secs_f64();
                (worker.join(), (dispatched, kernel))
            });
            let (unpacked, unpack, packed, pack) =
                worker.unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            self.timings.kernel += kernel;
            self.timings.unpack += unpack;
            self.timings.pack += pack;
            self.timings.overlapped += unpack + pack;
            // failures in the batch's order: the chunk before, this one, the one after
            if let Some(unpacked) = unpacked {
                let (before_runs, before_watches) = unpacked?;
                runs.extend(before_runs);
                watches.extend(before_watches);
            }
            dispatched?;
            next = packed.transpose()?;
            back = Some((chunk_runs, self.read_back_chunk(call)?));
        }
        if let Some((mut last_runs, readback)) = back {
            let clock = Instant::now();
            let last_watches = unpack_chunk(precision, readback, &mut last_runs)?;
            self.timings.unpack += clock.elapsed().as_secs_f64();
            runs.extend(last_runs);
            watches.extend(last_watches);
        }
        Ok((runs, watches))
    }

    /// The buffers for the chunk (made or reused), with the table's geometry and the
    /// parameter blocks written.
    fn prepare_chunk(&mut self, call: &ChunkCall<'_>, capacity: usize) -> Result<(), Error> {
        let (table, physics, limits) = (call.table, call.physics, call.limits);
        let n_tables = call.input.len();
        let precision = self.precision;
        let mut geometry = Vec::new();
        for s in &table.linear {
            geometry.extend([s.p1.x, s.p1.y, s.p1.z, s.p2.x, s.p2.y, s.p2.z]);
            geometry.extend([s.direction as f64, s.lx, s.ly, s.l0]);
        }
        for c in &table.circular {
            geometry.extend([c.center.x, c.center.y, c.center.z, c.radius]);
        }
        for p in &table.pockets {
            geometry.extend([p.center.x, p.center.y, p.center.z, p.radius, p.depth]);
        }
        geometry.push(0.0);
        // one parameter block for all the tables, or one per table (cfg's sim_stride)
        let sim: Vec<f64> = match physics {
            Physics::Shared(p) => param_block(&p, limits).to_vec(),
            _ => (0..n_tables)
                .flat_map(|k| param_block(&physics.of(k), limits))
                .collect(),
        };
        let sim_reals = if physics.is_shared() {
            SIM_REALS
        } else {
            SIM_REALS * capacity.max(n_tables)
        };
        self.buffers(
            call.layout,
            capacity.max(n_tables),
            call.record,
            geometry.len(),
            sim_reals,
        )?;
        let bufs = self.bufs.as_ref().expect("made by buffers");
        let queue = &self.queue;
        queue.write_buffer(&bufs.sim, 0, &real_bytes(precision, &sim));
        queue.write_buffer(&bufs.geometry, 0, &real_bytes(precision, &geometry));
        Ok(())
    }

    /// The packed host arrays copied to the mapped upload buffers, and these to the
    /// state's I/O region, waited for; for a chunk packed as one position and its strikes
    /// or its header ([`Expansion`]), copied to the events buffers and laid out into the
    /// I/O region by the shader's `expand_tables` or `expand_drawn`.
    fn upload_chunk(
        &mut self,
        call: &ChunkCall<'_>,
        host: &HostBlocks,
        expansion: Expansion,
    ) -> Result<(), Error> {
        let l = &call.layout;
        let n_tables = call.input.len();
        let real = self.precision.real_size();
        let bufs = self.bufs.as_ref().expect("made by prepare_chunk");
        // the packed bytes (the host arrays may be longer: kept from a larger chunk)
        let (len_r, len_u) = expansion.packed_len(l, n_tables, real);
        copy_to_mapped(
            &self.device,
            &[
                (&bufs.up_r, &host.r[..len_r]),
                (&bufs.up_u, &host.u[..len_u]),
            ],
        )?;
        let scopes = Scopes::push(&self.device);
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("kisstime event loop upload"),
            });
        let (len_r, len_u) = (len_r as u64, len_u as u64);
        let expand = match expansion {
            Expansion::Whole => None,
            Expansion::Strikes { cue } => Some((cue, "expand_tables")),
            Expansion::Drawn { cue } => Some((cue, "expand_drawn")),
        };
        if let Some((cue, label)) = expand {
            encoder.copy_buffer_to_buffer(&bufs.up_r, 0, &bufs.events_r, 0, len_r);
            encoder.copy_buffer_to_buffer(&bufs.up_u, 0, &bufs.events_u, 0, len_u);
            let groups = (n_tables as u32).div_ceil(EXPAND_THREADS);
            let groups_x = groups.min(self.max_groups_per_dim);
            let mut cfg = [0u32; 16];
            cfg[0] = n_tables as u32;
            cfg[6] = groups_x;
            cfg[15] = cue;
            self.queue
                .write_buffer(&bufs.cfg, 0, bytemuck::cast_slice(&cfg));
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes: None,
            });
            let pipelines = &self
                .pipelines
                .iter()
                .find(|(p, _)| p == l)
                .ok_or_else(|| gpu_error("no pipeline for the chunk's layout"))?
                .1;
            let (pipeline, bind) = match expansion {
                Expansion::Drawn { .. } => (&pipelines.drawn, &bufs.drawn_bind),
                _ => (&pipelines.expand, &bufs.expand_bind),
            };
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, bind, &[]);
            pass.dispatch_workgroups(groups_x, groups.div_ceil(groups_x), 1);
        } else {
            encoder.copy_buffer_to_buffer(&bufs.up_r, 0, &bufs.state_r, 0, len_r);
            encoder.copy_buffer_to_buffer(&bufs.up_u, 0, &bufs.state_u, 0, len_u);
        }
        self.queue.submit([encoder.finish()]);
        map_and_wait(&self.device, scopes, &self.watch, &[], "the upload")?;
        Ok(())
    }

    /// The chunk's dispatches, until every table is done: `events_per_dispatch` events a
    /// table each, the recorded events handed to `mode`'s callback after each.
    fn dispatch_chunk(
        &mut self,
        call: &ChunkCall<'_>,
        mode: &mut GpuOutput<'_>,
    ) -> Result<(), Error> {
        let (table, limits, first) = (call.table, call.limits, call.first);
        let (record, watch_cue, watch_stop) = (call.record, call.watch_cue, call.watch_stop);
        let n_tables = call.input.len();
        let precision = self.precision;
        let real = precision.real_size();
        let per = self.events_per_dispatch.max(1) as usize;
        let sim_stride = if call.physics.is_shared() {
            0
        } else {
            SIM_REALS
        };
        // without events, each dispatch after the first runs only the tables still running
        // (the shader lists them, in the halves of `live` by turns)
        let compact = !record;
        let group_tables = self
            .pipelines
            .iter()
            .find(|(l, _)| *l == call.layout)
            .ok_or_else(|| gpu_error("no pipeline for the chunk's layout"))?
            .1
            .tables;
        let mut n_active = n_tables as u32;
        let mut dispatch = 0u32;
        loop {
            let started = Instant::now();
            let tail = (n_active as usize) * TAIL_FRACTION < n_tables;
            let groups = n_active.div_ceil(group_tables);
            let groups_x = groups.min(self.max_groups_per_dim);
            let groups_y = groups.div_ceil(groups_x);
            #[cfg_attr(not(feature = "testing"), allow(unused_mut))]
            let mut row = groups_x;
            #[cfg(feature = "testing")]
            self.apply_pending_fault(&mut row);
            let bufs = self.bufs.as_ref().expect("made by buffers");
            let cfg: [u32; 16] = [
                n_tables as u32,
                table.linear.len() as u32,
                table.circular.len() as u32,
                table.pockets.len() as u32,
                u32::try_from(limits.max_events).unwrap_or(u32::MAX),
                per as u32,
                groups_x,
                u32::from(record),
                u32::from(dispatch == 0),
                watch_cue,
                u32::from(watch_stop),
                n_active,
                u32::from(compact),
                if dispatch % 2 == 1 {
                    n_tables as u32
                } else {
                    0
                },
                sim_stride as u32,
                0,
            ];
            self.queue
                .write_buffer(&bufs.cfg, 0, bytemuck::cast_slice(&cfg));
            self.queue
                .write_buffer(&bufs.running, 0, bytemuck::bytes_of(&0u32));
            dispatch += 1;
            let mut copies = vec![Copy {
                src: &bufs.running,
                offset: 0,
                dst: &bufs.back_running,
                len: 4,
            }];
            if let (Some(er), Some(eu)) = (&bufs.back_events_r, &bufs.back_events_u) {
                copies.push(Copy {
                    src: &bufs.events_u,
                    offset: 0,
                    dst: eu,
                    len: (n_tables * (1 + per * EVENT_UINTS) * 4) as u64,
                });
                copies.push(Copy {
                    src: &bufs.events_r,
                    offset: 0,
                    dst: er,
                    len: (n_tables * per * EVENT_REALS * real) as u64,
                });
            }
            self.submit(Some([row, groups_y]), &bufs.bind, &copies)?;
            self.dispatches += 1;
            // every mapped readback read and unmapped before any failure is returned
            let device_seconds = self.timer.as_ref().map(PassTimer::seconds);
            let read: Vec<(&wgpu::Buffer, u64)> = copies.iter().map(|c| (c.dst, c.len)).collect();
            let (running, events) = read_mapped(&read, |views| {
                let running: u32 = bytemuck::pod_read_unaligned(&views[0][..4]);
                let events = (views.len() == 3).then(|| {
                    let eu: Vec<u32> = bytemuck::pod_collect_to_vec(views[1]);
                    (eu, reals_of(precision, views[2]))
                });
                (running, events)
            })?;
            if let Some(seconds) = device_seconds {
                *self.timings.kernel_device.get_or_insert(0.0) += seconds?;
            }
            if tail {
                self.timings.kernel_tail += started.elapsed().as_secs_f64();
                self.timings.tail_dispatches += 1;
            }
            if let (GpuOutput::Events(on_event), Some((eu, er))) = (&mut *mode, events) {
                for k in 0..n_tables {
                    let base = k * (1 + per * EVENT_UINTS);
                    for e in 0..(eu[base] as usize).min(per) {
                        let u = &eu[base + 1 + e * EVENT_UINTS..base + 1 + (e + 1) * EVENT_UINTS];
                        let r0 = (k * per + e) * EVENT_REALS;
                        on_event(first + k, &event_record(u, &er[r0..r0 + EVENT_REALS])?);
                    }
                }
            }
            if running == 0 {
                break;
            }
            if compact {
                n_active = running;
            }
        }
        Ok(())
    }

    /// Only the I/O region (for a study, the watch region instead) copied to the readback
    /// buffers and mapped, for [`unpack_chunk`].
    fn read_back_chunk(&mut self, call: &ChunkCall<'_>) -> Result<ReadBack, Error> {
        let clock = Instant::now();
        let l = &call.layout;
        let watch_cue = call.watch_cue;
        let n_tables = call.input.len();
        let real = self.precision.real_size();
        let bufs = self.bufs.as_ref().expect("made by buffers");
        let watching = watch_cue != NO_WATCH;
        let io_reals = (n_tables * l.io_reals * real) as u64;
        let io_uints = (n_tables * l.io_uints * 4) as u64;
        let watch_reals = (n_tables * l.watch_reals * real) as u64;
        let watch_uints = (n_tables * l.watch_uints * 4) as u64;
        // a study's tables: the watch region alone (it holds the tables' ends), which
        // follows the I/O and cache regions; else the I/O region
        let copies = if watching {
            [
                Copy {
                    src: &bufs.state_r,
                    offset: (n_tables * (l.io_reals + l.cache_reals) * real) as u64,
                    dst: &bufs.back_r,
                    len: watch_reals,
                },
                Copy {
                    src: &bufs.state_u,
                    offset: (n_tables * (l.io_uints + l.cache_uints) * 4) as u64,
                    dst: &bufs.back_u,
                    len: watch_uints,
                },
            ]
        } else {
            [
                Copy {
                    src: &bufs.state_r,
                    offset: 0,
                    dst: &bufs.back_r,
                    len: io_reals,
                },
                Copy {
                    src: &bufs.state_u,
                    offset: 0,
                    dst: &bufs.back_u,
                    len: io_uints,
                },
            ]
        };
        self.submit_copies(&copies)?;
        self.timings.readback += clock.elapsed().as_secs_f64();
        Ok(ReadBack {
            back_r: bufs.back_r.clone(),
            back_u: bufs.back_u.clone(),
            len_r: copies[0].len,
            len_u: copies[1].len,
            layout: call.layout,
            watched: watching.then_some(call.watch_facts),
            unmapped: false,
        })
    }

    /// One submission: a dispatch of `groups` workgroups (none where `None`; timed on the
    /// device where the adapter has timestamps, the timer's readback mapped too), then
    /// `copies`; waits and maps each copy's destination. Any failure (validation, out of
    /// memory, a lost device, a failed map) is an error, and no buffer is left mapped then;
    /// on success the caller reads and unmaps them ([`read_mapped`]).
    fn submit(
        &self,
        groups: Option<[u32; 2]>,
        bind: &wgpu::BindGroup,
        copies: &[Copy<'_>],
    ) -> Result<(), Error> {
        let dev = &self.device;
        let scopes = Scopes::push(dev);
        let mut encoder = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("kisstime event loop"),
        });
        // the event loop's pass timed on the device, where it can be
        let timer = groups.and(self.timer.as_ref());
        if let Some([x, y]) = groups {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("kisstime event loop"),
                timestamp_writes: timer.map(PassTimer::writes),
            });
            let layout = self.bufs.as_ref().map(|b| b.layout);
            let pipeline = self
                .pipelines
                .iter()
                .find(|(l, _)| Some(*l) == layout)
                .map(|(_, p)| p)
                .ok_or_else(|| gpu_error("no pipeline for the buffers' layout"))?;
            pass.set_pipeline(&pipeline.simulate);
            pass.set_bind_group(0, bind, &[]);
            pass.dispatch_workgroups(x, y, 1);
        }
        // copies into the same destination go one after the other in it
        let mut filled: Vec<(&wgpu::Buffer, u64)> = Vec::new();
        for c in copies {
            let at = match filled.iter_mut().find(|(b, _)| std::ptr::eq(*b, c.dst)) {
                Some((_, used)) => {
                    let at = *used;
                    *used += c.len;
                    at
                }
                None => {
                    filled.push((c.dst, c.len));
                    0
                }
            };
            encoder.copy_buffer_to_buffer(c.src, c.offset, c.dst, at, c.len);
        }
        if let Some(timer) = timer {
            filled.push(timer.resolve(&mut encoder));
        }
        self.queue.submit([encoder.finish()]);
        map_and_wait(dev, scopes, &self.watch, &filled, "the GPU event loop")
    }

    /// [`GpuSimulator::submit`] of copies alone.
    fn submit_copies(&self, copies: &[Copy<'_>]) -> Result<(), Error> {
        let bind = &self.bufs.as_ref().expect("made by buffers").bind;
        self.submit(None, bind, copies)
    }
}

/// Every table of the chunk checked as the CPU loop checks it and its I/O block laid
/// out, then copied to the mapped upload buffers: the strikes' event records (with
/// their tables' places in the chunk) and the runs so far (none for a watched chunk).
fn pack_chunk(
    precision: Precision,
    call: &ChunkCall<'_>,
    host: &mut HostBlocks,
) -> Result<PackedChunk, Error> {
    if let Some(packed) = pack_drawn(precision, call, host)? {
        return Ok(packed);
    }
    if let Some(packed) = pack_expanded(precision, call, host)? {
        return Ok(packed);
    }
    let (table, physics, limits, input, first) = (
        call.table,
        call.physics,
        call.limits,
        call.input,
        call.first,
    );
    let l = &call.layout;
    let (record, watch_cue) = (call.record, call.watch_cue);
    let n_tables = input.len();
    let real = precision.real_size();
    // every table checked as the CPU loop checks it and laid out in the shader's
    // precision in host arrays kept across calls, Rayon over blocks of tables (the upload
    // copies them to the mapped upload buffers in large blocks: mapped memory may be
    // write-combining, and large sequential copies suit it)
    let len_r = (n_tables * l.io_reals * real) as u64;
    let len_u = (n_tables * l.io_uints * 4) as u64;
    let (host_r, host_u) = (&mut host.r, &mut host.u);
    host_r.resize(len_r as usize, 0);
    host_u.resize(len_u as usize, 0);
    // checked tables were checked by the caller
    let layout_checked = matches!(input, Input::Checked { .. });
    let make_runs = watch_cue == NO_WATCH;
    // a block's strike records (with their tables' places in the chunk) and its runs
    type Block = (Vec<(usize, EventRecord)>, Vec<GpuRun>);
    let packed: Vec<Result<Block, Error>> = host_r
        .par_chunks_mut(PACK_BLOCK * l.io_reals * real)
        .zip(host_u.par_chunks_mut(PACK_BLOCK * l.io_uints * 4))
        .enumerate()
        .map(|(b, (dst_r, dst_u))| {
            let start = b * PACK_BLOCK;
            let end = n_tables.min(start + PACK_BLOCK);
            let mut strikes = Vec::new();
            // each run's ball array made (and first written) here, beside its table's
            // layout: made in the unpack instead, the memory's first touch cost the
            // H200's host twice as much
            let mut runs = Vec::with_capacity(if make_runs { end - start } else { 0 });
            let mut buf = Vec::new();
            for (j, k) in (start..end).enumerate() {
                let (balls, strike) = input
                    .shot(k, &mut buf)
                    .map_err(|e| InputError::new(format!("table {}: {e}", first + k)))?;
                if make_runs {
                    runs.push(unfinished_run(balls));
                }
                let mut sr = [0.0; MAX_LAYOUT.io_reals];
                let mut su = [0u32; MAX_LAYOUT.io_uints];
                let (sr, su) = (&mut sr[..l.io_reals], &mut su[..l.io_uints]);
                let shot = ShotRef {
                    at: first + k,
                    balls,
                    strike,
                    layout_checked,
                };
                let params = physics.of(k);
                let record = pack_table(table, &params, limits, l, shot, record, sr, su)?;
                if let Some(record) = record {
                    strikes.push((k, record));
                }
                let at_r = j * l.io_reals * real;
                put_reals(precision, sr, &mut dst_r[at_r..at_r + l.io_reals * real]);
                let at_u = j * l.io_uints * 4;
                dst_u[at_u..at_u + l.io_uints * 4].copy_from_slice(bytemuck::cast_slice(su));
            }
            Ok((strikes, runs))
        })
        .collect();
    let mut strikes: Vec<(usize, EventRecord)> = Vec::new();
    let mut runs: Vec<GpuRun> = Vec::with_capacity(if make_runs { n_tables } else { 0 });
    let mut failed = None;
    for block in packed {
        match block {
            Ok((block_strikes, block_runs)) => {
                strikes.extend(block_strikes);
                runs.extend(block_runs);
            }
            Err(e) => {
                failed = Some(e);
                break;
            }
        }
    }
    if let Some(e) = failed {
        return Err(e);
    }
    Ok(PackedChunk {
        strikes,
        runs,
        expansion: Expansion::Whole,
    })
}

/// The position a chunk of one position struck many ways starts from, and the ball its
/// first table strikes: checked tables with the [`CheckedTables::one_position`] hint, no
/// events recorded, the first table's balls at rest (stationary or pocketed, their clocks
/// set to 0) and within the bucket, a strike. `None` for any other chunk (it is packed
/// whole). The expansions check the other tables against it, or the caller did.
fn chunk_position(call: &ChunkCall<'_>) -> Option<(Vec<BallState>, usize)> {
    let input = call.input;
    let Input::Checked { tables, .. } = input else {
        return None;
    };
    if !tables.one_position || call.record || input.len() == 0 {
        return None;
    }
    let mut buf = Vec::new();
    let Ok((balls, Some((cue, _)))) = input.shot(0, &mut buf) else {
        return None;
    };
    let at_rest = |b: &BallState| matches!(b.s, MotionState::Stationary | MotionState::Pocketed);
    if balls.len() > call.layout.gpu_max_balls || !balls.iter().all(at_rest) {
        return None;
    }
    Some((
        balls.iter().map(|b| BallState { t: 0.0, ..*b }).collect(),
        cue,
    ))
}

/// A chunk whose strikes the device draws ([`CheckedTables::drawn`], with
/// `one_position`, shared physics, no events recorded, the position at rest and on the
/// bucket) packed as the position's I/O block ([`start_table`] without the strike) and the
/// header of [`drawn_block`], for the shader's `expand_drawn` to draw each table's strike
/// and lay the tables out: what crosses the bus does not grow with the tables. The caller
/// checked the tables against the rule; the first table's balls are the position. `None`
/// for any other chunk.
fn pack_drawn(
    precision: Precision,
    call: &ChunkCall<'_>,
    host: &mut HostBlocks,
) -> Result<Option<PackedChunk>, Error> {
    let (physics, limits, input) = (call.physics, call.limits, call.input);
    let Input::Checked { tables, offset } = input else {
        return Ok(None);
    };
    let Some(drawn) = tables.drawn.map(|d| d.from(offset)) else {
        return Ok(None);
    };
    if !physics.is_shared() {
        return Ok(None);
    }
    let Some((position, cue)) = chunk_position(call) else {
        return Ok(None);
    };
    let l = &call.layout;
    let real = precision.real_size();
    let (host_r, host_u) = (&mut host.r, &mut host.u);
    host_r.resize((l.io_reals + DRAWN_REALS) * real, 0);
    host_u.resize((l.io_uints + DRAWN_UINTS) * 4, 0);
    let params = physics.of(0);
    let mut sr = [0.0; MAX_LAYOUT.io_reals];
    let mut su = [0u32; MAX_LAYOUT.io_uints];
    let (sr, su) = (&mut sr[..l.io_reals], &mut su[..l.io_uints]);
    start_table(&position, None, &params, limits, false, l, sr, su);
    put_reals(precision, sr, &mut host_r[..l.io_reals * real]);
    host_u[..l.io_uints * 4].copy_from_slice(bytemuck::cast_slice(su));
    let (mut hr, mut hu) = ([0.0; DRAWN_REALS], [0u32; DRAWN_UINTS]);
    drawn_block(&position, &drawn, &params, limits, &mut hr, &mut hu);
    put_reals(
        precision,
        &hr,
        &mut host_r[l.io_reals * real..(l.io_reals + DRAWN_REALS) * real],
    );
    host_u[l.io_uints * 4..(l.io_uints + DRAWN_UINTS) * 4]
        .copy_from_slice(bytemuck::cast_slice(&hu));
    // the runs so far (for final states; a watched chunk reads its watches back instead)
    let runs = match call.watch_cue == NO_WATCH {
        true => (0..input.len())
            .map(|_| unfinished_run(&position))
            .collect(),
        false => Vec::new(),
    };
    Ok(Some(PackedChunk {
        strikes: Vec::new(),
        runs,
        expansion: Expansion::Drawn { cue: cue as u32 },
    }))
}

/// A chunk of one position struck many ways ([`CheckedTables::one_position`], no
/// events recorded, every ball of the position stationary or pocketed, every table
/// striking the same ball) packed as the position's I/O block ([`start_table`] without
/// the strike) and each table's strike block ([`strike_block`]), for the shader's
/// `expand_tables` to lay the tables out on the device: 104 bytes a table cross the
/// bus instead of a whole block. `None` for any other chunk.
fn pack_expanded(
    precision: Precision,
    call: &ChunkCall<'_>,
    host: &mut HostBlocks,
) -> Result<Option<PackedChunk>, Error> {
    let (physics, limits, input, first) = (call.physics, call.limits, call.input, call.first);
    let Some((position, cue)) = chunk_position(call) else {
        return Ok(None);
    };
    let l = &call.layout;
    let n_tables = input.len();
    let real = precision.real_size();
    // the position's block, then each table's strike block, in the shader's precision
    let (host_r, host_u) = (&mut host.r, &mut host.u);
    host_r.resize((l.io_reals + n_tables * STRUCK_REALS) * real, 0);
    host_u.resize((l.io_uints + n_tables * STRUCK_UINTS) * 4, 0);
    let (head_r, blocks_r) = host_r.split_at_mut(l.io_reals * real);
    let (head_u, blocks_u) = host_u.split_at_mut(l.io_uints * 4);
    let mut sr = [0.0; MAX_LAYOUT.io_reals];
    let mut su = [0u32; MAX_LAYOUT.io_uints];
    let (sr, su) = (&mut sr[..l.io_reals], &mut su[..l.io_uints]);
    start_table(&position, None, &physics.of(0), limits, false, l, sr, su);
    put_reals(precision, sr, head_r);
    head_u.copy_from_slice(bytemuck::cast_slice(su));
    let make_runs = call.watch_cue == NO_WATCH;
    // Rayon over blocks of tables: each table checked as pack_table checks it; a table
    // that strikes another ball (or none) leaves the chunk to the whole blocks
    let packed: Vec<Result<Option<Vec<GpuRun>>, Error>> = blocks_r
        .par_chunks_mut(PACK_BLOCK * STRUCK_REALS * real)
        .zip(blocks_u.par_chunks_mut(PACK_BLOCK * STRUCK_UINTS * 4))
        .enumerate()
        .map(|(b, (dst_r, dst_u))| {
            let start = b * PACK_BLOCK;
            let end = n_tables.min(start + PACK_BLOCK);
            let mut runs = Vec::with_capacity(if make_runs { end - start } else { 0 });
            let mut buf = Vec::new();
            for (j, k) in (start..end).enumerate() {
                let bad = |e: SimError| InputError::new(format!("table {}: {e}", first + k));
                let (balls, strike) = input.shot(k, &mut buf).map_err(bad)?;
                let same =
                    |(b, p): (&BallState, &BallState)| (b.r, b.v, b.w, b.s) == (p.r, p.v, p.w, p.s);
                let Some((c, s)) = strike.filter(|(c, _)| *c == cue) else {
                    return Ok(None);
                };
                if balls.len() != position.len() || !balls.iter().zip(&position).all(same) {
                    return Ok(None);
                }
                EventLoop::check_input(balls, strike).map_err(bad)?;
                let (mut r, mut u) = ([0.0; STRUCK_REALS], [0u32; STRUCK_UINTS]);
                strike_block(&position, (c, s), &physics.of(k), limits, &mut r, &mut u);
                let at_r = j * STRUCK_REALS * real;
                put_reals(precision, &r, &mut dst_r[at_r..at_r + STRUCK_REALS * real]);
                let at_u = j * STRUCK_UINTS * 4;
                dst_u[at_u..at_u + STRUCK_UINTS * 4].copy_from_slice(bytemuck::cast_slice(&u));
                if make_runs {
                    runs.push(unfinished_run(balls));
                }
            }
            Ok(Some(runs))
        })
        .collect();
    let mut runs = Vec::with_capacity(if make_runs { n_tables } else { 0 });
    let mut whole = true;
    let mut failed = None;
    for block in packed {
        match block {
            Ok(Some(block_runs)) => runs.extend(block_runs),
            Ok(None) => whole = false,
            Err(e) => {
                failed = Some(e);
                break;
            }
        }
    }
    if let Some(e) = failed {
        return Err(e);
    }
    Ok(whole.then_some(PackedChunk {
        strikes: Vec::new(),
        runs,
        expansion: Expansion::Strikes { cue: cue as u32 },
    }))
}

/// A chunk's results copied to the readback buffers and mapped ([`GpuSimulator`]'s
/// `read_back_chunk`), waiting for [`unpack_chunk`]: the buffers are unmapped then, or
/// when this is dropped unread (a later failure).
struct ReadBack {
    back_r: wgpu::Buffer,
    back_u: wgpu::Buffer,
    len_r: u64,
    len_u: u64,
    layout: SimLayout,
    /// `Some(facts)` for watched runs (with the rules' facts where `facts`).
    watched: Option<bool>,
    unmapped: bool,
}

impl Drop for ReadBack {
    fn drop(&mut self) {
        if !self.unmapped {
            self.back_r.unmap();
            self.back_u.unmap();
        }
    }
}

/// A chunk's readback unpacked into its `runs` (or into the watched runs), Rayon over
/// tables; the readback buffers unmapped, whatever happened. Touches no device queue, so
/// the host runs it while the device runs the next chunk.
fn unpack_chunk(
    precision: Precision,
    mut back: ReadBack,
    runs: &mut [GpuRun],
) -> Result<Vec<WatchedRun>, Error> {
    let mapped = [(&back.back_r, back.len_r), (&back.back_u, back.len_u)];
    let out = read_mapped(&mapped, |views| {
        unpack(
            precision,
            &back.layout,
            runs,
            views[0],
            views[1],
            back.watched,
        )
    });
    back.unmapped = true;
    out?
}

/// Tables per chunk for a batch of `n` tables, at most `most`: a large batch (at least
/// twice [`PIPELINE_MIN_TABLES`]) in `chunks` chunks of at least [`PIPELINE_MIN_TABLES`],
/// so that the host's packing and unpacking of one chunk overlap the device's run of
/// another.
fn chunk_tables(n: usize, most: usize, chunks: usize) -> usize {
    let most = most.max(1);
    if n >= 2 * PIPELINE_MIN_TABLES {
        most.min(n.div_ceil(chunks.max(1)).max(PIPELINE_MIN_TABLES))
    } else {
        most
    }
}

/// A table's run before it is simulated: its balls, no event (the unpacking fills it).
fn unfinished_run(balls: &[BallState]) -> GpuRun {
    GpuRun {
        events: Vec::new(),
        balls: balls.to_vec(),
        outcome: Outcome {
            n_events: 0,
            t_end: 0.0,
            cut: None,
        },
    }
}

/// Tables packed by one Rayon task.
const PACK_BLOCK: usize = 256;

/// Threads of one `expand_tables` workgroup (its `@workgroup_size`).
const EXPAND_THREADS: u32 = 64;

/// One table to pack: its position in the batch, balls and strike, and whether its
/// layout was checked already (one position struck many ways).
struct ShotRef<'a> {
    at: usize,
    balls: &'a [BallState],
    strike: Option<(usize, CueStrike)>,
    layout_checked: bool,
}

/// Checks a table as the CPU loop checks it ([`check_layout`] unless done, and
/// [`EventLoop::check_input`]) and lays out its I/O block at its start in `sr` and `su`;
/// returns its run so far and the strike's event record.
#[allow(clippy::too_many_arguments)]
fn pack_table(
    table: &Table,
    params: &SimParams,
    limits: Limits,
    layout: &SimLayout,
    shot: ShotRef<'_>,
    record: bool,
    sr: &mut [f64],
    su: &mut [u32],
) -> Result<Option<EventRecord>, Error> {
    let at = shot.at;
    let bad = |e: SimError| Error::from(InputError::new(format!("table {at}: {e}")));
    if shot.balls.len() > layout.gpu_max_balls {
        return Err(Error::Unsupported(format!(
            "table {at}: {} balls, the GPU event loop was built for at most {}",
            shot.balls.len(),
            layout.gpu_max_balls
        )));
    }
    if !shot.layout_checked {
        check_layout(table, params.ball.r, shot.balls).map_err(bad)?;
    }
    EventLoop::check_input(shot.balls, shot.strike).map_err(bad)?;
    Ok(start_table(
        shot.balls,
        shot.strike,
        params,
        limits,
        record,
        layout,
        sr,
        su,
    ))
}

/// One copy of a submission: `len` bytes of `src` from `offset` to the readback buffer
/// `dst` (after the copies into `dst` before it).
struct Copy<'b> {
    src: &'b wgpu::Buffer,
    offset: u64,
    dst: &'b wgpu::Buffer,
    len: u64,
}

/// `f` of the first `len` bytes of each mapped buffer of `buffers`, which are all
/// unmapped then, whatever happened.
fn read_mapped<T>(
    buffers: &[(&wgpu::Buffer, u64)],
    f: impl FnOnce(&[&[u8]]) -> T,
) -> Result<T, Error> {
    let views: Result<Vec<wgpu::BufferView>, _> = buffers
        .iter()
        .map(|(b, len)| b.slice(..*len).get_mapped_range())
        .collect();
    let out = match views {
        Ok(views) => {
            let slices: Vec<&[u8]> = views.iter().map(|v| &v[..]).collect();
            Ok(f(&slices))
        }
        Err(e) => Err(gpu_error(format!("the results are not readable: {e}"))),
    };
    for (b, _) in buffers {
        b.unmap();
    }
    out
}

/// The runs (final states and outcomes) from the I/O blocks, or with `watch =
/// Some(facts)` the watched runs (with the rules' facts where `facts`) from the watch
/// blocks alone (each ends with its table's end), Rayon over tables.
fn unpack(
    precision: Precision,
    l: &SimLayout,
    runs: &mut [GpuRun],
    back_r: &[u8],
    back_u: &[u8],
    watch: Option<bool>,
) -> Result<Vec<WatchedRun>, Error> {
    let real = precision.real_size();
    let Some(facts) = watch else {
        let n = runs.len();
        let (io_r, io_u) = (
            &back_r[..n * l.io_reals * real],
            &back_u[..n * l.io_uints * 4],
        );
        runs.par_iter_mut()
            .zip(io_r.par_chunks(l.io_reals * real))
            .zip(io_u.par_chunks(l.io_uints * 4))
            .try_for_each(|((run, r), u)| {
                let (sr, su) = block::<{ MAX_LAYOUT.io_reals }, { MAX_LAYOUT.io_uints }>(
                    precision,
                    (r, l.io_reals),
                    (u, l.io_uints),
                );
                finish_table(l, run, &sr[..l.io_reals], &su[..l.io_uints])
            })?;
        return Ok(Vec::new());
    };
    // a watched batch: as many tables as its watch blocks, each with the table's end
    let n = back_u.len() / (l.watch_uints * 4);
    back_r[..n * l.watch_reals * real]
        .par_chunks(l.watch_reals * real)
        .zip(back_u[..n * l.watch_uints * 4].par_chunks(l.watch_uints * 4))
        .map(|(wr, wu)| {
            let (wsr, wsu) = block::<{ MAX_LAYOUT.watch_reals }, { MAX_LAYOUT.watch_uints }>(
                precision,
                (wr, l.watch_reals),
                (wu, l.watch_uints),
            );
            let (wsr, wsu) = (&wsr[..l.watch_reals], &wsu[..l.watch_uints]);
            let (cue, outcome, n_balls) = watched_end(l, wsr, wsu)?;
            Ok(WatchedRun {
                cue,
                outcome,
                watch: read_watch(l, wsr, wsu, n_balls, facts)?,
            })
        })
        .collect()
}

/// One table's block read back (`reals` reals in the shader's precision and `uints` u32s,
/// each with its count) into stack arrays as f64 and u32 (their first counts filled).
fn block<const R: usize, const U: usize>(
    precision: Precision,
    (reals, n_reals): (&[u8], usize),
    (uints, n_uints): (&[u8], usize),
) -> ([f64; R], [u32; U]) {
    let mut sr = [0.0; R];
    reals_into(precision, reals, &mut sr[..n_reals]);
    let mut su = [0u32; U];
    uints_into(uints, &mut su[..n_uints]);
    (sr, su)
}

/// One table's parameter block as the shader reads it (`SIM_REALS`: the ball's, the
/// resolver's, then max_time).
fn param_block(params: &SimParams, limits: Limits) -> [f64; SIM_REALS] {
    let b = &params.ball;
    let r = &params.resolver;
    let mut block = [
        b.m,
        b.r,
        b.u_s,
        b.u_r,
        b.u_sp,
        b.u_b,
        b.e_b,
        b.e_c,
        b.f_c,
        b.g,
        r.alciatore_a,
        r.alciatore_b,
        r.alciatore_c,
        r.omega_ratio,
        r.beta_t,
        r.beta_n,
        r.k_n,
        r.spacer,
        0.0,
    ];
    // `inf` (no time limit) as the largest finite number: the same comparisons, and no
    // infinity in a buffer (WGSL leaves its handling to the implementation)
    block[SIM_R_MAX_TIME] = limits.max_time.min(f64::MAX);
    block
}

/// `v` in the shader's precision, as bytes.
fn real_bytes(precision: Precision, v: &[f64]) -> Vec<u8> {
    let mut out = vec![0; v.len() * precision.real_size()];
    put_reals(precision, v, &mut out);
    out
}

/// Writes `v` into `dst` in the shader's precision (f32: the host's never as the
/// shader's).
fn put_reals(precision: Precision, v: &[f64], dst: &mut [u8]) {
    match precision {
        Precision::F64 => {
            for (x, d) in v.iter().zip(dst.chunks_exact_mut(8)) {
                d.copy_from_slice(&x.to_le_bytes());
            }
        }
        Precision::F32 => {
            for (&x, d) in v.iter().zip(dst.chunks_exact_mut(4)) {
                let narrow = if x >= NEVER_F64 { NEVER_F32 } else { x as f32 };
                d.copy_from_slice(&narrow.to_le_bytes());
            }
        }
    }
}

/// Reals read back in the shader's precision into `out`, as f64.
fn reals_into(precision: Precision, bytes: &[u8], out: &mut [f64]) {
    match precision {
        Precision::F64 => {
            for (o, b) in out.iter_mut().zip(bytes.chunks_exact(8)) {
                *o = f64::from_le_bytes(b.try_into().expect("8 bytes"));
            }
        }
        Precision::F32 => {
            for (o, b) in out.iter_mut().zip(bytes.chunks_exact(4)) {
                *o = f64::from(f32::from_le_bytes(b.try_into().expect("4 bytes")));
            }
        }
    }
}

/// u32s read back into `out`.
fn uints_into(bytes: &[u8], out: &mut [u32]) {
    for (o, b) in out.iter_mut().zip(bytes.chunks_exact(4)) {
        *o = u32::from_le_bytes(b.try_into().expect("4 bytes"));
    }
}

/// Reals read back in the shader's precision, as f64.
fn reals_of(precision: Precision, bytes: &[u8]) -> Vec<f64> {
    let mut out = vec![0.0; bytes.len() / precision.real_size()];
    reals_into(precision, bytes, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_large_batch_is_cut_into_a_few_chunks_of_many_tables() {
        let min = PIPELINE_MIN_TABLES;
        let chunks = |n, most| chunk_tables(n, most, PIPELINE_CHUNKS);
        // small batches: one chunk, or the limit's
        assert_eq!(chunks(1000, MAX_TABLES_PER_CHUNK), MAX_TABLES_PER_CHUNK);
        assert_eq!(
            chunks(2 * min - 1, MAX_TABLES_PER_CHUNK),
            MAX_TABLES_PER_CHUNK
        );
        assert_eq!(chunks(1000, 7), 7);
        assert_eq!(chunks(1000, 0), 1);
        // large ones: PIPELINE_CHUNKS chunks, none smaller than the minimum
        assert_eq!(chunks(2 * min, MAX_TABLES_PER_CHUNK), min);
        assert_eq!(chunks(1_000_000, MAX_TABLES_PER_CHUNK), 250_000);
        assert_eq!(chunks(1 << 18, MAX_TABLES_PER_CHUNK), 1 << 16);
        assert_eq!(chunks(100_000, MAX_TABLES_PER_CHUNK), min);
        // the bindings' limit still rules
        assert_eq!(chunks(1_000_000, 1000), 1000);
        for n in [2 * min, 100_000, 1_000_000, 4 * MAX_TABLES_PER_CHUNK] {
            let chunk = chunks(n, MAX_TABLES_PER_CHUNK);
            let count = n.div_ceil(chunk);
            assert!(
                chunk >= min && (2..=PIPELINE_CHUNKS).contains(&count),
                "{n}: {chunk}"
            );
        }
        // beyond that the chunks are the largest allowed
        assert_eq!(
            chunks(10_000_000, MAX_TABLES_PER_CHUNK),
            MAX_TABLES_PER_CHUNK
        );
        // KISSTIME_GPU_PIPELINE_CHUNKS: one chunk where the limit allows, or more
        assert_eq!(chunk_tables(1_000_000, MAX_TABLES_PER_CHUNK, 1), 1_000_000);
        assert_eq!(chunk_tables(1_000_000, MAX_TABLES_PER_CHUNK, 8), 125_000);
        assert_eq!(chunk_tables(100_000, MAX_TABLES_PER_CHUNK, 0), 100_000);
    }
}
