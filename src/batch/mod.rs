//! A batch of tables: the flat layout every backend reads, and the pair order.
//!
//! # Layout
//! A [`Batch`] is flat arrays: balls of all tables back to back, table `k` owning balls
//! `ball_start[k]..ball_start[k + 1]`, sorted by ball id, and pairs `pair_start[k]..` in
//! the pair order below. Nothing is allocated per table or per pair when answering.
//! Batches are built table by table ([`Batch::push_table`]) or from columns
//! ([`Batch::from_columns`], what file readers and the Python package hold).
//!
//! # Pair order
//! Tables in the order they were pushed (the readers push them by ascending table id);
//! within a table, pairs `(i, j)` of ball positions `i < j` in lexicographic order —
//! `(0,1), (0,2), …, (0,n−1), (1,2), …` — which is ascending ball-id order; [`pairs()`]
//! walks them and [`pair_index`] numbers them.
//!
//! # Next collision and its tie rule
//! See [`next`]: the pair in contact with the smallest time, the first in pair order among
//! equal times.

use std::collections::HashSet;

use crate::error::{Error, InputError};
use crate::model::Ball;

mod columns;
pub mod next;
pub mod pairs;
mod sim_input;

pub use next::{NextCollision, next_from_pairs};
pub use pairs::{Pairs, pair_index, pair_of_index, pairs, pairs_in_table};

/// Tables are handed to threads in groups of at least this many pairs.
const PAIRS_PER_TASK: usize = 4096;

/// Many tables of balls, laid out as flat arrays (see the module docs).
#[derive(Clone, Debug)]
pub struct Batch {
    table_ids: Vec<i64>,
    ball_start: Vec<usize>,
    pair_start: Vec<usize>,
    ball_ids: Vec<i64>,
    balls: Vec<Ball>,
    seen: HashSet<i64>,
    /// Where each ball was read (its line or row in the file, in ball order), and what
    /// that counts; empty for a batch built table by table.
    places: Vec<u64>,
    place_unit: &'static str,
}

/// The error for a table of more than [`crate::limits::MAX_TABLE_BALLS`] balls.
fn too_many_balls(table: i64, n: usize) -> InputError {
    InputError::new(format!(
        "a table has {n} balls ({} pairs); at most {} balls a table are supported",
        pairs_in_table(n),
        crate::limits::MAX_TABLE_BALLS
    ))
    .at_table(table)
}

impl Default for Batch {
    fn default() -> Batch {
        Batch::new()
    }
}

impl Batch {
    /// An empty batch.
    pub fn new() -> Batch {
        Batch {
            table_ids: Vec::new(),
            ball_start: vec![0],
            pair_start: vec![0],
            ball_ids: Vec::new(),
            balls: Vec::new(),
            seen: HashSet::new(),
            places: Vec::new(),
            place_unit: "row",
        }
    }

    /// Appends a table of `(ball id, ball)`; balls are stored sorted by id.
    ///
    /// Errors (nothing is appended then): a table id already in the batch, fewer than two
    /// balls, two balls with the same id, a number that is NaN or infinite or beyond the
    /// physical range ([`Ball::check_numbers`]). The error names the table and ball.
    pub fn push_table(
        &mut self,
        table: i64,
        balls: impl IntoIterator<Item = (i64, Ball)>,
    ) -> Result<(), Error> {
        if self.seen.contains(&table) {
            return Err(InputError::new("table id appears twice in the batch")
                .at_table(table)
                .into());
        }
        let mut table_balls: Vec<(i64, Ball)> = balls.into_iter().collect();
        table_balls.sort_by_key(|(id, _)| *id);
        if table_balls.len() < 2 {
            return Err(InputError::new(format!(
                "a table needs at least 2 balls, this one has {}",
                table_balls.len()
            ))
            .at_table(table)
            .into());
        }
        if table_balls.len() > crate::limits::MAX_TABLE_BALLS {
            return Err(too_many_balls(table, table_balls.len()).into());
        }
        for w in table_balls.windows(2) {
            if w[0].0 == w[1].0 {
                return Err(InputError::new("duplicate ball id")
                    .at_table(table)
                    .at_ball(w[0].0)
                    .into());
            }
        }
        for (id, ball) in &table_balls {
            if let Err((_, why)) = ball.check_numbers() {
                return Err(InputError::new(why).at_table(table).at_ball(*id).into());
            }
        }
        let n = table_balls.len();
        self.seen.insert(table);
        self.table_ids.push(table);
        for (id, ball) in table_balls {
            self.ball_ids.push(id);
            self.balls.push(ball);
        }
        self.ball_start.push(self.balls.len());
        let pairs = self.pair_start[self.pair_start.len() - 1] + pairs_in_table(n);
        self.pair_start.push(pairs);
        Ok(())
    }
}

