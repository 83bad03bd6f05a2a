//! # kisstime — when do two billiard balls collide?
//!
//! For every ball pair of a batch of billiard tables, the time at which the two balls first
//! come into contact while approaching, within the time their current motions last. Each
//! ball moves on a quadratic path between events (sliding, rolling, or still), so the
//! contact condition `|C(t)| = 2R` is a quartic in `t`; this crate finds its first relevant
//! root exactly and robustly, including the degenerate cases where existing simulators
//! fail (parallel rolling, identical motion, a ball that stops short, a just-collided
//! touching pair, grazes).
//!
//! Where things are:
//! - [`physics`]: the model — parameters, motion states, one ball's path, a pair's
//!   relative path and quartic;
//! - [`solver`]: the answer for one pair (rules 1–4) and the root finder;
//! - [`batch`]: the flat batch layout and the Rayon drivers [`pair_times`] and
//!   [`next_collisions`];
//! - [`gpu`]: the GPU backend (wgpu host code; the WGSL twins are in `shaders/`);
//! - [`engine`]: backend choice (`cpu`, `gpu`, `auto`) with CPU fallback;
//! - [`compare`]: two backends' answers against each other under the corpus's tiers;
//! - [`io`]: CSV input and output, and the format by file name;
//! - [`npy`]: NumPy `.npy` input and output for large batches;
//! - [`limits`]: what an input may ask for, checked before allocating;
//! - [`shot`], [`scenario`], [`study`], [`plot`]: Monte Carlo shot studies (the cue strike
//!   and the cue ball's motion, the TOML scenario, the study driver and its summary, the
//!   picture);
//! - the `kisstime` binary is a thin command-line layer over these.
//!
//! ```
//! use kisstime::{Ball, Batch, Params, Status, pair_times};
//!
//! let p = Params::default();
//! let mut batch = Batch::new();
//! // a cue ball rolling at 2 m/s straight at a still ball 1 m away
//! batch.push_table(0, [
//!     (0, Ball::rolling(0.0, 0.0, 2.0, 0.0, p.radius)),
//!     (1, Ball::at_rest(1.0, 0.0)),
//! ])?;
//! let pairs = pair_times(&batch, &p)?;
//! assert_eq!(pairs[0].status, Status::Hit);
//! assert!(pairs[0].t > 0.47 && pairs[0].t < 0.48);
//! # Ok::<(), kisstime::Error>(())
//! ```

#![warn(missing_docs)]

pub mod batch;
pub mod bench;
pub mod compare;
pub mod engine;
pub mod error;
pub mod gpu;
pub mod io;
pub mod limits;
pub mod npy;
pub mod physics;
pub mod plot;
pub mod scenario;
pub mod shot;
pub mod solver;
pub mod study;
pub mod workload;

pub use batch::{Batch, NextCollision, next_collisions, next_from_pairs, pair_times};
pub use engine::{Backend, Engine};
pub use error::{Error, InputError};
pub use gpu::{Fault, GpuEngine, Precision};
pub use physics::{Ball, BallPath, MotionState, Params, RelPath, ball_path};
pub use solver::{CONTACT_TOL, Contact, Status, pair_contact};
