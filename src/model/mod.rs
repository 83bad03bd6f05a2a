//! The vocabulary: vectors, physical parameters, balls and their motion states, the table,
//! and the precision a computation runs in. Everything else builds on these; this module
//! imports nothing from the rest of the crate but [`crate::error`].

pub mod ball;
pub mod params;
pub mod precision;
pub mod table;
pub mod vec2;

pub use ball::{Ball, MotionState, UnknownState};
pub use params::{
    DEFAULT_G, DEFAULT_MU_R, DEFAULT_MU_S, DEFAULT_MU_SP_PER_RADIUS, DEFAULT_RADIUS, Params,
};
pub use precision::Precision;
pub use table::{Cushion, Table};
pub use vec2::{Vec2, dot, norm, norm1, perp_dot};
