//! The `kisstime` command line: a thin layer over the library.
//!
//! Exit codes: 0 success, 2 bad input or usage (the message names the file, line, table and
//! ball), 1 a file that cannot be read or written.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};
use kisstime::io::{Format, PairsWriter, output_error};

#[path = "cli/progress.rs"]
mod progress;
use kisstime::physics::{
    DEFAULT_G, DEFAULT_MU_R, DEFAULT_MU_S, DEFAULT_MU_SP_PER_RADIUS, DEFAULT_RADIUS,
};
use kisstime::workload::{Scenario, generate};
use kisstime::{Backend, Engine, Error, Params, Precision};
use progress::Progress;

#[derive(Parser)]
#[command(
    name = "kisstime",
    version,
    about = "When do two billiard balls collide? Exact first-contact times for every ball pair \
             of many tables at once.",
    long_about = None
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Answer every ball pair of every table: when do they first touch while approaching?
    ///
    /// INPUT is CSV with the header `table,ball,state,x,y,vx,vy,wx,wy,wz` (SI units; state is
    /// stationary, spinning, sliding, rolling or pocketed; rows of one table need not be
    /// adjacent). The output is CSV `table,i,j,t,status,horizon`, one row per pair with
    /// i < j the ball ids, in ascending table then ball id order; `t` is the first contact
    /// time in seconds (`inf` for none), `status` is hit, none or overlap, and `horizon` is
    /// the time until the first of the two balls changes its motion state. The output is
    /// streamed: a few million pairs are held at a time, whatever the batch size.
    ///
    /// Files whose name ends in .npy are NumPy arrays instead of CSV, input and output
    /// (layouts in the README and `kisstime::npy`). Ctrl-C leaves no output file behind.
    Pairs(RunArgs),
    /// Each table's next collision: the earliest pair in contact, as an event loop asks
    /// after every event.
    ///
    /// INPUT as for `pairs`. The output is CSV `table,t,i,j,status`, one row per table in
    /// ascending id order: `t` the time in seconds, (i, j) the ball ids, status hit or
    /// overlap; `inf`, empty ids and `none` when no pair of the table collides. Ties: the
    /// smallest time, then the smallest (i, j). Files ending in .npy are NumPy arrays, as
    /// for `pairs`.
    Next(RunArgs),
    /// Measure each backend on a built-in workload generated in memory: pairs/s per pair
    /// and for the next collision, the GPU's upload / kernel / readback split, and whether
    /// the backends agree (pairs outside the precision's tier against the CPU f64).
    Bench(BenchArgs),
    /// Write a built-in workload as an input file, so that the CLI, other tools and other
    /// simulators can be timed on identical data.
    Gen(GenArgs),
    /// Monte Carlo shot study: re-play one intended shot under cue noise many times and
    /// count what the cue ball touches first (each object ball, a cushion, nothing).
    ///
    /// SCENARIO is a TOML file (table, balls, intended shot, noise; see
    /// examples/study.toml); without it the built-in study runs. Prints per outcome the
    /// count and fraction with a 95% confidence interval, and for the intended ball the time
    /// to contact and the cut angle. The same seed gives the same outcomes on every backend
    /// and thread count.
    Shots(ShotsArgs),
}

#[derive(Args)]
struct RunArgs {
    /// Input file: CSV, or a NumPy .npy array when the name ends in .npy.
    input: PathBuf,
    /// Write the output here instead of standard output (atomically: nothing is left under
    /// this name if the run fails or is interrupted); a name ending in .npy writes NumPy.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Where to compute: `cpu` (Rayon, f64), `gpu` (wgpu; an error when no GPU is usable),
    /// `auto` (the GPU when one works, else the CPU, saying why on stderr).
    #[arg(long, value_enum, default_value_t = BackendArg::Cpu)]
    backend: BackendArg,
    /// Floating-point precision: `f64` (CPU, and GPUs that offer SHADER_F64) or `f32`
    /// (GPU only). Default: f64 on the CPU, f32 on the GPU and auto.
    #[arg(long, value_enum)]
    precision: Option<PrecisionArg>,
    /// Print the backend and adapter used on stderr.
    #[arg(short, long)]
    verbose: bool,
    /// Worker threads for the CPU backend (default: one per core). Results do not depend
    /// on it.
    #[arg(long)]
    threads: Option<usize>,
    #[command(flatten)]
    physics: PhysicsArgs,
}

