//! The batch commands: `pairs`, `next`, `gen`, and what every command shares (opening the
//! engine, reading the input).

use std::path::Path;

use kisstime::io::{Format, PairsWriter, output_error};
use kisstime::workload::generate;
use kisstime::{Batch, Engine, Error, NextCollision, Params};

use super::args::{BackendArg, GenArgs, PrecisionArg, RunArgs, precision_for};
use super::progress::Progress;

/// Opens the engine the flags ask for, printing fallback notes (and with `--verbose` the
/// backend) on stderr.
pub fn open_engine(
    backend: BackendArg,
    precision: Option<PrecisionArg>,
    verbose: bool,
) -> Result<Engine, Error> {
    let backend = backend.backend();
    let mut engine = Engine::new(backend, precision_for(precision, backend))?;
    print_notes(&mut engine);
    if verbose {
        eprintln!("kisstime: computing on {}", engine.describe());
    }
    Ok(engine)
}

/// Prints the engine's notes (fallbacks) on stderr.
pub fn print_notes(engine: &mut Engine) {
    for note in engine.take_notes() {
        eprintln!("kisstime: {note}");
    }
}

/// Pairs per chunk of streamed per-pair output.
const STREAM_PAIRS: usize = 1 << 22;

/// Per-pair work at least this large gets a progress bar (on a terminal).
const SHOW_PAIRS: u64 = 1 << 25;

/// Reads a batch in the format its name says, with a progress bar for large files.
pub fn read_input(path: &Path) -> Result<Batch, Error> {
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
fn prepare(args: &RunArgs) -> Result<(Batch, Params, Engine), Error> {
    let params = args.physics.params();
    params.validate()?;
    let batch = read_input(&args.input)?;
    let engine = open_engine(args.backend, args.precision, args.verbose)?;
    Ok((batch, params, engine))
}

pub fn run_pairs(args: &RunArgs) -> Result<(), Error> {
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
    batch: &Batch,
    params: &Params,
) -> Result<Vec<NextCollision>, Error> {
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

pub fn run_next(args: &RunArgs) -> Result<(), Error> {
    let (batch, params, mut engine) = prepare(args)?;
    let next = next_with_progress(&mut engine, &batch, &params);
    print_notes(&mut engine);
    let next = next?;
    kisstime::io::write_output(args.output.as_deref(), |w| {
        kisstime::io::write_next(w, Format::of(args.output.as_deref()), &next).map_err(output_error)
    })
}

pub fn run_gen(args: &GenArgs) -> Result<(), Error> {
    let params = Params::default();
    let batch = generate(
        args.scenario.workload(),
        args.tables,
        args.balls as usize,
        args.seed,
        &params,
    );
    kisstime::io::write_output(Some(&args.output), |w| {
        kisstime::io::write_batch(w, Format::of(Some(&args.output)), &batch).map_err(output_error)
    })
}

/// Sets the number of Rayon worker threads (`--threads`).
pub fn set_threads(threads: Option<usize>) -> Result<(), String> {
    if let Some(n) = threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .map_err(|e| format!("cannot start {n} threads: {e}"))?;
    }
    Ok(())
}
