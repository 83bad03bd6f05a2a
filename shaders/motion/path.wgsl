// One ball's path between two events. WGSL twin of src/motion/path.rs (same names, same
// order); `real` is f32 or f64 (see real_f32.wgsl / real_f64.wgsl).
//
// Between events every ball that moves follows a quadratic path r(t) = c + b t + a t²
// until its next motion transition:
//   sliding:  a = −½ μs g û, û = u/|u|, u = (vx − R wy, vy + R wx); b = v; tmax = 2|u|/(7 μs g)
//   rolling:  a = −½ μr g v̂; b = v; tmax = |v|/(μr g)
//   stationary, spinning: a = b = 0, tmax = ∞ (NEVER here); pocketed: never collides.

// Path flag: the ball moves across the cloth on this path.
const PATH_MOVES: u32 = 1u;
// Path flag: the ball is pocketed and never collides.
const PATH_POCKETED: u32 = 2u;

// One ball's centre on its current motion, r(t) = c + b t + a t², valid for t in [0, tmax].
struct BallPath {
    a: real2,
    b: real2,
    c: real2,
    tmax: real,
    flags: u32,
}

// The unit vector of v, or zero for the zero vector.
fn unit_or_zero(v: real2) -> real2 {
    let len = norm(v);
    if len > 0.0 {
        return (1.0 / len) * v;
    }
    return real2(0.0, 0.0);
}

// A ball's path coefficients and motion time. `pos`, `vel` table-local; `w` the angular
// velocity (wx, wy, wz).
fn ball_path(state: u32, pos: real2, vel: real2, w: vec3<real>, params: Params) -> BallPath {
    let c = pos;
    let v = vel;
    if state == STATE_SLIDING {
        // contact-point velocity u = v + R ẑ × ω
        let u = real2(vel.x - params.radius * w.y, vel.y + params.radius * w.x);
        let a = (-0.5 * params.mu_s * params.g) * unit_or_zero(u);
        let tmax = 2.0 * norm(u) / (7.0 * params.mu_s * params.g);
        return BallPath(a, v, c, tmax, PATH_MOVES);
    }
    if state == STATE_ROLLING {
        let a = (-0.5 * params.mu_r * params.g) * unit_or_zero(v);
        let tmax = norm(v) / (params.mu_r * params.g);
        return BallPath(a, v, c, tmax, PATH_MOVES);
    }
    let zero = real2(0.0, 0.0);
    if state == STATE_POCKETED {
        return BallPath(zero, zero, c, NEVER, PATH_POCKETED);
    }
    return BallPath(zero, zero, c, NEVER, 0u);
}

// The horizon of a pair: H = min(tmax1, tmax2) (NEVER when neither ball moves).
// The horizon of a pair: H = min(tmax1, tmax2) (NEVER when neither ball moves).
fn pair_horizon(p1: BallPath, p2: BallPath) -> real {
    return min(p1.tmax, p2.tmax);
}
