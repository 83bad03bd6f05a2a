// The cue strike, pooltool's instantaneous_point model with squirt (spec §5.6). WGSL twin
// of src/resolve/stick_ball.rs (same functions, same order; the module documentation
// there has the model and its sources). The sines, cosines and the arctangent are
// real_sin, real_cos, real_atan2 (in f64 model/fmath.wgsl's, the Rust twin's bit for bit);
// π/2 is fmath's PIO2_HI (std::f64::consts::FRAC_PI_2 of the Rust twin).

// π/180 rounded, f64::to_radians's factor (0x3F91DF46_A2529D39).
const DEG_TO_RAD: real = 0.017453292519943295;

// A cue strike: pooltool's Cue.set_state(V0, phi, theta, a, b) arguments (V0 m/s; phi,
// theta degrees; a, b fractions of R).
struct CueStrike {
    v0: real,
    phi: real,
    theta: real,
    a: real,
    b: real,
}

// The squirt angle α = −throttle·atan2(2.5 a √(1−a²), 1 + m/m_e + 2.5(1−a²)).
fn squirt_angle(a: real, p: BallParams, cue: CueParams) -> real {
    let ratio = p.m / cue.end_mass;
    let num = 2.5 * a * sqrt(1.0 - a * a);
    let den = 1.0 + ratio + 2.5 * (1.0 - a * a);
    return -cue.squirt_throttle * real_atan2(num, den);
}

// Speed and ball-frame spin of the strike (§5.6 steps 1–3): (v, ω_B).
struct StrikeFrame {
    v: real,
    w: real3,
}

fn strike_ball_frame(s: CueStrike, p: BallParams, cue: CueParams) -> StrikeFrame {
    let theta = s.theta * DEG_TO_RAD;
    let st = real_sin(theta);
    let ct = real_cos(theta);
    // clamped: for a tip on the ball's rim (a² + b² = 1) the difference can round below 0
    let c_cue = sqrt(max(1.0 - s.a * s.a - s.b * s.b, 0.0));
    let a_b = s.a;
    let c_b = ct * c_cue - st * s.b;
    let b_b = st * c_cue + ct * s.b;
    let qa = p.r * a_b;
    let qc = p.r * c_b;
    let qb = p.r * b_b;
    let i_m = 0.4 * p.r * p.r;
    let qbc = qb * ct;
    let qcs = qc * st;
    let t = qa * qa + qbc * qbc + qcs * qcs - 2.0 * qb * qc * ct * st;
    let v = 2.0 * s.v0 / (1.0 + p.m / cue.mass + t / i_m);
    let w = (v / i_m) * real3(-qc * st + qb * ct, qa * st, -qa * ct);
    return StrikeFrame(v, w);
}

// The cue ball right after the strike (§5.6): position kept, labelled sliding.
fn cue_strike(ball: BallState, s: CueStrike, p: BallParams, cue: CueParams) -> BallState {
    let f = strike_ball_frame(s, p, cue);
    let theta = s.theta * DEG_TO_RAD;
    let rot = s.phi * DEG_TO_RAD + PIO2_HI;
    let v_b = real3(0.0, -f.v * real_cos(theta), 0.0);
    let v_t = rotate_z(rotate_z(v_b, rot), squirt_angle(s.a, p, cue));
    let w_t = cue.english_throttle * rotate_z(f.w, rot);
    return BallState(ball.r, v_t, w_t, STATE_SLIDING, ball.t);
}
