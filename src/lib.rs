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
//! Where things are — modules by the question they answer, imports pointing one way, from
//! the vocabulary up to the drivers:
//! - [`model`]: the vocabulary — vectors, parameters, balls and motion states, the table,
//!   the precision;
//! - [`motion`]: a ball's path between events, and its state after some time on it;
//! - [`query`]: when does something happen — [`query::roots`], [`query::ball_ball`] (the
//!   pair solver), [`query::ball_cushion`], [`query::ball_pocket`];
//! - [`resolve`]: what an event does — the cue strike, ball–ball, ball–cushion and
//!   ball–pocket collisions, the motion transitions;
//! - [`simulate`]: the event loop — whole shots from the strike to rest, pooltool 0.6.0's
//!   physics (CPU, f64), many tables at once, and the watch (a study's view of the events);
//! - [`game`]: the rules' verdict on a simulated shot (legal, foul, turn over, game over),
//!   as pooltool 0.6.0's rule sets judge it: [`game::nine_ball`];
//! - [`batch`]: the flat batch layout, the pair order and the next-collision tie rule;
//! - [`cpu`]: the Rayon drivers [`pair_times`] and [`next_collisions`] (f64, the
//!   reference);
//! - [`gpu`]: the GPU backend (wgpu host code; each WGSL twin in `shaders/` mirrors its
//!   Rust file: `shaders/query/ball_ball.wgsl` beside `src/query/ball_ball.rs`);
//! - [`engine`]: backend choice (`cpu`, `gpu`, `auto`) with CPU fallback, and the defaults;
//!   the one whole-shot entry point, [`engine::ShotEngine::simulate_with`], which streams
//!   either backend's results to a sink (the CLI, Python, the study and every new
//!   capability use it);
//! - [`compare`]: two backends' answers against each other under the corpus's tiers;
//! - [`io`]: CSV and NumPy `.npy` input and output, atomic output files, and the
//!   simulator's physical parameters in pooltool's names ([`io::physics`]: the one parser
//!   of `--physics`, a study's `[physics]` and Python's `physics=`);
//! - [`study`]: Monte Carlo shot studies — one shot under cue noise (or given strikes),
//!   every sample from the strike to rest through the engine's one entry point
//!   ([`study::run()`]): configuration, noise, the driver, statistics, and `data/studies`'
//!   reference format;
//! - [`plan`]: which shot to play — direct-pot candidates under common noise draws, judged
//!   by the game's rules, successive halving, fresh estimates of the finalists;
//! - [`env`](mod@env): learning environments — many games of 8-ball, 9-ball or a drill stepped
//!   at once for reinforcement-learning agents (Python's `kisstime.gym`);
//! - [`workload`]: reproducible built-in workloads; [`limits`], [`error`].
//!
//! The `kisstime` command line (`src/main.rs`, `src/cli/`) is a thin layer over these,
//! built with the default `cli` feature; `default-features = false` leaves the library
//! with only what the computation needs. The `testing` feature adds test hooks (fault
//! injection and chunk limits on [`GpuEngine`]).
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
pub mod compare;
pub mod cpu;
pub mod engine;
pub mod env;
pub mod error;
pub mod game;
pub mod gpu;
pub mod io;
pub mod limits;
pub mod model;
pub mod motion;
pub mod plan;
pub mod query;
pub mod resolve;
pub mod simulate;
pub mod study;
pub mod workload;

pub use batch::{Batch, NextCollision, next_from_pairs};
pub use cpu::{next_collisions, next_collisions_of, pair_times, pair_times_of};
pub use engine::{AutoRule, Backend, Engine};
pub use error::{Error, InputError};
pub use gpu::GpuEngine;
pub use model::{Ball, MotionState, Params, Precision, Vec2};
pub use motion::{BallPath, ball_path};
pub use query::{CONTACT_TOL, Contact, RelPath, Status, pair_contact};
