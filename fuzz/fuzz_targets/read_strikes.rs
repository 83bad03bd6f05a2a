//! The strike readers (`io::strikes::parse_strikes`, `parse_sample_strikes`: what
//! `kisstime simulate --strikes` and `kisstime shots --strikes` read) on arbitrary bytes,
//! the first byte choosing the reader and the format (CSV or `.npy`): never panics, never
//! hangs; an error whose message formats, or rows whose strikes are what the readers
//! promise (every number finite for a study's strikes, which are validated; a study's
//! sample ids do not repeat).
#![no_main]
use libfuzzer_sys::fuzz_target;

use std::collections::HashSet;

use kisstime::io::Format;
use kisstime::io::strikes::{parse_sample_strikes, parse_strikes};

fuzz_target!(|data: &[u8]| {
    let Some((&choice, rest)) = data.split_first() else {
        return;
    };
    let format = if choice & 1 == 0 {
        Format::Csv
    } else {
        Format::Npy
    };
    if choice & 2 == 0 {
        match parse_strikes(rest, "fuzz", format) {
            Err(e) => assert!(!e.to_string().is_empty()),
            Ok(rows) => {
                // rows are checked when put on a batch (match_strikes); here: read as given
                for r in &rows {
                    let _ = r.strike.validate();
                }
            }
        }
    } else {
        match parse_sample_strikes(rest, "fuzz", format) {
            Err(e) => assert!(!e.to_string().is_empty()),
            Ok(rows) => {
                let mut seen = HashSet::new();
                for r in &rows {
                    r.strike.validate().expect("a validated strike");
                    assert!(seen.insert(r.sample), "sample {} repeated", r.sample);
                }
            }
        }
    }
});
