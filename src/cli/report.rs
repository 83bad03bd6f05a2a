//! The shot study's reports: the summary as text, and one CSV row per sample.

use kisstime::study::{
    Class, Noise, Outcome, SAMPLE_COLUMNS, Sample, StudyConfig, Summary, noisy_strike, wilson,
};

/// A fraction as a percentage: two decimals, or three significant digits below 1 %.
fn percent(x: f64) -> String {
    let p = 100.0 * x;
    if p == 0.0 || p >= 1.0 {
        format!("{p:.2}")
    } else {
        let digits = (2 - p.log10().floor() as i32).max(0) as usize;
        format!("{p:.digits$}")
    }
}

/// The summary as text: one line per outcome (balls that are never hit first are left
/// out, except the intended one), then the intended ball's statistics.
pub fn summary_text(summary: &Summary) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<24} {:>9} {:>9}   95% confidence interval",
        "first contact", "count", "fraction"
    );
    for &(class, k) in &summary.counts {
        let label = match class {
            Class::Ball(id) if id == summary.intended => format!("ball {id} (intended)"),
            Class::Ball(id) if k == 0 => {
                let _ = id;
                continue;
            }
            Class::Ball(id) => format!("ball {id}"),
            Class::Cushion => "cushion".to_owned(),
            Class::Stopped => "stopped".to_owned(),
        };
        let (lo, hi) = wilson(k, summary.samples);
        let frac = if summary.samples > 0 {
            k as f64 / summary.samples as f64
        } else {
            0.0
        };
        let _ = writeln!(
            s,
            "  {label:<22} {k:>9} {:>8.2}%   [{}%, {}%]",
            100.0 * frac,
            percent(lo),
            percent(hi)
        );
    }
    let _ = writeln!(s);
    match (&summary.time, &summary.cut) {
        (Some(t), Some(c)) => {
            let _ = writeln!(
                s,
                "ball {} hit first ({} samples):{:>9} {:>9} {:>9} {:>9} {:>9}",
                summary.intended, t.n, "mean", "std", "p5", "p50", "p95"
            );
            let _ = writeln!(
                s,
                "  {:<30}{:>9.4} {:>9.4} {:>9.4} {:>9.4} {:>9.4}",
                "time to contact (s)", t.mean, t.std, t.p5, t.p50, t.p95
            );
            let _ = writeln!(
                s,
                "  {:<30}{:>9.2} {:>9.2} {:>9.2} {:>9.2} {:>9.2}",
                "cut angle (deg)", c.mean, c.std, c.p5, c.p50, c.p95
            );
        }
        _ => {
            let _ = writeln!(s, "ball {} is never hit first", summary.intended);
        }
    }
    s
}

/// Writes one CSV row per sample (header `SAMPLE_COLUMNS`): the noisy strike (recomputed
/// from `seed`), the outcome, the ball or cushion, the time, the cue ball's centre and speed,
/// the contact point, and the cut angle; empty fields where they do not apply. Numbers are the
/// shortest decimals that read back as the same f64.
pub fn write_samples_csv(
    out: &mut dyn std::io::Write,
    config: &StudyConfig,
    sigma: &Noise,
    seed: u64,
    samples: &[Sample],
) -> std::io::Result<()> {
    writeln!(out, "{SAMPLE_COLUMNS}")?;
    let mut buf = ryu::Buffer::new();
    let mut num = |v: f64| -> String {
        if v.is_finite() {
            buf.format(v).to_owned()
        } else {
            String::new()
        }
    };
    for (i, s) in samples.iter().enumerate() {
        let k = noisy_strike(config, sigma, seed, i as u64);
        let (ball, cushion) = match s.outcome {
            Outcome::Ball(id) => (id.to_string(), String::new()),
            Outcome::Cushion(c) => (String::new(), c.name().to_owned()),
            Outcome::Stopped => (String::new(), String::new()),
        };
        writeln!(
            out,
            "{i},{},{},{},{},{},{},{ball},{cushion},{},{},{},{},{},{},{}",
            num(k.v0),
            num(k.phi),
            num(k.theta),
            num(k.a),
            num(k.b),
            s.outcome.kind(),
            num(s.t),
            num(s.cue.x),
            num(s.cue.y),
            num(s.speed),
            num(s.contact.x),
            num(s.contact.y),
            num(s.cut)
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentages_keep_three_digits_when_small() {
        assert_eq!(percent(0.5), "50.00");
        assert_eq!(percent(0.0), "0.00");
        assert_eq!(percent(3.8e-5), "0.00380");
        assert_eq!(percent(0.0042), "0.420");
    }
}
