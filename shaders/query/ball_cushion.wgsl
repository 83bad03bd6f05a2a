// Ball–cushion detection (spec §4.4, §4.5). WGSL twin of src/query/ball_cushion.rs.

// pooltool's quadratic solver (ptmath/roots/quadratic.py: solve, §4.4), in its
// arithmetic: |A| < EPS gives the linear root twice (none if also |B| < EPS); otherwise
// β = B/2, Δ = β² − AC, τ₁ = (−β − √Δ)/A, τ₂ = −τ₁ − B/A. Where the Rust twin returns NaN
// (no root; Δ < 0), this returns NEVER: WGSL has no NaN to rely on, and NEVER is rejected
// the same way by the caller (it is never < the best so far).
fn quadratic_pooltool(a: real, b: real, c: real) -> real2 {
    if abs(a) < SIM_EPS {
        if abs(b) < SIM_EPS {
            return real2(NEVER, NEVER);
        }
        let t = -c / b;
        return real2(t, t);
    }
    let beta = b / 2.0;
    let disc = beta * beta - a * c;
    if disc < 0.0 {
        return real2(NEVER, NEVER);
    }
    let t1 = (-beta - sqrt(disc)) / a;
    return real2(t1, -t1 - b / a);
}

// Whether the path's centre at τ projects into the segment's extent:
// s = (p(τ) − p1)·(p2 − p1)/|p2 − p1|² ∈ [0, 1].
fn within_extent(path: Path, seg: LinearCushion, tau: real) -> bool {
    let q = position_at(path, tau);
    let d = real2(seg.p2.x - seg.p1.x, seg.p2.y - seg.p1.y);
    let rel = real2(q.x - seg.p1.x, q.y - seg.p1.y);
    let s = (rel.x * d.x + rel.y * d.y) / (d.x * d.x + d.y * d.y);
    return s >= 0.0 && s <= 1.0;
}

// The smallest accepted root of one side's quadratic A τ² + B τ + C = 0: τ > EPS
// (strictly, Q6) and within the segment's extent; NEVER if none.
fn side_time(path: Path, seg: LinearCushion, a: real, b: real, c: real) -> real {
    var best = NEVER;
    let roots = quadratic_pooltool(a, b, c);
    for (var k = 0u; k < 2u; k++) {
        let tau = roots[k];
        if tau > SIM_EPS && tau < best && within_extent(path, seg, tau) {
            best = tau;
        }
    }
    return best;
}

// τ until a translating ball's centre reaches the segment's checked offset line, R from
// it (§4.4), or NEVER (non-translating balls too). Each side is a quadratic: direction 0
// (SIDE1) solves A τ² + B τ + C₊ = 0, direction 1 (SIDE2) C₋, direction 2 both, with
// A = lx a_x + ly a_y, B = lx b_x + ly b_y, C± = l0 + lx c_x + ly c_y ± R‖l‖.
fn ball_linear_cushion_time(b: BallState, seg: LinearCushion, p: BallParams) -> real {
    if !ball_translating(b) {
        return NEVER;
    }
    return linear_cushion_time_on(trajectory(b, p), seg, p.r);
}

// ball_linear_cushion_time for a translating ball's path (computed once for all
// segments), radius the ball's.
fn linear_cushion_time_on(path: Path, seg: LinearCushion, radius: real) -> real {
    let a = seg.lx * path.a.x + seg.ly * path.a.y;
    let bb = seg.lx * path.b.x + seg.ly * path.b.y;
    let c0 = seg.l0 + seg.lx * path.c.x + seg.ly * path.c.y;
    let off = radius * sqrt(seg.lx * seg.lx + seg.ly * seg.ly);
    var best = NEVER;
    if seg.direction == 0u || seg.direction == 2u {
        best = min(best, side_time(path, seg, a, bb, c0 + off));
    }
    if seg.direction == 1u || seg.direction == 2u {
        best = min(best, side_time(path, seg, a, bb, c0 - off));
    }
    return best;
}

// τ until a translating ball's centre reaches distance r_c + R from the jaw's centre
// (§4.5; the whole circle, no arc restriction; from outside, or from inside where a kiss
// left it), or NEVER. See circle_crossing
// (query/ball_circle.wgsl) for the method.
fn ball_circular_cushion_time(b: BallState, seg: CircularCushion, p: BallParams) -> real {
    if !ball_translating(b) {
        return NEVER;
    }
    let path = trajectory(b, p);
    let center = real2(seg.center.x, seg.center.y);
    return circle_crossing(path, center, seg.radius + p.r);
}
