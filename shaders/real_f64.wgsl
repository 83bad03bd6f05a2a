// Precision prelude: f64 (needs the SHADER_F64 feature). Prepended to the twins by the
// host (src/gpu/shader.rs). Only arithmetic and sqrt are used on f64: transcendental
// builtins compile for f64 on Vulkan but return garbage.
alias real = f64;
alias real2 = vec2<f64>;
alias real3 = vec3<f64>;

// Rust twin: f64::EPSILON
const EPS: real = 2.220446049250313e-16;
// Rust twin: solver::ROOT_RTOL (4 EPS), the relative step size at which a refinement
// has converged.
const ROOT_RTOL: real = 8.881784197001252e-16;
// Rust twin: solver::APPROACH_BAND (64 EPS): a derivative of f at a touching contact
// counts as zero within this fraction of the magnitudes that formed it.
const APPROACH_BAND: real = 1.4210854715202004e-14;
// Rust twin: solver::CONTACT_TOL
const CONTACT_TOL: real = 1e-12;
// Rust twin: solver::PRUNE_SLACK
const PRUNE_SLACK: real = 1e-9;
// Rust twin: solver::ROOT_ATOL
const ROOT_ATOL: real = 1e-300;
// Rust twin: sim_params::EPS, pooltool's constants.EPS: 100 machine epsilons of `real`.
const SIM_EPS: real = 2.220446049250313e-14;
// Rust twin: bounds::BOX_SLACK: the slack of every box test, in m.
const BOX_SLACK: real = 1e-9;
// WGSL has no infinity: a ball that never stops has this motion time (Rust: f64::INFINITY).
const NEVER: real = 1.0e300;

// The transcendental functions the simulator's resolutions use (Rust: std's f64 ones):
// the arithmetic polyfills of model/fmath.wgsl, as f64 builtins return garbage.
fn real_exp(x: real) -> real {
    return exp_poly(x);
}
fn real_sin(x: real) -> real {
    return sin_poly(x);
}
fn real_cos(x: real) -> real {
    return cos_poly(x);
}
fn real_acos(x: real) -> real {
    return acos_poly(x);
}
fn real_atan2(y: real, x: real) -> real {
    return atan2_poly(y, x);
}