impl Batch {
    /// Number of tables.
    pub fn num_tables(&self) -> usize {
        self.table_ids.len()
    }

    /// Number of balls over all tables.
    pub fn num_balls(&self) -> usize {
        self.balls.len()
    }

    /// Number of pairs over all tables.
    pub fn num_pairs(&self) -> usize {
        self.pair_start[self.pair_start.len() - 1]
    }

    /// The id of table `k` (by position in the batch).
    pub fn table_id(&self, k: usize) -> i64 {
        self.table_ids[k]
    }

    /// The ball ids of table `k`, ascending.
    pub fn ball_ids(&self, k: usize) -> &[i64] {
        &self.ball_ids[self.ball_start[k]..self.ball_start[k + 1]]
    }

    /// Where ball `i` of table `k` was read — its line (CSV) or row (`.npy`) in the input
    /// file, with the unit (`"line"` or `"row"`) — for a batch that came from a file or
    /// from [`Batch::from_columns`] (the row given); `None` for one built table by table.
    pub fn ball_place(&self, k: usize, i: usize) -> Option<(&'static str, u64)> {
        let at = self.ball_start[k] + i;
        self.places.get(at).map(|&p| (self.place_unit, p))
    }

    /// The balls of table `k`, in ball-id order.
    pub fn balls(&self, k: usize) -> &[Ball] {
        &self.balls[self.ball_start[k]..self.ball_start[k + 1]]
    }

    /// The range of table `k`'s pairs in [`crate::pair_times`]'s output.
    pub fn pair_range(&self, k: usize) -> std::ops::Range<usize> {
        self.pair_start[k]..self.pair_start[k + 1]
    }

    /// The range of the pairs of the tables `tables` in [`crate::pair_times`]'s output.
    pub fn pairs_of_tables(&self, tables: std::ops::Range<usize>) -> std::ops::Range<usize> {
        self.pair_start[tables.start]..self.pair_start[tables.end]
    }

