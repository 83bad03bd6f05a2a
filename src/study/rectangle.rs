//! The shot study's table: a rectangle between the cushion noses (no pockets), and when
//! the cue ball reaches one of its cushion lines.
//!
//! The playing area is the rectangle `[0, length] × [0, width]` (the cushion noses); a
//! ball's centre reaches a cushion when it reaches the rectangle inset by `R`. Per side
//! that is a quadratic in `t` on the ball's current path. (This is the first-contact
//! study's model; the simulator's pocket table is [`crate::model::Table`].)

use crate::model::{Vec2, dot};
use crate::motion::path::{BallPath, PATH_MOVES};
use crate::query::roots::first_upcrossing;

/// The playing area: `[0, length] × [0, width]`, in metres, between the cushion noses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rectangle {
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

/// The first time in `[0, tend]` at which a ball on `path` reaches a cushion line (the
/// playing area inset by `radius`) moving outwards, and which cushion; `None` if it stays
/// inside. A ball already on a line and moving outwards reaches it at 0.
pub fn cushion_time(
    path: &BallPath,
    table: &Rectangle,
    radius: f64,
    tend: f64,
) -> Option<(f64, Cushion)> {
    if path.flags & PATH_MOVES == 0 {
        return None;
    }
    let mut best: Option<(f64, Cushion)> = None;
    for cushion in [Cushion::Left, Cushion::Right, Cushion::Bottom, Cushion::Top] {
        let n = cushion.normal();
        // signed distance of the centre beyond the line: s(t) = n·r(t) − limit, with the
        // line at n·r = limit (x = R, x = length − R, …)
        let limit = match cushion {
            Cushion::Left | Cushion::Bottom => -radius,
            Cushion::Right => table.length - radius,
            Cushion::Top => table.width - radius,
        };
        let (qa, qb, qc) = (dot(n, path.a), dot(n, path.b), dot(n, path.c) - limit);
        let t = if qc >= 0.0 {
            // on or beyond the line: reaches it now if moving outwards
            if qb > 0.0 || (qb == 0.0 && qa > 0.0) {
                Some(0.0)
            } else {
                first_upcrossing(qa, qb, qc)
            }
        } else {
            first_upcrossing(qa, qb, qc)
        };
        if let Some(t) = t.filter(|&t| t <= tend)
            && best.is_none_or(|(bt, _)| t < bt)
        {
            best = Some((t, cushion));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Ball, Params};
    use crate::motion::path::ball_path;

    #[test]
    fn cushion_line_reached_by_a_rolling_ball() {
        let p = Params::default();
        let table = Rectangle {
            length: 2.0,
            width: 1.0,
        };
        let ball = Ball::rolling(1.0, 0.5, 2.0, 0.0, p.radius);
        let path = ball_path(&ball, &p);
        let (t, c) = cushion_time(&path, &table, p.radius, path.tmax).unwrap();
        assert_eq!(c, Cushion::Right);
        let x = path.at(t).x;
        assert!((x - (2.0 - p.radius)).abs() < 1e-12);
    }
}