#[derive(Args)]
struct GenArgs {
    /// The workload: `rack` (the break: a 15-ball rack and the cue ball), `midshot` (one
    /// sliding and two rolling balls, the rest still), `spread` (every ball moving at
    /// random), `worst` (every ball moving towards every other: every pair fully solved).
    #[arg(long, value_enum, default_value_t = ScenarioArg::Midshot)]
    scenario: ScenarioArg,
    /// Number of tables.
    #[arg(long, default_value_t = 10_000)]
    tables: usize,
    /// Balls per table, 2 to 64 (the rack always has 16).
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u16).range(2..=64))]
    balls: u16,
    /// Random seed: the same seed gives the same file on every machine.
    #[arg(long, default_value_t = 42)]
    seed: u64,
    /// The file to write: CSV, or a NumPy .npy array when the name ends in .npy.
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Args)]
struct ShotsArgs {
    /// The study (TOML, see examples/study.toml). Default: the built-in study.
    scenario: Option<PathBuf>,
    /// Number of noisy samples.
    #[arg(long, default_value_t = 100_000, value_parser = clap::value_parser!(u64).range(1..))]
    samples: u64,
    /// Random seed: sample i's noise depends on (seed, i) only.
    #[arg(long, default_value_t = 42)]
    seed: u64,
    /// Where to compute the ball contacts (as for `pairs`).
    #[arg(long, value_enum, default_value_t = BackendArg::Cpu)]
    backend: BackendArg,
    /// Floating-point precision of the contacts (as for `pairs`).
    #[arg(long, value_enum)]
    precision: Option<PrecisionArg>,
    /// Multiply every noise standard deviation by this factor (replaces the file's
    /// `noise.factor`; 0 replays the intended shot exactly).
    #[arg(long, allow_negative_numbers = true)]
    noise: Option<f64>,
    /// Standard deviation of the cue speed in m/s (replaces the scaled value).
    #[arg(long, allow_negative_numbers = true)]
    sigma_v0: Option<f64>,
    /// Standard deviation of the aim azimuth in degrees (replaces the scaled value).
    #[arg(long, allow_negative_numbers = true)]
    sigma_phi: Option<f64>,
    /// Standard deviation of the cue elevation in degrees (replaces the scaled value).
    #[arg(long, allow_negative_numbers = true)]
    sigma_theta: Option<f64>,
    /// Standard deviation of the sideways tip offset in metres (replaces the scaled value).
    #[arg(long, allow_negative_numbers = true)]
    sigma_a: Option<f64>,
    /// Standard deviation of the vertical tip offset in metres (replaces the scaled value).
    #[arg(long, allow_negative_numbers = true)]
    sigma_b: Option<f64>,
    /// Write one CSV row per sample here (atomically).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Draw the study as a PNG here: the table, the spread of the first contacts, and the
    /// cut angles on the intended ball.
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Print the backend and adapter used on stderr.
    #[arg(short, long)]
    verbose: bool,
    /// Worker threads for the CPU backend (default: one per core). Results do not depend
    /// on it.
    #[arg(long)]
    threads: Option<usize>,
}

#[derive(Args)]
struct BenchArgs {
    /// Number of tables.
    #[arg(long, default_value_t = 10_000)]
    tables: usize,
    /// Balls per table, 2 to 64 (the rack always has 16).
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u16).range(2..=64))]
    balls: u16,
    /// The workload (see `kisstime gen --help`).
    #[arg(long, value_enum, default_value_t = ScenarioArg::Midshot)]
    scenario: ScenarioArg,
    /// Which backends to measure; `all` is the CPU and, when one is usable, the GPU.
    #[arg(long, value_enum, default_value_t = BenchBackend::All)]
    backend: BenchBackend,
    /// The GPU's precision (the CPU computes in f64).
    #[arg(long, value_enum, default_value_t = PrecisionArg::F32)]
    precision: PrecisionArg,
    /// Random seed of the workload.
    #[arg(long, default_value_t = 42)]
    seed: u64,
    /// Measured runs per operation, after one warm-up; the median is reported.
    #[arg(long, default_value_t = 3)]
    reps: usize,
    /// Print the report as JSON.
    #[arg(long)]
    json: bool,
    /// Worker threads for the CPU backend (default: one per core).
    #[arg(long)]
    threads: Option<usize>,
}

