//! Reading a batch file a chunk of tables at a time, so that a run over millions of tables
//! holds one chunk of its input, not the whole file ([`read_batch_chunks`]).
//!
//! A file can be read so only when its tables are already in order: each table's rows
//! adjacent, tables in ascending id order, balls in ascending id order within a table
//! (what `kisstime gen`, [`crate::io::write_batch`] and most generators write). Any other
//! order (which the input format allows: see [`crate::io`]) stops the read at the first
//! row out of order with [`Streamed::OutOfOrder`], and the caller reads the file whole
//! ([`crate::io::read_batch`]), which sorts it. Every chunk is checked and located exactly
//! as the whole file's tables are (the same readers, the same checks): an error names the
//! file, the line (CSV) or row (`.npy`), the table and the ball.

use std::io::Read;

use super::Format;
use super::columns::{BallRows, BallSink};
use crate::batch::Batch;
use crate::error::{Error, InputError};
use crate::model::Ball;

/// How a chunked read ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Streamed {
    /// Every table was handed over: the tables and balls in all.
    Done {
        /// Tables in the file.
        tables: usize,
        /// Balls in the file.
        balls: usize,
    },
    /// A row out of (table, ball) order, or a ball id repeated in a table: the file must be
    /// read whole (chunks before it may have been handed over).
    OutOfOrder,
    /// The file has no rows: read it whole, for the error a whole read gives.
    Empty,
}

/// Reads the batch file from `reader` in `format` and hands it to `each` in chunks of
/// consecutive tables, in file order: at most `max_tables` tables and, past the first
/// table of a chunk, at most `max_balls` balls a chunk. `each(batch, last)` gets a batch
/// of its own (table positions from 0) and whether it is the file's last chunk; its error
/// stops the read and is returned. `file` names the file in errors.
///
/// Tables, balls and errors are those of [`crate::io::read_batch`] on the same file where
/// it is in order (see the module docs); otherwise the read stops with
/// [`Streamed::OutOfOrder`] at the first row out of order.
pub fn read_batch_chunks<R: Read>(
    reader: R,
    format: Format,
    file: &str,
    max_tables: usize,
    max_balls: usize,
    each: impl FnMut(Batch, bool) -> Result<(), Error>,
) -> Result<Streamed, Error> {
    let unit = match format {
        Format::Csv => "line",
        Format::Npy => "row",
    };
    let mut chunks = Chunker {
        rows: BallRows::default(),
        last: None,
        tables_in_chunk: 0,
        tables: 0,
        balls: 0,
        max_tables: max_tables.max(1),
        max_balls: max_balls.max(1),
        out_of_order: false,
        unit,
        file,
        each,
    };
    let read = match format {
        Format::Csv => super::csv::read_rows_csv(reader, file, &mut chunks),
        Format::Npy => super::npy::read_rows_npy(reader, file, &mut chunks),
    };
    if chunks.out_of_order {
        return Ok(Streamed::OutOfOrder);
    }
    read?;
    if chunks.balls == 0 {
        return Ok(Streamed::Empty);
    }
    chunks.flush(true)?;
    Ok(Streamed::Done {
        tables: chunks.tables,
        balls: chunks.balls,
    })
}

/// The [`BallSink`] of [`read_batch_chunks`].
struct Chunker<'f, F> {
    /// The chunk being read.
    rows: BallRows,
    /// The last row's (table, ball).
    last: Option<(i64, i64)>,
    /// Tables in `rows`.
    tables_in_chunk: usize,
    /// Tables and balls read so far.
    tables: usize,
    balls: usize,
    max_tables: usize,
    max_balls: usize,
    /// Set when a row came out of order (the read then stops with an error of no meaning).
    out_of_order: bool,
    unit: &'static str,
    file: &'f str,
    each: F,
}

impl<F: FnMut(Batch, bool) -> Result<(), Error>> Chunker<'_, F> {
    /// Hands the chunk read so far to `each` as a batch.
    fn flush(&mut self, last: bool) -> Result<(), Error> {
        let rows = std::mem::take(&mut self.rows);
        self.tables_in_chunk = 0;
        let file = self.file;
        let batch = match self.unit {
            "line" => rows.into_batch("line", |e, at| e.in_file(file).at_line(at))?,
            _ => rows.into_batch("row", |e, at| e.in_file(file).at_row(at))?,
        };
        (self.each)(batch, last)
    }
}

