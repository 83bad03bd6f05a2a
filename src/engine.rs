//! Backend choice: one [`Engine`] answers collision batches, and one [`ShotEngine`]
//! simulates whole shots and shot studies, on the CPU, on the GPU, or on the GPU with the
//! CPU as fallback (`auto`).
//!
//! `auto` chooses the backend expected to be faster, by a rule from the measurements
//! (BENCHMARKS.md, an H200 beside 16 CPU cores):
//! - never a software (CPU-type) adapter such as Mesa's lavapipe: the CPU path is faster;
//! - whole shots and studies on a hardware GPU, for batches of at least
//!   [`auto_gpu_min_tables`] tables (samples); smaller ones on the CPU; a study only
//!   where the CPU has at most [`AUTO_STUDY_MAX_CPU_THREADS`] threads (more beat the GPU's
//!   study);
//! - the pair kernels (`pairs`, `next`) on the CPU: end to end (upload and readback
//!   included) the GPU's kernels are slower than the CPU's.
//!
//! Setting `KISSTIME_AUTO_GPU=always` makes `auto` use any adapter that opens, for every
//! size and for the kernels (how the tests exercise the GPU paths and the fallback on
//! lavapipe). Where `auto` chooses the CPU it leaves a note that says why, and
//! `describe` names what ran. A GPU failure during a batch (device lost, failed dispatch)
//! redoes that batch on the CPU, again with a note. `gpu` reports such failures as errors
//! and runs wherever it is asked. The CPU backend computes in f64 only; a fallback from
//! GPU f32 therefore computes in f64.

use crate::batch::{Batch, NextCollision};
use crate::cpu;
use crate::error::Error;
use crate::error::SimError;
use crate::gpu::{CheckedTables, GpuEngine, GpuOutput, GpuRun, GpuShot, GpuSimulator};
use crate::model::Params;
pub use crate::model::Precision;
use crate::model::ball_state::BallState;
use crate::model::sim_params::Physics;
use crate::model::table::Table;
use crate::query::ball_ball::Contact;
use crate::resolve::stick_ball::CueStrike;
use crate::simulate::batch::{EventRecord, check_input};
use crate::simulate::{
    BatchError, BatchOptions, BatchStats, Chunk, DrawnStrikes, EventLoop, Limits, simulate_batch,
};
use std::ops::Range;
use std::time::Instant;

use rayon::prelude::*;

/// Whole-shot batches and studies of fewer tables (samples) than this many per CPU
/// thread run on the CPU under `auto` ([`auto_gpu_min_tables`]): below it the GPU's fixed
/// costs (a dispatch and a readback every 32 events, ~25 for ordinary shots) outweigh its
/// speed. Measured on an H200 beside 16 threads (BENCHMARKS.md): 2,000 ordinary shots
/// ran at 74k shots/s on the GPU and 197k on the CPU, 10,000 at 361k and 206k; the
/// crossing, ~7,200 tables, is ~450 a thread.
pub const AUTO_GPU_MIN_TABLES_PER_THREAD: usize = 512;

/// `auto` runs a shot study on the GPU only where the CPU has at most this many threads:
/// measured on an H200 beside 16 threads (BENCHMARKS.md), the GPU's study of 10⁶ samples
/// ran at 470k samples/s end to end and the CPU's at 732k, ~46k a thread.
pub const AUTO_STUDY_MAX_CPU_THREADS: usize = 8;

/// Tables per chunk of [`ShotEngine::simulate_with`] on the GPU without recorded events:
/// large enough to fill an H200 (its event loop runs one workgroup a table), small enough
/// that a chunk's final states (~1 KB a table) stay a few hundred MB.
pub const GPU_STREAM_TABLES: usize = 1 << 18;

/// Tables per chunk of [`ShotEngine::simulate_with`] on the GPU when events are recorded:
/// a chunk of breaks (~200 events each, ~200 bytes an event kept) holds some 650 MB.
pub const GPU_STREAM_TABLES_EVENTS: usize = 1 << 14;

/// The smallest batch `auto` sends to the GPU here: [`AUTO_GPU_MIN_TABLES_PER_THREAD`]
/// times the CPU threads (8,192 with 16).
pub fn auto_gpu_min_tables() -> usize {
    AUTO_GPU_MIN_TABLES_PER_THREAD * rayon::current_num_threads()
}

/// Why whole shots and studies refuse f32 (the pair kernels keep it).
pub const F32_WHOLE_SHOTS: &str = "whole shots and studies are simulated in f64 only \
     (--precision f64): in f32 the GPU decides contacts to a micrometre, chattering balls \
     multiply their events, and about half of the held-out reference shots end elsewhere \
     than pooltool's (BENCHMARKS.md); f32 is for the pair kernels (pairs, next)";

