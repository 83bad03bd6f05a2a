//! The shot study's reports: the summary as text or JSON, and one CSV row per sample.

use std::fmt::Write as _;
use std::path::Path;

use kisstime::game::{Foul, Rules};
use kisstime::io::csv::format_finite;
use kisstime::study::reference::{first_contact_word, potted_field};
use kisstime::study::{
    Class, FirstContact, Noise, Result4, Sample, Stats, StudyConfig, Summary, Until, wilson,
};
use serde_json::{Value, json};

/// What the report says about the run besides its results.
pub struct Run<'a> {
    /// The study.
    pub scenario: &'a StudyConfig,
    /// The noise, for a noisy study (`None` with given strikes).
    pub sigma: Option<Noise>,
    /// The seed of a noisy study.
    pub seed: u64,
    /// The strike file, if strikes were given.
    pub strikes: Option<&'a Path>,
    /// Wall-clock seconds of the simulation.
    pub seconds: f64,
    /// Worker threads.
    pub threads: usize,
    /// What simulated, e.g. `cpu f64 (2 threads)` or `gpu f32: NVIDIA H200 (Vulkan, …)`.
    pub backend: String,
}

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

/// The label of a first-contact class.
fn class_label(config: &StudyConfig, class: Class) -> String {
    match class {
        Class::Ball(k) if k == config.intended => format!("ball {} (intended)", config.balls[k].id),
        Class::Ball(k) => format!("ball {}", config.balls[k].id),
        Class::Cushion => "cushion".to_owned(),
        Class::Pocket => "pocket".to_owned(),
        Class::Stopped => "stopped".to_owned(),
        Class::Nothing => "nothing (no event)".to_owned(),
    }
}

/// The rows of the summary that are counts: (section, label, count), in report order.
/// First contacts list every ball hit at least once (and the intended ball always).
fn count_rows(config: &StudyConfig, s: &Summary) -> Vec<(&'static str, String, usize)> {
    let mut rows = Vec::new();
    for &(class, k) in &s.first {
        let always = class == Class::Ball(config.intended);
        if k > 0 || always {
            rows.push(("first contact", class_label(config, class), k));
        }
    }
    if s.until == Until::FirstContact {
        return rows;
    }
    let intended = config.intended_id();
    for r in Result4::ALL {
        let label = match r {
            Result4::Pot => format!("pot ({intended} in, cue ball up)"),
            Result4::PotScratch => format!("pot + scratch ({intended} and cue ball in)"),
            Result4::Scratch => format!("scratch only (cue ball in, {intended} not)"),
            Result4::Miss => format!("miss ({intended} not in, cue ball up)"),
        };
        rows.push(("outcome", label, s.result(r)));
    }
    let called = config.pocket_id();
    rows.push((
        "potted",
        format!("ball {intended} potted, any pocket"),
        s.intended_potted(),
    ));
    for &(p, k) in &s.intended_pockets {
        let id = &config.table.pocket_ids[p];
        let note = if Some(id.as_str()) == called {
            " (called)"
        } else {
            ""
        };
        rows.push(("potted", format!("  ball {intended} in {id}{note}"), k));
    }
    rows.push((
        "potted",
        "cue ball potted (scratch)".to_owned(),
        s.scratches,
    ));
    for &(p, k) in &s.scratch_pockets {
        let id = &config.table.pocket_ids[p];
        rows.push(("potted", format!("  cue ball in {id}"), k));
    }
    for &(b, k) in &s.others_potted {
        rows.push(("potted", format!("ball {} potted", config.balls[b].id), k));
    }
    rows.push(("potted", "no ball hit (foul)".to_owned(), s.no_ball_hit));
    if let Some(g) = &s.game {
        let name = g.rules.name();
        rows.push(("game", format!("legal shot ({name})"), g.legal));
        for (f, &k) in Foul::ALL.iter().zip(&g.fouls) {
            if k > 0 {
                rows.push(("game", format!("  foul: {}", f.code()), k));
            }
        }
        let kept = if g.rules == Rules::ThreeCushion {
            "point (turn kept)"
        } else {
            "turn kept (the player shoots again)"
        };
        rows.push(("game", kept.to_owned(), g.turn_kept));
        if g.rules != Rules::ThreeCushion {
            rows.push(("game", "game won".to_owned(), g.won));
            let lost = if g.rules == Rules::Snooker {
                "game lost or tied"
            } else {
                "game lost"
            };
            rows.push(("game", lost.to_owned(), g.lost));
        }
    }
    if let (Some(t), Some(k)) = (config.target, s.in_target) {
        rows.push((
            "position",
            format!("cue ball in ({}, {}) r {}", t.x, t.y, t.radius),
            k,
        ));
    }
    rows
}

