//! The CPU drivers: every pair, or each table's next collision, for a batch, on the Rayon
//! thread pool in f64 — the reference every other backend is checked against.
//!
//! The per-table loops are the CPU twins of the GPU entry points in
//! `shaders/kernels.wgsl` (`pair_times`, `next_collisions`, with `cache_paths` for
//! `table_paths`).
//!
//! The searches for rule 4 of [`crate::query::ball_ball`] run a few pairs at a time in
//! lock step (`src/cpu/lanes.rs`, CPU only), and `next_collisions` rules most pairs out in
//! a prune pass first (`tables_next_masked`); both give the answers of
//! [`pair_contact`], bit for bit.
//!
//! # Determinism
//! Every pair is answered independently and every per-table reduction runs in pair order
//! on one thread, so results are bit-identical whatever the number of threads.

use std::ops::Range;

use rayon::prelude::*;

use crate::batch::{Batch, NextCollision, pairs};
use crate::cpu::lanes::{EntryQueue, pair_before_entry};
use crate::error::Error;
use crate::model::Vec2;
use crate::model::{Ball, Params};
use crate::motion::path::{BallPath, PATH_MOVES, PATH_POCKETED, ball_path};
use crate::query::ball_ball::{Contact, RelPath, pair_contact, passes_wide};

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
///
/// Each pair is [`pair_contact`]'s answer: the pairs that need its search for rule 4 wait
/// in a queue and are searched a few at a time (`src/cpu/lanes.rs`), the rest are answered
/// at once.
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
    let tasks = group_slices(batch, tables, &mut out, |g| batch.pairs_of_tables(g).len());
    // each worker keeps its scratch from task to task
    let scratch = || (Vec::new(), EntryQueue::new(params.radius));
    tasks
        .into_par_iter()
        .for_each_init(scratch, |(paths, queue), (group, slice)| {
            let mut at = 0;
            for k in group {
                table_paths(batch.balls(k), params, paths);
                for (i, j) in pairs(paths.len()) {
                    match pair_before_entry(&paths[i], &paths[j], params.radius) {
                        Ok(c) => slice[at] = c,
                        Err((rel, h)) => queue.push(rel, h, at, slice),
                    }
                    at += 1;
                }
            }
            queue.flush(slice);
        });
    Ok(out)
}

