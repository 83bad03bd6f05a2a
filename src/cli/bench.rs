//! `kisstime bench`: throughput of each backend on a built-in workload generated in
//! memory, and whether the backends agree.
//!
//! For each backend the batch is answered per pair (`pair_times`) and per table
//! (`next_collisions`), once to warm up and then `reps` times; the median wall time gives
//! pairs/s. For the GPU the upload / kernel / readback split of the last run is kept.
//! Every non-reference backend is compared with the CPU f64 answers under the corpus's
//! tiers (`kisstime::compare`).
//!
//! With `--sim breaks|ordinary` it times the simulator instead: built-in whole shots
//! ([`kisstime::workload::generate_shots`]) from the strike to rest without keeping the
//! events, on the CPU ([`simulate_batch`]) and on the GPU's event loop
//! ([`GpuSimulator`], with its upload / kernel / readback split), once to warm up and then
//! `reps` times; the median wall time gives shots/s and events/s.

use std::time::Instant;

use kisstime::compare::{compare_pairs, next_disagreements};
use kisstime::engine::{Backend, Engine, Precision};
use kisstime::gpu::{GpuRun, GpuShot, GpuSimulator, GpuTimings};
use kisstime::io::{output_error, write_output};
use kisstime::simulate::{BatchError, BatchOptions, SimParams, Table, simulate_batch};
use kisstime::workload::{ShotTable, ShotWorkload, Workload, generate, generate_shots};
use kisstime::{Batch, Error, Params};
use serde::Serialize;

use super::args::{BenchArgs, BenchBackend};

/// Runs `kisstime bench`: measures, then prints the report (text, or JSON with `--json`).
pub fn run(args: &BenchArgs) -> Result<(), Error> {
    if let Some(sim) = args.sim {
        let workload = sim.workload();
        let tables = args.tables.unwrap_or(match workload {
            ShotWorkload::Breaks => 2_000,
            ShotWorkload::Ordinary => 10_000,
        });
        let report = run_sim_bench(&SimBenchConfig {
            workload,
            tables,
            seed: args.seed,
            reps: args.reps,
            cpu: args.backend != BenchBackend::Gpu,
            gpu: (args.backend != BenchBackend::Cpu).then_some(args.precision.precision()),
        })?;
        if args.backend == BenchBackend::Gpu && report.backends.is_empty() {
            return Err(Error::GpuUnavailable(report.skipped.join("; ")));
        }
        let text = if args.json {
            serde_json::to_string_pretty(&report).expect("the report serialises") + "\n"
        } else {
            report.to_text()
        };
        return write_output(None, |w| w.write_all(text.as_bytes()).map_err(output_error));
    }
    let config = BenchConfig {
        scenario: args.scenario.workload(),
        tables: args.tables.unwrap_or(10_000),
        balls: args.balls as usize,
        seed: args.seed,
        cpu: args.backend != BenchBackend::Gpu,
        gpu: (args.backend != BenchBackend::Cpu).then_some(args.precision.precision()),
        reps: args.reps,
    };
    let report = run_bench(&config)?;
    if args.backend == BenchBackend::Gpu && report.backends.is_empty() {
        return Err(Error::GpuUnavailable(report.skipped.join("; ")));
    }
    let text = if args.json {
        serde_json::to_string_pretty(&report).expect("the report serialises") + "\n"
    } else {
        report.to_text()
    };
    write_output(None, |w| w.write_all(text.as_bytes()).map_err(output_error))
}

/// What to measure.
#[derive(Clone, Debug)]
pub struct BenchConfig {
    /// The workload.
    pub scenario: Workload,
    /// Tables in the batch.
    pub tables: usize,
    /// Balls per table.
    pub balls: usize,
    /// Workload seed.
    pub seed: u64,
    /// Measure the CPU backend.
    pub cpu: bool,
    /// Measure the GPU backend in this precision, if any.
    pub gpu: Option<Precision>,
    /// Measured repetitions per operation (after one warm-up).
    pub reps: usize,
}

