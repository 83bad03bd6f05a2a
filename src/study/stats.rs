//! What a study found: counts per first-contact class with Wilson intervals, and summary
//! statistics of the intended ball's contacts.

use super::config::StudyConfig;
use super::run::{Outcome, Sample};

/// Summary statistics of a set of values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stats {
    /// How many values.
    pub n: usize,
    /// Mean.
    pub mean: f64,
    /// Sample standard deviation (0 for one value).
    pub std: f64,
    /// 5th percentile (linear interpolation between order statistics).
    pub p5: f64,
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
}

impl Stats {
    /// The statistics of `values`, `None` when empty.
    pub fn of(values: &[f64]) -> Option<Stats> {
        if values.is_empty() {
            return None;
        }
        let n = values.len();
        let mean = values.iter().sum::<f64>() / n as f64;
        let var = if n > 1 {
            values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64
        } else {
            0.0
        };
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let q = |p: f64| {
            let x = p * (n - 1) as f64;
            let lo = x.floor() as usize;
            let hi = (lo + 1).min(n - 1);
            sorted[lo] + (x - lo as f64) * (sorted[hi] - sorted[lo])
        };
        Some(Stats {
            n,
            mean,
            std: var.sqrt(),
            p5: q(0.05),
            p50: q(0.5),
            p95: q(0.95),
        })
    }
}

/// The 95 % Wilson score interval of a proportion `k / n`.
pub fn wilson(k: usize, n: usize) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let z = 1.959_963_984_540_054;
    let (k, n) = (k as f64, n as f64);
    let p = k / n;
    let denom = 1.0 + z * z / n;
    let centre = (p + z * z / (2.0 * n)) / denom;
    let half = z / denom * (p * (1.0 - p) / n + z * z / (4.0 * n * n)).sqrt();
    // exactly 0 and 1 at the ends (the formula leaves rounding there)
    let lo = if k == 0.0 {
        0.0
    } else {
        (centre - half).max(0.0)
    };
    let hi = if k == n {
        1.0
    } else {
        (centre + half).min(1.0)
    };
    (lo, hi)
}

/// An outcome class of the summary: a ball, any cushion, or stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Class {
    /// The cue ball touched this ball first.
    Ball(i64),
    /// The cue ball reached a cushion first.
    Cushion,
    /// The cue ball stopped without touching anything.
    Stopped,
}

impl Class {
    /// The class of an outcome.
    pub fn of(o: Outcome) -> Class {
        match o {
            Outcome::Ball(id) => Class::Ball(id),
            Outcome::Cushion(_) => Class::Cushion,
            Outcome::Stopped => Class::Stopped,
        }
    }
}

/// What a study found.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// Samples.
    pub samples: usize,
    /// The intended object ball.
    pub intended: i64,
    /// Count per class: every object ball (in id order), then cushion, then stopped.
    pub counts: Vec<(Class, usize)>,
    /// Time to contact with the intended ball, over the samples that hit it first.
    pub time: Option<Stats>,
    /// Cut angle on the intended ball, degrees.
    pub cut: Option<Stats>,
}

impl Summary {
    /// Counts and statistics of `samples`.
    pub fn of(config: &StudyConfig, samples: &[Sample]) -> Summary {
        let mut ids: Vec<i64> = config
            .balls
            .iter()
            .map(|b| b.id)
            .filter(|&id| id != config.cue_ball)
            .collect();
        ids.sort_unstable();
        let mut counts: Vec<(Class, usize)> = ids
            .into_iter()
            .map(Class::Ball)
            .chain([Class::Cushion, Class::Stopped])
            .map(|c| (c, 0))
            .collect();
        let mut times = Vec::new();
        let mut cuts = Vec::new();
        for s in samples {
            let class = Class::of(s.outcome);
            if let Some(c) = counts.iter_mut().find(|(k, _)| *k == class) {
                c.1 += 1;
            }
            if s.outcome == Outcome::Ball(config.object_ball) {
                times.push(s.t);
                cuts.push(s.cut);
            }
        }
        Summary {
            samples: samples.len(),
            intended: config.object_ball,
            counts,
            time: Stats::of(&times),
            cut: Stats::of(&cuts),
        }
    }

    /// The count of a class.
    pub fn count(&self, class: Class) -> usize {
        self.counts
            .iter()
            .find(|(c, _)| *c == class)
            .map_or(0, |c| c.1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wilson_interval_brackets_the_proportion() {
        let (lo, hi) = wilson(50, 100);
        assert!(lo < 0.5 && hi > 0.5 && (0.5 - lo - (hi - 0.5)).abs() < 1e-12);
        assert_eq!(wilson(0, 100).0, 0.0);
        assert!(wilson(0, 100).1 > 0.0);
        assert_eq!(wilson(100, 100).1, 1.0);
    }

    #[test]
    fn stats_percentiles_interpolate() {
        let v: Vec<f64> = (0..=100).map(f64::from).collect();
        let s = Stats::of(&v).unwrap();
        assert_eq!((s.p5, s.p50, s.p95), (5.0, 50.0, 95.0));
        assert_eq!(s.mean, 50.0);
    }
}
