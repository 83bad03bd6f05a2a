//! The cue noise: sample `i`'s strike, drawn from the counter-based generator Philox
//! ([`super::philox`]) keyed by the seed at counter `i`, so results do not depend on the
//! thread count, the chunking, the backend or how many samples are drawn (the first `n`
//! samples of a larger study are the study of `n`). The twin of
//! `shaders/study/noise.wgsl`: the GPU draws a sample's strike from the same bits.
//!
//! # The draws
//! Philox's counter is `(i mod 2³², i div 2³², block, stream)` and its key the seed's low
//! and high words. The cue noise is stream 0: blocks 0, 1 and 2 give six uniforms
//! ([`open_unit`] of words 0–1 and 2–3), the first five turned into standard normals by
//! the normal quantile ([`normal_quantile`], exact arithmetic on both twins) in the order
//! `v0, phi, theta, a, b`. A sample's physics spread is stream 1 (blocks 0–4, ten
//! uniforms, one per parameter), so a study's strikes are the same with or without one.
//!
//! # On the device
//! Without a physics spread a study's strikes are a rule ([`drawn`]: the intended strike,
//! σ, the seed, the first index), which the engine hands the GPU as one header
//! ([`crate::simulate::DrawnStrikes`]); the event loop's `expand_drawn` then draws and
//! plays each sample's strike itself. [`draws_are_strikes`] makes sure first that no draw
//! can be a strike the simulator refuses, since the device checks none.

use super::config::{Noise, PhysicsSpread, StudyConfig, ball_field};
use super::philox::{open_unit, philox4x32};
use crate::model::fmath::normal_quantile;
use crate::model::sim_params::SimParams;
use crate::resolve::stick_ball::{CueStrike, MAX_PHI_DEGREES};
use crate::simulate::DrawnStrikes;

/// Philox's stream word for the cue noise.
const CUE_STREAM: u32 = 0;
/// Philox's stream word for a sample's physics: draws of their own, so that a study's
/// strikes are the same with or without a physics spread.
const PHYSICS_STREAM: u32 = 1;
/// The most rescalings [`clamped`] makes to bring a tip pushed off the ball back inside
/// (one or two are ever needed: the division leaves a² + b² a few ulps from 1).
const RIM_STEPS: u32 = 8;
/// 1 − 2⁻⁵²: [`clamped`]'s rescaling factor.
const RIM_SHRINK: f64 = 1.0 - f64::EPSILON;

/// Philox's four words for sample `i`'s `block` on `stream` under `seed`.
fn draw_block(seed: u64, i: u64, stream: u32, block: u32) -> [u32; 4] {
    philox4x32(
        [i as u32, (i >> 32) as u32, block, stream],
        [seed as u32, (seed >> 32) as u32],
    )
}

/// Sample `i`'s five standard normals of the cue noise, in the order `v0, phi, theta, a, b`.
pub fn cue_normals(seed: u64, i: u64) -> [f64; 5] {
    let w0 = draw_block(seed, i, CUE_STREAM, 0);
    let w1 = draw_block(seed, i, CUE_STREAM, 1);
    let w2 = draw_block(seed, i, CUE_STREAM, 2);
    [
        normal_quantile(open_unit(w0[0], w0[1])),
        normal_quantile(open_unit(w0[2], w0[3])),
        normal_quantile(open_unit(w1[0], w1[1])),
        normal_quantile(open_unit(w1[2], w1[3])),
        normal_quantile(open_unit(w2[0], w2[1])),
    ]
}

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
    let z = cue_normals(seed, i);
    clamped(CueStrike {
        v0: s.v0 + sigma.v0 * z[0],
        phi: s.phi + sigma.phi * z[1],
        theta: s.theta + sigma.theta * z[2],
        a: s.a + sigma.a / r * z[3],
        b: s.b + sigma.b / r * z[4],
    })
}