impl<F: FnMut(Batch, bool) -> Result<(), Error>> BallSink for Chunker<'_, F> {
    fn reserve(&mut self, _more: usize) -> Result<(), Error> {
        // a chunk at a time: nothing to reserve for the whole file
        Ok(())
    }

    fn push(&mut self, table: i64, id: i64, ball: Ball, at: u64) -> Result<(), Error> {
        let new_table = match self.last {
            Some((t, b)) if table < t || (table == t && id <= b) => {
                self.out_of_order = true;
                return Err(InputError::new("out of order").into());
            }
            Some((t, _)) => table != t,
            None => true,
        };
        if new_table {
            if self.tables_in_chunk >= self.max_tables
                || (self.tables_in_chunk > 0 && self.rows.len() >= self.max_balls)
            {
                self.flush(false)?;
            }
            self.tables_in_chunk += 1;
            self.tables += 1;
        }
        self.last = Some((table, id));
        self.balls += 1;
        self.rows.push(table, id, ball, at)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "table,ball,state,x,y,vx,vy,wx,wy,wz\n";

    fn row(t: i64, b: i64) -> String {
        format!(
            "{t},{b},stationary,{},0.5,0,0,0,0,0\n",
            0.2 + 0.1 * b as f64
        )
    }

    fn chunks(text: &str, tables: usize) -> (Result<Streamed, Error>, Vec<Vec<i64>>) {
        let mut seen = Vec::new();
        let r = read_batch_chunks(
            text.as_bytes(),
            Format::Csv,
            "t.csv",
            tables,
            1 << 20,
            |b, _| {
                seen.push((0..b.num_tables()).map(|k| b.table_id(k)).collect());
                Ok(())
            },
        );
        (r, seen)
    }

    #[test]
    fn tables_in_order_come_in_chunks_and_others_are_refused() {
        let text: String = std::iter::once(HEADER.to_owned())
            .chain((1..=5).flat_map(|t| [row(t, 0), row(t, 1)]))
            .collect();
        let (r, seen) = chunks(&text, 2);
        assert_eq!(
            r.unwrap(),
            Streamed::Done {
                tables: 5,
                balls: 10
            }
        );
        assert_eq!(seen, vec![vec![1, 2], vec![3, 4], vec![5]]);
        // the same batch as the whole read
        let whole = crate::io::read_batch_csv(text.as_bytes(), "t.csv").unwrap();
        let mut glued = Vec::new();
        read_batch_chunks(text.as_bytes(), Format::Csv, "t.csv", 2, 1, |b, _| {
            for k in 0..b.num_tables() {
                glued.push((b.table_id(k), b.ball_ids(k).to_vec(), b.balls(k).to_vec()));
            }
            Ok(())
        })
        .unwrap();
        for (k, g) in glued.iter().enumerate() {
            assert_eq!(g.0, whole.table_id(k));
            assert_eq!(g.1, whole.ball_ids(k));
            assert_eq!(g.2, whole.balls(k));
        }
        for bad in [
            format!("{HEADER}{}{}{}", row(2, 0), row(2, 1), row(1, 0)),
            format!("{HEADER}{}{}{}", row(1, 1), row(1, 0), row(2, 0)),
            format!("{HEADER}{}{}{}", row(1, 0), row(1, 0), row(2, 0)),
        ] {
            assert_eq!(chunks(&bad, 2).0.unwrap(), Streamed::OutOfOrder, "{bad}");
        }
        assert_eq!(chunks(HEADER, 2).0.unwrap(), Streamed::Empty);
    }

    #[test]
    fn errors_name_the_line_as_the_whole_read_does() {
        let text = format!(
            "{HEADER}{}{}{}{}",
            row(1, 0),
            row(1, 1),
            row(2, 0),
            row(3, 0)
        );
        let streamed = chunks(&text, 1).0.unwrap_err().to_string();
        let whole = crate::io::read_batch_csv(text.as_bytes(), "t.csv")
            .unwrap_err()
            .to_string();
        assert_eq!(streamed, whole);
        assert!(
            streamed.contains("t.csv") && streamed.contains("line 4"),
            "{streamed}"
        );
    }
}