/// The phases of a GPU call, in seconds (see [`GpuTimings`]): host packing, upload,
/// kernel, readback and host unpacking. The kernels' engine counts its packing in
/// `upload_s` and its unpacking in `readback_s` (its `pack_s` and `unpack_s` are 0).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct GpuSplit {
    /// Checking and laying out the input on the host.
    pub pack_s: f64,
    /// Writing it to the device.
    pub upload_s: f64,
    /// Dispatches until the results are ready.
    pub kernel_s: f64,
    /// Copying the results to mappable memory and mapping them.
    pub readback_s: f64,
    /// Converting the results into answers on the host.
    pub unpack_s: f64,
    /// The part of `pack_s` and `unpack_s` done while the device ran (the event loop
    /// packs a chunk and unpacks the one before while the device runs a chunk).
    pub overlapped_s: f64,
    /// The event loop's compute passes on the device's own clock (GPU timestamps), where
    /// the adapter has them (else null).
    pub kernel_device_s: Option<f64>,
    /// The part of `kernel_s` in the event loop's dispatches that ran fewer than a
    /// sixteenth of their chunk's tables (the long tail of the tables with many events).
    pub kernel_tail_s: f64,
    /// How many such dispatches ran.
    pub tail_dispatches: u64,
}

impl From<GpuTimings> for GpuSplit {
    fn from(t: GpuTimings) -> GpuSplit {
        GpuSplit {
            pack_s: t.pack,
            upload_s: t.upload,
            kernel_s: t.kernel,
            readback_s: t.readback,
            unpack_s: t.unpack,
            overlapped_s: t.overlapped,
            kernel_device_s: t.kernel_device,
            kernel_tail_s: t.kernel_tail,
            tail_dispatches: t.tail_dispatches,
        }
    }
}

/// How a backend's answers compare with the CPU f64 reference.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct BenchAgreement {
    /// Pairs whose answers differ beyond the precision's tier (should be 0).
    pub pairs_outside_tier: usize,
    /// Pairs that differ but graze within the tier's margin (excused).
    pub pairs_excused: usize,
    /// Tables whose next collision differs unexplained by a near-tie or a graze.
    pub tables_next_differ: usize,
}

/// One backend's figures.
#[derive(Clone, Debug, Serialize)]
pub struct BackendFigures {
    /// `cpu` or `gpu`.
    pub backend: String,
    /// `f64` or `f32`.
    pub precision: String,
    /// The device: CPU threads or the GPU adapter.
    pub device: String,
    /// Median seconds for all pairs' answers.
    pub pair_times_s: f64,
    /// Pairs per second for all pairs' answers.
    pub pair_times_pairs_per_s: f64,
    /// Median seconds for every table's next collision.
    pub next_collisions_s: f64,
    /// Pairs per second for every table's next collision.
    pub next_collisions_pairs_per_s: f64,
    /// GPU split of the per-pair run.
    pub pair_times_gpu_split: Option<GpuSplit>,
    /// GPU split of the next-collision run.
    pub next_collisions_gpu_split: Option<GpuSplit>,
    /// Agreement with the CPU f64 reference (`None` for the reference itself).
    pub agreement: Option<BenchAgreement>,
}

/// The whole report.
#[derive(Clone, Debug, Serialize)]
pub struct BenchReport {
    /// Workload name.
    pub scenario: String,
    /// Tables.
    pub tables: usize,
    /// Balls per table.
    pub balls: usize,
    /// Pairs in the batch.
    pub pairs: usize,
    /// Workload seed.
    pub seed: u64,
    /// Measured repetitions per operation.
    pub reps: usize,
    /// One entry per backend measured.
    pub backends: Vec<BackendFigures>,
    /// Backends that could not be measured, and why.
    pub skipped: Vec<String>,
}

