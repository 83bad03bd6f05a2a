//! A batch of tables, and the CPU (Rayon) drivers that answer every pair of every table.
//!
//! # Layout
//! A [`Batch`] is flat arrays: balls of all tables back to back, table `k` owning balls
//! `ball_start[k]..ball_start[k + 1]`, sorted by ball id, and pairs `pair_start[k]..` in
//! the pair order below. Nothing is allocated per table or per pair when answering.
//!
//! # Pair order
//! Tables in the order they were pushed (the CSV reader pushes them by ascending table
//! id); within a table, pairs `(i, j)` of ball positions `i < j` in lexicographic order —
//! `(0,1), (0,2), …, (0,n−1), (1,2), …` — which is ascending ball-id order. The pair
//! `(i, j)` of an `n`-ball table has local index `i·n − i(i+1)/2 + j − i − 1`
//! ([`pair_index`]).
//!
//! # Next collision and its tie rule
//! A table's next collision is the pair in contact (hit or overlap) with the smallest time;
//! among pairs with the very same time, the first in pair order (smallest first ball id,
//! then smallest second ball id).
//!
//! # Determinism
//! Every pair is answered independently and every per-table reduction runs in pair order
//! on one thread, so results are bit-identical whatever the number of threads.

use std::collections::HashSet;

use rayon::prelude::*;

use crate::error::{Error, InputError};
use crate::physics::{Ball, BallPath, Params, ball_path};
use crate::solver::{Contact, Status, pair_contact};

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

/// Pairs of an `n`-ball table.
pub fn pairs_in_table(n: usize) -> usize {
    n * n.saturating_sub(1) / 2
}

