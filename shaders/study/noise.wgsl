// The cue noise: sample i's strike from Philox keyed by the seed at counter i. WGSL twin
// of src/study/noise.rs (same functions, same order; the module documentation there has
// the layout of the draws). Twinned: draw_block, cue_normals, noisy_strike_of, clamped;
// the Rust side's noisy_strike (a study file's strike), drawn_strike, drawn, max_normal
// and draws_are_strikes (the host's description of a study's draws and its check),
// sample_physics (a sample's physics spread) and mix (self-play's and the environments'
// seeds) are the host's. CueStrike is resolve/stick_ball.wgsl's. The event loop's
// expand_drawn calls noisy_strike_of for each table of a study's chunk.

// Philox's stream word for the cue noise.
const CUE_STREAM: u32 = 0u;
// The most rescalings clamped makes to bring a tip pushed off the ball back inside (one
// or two are ever needed: the division leaves a² + b² a few ulps from 1).
const RIM_STEPS: u32 = 8u;
// 1 − 2⁻⁵² (f64::EPSILON is 2⁻⁵²): clamped's rescaling factor.
const RIM_SHRINK: real = 0.9999999999999998;

// The cue noise's five σ (V0 m/s; phi, theta degrees; a, b metres): the Rust Noise
// without its physics spread.
struct Noise {
    v0: real,
    phi: real,
    theta: real,
    a: real,
    b: real,
}

// Philox's four words for sample i's block on stream under seed (both as low, high words).
fn draw_block(seed: vec2<u32>, i: vec2<u32>, stream: u32, block: u32) -> vec4<u32> {
    return philox4x32(vec4<u32>(i.x, i.y, block, stream), seed);
}

// Sample i's five standard normals of the cue noise, in the order v0, phi, theta, a, b.
fn cue_normals(seed: vec2<u32>, i: vec2<u32>) -> array<real, 5> {
    let w0 = draw_block(seed, i, CUE_STREAM, 0u);
    let w1 = draw_block(seed, i, CUE_STREAM, 1u);
    let w2 = draw_block(seed, i, CUE_STREAM, 2u);
    return array<real, 5>(
        normal_quantile(open_unit(w0.x, w0.y)),
        normal_quantile(open_unit(w0.z, w0.w)),
        normal_quantile(open_unit(w1.x, w1.y)),
        normal_quantile(open_unit(w1.z, w1.w)),
        normal_quantile(open_unit(w2.x, w2.y)),
    );
}

// The noisy strike of sample i of the intended strike s on balls of radius r: s plus
// sigma times the five normals (the offsets' σ divided by r), then clamped.
fn noisy_strike_of(s: CueStrike, r: real, sigma: Noise, seed: vec2<u32>, i: vec2<u32>) -> CueStrike {
    let z = cue_normals(seed, i);
    return clamped(CueStrike(
        s.v0 + sigma.v0 * z[0],
        s.phi + sigma.phi * z[1],
        s.theta + sigma.theta * z[2],
        s.a + sigma.a / r * z[3],
        s.b + sigma.b / r * z[4],
    ));
}

// The strike with V0 ≥ 0, θ in [0°, 90°] and the tip on the ball (a² + b² ≤ 1, scaled
// back onto the rim when noise pushed it off). For finite strikes.
fn clamped(strike: CueStrike) -> CueStrike {
    var s = strike;
    s.v0 = select(s.v0, 0.0, s.v0 < 0.0);
    s.theta = select(select(s.theta, 90.0, s.theta > 90.0), 0.0, s.theta < 0.0);
    let rho = sqrt(s.a * s.a + s.b * s.b);
    if rho > 1.0 {
        s.a = s.a / rho;
        s.b = s.b / rho;
        // the division can leave a² + b² an ulp or two above 1
        for (var j = 0u; j < RIM_STEPS; j++) {
            if s.a * s.a + s.b * s.b <= 1.0 {
                break;
            }
            s.a = s.a * RIM_SHRINK;
            s.b = s.b * RIM_SHRINK;
        }
    }
    return s;
}
