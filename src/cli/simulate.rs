//! `kisstime simulate`: whole shots, from the strike to rest, for every table of a batch
//! ([`kisstime::simulate::simulate_batch`] on the CPU, streamed to the outputs chunk by
//! chunk; or the GPU event loop, [`kisstime::gpu::GpuSimulator`], for `--backend gpu|auto`).

use std::path::{Path, PathBuf};

use kisstime::engine::{Backend, Precision, ShotEngine};
use kisstime::game::Rules;
use kisstime::game::{Context, Shot};
use kisstime::io::Format;
use kisstime::io::context::{default_context, read_contexts};
use kisstime::io::physics::BatchPhysics;
use kisstime::io::sim_output::{EventsWriter, FinalWriter, OutcomesWriter, TableIds};
use kisstime::io::strikes::{StrikeRow, match_strikes, read_strikes};
use kisstime::io::table_json::table_by_name;
use kisstime::io::{output_error, write_output, write_outputs};
use kisstime::resolve::stick_ball::CueStrike;
use kisstime::simulate::{
    BallState, BatchError, BatchOptions, BatchStats, Limits, SimError, TableRun,
};
use kisstime::{Batch, Error, InputError};

use super::args::{RulesArg, SimulateArgs};
use super::commands::{check_output, read_input};
use super::progress::Progress;
use super::shot_plot::render_shot_png;

/// Tables from which a progress bar is shown (on a terminal).
const SHOW_TABLES: usize = 20_000;

/// A bad table found while simulating, as an input error naming the file, the line, the
/// table and the ball.
fn table_error(
    args: &SimulateArgs,
    batch: &Batch,
    strike_rows: &[StrikeRow],
    k: usize,
    error: SimError,
) -> Error {
    let input = args.input.display().to_string();
    let table = batch.table_id(k);
    let ids = batch.ball_ids(k);
    // the ball by its position in the table, and where the input file has it
    let in_input = |msg: String, index: Option<usize>| {
        let mut e = InputError::new(msg).in_file(&input).at_table(table);
        if let Some(i) = index.filter(|&i| i < ids.len()) {
            e = e.at_ball(ids[i]);
            match batch.ball_place(k, i) {
                Some(("line", line)) => e.line = Some(line),
                Some((_, row)) => e.row = Some(row),
                None => {}
            }
        }
        Error::from(e)
    };
    match error {
        SimError::Ball { index, reason } => in_input(reason, Some(index)),
        SimError::Overlap {
            first,
            second,
            depth,
        } => in_input(
            format!(
                "overlaps ball {} by {depth:.3e} m, both at rest",
                ids[first.min(ids.len() - 1)]
            ),
            Some(second),
        ),
        SimError::Strike(reason) => {
            let file = args
                .strikes
                .as_ref()
                .map_or_else(String::new, |p| p.display().to_string());
            let mut e = InputError::new(format!("strike: {reason}"))
                .in_file(file)
                .at_table(table);
            if let Some(r) = strike_rows.iter().find(|r| r.table == table) {
                e = kisstime::io::strikes::locate(
                    e,
                    &args
                        .strikes
                        .as_ref()
                        .unwrap_or(&PathBuf::new())
                        .display()
                        .to_string(),
                    Format::of(args.strikes.as_deref()),
                    r.at,
                )
                .at_ball(r.ball);
            }
            e.into()
        }
        other => in_input(other.to_string(), None),
    }
}

/// The position in the batch of the table `--plot` draws: `--table-id`, or the only table.
fn plotted_table(batch: &Batch, id: Option<i64>) -> Result<usize, Error> {
    let n = batch.num_tables();
    match id {
        Some(id) => (0..n).find(|&k| batch.table_id(k) == id).ok_or_else(|| {
            InputError::new(format!("--table-id {id}: no such table in the input"))
                .at_table(id)
                .into()
        }),
        None if n == 1 => Ok(0),
        None => Err(InputError::new(format!(
            "--plot draws one table and the input has {n}: choose it with --table-id"
        ))
        .into()),
    }
}

