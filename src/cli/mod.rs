//! The command line, built only with the `cli` feature: argument parsing ([`args`]), the
//! commands ([`commands`] for `pairs`, `next`, `gen`; [`shots`]; [`simulate`]; [`bench`]),
//! progress bars ([`progress`]) and the presentation of results ([`report`]: the study's
//! text, JSON and CSV; the pictures: [`study_plot`] of a study, [`shot_plot`] of one shot,
//! on what [`draw`] shares). Everything it computes comes from the library.

pub mod args;
pub mod bench;
pub mod commands;
pub mod draw;
pub mod plan;
pub mod progress;
pub mod report;
pub mod shot_plot;
pub mod shots;
pub mod simulate;
pub mod study_plot;
