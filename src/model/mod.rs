//! The vocabulary: vectors, physical parameters, balls and their states, the table, and
//! the precision a computation runs in. Everything else builds on these; this module
//! imports nothing from the rest of the crate but [`crate::error`].
//!
//! Two views of a ball: [`Ball`] (2-D position and velocity, 3-D spin: what the collision
//! kernels and their WGSL twins read) and [`BallState`] (pooltool's full 3-D state, what the
//! simulator evolves and resolves). [`Params`] are the kernels' parameters,
//! [`SimParams`] the simulator's (ball, cue, resolver). [`fmath`]: `exp`, `sin`, `cos`,
//! `acos` from arithmetic alone, for the GPU's f64 (twin `shaders/model/fmath.wgsl`; the
//! first piece of the GPU event loop).

pub mod ball;
pub mod ball_state;
pub mod fmath;
pub mod params;
pub mod precision;
pub mod sim_params;
pub mod table;
pub mod vec2;
pub mod vec3;

pub use ball::{Ball, MotionState, UnknownState};
pub use ball_state::BallState;
pub use params::{
    DEFAULT_G, DEFAULT_MU_R, DEFAULT_MU_S, DEFAULT_MU_SP_PER_RADIUS, DEFAULT_RADIUS, Params,
};
pub use precision::Precision;
pub use sim_params::{BallParams, CueParams, Physics, ResolverParams, SimParams};
pub use table::{CircularCushion, LinearCushion, Pocket, PocketTableSpecs, Table};
pub use vec2::{Vec2, dot, norm, norm1, perp_dot};
pub use vec3::Vec3;
