//! Cue strikes for `kisstime simulate`: a file of `table,ball,V0,phi,theta,a,b`
//! ([`STRIKE_COLUMNS`]), one row per struck table, with pooltool's `Cue.set_state`
//! conventions ([`CueStrike`]): V0 the cue speed in m/s, phi the aim in degrees
//! counter-clockwise from +x, theta the cue elevation in degrees, (a, b) the tip's contact
//! point as fractions of R (a side, b height). CSV with that header, or `.npy`: a 1-D
//! structured array with those fields (`table`, `ball` integers, the rest `<f8`) or a 2-D
//! float64 array of shape (N, 7) in that column order.
//!
//! [`read_strikes`] reads the rows; [`match_strikes`] puts them on a batch's tables and
//! checks them. Errors name the file, the line (CSV) or row (`.npy`), the table and the
//! ball.

use std::collections::HashMap;
use std::path::Path;

use super::Format;
use crate::batch::Batch;
use crate::error::{Error, InputError};
use crate::resolve::stick_ball::CueStrike;

/// The strike file's columns, in order.
pub const STRIKE_COLUMNS: [&str; 7] = ["table", "ball", "V0", "phi", "theta", "a", "b"];

/// The columns of a shot study's strike file (`kisstime shots --strikes`), in order: the
/// sample id, then the strike as in [`STRIKE_COLUMNS`].
pub const SAMPLE_STRIKE_COLUMNS: [&str; 6] = ["sample", "V0", "phi", "theta", "a", "b"];

/// One strike of a study's strike file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleStrike {
    /// The sample id.
    pub sample: i64,
    /// The strike, checked ([`CueStrike::validate`]).
    pub strike: CueStrike,
    /// Where it was read: the 1-based line (CSV) or the 0-based row (`.npy`).
    pub at: u64,
}

/// One strike as read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrikeRow {
    /// The table id.
    pub table: i64,
    /// The struck ball's id.
    pub ball: i64,
    /// The strike.
    pub strike: CueStrike,
    /// Where it was read: the 1-based line (CSV) or the 0-based row (`.npy`).
    pub at: u64,
}

#[allow(non_snake_case)]
mod record {
    /// One strike, a row of the structured `.npy` layout (the field names are the
    /// columns', `V0` included).
    #[derive(npyz::Deserialize, npyz::AutoSerialize, npyz::Serialize)]
    pub(super) struct StrikeRecord {
        pub table: i64,
        pub ball: i64,
        pub V0: f64,
        pub phi: f64,
        pub theta: f64,
        pub a: f64,
        pub b: f64,
    }

    /// One strike of a study's file, a row of its structured `.npy` layout.
    #[derive(npyz::Deserialize, npyz::AutoSerialize, npyz::Serialize)]
    pub(super) struct SampleRecord {
        pub sample: i64,
        pub V0: f64,
        pub phi: f64,
        pub theta: f64,
        pub a: f64,
        pub b: f64,
    }
}
use record::{SampleRecord, StrikeRecord};

/// Locates an error at `at` of `file` in the unit of `format` (line or row).
pub fn locate(e: InputError, file: &str, format: Format, at: u64) -> InputError {
    let e = e.in_file(file);
    match format {
        Format::Csv => e.at_line(at),
        Format::Npy => e.at_row(at),
    }
}

