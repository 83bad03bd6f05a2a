//! Pair order within a table: one iterator for the pairs, and their indices.
//!
//! Pairs `(i, j)` of ball positions `i < j < n` in lexicographic order —
//! `(0,1), (0,2), …, (0,n−1), (1,2), …`. The pair `(i, j)` of an `n`-ball table has local
//! index `i·n − i(i+1)/2 + j − i − 1` ([`pair_index`]); [`pair_of_index`] inverts it.

/// Pairs of an `n`-ball table.
pub fn pairs_in_table(n: usize) -> usize {
    n * n.saturating_sub(1) / 2
}

/// The local index of pair `(i, j)`, `i < j < n`, in pair order.
pub fn pair_index(n: usize, i: usize, j: usize) -> usize {
    i * n - i * (i + 1) / 2 + j - i - 1
}

/// The pairs `(i, j)`, `i < j < n`, of an `n`-ball table in pair order: the one loop over
/// a table's pairs. Its `k`-th item is the pair at local index `k`.
pub fn pairs(n: usize) -> Pairs {
    Pairs { n, i: 0, j: 1 }
}

/// The iterator of [`pairs`].
#[derive(Clone, Debug)]
pub struct Pairs {
    n: usize,
    i: usize,
    j: usize,
}

impl Iterator for Pairs {
    type Item = (usize, usize);

    #[inline]
    fn next(&mut self) -> Option<(usize, usize)> {
        if self.j >= self.n {
            return None;
        }
        let pair = (self.i, self.j);
        self.j += 1;
        if self.j == self.n {
            self.i += 1;
            self.j = self.i + 1;
        }
        Some(pair)
    }
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

#[cfg(test)]
mod tests {
    use super::*;

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
    fn pairs_walks_the_pair_order() {
        for n in 0..12 {
            let walked: Vec<(usize, usize)> = pairs(n).collect();
            assert_eq!(walked.len(), pairs_in_table(n));
            for (k, &(i, j)) in walked.iter().enumerate() {
                assert!(i < j && j < n);
                assert_eq!(pair_index(n, i, j), k);
            }
        }
    }
}