/// Sample `i`'s strike under `drawn` ([`crate::simulate::DrawnStrikes`]'s `draw`: the rule
/// the device runs): [`noisy_strike_of`] of its intended strike and σ.
pub fn drawn_strike(drawn: &DrawnStrikes, r: f64, i: u64) -> CueStrike {
    let [v0, phi, theta, a, b] = drawn.sigma;
    let sigma = Noise {
        v0,
        phi,
        theta,
        a,
        b,
        physics: PhysicsSpread::default(),
    };
    noisy_strike_of(drawn.shot, r, &sigma, drawn.seed, i)
}

/// The study's strikes as the rule [`drawn_strike`] for the device to draw
/// ([`crate::simulate::BatchOptions::drawn`]), samples from `first` on; `None` where a
/// draw could be a strike the simulator refuses ([`draws_are_strikes`]) or the physics
/// varies from sample to sample (the host then draws each sample).
pub fn drawn(config: &StudyConfig, sigma: &Noise, seed: u64, first: u64) -> Option<DrawnStrikes> {
    let s = [sigma.v0, sigma.phi, sigma.theta, sigma.a, sigma.b];
    let rule = DrawnStrikes {
        shot: config.shot,
        sigma: s,
        seed,
        first,
        draw: drawn_strike,
    };
    (sigma.physics.is_empty() && draws_are_strikes(config.shot, config.params.ball.r, &s))
        .then_some(rule)
}

/// The largest |z| a draw can give: the normal quantile of the smallest uniform Philox's
/// words give ([`open_unit`]`(0, 0)` = 2⁻⁵³; the largest, 1 − 2⁻⁵³, gives its negative).
pub fn max_normal() -> f64 {
    -normal_quantile(open_unit(0, 0))
}

/// Whether every strike drawn around `shot` with the σ `sigma` (V0, φ, θ, a, b) on balls of
/// radius `r` is one the simulator takes ([`CueStrike::validate`]): each number stays
/// finite and |φ| within [`MAX_PHI_DEGREES`] whatever the normals (|z| ≤ [`max_normal`]);
/// [`clamped`] sees to the rest (V0 ≥ 0, the tip on the ball).
pub fn draws_are_strikes(shot: CueStrike, r: f64, sigma: &[f64; 5]) -> bool {
    // a margin for the rounding of x + σ·z
    let z = max_normal() * (1.0 + 1e-9);
    let reach = |x: f64, s: f64| x.abs() + s.abs() * z;
    let x = [shot.v0, shot.phi, shot.theta, shot.a, shot.b];
    let s = [sigma[0], sigma[1], sigma[2], sigma[3] / r, sigma[4] / r];
    let within = |k: usize, most: f64| reach(x[k], s[k]) <= most;
    x.iter().chain(&s).all(|v| v.is_finite())
        && within(1, MAX_PHI_DEGREES * (1.0 - 1e-9))
        && [0, 2, 3, 4].into_iter().all(|k| within(k, 1e300))
}

/// Sample `i`'s physics: `base` with each parameter that `spread` varies scaled by
/// `1 + lo + (hi − lo)·u`, `u` uniform in (0, 1) from Philox keyed by `seed` at counter `i`
/// on a stream of its own (ten draws, one per parameter in `BALL_KEYS` order, whichever
/// vary: parameter `k` is block `k / 2`'s words `2(k mod 2)` and `2(k mod 2) + 1`).
/// `base` itself where nothing varies.
pub fn sample_physics(base: &SimParams, spread: &PhysicsSpread, seed: u64, i: u64) -> SimParams {
    if spread.is_empty() {
        return *base;
    }
    let mut p = *base;
    for (k, range) in spread.ranges.iter().enumerate() {
        let w = draw_block(seed, i, PHYSICS_STREAM, (k / 2) as u32);
        let j = 2 * (k % 2);
        let u = open_unit(w[j], w[j + 1]);
        if let Some((lo, hi)) = range {
            *ball_field(&mut p, k) *= 1.0 + lo + (hi - lo) * u;
        }
    }
    p
}

