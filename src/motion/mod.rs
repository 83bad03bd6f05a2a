//! Motion between events: pooltool's closed forms for a ball's state after some time
//! ([`mod@evolve`], with the transition times), and its horizontal path as a quadratic — for
//! the collision kernels ([`path`]) and for the simulator ([`mod@trajectory`]).

pub mod evolve;
pub mod path;
pub mod trajectory;

pub use evolve::{TransitionKind, evolve, next_transition};
pub use path::{BallPath, PATH_MOVES, PATH_POCKETED, ball_path, pair_horizon};
pub use trajectory::{Path, trajectory};
