// A translating ball's horizontal trajectory polynomial p(τ) = a τ² + b τ + c, valid until
// its next transition (spec §4.1). WGSL twin of src/motion/trajectory.rs.

// A ball's trajectory polynomial and how long it holds: a = −½ μ g d̂ (half the
// acceleration), b = v_xy, c = r_xy; the horizon is slightly extended (horizon_margin),
// NEVER for a ball that does not translate (Rust: Path).
struct Path {
    a: real2,
    b: real2,
    c: real2,
    horizon: real,
}

// The path of a ball that does not translate, at c: a = b = 0, horizon NEVER (Rust:
// Path::still).
fn path_still(c: real2) -> Path {
    return Path(real2(0.0, 0.0), real2(0.0, 0.0), c, NEVER);
}

// A horizon h widened by a relative 1e-9 and an absolute 1e-12 s. A root past the ball's
// next transition never fires (the transition comes first and invalidates the entry), so
// searching a little past the horizon changes nothing, and it keeps a root within
// rounding of the transition time where pooltool has it.
fn horizon_margin(h: real) -> real {
    return h * (1.0 + 1e-9) + 1e-12;
}

// The trajectory polynomial of §4.1: sliding μ = μ_s, d̂ = unit(u_rel) (unit(v) if the
// slip is exactly 0); rolling μ = μ_r, d̂ = unit(v); otherwise a = b = 0.
fn trajectory(s: BallState, p: BallParams) -> Path {
    let c = real2(s.r.x, s.r.y);
    var mu: real;
    var dir: real3;
    var h: real;
    switch s.s {
        case STATE_SLIDING: {
            let u = xy3(rel_velocity(s.v, s.w, p.r));
            if norm3(u) == 0.0 {
                dir = unit3(xy3(s.v));
            } else {
                dir = unit3(u);
            }
            mu = p.u_s;
            h = slide_time(s, p);
        }
        case STATE_ROLLING: {
            mu = p.u_r;
            dir = unit3(xy3(s.v));
            h = roll_time(s, p);
        }
        default: {
            return path_still(c);
        }
    }
    let k = -0.5 * mu * p.g;
    return Path(real2(k * dir.x, k * dir.y), real2(s.v.x, s.v.y), c, horizon_margin(h));
}

// The path's position at τ, c + τ (b + τ a).
fn position_at(path: Path, tau: real) -> real2 {
    let a = path.a;
    let b = path.b;
    let c = path.c;
    return real2(c.x + tau * (b.x + tau * a.x), c.y + tau * (b.y + tau * a.y));
}
