//! The columns of the files, and the balls as read, before they become a batch.

use crate::batch::Batch;
use crate::error::{Error, InputError};
use crate::model::Ball;

/// The input columns, in order.
pub const BALL_COLUMNS: [&str; 10] = [
    "table", "ball", "state", "x", "y", "vx", "vy", "wx", "wy", "wz",
];
/// The numeric ball columns, in the order of [`Ball::numbers`].
pub const BALL_NUMBER_COLUMNS: [&str; 7] = Ball::NUMBER_NAMES;
/// The per-pair output columns.
pub const PAIR_COLUMNS: &str = "table,i,j,t,status,horizon";
/// The per-table output columns of `kisstime next`.
pub const NEXT_COLUMNS: &str = "table,t,i,j,status";

/// Balls as read, in file order, before they are sorted into a [`Batch`]: one column per
/// field, so that a file of millions of balls is held once, compactly, and handed to the
/// batch without copying when it is already in (table, ball) order.
#[derive(Default)]
pub(crate) struct BallRows {
    tables: Vec<i64>,
    ids: Vec<i64>,
    balls: Vec<Ball>,
    /// Where each ball is in the file: its line (CSV) or row (NPY).
    at: Vec<u64>,
}

/// Where a reader hands the balls it reads, in file order: [`BallRows`] (a whole batch) or
/// [`crate::io::stream`]'s chunks.
pub(crate) trait BallSink {
    /// Room for `more` balls (the count a `.npy` header gives).
    fn reserve(&mut self, more: usize) -> Result<(), Error>;
    /// One ball read at `at` (a line or a row).
    fn push(&mut self, table: i64, id: i64, ball: Ball, at: u64) -> Result<(), Error>;
}

impl BallSink for BallRows {
    fn reserve(&mut self, more: usize) -> Result<(), Error> {
        BallRows::reserve(self, more)
    }
    fn push(&mut self, table: i64, id: i64, ball: Ball, at: u64) -> Result<(), Error> {
        BallRows::push(self, table, id, ball, at)
    }
}

impl BallRows {
    /// The number of balls held.
    pub(crate) fn len(&self) -> usize {
        self.balls.len()
    }

    /// Makes room for `more` balls, refusing ([`Error::TooLarge`]) when that needs more
    /// memory than is available.
    pub(crate) fn reserve(&mut self, more: usize) -> Result<(), Error> {
        let len = self.balls.len() as u64;
        let want = len.saturating_add(more as u64);
        crate::limits::check_memory(
            &format!("a batch of {want} balls"),
            want.saturating_mul(crate::limits::BYTES_PER_BALL),
        )?;
        self.tables.reserve_exact(more);
        self.ids.reserve_exact(more);
        self.balls.reserve_exact(more);
        self.at.reserve_exact(more);
        Ok(())
    }

    /// Appends one ball read at `at` (a line or a row). The columns grow by doubling, each
    /// growth checked against the available memory first.
    pub(crate) fn push(&mut self, table: i64, id: i64, ball: Ball, at: u64) -> Result<(), Error> {
        if self.balls.len() == self.balls.capacity() {
            self.reserve(self.balls.len().max(4096))?;
        }
        self.tables.push(table);
        self.ids.push(id);
        self.balls.push(ball);
        self.at.push(at);
        Ok(())
    }

    /// Sorts the balls by (table, ball) — stably, so of two balls with the same ids the
    /// later in the file is reported — and builds the batch ([`Batch::from_columns`]).
    /// `locate` adds a ball's place (`at`) and the file name to an error; `unit` names
    /// what `at` counts (`line`, `row`).
    pub(crate) fn into_batch(
        self,
        unit: &'static str,
        locate: impl Fn(InputError, u64) -> InputError,
    ) -> Result<Batch, Error> {
        let BallRows {
            tables,
            ids,
            balls,
            at,
        } = self;
        Batch::from_columns_located(tables, ids, balls, unit, |row| at[row], locate)
    }
}
