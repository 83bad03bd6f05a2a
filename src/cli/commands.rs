//! The batch commands: `pairs`, `next`, `gen`, and what every command shares (opening the
//! engine, reading the input).

use std::path::Path;

use kisstime::io::{Format, PairsWriter, output_error};
use kisstime::workload::generate;
use kisstime::{Batch, Engine, Error, InputError, NextCollision, Params};

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
    if let Some(out) = &args.output {
        check_output(out, "-o", &["csv", "npy"])?;
    }
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
    check_output(&args.output, "-o", &["csv", "npy"])?;
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

/// The most worker threads `--threads` may ask for: far more than any machine's cores,
/// far fewer than the thousands of OS threads that exhaust one.
pub const MAX_THREADS: usize = 1024;

/// Sets the number of Rayon worker threads (`--threads`), refusing 0 and more than
/// [`MAX_THREADS`] before any thread starts.
pub fn set_threads(threads: Option<usize>) -> Result<(), Error> {
    if let Some(n) = threads {
        if n == 0 || n > MAX_THREADS {
            return Err(Error::Unsupported(format!(
                "--threads {n}: give 1 to {MAX_THREADS} (this machine has {} cores)",
                std::thread::available_parallelism().map_or(1, |c| c.get())
            )));
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .map_err(|e| Error::Unsupported(format!("cannot start {n} threads: {e}")))?;
    }
    Ok(())
}

/// Refuses an output path before anything is computed: its folder must exist (else an
/// [`Error::Io`], exit 1), and its name must end in one of `extensions` (else bad input,
/// exit 2) (the formats the output is written in; `csv` also
/// stands for a name with no extension). `-` (standard output) and anything that exists
/// and is not a regular file or a folder (a device such as `/dev/null`, a FIFO) pass.
pub fn check_output(path: &Path, what: &str, extensions: &[&str]) -> Result<(), Error> {
    if path.as_os_str() == "-" {
        return Ok(());
    }
    if let Ok(meta) = std::fs::metadata(path)
        && !meta.is_file()
        && !meta.is_dir()
    {
        return Ok(());
    }
    let named = path.display();
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let known = match &ext {
        Some(e) => extensions.contains(&e.as_str()),
        None => extensions.contains(&"csv"),
    };
    if !known {
        let list: Vec<String> = extensions.iter().map(|e| format!(".{e}")).collect();
        return Err(InputError::new(format!(
            "{what} {named}: written as {}; name it so",
            list.join(" or ")
        ))
        .into());
    }
    if path.is_dir() {
        // cannot be written: an I/O error, as when writing fails (exit 1)
        return Err(Error::Io {
            path: format!("{what} {named}"),
            source: std::io::Error::new(
                std::io::ErrorKind::IsADirectory,
                "a folder of that name is in the way",
            ),
        });
    }
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        // cannot be written: an I/O error, as when writing fails (exit 1)
        return Err(Error::Io {
            path: format!("{what} {named}"),
            source: std::io::Error::new(
                std::io::ErrorKind::NotFound,
                format!("the folder {} does not exist", dir.display()),
            ),
        });
    }
    Ok(())
}