/// Backends to benchmark.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum BenchBackend {
    /// The CPU only.
    Cpu,
    /// The GPU only (the CPU still computes the reference answers, untimed).
    Gpu,
    /// Both.
    All,
}

/// A built-in workload.
#[derive(Clone, Copy, ValueEnum)]
enum ScenarioArg {
    /// The break.
    Rack,
    /// A few balls moving, the rest still.
    Midshot,
    /// Every ball moving at random.
    Spread,
    /// Every ball moving towards every other.
    Worst,
}

impl ScenarioArg {
    fn scenario(self) -> Scenario {
        match self {
            ScenarioArg::Rack => Scenario::Rack,
            ScenarioArg::Midshot => Scenario::Midshot,
            ScenarioArg::Spread => Scenario::Spread,
            ScenarioArg::Worst => Scenario::Worst,
        }
    }
}

/// The compute backend.
#[derive(Clone, Copy, ValueEnum)]
enum BackendArg {
    /// Rayon on all cores, f64: the reference.
    Cpu,
    /// The GPU through wgpu.
    Gpu,
    /// The GPU when one works, else the CPU.
    Auto,
}

/// The floating-point precision.
#[derive(Clone, Copy, ValueEnum)]
enum PrecisionArg {
    /// IEEE single precision.
    F32,
    /// IEEE double precision.
    F64,
}

#[derive(Args)]
struct PhysicsArgs {
    /// Ball radius R in metres.
    #[arg(long, default_value_t = DEFAULT_RADIUS, allow_negative_numbers = true)]
    radius: f64,
    /// Sliding friction coefficient.
    #[arg(long, default_value_t = DEFAULT_MU_S, allow_negative_numbers = true)]
    mu_s: f64,
    /// Rolling friction coefficient.
    #[arg(long, default_value_t = DEFAULT_MU_R, allow_negative_numbers = true)]
    mu_r: f64,
    /// Spinning friction coefficient in metres [default: 0.444 × radius]. Spin about the
    /// vertical axis never moves a ball, so it does not change collision times.
    #[arg(long, allow_negative_numbers = true)]
    mu_sp: Option<f64>,
    /// Gravitational acceleration in m/s².
    #[arg(long, default_value_t = DEFAULT_G, allow_negative_numbers = true)]
    g: f64,
}

impl PhysicsArgs {
    fn params(&self) -> Params {
        Params {
            radius: self.radius,
            mu_s: self.mu_s,
            mu_r: self.mu_r,
            mu_sp: self.mu_sp.unwrap_or(DEFAULT_MU_SP_PER_RADIUS * self.radius),
            g: self.g,
        }
    }
}

/// Opens the engine the flags ask for, printing fallback notes (and with `--verbose` the
/// backend) on stderr.
fn open_engine(
    backend: BackendArg,
    precision: Option<PrecisionArg>,
    verbose: bool,
) -> Result<Engine, Error> {
    let backend = match backend {
        BackendArg::Cpu => Backend::Cpu,
        BackendArg::Gpu => Backend::Gpu,
        BackendArg::Auto => Backend::Auto,
    };
    let precision = match (precision, backend) {
        (Some(PrecisionArg::F32), _) => Precision::F32,
        (Some(PrecisionArg::F64), _) | (None, Backend::Cpu) => Precision::F64,
        (None, _) => Precision::F32,
    };
    let mut engine = Engine::new(backend, precision)?;
    print_notes(&mut engine);
    if verbose {
        eprintln!("kisstime: computing on {}", engine.describe());
    }
    Ok(engine)
}

fn print_notes(engine: &mut Engine) {
    for note in engine.take_notes() {
        eprintln!("kisstime: {note}");
    }
}

/// Pairs per chunk of streamed per-pair output.
const STREAM_PAIRS: usize = 1 << 22;

/// Per-pair work at least this large gets a progress bar (on a terminal).
const SHOW_PAIRS: u64 = 1 << 25;

