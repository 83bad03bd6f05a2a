// Motion between events: pooltool's closed forms (spec §2). WGSL twin of
// src/motion/evolve.rs (same functions, same order; the sources are named there).
//
// τ is the time since the state given. z and v_z never change. The label is never changed
// here: only transition events change labels (§2.5), so evolve chains the states
// internally only to absorb rounding at a transition time.

// The transitions a ball's motion can end in (§2.6) (Rust: TransitionKind).
const TRANSITION_SLIDING_ROLLING: u32 = 0u;
const TRANSITION_ROLLING_SPINNING: u32 = 1u;
const TRANSITION_ROLLING_STATIONARY: u32 = 2u;
const TRANSITION_SPINNING_STATIONARY: u32 = 3u;

// The z-spin after τ (§2): it decays at α_sp towards 0 and never passes it; unchanged for
// τ = 0 or |ω_z| < EPS.
fn decay_spin_z(wz: real, tau: real, p: BallParams) -> real {
    if tau == 0.0 || abs(wz) < SIM_EPS {
        return wz;
    }
    let alpha = spin_decel(p);
    let sign = select(real(-1.0), real(1.0), wz > 0.0);
    return wz - sign * alpha * min(tau, abs(wz) / alpha);
}

// τ_slide = 2|u_rel|/(7 μ_s g) (§2.1): when the cloth slip of a sliding ball vanishes.
fn slide_time(b: BallState, p: BallParams) -> real {
    let u = rel_velocity(b.v, b.w, p.r);
    return 2.0 * norm3(u) / (7.0 * p.u_s * p.g);
}

// τ_roll = |v|/(μ_r g) (§2.2): when a rolling ball stops.
fn roll_time(b: BallState, p: BallParams) -> real {
    return norm3(b.v) / (p.u_r * p.g);
}

// τ_spin = |ω_z|/α_sp = 2R|ω_z|/(5 μ_sp g) (§2.3): when a spinning ball stops spinning.
fn spin_time(b: BallState, p: BallParams) -> real {
    return abs(b.w.z) * 2.0 * p.r / (5.0 * p.u_sp * p.g);
}

// A sliding ball after τ (§2.1): constant deceleration μ_s g against the slip direction
// û, spin changed by the friction torque, z-spin decaying. Valid for τ ≤ τ_slide.
fn evolve_slide(b: BallState, tau: real, p: BallParams) -> BallState {
    let u_hat = unit3(xy3(rel_velocity(b.v, b.w, p.r)));
    let k = p.u_s * p.g;
    let r = b.r + tau * b.v - (0.5 * k * tau * tau) * u_hat;
    let v = b.v - (k * tau) * u_hat;
    // û × ẑ = (û_y, −û_x, 0)
    let dw = (5.0 * k * tau / (2.0 * p.r)) * real3(u_hat.y, -u_hat.x, 0.0);
    let w = real3(b.w.x - dw.x, b.w.y - dw.y, decay_spin_z(b.w.z, tau, p));
    return BallState(real3(r.x, r.y, b.r.z), real3(v.x, v.y, b.v.z), w, b.s, b.t);
}

// A rolling ball after τ (§2.2): deceleration μ_r g along v̂, ω_xy recomputed from v
// (Q13), z-spin decaying. τ = 0 returns the state untouched. Valid for τ ≤ τ_roll.
fn evolve_roll(b: BallState, tau: real, p: BallParams) -> BallState {
    if tau == 0.0 {
        return b;
    }
    let v_hat = unit3(xy3(b.v));
    let k = p.u_r * p.g;
    let r = b.r + tau * b.v - (0.5 * k * tau * tau) * v_hat;
    let v = b.v - (k * tau) * v_hat;
    let w = real3(-v.y / p.r, v.x / p.r, decay_spin_z(b.w.z, tau, p));
    return BallState(real3(r.x, r.y, b.r.z), real3(v.x, v.y, b.v.z), w, b.s, b.t);
}

// A spinning ball after τ (§2.3): only ω_z changes (decays).
fn evolve_spin(b: BallState, tau: real, p: BallParams) -> BallState {
    let w = real3(b.w.x, b.w.y, decay_spin_z(b.w.z, tau, p));
    return BallState(b.r, b.v, w, b.s, b.t);
}

// Rolling, then spinning, then at rest, for τ (the tail of §2.5's chain).
fn evolve_from_roll(b: BallState, tau: real, p: BallParams) -> BallState {
    let t_roll = roll_time(b, p);
    if tau < t_roll {
        return evolve_roll(b, tau, p);
    }
    let rolled = evolve_roll(b, t_roll, p);
    return evolve_from_spin(rolled, tau - t_roll, p);
}

// Spinning, then at rest, for τ.
fn evolve_from_spin(b: BallState, tau: real, p: BallParams) -> BallState {
    let t_spin = spin_time(b, p);
    return evolve_spin(b, min(tau, t_spin), p);
}

// evolve_ball_motion (§2.5): the state after τ, chaining slide → roll → spin → rest
// through the states reached (each duration recomputed from the intermediate state). The
// label of `b` is kept. Stationary and pocketed balls do not change.
fn evolve(b: BallState, tau: real, p: BallParams) -> BallState {
    switch b.s {
        case STATE_SLIDING: {
            let t_slide = slide_time(b, p);
            if tau < t_slide {
                return evolve_slide(b, tau, p);
            }
            let slid = evolve_slide(b, t_slide, p);
            return evolve_from_roll(slid, tau - t_slide, p);
        }
        case STATE_ROLLING: {
            return evolve_from_roll(b, tau, p);
        }
        case STATE_SPINNING: {
            return evolve_from_spin(b, tau, p);
        }
        default: {
            return b;
        }
    }
}

// The ball's next transition from its current state (§2.6): τ in .x, the TRANSITION_*
// kind in .y (as a real); τ = NEVER for stationary and pocketed balls (Rust: None). A
// rolling ball spins next only if τ_spin > τ_roll (strictly).
fn next_transition(b: BallState, p: BallParams) -> real2 {
    switch b.s {
        case STATE_SLIDING: {
            return real2(slide_time(b, p), real(TRANSITION_SLIDING_ROLLING));
        }
        case STATE_ROLLING: {
            let t_roll = roll_time(b, p);
            let t_spin = spin_time(b, p);
            let kind = select(TRANSITION_ROLLING_STATIONARY, TRANSITION_ROLLING_SPINNING, t_spin > t_roll);
            return real2(t_roll, real(kind));
        }
        case STATE_SPINNING: {
            return real2(spin_time(b, p), real(TRANSITION_SPINNING_STATIONARY));
        }
        default: {
            return real2(NEVER, real(TRANSITION_SLIDING_ROLLING));
        }
    }
}