/// One statistics row: label, then mean, std, p5, p50, p95 with `digits` decimals.
fn stats_row(out: &mut String, label: &str, st: &Stats, digits: usize) {
    let _ = writeln!(
        out,
        "  {label:<34}{:>9.digits$} {:>9.digits$} {:>9.digits$} {:>9.digits$} {:>9.digits$}",
        st.mean, st.std, st.p5, st.p50, st.p95
    );
}

/// The heading of a statistics block.
fn stats_head(out: &mut String, title: &str) {
    let _ = writeln!(
        out,
        "{title:<36}{:>9} {:>9} {:>9} {:>9} {:>9}",
        "mean", "std", "p5", "p50", "p95"
    );
}

/// The description of the run: scenario, noise or strike file.
fn preamble(run: &Run<'_>, samples: usize) -> String {
    let c = run.scenario;
    let mut s = format!("kisstime shots: {}\n", c.source);
    let _ = write!(
        s,
        "table {}, {} balls; cue ball {}, intended ball {}",
        c.table_name,
        c.balls.len(),
        c.cue_id(),
        c.intended_id()
    );
    if let Some(p) = c.pocket_id() {
        let _ = write!(s, " into {p}");
    }
    if let Some(t) = c.target {
        let _ = write!(s, "; target circle ({}, {}) r {} m", t.x, t.y, t.radius);
    }
    s.push('\n');
    match (run.sigma, run.strikes) {
        (Some(sigma), _) => {
            let _ = writeln!(
                s,
                "{samples} samples, seed {}; noise σ: V0 {} m/s, phi {}°, theta {}°, a {} mm, \
                 b {} mm",
                run.seed,
                sigma.v0,
                sigma.phi,
                sigma.theta,
                1e3 * sigma.a,
                1e3 * sigma.b
            );
            let varies = sigma.physics.named();
            if !varies.is_empty() {
                let parts: Vec<String> = varies
                    .iter()
                    .map(|(k, lo, hi)| format!("{k} {:+.1} % to {:+.1} %", 100.0 * lo, 100.0 * hi))
                    .collect();
                let _ = writeln!(
                    s,
                    "physics drawn per sample (uniform): {}",
                    parts.join(", ")
                );
            }
        }
        (None, Some(path)) => {
            let _ = writeln!(s, "{samples} strikes from {}, no noise", path.display());
        }
        (None, None) => {
            let _ = writeln!(s, "{samples} samples");
        }
    }
    s
}