/// The strike with V0 ≥ 0, θ in [0°, 90°] and the tip on the ball (a² + b² ≤ 1, scaled
/// back onto the rim when noise pushed it off). For finite strikes.
pub fn clamped(s: CueStrike) -> CueStrike {
    let mut s = s;
    s.v0 = if s.v0 < 0.0 { 0.0 } else { s.v0 };
    // below 0 or above 90 (the shader's two selects; a −0 stays −0 on both)
    s.theta = s.theta.clamp(0.0, 90.0);
    let rho = (s.a * s.a + s.b * s.b).sqrt();
    if rho > 1.0 {
        s.a /= rho;
        s.b /= rho;
        // the division can leave a² + b² an ulp or two above 1
        for _ in 0..RIM_STEPS {
            if s.a * s.a + s.b * s.b <= 1.0 {
                break;
            }
            s.a *= RIM_SHRINK;
            s.b *= RIM_SHRINK;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cue_normals_are_standard_normal_and_independent() {
        let n = 200_000u64;
        let mut sum = [0.0; 5];
        let mut sq = [0.0; 5];
        let mut cross = [[0.0; 5]; 5];
        let probs = [0.001, 0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99, 0.999];
        let mut below = [[0u64; 9]; 5];
        for i in 0..n {
            let z = cue_normals(42, i);
            for j in 0..5 {
                sum[j] += z[j];
                sq[j] += z[j] * z[j];
                for k in 0..5 {
                    cross[j][k] += z[j] * z[k];
                }
                for (c, p) in probs.iter().enumerate() {
                    below[j][c] += u64::from(z[j] <= normal_quantile(*p));
                }
            }
        }
        let nf = n as f64;
        for j in 0..5 {
            let mean = sum[j] / nf;
            let var = sq[j] / nf - mean * mean;
            // 5σ: the mean's σ is 1/√n, the variance's √(2/n)
            assert!(mean.abs() < 5.0 / nf.sqrt(), "normal {j}: mean {mean}");
            assert!(
                (var - 1.0).abs() < 5.0 * (2.0 / nf).sqrt(),
                "normal {j}: var {var}"
            );
            for (k, c) in cross[j].iter().enumerate().take(j) {
                let r = c / nf;
                assert!(
                    r.abs() < 5.0 / nf.sqrt(),
                    "normals {j}, {k}: correlation {r}"
                );
            }
            for (c, p) in probs.iter().enumerate() {
                let frac = below[j][c] as f64 / nf;
                let sd = (p * (1.0 - p) / nf).sqrt();
                assert!(
                    (frac - p).abs() < 5.0 * sd,
                    "normal {j}: P(z ≤ Φ⁻¹({p})) = {frac}"
                );
            }
        }
    }

    #[test]
    fn seeds_and_samples_draw_apart() {
        let a = cue_normals(1, 0);
        assert_ne!(a, cue_normals(2, 0));
        assert_ne!(a, cue_normals(1, 1));
        // the seed's and the index's high words count
        assert_ne!(a, cue_normals(1 | (1 << 32), 0));
        assert_ne!(a, cue_normals(1, 1 << 32));
        assert_eq!(a, cue_normals(1, 0));
    }

    #[test]
    fn noise_that_pushes_the_tip_off_the_ball_leaves_it_on_the_rim() {
        let s = CueStrike {
            v0: 0.05,
            phi: 10.0,
            theta: 89.0,
            a: 0.99,
            b: -0.1,
        };
        let sigma = Noise {
            v0: 0.5,
            theta: 5.0,
            a: 0.02,
            b: 0.02,
            ..Noise::default()
        };
        let mut on_rim = 0;
        for i in 0..20_000 {
            let t = noisy_strike_of(s, 0.028_575, &sigma, 7, i);
            assert!(t.a * t.a + t.b * t.b <= 1.0, "sample {i}: {t:?}");
            assert!(
                t.v0 >= 0.0 && (0.0..=90.0).contains(&t.theta),
                "sample {i}: {t:?}"
            );
            on_rim += usize::from(t.a * t.a + t.b * t.b > 1.0 - 1e-12);
        }
        assert!(on_rim > 1000, "the rim case is exercised: {on_rim}");
    }

    #[test]
    fn the_largest_normal_is_the_extreme_words_quantile() {
        let z = max_normal();
        // Φ⁻¹(2⁻⁵³) = −8.2095361516013868… (mpmath, 30 digits)
        assert!((z - 8.209_536_151_601_387).abs() < 1e-13, "{z}");
        assert_eq!(normal_quantile(open_unit(u32::MAX, u32::MAX)), z);
        assert_eq!(normal_quantile(open_unit(0, 0)), -z);
    }

    #[test]
    fn draws_are_strikes_where_no_normal_can_break_one() {
        let shot = StudyConfig::builtin().shot;
        let r = 0.028_575;
        let sigma = [0.075, 0.125, 0.1, 0.0005, 0.0005];
        assert!(draws_are_strikes(shot, r, &sigma));
        // φ: |φ| + σ·z_max against 10⁷ degrees
        let z = max_normal();
        let phi = |s: f64| [0.075, s, 0.1, 0.0005, 0.0005];
        let edge = (MAX_PHI_DEGREES - shot.phi.abs()) / z;
        assert!(draws_are_strikes(shot, r, &phi(0.999 * edge)));
        assert!(!draws_are_strikes(shot, r, &phi(1.001 * edge)));
        // anything not finite, or a draw that could overflow
        for k in 0..5 {
            for bad in [f64::NAN, f64::INFINITY] {
                let mut s = sigma;
                s[k] = bad;
                assert!(!draws_are_strikes(shot, r, &s), "σ {k} = {bad}");
            }
        }
        assert!(!draws_are_strikes(
            shot,
            r,
            &[0.075, 0.125, 0.1, 1e299, 0.0005]
        ));
        let mut far = shot;
        far.v0 = f64::NAN;
        assert!(!draws_are_strikes(far, r, &sigma));
    }

    #[test]
    fn a_drawn_study_is_the_rule_of_its_noisy_strikes() {
        let config = StudyConfig::builtin();
        let sigma = Noise::default();
        let d = drawn(&config, &sigma, 9, 1000).expect("the built-in noise is drawn");
        let r = config.params.ball.r;
        for k in [0, 1, 77, 4096] {
            assert_eq!(
                d.strike(r, k),
                noisy_strike(&config, &sigma, 9, 1000 + k as u64)
            );
            assert_eq!(d.from(k).strike(r, 0), d.strike(r, k));
        }
        // a physics spread is drawn by the host; so is noise that could break a strike
        let mut spread = sigma;
        spread.physics.ranges[0] = Some((-0.1, 0.1));
        assert!(drawn(&config, &spread, 9, 0).is_none());
        let wild = Noise {
            phi: 1e7,
            ..Noise::default()
        };
        assert!(drawn(&config, &wild, 9, 0).is_none());
    }

    #[test]
    fn a_physics_spread_scales_within_its_range_on_draws_of_its_own() {
        let base = SimParams::default();
        let mut spread = PhysicsSpread::default();
        spread.ranges[0] = Some((-0.1, 0.2));
        let mut lo_seen = f64::INFINITY;
        let mut hi_seen = f64::NEG_INFINITY;
        for i in 0..10_000 {
            let mut p = sample_physics(&base, &spread, 3, i);
            let mut b = base;
            let scale = *ball_field(&mut p, 0) / *ball_field(&mut b, 0);
            assert!((0.9..1.2).contains(&scale), "sample {i}: {scale}");
            lo_seen = lo_seen.min(scale);
            hi_seen = hi_seen.max(scale);
        }
        assert!(lo_seen < 0.901 && hi_seen > 1.199, "{lo_seen} … {hi_seen}");
        assert_eq!(sample_physics(&base, &PhysicsSpread::default(), 3, 0), base);
    }
}
