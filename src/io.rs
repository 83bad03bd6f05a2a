//! Reading and writing batches as CSV.
//!
//! # Input
//! Header `table,ball,state,x,y,vx,vy,wx,wy,wz`, one row a ball: `table` and `ball` are
//! integer ids, `state` one of `stationary`, `spinning`, `sliding`, `rolling`, `pocketed`,
//! then position (m), velocity (m/s) and angular velocity (rad/s). Rows of one table need
//! not be adjacent; fields may be padded with spaces. Tables are answered in ascending id
//! order, balls in ascending id order.
//!
//! # Output
//! [`write_pairs_csv`]: header `table,i,j,t,status,horizon`, one row a pair with `i < j`
//! the ball ids, `t` and `horizon` in seconds printed as the shortest decimal that reads
//! back as the same f64 (`inf` when there is no collision or no horizon), `status` one of
//! `hit`, `none`, `overlap`.

use std::collections::BTreeMap;
use std::collections::HashMap;
use std::io::{Read, Write};
use std::path::Path;

use crate::batch::Batch;
use crate::error::{Error, InputError};
use crate::physics::{Ball, MotionState};
use crate::solver::Contact;

/// The input columns, in order.
pub const BALL_COLUMNS: [&str; 10] = [
    "table", "ball", "state", "x", "y", "vx", "vy", "wx", "wy", "wz",
];
/// The numeric ball columns, in the order of [`Ball::numbers`].
pub const BALL_NUMBER_COLUMNS: [&str; 7] = ["x", "y", "vx", "vy", "wx", "wy", "wz"];
/// The per-pair output columns.
pub const PAIR_COLUMNS: &str = "table,i,j,t,status,horizon";

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

/// One parsed row, before grouping by table.
struct Row {
    line: u64,
    ball: i64,
    data: Ball,
}

/// Reads a batch from CSV text; `file` is the name used in error messages.
pub fn read_batch_csv<R: Read>(reader: R, file: &str) -> Result<Batch, Error> {
    let err = |line: u64, msg: String| InputError::new(msg).in_file(file).at_line(line);
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(reader);
    let mut records = rdr.records();
    let header = match records.next() {
        None => return Err(err(1, "the file is empty; expected the header line".into()).into()),
        Some(rec) => rec.map_err(|e| csv_error(e, file))?,
    };
    check_header(&header).map_err(|m| err(1, m))?;

    let mut tables: BTreeMap<i64, Vec<Row>> = BTreeMap::new();
    let mut first_line: HashMap<(i64, i64), u64> = HashMap::new();
    for rec in records {
        let rec = rec.map_err(|e| csv_error(e, file))?;
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
            .map_err(|e: crate::physics::UnknownState| at(e.to_string()))?;
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
        if let Some(first) = first_line.insert((table, ball), line) {
            return Err(at(format!("duplicate ball id (first on line {first})")).into());
        }
        let data = Ball {
            state,
            x: v[0],
            y: v[1],
            vx: v[2],
            vy: v[3],
            wx: v[4],
            wy: v[5],
            wz: v[6],
        };
        tables
            .entry(table)
            .or_default()
            .push(Row { line, ball, data });
    }

    let mut batch = Batch::new();
    for (table, rows) in tables {
        if rows.len() < 2 {
            let row = &rows[0];
            return Err(err(
                row.line,
                format!("a table needs at least 2 balls, table {table} has 1"),
            )
            .at_table(table)
            .at_ball(row.ball)
            .into());
        }
        batch
            .push_table(table, rows.iter().map(|r| (r.ball, r.data)))
            .map_err(|e| match e {
                Error::Input(ie) => Error::Input(ie.in_file(file)),
                other => other,
            })?;
    }
    Ok(batch)
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

/// Writes per-pair answers (as [`crate::pair_times`] returns them) as CSV (module docs).
pub fn write_pairs_csv<W: Write + ?Sized>(
    out: &mut W,
    batch: &Batch,
    contacts: &[Contact],
) -> std::io::Result<()> {
    writeln!(out, "{PAIR_COLUMNS}")?;
    let mut tb = ryu::Buffer::new();
    let mut hb = ryu::Buffer::new();
    for k in 0..batch.num_tables() {
        let ids = batch.ball_ids(k);
        let table = batch.table_id(k);
        let mut at = batch.pair_range(k).start;
        for i in 0..ids.len() {
            for j in i + 1..ids.len() {
                let c = &contacts[at];
                at += 1;
                writeln!(
                    out,
                    "{table},{},{},{},{},{}",
                    ids[i],
                    ids[j],
                    format_time(c.t, &mut tb),
                    c.status,
                    format_time(c.horizon, &mut hb)
                )?;
            }
        }
    }
    Ok(())
}

/// Writes to `path` atomically: the content goes to a temporary file in the same folder,
/// which is renamed over `path` only when `write` succeeded and the data reached the disk.
/// On any error nothing is left under `path` (an earlier file there is kept as it was).
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), Error> {
    let name = path.display().to_string();
    let io = |source| Error::Io {
        path: name.clone(),
        source,
    };
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let tmp = tempfile::Builder::new()
        .prefix(".kisstime-")
        .tempfile_in(dir)
        .map_err(io)?;
    let mut w = std::io::BufWriter::new(tmp);
    write(&mut w).map_err(io)?;
    let tmp = w.into_inner().map_err(|e| io(e.into_error()))?;
    tmp.as_file().sync_all().map_err(io)?;
    tmp.persist(path).map_err(|e| io(e.error))?;
    Ok(())
}
