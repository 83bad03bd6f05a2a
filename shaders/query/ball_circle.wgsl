// When does a ball's path enter a fixed circle? The quartic of spec §4.5–4.6, shared by
// the circular cushions (jaws) and the pockets. WGSL twin of src/query/ball_circle.rs.

// The first τ in (0, horizon] at which the path enters the circle of radius rho about
// center (|p(τ) − q|² goes from > ρ² to ≤ ρ²), or NEVER: the smallest positive root of
// pooltool's quartic for a ball that starts outside the circle, found by the exact
// bracketing root finder first_entry (query/ball_ball.wgsl). The Rust twin's docs say how
// it differs from pooltool's root filter.
fn circle_entry(path: Path, center: real2, rho: real) -> real {
    if path.horizon >= NEVER {
        return NEVER;
    }
    let rel = RelPath(path.a, path.b, path.c - center);
    let t = first_entry(rel, rho * rho, path.horizon, false);
    return select(NEVER, t, t >= 0.0);
}
