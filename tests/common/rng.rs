//! A seeded random stream for generated test cases: `rand_pcg`'s PCG (the crate's own
//! generator), so a failing case replays from its seed, with the few draws the tests use.

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;

/// A seeded generator; the same seed gives the same cases on every machine.
pub struct TestRng(Pcg64Mcg);

impl TestRng {
    pub fn new(seed: u64) -> Self {
        TestRng(Pcg64Mcg::seed_from_u64(seed))
    }

    /// Uniform on `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        self.0.random()
    }

    /// Uniform on `[lo, hi)` (`lo` when the range is empty).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform on `0..n`.
    pub fn below(&mut self, n: usize) -> usize {
        self.0.random_range(0..n)
    }

    pub fn coin(&mut self) -> bool {
        self.0.random()
    }

    /// ±1, even odds.
    pub fn sign(&mut self) -> f64 {
        if self.coin() { 1.0 } else { -1.0 }
    }

    /// ±10^u with u uniform on `[lo, hi)`: many magnitudes.
    pub fn log_signed(&mut self, lo: f64, hi: f64) -> f64 {
        let m = 10f64.powf(self.range(lo, hi));
        m * self.sign()
    }
}
