//! Monte Carlo shot studies: one table, one intended shot, re-played many times under cue
//! noise (or for given strikes), every sample from the strike to rest on the simulator,
//! and what came of it: the first contact, the balls potted, where the cue ball ended.
//!
//! - [`config`]: the study file (TOML, the simulator's frame) and the built-in study;
//! - [`reference`](mod@reference): the reference format of `data/studies` (pooltool's scenario JSON,
//!   its outcome columns);
//! - [`noise`]: each sample's noisy strike, from [`philox`], the counter-based generator;
//! - [`mod@run`]: the driver over samples, through the one whole-shot entry point
//!   ([`crate::engine::ShotEngine::simulate_with`], either backend) watching the cue ball,
//!   to rest or to the first contact, and [`sample_of`], which turns a sample's watch into
//!   its outcome;
//! - [`stats`]: counts, Wilson intervals and summary statistics, from the samples or
//!   tallied as they come ([`summarize`]: a study's summary without keeping its samples).
//!
//! The strike is pooltool 0.6.0's (`instantaneous_point` with squirt,
//! [`crate::resolve::stick_ball`]). Presentation — the text and JSON summary, the
//! per-sample CSV and the picture — is the command line's (`src/cli/`).

pub mod config;
pub mod noise;
pub mod philox;
pub mod reference;
pub mod run;
pub mod stats;

pub use config::{
    BUILTIN_NAME, BUILTIN_TOML, NOISE_PRESETS, Noise, PhysicsSpread, Spot, StudyConfig, StudyGame,
    Target,
};
pub use noise::{clamped, cue_normals, mix, noisy_strike, noisy_strike_of, sample_physics};
pub use reference::{REFERENCE_COLUMNS, write_reference_csv};
pub use run::{
    CHUNK, Collect, FirstContact, Pot, RunOptions, Sample, Samples, Until, run, run_into,
    run_samples, run_strikes, run_study, sample_of, summarize,
};
pub use stats::{Class, GameCounts, Result4, Stats, Summary, Tally, potted_as_called, wilson};
