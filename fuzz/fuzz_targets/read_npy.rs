//! The NPY reader on arbitrary bytes: never panics, never hangs; either an error (whose
//! message can be formatted) or a valid batch that survives a write/read round trip.
#![no_main]
use libfuzzer_sys::fuzz_target;

#[path = "batch_check.rs"]
mod batch_check;

fuzz_target!(|data: &[u8]| {
    match kisstime::io::npy::read_batch_npy(data, "fuzz.npy") {
        Ok(batch) => {
            batch_check::check_batch(&batch);
            batch_check::check_round_trips(&batch);
        }
        Err(e) => {
            assert!(!e.to_string().is_empty());
        }
    }
});