/// How `auto` chooses (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum AutoRule {
    /// The measured rule: a hardware GPU only, whole shots and studies from
    /// [`auto_gpu_min_tables`] tables, the kernels on the CPU.
    #[default]
    Measured,
    /// Any adapter that opens, for every size and for the kernels (to exercise the GPU
    /// paths and the fallback, e.g. on lavapipe).
    AnyGpu,
}

impl AutoRule {
    /// [`AutoRule::AnyGpu`] where `KISSTIME_AUTO_GPU=always`, else the measured rule.
    pub fn from_env() -> AutoRule {
        if std::env::var("KISSTIME_AUTO_GPU").is_ok_and(|v| v == "always") {
            AutoRule::AnyGpu
        } else {
            AutoRule::Measured
        }
    }
}

/// The backend used when none is asked for: the CPU, the reference.
pub const DEFAULT_BACKEND: Backend = Backend::Cpu;
/// The precision used when none is asked for: f64 on the CPU, f32 on a GPU (every GPU has
/// it; f64 only where the adapter offers `SHADER_F64`).
pub fn default_precision(backend: Backend) -> Precision {
    match backend {
        Backend::Cpu => Precision::F64,
        Backend::Gpu | Backend::Auto => Precision::F32,
    }
}

/// Where batches are computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Backend {
    /// Rayon on all cores, f64: the reference.
    Cpu,
    /// A GPU through wgpu; an error when none is usable.
    Gpu,
    /// The GPU when one is usable, else the CPU; GPU failures are redone on the CPU.
    Auto,
}

impl Backend {
    /// `cpu`, `gpu` or `auto`.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Cpu => "cpu",
            Backend::Gpu => "gpu",
            Backend::Auto => "auto",
        }
    }
}

/// What [`Engine`] and [`ShotEngine`] share: the backend asked for, the GPU side while it
/// is in use, and the notes about fallbacks.
struct Chosen<G> {
    backend: Backend,
    rule: AutoRule,
    gpu: Option<G>,
    notes: Vec<String>,
}

/// The GPU side of a backend ([`GpuEngine`] for the kernels, [`GpuSimulator`] for shots).
trait GpuSide: Sized {
    /// Whether `auto` uses it at all (where it can beat the CPU end to end).
    const AUTO_PAYS: bool;
    /// Why `auto` does not, for the note.
    const AUTO_WHY_NOT: &'static str = "";
    /// Opens it in `precision`.
    fn open(precision: Precision) -> Result<Self, Error>;
    /// Its precision.
    fn precision(&self) -> Precision;
    /// Its adapter.
    fn adapter(&self) -> &crate::gpu::AdapterSummary;
}

impl GpuSide for GpuEngine {
    const AUTO_PAYS: bool = false;
    const AUTO_WHY_NOT: &'static str = "end to end (upload and readback included) the GPU's \
         pair kernels are slower than the CPU's (BENCHMARKS.md)";
    fn open(precision: Precision) -> Result<Self, Error> {
        GpuEngine::new(precision)
    }
    fn precision(&self) -> Precision {
        GpuEngine::precision(self)
    }
    fn adapter(&self) -> &crate::gpu::AdapterSummary {
        GpuEngine::adapter(self)
    }
}

impl GpuSide for GpuSimulator {
    const AUTO_PAYS: bool = true;
    fn open(precision: Precision) -> Result<Self, Error> {
        GpuSimulator::new(precision)
    }
    fn precision(&self) -> Precision {
        GpuSimulator::precision(self)
    }
    fn adapter(&self) -> &crate::gpu::AdapterSummary {
        GpuSimulator::adapter(self)
    }
}

impl<G: GpuSide> Chosen<G> {
    /// Opens `backend` (see [`Engine::new`]); `doing` names the work in the notes
    /// ("computing", "simulating").
    fn open(
        backend: Backend,
        precision: Precision,
        rule: AutoRule,
        doing: &str,
    ) -> Result<Chosen<G>, Error> {
        let mut notes = Vec::new();
        let any = rule == AutoRule::AnyGpu;
        let gpu = match backend {
            Backend::Cpu => {
                if precision == Precision::F32 {
                    return Err(Error::Unsupported(
                        "the CPU backend computes in f64 only; use --precision f64, or \
                         --backend gpu/auto for f32"
                            .into(),
                    ));
                }
                None
            }
            Backend::Gpu => Some(G::open(precision)?),
            Backend::Auto if !G::AUTO_PAYS && !any => {
                notes.push(format!(
                    "auto: {}; {doing} on the CPU in f64 (--backend gpu runs it on the GPU)",
                    G::AUTO_WHY_NOT
                ));
                None
            }
            Backend::Auto => match G::open(precision) {
                Ok(g) if g.adapter().is_software() && !any => {
                    notes.push(format!(
                        "auto: the GPU adapter {} is a software (CPU-type) one, slower than \
                         the CPU path; {doing} on the CPU in f64 (--backend gpu runs it there)",
                        g.adapter().name
                    ));
                    None
                }
                Ok(g) => Some(g),
                Err(e) => {
                    notes.push(format!("no usable GPU, {doing} on the CPU in f64: {e}"));
                    None
                }
            },
        };
        Ok(Chosen {
            backend,
            rule,
            gpu,
            notes,
        })
    }

