//! Ball–cushion detection (spec §4.4, §4.5; `evolution/event_based/solve.py:
//! ball_linear_cushion_collision_time`, `ball_circular_cushion_collision_coeffs`).

use crate::model::Vec2;
use crate::model::ball_state::BallState;
use crate::model::sim_params::{BallParams, EPS};
use crate::model::table::{CircularCushion, LinearCushion};
use crate::motion::trajectory::{Path, position_at, trajectory};
use crate::query::ball_circle::circle_crossing;

/// pooltool's quadratic solver (`ptmath/roots/quadratic.py: solve`, §4.4), copied in its
/// arithmetic: `|A| < EPS` gives the linear root twice (none if also `|B| < EPS`);
/// otherwise `β = B/2`, `Δ = β² − AC`, `τ₁ = (−β − √Δ)/A`, `τ₂ = −τ₁ − B/A` (NaN for
/// `Δ < 0`, which the caller rejects).
pub fn quadratic_pooltool(a: f64, b: f64, c: f64) -> [f64; 2] {
    if a.abs() < EPS {
        if b.abs() < EPS {
            return [f64::NAN, f64::NAN];
        }
        let t = -c / b;
        return [t, t];
    }
    let beta = b / 2.0;
    let disc = beta * beta - a * c;
    let t1 = (-beta - disc.sqrt()) / a;
    [t1, -t1 - b / a]
}

/// Whether the path's centre at τ projects into the segment's extent:
/// `s = (p(τ) − p1)·(p2 − p1)/|p2 − p1|² ∈ [0, 1]`.
fn within_extent(path: &Path, seg: &LinearCushion, tau: f64) -> bool {
    let q = position_at(path, tau);
    let d = Vec2::new(seg.p2.x - seg.p1.x, seg.p2.y - seg.p1.y);
    let rel = Vec2::new(q.x - seg.p1.x, q.y - seg.p1.y);
    let s = (rel.x * d.x + rel.y * d.y) / (d.x * d.x + d.y * d.y);
    (0.0..=1.0).contains(&s)
}

/// The smallest accepted root of one side's quadratic `A τ² + B τ + C = 0`: τ > EPS
/// (strictly, Q6) and within the segment's extent; `∞` if none.
fn side_time(path: &Path, seg: &LinearCushion, a: f64, b: f64, c: f64) -> f64 {
    let mut best = f64::INFINITY;
    for tau in quadratic_pooltool(a, b, c) {
        if tau > EPS && tau < best && within_extent(path, seg, tau) {
            best = tau;
        }
    }
    best
}

/// τ until a translating ball's centre reaches the segment's checked offset line, `R`
/// from it (§4.4), or `∞` (non-translating balls too). The line's signed value is linear
/// in position, so each side is a quadratic: direction 0 (SIDE1) solves
/// `A τ² + B τ + C₊ = 0`, direction 1 (SIDE2) `C₋`, direction 2 both, with
/// `A = lx a_x + ly a_y`, `B = lx b_x + ly b_y`, `C± = l0 + lx c_x + ly c_y ± R‖l‖`.
pub fn ball_linear_cushion_time(b: &BallState, seg: &LinearCushion, p: &BallParams) -> f64 {
    if !b.translating() {
        return f64::INFINITY;
    }
    linear_cushion_time_on(&trajectory(b, p), seg, p.r)
}

/// [`ball_linear_cushion_time`] for a translating ball's path (computed once for all
/// segments), `radius` the ball's.
pub fn linear_cushion_time_on(path: &Path, seg: &LinearCushion, radius: f64) -> f64 {
    let a = seg.lx * path.a.x + seg.ly * path.a.y;
    let bb = seg.lx * path.b.x + seg.ly * path.b.y;
    let c0 = seg.l0 + seg.lx * path.c.x + seg.ly * path.c.y;
    let off = radius * (seg.lx * seg.lx + seg.ly * seg.ly).sqrt();
    let mut best = f64::INFINITY;
    if seg.direction == 0 || seg.direction == 2 {
        best = best.min(side_time(path, seg, a, bb, c0 + off));
    }
    if seg.direction == 1 || seg.direction == 2 {
        best = best.min(side_time(path, seg, a, bb, c0 - off));
    }
    best
}

/// τ until a translating ball's centre reaches distance `r_c + R` from the jaw's centre
/// (§4.5; the whole circle, no arc restriction; from outside, or from inside where a kiss
/// left it), or `∞`. See
/// [`crate::query::ball_circle::circle_crossing`] for the method.
pub fn ball_circular_cushion_time(b: &BallState, seg: &CircularCushion, p: &BallParams) -> f64 {
    if !b.translating() {
        return f64::INFINITY;
    }
    let path = trajectory(b, p);
    let center = Vec2::new(seg.center.x, seg.center.y);
    circle_crossing(&path, center, seg.radius + p.r)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::MotionState;
    use crate::model::table::Table;
    use crate::model::vec3::Vec3;

    fn sliding(x: f64, y: f64, vx: f64, vy: f64) -> BallState {
        BallState {
            v: Vec3::new(vx, vy, 0.0),
            s: MotionState::Sliding,
            ..BallState::at_rest(x, y, BallParams::default().r)
        }
    }

    #[test]
    fn quadratic_cases() {
        assert_eq!(quadratic_pooltool(0.0, 2.0, -4.0), [2.0, 2.0]);
        assert!(quadratic_pooltool(0.0, 0.0, 1.0)[0].is_nan());
        let [t1, t2] = quadratic_pooltool(1.0, -3.0, 2.0);
        assert_eq!((t1.min(t2), t1.max(t2)), (1.0, 2.0));
        assert!(quadratic_pooltool(1.0, 0.0, 1.0)[0].is_nan());
    }

    #[test]
    fn rail_nine_hit_time() {
        let p = BallParams::default();
        let t = Table::nine_foot();
        let rail9 = &t.linear[5];
        assert_eq!(t.linear_ids[5], "9");
        let b = sliding(0.6, 2.0, 0.0, 3.0);
        let tau = ball_linear_cushion_time(&b, rail9, &p);
        // y(τ) = 2 + τ − ½ μ_s g τ² reaches l − R
        let k = 0.5 * 0.2 * 9.81;
        let gap = 2.54 - p.r - 2.0;
        let expect = (3.0 - (9.0 - 4.0 * k * gap).sqrt()) / (2.0 * k);
        assert!((tau - expect).abs() < 1e-12, "{tau} {expect}");
        // moving away: only the polynomial's return, after the slide has ended (the
        // transition comes first)
        let away = sliding(0.6, 2.0, 0.0, -1.0);
        let t_away = ball_linear_cushion_time(&away, rail9, &p);
        assert!(t_away > crate::motion::evolve::slide_time(&away, &p));
        // outside the extent: no hit
        assert_eq!(
            ball_linear_cushion_time(&sliding(0.02, 2.0, 0.0, 1.0), rail9, &p),
            f64::INFINITY
        );
    }

    #[test]
    fn jaw_arc_hit() {
        let p = BallParams::default();
        let t = Table::nine_foot();
        let jaw = &t.circular[5];
        assert_eq!(t.circular_ids[5], "8t");
        // aimed straight at the arc's centre from below
        let b = sliding(jaw.center.x, 2.3, 0.0, 3.0);
        let tau = ball_circular_cushion_time(&b, jaw, &p);
        let path = trajectory(&b, &p);
        let y = position_at(&path, tau).y;
        assert!((y - (jaw.center.y - jaw.radius - p.r)).abs() < 1e-12);
    }
}
