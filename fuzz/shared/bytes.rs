//! The fuzzer's bytes read as a stream of choices (zeros once they run out), shared by the
//! targets that decode structured inputs (`event_loop`, `rules_judge`).
#![allow(dead_code)]

pub struct Bytes<'a> {
    data: &'a [u8],
}

impl<'a> Bytes<'a> {
    pub fn new(data: &'a [u8]) -> Self {
        Bytes { data }
    }

    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    pub fn u8(&mut self) -> u8 {
        match self.data.split_first() {
            Some((&b, rest)) => {
                self.data = rest;
                b
            }
            None => 0,
        }
    }

    pub fn u32(&mut self) -> u32 {
        let mut v = 0u32;
        for _ in 0..4 {
            v = (v << 8) | self.u8() as u32;
        }
        v
    }

    pub fn u64(&mut self) -> u64 {
        let mut v = 0u64;
        for _ in 0..8 {
            v = (v << 8) | self.u8() as u64;
        }
        v
    }

    /// A number in `[0, 1)` from two bytes (coarse: enough for layouts), or 8 bytes
    /// when `fine`.
    pub fn unit(&mut self) -> f64 {
        let hi = self.u8() as u64;
        let lo = self.u8() as u64;
        ((hi << 8) | lo) as f64 / 65536.0
    }

    /// A uniform number in `[0, 1)` at full precision.
    pub fn unit_fine(&mut self) -> f64 {
        (self.u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A number in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// A boolean that is true once in `n` (on average, for bytes uniform).
    pub fn one_in(&mut self, n: u8) -> bool {
        self.u8() % n == 0
    }

    /// Any f64, raw bits (NaN and infinities included).
    pub fn raw_f64(&mut self) -> f64 {
        f64::from_bits(self.u64())
    }
}
