//! The CPU backend: Rayon drivers over a batch, in f64 (the reference).
//!
//! [`kernels`] holds the per-table loops, the CPU twins of `shaders/kernels.wgsl`.

pub mod kernels;
mod lanes;

pub use kernels::{next_collisions, next_collisions_of, pair_times, pair_times_of};