/// Reads a strike file (CSV, or `.npy` when its name says so).
pub fn read_strikes(path: &Path) -> Result<Vec<StrikeRow>, Error> {
    let name = path.display().to_string();
    let io = |source| Error::Io {
        path: name.clone(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let reader = std::io::BufReader::new(file);
    parse_strikes(reader, &name, Format::of(Some(path)))
}

/// [`read_strikes`] of bytes from `reader` in `format` (`file` names them in errors).
pub fn parse_strikes(
    reader: impl std::io::Read,
    file: &str,
    format: Format,
) -> Result<Vec<StrikeRow>, Error> {
    match format {
        Format::Csv => read_csv(reader, file, &STRIKE_COLUMNS),
        Format::Npy => read_npy(reader, file, &STRIKE_COLUMNS),
    }
}

/// [`read_strikes`] a row at a time: each row, in file order, handed to `each` (whose
/// error stops the read and is returned), so that a file of millions of strikes need not be
/// held (`kisstime simulate` streams its inputs this way; see [`crate::io::stream`]).
pub fn read_strikes_each(
    path: &Path,
    each: &mut dyn FnMut(StrikeRow) -> Result<(), Error>,
) -> Result<(), Error> {
    let name = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|source| Error::Io {
        path: name.clone(),
        source,
    })?;
    let reader = std::io::BufReader::new(file);
    match Format::of(Some(path)) {
        Format::Csv => each_csv(reader, &name, &STRIKE_COLUMNS, each),
        Format::Npy => each_npy(reader, &name, &STRIKE_COLUMNS, each),
    }
}

/// Reads a shot study's strike file ([`SAMPLE_STRIKE_COLUMNS`]; CSV, or `.npy` when its
/// name says so: a 1-D structured array with those fields, `sample` an integer, or a 2-D
/// float64 array of shape (N, 6)). Every strike is checked ([`CueStrike::validate`]: finite,
/// V0 ≥ 0, the tip on the ball) and sample ids must not repeat; errors name the file, the
/// line or row and the sample.
pub fn read_sample_strikes(path: &Path) -> Result<Vec<SampleStrike>, Error> {
    let name = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|source| Error::Io {
        path: name.clone(),
        source,
    })?;
    let reader = std::io::BufReader::new(file);
    parse_sample_strikes(reader, &name, Format::of(Some(path)))
}

/// [`read_sample_strikes`] of bytes from `reader` in `format` (`file` names them in
/// errors).
pub fn parse_sample_strikes(
    reader: impl std::io::Read,
    file: &str,
    format: Format,
) -> Result<Vec<SampleStrike>, Error> {
    let rows = match format {
        Format::Csv => read_csv(reader, file, &SAMPLE_STRIKE_COLUMNS)?,
        Format::Npy => read_npy(reader, file, &SAMPLE_STRIKE_COLUMNS)?,
    };
    sample_strikes(rows, file, format)
}

/// A study's strikes from columns held in memory (the Python package's arrays), checked
/// and located as [`read_sample_strikes`] checks a `.npy` file's rows (`source` in place
/// of the file name): `sample[r]` and `v[k][r]` for `V0, phi, theta, a, b`.
pub fn sample_strikes_from_columns(
    source: &str,
    sample: &[i64],
    v: [&[f64]; 5],
) -> Result<Vec<SampleStrike>, Error> {
    let rows = rows_from_columns(source, sample, None, v)?;
    sample_strikes(rows, source, Format::Npy)
}

/// `kisstime simulate`'s strikes from columns held in memory (`table[r]`, `ball[r]`,
/// `v[k][r]` for `V0, phi, theta, a, b`), located by row as in a `.npy` file; check them
/// with [`match_strikes`] (format [`Format::Npy`]).
pub fn strike_rows_from_columns(
    source: &str,
    table: &[i64],
    ball: &[i64],
    v: [&[f64]; 5],
) -> Result<Vec<StrikeRow>, Error> {
    rows_from_columns(source, table, Some(ball), v)
}

fn rows_from_columns(
    source: &str,
    ids: &[i64],
    balls: Option<&[i64]>,
    v: [&[f64]; 5],
) -> Result<Vec<StrikeRow>, Error> {
    let n = ids.len();
    if balls.is_some_and(|b| b.len() != n) || v.iter().any(|c| c.len() != n) {
        return Err(InputError::new("strike columns of different lengths")
            .in_file(source)
            .into());
    }
    Ok((0..n)
        .map(|r| {
            let ball = balls.map_or(0, |b| b[r]);
            row(
                ids[r],
                ball,
                [v[0][r], v[1][r], v[2][r], v[3][r], v[4][r]],
                r as u64,
            )
        })
        .collect())
}

/// Checks the rows of a study's strike file (see [`read_sample_strikes`]).
fn sample_strikes(
    rows: Vec<StrikeRow>,
    file: &str,
    format: Format,
) -> Result<Vec<SampleStrike>, Error> {
    let mut seen: HashMap<i64, u64> = HashMap::with_capacity(rows.len());
    let mut out = Vec::with_capacity(rows.len());
    for r in rows {
        let at = |msg: String| {
            Error::from(locate(
                InputError::new(format!("sample {}: {msg}", r.table)),
                file,
                format,
                r.at,
            ))
        };
        if let Some(first) = seen.insert(r.table, r.at) {
            let unit = if format == Format::Csv { "line" } else { "row" };
            return Err(at(format!("the sample id is also on {unit} {first}")));
        }
        r.strike.validate().map_err(|e| at(e.to_string()))?;
        out.push(SampleStrike {
            sample: r.table,
            strike: r.strike,
            at: r.at,
        });
    }
    if out.is_empty() {
        return Err(InputError::new("no strikes: the file has no rows")
            .in_file(file)
            .into());
    }
    Ok(out)
}

