// Transition resolution (spec §2.7 / §5.7; `physics/resolve/transition/__init__.py:
// CanonicalTransition`). WGSL twin of src/resolve/transition.rs.
//
// - sliding → rolling: only the label changes;
// - rolling → spinning: v = 0 and ω_x = ω_y = 0, ω_z kept;
// - rolling → stationary, spinning → stationary: v = ω = 0.
//
// Deviation (Q12): pooltool asserts that the zeroed components are already below 1e-12;
// here they are zeroed whatever their size, so a rounding excess never stops a table.
//
// Needs (before it): the precision prelude, model/ball.wgsl, model/ball_state.wgsl,
// motion/evolve.wgsl (the TRANSITION_* codes).

// The ball after transition `kind` (a TRANSITION_* code of motion/evolve.wgsl; module
// docs). Position and reference time are kept; the caller stamps the time. (WGSL's
// switch needs a default: the two → stationary kinds, and any other code, take it.)
fn resolve_transition(b: BallState, kind: u32) -> BallState {
    switch kind {
        case TRANSITION_SLIDING_ROLLING: {
            return BallState(b.r, b.v, b.w, STATE_ROLLING, b.t);
        }
        case TRANSITION_ROLLING_SPINNING: {
            return BallState(b.r, real3(0.0, 0.0, 0.0), real3(0.0, 0.0, b.w.z), STATE_SPINNING, b.t);
        }
        case TRANSITION_ROLLING_STATIONARY, TRANSITION_SPINNING_STATIONARY, default: {
            return BallState(b.r, real3(0.0, 0.0, 0.0), real3(0.0, 0.0, 0.0), STATE_STATIONARY, b.t);
        }
    }
}