    fn describe(&self) -> String {
        match &self.gpu {
            Some(g) => format!("gpu {}: {}", g.precision().name(), g.adapter()),
            None => cpu_description(),
        }
    }

    /// Runs `on_gpu` when there is a GPU, with the CPU as the `auto` fallback: `what` is
    /// what was redone, for the note ("the batch was").
    fn run<T>(
        &mut self,
        what: &str,
        on_gpu: impl FnOnce(&mut G) -> Result<T, Error>,
        on_cpu: impl FnOnce() -> Result<T, Error>,
    ) -> Result<T, Error> {
        let Some(gpu) = self.gpu.as_mut() else {
            return on_cpu();
        };
        match on_gpu(gpu) {
            Err(e @ (Error::Gpu(_) | Error::GpuUnavailable(_)))
                if self.backend == Backend::Auto =>
            {
                self.notes.push(format!(
                    "{e}; {what} redone on the CPU in f64, and the CPU is used from now on"
                ));
                self.gpu = None;
                on_cpu()
            }
            other => other,
        }
    }
}

/// A configured backend, reusable across many batches (GPU resources are kept).
pub struct Engine {
    chosen: Chosen<GpuEngine>,
}

impl Engine {
    /// Opens the backend.
    ///
    /// Errors: `cpu` with f32 ([`Error::Unsupported`]); `gpu` without a usable adapter or
    /// without f64 support when f64 is asked for ([`Error::GpuUnavailable`]) or a device
    /// that fails to start ([`Error::Gpu`]). `auto` never fails for want of a GPU.
    pub fn new(backend: Backend, precision: Precision) -> Result<Engine, Error> {
        Engine::with_rule(backend, precision, AutoRule::from_env())
    }

    /// [`Engine::new`] with `auto` choosing by `rule`.
    pub fn with_rule(
        backend: Backend,
        precision: Precision,
        rule: AutoRule,
    ) -> Result<Engine, Error> {
        Ok(Engine {
            chosen: Chosen::open(backend, precision, rule, "computing")?,
        })
    }

    /// The backend asked for.
    pub fn backend(&self) -> Backend {
        self.chosen.backend
    }

    /// The GPU engine in use, if any.
    pub fn gpu(&mut self) -> Option<&mut GpuEngine> {
        self.chosen.gpu.as_mut()
    }

    /// What computes the batches now, e.g. `"gpu f32: NVIDIA H100 (Vulkan, …)"` or
    /// `"cpu f64 (2 threads)"`.
    pub fn describe(&self) -> String {
        self.chosen.describe()
    }

    /// Messages for the user about fallbacks since the last call (one line each).
    pub fn take_notes(&mut self) -> Vec<String> {
        std::mem::take(&mut self.chosen.notes)
    }

    /// The answer for every pair of every table, in pair order (see [`crate::batch`]).
    pub fn pair_times(&mut self, batch: &Batch, params: &Params) -> Result<Vec<Contact>, Error> {
        self.pair_times_of(batch, params, 0..batch.num_tables())
    }

    /// The answers for the pairs of the tables `tables` only (positions in the batch): the
    /// slice `batch.pairs_of_tables(tables)` of [`Engine::pair_times`]'s output. Callers
    /// that stream per-pair output over `batch.table_chunks(..)` hold one chunk at a time.
    pub fn pair_times_of(
        &mut self,
        batch: &Batch,
        params: &Params,
        tables: std::ops::Range<usize>,
    ) -> Result<Vec<Contact>, Error> {
        let cpu_tables = tables.clone();
        self.chosen.run(
            redone(batch, &tables),
            |g| g.pair_times_of(batch, params, tables),
            || cpu::pair_times_of(batch, params, cpu_tables),
        )
    }

    /// The next collision of every table, in table order (see [`crate::batch`]).
    pub fn next_collisions(
        &mut self,
        batch: &Batch,
        params: &Params,
    ) -> Result<Vec<NextCollision>, Error> {
        self.next_collisions_of(batch, params, 0..batch.num_tables())
    }

    /// The next collision of the tables `tables` only (positions in the batch): the slice
    /// `tables` of [`Engine::next_collisions`]'s output.
    pub fn next_collisions_of(
        &mut self,
        batch: &Batch,
        params: &Params,
        tables: std::ops::Range<usize>,
    ) -> Result<Vec<NextCollision>, Error> {
        let cpu_tables = tables.clone();
        self.chosen.run(
            redone(batch, &tables),
            |g| g.next_collisions_of(batch, params, tables),
            || cpu::next_collisions_of(batch, params, cpu_tables),
        )
    }
}

