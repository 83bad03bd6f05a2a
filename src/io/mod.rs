//! Reading and writing batches and answers, in CSV ([`mod@csv`]) or NumPy `.npy`
//! ([`npy`]), chosen by the file name ([`Format`]); outputs are written atomically
//! ([`atomic`]). Tables from JSON ([`table_json`]); the simulator's physical parameters in
//! pooltool's names, from TOML or JSON ([`physics`]); the full-shot reference set's files
//! ([`shot_set`]); `kisstime simulate`'s strikes ([`strikes`]) and outputs
//! ([`sim_output`]).
//!
//! # Input
//! Header `table,ball,state,x,y,vx,vy,wx,wy,wz` ([`BALL_COLUMNS`]), one row a ball:
//! `table` and `ball` are integer ids, `state` one of `stationary`, `spinning`, `sliding`,
//! `rolling`, `pocketed`, then position (m), velocity (m/s) and angular velocity (rad/s).
//! Rows of one table need not be adjacent; fields may be padded with spaces. Tables are
//! answered in ascending id order, balls in ascending id order.
//!
//! # Output
//! Per pair: header `table,i,j,t,status,horizon`, one row a pair with `i < j` the ball
//! ids, `t` and `horizon` in seconds printed as the shortest decimal that reads back as the
//! same f64 (`inf` when there is no collision or no horizon), `status` one of `hit`,
//! `none`, `overlap`. Per table (next collision): header `table,t,i,j,status`, one row a
//! table, `inf` and empty ids when the table has no collision.

use std::io::{Read, Write};
use std::path::Path;

use crate::batch::{Batch, NextCollision};
use crate::error::Error;
use crate::query::ball_ball::Contact;

pub mod atomic;
mod columns;
pub mod context;
pub mod csv;
pub mod npy;
pub mod physics;
pub mod shot_set;
pub mod sim_output;
pub mod stream;
pub mod strikes;
pub mod table_json;

pub use self::atomic::{
    Output, output_error, remove_unfinished_outputs, write_output, write_outputs,
};
pub use self::columns::{BALL_COLUMNS, BALL_NUMBER_COLUMNS, NEXT_COLUMNS, PAIR_COLUMNS};
pub use self::csv::{
    format_time, read_batch_csv, read_batch_csv_path, write_batch_csv, write_next_csv,
    write_pairs_csv, write_pairs_rows,
};
pub use self::npy::{read_batch_npy, read_batch_npy_path, write_batch_npy, write_next_npy};

/// A file format, chosen by the file name: `.npy` (any case) is [`npy`]'s NumPy
/// layout, anything else CSV.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Comma-separated text with a header line.
    Csv,
    /// NumPy's binary `.npy` (see [`npy`]).
    Npy,
}

impl Format {
    /// The format of the file at `path` (CSV for standard output, `None`).
    pub fn of(path: Option<&Path>) -> Format {
        match path.and_then(|p| p.extension()) {
            Some(ext) if ext.eq_ignore_ascii_case("npy") => Format::Npy,
            _ => Format::Csv,
        }
    }
}

/// Reads a batch in `format` from `reader`; `file` is the name used in error messages.
pub fn read_batch<R: Read>(reader: R, format: Format, file: &str) -> Result<Batch, Error> {
    match format {
        Format::Csv => read_batch_csv(reader, file),
        Format::Npy => npy::read_batch_npy(reader, file),
    }
}

/// Writes a batch as an input file in `format`.
pub fn write_batch(out: &mut dyn Write, format: Format, batch: &Batch) -> std::io::Result<()> {
    match format {
        Format::Csv => write_batch_csv(out, batch),
        Format::Npy => npy::write_batch_npy(out, batch),
    }
}

/// Writes each table's next collision in `format`.
pub fn write_next(
    out: &mut dyn Write,
    format: Format,
    next: &[NextCollision],
) -> std::io::Result<()> {
    match format {
        Format::Csv => write_next_csv(out, next),
        Format::Npy => npy::write_next_npy(out, next),
    }
}

/// Per-pair output in either format, written chunk by chunk as the answers come.
pub struct PairsWriter<'w> {
    sink: PairsSink<'w>,
}

enum PairsSink<'w> {
    Csv(&'w mut dyn Write),
    Npy(npy::PairsNpy<&'w mut dyn Write>),
}

impl<'w> PairsWriter<'w> {
    /// Starts the output of all pairs of `batch` (the CSV header, or the `.npy` header
    /// promising every pair).
    pub fn new(
        out: &'w mut dyn Write,
        format: Format,
        batch: &Batch,
    ) -> std::io::Result<PairsWriter<'w>> {
        let sink = match format {
            Format::Csv => {
                writeln!(out, "{PAIR_COLUMNS}")?;
                PairsSink::Csv(out)
            }
            Format::Npy => PairsSink::Npy(npy::PairsNpy::new(out, batch)?),
        };
        Ok(PairsWriter { sink })
    }

    /// Appends the answers `contacts` of the tables `tables` (positions in the batch), as
    /// [`crate::pair_times_of`] returns them.
    pub fn write_rows(
        &mut self,
        batch: &Batch,
        tables: std::ops::Range<usize>,
        contacts: &[Contact],
    ) -> std::io::Result<()> {
        match &mut self.sink {
            PairsSink::Csv(out) => self::csv::write_pairs_rows(*out, batch, tables, contacts),
            PairsSink::Npy(npy) => npy.write_rows(batch, tables, contacts),
        }
    }

    /// Ends the output (for `.npy`, an error if pairs are missing).
    pub fn finish(self) -> std::io::Result<()> {
        match self.sink {
            PairsSink::Csv(_) => Ok(()),
            PairsSink::Npy(npy) => npy.finish(),
        }
    }
}
