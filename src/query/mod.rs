//! Queries: when does something happen? One module per question, in the spirit of
//! `parry`'s `query` folder:
//!
//! - [`roots`]: roots of quadratics, the building block of the others;
//! - [`ball_ball`]: when two balls first come into contact (the quartic solver, for paths
//!   and for the simulator's ball states);
//! - [`ball_circle`]: when a ball's path enters a fixed circle (jaws and pockets);
//! - [`ball_cushion`]: when a ball reaches a straight cushion or a jaw;
//! - [`ball_pocket`]: when a ball falls into a pocket;
//! - [`bounds`]: cheap box tests that rule a query out before it is solved.

pub mod ball_ball;
pub mod ball_circle;
pub mod ball_cushion;
pub mod ball_pocket;
pub mod bounds;
pub mod roots;

pub use ball_ball::{CONTACT_TOL, Contact, RelPath, Status, ball_ball_time, pair_contact};
pub use ball_cushion::{ball_circular_cushion_time, ball_linear_cushion_time};
pub use ball_pocket::ball_pocket_time;