/// What a fallback note says was redone on the CPU: the whole batch or a chunk of it.
fn redone(batch: &Batch, tables: &std::ops::Range<usize>) -> &'static str {
    if *tables == (0..batch.num_tables()) {
        "the batch was"
    } else {
        "the chunk was"
    }
}

/// A configured backend for whole shots and shot studies: the CPU's event loop
/// ([`crate::simulate`]), the GPU's ([`GpuSimulator`]), or the GPU with the CPU as
/// fallback (`auto`), reusable across many batches.
///
/// `auto` opens the GPU when it works in the precision asked for and otherwise uses the
/// CPU, with a note; tables of any ball count the CPU takes (up to [`crate::gpu::GPU_MAX_BALLS`]) run on
/// the GPU (on the build for the largest table's bucket); a GPU failure during a batch (device lost, failed dispatch, failed
/// readback) redoes that batch on the CPU in f64 with a note, and the CPU is used from then
/// on. `gpu` reports each of these as an error. Bad input is an error on every backend.
pub struct ShotEngine {
    chosen: Chosen<GpuSimulator>,
    /// Whether the last call ran on the CPU although a GPU is open (`auto`, a small batch).
    last_on_cpu: bool,
    /// Tables per GPU chunk of [`ShotEngine::simulate_with`], where set (else the defaults).
    gpu_chunk: Option<usize>,
}

impl ShotEngine {
    /// Opens the backend, `auto` choosing by [`AutoRule::from_env`]. Errors as
    /// [`Engine::new`].
    pub fn new(backend: Backend, precision: Precision) -> Result<ShotEngine, Error> {
        ShotEngine::with_rule(backend, precision, AutoRule::from_env())
    }

    /// [`ShotEngine::new`] with `auto` choosing by `rule`.
    ///
    /// Whole shots are simulated in f64 only: f32 is refused on every backend
    /// ([`F32_WHOLE_SHOTS`] says why).
    pub fn with_rule(
        backend: Backend,
        precision: Precision,
        rule: AutoRule,
    ) -> Result<ShotEngine, Error> {
        if precision == Precision::F32 && backend != Backend::Cpu {
            return Err(Error::Unsupported(F32_WHOLE_SHOTS.into()));
        }
        Ok(ShotEngine {
            chosen: Chosen::open(backend, precision, rule, "simulating")?,
            last_on_cpu: false,
            gpu_chunk: None,
        })
    }

    /// The backend asked for.
    pub fn backend(&self) -> Backend {
        self.chosen.backend
    }

    /// Sets the tables per GPU chunk of [`ShotEngine::simulate_with`] (at least 1; `None`:
    /// [`GPU_STREAM_TABLES`] or [`GPU_STREAM_TABLES_EVENTS`]). The results do not depend on
    /// it; only memory and speed do.
    pub fn set_gpu_chunk_tables(&mut self, tables: Option<usize>) {
        self.gpu_chunk = tables.map(|n| n.max(1));
    }

    /// The GPU event loop in use, if any.
    pub fn gpu(&mut self) -> Option<&mut GpuSimulator> {
        self.chosen.gpu.as_mut()
    }

    /// What simulated the last call (before any call: what will), e.g. `"gpu f64: NVIDIA
    /// H200 (Vulkan, …)"` or `"cpu f64 (2 threads)"`.
    pub fn describe(&self) -> String {
        if self.last_on_cpu {
            cpu_description()
        } else {
            self.chosen.describe()
        }
    }

    /// Messages for the user about fallbacks since the last call (one line each).
    pub fn take_notes(&mut self) -> Vec<String> {
        std::mem::take(&mut self.chosen.notes)
    }

    /// Whether a call of `n_tables` tables (samples; `study`: a shot study) runs on the
    /// CPU: there is no GPU, or `auto` measured the CPU faster for a batch this small, or
    /// for a study on this many threads. The one place the backend is chosen per call.
    fn cpu_for(&self, n_tables: usize, study: bool) -> bool {
        self.chosen.gpu.is_none()
            || (self.chosen.backend == Backend::Auto
                && self.chosen.rule == AutoRule::Measured
                && (n_tables < auto_gpu_min_tables()
                    || (study && rayon::current_num_threads() > AUTO_STUDY_MAX_CPU_THREADS)))
    }

    /// [`Chosen::run`] for work of `n_tables` tables (samples), on the CPU where
    /// [`ShotEngine::cpu_for`] says so.
    fn run<T>(
        &mut self,
        what: &str,
        n_tables: usize,
        study: bool,
        on_gpu: impl FnOnce(&mut GpuSimulator) -> Result<T, Error>,
        on_cpu: impl FnOnce() -> Result<T, Error>,
    ) -> Result<T, Error> {
        self.last_on_cpu = false;
        if self.chosen.gpu.is_some() && self.cpu_for(n_tables, study) {
            self.last_on_cpu = true;
            return on_cpu();
        }
        self.chosen.run(&format!("{what} was"), on_gpu, on_cpu)
    }