/// The summary as text.
pub fn summary_text(run: &Run<'_>, s: &Summary) -> String {
    let c = run.scenario;
    let mut out = preamble(run, s.samples);
    let n = s.samples;
    let mut section = "";
    let rows = count_rows(c, s);
    // the label column fits the longest label, so the counts line up under "count"
    let width = rows
        .iter()
        .map(|(_, label, _)| label.chars().count())
        .max()
        .unwrap_or(0)
        .max(32);
    for (sec, label, k) in rows {
        if sec != section {
            section = sec;
            let title = match sec {
                "first contact" => "first contact",
                "outcome" => "outcome (every ball at rest)",
                "potted" => "balls potted",
                "game" => "game (the rules' verdict)",
                _ => "position play",
            };
            let _ = writeln!(
                out,
                "\n{title:<w$} {:>9} {:>9}   95% confidence interval",
                "count",
                "fraction",
                w = width + 2
            );
        }
        let (lo, hi) = wilson(k, n);
        let frac = if n > 0 { k as f64 / n as f64 } else { 0.0 };
        let _ = writeln!(
            out,
            "  {label:<width$} {k:>9} {:>8}%   [{}%, {}%]",
            percent(frac),
            percent(lo),
            percent(hi)
        );
    }
    if s.cut > 0 {
        let _ = writeln!(
            out,
            "\n{} samples were cut by the event or time cap (counted above as they stood)",
            s.cut
        );
    } else {
        let _ = writeln!(out, "\nno sample was cut by the event or time cap");
    }
    let _ = writeln!(out);
    let intended = c.intended_id();
    if let (Some(t), Some(a)) = (&s.contact_time, &s.cut_angle) {
        stats_head(
            &mut out,
            &format!("ball {intended} hit first ({} samples)", t.n),
        );
        stats_row(&mut out, "time to contact (s)", t, 4);
        stats_row(&mut out, "cut angle (deg)", a, 2);
    } else {
        let _ = writeln!(out, "ball {intended} is never hit first");
    }
    if s.until == Until::Rest {
        if let Some(t) = &s.pot_time {
            stats_head(
                &mut out,
                &format!("ball {intended} potted ({} samples)", t.n),
            );
            stats_row(&mut out, "time to pot (s)", t, 4);
        }
        if let Some((x, y)) = &s.cue_final {
            stats_head(&mut out, &format!("cue ball final, on table ({})", x.n));
            stats_row(&mut out, "x (m)", x, 4);
            stats_row(&mut out, "y (m)", y, 4);
        }
    }
    if let Some(g) = &s.game
        && let Some(p) = &g.points
    {
        stats_head(
            &mut out,
            &format!("points ({}, every sample)", g.rules.name()),
        );
        stats_row(&mut out, "scored by the player who shot", p, 3);
        if let Some(f) = &g.foul_points {
            stats_row(&mut out, "foul points to the opponent", f, 3);
        }
    }
    if let (Some(e), Some(d)) = (&s.events, &s.duration) {
        stats_head(&mut out, "every sample");
        stats_row(&mut out, "events", e, 1);
        stats_row(&mut out, "duration (s)", d, 3);
    }
    let _ = writeln!(
        out,
        "\n{n} samples in {:.3} s: {:.0} samples/s on {}",
        run.seconds,
        n as f64 / run.seconds.max(1e-9),
        run.backend
    );
    out
}

/// The summary as one JSON object (for scripts): the study's counts and statistics
/// ([`Summary::to_json`]) with the run's description added (seed, noise or strike file,
/// time, threads, backend).
pub fn summary_json(run: &Run<'_>, s: &Summary) -> String {
    let mut v = s.to_json(run.scenario);
    let n = s.samples;
    let extra = json!({
        "seed": run.sigma.map(|_| run.seed),
        "strikes": run.strikes.map(|p| p.display().to_string()),
        "noise": run.sigma.map(|g| {
            let mut noise = json!({
                "V0": g.v0, "phi": g.phi, "theta": g.theta, "a_m": g.a, "b_m": g.b
            });
            let varies = g.physics.named();
            if let (false, Value::Object(m)) = (varies.is_empty(), &mut noise) {
                // each varying parameter's relative range [lo, hi]
                let ranges: serde_json::Map<String, Value> = varies
                    .iter()
                    .map(|(k, lo, hi)| ((*k).to_owned(), json!([lo, hi])))
                    .collect();
                m.insert("physics".to_owned(), Value::Object(ranges));
            }
            noise
        }),
        "seconds": run.seconds,
        "samples_per_s": n as f64 / run.seconds.max(1e-9),
        "threads": run.threads,
        "backend": run.backend,
    });
    if let (Value::Object(m), Value::Object(e)) = (&mut v, extra) {
        m.extend(e);
    }
    v.to_string()
}

/// The per-sample CSV's columns.
pub const SAMPLE_COLUMNS: &str = "sample,V0,phi,theta,a,b,first_contact,first_ball,first_cushion,first_t,contact_cue_x,contact_cue_y,speed,contact_x,contact_y,cut_angle,result,intended_potted,intended_pocket,cue_potted,potted,cue_x,cue_y,in_target,n_events,duration,cut";

/// The verdict columns a study with a game adds to [`SAMPLE_COLUMNS`].
pub const GAME_COLUMNS: &str = "legal,foul,turn_over,game_over,won,points,foul_points";

/// The text of a first contact's segment, jaw or pocket id.
fn first_cushion(c: &StudyConfig, f: &FirstContact) -> String {
    match *f {
        FirstContact::Cushion {
            circular: false,
            index,
        } => c.table.linear_ids[index as usize].clone(),
        FirstContact::Cushion {
            circular: true,
            index,
        } => c.table.circular_ids[index as usize].clone(),
        FirstContact::Pocket(p) => c.table.pocket_ids[p as usize].clone(),
        _ => String::new(),
    }
}

