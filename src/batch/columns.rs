//! Building a batch from columns: balls given as parallel arrays of table ids, ball ids
//! and states, in any order.

use super::{Batch, pairs_in_table, too_many_balls};
use crate::error::{Error, InputError};
use crate::model::Ball;

impl Batch {
    /// A batch from balls given as columns — `tables[r]`, `ball_ids[r]`, `balls[r]` for
    /// row `r` — in any row order: what a file reader or a NumPy caller holds. Rows are
    /// sorted by (table id, ball id), stably; when they already are, the columns are taken
    /// over without copying.
    ///
    /// Errors name the row (`InputError::row`, 0-based, in the order given), the table and
    /// the ball: columns of different lengths, a table with fewer than two balls or more
    /// than [`crate::limits::MAX_TABLE_BALLS`], a ball id twice in a table (the later row
    /// is reported), a number that is NaN or infinite or beyond the physical range
    /// ([`Ball::check_numbers`]); [`Error::TooLarge`] when sorting
    /// needs more memory than is available.
    pub fn from_columns(
        tables: Vec<i64>,
        ball_ids: Vec<i64>,
        balls: Vec<Ball>,
    ) -> Result<Batch, Error> {
        Batch::from_columns_located(
            tables,
            ball_ids,
            balls,
            "row",
            |row| row as u64,
            |e, row| e.at_row(row),
        )
    }

    /// [`Batch::from_columns`] for a reader: `place(row)` is where row `row` was read (a
    /// line or a row of the file, counted in `unit`s), and `locate` adds a place to an
    /// error.
    pub(crate) fn from_columns_located(
        mut tables: Vec<i64>,
        mut ball_ids: Vec<i64>,
        mut balls: Vec<Ball>,
        unit: &'static str,
        place: impl Fn(usize) -> u64,
        locate: impl Fn(InputError, u64) -> InputError,
    ) -> Result<Batch, Error> {
        if ball_ids.len() != tables.len() || balls.len() != tables.len() {
            return Err(InputError::new(format!(
                "columns of different lengths: {} table ids, {} ball ids, {} balls",
                tables.len(),
                ball_ids.len(),
                balls.len()
            ))
            .into());
        }
        let key = |t: &[i64], b: &[i64], r: usize| (t[r], b[r]);
        let sorted =
            (1..tables.len()).all(|r| key(&tables, &ball_ids, r - 1) <= key(&tables, &ball_ids, r));
        // the original row of each sorted row
        let mut order: Vec<usize> = Vec::new();
        if !sorted {
            // the sort order, then each column copied once more
            let n = tables.len() as u64;
            crate::limits::check_memory(
                &format!("sorting a batch of {n} balls"),
                n.saturating_mul(2 * crate::limits::BYTES_PER_BALL),
            )?;
            order = (0..tables.len()).collect();
            order.sort_by_key(|&r| key(&tables, &ball_ids, r));
            tables = order.iter().map(|&r| tables[r]).collect();
            ball_ids = order.iter().map(|&r| ball_ids[r]).collect();
            balls = order.iter().map(|&r| balls[r]).collect();
        }
        let original = |r: usize| if sorted { r } else { order[r] };
        let mut batch =
            Batch::from_sorted_columns(&tables, ball_ids, balls).map_err(|(row, mut e)| {
                if row > 0 && tables[row - 1] == tables[row] && e.message == "duplicate ball id" {
                    let first = place(original(row - 1));
                    e.message = format!("duplicate ball id (first on {unit} {first})");
                }
                Error::from(locate(e, place(original(row))))
            })?;
        batch.places = (0..tables.len()).map(|r| place(original(r))).collect();
        batch.place_unit = unit;
        Ok(batch)
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
                if let Err((_, why)) = ball.check_numbers() {
                    return Err((
                        row,
                        InputError::new(why)
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
}
