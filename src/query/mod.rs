//! Queries: when does something happen? One module per question, in the spirit of
//! `parry`'s `query` folder:
//!
//! - [`roots`]: roots of quadratics, the building block of the others;
//! - [`ball_ball`]: when two balls first come into contact (the quartic solver);
//! - [`ball_cushion`]: when a ball reaches a cushion line of the rectangular playing area.

pub mod ball_ball;
pub mod ball_cushion;
pub mod roots;

pub use ball_ball::{CONTACT_TOL, Contact, RelPath, Status, pair_contact};
pub use ball_cushion::cushion_time;
