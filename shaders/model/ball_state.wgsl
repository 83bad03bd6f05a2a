// One ball's full state in the event loop (spec §0). WGSL twin of
// src/model/ball_state.rs.

// A ball's state: position r, velocity v, angular velocity w, the motion label s
// (STATE_* of model/ball.wgsl) and the reference time t of the last event that changed
// the ball (Rust: BallState).
struct BallState {
    r: real3,
    v: real3,
    w: real3,
    s: u32,
    t: real,
}

// Whether the ball moves across the cloth (sliding or rolling) (Rust:
// BallState::translating).
fn ball_translating(b: BallState) -> bool {
    return b.s == STATE_SLIDING || b.s == STATE_ROLLING;
}

// The cloth slip velocity u = v + ω × (−R ẑ) = (v_x − R ω_y, v_y + R ω_x, v_z)
// (pooltool's ptmath.rel_velocity, spec §0).
fn rel_velocity(v: real3, w: real3, radius: real) -> real3 {
    return real3(v.x - radius * w.y, v.y + radius * w.x, v.z);
}

// The kinetic energy ½ m|v|² + ½ (2/5 m R²)|ω|² (pooltool's ptmath.get_ball_energy,
// spec §0), used for the stick check and the tie rule (§3).
fn ball_energy(b: BallState, p: BallParams) -> real {
    let inertia = 0.4 * p.m * p.r * p.r;
    return 0.5 * p.m * dot3(b.v, b.v) + 0.5 * inertia * dot3(b.w, b.w);
}
