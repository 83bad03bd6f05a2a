//! Cheap bounds that rule a query out before it is solved: the axis-aligned box a ball's
//! centre stays in while its current motion lasts, and tests of that box against another
//! box, a circle and a segment's extent.
//!
//! Each test is conservative: it says "cannot happen" only when the exact solver, run on
//! the same path, could not find the event within the path's horizon either (the slack
//! [`BOX_SLACK`] is far above the rounding of the polynomials, far below any real gap).
//! The simulator uses them to skip solves whose answer would be `∞`, so its event
//! sequences do not change.

use crate::model::Vec2;
use crate::model::table::LinearCushion;
use crate::motion::trajectory::Path;

/// Slack of every box test, in m.
pub const BOX_SLACK: f64 = 1e-9;

/// The axis-aligned box `[lo, hi]` that holds a path's centre over `[0, horizon]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathBox {
    /// Smallest x and y.
    pub lo: Vec2,
    /// Largest x and y.
    pub hi: Vec2,
}

/// `(min, max)` of `c + b τ + a τ²` over `τ ∈ [0, h]` (`h` finite): the ends and, if it
/// lies inside, the vertex `τ = −b/(2a)`.
fn axis_range(a: f64, b: f64, c: f64, h: f64) -> (f64, f64) {
    let end = c + h * (b + h * a);
    let (mut lo, mut hi) = (c.min(end), c.max(end));
    if a != 0.0 {
        let tv = -b / (2.0 * a);
        if tv > 0.0 && tv < h {
            let v = c + tv * (b + tv * a);
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    (lo, hi)
}

/// The box of `path` over its horizon; a single point for a path that does not move
/// (infinite horizon, `a = b = 0`).
pub fn path_box(path: &Path) -> PathBox {
    if !path.horizon.is_finite() {
        return PathBox {
            lo: path.c,
            hi: path.c,
        };
    }
    let h = path.horizon;
    let (x0, x1) = axis_range(path.a.x, path.b.x, path.c.x, h);
    let (y0, y1) = axis_range(path.a.y, path.b.y, path.c.y, h);
    PathBox {
        lo: Vec2::new(x0, y0),
        hi: Vec2::new(x1, y1),
    }
}

/// Whether the boxes are farther apart than `dist` along x or along y (then no two
/// points of them are within `dist`).
pub fn boxes_apart(p: &PathBox, q: &PathBox, dist: f64) -> bool {
    let d = dist + BOX_SLACK;
    p.lo.x - q.hi.x > d || q.lo.x - p.hi.x > d || p.lo.y - q.hi.y > d || q.lo.y - p.hi.y > d
}

/// Whether every point of the box is farther than `rho` from `center`.
pub fn box_outside_circle(p: &PathBox, center: Vec2, rho: f64) -> bool {
    let dx = (p.lo.x - center.x).max(center.x - p.hi.x).max(0.0);
    let dy = (p.lo.y - center.y).max(center.y - p.hi.y).max(0.0);
    let d = rho + BOX_SLACK;
    dx * dx + dy * dy > d * d
}

/// Whether no point of the box projects into the segment's extent: the projection
/// `s = (q − p1)·(p2 − p1)/|p2 − p1|²`, linear in `q`, is below 0 or above 1 (by more than
/// the slack) at every corner.
pub fn box_outside_extent(p: &PathBox, seg: &LinearCushion) -> bool {
    let d = Vec2::new(seg.p2.x - seg.p1.x, seg.p2.y - seg.p1.y);
    let len2 = d.x * d.x + d.y * d.y;
    // the corners that minimise and maximise (q − p1)·d
    let (x_min, x_max) = if d.x >= 0.0 {
        (p.lo.x, p.hi.x)
    } else {
        (p.hi.x, p.lo.x)
    };
    let (y_min, y_max) = if d.y >= 0.0 {
        (p.lo.y, p.hi.y)
    } else {
        (p.hi.y, p.lo.y)
    };
    let proj = |x: f64, y: f64| (x - seg.p1.x) * d.x + (y - seg.p1.y) * d.y;
    let slack = BOX_SLACK * len2.sqrt();
    proj(x_max, y_max) < -slack || proj(x_min, y_min) > len2 + slack
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::vec3::Vec3;
    use crate::motion::trajectory::position_at;

    fn path(a: (f64, f64), b: (f64, f64), c: (f64, f64), h: f64) -> Path {
        Path {
            a: Vec2::new(a.0, a.1),
            b: Vec2::new(b.0, b.1),
            c: Vec2::new(c.0, c.1),
            horizon: h,
        }
    }

    /// Points of the path over its horizon, ends included.
    fn samples(p: &Path) -> Vec<Vec2> {
        (0..=1000)
            .map(|k| position_at(p, p.horizon * k as f64 / 1000.0))
            .collect()
    }

    #[test]
    fn the_box_holds_the_path_and_is_tight() {
        // a ball decelerating to a stop halfway along x and curving in y
        let p = path((-0.5, 0.3), (1.0, -0.4), (0.2, 0.9), 1.5);
        let bx = path_box(&p);
        let pts = samples(&p);
        for q in &pts {
            assert!(q.x >= bx.lo.x - 1e-15 && q.x <= bx.hi.x + 1e-15);
            assert!(q.y >= bx.lo.y - 1e-15 && q.y <= bx.hi.y + 1e-15);
        }
        let max_x = pts.iter().map(|q| q.x).fold(f64::MIN, f64::max);
        let min_y = pts.iter().map(|q| q.y).fold(f64::MAX, f64::min);
        assert!((bx.hi.x - max_x).abs() < 1e-6 && (bx.lo.y - min_y).abs() < 1e-6);
        let still = path_box(&Path::still(Vec2::new(0.3, 0.4)));
        assert_eq!(
            (still.lo, still.hi),
            (Vec2::new(0.3, 0.4), Vec2::new(0.3, 0.4))
        );
    }

    #[test]
    fn box_tests_rule_out_only_what_cannot_happen() {
        let p = path((0.0, 0.0), (1.0, 0.0), (0.0, 0.0), 1.0);
        let bx = path_box(&p);
        let at = |x: f64, y: f64| path_box(&Path::still(Vec2::new(x, y)));
        // a ball 2R + 1 mm above the line is apart, one 2R − 1 mm above is not
        let r = 0.028575;
        assert!(boxes_apart(&bx, &at(0.5, 2.0 * r + 1e-3), 2.0 * r));
        assert!(!boxes_apart(&bx, &at(0.5, 2.0 * r - 1e-3), 2.0 * r));
        assert!(boxes_apart(&bx, &at(1.0 + 2.0 * r + 1e-3, 0.0), 2.0 * r));
        // circles
        assert!(box_outside_circle(&bx, Vec2::new(0.5, 0.2), 0.1));
        assert!(!box_outside_circle(&bx, Vec2::new(0.5, 0.05), 0.1));
        assert!(!box_outside_circle(&bx, Vec2::new(1.09, 0.0), 0.1));
        // segment extents: a rail from (2, −1) to (2, 1) is beyond the path's reach along
        // it only if the path's box lies entirely above or below it
        let seg = crate::model::table::LinearCushion::new(
            Vec3::new(2.0, -1.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
            0,
        );
        assert!(!box_outside_extent(&bx, &seg));
        let high = path((0.0, 0.0), (1.0, 0.0), (0.0, 1.5), 1.0);
        assert!(box_outside_extent(&path_box(&high), &seg));
        let reversed = crate::model::table::LinearCushion::new(seg.p2, seg.p1, 0);
        assert!(box_outside_extent(&path_box(&high), &reversed));
        assert!(!box_outside_extent(&bx, &reversed));
    }
}
