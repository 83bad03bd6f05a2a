//! A table's next collision, and the tie rule that picks it.
//!
//! A table's next collision is the pair in contact (hit or overlap) with the smallest
//! time; among pairs with the very same time, the first in pair order (smallest first
//! ball id, then smallest second ball id). Every backend applies this one rule: the CPU
//! drivers through [`NextCollision::consider`], the GPU kernel through its twin
//! `comes_first`, and [`next_from_pairs`] on per-pair output.

use super::{Batch, pair_index, pairs};
use crate::query::ball_ball::{Contact, Status};

/// The next collision of one table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NextCollision {
    /// The table's id.
    pub table: i64,
    /// Time of the next collision in seconds; `∞` when none of the table's pairs collides.
    pub t: f64,
    /// The colliding pair's ball ids `(i, j)`, `i < j`; `None` when there is no collision.
    pub pair: Option<(i64, i64)>,
    /// [`Status::Hit`], [`Status::Overlap`], or [`Status::None`].
    pub status: Status,
    /// The table's horizon: the time until the first of its balls changes motion state
    /// (the smallest pair horizon; `∞` when no ball moves). An event loop needs it beside
    /// the next collision: whichever comes first is the table's next event.
    pub horizon: f64,
}

impl NextCollision {
    /// No collision (yet) for `table`.
    pub fn none(table: i64) -> NextCollision {
        NextCollision {
            table,
            t: f64::INFINITY,
            pair: None,
            status: Status::None,
            horizon: f64::INFINITY,
        }
    }

    /// Takes `c`, the answer for balls `i`, `j`, if it comes first under the tie rule, and
    /// its horizon into the table's; pairs must be considered in pair order.
    pub fn consider(&mut self, c: Contact, i: i64, j: i64) {
        self.horizon = self.horizon.min(c.horizon);
        if c.status.is_contact() && (self.pair.is_none() || c.t < self.t) {
            self.t = c.t;
            self.pair = Some((i, j));
            self.status = c.status;
        }
    }
}

/// Reduces per-pair answers (as [`crate::pair_times`] returns them) to each table's next
/// collision with the same tie rule as [`crate::next_collisions`].
pub fn next_from_pairs(batch: &Batch, pairs_answers: &[Contact]) -> Vec<NextCollision> {
    (0..batch.num_tables())
        .map(|k| {
            let ids = batch.ball_ids(k);
            let n = ids.len();
            let local = &pairs_answers[batch.pair_range(k)];
            let mut best = NextCollision::none(batch.table_id(k));
            for (i, j) in pairs(n) {
                best.consider(local[pair_index(n, i, j)], ids[i], ids[j]);
            }
            best
        })
        .collect()
}