/// Reads CSV rows of `columns`: [`STRIKE_COLUMNS`] (table and ball ids) or
/// [`SAMPLE_STRIKE_COLUMNS`] (a sample id, returned as the row's `table`, `ball` = 0).
fn read_csv(
    reader: impl std::io::Read,
    file: &str,
    columns: &[&str],
) -> Result<Vec<StrikeRow>, Error> {
    let mut rows = Vec::new();
    each_csv(reader, file, columns, &mut |r| {
        rows.push(r);
        Ok(())
    })?;
    Ok(rows)
}

/// [`read_csv`]'s rows handed to `push` one at a time, in file order.
fn each_csv(
    reader: impl std::io::Read,
    file: &str,
    columns: &[&str],
    push: &mut dyn FnMut(StrikeRow) -> Result<(), Error>,
) -> Result<(), Error> {
    let ids = columns.len() - 5;
    let err =
        |line: u64, msg: String| Error::from(locate(InputError::new(msg), file, Format::Csv, line));
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(reader);
    let bad_csv = |e: csv::Error| {
        let line = e.position().map_or(0, |p| p.line());
        err(line, format!("unreadable CSV: {e}"))
    };
    let mut rec = csv::StringRecord::new();
    if !rdr.read_record(&mut rec).map_err(bad_csv)? {
        return Err(err(1, "the file is empty; expected the header line".into()));
    }
    let header: Vec<&str> = rec.iter().collect();
    if header != columns {
        return Err(err(
            1,
            format!(
                "the header must be {} (found {})",
                columns.join(","),
                header.join(",")
            ),
        ));
    }
    while rdr.read_record(&mut rec).map_err(bad_csv)? {
        let line = rec.position().map_or(0, |p| p.line());
        if rec.len() != columns.len() {
            return Err(err(
                line,
                format!(
                    "expected {} fields ({}), found {}",
                    columns.len(),
                    columns.join(","),
                    rec.len()
                ),
            ));
        }
        let table: i64 = rec[0].parse().map_err(|_| {
            err(
                line,
                format!("{} id {:?} is not an integer", columns[0], &rec[0]),
            )
        })?;
        let ball: i64 = if ids == 1 {
            0
        } else {
            rec[1].parse().map_err(|_| {
                Error::from(
                    locate(
                        InputError::new(format!("ball id {:?} is not an integer", &rec[1])),
                        file,
                        Format::Csv,
                        line,
                    )
                    .at_table(table),
                )
            })?
        };
        let mut v = [0.0f64; 5];
        for (k, x) in v.iter_mut().enumerate() {
            let text = &rec[ids + k];
            *x = text.parse().map_err(|_| {
                let e = InputError::new(format!("{} {text:?} is not a number", columns[ids + k]));
                let e = locate(e, file, Format::Csv, line);
                Error::from(if ids == 1 {
                    InputError {
                        message: format!("sample {table}: {}", e.message),
                        ..e
                    }
                } else {
                    e.at_table(table).at_ball(ball)
                })
            })?;
        }
        push(row(table, ball, v, line))?;
    }
    Ok(())
}

fn row(table: i64, ball: i64, v: [f64; 5], at: u64) -> StrikeRow {
    let [v0, phi, theta, a, b] = v;
    StrikeRow {
        table,
        ball,
        strike: CueStrike {
            v0,
            phi,
            theta,
            a,
            b,
        },
        at,
    }
}

/// Reads `.npy` rows of `columns` (as [`read_csv`]).
fn read_npy(
    reader: impl std::io::Read,
    file: &str,
    columns: &[&str],
) -> Result<Vec<StrikeRow>, Error> {
    let mut rows = Vec::new();
    each_npy(reader, file, columns, &mut |r| {
        rows.push(r);
        Ok(())
    })?;
    Ok(rows)
}

