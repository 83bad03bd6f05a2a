//! CSV input and output (the layouts are in [`crate::io`]).

use std::io::{Read, Write};
use std::path::Path;

use super::columns::{
    BALL_COLUMNS, BALL_NUMBER_COLUMNS, BallRows, BallSink, NEXT_COLUMNS, PAIR_COLUMNS,
};
use crate::batch::{Batch, NextCollision};
use crate::error::{Error, InputError};
use crate::model::{Ball, MotionState, UnknownState};
use crate::query::ball_ball::Contact;

/// Reads a batch from a CSV file (see the module docs). Errors name the file, the line,
/// and the table and ball where known.
pub fn read_batch_csv_path(path: &Path) -> Result<Batch, Error> {
    let name = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|source| Error::Io {
        path: name.clone(),
        source,
    })?;
    read_batch_csv(std::io::BufReader::new(file), &name)
}

/// Reads a batch from CSV text; `file` is the name used in error messages.
pub fn read_batch_csv<R: Read>(reader: R, file: &str) -> Result<Batch, Error> {
    let mut rows = BallRows::default();
    read_rows_csv(reader, file, &mut rows)?;
    rows.into_batch("line", |e, line| e.in_file(file).at_line(line))
}

/// The balls of a CSV batch, each checked, handed to `rows` in file order with their line.
pub(crate) fn read_rows_csv<R: Read>(
    reader: R,
    file: &str,
    rows: &mut impl BallSink,
) -> Result<(), Error> {
    let err = |line: u64, msg: String| InputError::new(msg).in_file(file).at_line(line);
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(reader);
    let mut rec = csv::StringRecord::new();
    if !rdr.read_record(&mut rec).map_err(|e| csv_error(e, file))? {
        return Err(err(1, "the file is empty; expected the header line".into()).into());
    }
    check_header(&rec).map_err(|m| err(1, m))?;

    while rdr.read_record(&mut rec).map_err(|e| csv_error(e, file))? {
        let line = rec.position().map_or(0, |p| p.line());
        if rec.len() != BALL_COLUMNS.len() {
            return Err(err(
                line,
                format!(
                    "expected {} fields ({}), found {}",
                    BALL_COLUMNS.len(),
                    BALL_COLUMNS.join(","),
                    rec.len()
                ),
            )
            .into());
        }
        let table: i64 = rec[0]
            .parse()
            .map_err(|_| err(line, format!("table id {:?} is not an integer", &rec[0])))?;
        let ball: i64 = rec[1].parse().map_err(|_| {
            err(line, format!("ball id {:?} is not an integer", &rec[1])).at_table(table)
        })?;
        let at = |msg: String| err(line, msg).at_table(table).at_ball(ball);
        let state: MotionState = rec[2]
            .parse()
            .map_err(|e: UnknownState| at(e.to_string()))?;
        let mut v = [0.0f64; 7];
        for (k, name) in BALL_NUMBER_COLUMNS.iter().enumerate() {
            let text = &rec[3 + k];
            let value: f64 = text
                .parse()
                .map_err(|_| at(format!("{name} {text:?} is not a number")))?;
            if !value.is_finite() {
                return Err(at(format!("{name} is {text}, numbers must be finite")).into());
            }
            v[k] = value;
        }
        rows.push(table, ball, Ball::from_numbers(state, v), line)?;
    }
    Ok(())
}

/// Checks the header row against [`BALL_COLUMNS`], naming a missing or extra column.
fn check_header(header: &csv::StringRecord) -> Result<(), String> {
    let got: Vec<&str> = header.iter().collect();
    if got == BALL_COLUMNS {
        return Ok(());
    }
    let expected = BALL_COLUMNS.join(",");
    if let Some(missing) = BALL_COLUMNS.iter().find(|c| !got.contains(c)) {
        return Err(format!(
            "missing column {missing:?}; the header must be {expected}"
        ));
    }
    if let Some(extra) = got.iter().find(|c| !BALL_COLUMNS.contains(c)) {
        return Err(format!(
            "unexpected column {extra:?}; the header must be {expected}"
        ));
    }
    Err(format!(
        "columns out of order or repeated ({}); the header must be {expected}",
        got.join(",")
    ))
}

