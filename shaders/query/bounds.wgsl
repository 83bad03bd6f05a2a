// Cheap bounds that rule a query out before it is solved: the axis-aligned box a ball's
// centre stays in while its current motion lasts, and tests of that box against another
// box, a circle and a segment's extent. WGSL twin of src/query/bounds.rs.
//
// Each test is conservative: it says "cannot happen" only when the exact solver, run on
// the same path, could not find the event within the path's horizon either (the slack
// BOX_SLACK of the precision prelude is far above the rounding of the polynomials, far
// below any real gap). The simulator uses them to skip solves whose answer would be
// never, so its event sequences do not change.

// The axis-aligned box [lo, hi] that holds a path's centre over [0, horizon] (Rust:
// PathBox).
struct PathBox {
    lo: real2,
    hi: real2,
}

// (min, max) of c + b τ + a τ² over τ ∈ [0, h] (h finite): the ends and, if it lies
// inside, the vertex τ = −b/(2a).
fn axis_range(a: real, b: real, c: real, h: real) -> real2 {
    let end = c + h * (b + h * a);
    var lo = min(c, end);
    var hi = max(c, end);
    if a != 0.0 {
        let tv = -b / (2.0 * a);
        if tv > 0.0 && tv < h {
            let v = c + tv * (b + tv * a);
            lo = min(lo, v);
            hi = max(hi, v);
        }
    }
    return real2(lo, hi);
}

// The box of `path` over its horizon; a single point for a path that does not move
// (horizon NEVER, a = b = 0).
fn path_box(path: Path) -> PathBox {
    if path.horizon >= NEVER {
        return PathBox(path.c, path.c);
    }
    let h = path.horizon;
    let x = axis_range(path.a.x, path.b.x, path.c.x, h);
    let y = axis_range(path.a.y, path.b.y, path.c.y, h);
    return PathBox(real2(x.x, y.x), real2(x.y, y.y));
}

// Whether the boxes are farther apart than `dist` along x or along y (then no two points
// of them are within `dist`).
fn boxes_apart(p: PathBox, q: PathBox, dist: real) -> bool {
    let d = dist + BOX_SLACK;
    return p.lo.x - q.hi.x > d || q.lo.x - p.hi.x > d || p.lo.y - q.hi.y > d || q.lo.y - p.hi.y > d;
}

// Whether every point of the box is farther than `rho` from `center`.
fn box_outside_circle(p: PathBox, center: real2, rho: real) -> bool {
    let dx = max(max(p.lo.x - center.x, center.x - p.hi.x), 0.0);
    let dy = max(max(p.lo.y - center.y, center.y - p.hi.y), 0.0);
    let d = rho + BOX_SLACK;
    return dx * dx + dy * dy > d * d;
}

// Whether no point of the box projects into the segment's extent: the projection
// s = (q − p1)·(p2 − p1)/|p2 − p1|², linear in q, is below 0 or above 1 (by more than the
// slack) at every corner.
fn box_outside_extent(p: PathBox, seg: LinearCushion) -> bool {
    let d = real2(seg.p2.x - seg.p1.x, seg.p2.y - seg.p1.y);
    let len2 = d.x * d.x + d.y * d.y;
    // the corners that minimise and maximise (q − p1)·d
    let x_min = select(p.hi.x, p.lo.x, d.x >= 0.0);
    let x_max = select(p.lo.x, p.hi.x, d.x >= 0.0);
    let y_min = select(p.hi.y, p.lo.y, d.y >= 0.0);
    let y_max = select(p.lo.y, p.hi.y, d.y >= 0.0);
    let proj_max = (x_max - seg.p1.x) * d.x + (y_max - seg.p1.y) * d.y;
    let proj_min = (x_min - seg.p1.x) * d.x + (y_min - seg.p1.y) * d.y;
    let slack = BOX_SLACK * sqrt(len2);
    return proj_max < -slack || proj_min > len2 + slack;
}