    /// `(table id, i, j)` for every pair of the tables `tables` (positions in the batch),
    /// `i < j` the ball ids, in pair order: the rows that go with
    /// [`crate::pair_times_of`]`(tables)`'s answers.
    pub fn pair_ids(
        &self,
        tables: std::ops::Range<usize>,
    ) -> impl Iterator<Item = (i64, i64, i64)> + '_ {
        tables.flat_map(move |k| {
            let (table, ids) = (self.table_id(k), self.ball_ids(k));
            pairs(ids.len()).map(move |(i, j)| (table, ids[i], ids[j]))
        })
    }

    /// Consecutive ranges of whole tables of about `pairs` pairs each (at least one table
    /// each), covering the batch: the unit in which per-pair output is streamed.
    pub fn table_chunks(&self, pairs: usize) -> Vec<std::ops::Range<usize>> {
        let mut chunks = Vec::new();
        let mut first = 0;
        while first < self.num_tables() {
            let mut end = first + 1;
            while end < self.num_tables()
                && self.pair_start[end + 1] - self.pair_start[first] <= pairs
            {
                end += 1;
            }
            chunks.push(first..end);
            first = end;
        }
        chunks
    }

    /// Consecutive groups of the tables `tables` of at least `PAIRS_PER_TASK` (4096) pairs each
    /// (the last may be smaller), as table ranges.
    pub(crate) fn table_groups(
        &self,
        tables: std::ops::Range<usize>,
    ) -> Vec<std::ops::Range<usize>> {
        let mut groups = Vec::new();
        let mut first = tables.start;
        while first < tables.end {
            let mut end = first;
            while end < tables.end && self.pair_start[end] - self.pair_start[first] < PAIRS_PER_TASK
            {
                end += 1;
            }
            groups.push(first..end);
            first = end;
        }
        groups
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{MotionState, Params};

    #[test]
    fn sorted_columns_make_the_same_batch_as_push_table() {
        use crate::workload::{Workload, generate};
        let batch = generate(Workload::Rack, 20, 16, 1, &Params::default());
        let mut tables = Vec::new();
        for k in 0..batch.num_tables() {
            tables.extend(std::iter::repeat_n(
                batch.table_id(k),
                batch.ball_ids(k).len(),
            ));
        }
        let same = Batch::from_sorted_columns(&tables, batch.ball_ids.clone(), batch.balls.clone())
            .unwrap();
        assert_eq!(same.table_ids, batch.table_ids);
        assert_eq!(same.ball_start, batch.ball_start);
        assert_eq!(same.pair_start, batch.pair_start);
        assert_eq!(same.balls, batch.balls);
        // a lone ball, a duplicate, rows out of order: errors at the row
        let (row, e) =
            Batch::from_sorted_columns(&[1, 2, 2], vec![0, 0, 1], vec![Ball::at_rest(0.0, 0.0); 3])
                .unwrap_err();
        assert_eq!((row, e.table, e.ball), (0, Some(1), Some(0)));
        let (row, e) =
            Batch::from_sorted_columns(&[1, 1], vec![4, 4], vec![Ball::at_rest(0.0, 0.0); 2])
                .unwrap_err();
        assert_eq!((row, e.message.as_str()), (1, "duplicate ball id"));
        let (row, _) = Batch::from_sorted_columns(
            &[2, 2, 1, 1],
            vec![0, 1, 0, 1],
            vec![Ball::at_rest(0.0, 0.0); 4],
        )
        .unwrap_err();
        assert_eq!(row, 2);
    }

    #[test]
    fn push_table_rejects_bad_tables_and_appends_nothing() {
        let mut b = Batch::new();
        let ball = Ball::at_rest(0.0, 0.0);
        let err = b.push_table(7, [(1, ball)]).unwrap_err().to_string();
        assert!(
            err.contains("table 7") && err.contains("at least 2"),
            "{err}"
        );
        let err = b
            .push_table(7, [(3, ball), (3, Ball::at_rest(1.0, 0.0))])
            .unwrap_err()
            .to_string();
        assert!(err.contains("ball 3") && err.contains("duplicate"), "{err}");
        let nan = Ball {
            vy: f64::NAN,
            state: MotionState::Rolling,
            ..ball
        };
        let err = b
            .push_table(7, [(1, ball), (2, nan)])
            .unwrap_err()
            .to_string();
        assert!(err.contains("ball 2") && err.contains("vy"), "{err}");
        assert_eq!(b.num_tables(), 0);
        assert_eq!(b.num_pairs(), 0);
        b.push_table(7, [(2, ball), (1, Ball::at_rest(1.0, 0.0))])
            .unwrap();
        assert_eq!(b.ball_ids(0), &[1, 2]);
        let err = b
            .push_table(7, [(1, ball), (2, ball)])
            .unwrap_err()
            .to_string();
        assert!(err.contains("twice"), "{err}");
    }

    #[test]
    fn from_columns_sorts_any_row_order_and_names_the_given_row() {
        use crate::workload::{Workload, generate};
        let batch = generate(Workload::Spread, 30, 5, 3, &Params::default());
        // the rows of every table, in reverse order
        let mut rows = Vec::new();
        for k in 0..batch.num_tables() {
            for (id, ball) in batch.ball_ids(k).iter().zip(batch.balls(k)) {
                rows.push((batch.table_id(k), *id, *ball));
            }
        }
        rows.reverse();
        let same = Batch::from_columns(
            rows.iter().map(|r| r.0).collect(),
            rows.iter().map(|r| r.1).collect(),
            rows.iter().map(|r| r.2).collect(),
        )
        .unwrap();
        assert_eq!(same.table_ids, batch.table_ids);
        assert_eq!(same.ball_ids, batch.ball_ids);
        assert_eq!(same.balls, batch.balls);
        assert_eq!(same.pair_start, batch.pair_start);
        // a duplicate id: the later of the two rows given, and where the first one is
        let ball = Ball::at_rest(0.0, 0.0);
        let err = Batch::from_columns(vec![5, 4, 5, 5, 4], vec![2, 0, 1, 2, 1], vec![ball; 5])
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("row 3") && err.contains("first on row 0") && err.contains("ball 2"),
            "{err}"
        );
        let err = Batch::from_columns(vec![1, 1], vec![0], vec![ball; 2])
            .unwrap_err()
            .to_string();
        assert!(err.contains("different lengths"), "{err}");
    }
}