/// Writes one CSV row per sample (header [`SAMPLE_COLUMNS`]), `ids[k]` the sample id of
/// `samples[k]`: the strike, the first contact (its kind, the ball or the cushion/pocket
/// id, the time, the cue ball's centre and speed then, the contact point, the cut angle),
/// then — to rest only — the outcome (`pot`, `pot+scratch`, `scratch`, `miss`), the
/// intended ball potted and where, the cue ball potted, every ball potted as `ball@pocket`
/// in order, the cue ball's final position, whether it is in the target circle, and for
/// every sample the event count, the duration and the cap that cut it (`max_events`,
/// `max_time`, empty). With a game (`[game]`) seven more columns, [`GAME_COLUMNS`]: the
/// verdict (`legal`, `foul` code or empty, `turn_over`, `game_over`, `won`, `points`,
/// `foul_points`, as `simulate --rules` writes them). Empty fields where they do not apply; numbers are the
/// shortest decimals that read back as the same f64.
pub fn write_samples_csv(
    out: &mut dyn std::io::Write,
    c: &StudyConfig,
    ids: &[i64],
    samples: &[Sample],
    until: Until,
) -> std::io::Result<()> {
    match c.game {
        Some(_) => writeln!(out, "{SAMPLE_COLUMNS},{GAME_COLUMNS}")?,
        None => writeln!(out, "{SAMPLE_COLUMNS}")?,
    }
    let mut buf = ryu::Buffer::new();
    let mut num = |v: f64| -> String { format_finite(v, &mut buf).to_owned() };
    for (id, s) in ids.iter().zip(samples) {
        let k = s.strike;
        let kind = match s.first {
            FirstContact::Ball(_) => "ball",
            FirstContact::Cushion { .. } => "cushion",
            FirstContact::Pocket(_) => "pocket",
            FirstContact::Stopped => "stopped",
            FirstContact::Nothing => "nothing",
        };
        let ball = match s.first {
            FirstContact::Ball(_) => first_contact_word(c, &s.first),
            _ => "",
        };
        let (px, py) = s.contact_point;
        let mut row = format!(
            "{id},{},{},{},{},{},{kind},{ball},{},{},{},{},{},{},{},{}",
            num(k.v0),
            num(k.phi),
            num(k.theta),
            num(k.a),
            num(k.b),
            first_cushion(c, &s.first),
            num(s.first_t),
            num(s.contact_cue.0),
            num(s.contact_cue.1),
            num(s.contact_speed),
            num(px),
            num(py),
            num(s.cut_angle),
        );
        if until == Until::Rest {
            let intended = s.pocket_of(c.intended);
            let in_target = match c.target {
                Some(t) if s.pocket_of(c.cue).is_none() => {
                    u8::from(t.contains(s.cue_final.0, s.cue_final.1)).to_string()
                }
                Some(_) => "0".to_owned(),
                None => String::new(),
            };
            let _ = write!(
                row,
                ",{},{},{},{},{},{},{},{in_target}",
                Result4::of(c, s).name(),
                u8::from(intended.is_some()),
                intended.map_or("", |p| c.table.pocket_ids[p].as_str()),
                u8::from(s.pocket_of(c.cue).is_some()),
                potted_field(c, s),
                num(s.cue_final.0),
                num(s.cue_final.1),
            );
        } else {
            row.push_str(",,,,,,,,");
        }
        let cut = match s.cut {
            Some(kisstime::simulate::Cut::MaxEvents) => "max_events",
            Some(kisstime::simulate::Cut::MaxTime) => "max_time",
            None => "",
        };
        let _ = write!(row, ",{},{},{cut}", s.n_events, num(s.duration));
        if c.game.is_some() {
            match s.verdict {
                Some(v) => {
                    let _ = write!(
                        row,
                        ",{},{},{},{},{},{},{}",
                        u8::from(v.legal),
                        v.foul.map_or("", |f| f.code()),
                        u8::from(v.turn_over),
                        u8::from(v.game_over),
                        u8::from(v.won),
                        v.points,
                        v.foul_points
                    );
                }
                None => row.push_str(",,,,,,,"),
            }
        }
        writeln!(out, "{row}")?;
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
