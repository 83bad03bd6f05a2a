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
}
use record::StrikeRecord;

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
    match Format::of(Some(path)) {
        Format::Csv => read_csv(reader, &name),
        Format::Npy => read_npy(reader, &name),
    }
}

fn read_csv(reader: impl std::io::Read, file: &str) -> Result<Vec<StrikeRow>, Error> {
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
    if header != STRIKE_COLUMNS {
        return Err(err(
            1,
            format!(
                "the header must be {} (found {})",
                STRIKE_COLUMNS.join(","),
                header.join(",")
            ),
        ));
    }
    let mut rows = Vec::new();
    while rdr.read_record(&mut rec).map_err(bad_csv)? {
        let line = rec.position().map_or(0, |p| p.line());
        if rec.len() != STRIKE_COLUMNS.len() {
            return Err(err(
                line,
                format!(
                    "expected {} fields ({}), found {}",
                    STRIKE_COLUMNS.len(),
                    STRIKE_COLUMNS.join(","),
                    rec.len()
                ),
            ));
        }
        let table: i64 = rec[0]
            .parse()
            .map_err(|_| err(line, format!("table id {:?} is not an integer", &rec[0])))?;
        let ball: i64 = rec[1].parse().map_err(|_| {
            Error::from(
                locate(
                    InputError::new(format!("ball id {:?} is not an integer", &rec[1])),
                    file,
                    Format::Csv,
                    line,
                )
                .at_table(table),
            )
        })?;
        let mut v = [0.0f64; 5];
        for (k, x) in v.iter_mut().enumerate() {
            let text = &rec[2 + k];
            *x = text.parse().map_err(|_| {
                Error::from(
                    locate(
                        InputError::new(format!(
                            "{} {text:?} is not a number",
                            STRIKE_COLUMNS[2 + k]
                        )),
                        file,
                        Format::Csv,
                        line,
                    )
                    .at_table(table)
                    .at_ball(ball),
                )
            })?;
        }
        rows.push(row(table, ball, v, line));
    }
    Ok(rows)
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

fn read_npy(reader: impl std::io::Read, file: &str) -> Result<Vec<StrikeRow>, Error> {
    let bad = |msg: String| Error::from(InputError::new(msg).in_file(file));
    let npy =
        npyz::NpyFile::new(reader).map_err(|e| bad(format!("not a readable .npy file: {e}")))?;
    let expected = format!(
        "expected a 1-D structured array with fields {} (table, ball integers), or a 2-D \
         float64 array of shape (N, 7)",
        STRIKE_COLUMNS.join(",")
    );
    let shape = npy.shape().to_vec();
    let read_err = |row: u64, e: std::io::Error| {
        Error::from(
            InputError::new(format!("unreadable data: {e}"))
                .in_file(file)
                .at_row(row),
        )
    };
    let mut rows = Vec::new();
    match npy.dtype() {
        npyz::DType::Record(_) if shape.len() == 1 => {
            let data = npy
                .data::<StrikeRecord>()
                .map_err(|e| bad(format!("{expected}: {e}")))?;
            for (r, rec) in (0u64..).zip(data) {
                let s = rec.map_err(|e| read_err(r, e))?;
                rows.push(row(s.table, s.ball, [s.V0, s.phi, s.theta, s.a, s.b], r));
            }
        }
        npyz::DType::Plain(_) if shape.len() == 2 && shape[1] == 7 => {
            let data: Vec<f64> = npy
                .into_vec()
                .map_err(|e| bad(format!("{expected}: {e}")))?;
            for (r, v) in (0u64..).zip(data.chunks_exact(7)) {
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
                let table = id(v[0], "table")?;
                let ball = id(v[1], "ball")?;
                rows.push(row(table, ball, [v[2], v[3], v[4], v[5], v[6]], r));
            }
        }
        other => {
            return Err(bad(format!(
                "{expected}; found {} of shape {shape:?}",
                other.descr()
            )));
        }
    }
    Ok(rows)
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
        let rows = read_csv(text.as_bytes(), "s.csv").unwrap();
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
            let err = read_csv(text.as_bytes(), "s.csv")
                .and_then(|rows| match_strikes(&batch, &rows, "s.csv", Format::Csv))
                .unwrap_err()
                .to_string();
            assert!(err.contains(want), "{bad}: {err}");
        }
        let twice = "table,ball,V0,phi,theta,a,b\n1,0,2,90,0,0,0\n1,4,2,90,0,0,0\n";
        let rows = read_csv(twice.as_bytes(), "s.csv").unwrap();
        let err = match_strikes(&batch, &rows, "s.csv", Format::Csv)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("line 3, table 1") && err.contains("line 2"),
            "{err}"
        );
    }
}
