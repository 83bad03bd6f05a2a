//! pooltool's candidate-time caches as flat arrays (spec §3; `evolution/event_based/
//! cache.py`): one slot per (ball pair), (ball, segment), (ball, jaw), (ball, pocket),
//! holding an absolute time and an insertion stamp.
//!
//! pooltool keeps each category in a dict; `min` over a dict returns, of equal times, the
//! entry inserted first, and an invalidated entry is deleted and later re-inserted at the
//! end. The stamp reproduces that order: of equal times the smaller stamp wins. Each step
//! of the loop fills a category's missing entries once, in the category's fixed order
//! (pairs in combinations order, a ball–table category ball by ball and item by item), so
//! the insertion order within a category is (step, position in that order):
//! [`insertion_stamp`]. A stamp depends on nothing but its own entry, so the entries can be
//! filled in any order, or in parallel, as the GPU twin does.

/// One cached candidate: absolute time `t` (`∞` for never; NaN while missing) and the
/// insertion stamp `seq`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slot {
    /// Absolute time in s.
    pub t: f64,
    /// Insertion stamp (dict order).
    pub seq: u64,
}

impl Slot {
    /// A slot whose entry must be (re)computed.
    pub const MISSING: Slot = Slot {
        t: f64::NAN,
        seq: 0,
    };

    /// Whether the entry must be (re)computed.
    pub fn is_missing(&self) -> bool {
        self.t.is_nan()
    }
}

/// The slot with the smallest time, of equal times the one inserted first:
/// `(index, time)`, or `None` for an empty list. Missing slots must have been filled.
pub fn earliest(slots: &[Slot]) -> Option<(usize, f64)> {
    let mut best: Option<(usize, Slot)> = None;
    for (k, s) in slots.iter().enumerate() {
        let better = match best {
            None => true,
            Some((_, b)) => s.t < b.t || (s.t == b.t && s.seq < b.seq),
        };
        if better {
            best = Some((k, *s));
        }
    }
    best.map(|(k, s)| (k, s.t))
}

/// The earliest entry of one ball's row of a ball–table category (its slots for every
/// segment, jaw or pocket): those entries are always computed and invalidated together,
/// so the row keeps only its earliest slot (of equal times the first inserted) and that
/// item's index. The earliest of the rows is then the category's earliest entry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowBest {
    /// The row's earliest slot.
    pub slot: Slot,
    /// Its item (segment, jaw or pocket index).
    pub item: u32,
}

impl RowBest {
    /// A row whose entries must be (re)computed.
    pub const MISSING: RowBest = RowBest {
        slot: Slot::MISSING,
        item: 0,
    };
}

/// The row with the earliest slot, of equal times the one inserted first (as [`earliest`]
/// over all the rows' slots): `(ball, row)`, or `None` for no rows. Missing rows must have
/// been filled.
pub fn earliest_row(rows: &[RowBest]) -> Option<(usize, RowBest)> {
    let mut best: Option<(usize, RowBest)> = None;
    for (i, r) in rows.iter().enumerate() {
        let better = match best {
            None => true,
            Some((_, b)) => {
                r.slot.t < b.slot.t || (r.slot.t == b.slot.t && r.slot.seq < b.slot.seq)
            }
        };
        if better {
            best = Some((i, *r));
        }
    }
    best
}

/// The insertion stamp of an entry filled in the step after `n_events` events at position
/// `index` of its category's fill order: `(n_events, index)` as one number, compared as
/// the pair is, lexicographically.
pub fn insertion_stamp(n_events: usize, index: usize) -> u64 {
    ((n_events as u64) << 32) | index as u64
}

/// The index of pair `(i, j)`, `i < j < n`, in `itertools.combinations` order.
pub fn pair_index(i: usize, j: usize, n: usize) -> usize {
    i * n - i * (i + 1) / 2 + (j - i - 1)
}

/// The pair `(i, j)` at combinations index `k` of `n` balls.
pub fn pair_at(k: usize, n: usize) -> (usize, usize) {
    let mut i = 0;
    let mut start = 0;
    while start + (n - i - 1) <= k {
        start += n - i - 1;
        i += 1;
    }
    (i, i + 1 + (k - start))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pair_order_is_combinations_order() {
        let n = 5;
        let mut k = 0;
        for i in 0..n {
            for j in i + 1..n {
                assert_eq!(pair_index(i, j, n), k);
                assert_eq!(pair_at(k, n), (i, j));
                k += 1;
            }
        }
    }

    #[test]
    fn ties_go_to_the_first_inserted() {
        let slots = [
            Slot { t: 2.0, seq: 5 },
            Slot { t: 1.0, seq: 9 },
            Slot { t: 1.0, seq: 3 },
            Slot {
                t: f64::INFINITY,
                seq: 0,
            },
        ];
        assert_eq!(earliest(&slots), Some((2, 1.0)));
        assert_eq!(earliest(&[]), None);
    }
}
