//! When does a ball reach a cushion line of the rectangular playing area?
//!
//! The playing area is the rectangle `[0, length] × [0, width]` (the cushion noses); a
//! ball's centre reaches a cushion when it reaches the rectangle inset by `R`. Per side
//! that is a quadratic in `t` on the ball's current path.

use crate::model::{Cushion, Table, dot};
use crate::motion::path::{BallPath, PATH_MOVES};
use crate::query::roots::first_upcrossing;

/// The first time in `[0, tend]` at which a ball on `path` reaches a cushion line (the
/// playing area inset by `radius`) moving outwards, and which cushion; `None` if it stays
/// inside. A ball already on a line and moving outwards reaches it at 0.
pub fn cushion_time(
    path: &BallPath,
    table: &Table,
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
        let table = Table {
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
