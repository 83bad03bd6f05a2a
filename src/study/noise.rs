//! The cue noise: sample `i`'s strike, drawn from a PCG generator seeded by `(seed, i)`
//! only, so results do not depend on the thread count, the chunking or how many samples
//! are drawn (the first `n` samples of a larger study are the study of `n`).

use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rand_pcg::Pcg64Mcg;

use rand::RngExt;

use super::config::{Noise, PhysicsSpread, StudyConfig, ball_field};
use crate::model::sim_params::SimParams;
use crate::resolve::stick_ball::CueStrike;

/// Told apart from the cue noise's: sample `i`'s physics comes from a generator of its own,
/// so that a study's strikes are the same with or without a physics spread.
const PHYSICS_STREAM: u64 = 0x7068_7973_6963_7321;

/// The noisy strike of sample `i`: the intended strike plus `sigma` times five standard
/// normals (drawn in the order `v0, phi, theta, a, b`), with the offsets' σ (metres)
/// divided by R, then clamped into the physical range ([`clamped`]).
pub fn noisy_strike(config: &StudyConfig, sigma: &Noise, seed: u64, i: u64) -> CueStrike {
    noisy_strike_of(config.shot, config.params.ball.r, sigma, seed, i)
}

/// [`noisy_strike`] of the intended strike `s` on balls of radius `r`: sample `i` of any
/// intended strike draws the same five normals for the same `(seed, i)`, so that strikes
/// compared sample by sample meet the same noise (common random numbers: the planner's).
pub fn noisy_strike_of(s: CueStrike, r: f64, sigma: &Noise, seed: u64, i: u64) -> CueStrike {
    let mut rng = Pcg64Mcg::seed_from_u64(mix(seed, i));
    let mut z = [0.0f64; 5];
    for v in &mut z {
        *v = StandardNormal.sample(&mut rng);
    }
    clamped(CueStrike {
        v0: s.v0 + sigma.v0 * z[0],
        phi: s.phi + sigma.phi * z[1],
        theta: s.theta + sigma.theta * z[2],
        a: s.a + sigma.a / r * z[3],
        b: s.b + sigma.b / r * z[4],
    })
}

/// Sample `i`'s physics: `base` with each parameter that `spread` varies scaled by
/// `1 + lo + (hi − lo)·u`, `u` uniform in [0, 1) from a PCG generator seeded by
/// `(seed, i)` on a stream of its own (ten draws, one per parameter in `BALL_KEYS` order,
/// whichever vary). `base` itself where nothing varies.
pub fn sample_physics(base: &SimParams, spread: &PhysicsSpread, seed: u64, i: u64) -> SimParams {
    if spread.is_empty() {
        return *base;
    }
    let mut rng = Pcg64Mcg::seed_from_u64(mix(seed ^ PHYSICS_STREAM, i));
    let mut p = *base;
    for (k, range) in spread.ranges.iter().enumerate() {
        let u: f64 = rng.random();
        if let Some((lo, hi)) = range {
            *ball_field(&mut p, k) *= 1.0 + lo + (hi - lo) * u;
        }
    }
    p
}

/// The strike with V0 ≥ 0, θ in [0°, 90°] and the tip on the ball (a² + b² ≤ 1, scaled
/// back onto the rim when noise pushed it off).
pub fn clamped(s: CueStrike) -> CueStrike {
    let mut s = s;
    s.v0 = s.v0.max(0.0);
    s.theta = s.theta.clamp(0.0, 90.0);
    let rho = (s.a * s.a + s.b * s.b).sqrt();
    if rho > 1.0 {
        s.a /= rho;
        s.b /= rho;
        // the division can leave a² + b² one ulp above 1
        while s.a * s.a + s.b * s.b > 1.0 {
            s.a *= 1.0 - f64::EPSILON;
            s.b *= 1.0 - f64::EPSILON;
        }
    }
    s
}

/// SplitMix64's finaliser.
fn splitmix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// One 64-bit seed from a seed and a counter (the study's seed and the sample index;
/// self-play's and the learning environments' seeds of games, tables and episodes).
pub fn mix(seed: u64, i: u64) -> u64 {
    splitmix(splitmix(seed).wrapping_add(i.wrapping_mul(0x9e37_79b9_7f4a_7c15)))
}
