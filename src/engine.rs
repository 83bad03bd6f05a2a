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
use crate::gpu::{GPU_MAX_BALLS, GpuEngine, GpuRun, GpuShot, GpuSimulator};
use crate::model::Params;
pub use crate::model::Precision;
use crate::model::sim_params::SimParams;
use crate::model::table::Table;
use crate::query::ball_ball::Contact;
use crate::resolve::stick_ball::CueStrike;
use crate::simulate::check::check_layout;
use crate::simulate::{BatchError, BatchOptions, EventLoop, Limits, MAX_BALLS, simulate_batch};
use crate::study::{self, Noise, RunOptions, Sample, StudyConfig};

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
            None => format!("cpu f64 ({} threads)", rayon::current_num_threads()),
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
/// CPU, with a note; a table or study of more than [`GPU_MAX_BALLS`] balls is run on the
/// CPU with a note; a GPU failure during a batch (device lost, failed dispatch, failed
/// readback) redoes that batch on the CPU in f64 with a note, and the CPU is used from then
/// on. `gpu` reports each of these as an error. Bad input is an error on every backend.
pub struct ShotEngine {
    chosen: Chosen<GpuSimulator>,
    /// Whether the last call ran on the CPU although a GPU is open (`auto`, a small batch).
    last_on_cpu: bool,
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
        })
    }

    /// The backend asked for.
    pub fn backend(&self) -> Backend {
        self.chosen.backend
    }

    /// The GPU event loop in use, if any.
    pub fn gpu(&mut self) -> Option<&mut GpuSimulator> {
        self.chosen.gpu.as_mut()
    }

    /// What simulated the last call (before any call: what will), e.g. `"gpu f64: NVIDIA
    /// H200 (Vulkan, …)"` or `"cpu f64 (2 threads)"`.
    pub fn describe(&self) -> String {
        if self.last_on_cpu {
            format!("cpu f64 ({} threads)", rayon::current_num_threads())
        } else {
            self.chosen.describe()
        }
    }

    /// Messages for the user about fallbacks since the last call (one line each).
    pub fn take_notes(&mut self) -> Vec<String> {
        std::mem::take(&mut self.chosen.notes)
    }

    /// [`Chosen::run`] for work of at most `n_balls` balls a table: more than
    /// [`GPU_MAX_BALLS`] is an error with `gpu` and the CPU's work with `auto`.
    #[allow(clippy::too_many_arguments)]
    fn run<T>(
        &mut self,
        what: &str,
        n_balls: usize,
        n_tables: usize,
        study: bool,
        on_gpu: impl FnOnce(&mut GpuSimulator) -> Result<T, Error>,
        on_cpu: impl FnOnce() -> Result<T, Error>,
    ) -> Result<T, Error> {
        self.last_on_cpu = false;
        if self.chosen.gpu.is_some()
            && self.chosen.backend == Backend::Auto
            && self.chosen.rule == AutoRule::Measured
            && (n_tables < auto_gpu_min_tables()
                || (study && rayon::current_num_threads() > AUTO_STUDY_MAX_CPU_THREADS))
        {
            // the CPU is faster for a batch this small, or for a study on this many threads
            self.last_on_cpu = true;
            return on_cpu();
        }
        if self.chosen.gpu.is_some() && n_balls > GPU_MAX_BALLS {
            let why = format!(
                "{what} has tables of {n_balls} balls; the GPU event loop takes at most \
                 {GPU_MAX_BALLS}"
            );
            if self.chosen.backend == Backend::Auto {
                self.chosen
                    .notes
                    .push(format!("{why}: simulated on the CPU in f64"));
                self.last_on_cpu = true;
                return on_cpu();
            }
            return Err(Error::Unsupported(why));
        }
        self.chosen.run(&format!("{what} was"), on_gpu, on_cpu)
    }

    /// Simulates every shot on `table` to rest (or to a limit), in shot order, as
    /// [`GpuSimulator::simulate`] does; on the CPU through
    /// [`crate::simulate::simulate_batch`]. Every table is checked first, on the host, as
    /// `simulate_batch` checks it (`check_layout` and [`EventLoop::reset`]): the first bad
    /// one is [`BatchError::Table`] with its position, whatever the backend; any other
    /// error is [`BatchError::Sink`].
    pub fn simulate(
        &mut self,
        table: &Table,
        params: SimParams,
        limits: Limits,
        shots: &[GpuShot],
        record_events: bool,
    ) -> Result<Vec<GpuRun>, BatchError<Error>> {
        let mut lp = EventLoop::new(table, params, limits, MAX_BALLS)
            .map_err(|error| BatchError::Table { table: 0, error })?;
        for (k, shot) in shots.iter().enumerate() {
            check_layout(table, params.ball.r, &shot.balls)
                .and_then(|()| lp.reset(&shot.balls, shot.strike))
                .map_err(|error| BatchError::Table { table: k, error })?;
        }
        let n_balls = shots.iter().map(|s| s.balls.len()).max().unwrap_or(0);
        self.run(
            "the batch",
            n_balls,
            shots.len(),
            false,
            |g| g.simulate(table, params, limits, shots, record_events),
            || simulate_on_cpu(table, params, limits, shots, record_events),
        )
        .map_err(BatchError::Sink)
    }

    /// [`study::run_study`] on this backend ([`study::run_study_gpu`] on the GPU).
    pub fn run_study(
        &mut self,
        config: &StudyConfig,
        sigma: &Noise,
        samples: usize,
        seed: u64,
        options: &RunOptions,
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<Vec<Sample>, Error> {
        let progress = std::cell::RefCell::new(progress);
        self.run(
            "the study",
            config.balls.len(),
            samples,
            true,
            |g| {
                study::run_study_gpu(g, config, sigma, samples, seed, options, &mut |d, n| {
                    (progress.borrow_mut())(d, n)
                })
            },
            || {
                study::run_study(config, sigma, samples, seed, options, &mut |d, n| {
                    (progress.borrow_mut())(d, n)
                })
            },
        )
    }

    /// [`study::run_strikes`] on this backend ([`study::run_strikes_gpu`] on the GPU).
    pub fn run_strikes(
        &mut self,
        config: &StudyConfig,
        strikes: &[CueStrike],
        options: &RunOptions,
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<Vec<Sample>, Error> {
        let progress = std::cell::RefCell::new(progress);
        self.run(
            "the study",
            config.balls.len(),
            strikes.len(),
            true,
            |g| {
                study::run_strikes_gpu(g, config, strikes, options, &mut |d, n| {
                    (progress.borrow_mut())(d, n)
                })
            },
            || {
                study::run_strikes(config, strikes, options, &mut |d, n| {
                    (progress.borrow_mut())(d, n)
                })
            },
        )
    }
}

/// [`ShotEngine::simulate`] on the CPU.
fn simulate_on_cpu(
    table: &Table,
    params: SimParams,
    limits: Limits,
    shots: &[GpuShot],
    record_events: bool,
) -> Result<Vec<GpuRun>, Error> {
    let options = BatchOptions {
        limits,
        record_events,
        // ShotEngine::simulate checked every layout already
        check_layout: false,
        ..BatchOptions::default()
    };
    let mut runs = Vec::with_capacity(shots.len());
    let input = |k: usize, balls: &mut Vec<crate::model::ball_state::BallState>| {
        balls.clear();
        balls.extend_from_slice(&shots[k].balls);
        Ok(shots[k].strike)
    };
    simulate_batch(table, params, &options, shots.len(), input, |chunk| {
        runs.extend(chunk.iter().map(|run| GpuRun {
            events: run.events.to_vec(),
            balls: run.balls.to_vec(),
            outcome: run.outcome,
        }));
        Ok::<(), Error>(())
    })
    .map_err(|e| match e {
        // the tables were checked before
        BatchError::Table { table, error } => Error::from(crate::error::InputError::new(format!(
            "table {table}: {error}"
        ))),
        BatchError::Sink(e) => e,
    })?;
    Ok(runs)
}