/// A write error on the output `path` (standard output when `None`).
fn out_err(path: Option<&Path>) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::Io {
        path: path.map_or_else(|| "standard output".to_owned(), |p| p.display().to_string()),
        source,
    }
}

/// The most tables and (past a chunk's first table) balls of one chunk of an input read in
/// chunks: a chunk is then a few tens of MB, and as many tables as the GPU's stream takes
/// at once.
const STREAM_TABLES: usize = kisstime::engine::GPU_STREAM_TABLES;
const STREAM_BALLS: usize = 1 << 21;

/// Tables of the input with their strikes and contexts: the whole input, or one chunk of
/// it (table positions from 0 either way).
struct Piece {
    batch: Batch,
    strike_rows: Vec<StrikeRow>,
    strikes: Vec<Option<(usize, CueStrike)>>,
    contexts: Vec<Context>,
}

/// The input: read whole (`whole`), or counted and checked by a first read in chunks and
/// read again chunk by chunk while simulating (`whole` is `None`).
struct Input {
    physics: BatchPhysics,
    whole: Option<Piece>,
    tables: usize,
    balls: usize,
    strikes: usize,
}

impl Input {
    /// Reads the input and the files beside it: in chunks where the input is a regular
    /// file in table order and nothing needs every table at once (`--plot`, `--context`,
    /// per-table `--physics`); otherwise whole, as before.
    fn open(args: &SimulateArgs, rules: Option<Rules>) -> Result<Input, Error> {
        let regular = |p: &Path| std::fs::metadata(p).is_ok_and(|m| m.is_file());
        let per_table_physics = args
            .physics
            .as_deref()
            .and_then(Path::extension)
            .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
        let chunked = args.plot.is_none()
            && args.context.is_none()
            && !per_table_physics
            && regular(&args.input)
            && args.strikes.as_deref().is_none_or(regular);
        if chunked {
            let physics = kisstime::io::physics::read_batch_physics_on(
                args.physics.as_deref(),
                &[],
                &args.table,
            )?;
            // the first read: every chunk checked as the run will read it, nothing kept
            if let Some((tables, balls, strikes)) =
                each_piece(args, rules, chunk_tables(args), &mut |_| Ok(()))?
            {
                return Ok(Input {
                    physics,
                    whole: None,
                    tables,
                    balls,
                    strikes,
                });
            }
        }
        let batch = read_input(&args.input)?;
        let n = batch.num_tables();
        let ids: Vec<i64> = (0..n).map(|k| batch.table_id(k)).collect();
        let physics = kisstime::io::physics::read_batch_physics_on(
            args.physics.as_deref(),
            &ids,
            &args.table,
        )?;
        let (strike_rows, strikes) = match &args.strikes {
            Some(path) => {
                let rows = read_strikes(path)?;
                let file = path.display().to_string();
                let strikes = match_strikes(&batch, &rows, &file, Format::of(Some(path)))?;
                (rows, strikes)
            }
            None => (Vec::new(), Vec::new()),
        };
        let contexts: Vec<Context> = match (rules, &args.context) {
            (Some(rules), Some(path)) => {
                let table = table_by_name(&args.table)?;
                read_contexts(path, rules, &ids, |k| batch.ball_ids(k), &table.pocket_ids)?
            }
            (Some(rules), None) => vec![default_context(rules); n],
            (None, _) => Vec::new(),
        };
        Ok(Input {
            physics,
            tables: n,
            balls: batch.num_balls(),
            strikes: strike_rows.len(),
            whole: Some(Piece {
                contexts: game_contexts(args, rules, contexts),
                batch,
                strike_rows,
                strikes,
            }),
        })
    }

