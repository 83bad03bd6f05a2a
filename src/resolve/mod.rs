//! Resolutions: what an event does to the balls it involves. Today the cue strike
//! ([`stick_ball`]); the simulator adds ball–ball, ball–cushion, ball–pocket and the
//! motion transitions beside it.

pub mod stick_ball;

pub use stick_ball::{DEFAULT_BALL_MASS, DEFAULT_CUE_MASS, Masses, Strike, cue_strike};