    /// **The** whole-shot entry point: simulates `n_tables` tables on `table` from the
    /// strike to rest (or to a limit) on this engine's backend, and hands the results to
    /// `sink` one [`Chunk`] at a time, in table order, with bounded memory whatever
    /// `n_tables` is. The CLI's `simulate`, the Python module and every other caller come
    /// through here; none of them chooses a backend or converts results itself.
    ///
    /// `input(k, balls)` is [`simulate_batch`]'s: it fills `balls` with table `k`'s balls
    /// (pooltool's ball order) and returns its strike. Each table is checked as
    /// `simulate_batch` checks it, whatever the backend ([`crate::simulate::check_layout`] when
    /// `options.check_layout`, and [`EventLoop::reset`]); the first bad table in table order
    /// stops the run with [`BatchError::Table`] before its chunk reaches the sink. A sink
    /// error is [`BatchError::Sink`]; a backend error (a GPU failure with `gpu`) is
    /// `BatchError::Sink` too, carried as `E: From<Error>`.
    ///
    /// With [`BatchOptions::watch`] (a study's run: `study::run`) each table's results are
    /// its watch ([`crate::simulate::watch`]: the watched ball's first contact and every
    /// pot), its watched ball's final state and its outcome; no event is recorded, and on
    /// the GPU no event crosses the bus. `physics` may be drawn per table
    /// ([`Physics::Drawn`]): nothing is then held per table.
    ///
    /// Backends: the CPU runs [`simulate_batch`] (chunks of `options.chunk_tables`); the GPU
    /// runs chunks of [`GPU_STREAM_TABLES`] tables ([`GPU_STREAM_TABLES_EVENTS`] when events
    /// are recorded; [`ShotEngine::set_gpu_chunk_tables`] changes it), each checked here
    /// (Rayon over tables) and then packed straight from `input` by
    /// [`GpuSimulator::simulate_checked`]; from the second chunk on, the device runs a chunk
    /// while the host hands the chunk before it to `sink` and checks the chunk after it
    /// (`sink` is called on the calling thread, chunk after chunk in order, as on the CPU;
    /// a bad table is reported after the chunks before it reached the sink). `auto` decides for the whole call
    /// ([`auto_gpu_min_tables`]; a watched call by the study's rule,
    /// [`AUTO_STUDY_MAX_CPU_THREADS`]); a GPU failure redoes that chunk and the rest on the
    /// CPU, with a note. The results are the same on every backend (in f64 the same events,
    /// their times within ~1e-12 s on the reference sets; see docs/gpu.md).
    ///
    /// A GPU failure under `auto` after chunks have reached the sink cannot be undone here:
    /// the chunks before it are the GPU's and the rest would be the CPU's, the same events
    /// but not bit for bit. `simulate_with` then finishes on the CPU and its note says
    /// which tables ran where; [`ShotEngine::simulate_restartable`] instead starts the
    /// whole call over on the CPU, so that every result is the CPU's.
    ///
    /// [`BatchStats::sim_seconds`] counts the simulation only (each chunk's check and
    /// run), not the sink's time.
    #[allow(clippy::too_many_arguments)]
    pub fn simulate_with<'p, E: From<Error>>(
        &mut self,
        table: &Table,
        physics: impl Into<Physics<'p>>,
        options: &BatchOptions,
        n_tables: usize,
        input: impl Fn(usize, &mut Vec<BallState>) -> Result<Option<(usize, CueStrike)>, SimError>
        + Sync,
        sink: impl FnMut(&Chunk) -> Result<(), E>,
    ) -> Result<BatchStats, BatchError<E>> {
        self.simulate_inner(table, physics, options, n_tables, input, None, sink)
    }

    /// [`ShotEngine::simulate_with`] for a caller that can start over: where the GPU fails
    /// under `auto` after chunks have reached `sink`, `restart()` is called (it forgets what
    /// the sink was given, or returns the error to stop with) and the whole call is then
    /// redone on the CPU from its first table, with a note, so that every result the sink
    /// keeps is the CPU's, bit for bit. A failure before any chunk reached the sink needs
    /// no restart (that chunk and the rest run on the CPU).
    #[allow(clippy::too_many_arguments)]
    pub fn simulate_restartable<'p, E: From<Error>>(
        &mut self,
        table: &Table,
        physics: impl Into<Physics<'p>>,
        options: &BatchOptions,
        n_tables: usize,
        input: impl Fn(usize, &mut Vec<BallState>) -> Result<Option<(usize, CueStrike)>, SimError>
        + Sync,
        mut restart: impl FnMut() -> Result<(), E>,
        sink: impl FnMut(&Chunk) -> Result<(), E>,
    ) -> Result<BatchStats, BatchError<E>> {
        self.simulate_inner(
            table,
            physics,
            options,
            n_tables,
            input,
            Some(&mut restart),
            sink,
        )
    }

    /// [`ShotEngine::simulate_with`] and [`ShotEngine::simulate_restartable`].
    #[allow(clippy::too_many_arguments)]
    fn simulate_inner<'p, E: From<Error>>(
        &mut self,
        table: &Table,
        physics: impl Into<Physics<'p>>,
        options: &BatchOptions,
        n_tables: usize,
        input: impl Fn(usize, &mut Vec<BallState>) -> Result<Option<(usize, CueStrike)>, SimError>
        + Sync,
        restart: Option<&mut dyn FnMut() -> Result<(), E>>,
        mut sink: impl FnMut(&Chunk) -> Result<(), E>,
    ) -> Result<BatchStats, BatchError<E>> {
        let physics = physics.into();
        // a watched batch is a study's: `auto` chooses for it by the study's rule
        let study = options.watch.is_some();
        self.last_on_cpu = false;
        if self.cpu_for(n_tables, study) {
            self.last_on_cpu = self.chosen.gpu.is_some();
            return simulate_batch(table, physics, options, n_tables, input, sink);
        }
        // the parameters, checked once (each table's, where per table)
        physics
            .check(n_tables)
            .map_err(|(table, error)| BatchError::Table { table, error })?;
        EventLoop::new(table, physics.first(), options.limits, 0)
            .map_err(|error| BatchError::Table { table: 0, error })?;
        let per = self.gpu_chunk.unwrap_or(if options.record_events {
            GPU_STREAM_TABLES_EVENTS
        } else {
            GPU_STREAM_TABLES
        });
        let ranges: Vec<Range<usize>> = (0..n_tables)
            .step_by(per)
            .map(|start| start..n_tables.min(start + per))
            .collect();
        // a study's strikes the device draws itself: shared physics, one position, no events
        // recorded (a watched batch records none)
        let records = options.record_events && options.watch.is_none();
        let drawn = options
            .drawn
            .filter(|_| physics.is_shared() && options.one_position && !records);
        // a chunk's check, with whether the device draws its strikes, and its seconds
        let check = |range: Range<usize>| {
            let started = Instant::now();
            let (most, drawn) = match drawn
                .and_then(|d| check_drawn(table, physics, options, range.clone(), &input, &d))
            {
                Some(most) => (most, true),
                None => (check_chunk(table, physics, options, range, &input), false),
            };
            (most, drawn, started.elapsed().as_secs_f64())
        };
        let mut stats = BatchStats::default();
        // a simulated chunk handed to the sink, counted in the stats
        let mut sink_chunk = |chunk: &Chunk, seconds: f64, stats: &mut BatchStats| {
            stats.sim_seconds += seconds;
            stats.tables += chunk.len();
            stats.events += chunk.n_events();
            stats.cut += chunk.iter().filter(|r| r.outcome.cut.is_some()).count();
            sink(chunk).map_err(BatchError::Sink)
        };
        let what = if study { "the study" } else { "the batch" };
        // each chunk checked before its turn; a chunk simulated and not yet at the sink
        let mut checked = ranges.first().map(|r| check(r.clone()));
        let mut pending: Option<(Chunk, f64)> = None;
        for (c, range) in ranges.iter().enumerate() {
            let (start, end) = (range.start, range.end);
            let (most, drawn_here, check_seconds) =
                checked.take().expect("checked before its turn");
            let max_balls = match most {
                Ok(most) => most,
                Err((table, error)) => {
                    // the chunks before it reach the sink first, as one after the other
                    if let Some((chunk, seconds)) = pending.take() {
                        sink_chunk(&chunk, seconds, &mut stats)?;
                    }
                    return Err(BatchError::Table { table, error });
                }
            };
            let fill = |k: usize, balls: &mut Vec<BallState>| input(start + k, balls);
            let tables = CheckedTables {
                fill: &fill,
                n_tables: end - start,
                max_balls,
                one_position: options.one_position,
                drawn: drawn.filter(|_| drawn_here).map(|d| d.from(start)),
            };
            let part = physics.part(start..end);
            let after = ranges.get(c + 1).cloned();
            let chunk = match self.chosen.gpu.as_mut() {
                // after the first chunk the device runs this chunk while the host hands the
                // chunk before to the sink and checks the chunk after
                Some(g) if start > 0 => {
                    let (ran, sunk, next) = std::thread::scope(|s| {
                        let device = s.spawn(|| {
                            let started = Instant::now();
                            let ran = gpu_chunk(g, table, part, options, tables, start);
                            (ran, started.elapsed().as_secs_f64())
                        });
                        let sunk = match pending.take() {
                            Some((chunk, seconds)) => sink_chunk(&chunk, seconds, &mut stats),
                            None => Ok(()),
                        };
                        let next = after.filter(|_| sunk.is_ok()).map(check);
                        let ran = device
                            .join()
                            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
                        (ran, sunk, next)
                    });
                    sunk?;
                    checked = next;
                    let (ran, mut seconds) = ran;
                    let ran = match ran {
                        Ok(chunk) => Ok(chunk),
                        // after chunks reached the sink: a GPU failure under `auto` is not
                        // redone for this chunk alone
                        Err(e @ (Error::Gpu(_) | Error::GpuUnavailable(_)))
                            if self.chosen.backend == Backend::Auto =>
                        {
                            self.chosen.gpu = None;
                            if let Some(restart) = restart {
                                if let Err(stop) = restart() {
                                    // the caller stops (and may start over itself)
                                    self.chosen.notes.push(format!(
                                        "{e}; after {start} of {n_tables} tables, and the \
                                         CPU is used from now on"
                                    ));
                                    return Err(BatchError::Sink(stop));
                                }
                                self.chosen.notes.push(format!(
                                    "{e}; after {start} of {n_tables} tables {what} was \
                                     redone on the CPU in f64 from its first table, and the \
                                     CPU is used from now on"
                                ));
                                return simulate_batch(
                                    table, physics, options, n_tables, &input, &mut sink,
                                );
                            }
                            self.chosen.notes.push(format!(
                                "{e}; tables {start} to {} of {what} were simulated on the \
                                 CPU in f64 (the first {start} on the GPU), and the CPU is \
                                 used from now on",
                                n_tables - 1
                            ));
                            let started = Instant::now();
                            let chunk = cpu_chunk(table, part, options, tables, start);
                            // the failed run's time, and the CPU's
                            seconds += started.elapsed().as_secs_f64();
                            chunk
                        }
                        Err(e) => Err(e),
                    };
                    let chunk = ran.map_err(|e| BatchError::Sink(E::from(e)))?;
                    // the chunk's check and run (the sink and the next check ran beside it)
                    (chunk, check_seconds + seconds)
                }
                _ => {
                    if let Some((chunk, seconds)) = pending.take() {
                        sink_chunk(&chunk, seconds, &mut stats)?;
                    }
                    let started = Instant::now();
                    let chunk = self
                        .run(
                            what,
                            n_tables,
                            study,
                            |g| gpu_chunk(g, table, part, options, tables, start),
                            || cpu_chunk(table, part, options, tables, start),
                        )
                        .map_err(|e| BatchError::Sink(E::from(e)))?;
                    let seconds = started.elapsed().as_secs_f64();
                    checked = after.map(check);
                    (chunk, check_seconds + seconds)
                }
            };
            pending = Some(chunk);
        }
        if let Some((chunk, seconds)) = pending.take() {
            sink_chunk(&chunk, seconds, &mut stats)?;
        }
        Ok(stats)
    }

    /// Every shot of `shots` simulated through [`ShotEngine::simulate_with`] and collected
    /// (one [`GpuRun`] a shot, in shot order): for callers that hold the whole batch.
    pub fn simulate<'p>(
        &mut self,
        table: &Table,
        physics: impl Into<Physics<'p>>,
        limits: Limits,
        shots: &[GpuShot],
        record_events: bool,
    ) -> Result<Vec<GpuRun>, BatchError<Error>> {
        let options = BatchOptions {
            limits,
            record_events,
            ..BatchOptions::default()
        };
        let runs = Vec::with_capacity(shots.len());
        let input = |k: usize, balls: &mut Vec<BallState>| {
            balls.clear();
            balls.extend_from_slice(&shots[k].balls);
            Ok(shots[k].strike)
        };
        let runs = std::cell::RefCell::new(runs);
        self.simulate_restartable(
            table,
            physics,
            &options,
            shots.len(),
            input,
            || {
                runs.borrow_mut().clear();
                Ok::<(), Error>(())
            },
            |chunk| {
                runs.borrow_mut().extend(chunk.iter().map(|run| GpuRun {
                    events: run.events.to_vec(),
                    balls: run.balls.to_vec(),
                    outcome: run.outcome,
                }));
                Ok::<(), Error>(())
            },
        )?;
        Ok(runs.into_inner())
    }
}

