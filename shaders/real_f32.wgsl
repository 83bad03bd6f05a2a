// Precision prelude: f32. Prepended to the twins by the host (src/gpu/shader.rs). The f64
// prelude, real_f64.wgsl, defines the same names.
alias real = f32;
alias real2 = vec2<f32>;
alias real3 = vec3<f32>;

// Rust twin: f64::EPSILON
const EPS: real = 1.1920929e-7;
// Rust twin: solver::ROOT_RTOL (4 EPS), the relative step size at which a refinement
// has converged.
const ROOT_RTOL: real = 4.76837158e-7;
// Rust twin: solver::APPROACH_BAND (64 EPS): a derivative of f at a touching contact
// counts as zero within this fraction of the magnitudes that formed it.
const APPROACH_BAND: real = 7.62939453e-6;
// Rust twin: solver::CONTACT_TOL (1e-12 m there). An f32 coordinate of a table-local
// position is rounded to 6e-8 m, so touching is decided to a micrometre here.
const CONTACT_TOL: real = 1e-6;
// Rust twin: solver::PRUNE_SLACK (1e-9 there), far above f32 rounding of the projections.
const PRUNE_SLACK: real = 1e-5;
// Rust twin: solver::ROOT_ATOL
const ROOT_ATOL: real = 1e-30;
// Rust twin: sim_params::EPS, pooltool's constants.EPS: 100 machine epsilons of `real`.
const SIM_EPS: real = 1.1920929e-5;
// Rust twin: bounds::BOX_SLACK (1e-9 there), far above f32 rounding of a table-local position: the slack of every box test, in m.
const BOX_SLACK: real = 1e-5;
// WGSL has no infinity: a ball that never stops has this motion time (Rust: f64::INFINITY).
const NEVER: real = 3.0e38;

// The transcendental functions the simulator's resolutions use (Rust: std's f64 ones):
// WGSL's f32 builtins, which are safe.
fn real_exp(x: real) -> real {
    return exp(x);
}
fn real_sin(x: real) -> real {
    return sin(x);
}
fn real_cos(x: real) -> real {
    return cos(x);
}
fn real_acos(x: real) -> real {
    return acos(x);
}
fn real_atan2(y: real, x: real) -> real {
    return atan2(y, x);
}
