// When does a ball's path cross a fixed circle? The quartic of spec §4.5–4.6, shared by
// the circular cushions (jaws) and the pockets. WGSL twin of src/query/ball_circle.rs.

// The first τ in (0, horizon] at which the path crosses the circle of radius rho about
// center, or NEVER: where it starts outside (|p(0) − q|² ≥ ρ²), the first entry (|p(τ) − q|²
// goes from > ρ² to ≤ ρ²); where it starts inside, the first exit. This is the smallest
// positive root of pooltool's quartic, whose detection does not ask which way the path
// crosses, found by the exact bracketing root finders first_entry and first_exit
// (query/ball_ball.wgsl). The Rust twin's docs say how it differs from pooltool's root
// filter, and how a shot leaves a ball inside a pocket's circle (FUZZING.md, finding 32).
fn circle_crossing(path: Path, center: real2, rho: real) -> real {
    if path.horizon >= NEVER {
        return NEVER;
    }
    let rel = RelPath(path.a, path.b, path.c - center);
    let rho2 = rho * rho;
    let f0 = contact_fn(rel, rho2, 0.0, 0u).x;
    var t: real;
    if f0 < 0.0 {
        t = first_exit(rel, rho2, path.horizon);
    } else {
        t = first_entry(rel, rho2, path.horizon, false);
    }
    return select(NEVER, t, t >= 0.0);
}
