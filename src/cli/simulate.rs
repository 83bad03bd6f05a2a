//! `kisstime simulate`: whole shots, from the strike to rest, for every table of a batch
//! ([`kisstime::simulate::simulate_batch`] on the CPU, streamed to the outputs chunk by
//! chunk; or the GPU event loop, [`kisstime::gpu::GpuSimulator`], for `--backend gpu|auto`).

use std::io::Write;
use std::path::{Path, PathBuf};

use kisstime::engine::{Backend, Precision, ShotEngine};
use kisstime::game::{Context, Shot};
use kisstime::io::Format;
use kisstime::io::context::{default_context, read_contexts};
use kisstime::io::sim_output::{EventsWriter, FinalWriter, OutcomesWriter, TableIds};
use kisstime::io::strikes::{StrikeRow, match_strikes, read_strikes};
use kisstime::io::table_json::table_by_name;
use kisstime::io::{output_error, write_output};
use kisstime::simulate::{BallState, BatchError, BatchOptions, Limits, SimError, TableRun};
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

/// An optional output: written atomically to `path`, or to standard output when
/// `to_stdout`, or not at all (`body` gets `None`).
fn maybe_output(
    path: Option<&Path>,
    to_stdout: bool,
    body: impl FnOnce(Option<&mut dyn Write>) -> Result<(), Error>,
) -> Result<(), Error> {
    if path.is_some() || to_stdout {
        write_output(path, |w| body(Some(w)))
    } else {
        body(None)
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
    let batch = read_input(&args.input)?;
    let batch_physics = kisstime::io::physics::read_batch_physics_on(
        args.physics.as_deref(),
        &(0..batch.num_tables())
            .map(|k| batch.table_id(k))
            .collect::<Vec<_>>(),
        &args.table,
    )?;
    let physics = batch_physics.as_physics();
    let plotted = match &args.plot {
        Some(_) => Some(plotted_table(&batch, args.table_id)?),
        None => None,
    };
    let (strike_rows, strikes) = match &args.strikes {
        Some(path) => {
            let rows = read_strikes(path)?;
            let file = path.display().to_string();
            let strikes = match_strikes(&batch, &rows, &file, Format::of(Some(path)))?;
            (rows, strikes)
        }
        None => (Vec::new(), Vec::new()),
    };
    let n = batch.num_tables();
    let rules = args.rules.map(RulesArg::rules);
    let contexts: Vec<Context> = match (rules, &args.context) {
        (Some(rules), Some(path)) => {
            let ids: Vec<i64> = (0..n).map(|k| batch.table_id(k)).collect();
            read_contexts(path, rules, &ids, |k| batch.ball_ids(k), &table.pocket_ids)?
        }
        (Some(rules), None) => vec![default_context(rules); n],
        (None, _) => Vec::new(),
    };
    // the game's part of each context (8-ball: every shot but the break is called)
    let contexts: Vec<Context> = match rules {
        Some(rules) => contexts
            .into_iter()
            .map(|c| rules.context(Context { wpa: args.wpa, ..c }))
            .collect(),
        None => contexts,
    };
    if args.verbose {
        eprintln!(
            "kisstime: simulating {n} tables ({} balls, {} strikes) on {} with {} threads",
            batch.num_balls(),
            strike_rows.len(),
            args.table,
            rayon::current_num_threads()
        );
    }
    let options = BatchOptions {
        limits,
        // the rules judge a shot from its events
        record_events: args.output.is_some() || args.rules.is_some(),
        ..BatchOptions::default()
    };
    let mut engine = ShotEngine::new(args.backend.backend(), args.precision.precision())?;
    let say = |engine: &mut ShotEngine| {
        for note in engine.take_notes() {
            eprintln!("kisstime: {note}");
        }
    };
    say(&mut engine);
    let events_path = args.output.as_deref();
    let final_path = args.final_states.as_deref();
    let outcomes_path = args.outcomes.as_deref();
    let final_to_stdout = events_path.is_none() && final_path.is_none();
    let mut stats = None;
    let mut first_cut = None;
    maybe_output(events_path, false, |events_out| {
        maybe_output(final_path, final_to_stdout, |final_out| {
            maybe_output(outcomes_path, false, |outcomes_out| {
                let e_err = out_err(events_path);
                let f_err = out_err(final_path);
                let o_err = out_err(outcomes_path);
                let mut events = match events_out {
                    Some(w) => Some(EventsWriter::new(w, Format::of(events_path)).map_err(&e_err)?),
                    None => None,
                };
                let mut finals = match final_out {
                    Some(w) => Some(
                        FinalWriter::new(w, Format::of(final_path), batch.num_balls() as u64)
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
                        OutcomesWriter::new(w, Format::of(outcomes_path), n as u64)
                            .map_err(&o_err)?,
                    ),
                    None => None,
                };
                let mut start = Vec::new();
                let bar = Progress::new("simulating", n as u64, "tables", n >= SHOW_TABLES);
                let mut write_run = |run: &TableRun| -> Result<(), Error> {
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
                                .judge(&shot, &contexts[k])
                                .map_err(|e| table_error(args, &batch, &strike_rows, k, e))?;
                            w.write_judged(ids, run, &v).map_err(&o_err)?;
                        }
                        (Some(w), None) => w.write_table(ids, run).map_err(&o_err)?,
                        (None, _) => {}
                    }
                    Ok(())
                };
                let input = batch.sim_input_for(&strikes, physics);
                let result = engine.simulate_with(&table, physics, &options, n, input, |chunk| {
                    for run in chunk.iter() {
                        write_run(&run)?;
                    }
                    bar.inc(chunk.len() as u64);
                    Ok::<(), Error>(())
                });
                say(&mut engine);
                bar.done();
                let s = result.map_err(|e| match e {
                    BatchError::Table { table: k, error } => {
                        table_error(args, &batch, &strike_rows, k, error)
                    }
                    BatchError::Sink(e) => e,
                })?;
                if let Some(w) = events {
                    w.finish().map_err(&e_err)?;
                }
                if let Some(w) = finals {
                    w.finish().map_err(&f_err)?;
                }
                if let Some(w) = outcomes {
                    w.finish().map_err(&o_err)?;
                }
                stats = Some(s);
                Ok(())
            })
        })
    })?;
    if let (Some(path), Some(k)) = (&args.plot, plotted) {
        let balls: Vec<BallState> = batch
            .balls(k)
            .iter()
            .map(|b| BallState::from_ball(b, physics.of(k).ball.r))
            .collect();
        let strike = strikes.get(k).copied().flatten();
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
    if let Some(s) = stats {
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
    }
    Ok(())
}