    /// Hands every piece of the input to `f`, in table order.
    fn for_each(
        &self,
        args: &SimulateArgs,
        rules: Option<Rules>,
        f: &mut dyn FnMut(&Piece) -> Result<(), Error>,
    ) -> Result<(), Error> {
        match &self.whole {
            Some(piece) => f(piece),
            None => match each_piece(args, rules, chunk_tables(args), &mut |p| f(&p))? {
                Some(counts) if counts == (self.tables, self.balls, self.strikes) => Ok(()),
                _ => Err(InputError::new("the input changed while it was being read")
                    .in_file(args.input.display().to_string())
                    .into()),
            },
        }
    }
}

/// The tables of a chunk of the input (`--input-chunk-tables`, else [`STREAM_TABLES`]).
fn chunk_tables(args: &SimulateArgs) -> usize {
    args.input_chunk_tables.unwrap_or(STREAM_TABLES).max(1)
}

/// The game's part of each context (8-ball: every shot but the break is called).
fn game_contexts(
    args: &SimulateArgs,
    rules: Option<Rules>,
    contexts: Vec<Context>,
) -> Vec<Context> {
    match rules {
        Some(rules) => contexts
            .into_iter()
            .map(|c| rules.context(Context { wpa: args.wpa, ..c }))
            .collect(),
        None => contexts,
    }
}

/// Reads the input (a regular file) and its strike file in chunks of `max_tables` tables,
/// in step, and hands each chunk to `f` with its strikes matched and its contexts (the
/// defaults: `--context` is not read so): the tables, balls and strikes in all, or `None`
/// where the input or the strike file is not in table order (nothing more is read; the
/// caller reads them whole). Errors are a whole read's, naming file, line, table and ball.
fn each_piece(
    args: &SimulateArgs,
    rules: Option<Rules>,
    max_tables: usize,
    f: &mut dyn FnMut(Piece) -> Result<(), Error>,
) -> Result<Option<(usize, usize, usize)>, Error> {
    use kisstime::io::stream::{Streamed, read_batch_chunks};
    let file = args.input.display().to_string();
    let reader = std::fs::File::open(&args.input).map_err(|source| Error::Io {
        path: file.clone(),
        source,
    })?;
    let reader = std::io::BufReader::with_capacity(1 << 20, reader);
    let strike_file = args
        .strikes
        .as_ref()
        .map_or_else(String::new, |p| p.display().to_string());
    let strike_format = Format::of(args.strikes.as_deref());
    let strikes_out_of_order = std::cell::Cell::new(false);
    let mut n_strikes = 0;
    let streamed = std::thread::scope(|scope| {
        // the strike file, read on a thread of its own and taken in step with the tables
        let (tx, rx) = std::sync::mpsc::sync_channel::<Result<StrikeRow, Error>>(1 << 12);
        if let Some(path) = &args.strikes {
            scope.spawn(move || {
                let stopped = || Error::Unsupported("stopped".into());
                let read = kisstime::io::strikes::read_strikes_each(path, &mut |row| {
                    tx.send(Ok(row)).map_err(|_| stopped())
                });
                if let Err(e) = read {
                    let _ = tx.send(Err(e));
                }
            });
        } else {
            drop(tx);
        }
        let mut peeked: Option<StrikeRow> = None;
        let mut last_strike = i64::MIN;
        let streamed = read_batch_chunks(
            reader,
            Format::of(Some(&args.input)),
            &file,
            max_tables,
            STREAM_BALLS,
            |batch, last| {
                let n = batch.num_tables();
                let hi = batch.table_id(n - 1);
                let mut rows = Vec::new();
                loop {
                    let row = match peeked.take() {
                        Some(row) => row,
                        None => match rx.recv() {
                            Ok(row) => row?,
                            Err(_) => break,
                        },
                    };
                    if row.table < last_strike {
                        strikes_out_of_order.set(true);
                        return Err(InputError::new("out of order").into());
                    }
                    last_strike = row.table;
                    if !last && row.table > hi {
                        peeked = Some(row);
                        break;
                    }
                    rows.push(row);
                }
                n_strikes += rows.len();
                let strikes = match &args.strikes {
                    Some(_) => match_strikes(&batch, &rows, &strike_file, strike_format)?,
                    None => Vec::new(),
                };
                let contexts = match rules {
                    Some(rules) => vec![default_context(rules); n],
                    None => Vec::new(),
                };
                f(Piece {
                    contexts: game_contexts(args, rules, contexts),
                    batch,
                    strike_rows: rows,
                    strikes,
                })
            },
        );
        // the strike thread stops at its next row
        drop(rx);
        streamed
    });
    if strikes_out_of_order.get() {
        return Ok(None);
    }
    match streamed? {
        Streamed::Done { tables, balls } => Ok(Some((tables, balls, n_strikes))),
        Streamed::OutOfOrder | Streamed::Empty => Ok(None),
    }
}

