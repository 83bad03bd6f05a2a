//! Monte Carlo shot studies: one table, one intended shot, re-played many times under cue
//! noise, and what the cue ball meets first.
//!
//! - [`config`]: the study file (TOML) and the built-in study;
//! - [`noise`]: each sample's noisy strike;
//! - [`run`]: the batch-driven loop over samples, and one sample on its own;
//! - [`stats`]: counts, Wilson intervals and summary statistics.
//!
//! Presentation — the text summary, the per-sample CSV and the picture — is the command
//! line's (`src/cli/`).

pub mod config;
pub mod noise;
pub mod run;
pub mod stats;

pub use config::{BUILTIN_NAME, BUILTIN_TOML, Noise, Spot, StudyConfig};
pub use noise::noisy_strike;
pub use run::{CHUNK, Outcome, SAMPLE_COLUMNS, Sample, grazes, run_study, simulate_one};
pub use stats::{Class, Stats, Summary, wilson};