/// Tables `tables` of `input`, each checked as [`simulate_batch`] checks it (Rayon over
/// tables, nothing kept; the parameters were checked before): the most balls a table has,
/// or the first bad table's position (in table order) and error.
fn check_chunk(
    table: &Table,
    physics: Physics<'_>,
    options: &BatchOptions,
    tables: Range<usize>,
    input: &(impl Fn(usize, &mut Vec<BallState>) -> Result<Option<(usize, CueStrike)>, SimError> + Sync),
) -> Result<usize, (usize, SimError)> {
    let verdicts: Vec<Result<usize, (usize, SimError)>> = tables
        .into_par_iter()
        .with_min_len(64)
        .map_init(Vec::new, |balls, k| {
            let fail = |e| (k, e);
            let strike = input(k, balls).map_err(fail)?;
            let radius = physics.of(k).ball.r;
            check_input(table, radius, options, balls, strike).map_err(fail)?;
            Ok(balls.len())
        })
        .collect();
    verdicts
        .into_iter()
        .try_fold(0, |most, v| v.map(|n| most.max(n)))
}

/// The check of a chunk whose strikes the device draws ([`BatchOptions::drawn`]): its
/// first table checked as [`check_chunk`] checks it, and its first and last tables compared
/// with the rule (the same balls, the same struck ball, the rule's strikes) — the study
/// draws every strike valid, and its input gives the same balls to every table. The most
/// balls a table has, or `None` where the tables differ from the rule (the chunk is then
/// checked table by table and packed as usual).
fn check_drawn(
    table: &Table,
    physics: Physics<'_>,
    options: &BatchOptions,
    tables: Range<usize>,
    input: &(impl Fn(usize, &mut Vec<BallState>) -> Result<Option<(usize, CueStrike)>, SimError> + Sync),
    drawn: &DrawnStrikes,
) -> Option<Result<usize, (usize, SimError)>> {
    let (first, last) = (tables.start, tables.end.checked_sub(1)?);
    let r = physics.of(first).ball.r;
    let (mut a, mut b) = (Vec::new(), Vec::new());
    let strike_a = input(first, &mut a).ok()?;
    let strike_b = input(last, &mut b).ok()?;
    let (cue, s_a) = strike_a?;
    let (cue_b, s_b) = strike_b?;
    let same =
        cue == cue_b && a == b && s_a == drawn.strike(r, first) && s_b == drawn.strike(r, last);
    if !same {
        return None;
    }
    Some(
        check_input(table, r, options, &a, strike_a)
            .map(|()| a.len())
            .map_err(|e| (first, e)),
    )
}