/// Whether every output named is a file that a failed attempt leaves untouched (written
/// atomically), so that the run can start over: no standard output, device or FIFO.
fn outputs_restartable(paths: &[Option<&Path>], to_stdout: bool) -> bool {
    !to_stdout
        && paths
            .iter()
            .flatten()
            .all(|p| p.as_os_str() != "-" && std::fs::metadata(p).map_or(true, |m| m.is_file()))
}

pub fn run(args: &SimulateArgs) -> Result<(), Error> {
    if args.backend.backend() == Backend::Cpu && args.precision.precision() == Precision::F32 {
        return Err(InputError::new(
            "--precision f32 needs --backend gpu or auto: the CPU simulates in f64 only",
        )
        .into());
    }
    let limits = Limits::new(args.max_events, args.max_time)?;
    if let Some(path) = &args.plot {
        check_output(path, "--plot", &["png"])?;
    }
    for (flag, path) in [
        ("-o", &args.output),
        ("--final", &args.final_states),
        ("--outcomes", &args.outcomes),
    ] {
        if let Some(path) = path {
            check_output(path, flag, &["csv", "npy"])?;
        }
    }
    let table = table_by_name(&args.table)?;
    let rules = args.rules.map(RulesArg::rules);
    let input = Input::open(args, rules)?;
    let plotted = match (&args.plot, &input.whole) {
        (Some(_), Some(piece)) => Some(plotted_table(&piece.batch, args.table_id)?),
        _ => None,
    };
    let n = input.tables;
    if args.verbose {
        eprintln!(
            "kisstime: simulating {n} tables ({} balls, {} strikes) on {} with {} threads{}",
            input.balls,
            input.strikes,
            args.table,
            rayon::current_num_threads(),
            if input.whole.is_none() {
                "; the input read in chunks"
            } else {
                ""
            }
        );
    }
    let options = BatchOptions {
        limits,
        // the rules judge a shot from its events
        record_events: args.output.is_some() || args.rules.is_some(),
        ..BatchOptions::default()
    };
    let mut engine = ShotEngine::new(args.backend.backend(), args.precision.precision())?;
    #[cfg(feature = "testing")]
    inject_test_fault(&mut engine);
    let say = |engine: &mut ShotEngine| {
        for note in engine.take_notes() {
            eprintln!("kisstime: {note}");
        }
    };
    say(&mut engine);
    let events_path = args.output.as_deref();
    let final_path = args.final_states.as_deref();
    let outcomes_path = args.outcomes.as_deref();
    // the final states go to standard output when no output was named for them or the
    // events, unless the outcomes go there (two tables in one stream would be no use)
    let outcomes_to_stdout = outcomes_path.is_some_and(|p| p.as_os_str() == "-");
    let final_to_stdout = events_path.is_none() && final_path.is_none() && !outcomes_to_stdout;
    let mut stats;
    let mut first_cut;
    loop {
        // set where the GPU failed under `auto` after tables were written: the attempt
        // stops, and the run starts over on the CPU (which the engine now uses)
        let restart = std::cell::Cell::new(false);
        let written = std::cell::Cell::new(0usize);
        stats = BatchStats::default();
        first_cut = None;
        // the files are renamed into place together, when all are complete
        let paths = [
            events_path.map(Some),
            final_path.map(Some).or(final_to_stdout.then_some(None)),
            outcomes_path.map(Some),
        ];
        let attempt = write_outputs(paths, |[events_out, final_out, outcomes_out]| {
            let e_err = out_err(events_path);
            let f_err = out_err(final_path);
            let o_err = out_err(outcomes_path);
            let mut events = match events_out {
                Some(w) => Some(EventsWriter::new(w, Format::of(events_path)).map_err(&e_err)?),
                None => None,
            };
            let mut finals = match final_out {
                Some(w) => Some(
                    FinalWriter::new(w, Format::of(final_path), input.balls as u64)
                        .map_err(&f_err)?,
                ),
                None => None,
            };
            let mut outcomes = match outcomes_out {
                Some(w) if args.rules.is_some() => Some(
                    OutcomesWriter::with_verdicts(w, Format::of(outcomes_path), n as u64)
                        .map_err(&o_err)?,
                ),
                Some(w) => Some(
                    OutcomesWriter::new(w, Format::of(outcomes_path), n as u64).map_err(&o_err)?,
                ),
                None => None,
            };
            let physics = input.physics.as_physics();
            let mut start = Vec::new();
            let bar = Progress::new("simulating", n as u64, "tables", n >= SHOW_TABLES);
            let mut write_run = |piece: &Piece, run: &TableRun| -> Result<(), Error> {
                let batch = &piece.batch;
                let ids = TableIds {
                    table: batch.table_id(run.table),
                    balls: batch.ball_ids(run.table),
                };
                if run.outcome.cut.is_some() && first_cut.is_none() {
                    first_cut = Some(ids.table);
                }
                if let Some(w) = events.as_mut() {
                    w.write_table(ids, &table, run).map_err(&e_err)?;
                }
                if let Some(w) = finals.as_mut() {
                    w.write_table(ids, &table, run).map_err(&f_err)?;
                }
                match (outcomes.as_mut(), rules) {
                    (Some(w), Some(rules)) => {
                        let k = run.table;
                        let r = physics.of(k).ball.r;
                        start.clear();
                        start.extend(batch.balls(k).iter().map(|b| BallState::from_ball(b, r)));
                        let shot = Shot {
                            ids: ids.balls,
                            start: &start,
                            events: run.events,
                        };
                        let v = rules
                            .judge(&shot, &piece.contexts[k])
                            .map_err(|e| table_error(args, batch, &piece.strike_rows, k, e))?;
                        w.write_judged(ids, run, &v).map_err(&o_err)?;
                    }
                    (Some(w), None) => w.write_table(ids, run).map_err(&o_err)?,
                    (None, _) => {}
                }
                Ok(())
            };
            let stop = || {
                restart.set(true);
                Error::Gpu("the GPU failed after tables were written".into())
            };
            let result = input.for_each(args, rules, &mut |piece| {
                let batch = &piece.batch;
                let had_gpu = engine.gpu().is_some();
                let sim_input = batch.sim_input_for(&piece.strikes, physics);
                let result = engine.simulate_restartable(
                    &table,
                    physics,
                    &options,
                    batch.num_tables(),
                    sim_input,
                    || Err(stop()),
                    |chunk| {
                        for run in chunk.iter() {
                            write_run(piece, &run)?;
                        }
                        written.set(written.get() + chunk.len());
                        bar.inc(chunk.len() as u64);
                        Ok::<(), Error>(())
                    },
                );
                say(&mut engine);
                let s = result.map_err(|e| match e {
                    BatchError::Table { table: k, error } => {
                        table_error(args, batch, &piece.strike_rows, k, error)
                    }
                    BatchError::Sink(e) => e,
                })?;
                // the GPU failed at this piece's start, after earlier pieces were
                // written from it
                if had_gpu && engine.gpu().is_none() && written.get() > s.tables {
                    return Err(stop());
                }
                stats.tables += s.tables;
                stats.events += s.events;
                stats.cut += s.cut;
                stats.sim_seconds += s.sim_seconds;
                Ok(())
            });
            bar.done();
            result?;
            if let Some(w) = events {
                w.finish().map_err(&e_err)?;
            }
            if let Some(w) = finals {
                w.finish().map_err(&f_err)?;
            }
            if let Some(w) = outcomes {
                w.finish().map_err(&o_err)?;
            }
            Ok(())
        });
        match attempt {
            Err(_) if restart.get() => {
                let where_to = [events_path, final_path, outcomes_path];
                if !outputs_restartable(&where_to, final_to_stdout) {
                    return Err(Error::Gpu(format!(
                        "the GPU failed after {} of {n} tables had been written to an output \
                         that cannot be taken back (standard output, a device or a FIFO), and \
                         the rest would have been the CPU's; nothing more was written: run \
                         again, or with --backend cpu",
                        written.get()
                    )));
                }
                eprintln!(
                    "kisstime: the GPU failed after {} of {n} tables; every output is written \
                     again from the first table on the CPU in f64",
                    written.get()
                );
            }
            other => {
                other?;
                break;
            }
        }
    }
    if let (Some(path), Some(k), Some(piece)) = (&args.plot, plotted, &input.whole) {
        let batch = &piece.batch;
        let physics = input.physics.as_physics();
        let balls: Vec<BallState> = batch
            .balls(k)
            .iter()
            .map(|b| BallState::from_ball(b, physics.of(k).ball.r))
            .collect();
        let strike = piece.strikes.get(k).copied().flatten();
        let label = format!("Table {}", batch.table_id(k));
        let png = render_shot_png(
            &table,
            physics.of(k),
            options.limits,
            &balls,
            batch.ball_ids(k),
            strike,
            &label,
            &[],
        )?;
        write_output(Some(path), |w| w.write_all(&png).map_err(output_error))?;
    }
    let ran_on = engine.describe();
    let s = stats;
    let secs = s.sim_seconds.max(1e-9);
    eprintln!(
        "{} tables, {} events in {:.3} s: {:.0} tables/s, {:.0} events/s on {ran_on}",
        s.tables,
        s.events,
        s.sim_seconds,
        s.tables as f64 / secs,
        s.events as f64 / secs
    );
    if let Some(first) = first_cut {
        eprintln!(
            "kisstime: {} tables were cut by --max-events or --max-time (the first: table \
             {first}){}",
            s.cut,
            if outcomes_path.is_some() {
                ""
            } else {
                "; --outcomes lists them"
            }
        );
    }
    Ok(())
}