/// [`read_npy`]'s rows handed to `push` one at a time, in file order.
fn each_npy(
    reader: impl std::io::Read,
    file: &str,
    columns: &[&str],
    push: &mut dyn FnMut(StrikeRow) -> Result<(), Error>,
) -> Result<(), Error> {
    let ids = columns.len() - 5;
    let bad = |msg: String| Error::from(InputError::new(msg).in_file(file));
    // the header checked as a batch's is (a fuzzed header hung or overflowed npyz)
    let npy = crate::io::npy::open_npy(reader).map_err(bad)?;
    let expected = format!(
        "expected a 1-D structured array with fields {} ({} integer{}), or a 2-D float64 \
         array of shape (N, {})",
        columns.join(","),
        columns[..ids].join(", "),
        if ids == 1 { "" } else { "s" },
        columns.len()
    );
    let shape = npy.shape().to_vec();
    let read_err = |row: u64, e: std::io::Error| {
        Error::from(
            InputError::new(format!("unreadable data: {e}"))
                .in_file(file)
                .at_row(row),
        )
    };
    match npy.dtype() {
        npyz::DType::Record(_) if shape.len() == 1 && ids == 2 => {
            let data = npy
                .data::<StrikeRecord>()
                .map_err(|e| bad(format!("{expected}: {e}")))?;
            for (r, rec) in (0u64..).zip(data) {
                let s = rec.map_err(|e| read_err(r, e))?;
                push(row(s.table, s.ball, [s.V0, s.phi, s.theta, s.a, s.b], r))?;
            }
        }
        npyz::DType::Record(_) if shape.len() == 1 => {
            let data = npy
                .data::<SampleRecord>()
                .map_err(|e| bad(format!("{expected}: {e}")))?;
            for (r, rec) in (0u64..).zip(data) {
                let s = rec.map_err(|e| read_err(r, e))?;
                push(row(s.sample, 0, [s.V0, s.phi, s.theta, s.a, s.b], r))?;
            }
        }
        npyz::DType::Plain(_) if shape.len() == 2 && shape[1] == columns.len() as u64 => {
            let data: Vec<f64> = npy
                .into_vec()
                .map_err(|e| bad(format!("{expected}: {e}")))?;
            for (r, v) in (0u64..).zip(data.chunks_exact(columns.len())) {
                let id = |x: f64, what: &str| {
                    if x.fract() == 0.0 && x.abs() < 9.0e15 {
                        Ok(x as i64)
                    } else {
                        Err(Error::from(
                            InputError::new(format!("{what} id {x} is not an integer"))
                                .in_file(file)
                                .at_row(r),
                        ))
                    }
                };
                let table = id(v[0], columns[0])?;
                let ball = if ids == 2 { id(v[1], "ball")? } else { 0 };
                let f = &v[ids..];
                push(row(table, ball, [f[0], f[1], f[2], f[3], f[4]], r))?;
            }
        }
        other => {
            return Err(bad(format!(
                "{expected}; found {} of shape {shape:?}",
                other.descr()
            )));
        }
    }
    Ok(())
}