/// One chunk of [`ShotEngine::simulate_with`] on the GPU (tables checked), as a [`Chunk`]
/// of tables `first..`: the runs, with their events where recorded, or the watched runs.
fn gpu_chunk(
    gpu: &mut GpuSimulator,
    table: &Table,
    physics: Physics<'_>,
    options: &BatchOptions,
    tables: CheckedTables<'_>,
    first: usize,
) -> Result<Chunk, Error> {
    let limits = options.limits;
    if let Some(watch) = options.watch {
        let output = GpuOutput::Watch(watch);
        let (_, watched) = gpu.simulate_checked(table, physics, limits, tables, output)?;
        let mut chunk = Chunk::empty_watched(first);
        for run in &watched {
            chunk.push_watched(run.cue, run.outcome, run.watch.as_table_watch());
        }
        return Ok(chunk);
    }
    let mut events: Vec<Vec<EventRecord>> = Vec::new();
    let runs = if options.record_events {
        events.resize(tables.n_tables, Vec::new());
        let mut keep = |k: usize, e: &EventRecord| events[k].push(*e);
        let output = GpuOutput::Events(&mut keep);
        gpu.simulate_checked(table, physics, limits, tables, output)?
            .0
    } else {
        let output = GpuOutput::Finals;
        gpu.simulate_checked(table, physics, limits, tables, output)?
            .0
    };
    let mut chunk = Chunk::empty(first);
    for (k, run) in runs.iter().enumerate() {
        let ev = events.get(k).map_or(&[][..], |e| &e[..]);
        chunk.push(ev, &run.balls, run.outcome);
    }
    Ok(chunk)
}