/// The median wall time of `reps` timed runs of `run` after one warm-up, with the value of
/// the warm-up (every run gives the same). Each timed run's value is dropped before the
/// next starts, so a run reuses the memory of the one before, as in a real event loop.
fn timed<T>(reps: usize, mut run: impl FnMut() -> Result<T, Error>) -> Result<(f64, T), Error> {
    let value = run()?;
    let mut times = Vec::with_capacity(reps.max(1));
    for _ in 0..reps.max(1) {
        let clock = Instant::now();
        drop(run()?);
        times.push(clock.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    Ok((times[times.len() / 2], value))
}

/// Runs the benchmark.
pub fn run_bench(config: &BenchConfig) -> Result<BenchReport, Error> {
    let params = Params::default();
    let batch: Batch = generate(
        config.scenario,
        config.tables,
        config.balls,
        config.seed,
        &params,
    );
    let pairs = batch.num_pairs() as f64;
    let mut report = BenchReport {
        scenario: config.scenario.name().to_owned(),
        tables: batch.num_tables(),
        balls: config.balls,
        pairs: batch.num_pairs(),
        seed: config.seed,
        reps: config.reps,
        backends: Vec::new(),
        skipped: Vec::new(),
    };
    // the reference: CPU f64 answers (timed when the CPU is measured)
    let reference = kisstime::pair_times(&batch, &params)?;
    let reference_next = kisstime::next_collisions(&batch, &params)?;
    if config.cpu {
        let (pt, _) = timed(config.reps, || kisstime::pair_times(&batch, &params))?;
        let (nt, _) = timed(config.reps, || kisstime::next_collisions(&batch, &params))?;
        report.backends.push(BackendFigures {
            backend: "cpu".into(),
            precision: "f64".into(),
            device: format!("{} threads", rayon::current_num_threads()),
            pair_times_s: pt,
            pair_times_pairs_per_s: pairs / pt,
            next_collisions_s: nt,
            next_collisions_pairs_per_s: pairs / nt,
            pair_times_gpu_split: None,
            next_collisions_gpu_split: None,
            agreement: None,
        });
    }
    if let Some(precision) = config.gpu {
        match Engine::new(Backend::Gpu, precision) {
            Err(e) => report
                .skipped
                .push(format!("gpu {}: {e}", precision.name())),
            Ok(mut engine) => {
                let gpu = engine.gpu().expect("a GPU engine");
                let device = gpu.adapter().to_string();
                let (pt, got) = timed(config.reps, || gpu.pair_times(&batch, &params))?;
                let pair_split = GpuSplit::from(gpu.timings());
                let (nt, next) = timed(config.reps, || gpu.next_collisions(&batch, &params))?;
                let next_split = GpuSplit::from(gpu.timings());
                let agreement = compare_pairs(
                    &batch,
                    &params,
                    &reference,
                    &got,
                    precision,
                    |_, _, _, _, _| {},
                );
                let tables_next_differ = next_disagreements(
                    &batch,
                    &params,
                    precision,
                    &reference,
                    &reference_next,
                    &next,
                );
                report.backends.push(BackendFigures {
                    backend: "gpu".into(),
                    precision: precision.name().into(),
                    device,
                    pair_times_s: pt,
                    pair_times_pairs_per_s: pairs / pt,
                    next_collisions_s: nt,
                    next_collisions_pairs_per_s: pairs / nt,
                    pair_times_gpu_split: Some(pair_split),
                    next_collisions_gpu_split: Some(next_split),
                    agreement: Some(BenchAgreement {
                        pairs_outside_tier: agreement.outside_tier,
                        pairs_excused: agreement.excused,
                        tables_next_differ,
                    }),
                });
            }
        }
    }
    Ok(report)
}

/// The report of `kisstime bench --sim`.
#[derive(Clone, Debug, Serialize)]
pub struct SimBenchReport {
    /// Always `sim`: tells this report from the kernels' one.
    pub mode: String,
    /// The workload (`breaks`, `ordinary`).
    pub workload: String,
    /// Tables (shots) simulated per run.
    pub tables: usize,
    /// Balls over all tables.
    pub balls: usize,
    /// Workload seed.
    pub seed: u64,
    /// Measured runs (after one warm-up).
    pub reps: usize,
    /// Rayon worker threads.
    pub threads: usize,
    /// One entry per backend measured.
    pub backends: Vec<SimFigures>,
    /// Backends that could not be measured, and why.
    pub skipped: Vec<String>,
}

/// One backend's figures for `kisstime bench --sim`.
#[derive(Clone, Debug, Serialize)]
pub struct SimFigures {
    /// `cpu` or `gpu`.
    pub backend: String,
    /// `f64` or `f32`.
    pub precision: String,
    /// The device: CPU threads or the GPU adapter.
    pub device: String,
    /// Median wall time of one run (end to end), in seconds.
    pub median_s: f64,
    /// Shots per second (tables / median time).
    pub shots_per_s: f64,
    /// Events per second (events / median time).
    pub events_per_s: f64,
    /// Events per run, over all tables.
    pub events: usize,
    /// Mean events per shot.
    pub events_per_shot: f64,
    /// Tables cut by an event or time limit (should be 0).
    pub cut: usize,
    /// GPU: the last run's upload / kernel / readback split ("kernel": every dispatch of
    /// the event loop, waited for).
    pub gpu_split: Option<GpuSplit>,
    /// GPU: dispatches per run.
    pub dispatches: Option<u64>,
    /// GPU: shots per second of the kernel time alone.
    pub kernel_shots_per_s: Option<f64>,
    /// GPU, when the CPU ran too: tables whose event count differs from the CPU's, and
    /// tables with a ball more than 1e-6 m from the CPU's final position.
    pub tables_differ: Option<(usize, usize)>,
    /// GPU, when the CPU ran too: tables whose run is not the CPU's to the last bit (another
    /// event count, or a final state that differs in any number).
    pub tables_not_identical: Option<usize>,
    /// GPU: whether the event loop ran as exact SPIR-V (docs/gpu.md, "Bit for bit with the
    /// CPU").
    pub exact: Option<bool>,
}

/// What the sim bench measures: the CPU, and the GPU in a precision.
#[derive(Clone, Copy, Debug)]
pub struct SimBenchConfig {
    /// The workload.
    pub workload: ShotWorkload,
    /// Tables (shots).
    pub tables: usize,
    /// Workload seed.
    pub seed: u64,
    /// Measured runs after one warm-up.
    pub reps: usize,
    /// Measure the CPU.
    pub cpu: bool,
    /// Measure the GPU event loop in this precision, if any.
    pub gpu: Option<Precision>,
}

/// Runs `kisstime bench --sim`: the configured shots simulated on each backend once to
/// warm up and then `reps` times, without keeping the events.
pub fn run_sim_bench(config: &SimBenchConfig) -> Result<SimBenchReport, Error> {
    let params = SimParams::default();
    let table = Table::nine_foot();
    let workload = config.workload;
    let shots: Vec<ShotTable> = generate_shots(workload, config.tables, config.seed, params.ball.r);
    let options = BatchOptions {
        record_events: false,
        ..BatchOptions::default()
    };
    let generated = |e: String| Error::Unsupported(format!("generated {}: {e}", workload.name()));
    let mut report = SimBenchReport {
        mode: "sim".into(),
        workload: workload.name().into(),
        tables: shots.len(),
        balls: shots.iter().map(|s| s.balls.len()).sum(),
        seed: config.seed,
        reps: config.reps,
        threads: rayon::current_num_threads(),
        backends: Vec::new(),
        skipped: Vec::new(),
    };
    let figures = |backend: &str, precision: &str, device: String, median: f64, runs: &[GpuRun]| {
        let events: usize = runs.iter().map(|r| r.outcome.n_events).sum();
        SimFigures {
            backend: backend.into(),
            precision: precision.into(),
            device,
            median_s: median,
            shots_per_s: runs.len() as f64 / median,
            events_per_s: events as f64 / median,
            events,
            events_per_shot: events as f64 / runs.len().max(1) as f64,
            cut: runs.iter().filter(|r| r.outcome.cut.is_some()).count(),
            gpu_split: None,
            dispatches: None,
            kernel_shots_per_s: None,
            tables_differ: None,
            tables_not_identical: None,
            exact: None,
        }
    };
    let mut cpu_runs = None;
    if config.cpu {
        let run = || {
            let mut runs = Vec::with_capacity(shots.len());
            simulate_batch(
                &table,
                params,
                &options,
                shots.len(),
                |k, buf| {
                    let s = &shots[k];
                    buf.clear();
                    buf.extend_from_slice(&s.balls);
                    Ok(s.strike())
                },
                |chunk| {
                    runs.extend(chunk.iter().map(|r| GpuRun {
                        events: Vec::new(),
                        balls: r.balls.to_vec(),
                        outcome: r.outcome,
                    }));
                    Ok::<(), std::convert::Infallible>(())
                },
            )
            .map_err(|e| match e {
                BatchError::Table { table, error } => generated(format!("table #{table}: {error}")),
                BatchError::Sink(never) => match never {},
            })?;
            Ok(runs)
        };
        let (median, runs) = timed(config.reps, run)?;
        let device = format!("{} threads", rayon::current_num_threads());
        report
            .backends
            .push(figures("cpu", "f64", device, median, &runs));
        cpu_runs = Some(runs);
    }
    if let Some(precision) = config.gpu {
        match GpuSimulator::new(precision) {
            Err(e) => report
                .skipped
                .push(format!("gpu {}: {e}", precision.name())),
            Ok(mut gpu) => {
                let inputs: Vec<GpuShot> = shots
                    .iter()
                    .map(|s| GpuShot {
                        balls: s.balls.clone(),
                        strike: s.strike(),
                    })
                    .collect();
                let limits = options.limits;
                let (median, runs) = timed(config.reps, || {
                    gpu.simulate(&table, params, limits, &inputs, false)
                })?;
                let split = GpuSplit::from(gpu.timings());
                let device = gpu.adapter().to_string();
                let mut f = figures("gpu", precision.name(), device, median, &runs);
                f.kernel_shots_per_s = Some(runs.len() as f64 / split.kernel_s.max(1e-12));
                f.gpu_split = Some(split);
                f.dispatches = Some(gpu.dispatches());
                f.tables_differ = cpu_runs.as_ref().map(|cpu| {
                    let events = cpu
                        .iter()
                        .zip(&runs)
                        .filter(|(c, g)| c.outcome.n_events != g.outcome.n_events)
                        .count();
                    let moved = cpu
                        .iter()
                        .zip(&runs)
                        .filter(|(c, g)| {
                            c.balls
                                .iter()
                                .zip(&g.balls)
                                .any(|(a, b)| (a.r.x - b.r.x).hypot(a.r.y - b.r.y) > 1e-6)
                        })
                        .count();
                    (events, moved)
                });
                f.tables_not_identical = cpu_runs.as_ref().map(|cpu| {
                    cpu.iter()
                        .zip(&runs)
                        .filter(|(c, g)| {
                            c.outcome.n_events != g.outcome.n_events || c.balls != g.balls
                        })
                        .count()
                });
                f.exact = Some(gpu.exact());
                report.backends.push(f);
            }
        }
    }
    Ok(report)
}

impl SimBenchReport {
    /// The report as readable lines.
    pub fn to_text(&self) -> String {
        let mut out = format!(
            "kisstime bench --sim: {}, {} tables ({} balls), seed {}, {} threads, median of {} runs\n\n",
            self.workload, self.tables, self.balls, self.seed, self.threads, self.reps,
        );
        for f in &self.backends {
            out += &format!(
                "{} {}: {:.3} s a run: {:.0} shots/s, {:.0} events/s, {:.1} events per shot, {} tables cut\n",
                f.backend,
                f.precision,
                f.median_s,
                f.shots_per_s,
                f.events_per_s,
                f.events_per_shot,
                f.cut
            );
            if let (Some(s), Some(k)) = (&f.gpu_split, f.kernel_shots_per_s) {
                out += &format!(
                    "  device: {}\n  pack {:.1} ms, upload {:.1} ms, kernel {:.1} ms{} ({} dispatches, {} of them of under a sixteenth of the tables: {:.1} ms; {k:.0} shots/s), readback {:.1} ms, unpack {:.1} ms ({:.1} ms of packing and unpacking while the kernel ran)\n",
                    f.device,
                    1e3 * s.pack_s,
                    1e3 * s.upload_s,
                    1e3 * s.kernel_s,
                    match s.kernel_device_s {
                        Some(d) => format!(" ({:.1} ms on the device's clock)", 1e3 * d),
                        None => String::new(),
                    },
                    f.dispatches.unwrap_or(0),
                    s.tail_dispatches,
                    1e3 * s.kernel_tail_s,
                    1e3 * s.readback_s,
                    1e3 * s.unpack_s,
                    1e3 * s.overlapped_s
                );
            }
            if let Some((events, moved)) = f.tables_differ {
                let exact = f.tables_not_identical.unwrap_or(0);
                out += &format!(
                    "  against the CPU: {events} tables with another event count, {moved} with a ball > 1e-6 m away, {exact} not identical to the last bit\n"
                );
            }
        }
        for s in &self.skipped {
            out += &format!("\nskipped: {s}\n");
        }
        out
    }
}

/// Pairs per second in a readable unit.
fn rate(pairs_per_s: f64) -> String {
    if pairs_per_s >= 1e9 {
        format!("{:.2} G pairs/s", pairs_per_s / 1e9)
    } else {
        format!("{:.1} M pairs/s", pairs_per_s / 1e6)
    }
}

impl BenchReport {
    /// The report as a readable table.
    pub fn to_text(&self) -> String {
        let mut out = format!(
            "kisstime bench: {}, {} tables x {} balls = {} pairs, seed {}, median of {} runs\n\n",
            self.scenario, self.tables, self.balls, self.pairs, self.seed, self.reps
        );
        out += &format!(
            "{:<9} {:>18} {:>18}  {}\n",
            "backend", "per-pair", "next collision", "agreement with cpu f64"
        );
        for b in &self.backends {
            let agreement = match &b.agreement {
                None => "reference".to_owned(),
                Some(a) => format!(
                    "{} pairs outside the {} tier ({} grazes excused), {} tables' next collision differ",
                    a.pairs_outside_tier, b.precision, a.pairs_excused, a.tables_next_differ
                ),
            };
            out += &format!(
                "{:<9} {:>18} {:>18}  {}\n",
                format!("{} {}", b.backend, b.precision),
                rate(b.pair_times_pairs_per_s),
                rate(b.next_collisions_pairs_per_s),
                agreement
            );
        }
        for b in &self.backends {
            out += &format!("\n{} {} device: {}\n", b.backend, b.precision, b.device);
            for (what, split) in [
                ("per-pair", &b.pair_times_gpu_split),
                ("next collision", &b.next_collisions_gpu_split),
            ] {
                if let Some(s) = split {
                    out += &format!(
                        "  {what}: upload {:.1} ms, kernel {:.1} ms{}, readback {:.1} ms\n",
                        1e3 * s.upload_s,
                        1e3 * s.kernel_s,
                        match s.kernel_device_s {
                            Some(d) => format!(" ({:.1} ms on the device's clock)", 1e3 * d),
                            None => String::new(),
                        },
                        1e3 * s.readback_s
                    );
                }
            }
        }
        for s in &self.skipped {
            out += &format!("\nskipped: {s}\n");
        }
        out
    }
}