/// Puts `rows` (read from `file`, in `format`) on the tables of `batch`: for each table
/// position, the struck ball's index in the table and the strike, or `None`. Errors name
/// the file, the line or row, the table and the ball: a table or ball not in the batch,
/// two strikes for one table, a strike that is not finite, has V0 < 0 or a² + b² > 1
/// ([`CueStrike::validate`]).
pub fn match_strikes(
    batch: &Batch,
    rows: &[StrikeRow],
    file: &str,
    format: Format,
) -> Result<Vec<Option<(usize, CueStrike)>>, Error> {
    let position: HashMap<i64, usize> = (0..batch.num_tables())
        .map(|k| (batch.table_id(k), k))
        .collect();
    let mut strikes = vec![None; batch.num_tables()];
    let mut seen: Vec<Option<u64>> = vec![None; batch.num_tables()];
    for r in rows {
        let at = |msg: String| locate(InputError::new(msg), file, format, r.at).at_table(r.table);
        let &k = position
            .get(&r.table)
            .ok_or_else(|| at("no such table in the input".to_owned()))?;
        let i = batch
            .ball_ids(k)
            .binary_search(&r.ball)
            .map_err(|_| at("no such ball on this table".to_owned()).at_ball(r.ball))?;
        if let Some(first) = seen[k] {
            let unit = if format == Format::Csv { "line" } else { "row" };
            return Err(at(format!(
                "a second strike for this table (the first is on {unit} {first}); at most one \
                 strike a table"
            ))
            .at_ball(r.ball)
            .into());
        }
        r.strike
            .validate()
            .map_err(|e| at(e.to_string()).at_ball(r.ball))?;
        seen[k] = Some(r.at);
        strikes[k] = Some((i, r.strike));
    }
    Ok(strikes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Ball;

    fn samples(text: &str) -> Result<Vec<SampleStrike>, Error> {
        let rows = read_csv(text.as_bytes(), "k.csv", &SAMPLE_STRIKE_COLUMNS)?;
        sample_strikes(rows, "k.csv", Format::Csv)
    }

    #[test]
    fn sample_strikes_are_read_and_bad_ones_named() {
        let ok =
            samples("sample,V0,phi,theta,a,b\n7,1.5,201.75,5,0,0.2\n2,1,90,0,0.1,0\n").unwrap();
        assert_eq!((ok[0].sample, ok[0].strike.phi, ok[0].at), (7, 201.75, 2));
        assert_eq!((ok[1].sample, ok[1].strike.a), (2, 0.1));
        for (bad, want) in [
            (
                "1,1.5,90,0,0.8,0.8",
                "k.csv, line 2: sample 1: strike: a² + b² > 1",
            ),
            ("1,-1,90,0,0,0", "line 2: sample 1: strike: V0 = -1 < 0"),
            (
                "1,x,90,0,0,0",
                "k.csv, line 2: sample 1: V0 \"x\" is not a number",
            ),
            ("q,1,90,0,0,0", "line 2: sample id \"q\" is not an integer"),
            ("1,1,90,0,0", "line 2: expected 6 fields"),
            (
                "1,1,90,0,0,0\n1,1,90,0,0,0",
                "line 3: sample 1: the sample id is also on line 2",
            ),
        ] {
            let err = samples(&format!("sample,V0,phi,theta,a,b\n{bad}\n")).unwrap_err();
            assert!(err.to_string().contains(want), "{bad}: {err}");
        }
        let err = samples("table,ball,V0,phi,theta,a,b\n")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("line 1: the header must be sample,V0,phi,theta,a,b"),
            "{err}"
        );
        let err = samples("sample,V0,phi,theta,a,b\n")
            .unwrap_err()
            .to_string();
        assert!(err.contains("no strikes"), "{err}");
    }

    #[test]
    fn strikes_are_matched_and_bad_ones_named() {
        let mut batch = Batch::new();
        for t in [3, 1] {
            batch
                .push_table(
                    t,
                    [(0, Ball::at_rest(0.5, 0.5)), (4, Ball::at_rest(0.5, 1.5))],
                )
                .unwrap();
        }
        let text = "table,ball,V0,phi,theta,a,b\n3,4,2,90,0,0.1,0.2\n";
        let rows = read_csv(text.as_bytes(), "s.csv", &STRIKE_COLUMNS).unwrap();
        let m = match_strikes(&batch, &rows, "s.csv", Format::Csv).unwrap();
        // table 3 was pushed first
        assert_eq!(m[0].map(|s| s.0), Some(1));
        assert_eq!(m[1], None);
        for (bad, want) in [
            ("9,4,2,90,0,0,0", "s.csv, line 2, table 9: no such table"),
            (
                "3,5,2,90,0,0,0",
                "s.csv, line 2, table 3, ball 5: no such ball",
            ),
            (
                "3,4,2,90,0,0.8,0.8",
                "s.csv, line 2, table 3, ball 4: strike: a² + b² > 1",
            ),
            ("3,4,nan,90,0,0,0", "table 3, ball 4: strike: non-finite"),
            ("3,4,2,90,0,0\n", "line 2: expected 7 fields"),
        ] {
            let text = format!("table,ball,V0,phi,theta,a,b\n{bad}\n");
            let err = read_csv(text.as_bytes(), "s.csv", &STRIKE_COLUMNS)
                .and_then(|rows| match_strikes(&batch, &rows, "s.csv", Format::Csv))
                .unwrap_err()
                .to_string();
            assert!(err.contains(want), "{bad}: {err}");
        }
        let twice = "table,ball,V0,phi,theta,a,b\n1,0,2,90,0,0,0\n1,4,2,90,0,0,0\n";
        let rows = read_csv(twice.as_bytes(), "s.csv", &STRIKE_COLUMNS).unwrap();
        let err = match_strikes(&batch, &rows, "s.csv", Format::Csv)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("line 3, table 1") && err.contains("line 2"),
            "{err}"
        );
    }
}