/// Reads a batch in the format its name says, with a progress bar for large files.
fn read_input(path: &Path) -> Result<kisstime::Batch, Error> {
    let name = path.display().to_string();
    let io = |source| Error::Io {
        path: name.clone(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let bar = Progress::bytes("reading", file.metadata().map_err(io)?.len());
    let reader = std::io::BufReader::with_capacity(1 << 20, bar.wrap_read(file));
    let batch = kisstime::io::read_batch(reader, Format::of(Some(path)), &name);
    bar.done();
    batch
}

/// Reads the input and opens the engine.
fn prepare(args: &RunArgs) -> Result<(kisstime::Batch, Params, Engine), Error> {
    let params = args.physics.params();
    params.validate()?;
    let batch = read_input(&args.input)?;
    let engine = open_engine(args.backend, args.precision, args.verbose)?;
    Ok((batch, params, engine))
}

fn run_pairs(args: &RunArgs) -> Result<(), Error> {
    let (batch, params, mut engine) = prepare(args)?;
    let format = Format::of(args.output.as_deref());
    let result = kisstime::io::write_output(args.output.as_deref(), |w| {
        let mut out = PairsWriter::new(w, format, &batch).map_err(output_error)?;
        let pairs = batch.num_pairs() as u64;
        let bar = Progress::new("pairs", pairs, "pairs", pairs >= SHOW_PAIRS);
        for tables in batch.table_chunks(STREAM_PAIRS) {
            let contacts = engine.pair_times_of(&batch, &params, tables.clone())?;
            out.write_rows(&batch, tables, &contacts)
                .map_err(output_error)?;
            bar.inc(contacts.len() as u64);
        }
        bar.done();
        out.finish().map_err(output_error)
    });
    print_notes(&mut engine);
    result
}

/// Every table's next collision, in chunks of tables so that a bar can show progress.
fn next_with_progress(
    engine: &mut Engine,
    batch: &kisstime::Batch,
    params: &Params,
) -> Result<Vec<kisstime::NextCollision>, Error> {
    let long = batch.num_pairs() as u64 >= SHOW_PAIRS;
    let bar = Progress::new("next collisions", batch.num_tables() as u64, "tables", long);
    let mut next = Vec::with_capacity(batch.num_tables());
    for tables in batch.table_chunks(8 * STREAM_PAIRS) {
        next.extend(engine.next_collisions_of(batch, params, tables.clone())?);
        bar.inc(tables.len() as u64);
    }
    bar.done();
    Ok(next)
}

fn run_next(args: &RunArgs) -> Result<(), Error> {
    let (batch, params, mut engine) = prepare(args)?;
    let next = next_with_progress(&mut engine, &batch, &params);
    print_notes(&mut engine);
    let next = next?;
    kisstime::io::write_output(args.output.as_deref(), |w| {
        kisstime::io::write_next(w, Format::of(args.output.as_deref()), &next).map_err(output_error)
    })
}

fn run_gen(args: &GenArgs) -> Result<(), Error> {
    let params = Params::default();
    let batch = generate(
        args.scenario.scenario(),
        args.tables,
        args.balls as usize,
        args.seed,
        &params,
    );
    kisstime::io::write_output(Some(&args.output), |w| {
        kisstime::io::write_batch(w, Format::of(Some(&args.output)), &batch).map_err(output_error)
    })
}

fn run_bench(args: &BenchArgs) -> Result<(), Error> {
    let config = kisstime::bench::BenchConfig {
        scenario: args.scenario.scenario(),
        tables: args.tables,
        balls: args.balls as usize,
        seed: args.seed,
        cpu: args.backend != BenchBackend::Gpu,
        gpu: (args.backend != BenchBackend::Cpu).then_some(match args.precision {
            PrecisionArg::F32 => Precision::F32,
            PrecisionArg::F64 => Precision::F64,
        }),
        reps: args.reps,
    };
    let report = kisstime::bench::run_bench(&config)?;
    if args.backend == BenchBackend::Gpu && report.backends.is_empty() {
        return Err(Error::GpuUnavailable(report.skipped.join("; ")));
    }
    let text = if args.json {
        serde_json::to_string_pretty(&report).expect("the report serialises") + "\n"
    } else {
        report.to_text()
    };
    kisstime::io::write_output(None, |w| {
        w.write_all(text.as_bytes())
            .map_err(kisstime::io::output_error)
    })
}

/// The noise of a shot study: the file's, scaled by `--noise`, with `--sigma-*` overrides.
fn shots_sigma(
    args: &ShotsArgs,
    scenario: &kisstime::scenario::Scenario,
) -> Result<kisstime::scenario::Noise, Error> {
    let check = |name: &'static str, value: f64| {
        if value.is_finite() && value >= 0.0 {
            Ok(value)
        } else {
            Err(Error::Unsupported(format!(
                "invalid {name} {value}: it must be finite and not negative"
            )))
        }
    };
    let factor = check("--noise", args.noise.unwrap_or(scenario.noise_factor))?;
    let mut sigma = scenario.noise.scaled(factor);
    for (name, value, slot) in [
        ("--sigma-v0", args.sigma_v0, &mut sigma.v0),
        ("--sigma-phi", args.sigma_phi, &mut sigma.phi),
        ("--sigma-theta", args.sigma_theta, &mut sigma.theta),
        ("--sigma-a", args.sigma_a, &mut sigma.a),
        ("--sigma-b", args.sigma_b, &mut sigma.b),
    ] {
        if let Some(v) = value {
            *slot = check(name, v)?;
        }
    }
    Ok(sigma)
}

fn run_shots(args: &ShotsArgs) -> Result<(), Error> {
    use kisstime::scenario::Scenario as Study;
    use kisstime::study::{Summary, run_study, write_samples_csv};
    let scenario = match &args.scenario {
        Some(path) => Study::read(path)?,
        None => Study::builtin(),
    };
    let sigma = shots_sigma(args, &scenario)?;
    let mut engine = open_engine(args.backend, args.precision, args.verbose)?;
    let n = args.samples as usize;
    let started = std::time::Instant::now();
    let bar = Progress::new("shots", n as u64, "samples", n >= 100_000);
    let samples = run_study(
        &scenario,
        &sigma,
        n,
        args.seed,
        &mut engine,
        &mut |done, _| bar.set(done as u64),
    );
    bar.done();
    let seconds = started.elapsed().as_secs_f64();
    print_notes(&mut engine);
    let samples = samples?;
    let summary = Summary::of(&scenario, &samples);
    let text = format!(
        "kisstime shots: {}\n{n} samples, seed {}; noise σ: v0 {} m/s, phi {}°, theta {}°, \
         a {} mm, b {} mm\n\n{}\n{n} samples in {seconds:.3} s: {:.0} samples/s on {}\n",
        scenario.source,
        args.seed,
        sigma.v0,
        sigma.phi,
        sigma.theta,
        1e3 * sigma.a,
        1e3 * sigma.b,
        summary.to_text(),
        n as f64 / seconds,
        engine.describe()
    );
    kisstime::io::write_output(None, |w| {
        w.write_all(text.as_bytes())
            .map_err(kisstime::io::output_error)
    })?;
    if let Some(path) = &args.output {
        kisstime::io::write_output(Some(path), |w| {
            write_samples_csv(w, &scenario, &sigma, args.seed, &samples)
                .map_err(kisstime::io::output_error)
        })?;
    }
    if let Some(path) = &args.plot {
        kisstime::plot::write_study_png(path, &scenario, &samples, &summary)?;
    }
    Ok(())
}

fn set_threads(threads: Option<usize>) -> Result<(), String> {
    if let Some(n) = threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .map_err(|e| format!("cannot start {n} threads: {e}"))?;
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    // Ctrl-C (or SIGTERM): leave no output file, finished or half-written, behind
    let _ = ctrlc::set_handler(|| {
        kisstime::io::remove_unfinished_outputs();
        eprintln!("kisstime: interrupted; nothing was written");
        std::process::exit(130);
    });
    let threads = match &cli.command {
        Command::Pairs(a) | Command::Next(a) => a.threads,
        Command::Bench(a) => a.threads,
        Command::Gen(_) => None,
        Command::Shots(a) => a.threads,
    };
    if let Err(e) = set_threads(threads) {
        eprintln!("kisstime: {e}");
        return ExitCode::from(1);
    }
    let result = match &cli.command {
        Command::Pairs(args) => run_pairs(args),
        Command::Next(args) => run_next(args),
        Command::Bench(args) => run_bench(args),
        Command::Gen(args) => run_gen(args),
        Command::Shots(args) => run_shots(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // a closed pipe (`kisstime pairs … | head`) is not an error of ours
        Err(Error::Io { source, .. }) if source.kind() == std::io::ErrorKind::BrokenPipe => {
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("kisstime: error: {e}");
            ExitCode::from(if e.is_bad_input() { 2 } else { 1 })
        }
    }
}
