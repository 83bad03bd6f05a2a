//! Refinement in the continuous strike: the cross-entropy method (CEM) around the best few
//! candidates that the halving kept, since the candidates' grid (four speeds, five tip
//! offsets, the ghost-ball aim or a fan around a mirror's) only samples the strike.
//!
//! Method (Rubinstein and Kroese, *The Cross-Entropy Method*, 2004, ch. 4, for continuous
//! optimisation): around each of the [`LEADERS`] best candidates, a Gaussian over the
//! strike's V0, φ, a and b (θ kept), its mean the candidate's strike and its σ
//! [`SIGMA`] (φ's wider for banks and kicks, whose mirror aim is rougher:
//! [`SIGMA_PHI_REBOUND`]). Each generation draws [`CHILDREN`] strikes from every leader's
//! Gaussian, plays them all in one engine call on **the same noise draws** as its parent
//! (common random numbers: a child and its parent differ by their strikes, not their
//! luck; the parents are played on those draws with the first generation), then moves
//! each mean to the average of its [`ELITES`] best strikes so far (the parent's included)
//! and shrinks σ by [`SHRINK`]. Each leader's best child, where it beats its parent on
//! those draws, joins the finalists; the planner's fresh final estimates then rank them
//! with the rest, so a child chosen for a lucky run is not reported with its luck.
//!
//! The children are drawn from a PCG generator seeded by the plan's seed only, so a plan
//! with a sample budget is the same at every run. A strike is kept in the playable range:
//! V0 in [`V0_RANGE`], the tip within [`MAX_TIP`] of the centre (well inside the miscue
//! limit), φ in [0°, 360°).

use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rand_pcg::Pcg64Mcg;

use super::candidates::{Candidate, Kind};
use super::evaluate::{Estimate, evaluate};
use crate::engine::ShotEngine;
use crate::error::Error;
use crate::resolve::stick_ball::CueStrike;
use crate::study::{Noise, StudyConfig, mix};

/// The candidates refined.
pub const LEADERS: usize = 3;
/// Strikes drawn around each leader a generation.
pub const CHILDREN: usize = 8;
/// Generations.
pub const GENERATIONS: usize = 2;
/// The strikes (the parent's included) whose average is the next generation's mean.
pub const ELITES: usize = 3;
/// The first generation's σ: V0 (m/s), φ (degrees), a and b (fractions of R).
pub const SIGMA: [f64; 4] = [0.4, 0.2, 0.15, 0.15];
/// φ's first σ around a bank or a kick, degrees.
pub const SIGMA_PHI_REBOUND: f64 = 0.6;
/// σ's factor from one generation to the next.
pub const SHRINK: f64 = 0.6;
/// The speeds a refined strike keeps to, m/s (up to its parent's where that is faster).
pub const V0_RANGE: (f64, f64) = (0.5, 6.0);
/// The farthest a refined strike's tip goes from the centre (a fraction of R).
pub const MAX_TIP: f64 = 0.5;

/// Samples a refinement plays around `leaders` candidates with `per` samples each strike
/// (the leaders' own included): what [`refine`] spends.
pub fn cost(leaders: usize, per: u64) -> usize {
    leaders * (CHILDREN * GENERATIONS + 1) * per as usize
}

