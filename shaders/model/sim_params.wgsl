// Parameters of the simulation, pooltool 0.6.0's (spec §1). WGSL twin of
// src/model/sim_params.rs.

// pooltool's constants.EPS, 100 machine epsilons (spec §0), is SIM_EPS of the precision
// prelude (naga does not fold f64 constant expressions).
// pooltool's constants.MIN_DIST: the spacer every make_kiss leaves (spec §1.4, Q1).
const MIN_DIST: real = 1e-6;

// A ball's physical constants (spec §1.1), in SI units (Rust: BallParams).
struct BallParams {
    m: real,
    r: real,
    u_s: real,
    u_r: real,
    u_sp: real,
    u_b: real,
    e_b: real,
    e_c: real,
    f_c: real,
    g: real,
}

// The spin angular deceleration α_sp = 5 μ_sp g / (2R) in rad/s² (spec §1.1).
fn spin_decel(p: BallParams) -> real {
    return 5.0 * p.u_sp * p.g / (2.0 * p.r);
}

// The default resolver's constants (spec §1.3, §1.4, §5.2, §5.4) (Rust: ResolverParams).
struct ResolverParams {
    alciatore_a: real,
    alciatore_b: real,
    alciatore_c: real,
    omega_ratio: real,
    beta_t: real,
    beta_n: real,
    k_n: real,
    spacer: real,
}

// Stronge's η² = (β_t/β_n)/omega_ratio² (spec §1.4).
fn eta2(rp: ResolverParams) -> real {
    return (rp.beta_t / rp.beta_n) / (rp.omega_ratio * rp.omega_ratio);
}

// Everything the event loop needs besides the table and the balls (Rust: SimParams; the
// cue's part stays on the host).
struct SimParams {
    ball: BallParams,
    resolver: ResolverParams,
}

// The cue's parameters for the strike (spec §5.6) (Rust: CueParams): its mass M and end
// mass m_e in kg, instantaneous_point's english and squirt throttles.
struct CueParams {
    mass: real,
    end_mass: real,
    english_throttle: real,
    squirt_throttle: real,
}