/// The test hook of the `testing` feature (never in an ordinary build): with
/// `KISSTIME_TEST_GPU_FAULT=lost-after:N` or `dispatch-after:N` the GPU event loop (4 events
/// a dispatch, chunks of `KISSTIME_TEST_GPU_CHUNK` tables, default 8) loses its device, or
/// has a dispatch fail, after N dispatches: how `tests/gpu_event_loop_faults.rs` makes a GPU
/// fail in the middle of a `kisstime simulate` run.
#[cfg(feature = "testing")]
fn inject_test_fault(engine: &mut ShotEngine) {
    use kisstime::gpu::Fault;
    let Ok(spec) = std::env::var("KISSTIME_TEST_GPU_FAULT") else {
        return;
    };
    let (kind, n) = spec.split_once(':').unwrap_or((spec.as_str(), "0"));
    let n: u32 = n.parse().unwrap_or(0);
    let fault = match kind {
        "lost-after" => Fault::DeviceLostAfter(n),
        _ => Fault::FailedDispatchAfter(n),
    };
    let chunk = std::env::var("KISSTIME_TEST_GPU_CHUNK")
        .ok()
        .and_then(|c| c.parse().ok())
        .unwrap_or(8);
    engine.set_gpu_chunk_tables(Some(chunk));
    if let Some(g) = engine.gpu() {
        g.events_per_dispatch = 4;
        g.inject_fault(fault);
    }
}
