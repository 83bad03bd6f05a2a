//! Replays a shot study's strikes in the reference format of `data/studies` and writes
//! one outcome row per sample with the reference's columns.
//!
//! ```text
//! cargo run --release --example replay_study -- SCENARIO.json STRIKES.csv OUT.csv
//! ```
//!
//! Reads the scenario (pooltool's frame and vocabulary,
//! [`kisstime::study::reference`]) and the strikes (`sample,V0,phi,theta,a,b`, CSV or
//! `.npy`), runs every strike to rest through the same code as `kisstime shots
//! --strikes` ([`kisstime::study::run_strikes`], pooltool 0.6.0's physics, all cores),
//! writes OUT.csv atomically (`sample,first_contact,first_t,intended_potted,
//! intended_pocket,cue_potted,potted,cue_x,cue_y,n_events,duration`) and prints as its last
//! line `N samples in S s: X samples/s` (simulation time only). `tests/study_reference.rs`
//! compares the rows with pooltool's, sample by sample.

use std::path::PathBuf;

use kisstime::io::strikes::read_sample_strikes;
use kisstime::io::{output_error, write_output};
use kisstime::study::{RunOptions, StudyConfig, run_strikes, write_reference_csv};

fn main() {
    if let Err(e) = run() {
        eprintln!("replay_study: {e}");
        std::process::exit(if e.is_bad_input() { 2 } else { 1 });
    }
}

fn run() -> Result<(), kisstime::Error> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [scenario, strikes, out] = args.as_slice() else {
        eprintln!("usage: replay_study SCENARIO.json STRIKES.csv OUT.csv");
        std::process::exit(2);
    };
    let config = StudyConfig::read_reference(&PathBuf::from(scenario))?;
    let rows = read_sample_strikes(&PathBuf::from(strikes))?;
    let ids: Vec<i64> = rows.iter().map(|r| r.sample).collect();
    let strikes: Vec<_> = rows.iter().map(|r| r.strike).collect();
    let started = std::time::Instant::now();
    let samples = run_strikes(&config, &strikes, &RunOptions::default(), &mut |_, _| {})?;
    let seconds = started.elapsed().as_secs_f64();
    write_output(Some(&PathBuf::from(out)), |w| {
        write_reference_csv(w, &config, &ids, &samples).map_err(output_error)
    })?;
    let n = samples.len();
    println!(
        "{n} samples in {seconds:.3} s: {:.0} samples/s",
        n as f64 / seconds
    );
    Ok(())
}
