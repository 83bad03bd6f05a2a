//! Resolutions: what an event does to the balls it involves (pooltool 0.6.0's default
//! resolver, `docs/reference/pooltool-physics.md` §5):
//!
//! - [`stick_ball`]: the cue strike (instantaneous point contact with squirt);
//! - [`ball_ball`]: `frictional_inelastic` with Alciatore's friction, after make_kiss;
//! - [`ball_cushion`]: `stronge_compliant` for straight cushions and jaws, after make_kiss,
//!   with the Stronge model itself in [`stronge`];
//! - [`ball_pocket`]: the canonical pocket;
//! - [`transition`]: the motion transitions (sliding → rolling → spinning → stationary).

pub mod ball_ball;
pub mod ball_cushion;
pub mod ball_pocket;
pub mod stick_ball;
pub mod stronge;
pub mod transition;

pub use ball_ball::resolve_ball_ball;
pub use ball_cushion::{resolve_circular_cushion, resolve_linear_cushion};
pub use ball_pocket::resolve_pocket;
pub use stick_ball::{CueStrike, cue_strike};
pub use transition::resolve_transition;