/// The table groups of `tables` ([`Batch::table_groups`], one Rayon task each), each with
/// its own slice of `out`, in order: `len(group)` items each.
fn group_slices<'a, T>(
    batch: &Batch,
    tables: Range<usize>,
    out: &'a mut [T],
    len: impl Fn(Range<usize>) -> usize,
) -> Vec<(Range<usize>, &'a mut [T])> {
    let mut tasks = Vec::new();
    let mut rest = out;
    for group in batch.table_groups(tables) {
        let (head, tail) = rest.split_at_mut(len(group.clone()));
        tasks.push((group, head));
        rest = tail;
    }
    tasks
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
/// table has at least two). Tables of up to [`MASK_BALLS`] balls take
/// [`tables_next_masked`] instead, with the same answers. The GPU twin
/// (`shaders/kernels.wgsl`) spreads every pair over its workgroup instead; the answers are
/// the same.
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

/// Tables of up to this many balls take [`tables_next_masked`] (one bit a ball).
const MASK_BALLS: usize = 64;

/// A table of up to [`MASK_BALLS`] balls for [`tables_next_masked`]: its ball paths, its
/// balls' flags as bit masks, and the centres of its still balls as columns (the layout of
/// [`prune_still`]).
struct TableMasks {
    n: usize,
    paths: [BallPath; MASK_BALLS],
    /// Bit `i`: ball `i` moves (and is on the table).
    moving: u64,
    /// The still balls on the table, ascending: their numbers and centres.
    still: [usize; MASK_BALLS],
    still_x: [f64; MASK_BALLS],
    still_y: [f64; MASK_BALLS],
    n_still: usize,
    /// Scratch of [`prune_still`]: whether each still ball's pair needs its solve.
    keep: [bool; MASK_BALLS],
    /// Bit `j` of row `i`: pair `(i, j)` is solved.
    rows: [u64; MASK_BALLS],
}

impl TableMasks {
    /// Empty.
    fn new() -> TableMasks {
        let still = BallPath {
            a: Vec2::ZERO,
            b: Vec2::ZERO,
            c: Vec2::ZERO,
            tmax: f64::INFINITY,
            flags: 0,
        };
        TableMasks {
            n: 0,
            paths: [still; MASK_BALLS],
            moving: 0,
            still: [0; MASK_BALLS],
            still_x: [0.0; MASK_BALLS],
            still_y: [0.0; MASK_BALLS],
            n_still: 0,
            keep: [false; MASK_BALLS],
            rows: [0; MASK_BALLS],
        }
    }

    /// The paths of `balls` (at most [`MASK_BALLS`]), by [`ball_path`].
    fn fill(&mut self, balls: &[Ball], params: &Params) {
        let n = balls.len().min(MASK_BALLS);
        self.n = n;
        self.moving = 0;
        self.n_still = 0;
        for (i, ball) in balls[..n].iter().enumerate() {
            let p = ball_path(ball, params);
            self.paths[i] = p;
            if p.flags & PATH_POCKETED != 0 {
                continue;
            }
            if p.flags & PATH_MOVES != 0 {
                self.moving |= 1 << i;
            } else {
                let s = self.n_still;
                self.still[s] = i;
                self.still_x[s] = p.c.x;
                self.still_y[s] = p.c.y;
                self.n_still = s + 1;
            }
        }
    }
}

/// [`table_next`] for tables of up to [`MASK_BALLS`] balls, with the same answers: the
/// prunes run first, then only the pairs they keep are solved. Writes the next collision
/// of each table of `tables` to `out` (as long as `tables`).
///
/// Of the pairs that can answer (both balls on the table, at least one moving), a pair of
/// a moving and a still ball that [`passes_wide`] is not solved: [`pair_contact`] answers
/// it "none" (its first test), and a "none" changes nothing but the pair's horizon, already
/// in the table's. That test runs first for all the still balls of each moving ball at
/// once ([`prune_still`]): a loop over columns without branches that the compiler
/// vectorises. The pairs kept (a bit mask per ball) then go through
/// [`pair_before_entry`] in pair order; a "none" is dropped there for the same reason,
/// those that need the search wait in an [`EntryQueue`] shared by the tables, solved a few
/// at a time, and each table's answers are then taken in pair order, so the tie rule
/// picks what [`table_next`] picks. The table's horizon is the minimum of its moving balls'
/// `tmax` (every other ball's is `∞`). In
/// `midshot` (3 moving balls of 16) 42 pairs of 120 can answer; ~3 of them are left after
/// the prune pass and ~1.2 searched. CPU only: the GPU twin spreads the pairs over its
/// workgroup, where a prune pass would only add a barrier.
fn tables_next_masked(
    batch: &Batch,
    tables: Range<usize>,
    params: &Params,
    s: &mut NextScratch,
    out: &mut [NextCollision],
) {
    let radius = params.radius;
    let t = &mut s.masks;
    s.kept.clear();
    s.answers.clear();
    for k in tables.clone() {
        t.fill(batch.balls(k), params);
        let n = t.n.min(MASK_BALLS);
        let mut best = NextCollision::none(batch.table_id(k));
        // a still or pocketed ball's tmax is ∞: the table's horizon is its moving balls'
        best.horizon = BitIter(t.moving).fold(f64::INFINITY, |h, m| h.min(t.paths[m].tmax));
        out[k - tables.start] = best;
        t.rows[..n].fill(0);
        for m in BitIter(t.moving) {
            // moving pairs (m, j), j > m: left to pair_before_entry
            t.rows[m] |= t.moving & u64::MAX.checked_shl(m as u32 + 1).unwrap_or(0);
            for st in BitIter(prune_still(t, m, radius)) {
                let j = t.still[st];
                if j > m {
                    t.rows[m] |= 1 << j;
                } else {
                    t.rows[j] |= 1 << m;
                }
            }
        }
        let ids = batch.ball_ids(k);
        for i in 0..n {
            for j in BitIter(t.rows[i]) {
                match pair_before_entry(&t.paths[i], &t.paths[j], radius) {
                    // a "none" changes nothing but the pair's horizon, already the table's
                    Ok(c) if !c.status.is_contact() => {}
                    Ok(c) => {
                        s.kept.push((k, ids[i], ids[j]));
                        s.answers.push(c);
                    }
                    Err((rel, h)) => {
                        let slot = s.answers.len();
                        s.kept.push((k, ids[i], ids[j]));
                        s.answers.push(Contact::none(h));
                        s.queue.push(rel, h, slot, &mut s.answers);
                    }
                }
            }
        }
    }
    s.queue.flush(&mut s.answers);
    for (&(k, i, j), &c) in s.kept.iter().zip(&s.answers) {
        out[k - tables.start].consider(c, i, j);
    }
}

/// The numbers of the set bits of a mask, ascending.
struct BitIter(u64);

impl Iterator for BitIter {
    type Item = usize;

    fn next(&mut self) -> Option<usize> {
        if self.0 == 0 {
            return None;
        }
        let i = self.0.trailing_zeros() as usize;
        self.0 &= self.0 - 1;
        Some(i)
    }
}

/// Scratch space of [`next_collisions_of`]'s workers, reused from chunk to chunk.
struct NextScratch {
    /// [`tables_next_masked`]'s tables.
    masks: TableMasks,
    /// The pairs kept, in order: table, ball ids.
    kept: Vec<(usize, i64, i64)>,
    /// Their answers.
    answers: Vec<Contact>,
    queue: EntryQueue,
    /// [`table_next`]'s paths and moving balls, for tables of more than [`MASK_BALLS`].
    paths: Vec<BallPath>,
    moving: Vec<usize>,
}

/// Tables that [`tables_next_masked`] takes at a time: enough searches to fill its queue.
const NEXT_CHUNK: usize = 16;

/// For moving ball `m`, bit `s`: whether the pair of `m` and the `s`-th still ball does
/// not [`passes_wide`] (so [`pair_contact`] must see it).
///
/// The relative path is the one [`pair_contact`] builds ([`RelPath::between`], the
/// lower-numbered ball first): with a still ball's `a = b = 0` and `tmax = ∞`, its `a`, `b`
/// and the horizon are the same for every still ball on one side of `m`, and only `C`
/// varies. Two loops over the still balls' centres, without branches.
fn prune_still(t: &mut TableMasks, m: usize, radius: f64) -> u64 {
    let pm = t.paths[m];
    debug_assert!(t.still[..t.n_still].iter().all(|&j| {
        let p = &t.paths[j];
        (p.a, p.b, p.tmax) == (Vec2::ZERO, Vec2::ZERO, f64::INFINITY)
    }));
    let n_still = t.n_still.min(MASK_BALLS);
    let split = t.still[..n_still].partition_point(|&j| j < m);
    let h = pm.tmax;
    let (xs, ys, keep) = (&t.still_x, &t.still_y, &mut t.keep);
    // still ball j < m: C(t) is m's path minus j's
    let (a, b) = (pm.a - Vec2::ZERO, pm.b - Vec2::ZERO);
    for s in 0..split {
        let c = Vec2::new(pm.c.x - xs[s], pm.c.y - ys[s]);
        keep[s] = !passes_wide(&RelPath { a, b, c }, radius, h);
    }
    // still ball j > m: j's path minus m's
    let (a, b) = (Vec2::ZERO - pm.a, Vec2::ZERO - pm.b);
    for s in split..n_still {
        let c = Vec2::new(xs[s] - pm.c.x, ys[s] - pm.c.y);
        keep[s] = !passes_wide(&RelPath { a, b, c }, radius, h);
    }
    keep[..n_still]
        .iter()
        .enumerate()
        .fold(0, |bits, (s, &kept)| bits | (u64::from(kept) << s))
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
    let mut out = vec![NextCollision::none(0); tables.len()];
    let tasks = group_slices(batch, tables, &mut out, |g| g.len());
    // each worker keeps its scratch from task to task
    let scratch = || NextScratch {
        masks: TableMasks::new(),
        kept: Vec::new(),
        answers: Vec::new(),
        queue: EntryQueue::new(params.radius),
        paths: Vec::new(),
        moving: Vec::new(),
    };
    tasks
        .into_par_iter()
        .for_each_init(scratch, |scratch, (group, slice)| {
            let mut k = group.start;
            while k < group.end {
                // a run of small tables in chunks, or one large table
                let mut end = k;
                while end < group.end
                    && end - k < NEXT_CHUNK
                    && batch.balls(end).len() <= MASK_BALLS
                {
                    end += 1;
                }
                let at = k - group.start;
                if end > k {
                    let chunk = &mut slice[at..at + (end - k)];
                    tables_next_masked(batch, k..end, params, scratch, chunk);
                    k = end;
                } else {
                    let (paths, moving) = (&mut scratch.paths, &mut scratch.moving);
                    table_paths(batch.balls(k), params, paths);
                    slice[at] = table_next(batch, k, paths, params.radius, moving);
                    k += 1;
                }
            }
        });
    Ok(out)
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

    /// Tables of every kind and size around the prune pass's limit, some balls pocketed.
    fn mixed_batch() -> Batch {
        use crate::workload::{Workload, generate};
        let p = Params::default();
        let mut batch = Batch::new();
        let mut id = 0;
        for (w, n) in [
            (Workload::Midshot, 2),
            (Workload::Midshot, 16),
            (Workload::Spread, 5),
            (Workload::Worst, 16),
            (Workload::Rack, 16),
            (Workload::Spread, 63),
            (Workload::Midshot, 64),
            (Workload::Spread, 65),
            (Workload::Worst, 70),
        ] {
            let src = generate(w, 12, n, id as u64, &p);
            for k in 0..src.num_tables() {
                let balls = src.balls(k).iter().enumerate().map(|(i, b)| {
                    let mut b = *b;
                    if (i + k) % 7 == 3 {
                        b.state = crate::model::MotionState::Pocketed;
                    }
                    (i as i64, b)
                });
                batch.push_table(id, balls).unwrap();
                id += 1;
            }
        }
        batch
    }

    #[test]
    fn prunes_and_lanes_give_pair_contacts_answers() {
        let p = Params::default();
        let batch = mixed_batch();
        let got = pair_times(&batch, &p).unwrap();
        let mut at = 0;
        for k in 0..batch.num_tables() {
            let paths: Vec<BallPath> = batch.balls(k).iter().map(|b| ball_path(b, &p)).collect();
            for (i, j) in pairs(paths.len()) {
                let want = pair_contact(&paths[i], &paths[j], p.radius);
                assert_eq!(
                    got[at].t.to_bits(),
                    want.t.to_bits(),
                    "table {k} pair {i} {j}"
                );
                assert_eq!(got[at], want, "table {k} pair {i} {j}");
                at += 1;
            }
        }
        let next = next_collisions(&batch, &p).unwrap();
        let mut moving = Vec::new();
        for (k, n) in next.iter().enumerate() {
            let paths: Vec<BallPath> = batch.balls(k).iter().map(|b| ball_path(b, &p)).collect();
            let want = table_next(&batch, k, &paths, p.radius, &mut moving);
            assert_eq!(*n, want, "table {k}");
            assert_eq!(n.t.to_bits(), want.t.to_bits(), "table {k}");
        }
        assert_eq!(crate::batch::next_from_pairs(&batch, &got), next);
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