/// One chunk of [`ShotEngine::simulate_with`] on the CPU (tables checked), where the GPU
/// fell back: [`simulate_batch`] of its tables in one piece, as tables `first..`.
fn cpu_chunk(
    table: &Table,
    physics: Physics<'_>,
    options: &BatchOptions,
    tables: CheckedTables<'_>,
    first: usize,
) -> Result<Chunk, Error> {
    let options = BatchOptions {
        // ShotEngine::simulate_with checked every table already
        check_layout: false,
        chunk_tables: tables.n_tables.max(1),
        ..*options
    };
    let mut out = None;
    simulate_batch(
        table,
        physics,
        &options,
        tables.n_tables,
        tables.fill,
        |chunk| {
            out = Some(chunk.renumbered(first));
            Ok::<(), Error>(())
        },
    )
    .map_err(|e| match e {
        // the tables were checked before
        BatchError::Table { table, error } => Error::from(crate::error::InputError::new(format!(
            "table {}: {error}",
            first + table
        ))),
        BatchError::Sink(e) => e,
    })?;
    Ok(out.unwrap_or_else(|| Chunk::empty(first)))
}

/// `"cpu f64 (2 threads)"`, `"cpu f64 (1 thread)"`: the CPU backend and its pool's size.
fn cpu_description() -> String {
    match rayon::current_num_threads() {
        1 => "cpu f64 (1 thread)".to_owned(),
        n => format!("cpu f64 ({n} threads)"),
    }
}
