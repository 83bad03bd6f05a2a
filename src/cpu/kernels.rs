//! The CPU drivers: every pair, or each table's next collision, for a batch, on the Rayon
//! thread pool in f64 — the reference every other backend is checked against.
//!
//! The per-table loops are the CPU twins of the GPU entry points in
//! `shaders/kernels.wgsl` (`pair_times`, `next_collisions`, with `cache_paths` for
//! `table_paths`).
//!
//! # Determinism
//! Every pair is answered independently and every per-table reduction runs in pair order
//! on one thread, so results are bit-identical whatever the number of threads.

use std::ops::Range;

use rayon::prelude::*;

use crate::batch::{Batch, NextCollision, pairs};
use crate::error::Error;
use crate::model::{Ball, Params};
use crate::motion::path::{BallPath, PATH_MOVES, PATH_POCKETED, ball_path};
use crate::query::ball_ball::{Contact, pair_contact};

/// Fills `paths` with the paths of `balls` (WGSL twin: `cache_paths`).
pub(crate) fn table_paths(balls: &[Ball], params: &Params, paths: &mut Vec<BallPath>) {
    paths.clear();
    paths.extend(balls.iter().map(|b| ball_path(b, params)));
}

/// The answer for every pair of every table, in pair order (see [`crate::batch`]).
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
    tables: Range<usize>,
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
        let len = batch.pairs_of_tables(group.clone()).len();
        let (head, tail) = rest.split_at_mut(len);
        tasks.push((group, head));
        rest = tail;
    }
    tasks.into_par_iter().for_each(|(group, slice)| {
        let mut paths = Vec::new();
        let mut at = 0;
        for k in group {
            table_paths(batch.balls(k), params, &mut paths);
            for (i, j) in pairs(paths.len()) {
                slice[at] = pair_contact(&paths[i], &paths[j], params.radius);
                at += 1;
            }
        }
    });
    Ok(out)
}

/// The next collision of table `k` from its ball paths (the tie rule of
/// [`crate::batch::next`]). `moving` is scratch space.
///
/// Only the pairs that can answer are solved: neither ball pocketed and at least one
/// moving (rule 1 of [`pair_contact`] answers every other pair "none" with the pair's
/// horizon). They are visited in pair order — for each `i`, every later ball if `i`
/// moves, else only the later moving balls — so the earliest-time, first-in-order tie
/// rule picks what the loop over every pair picks. The table's horizon, the minimum of
/// the pairs' `min(tmax_i, tmax_j)` over every pair, is the minimum over the balls (a
/// table has at least two). In `midshot` (3 moving balls of 16) that is 42 pairs of 120.
/// The GPU twin (`shaders/kernels.wgsl`) spreads every pair over its workgroup instead;
/// the answers are the same.
fn table_next(
    batch: &Batch,
    k: usize,
    paths: &[BallPath],
    radius: f64,
    moving: &mut Vec<usize>,
) -> NextCollision {
    let ids = batch.ball_ids(k);
    let mut best = NextCollision::none(batch.table_id(k));
    best.horizon = paths.iter().fold(f64::INFINITY, |h, p| h.min(p.tmax));
    let pocketed = |p: &BallPath| p.flags & PATH_POCKETED != 0;
    let moves = |p: &BallPath| p.flags & PATH_MOVES != 0 && !pocketed(p);
    moving.clear();
    moving.extend((0..paths.len()).filter(|&i| moves(&paths[i])));
    for (i, pi) in paths.iter().enumerate() {
        if pocketed(pi) {
            continue;
        }
        if moves(pi) {
            for (j, pj) in paths.iter().enumerate().skip(i + 1) {
                if !pocketed(pj) {
                    best.consider(pair_contact(pi, pj, radius), ids[i], ids[j]);
                }
            }
        } else {
            let from = moving.partition_point(|&j| j <= i);
            for &j in &moving[from..] {
                best.consider(pair_contact(pi, &paths[j], radius), ids[i], ids[j]);
            }
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
    tables: Range<usize>,
) -> Result<Vec<NextCollision>, Error> {
    params.validate()?;
    let groups = batch.table_groups(tables);
    let per_group: Vec<Vec<NextCollision>> = groups
        .into_par_iter()
        .map(|group| {
            let (mut paths, mut moving) = (Vec::new(), Vec::new());
            group
                .map(|k| {
                    table_paths(batch.balls(k), params, &mut paths);
                    table_next(batch, k, &paths, params.radius, &mut moving)
                })
                .collect()
        })
        .collect();
    Ok(per_group.into_iter().flatten().collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streamed_chunks_reassemble_the_whole_answer() {
        use crate::workload::{Workload, generate};
        let p = Params::default();
        let batch = generate(Workload::Spread, 300, 12, 5, &p);
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
    fn next_collisions_carry_the_tables_horizon() {
        use crate::workload::{Workload, generate};
        let p = Params::default();
        let batch = generate(Workload::Midshot, 50, 8, 3, &p);
        let next = next_collisions(&batch, &p).unwrap();
        for (k, n) in next.iter().enumerate() {
            let soonest = batch
                .balls(k)
                .iter()
                .map(|b| ball_path(b, &p).tmax)
                .fold(f64::INFINITY, f64::min);
            assert_eq!(n.horizon, soonest, "table {k}");
            assert!(n.horizon.is_finite(), "midshot tables have moving balls");
        }
        let pairs = pair_times(&batch, &p).unwrap();
        assert_eq!(crate::batch::next_from_pairs(&batch, &pairs), next);
    }
}
