//! Monte Carlo shot studies: one table, one intended shot, re-played many times under cue
//! noise, and what the cue ball meets first.
//!
//! - [`config`]: the study file (TOML) and the built-in study;
//! - [`strike`], [`cue_ball`], [`rectangle`]: the first-contact model — the cue strike
//!   without squirt, the cue ball's 2-D motion, the rectangular table's cushion lines (the
//!   simulator's physics, which the study is to move onto, is in [`crate::resolve`],
//!   [`crate::motion`], [`crate::query`]);
//! - [`noise`]: each sample's noisy strike;
//! - [`run`]: the batch-driven loop over samples, and one sample on its own;
//! - [`stats`]: counts, Wilson intervals and summary statistics.
//!
//! Presentation — the text summary, the per-sample CSV and the picture — is the command
//! line's (`src/cli/`).

pub mod config;
pub mod cue_ball;
pub mod noise;
pub mod rectangle;
pub mod run;
pub mod stats;
pub mod strike;

pub use config::{BUILTIN_NAME, BUILTIN_TOML, Noise, Spot, StudyConfig};
pub use noise::noisy_strike;
pub use run::{CHUNK, Outcome, SAMPLE_COLUMNS, Sample, grazes, run_study, simulate_one};
pub use stats::{Class, Stats, Summary, wilson};
