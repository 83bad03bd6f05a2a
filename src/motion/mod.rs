//! Motion between events: a ball's path on its current motion ([`path`]) and its state
//! after some time on it, or at its end ([`mod@evolve`]).

pub mod evolve;
pub mod path;

pub use evolve::{contact_velocity, end_of_motion, evolve};
pub use path::{BallPath, PATH_MOVES, PATH_POCKETED, ball_path, pair_horizon};