/// A CSV syntax or encoding error as an input error with its line.
fn csv_error(e: csv::Error, file: &str) -> Error {
    let line = e.position().map(|p| p.line());
    let mut ie = InputError::new(format!("unreadable CSV: {e}")).in_file(file);
    ie.line = line;
    if let csv::ErrorKind::Io(_) = e.kind() {
        return Error::Io {
            path: file.to_owned(),
            source: std::io::Error::other(e.to_string()),
        };
    }
    ie.into()
}

/// Formats a time as the shortest decimal that reads back as the same f64; `inf` for ∞.
pub fn format_time(t: f64, buf: &mut ryu::Buffer) -> &str {
    if t == f64::INFINITY {
        "inf"
    } else {
        buf.format(t)
    }
}

/// Formats a number as the shortest decimal that reads back as the same f64; empty for a
/// value that is not finite (a field that does not apply, as the per-sample CSVs write it).
pub fn format_finite(v: f64, buf: &mut ryu::Buffer) -> &str {
    if v.is_finite() { buf.format(v) } else { "" }
}

/// Writes per-pair answers (as [`crate::pair_times`] returns them) as CSV (the layout in [`crate::io`]).
pub fn write_pairs_csv<W: Write + ?Sized>(
    out: &mut W,
    batch: &Batch,
    contacts: &[Contact],
) -> std::io::Result<()> {
    writeln!(out, "{PAIR_COLUMNS}")?;
    write_pairs_rows(out, batch, 0..batch.num_tables(), contacts)
}

/// Writes the per-pair rows (no header) of the tables `tables`, whose answers are
/// `contacts` (as [`crate::pair_times_of`] returns them).
pub fn write_pairs_rows<W: Write + ?Sized>(
    out: &mut W,
    batch: &Batch,
    tables: std::ops::Range<usize>,
    contacts: &[Contact],
) -> std::io::Result<()> {
    let mut tb = ryu::Buffer::new();
    let mut hb = ryu::Buffer::new();
    for ((table, i, j), c) in batch.pair_ids(tables).zip(contacts) {
        writeln!(
            out,
            "{table},{i},{j},{},{},{}",
            format_time(c.t, &mut tb),
            c.status,
            format_time(c.horizon, &mut hb)
        )?;
    }
    Ok(())
}

/// Writes each table's next collision as CSV `table,t,i,j,status`: `t` the shortest decimal
/// that reads back as the same f64, `inf` and empty ids when the table has none.
pub fn write_next_csv<W: Write + ?Sized>(
    out: &mut W,
    next: &[NextCollision],
) -> std::io::Result<()> {
    writeln!(out, "{NEXT_COLUMNS}")?;
    let mut tb = ryu::Buffer::new();
    for n in next {
        let t = format_time(n.t, &mut tb);
        match n.pair {
            Some((i, j)) => writeln!(out, "{},{t},{i},{j},{}", n.table, n.status)?,
            None => writeln!(out, "{},{t},,,{}", n.table, n.status)?,
        }
    }
    Ok(())
}

/// Writes a batch as input CSV (the layout in [`crate::io`]), numbers as the shortest decimals that read
/// back as the same f64: `read_batch_csv` of the result gives the same batch.
pub fn write_batch_csv<W: Write + ?Sized>(out: &mut W, batch: &Batch) -> std::io::Result<()> {
    writeln!(out, "{}", BALL_COLUMNS.join(","))?;
    let mut buf = ryu::Buffer::new();
    for k in 0..batch.num_tables() {
        let table = batch.table_id(k);
        for (id, ball) in batch.ball_ids(k).iter().zip(batch.balls(k)) {
            write!(out, "{table},{id},{}", ball.state)?;
            for v in ball.numbers() {
                write!(out, ",{}", buf.format(v))?;
            }
            writeln!(out)?;
        }
    }
    Ok(())
}