/// Refines `leaders` (indices in `candidates`; module docs): every strike drawn is
/// appended to `candidates`, and every one (and the leaders) played on the noise draws
/// `draws`. Returns, for each leader whose best child beat it on those draws, that
/// child's index.
pub fn refine(
    engine: &mut ShotEngine,
    config: &StudyConfig,
    candidates: &mut Vec<Candidate>,
    leaders: &[usize],
    (noise, seed, draws): (&Noise, u64, std::ops::Range<u64>),
) -> Result<Vec<usize>, Error> {
    let mut estimates = vec![Estimate::default(); candidates.len()];
    let mut rng = Pcg64Mcg::seed_from_u64(mix(seed, 0x0063_656d));
    // each leader's search: its mean, σ and the strikes seen (indices)
    let mut searches: Vec<([f64; 4], [f64; 4], Vec<usize>)> = leaders
        .iter()
        .map(|&l| {
            let s = candidates[l].strike;
            let mut sigma = SIGMA;
            if matches!(candidates[l].kind, Kind::Bank { .. } | Kind::Kick { .. }) {
                sigma[1] = SIGMA_PHI_REBOUND;
            }
            ([s.v0, s.phi, s.a, s.b], sigma, vec![l])
        })
        .collect();
    for g in 0..GENERATIONS {
        // the parents meet the draws with the first generation
        let mut born = if g == 0 { leaders.to_vec() } else { Vec::new() };
        for (k, (mean, sigma, seen)) in searches.iter_mut().enumerate() {
            let parent = candidates[leaders[k]];
            for _ in 0..CHILDREN {
                let mut z = [0.0f64; 4];
                for v in &mut z {
                    *v = StandardNormal.sample(&mut rng);
                }
                let strike = playable(
                    CueStrike {
                        v0: mean[0] + sigma[0] * z[0],
                        phi: mean[1] + sigma[1] * z[1],
                        theta: parent.strike.theta,
                        a: mean[2] + sigma[2] * z[2],
                        b: mean[3] + sigma[3] * z[3],
                    },
                    V0_RANGE.1.max(parent.strike.v0),
                );
                candidates.push(Candidate { strike, ..parent });
                estimates.push(Estimate::default());
                seen.push(candidates.len() - 1);
                born.push(candidates.len() - 1);
            }
        }
        evaluate(
            engine,
            config,
            candidates,
            &born,
            (noise, seed, draws.clone()),
            &mut estimates,
        )?;
        for (mean, sigma, seen) in &mut searches {
            seen.sort_by(|&a, &b| {
                estimates[b]
                    .value()
                    .total_cmp(&estimates[a].value())
                    .then(a.cmp(&b))
            });
            let elites = &seen[..ELITES.min(seen.len())];
            let centre = candidates[elites[0]].strike.phi;
            let mut m = [0.0; 4];
            for &e in elites {
                let s = candidates[e].strike;
                // φ averaged as offsets from the best, so that 359° and 1° average to 0°
                let dphi = (s.phi - centre + 180.0).rem_euclid(360.0) - 180.0;
                for (mi, v) in m.iter_mut().zip([s.v0, centre + dphi, s.a, s.b]) {
                    *mi += v / elites.len() as f64;
                }
            }
            *mean = m;
            for s in sigma.iter_mut() {
                *s *= SHRINK;
            }
        }
    }
    // each search's best strike, where it is a child (seen[0] is the best: sorted above)
    Ok(searches
        .iter()
        .map(|(_, _, seen)| seen[0])
        .filter(|&best| !leaders.contains(&best))
        .collect())
}

/// `s` kept in the refinement's range (module docs), its speed at most `v_max` (the
/// range's, or a faster parent's: a break's).
fn playable(s: CueStrike, v_max: f64) -> CueStrike {
    let mut s = s;
    s.v0 = s.v0.clamp(V0_RANGE.0, v_max);
    s.phi = s.phi.rem_euclid(360.0);
    let rho = s.a.hypot(s.b);
    if rho > MAX_TIP {
        s.a *= MAX_TIP / rho;
        s.b *= MAX_TIP / rho;
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_refined_strike_stays_playable() {
        let s = playable(
            CueStrike {
                v0: 40.0,
                phi: -10.0,
                theta: 5.0,
                a: 0.9,
                b: -0.9,
            },
            V0_RANGE.1,
        );
        assert_eq!(s.v0, V0_RANGE.1);
        assert!((s.phi - 350.0).abs() < 1e-12);
        assert!(s.a.hypot(s.b) <= MAX_TIP + 1e-12);
        assert!(s.a > 0.0 && s.b < 0.0);
        assert_eq!(playable(CueStrike { v0: 0.0, ..s }, 9.0).v0, V0_RANGE.0);
        assert_eq!(playable(CueStrike { v0: 12.0, ..s }, 9.0).v0, 9.0);
    }
}
