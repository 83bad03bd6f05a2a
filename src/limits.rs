//! Limits: how much an input may ask for, checked before the memory is allocated.
//!
//! A batch is held as columns, about [`BYTES_PER_BALL`] bytes a ball; per-pair answers take
//! [`BYTES_PER_PAIR`] bytes a pair for the tables answered at once. An input whose needs
//! exceed the memory the operating system reports as available (`MemAvailable` on Linux;
//! no check where it is not known) is refused with [`Error::TooLarge`], and so is a table
//! of more than [`MAX_TABLE_BALLS`] balls, whatever the memory.

use crate::error::Error;

/// The most balls one table may have: its pairs must be countable in 32 bits with room for
/// the GPU's status bits (`n(n − 1)/2 < 2³⁰`), and at 32,768 balls a table already has
/// 537 M pairs.
pub const MAX_TABLE_BALLS: usize = 32_768;

/// Memory per ball while reading and holding a batch: the ball (64 bytes), its table and
/// ball ids and its place in the file (8 each).
pub const BYTES_PER_BALL: u64 = 88;

/// Memory per pair of per-pair answers ([`crate::Contact`]).
pub const BYTES_PER_PAIR: u64 = std::mem::size_of::<crate::query::ball_ball::Contact>() as u64;

/// The memory available to this process in bytes, as the operating system reports it, or
/// `None` where it is not known.
pub fn available_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kb.checked_mul(1024)
}

/// Refuses `what` when it needs more than `bytes` of memory and that is more than is
/// available (see the module docs).
pub fn check_memory(what: &str, bytes: u64) -> Result<(), Error> {
    match available_memory() {
        Some(avail) if bytes > avail => Err(Error::TooLarge(format!(
            "{what} needs about {} of memory, more than the {} available",
            human(bytes),
            human(avail)
        ))),
        _ => Ok(()),
    }
}

/// A byte count for people: `1.4 GB`.
pub fn human(bytes: u64) -> String {
    let b = bytes as f64;
    match b {
        b if b >= 1e12 => format!("{:.1} TB", b / 1e12),
        b if b >= 1e9 => format!("{:.1} GB", b / 1e9),
        b if b >= 1e6 => format!("{:.1} MB", b / 1e6),
        _ => format!("{bytes} bytes"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn absurd_needs_are_refused_with_both_figures() {
        if available_memory().is_none() {
            eprintln!("skipped: the available memory is not known on this system");
            return;
        }
        let err = check_memory("a batch of 10^15 balls", 88_000_000_000_000_000)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("88000.0 TB") && err.contains("available"),
            "{err}"
        );
        assert!(check_memory("a small batch", 1000).is_ok());
    }

    #[test]
    fn the_table_limit_fits_the_gpu_pair_code() {
        let pairs = MAX_TABLE_BALLS * (MAX_TABLE_BALLS - 1) / 2;
        assert!(pairs < 1 << 30);
    }
}
