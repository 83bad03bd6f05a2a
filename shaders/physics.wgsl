// The physics: what a ball does between two events, and what two balls do relative to
// each other. WGSL twin of src/physics.rs (same names, same order); `real` is f32 or f64
// (see real_f32.wgsl / real_f64.wgsl).
//
// Between events every ball that moves follows a quadratic path r(t) = c + b t + a t²
// until its next motion transition:
//   sliding:  a = −½ μs g û, û = u/|u|, u = (vx − R wy, vy + R wx); b = v; tmax = 2|u|/(7 μs g)
//   rolling:  a = −½ μr g v̂; b = v; tmax = |v|/(μr g)
//   stationary, spinning: a = b = 0, tmax = ∞ (NEVER here); pocketed: never collides.
// For a pair, C(t) = C + B t + A t² (ball 2 minus ball 1) is what the solver works on.

// Motion states, pooltool's codes (Rust: MotionState).
const STATE_STATIONARY: u32 = 0u;
const STATE_SPINNING: u32 = 1u;
const STATE_SLIDING: u32 = 2u;
const STATE_ROLLING: u32 = 3u;
const STATE_POCKETED: u32 = 4u;

// Path flag: the ball moves across the cloth on this path.
const PATH_MOVES: u32 = 1u;
// Path flag: the ball is pocketed and never collides.
const PATH_POCKETED: u32 = 2u;

// The physical parameters of one batch (Rust: Params; mu_sp is not needed here).
struct Params {
    radius: real,
    mu_s: real,
    mu_r: real,
    g: real,
}

// Dot product: the WGSL builtin `dot`.

// Euclidean length, sqrt(dot(a, a)) (not the `length` builtin).
fn norm(a: real2) -> real {
    return sqrt(dot(a, a));
}

// The 2-D cross product a.x b.y − a.y b.x: |a| times the signed distance of b from the
// line along a.
fn perp_dot(a: real2, b: real2) -> real {
    return a.x * b.y - a.y * b.x;
}

// The 1-norm |a.x| + |a.y|, an upper bound of norm without a square root.
fn norm1(a: real2) -> real {
    return abs(a.x) + abs(a.y);
}

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

// The centre difference of a pair, ball 2 minus ball 1: C(t) = C + B t + A t².
struct RelPath {
    a: real2,
    b: real2,
    c: real2,
}

// The relative path of ball 2 seen from ball 1 (Rust: RelPath::between).
fn rel_between(p1: BallPath, p2: BallPath) -> RelPath {
    return RelPath(p2.a - p1.a, p2.b - p1.b, p2.c - p1.c);
}

// C(t), evaluated from the vectors (Rust: RelPath::at).
fn rel_at(rel: RelPath, t: real) -> real2 {
    return rel.c + t * (rel.b + t * rel.a);
}

// C'(t) = B + 2 t A, the relative velocity (Rust: RelPath::velocity_at).
fn rel_velocity_at(rel: RelPath, t: real) -> real2 {
    return rel.b + (2.0 * t) * rel.a;
}

// The horizon of a pair: H = min(tmax1, tmax2) (NEVER when neither ball moves).
fn pair_horizon(p1: BallPath, p2: BallPath) -> real {
    return min(p1.tmax, p2.tmax);
}