/// The local index of pair `(i, j)`, `i < j < n`, in pair order.
pub fn pair_index(n: usize, i: usize, j: usize) -> usize {
    i * n - i * (i + 1) / 2 + j - i - 1
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
        }
    }

    /// Appends a table of `(ball id, ball)`; balls are stored sorted by id.
    ///
    /// Errors (nothing is appended then): a table id already in the batch, fewer than two
    /// balls, two balls with the same id, a number that is NaN or infinite. The error
    /// names the table and ball.
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
            if let Some(k) = ball.numbers().iter().position(|v| !v.is_finite()) {
                return Err(InputError::new(format!(
                    "{} is {}, numbers must be finite",
                    crate::io::BALL_NUMBER_COLUMNS[k],
                    ball.numbers()[k]
                ))
                .at_table(table)
                .at_ball(*id)
                .into());
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

    /// A batch from balls given as columns already sorted by (table id, ball id), taking
    /// the columns over without copying them: what the file readers build for large inputs.
    ///
    /// Errors, as `(row, error)` with the row the error is about: a table with fewer than two
    /// balls, a ball id twice in a table (the row is the second), a number that is NaN or
    /// infinite. Rows out of order are a bug of the caller, reported as an error too.
    pub(crate) fn from_sorted_columns(
        tables: &[i64],
        ball_ids: Vec<i64>,
        balls: Vec<Ball>,
    ) -> Result<Batch, (usize, InputError)> {
        debug_assert!(tables.len() == ball_ids.len() && tables.len() == balls.len());
        let mut batch = Batch {
            ball_ids,
            balls,
            ..Batch::new()
        };
        let mut first = 0;
        while first < tables.len() {
            let table = tables[first];
            let mut end = first + 1;
            while end < tables.len() && tables[end] == table {
                let (prev, id) = (batch.ball_ids[end - 1], batch.ball_ids[end]);
                if id <= prev {
                    let what = if id == prev {
                        "duplicate ball id"
                    } else {
                        "rows out of order (a bug in the reader)"
                    };
                    return Err((end, InputError::new(what).at_table(table).at_ball(id)));
                }
                end += 1;
            }
            if end < tables.len() && tables[end] < table {
                return Err((
                    end,
                    InputError::new("rows out of order (a bug in the reader)")
                        .at_table(tables[end]),
                ));
            }
            if end - first > crate::limits::MAX_TABLE_BALLS {
                return Err((first, too_many_balls(table, end - first)));
            }
            if end - first < 2 {
                return Err((
                    first,
                    InputError::new(format!(
                        "a table needs at least 2 balls, table {table} has 1"
                    ))
                    .at_table(table)
                    .at_ball(batch.ball_ids[first]),
                ));
            }
            for row in first..end {
                let ball = &batch.balls[row];
                if let Some(k) = ball.numbers().iter().position(|v| !v.is_finite()) {
                    return Err((
                        row,
                        InputError::new(format!(
                            "{} is {}, numbers must be finite",
                            crate::io::BALL_NUMBER_COLUMNS[k],
                            ball.numbers()[k]
                        ))
                        .at_table(table)
                        .at_ball(batch.ball_ids[row]),
                    ));
                }
            }
            batch.seen.insert(table);
            batch.table_ids.push(table);
            batch.ball_start.push(end);
            let pairs = batch.pair_start[batch.pair_start.len() - 1] + pairs_in_table(end - first);
            batch.pair_start.push(pairs);
            first = end;
        }
        Ok(batch)
    }

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

    /// The balls of table `k`, in ball-id order.
    pub fn balls(&self, k: usize) -> &[Ball] {
        &self.balls[self.ball_start[k]..self.ball_start[k + 1]]
    }

    /// The range of table `k`'s pairs in [`pair_times`]'s output.
    pub fn pair_range(&self, k: usize) -> std::ops::Range<usize> {
        self.pair_start[k]..self.pair_start[k + 1]
    }

    /// The range of the pairs of the tables `tables` in [`pair_times`]'s output.
    pub fn pairs_of_tables(&self, tables: std::ops::Range<usize>) -> std::ops::Range<usize> {
        self.pair_start[tables.start]..self.pair_start[tables.end]
    }

    /// `(table id, i, j)` for every pair of the tables `tables` (positions in the batch),
    /// `i < j` the ball ids, in pair order: the rows that go with
    /// [`pair_times_of`]`(tables)`'s answers.
    pub fn pair_ids(
        &self,
        tables: std::ops::Range<usize>,
    ) -> impl Iterator<Item = (i64, i64, i64)> + '_ {
        tables.flat_map(move |k| {
            let (table, ids) = (self.table_id(k), self.ball_ids(k));
            (0..ids.len())
                .flat_map(move |i| (i + 1..ids.len()).map(move |j| (table, ids[i], ids[j])))
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

    /// Consecutive groups of the tables `tables` of at least [`PAIRS_PER_TASK`] pairs each
    /// (the last may be smaller), as table ranges.
    fn table_groups(&self, tables: std::ops::Range<usize>) -> Vec<std::ops::Range<usize>> {
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
}

/// The pair `(i, j)`, `i < j < n`, at local index `p` in pair order: the inverse of
/// [`pair_index`]. Row `i` starts at `s(i) = i (2n − i − 1) / 2`; an f32 estimate of `i`
/// (the shader's arithmetic) is corrected exactly. WGSL twin: `pair_of_index` in
/// `shaders/kernels.wgsl`.
pub fn pair_of_index(n: usize, p: usize) -> (usize, usize) {
    let m = (2 * n - 1) as f32;
    let mut i = (0.5 * (m - (m * m - 8.0 * p as f32).max(0.0).sqrt()))
        .floor()
        .max(0.0) as usize;
    i = i.min(n - 2);
    // correct the estimate: s(i) ≤ p < s(i + 1)
    while i > 0 && i * (2 * n - i - 1) / 2 > p {
        i -= 1;
    }
    while i + 1 < n - 1 && (i + 1) * (2 * n - i - 2) / 2 <= p {
        i += 1;
    }
    let j = p - i * (2 * n - i - 1) / 2 + i + 1;
    (i, j)
}

impl NextCollision {
    /// No collision yet for `table`.
    pub(crate) fn none(table: i64) -> NextCollision {
        NextCollision {
            table,
            t: f64::INFINITY,
            pair: None,
            status: Status::None,
        }
    }

    /// Takes `c`, the answer for balls `i`, `j`, if it comes first under the tie rule;
    /// pairs must be considered in pair order.
    fn consider(&mut self, c: Contact, i: i64, j: i64) {
        if c.status.is_contact() && (self.pair.is_none() || c.t < self.t) {
            self.t = c.t;
            self.pair = Some((i, j));
            self.status = c.status;
        }
    }
}

/// Fills `paths` with the paths of `balls` (WGSL twin: `cache_paths`).
pub(crate) fn table_paths(balls: &[Ball], params: &Params, paths: &mut Vec<BallPath>) {
    paths.clear();
    paths.extend(balls.iter().map(|b| ball_path(b, params)));
}

/// The answer for every pair of every table, in pair order (see the module docs).
///
/// Runs on the Rayon thread pool; the result does not depend on the number of threads.
pub fn pair_times(batch: &Batch, params: &Params) -> Result<Vec<Contact>, Error> {
    pair_times_of(batch, params, 0..batch.num_tables())
}

/// The answer for every pair of the tables `tables` (positions in the batch), in pair
/// order: the slice `batch.pairs_of_tables(tables)` of [`pair_times`]'s output.
pub fn pair_times_of(
    batch: &Batch,
    params: &Params,
    tables: std::ops::Range<usize>,
) -> Result<Vec<Contact>, Error> {
    params.validate()?;
    let n_pairs = batch.pairs_of_tables(tables.clone()).len();
    crate::limits::check_memory(
        &format!("answering {n_pairs} pairs at once"),
        (n_pairs as u64).saturating_mul(crate::limits::BYTES_PER_PAIR),
    )?;
    let mut out = vec![Contact::none(f64::INFINITY); n_pairs];
    // hand each group of tables its own slice of the output
    let mut tasks = Vec::new();
    let mut rest: &mut [Contact] = &mut out;
    for group in batch.table_groups(tables) {
        let len = batch.pair_start[group.end] - batch.pair_start[group.start];
        let (head, tail) = rest.split_at_mut(len);
        tasks.push((group, head));
        rest = tail;
    }
    tasks.into_par_iter().for_each(|(group, slice)| {
        let mut paths = Vec::new();
        let mut at = 0;
        for k in group {
            table_paths(batch.balls(k), params, &mut paths);
            let n = paths.len();
            for i in 0..n {
                for j in i + 1..n {
                    slice[at] = pair_contact(&paths[i], &paths[j], params.radius);
                    at += 1;
                }
            }
        }
    });
    Ok(out)
}

/// The next collision of table `k` from its ball paths (the tie rule in the module docs).
fn table_next(batch: &Batch, k: usize, paths: &[BallPath], radius: f64) -> NextCollision {
    let ids = batch.ball_ids(k);
    let mut best = NextCollision::none(batch.table_id(k));
    let n = paths.len();
    for i in 0..n {
        for j in i + 1..n {
            best.consider(pair_contact(&paths[i], &paths[j], radius), ids[i], ids[j]);
        }
    }
    best
}

/// The next collision of every table, in table order.
///
/// Runs on the Rayon thread pool; the result does not depend on the number of threads.
pub fn next_collisions(batch: &Batch, params: &Params) -> Result<Vec<NextCollision>, Error> {
    next_collisions_of(batch, params, 0..batch.num_tables())
}

/// The next collision of the tables `tables` only (positions in the batch), in table order:
/// the slice `tables` of [`next_collisions`]'s output.
pub fn next_collisions_of(
    batch: &Batch,
    params: &Params,
    tables: std::ops::Range<usize>,
) -> Result<Vec<NextCollision>, Error> {
    params.validate()?;
    let groups = batch.table_groups(tables);
    let per_group: Vec<Vec<NextCollision>> = groups
        .into_par_iter()
        .map(|group| {
            let mut paths = Vec::new();
            group
                .map(|k| {
                    table_paths(batch.balls(k), params, &mut paths);
                    table_next(batch, k, &paths, params.radius)
                })
                .collect()
        })
        .collect();
    Ok(per_group.into_iter().flatten().collect())
}

/// Reduces per-pair answers (as [`pair_times`] returns them) to each table's next
/// collision with the same tie rule as [`next_collisions`].
pub fn next_from_pairs(batch: &Batch, pairs: &[Contact]) -> Vec<NextCollision> {
    (0..batch.num_tables())
        .map(|k| {
            let ids = batch.ball_ids(k);
            let n = ids.len();
            let local = &pairs[batch.pair_range(k)];
            let mut best = NextCollision::none(batch.table_id(k));
            for i in 0..n {
                for j in i + 1..n {
                    best.consider(local[pair_index(n, i, j)], ids[i], ids[j]);
                }
            }
            best
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::MotionState;

    #[test]
    fn pair_index_enumerates_in_order() {
        for n in 2..10 {
            let mut k = 0;
            for i in 0..n {
                for j in i + 1..n {
                    assert_eq!(pair_index(n, i, j), k);
                    k += 1;
                }
            }
            assert_eq!(k, pairs_in_table(n));
        }
    }

    #[test]
    fn pair_of_index_inverts_pair_index() {
        for n in [2, 3, 4, 5, 16, 64, 65, 300, 2000] {
            for i in 0..n {
                for j in i + 1..n {
                    assert_eq!(pair_of_index(n, pair_index(n, i, j)), (i, j), "n={n}");
                }
            }
        }
    }

    #[test]
    fn streamed_chunks_reassemble_the_whole_answer() {
        use crate::workload::{Scenario, generate};
        let p = Params::default();
        let batch = generate(Scenario::Spread, 300, 12, 5, &p);
        let whole = pair_times(&batch, &p).unwrap();
        for pairs in [1, 66, 1000, 5000, usize::MAX] {
            let chunks = batch.table_chunks(pairs);
            assert_eq!(chunks.first().unwrap().start, 0);
            assert_eq!(chunks.last().unwrap().end, batch.num_tables());
            let mut joined = Vec::new();
            for c in &chunks {
                assert!(c.len() == 1 || batch.pairs_of_tables(c.clone()).len() <= pairs);
                joined.extend(pair_times_of(&batch, &p, c.clone()).unwrap());
            }
            assert_eq!(joined, whole, "chunks of {pairs} pairs");
            let mut next = Vec::new();
            for c in &chunks {
                next.extend(next_collisions_of(&batch, &p, c.clone()).unwrap());
            }
            assert_eq!(
                next,
                next_collisions(&batch, &p).unwrap(),
                "chunks of {pairs}"
            );
        }
    }

    #[test]
    fn sorted_columns_make_the_same_batch_as_push_table() {
        use crate::workload::{Scenario, generate};
        let batch = generate(Scenario::Rack, 20, 16, 1, &Params::default());
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
}
