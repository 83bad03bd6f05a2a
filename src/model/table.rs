//! The table's playing area and its cushions, as the shot study models them: a rectangle
//! between the cushion noses (no pockets).

use crate::model::Vec2;

/// The playing area: `[0, length] × [0, width]`, in metres, between the cushion noses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Table {
    /// Extent along x.
    pub length: f64,
    /// Extent along y.
    pub width: f64,
}

/// A cushion of the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Cushion {
    /// The cushion along `x = 0`.
    Left,
    /// The cushion along `x = length`.
    Right,
    /// The cushion along `y = 0`.
    Bottom,
    /// The cushion along `y = width`.
    Top,
}

impl Cushion {
    /// `left`, `right`, `bottom`, `top`.
    pub fn name(self) -> &'static str {
        match self {
            Cushion::Left => "left",
            Cushion::Right => "right",
            Cushion::Bottom => "bottom",
            Cushion::Top => "top",
        }
    }

    /// The outward unit normal.
    pub fn normal(self) -> Vec2 {
        match self {
            Cushion::Left => Vec2::new(-1.0, 0.0),
            Cushion::Right => Vec2::new(1.0, 0.0),
            Cushion::Bottom => Vec2::new(0.0, -1.0),
            Cushion::Top => Vec2::new(0.0, 1.0),
        }
    }
}
