//! The picture of a shot study (`kisstime shots --plot study.png`): the table from above
//! with its real pockets, cushions and jaws, the balls, the intended shot's paths to rest,
//! and a heat map of where the cue ball came to rest, coloured by outcome (pot, miss; with
//! a game, by the verdict: the table kept or not, and the verdict's bars beside);
//! scratches are counted at the pocket they went into. Beside it the outcome fractions with
//! their 95 % intervals; below, the first contacts and the histogram of the cut angle on
//! the intended ball. Drawn with `plotters` into memory as PNG bytes (the command writes
//! them atomically).

use plotters::prelude::*;
use plotters::style::FontStyle;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use kisstime::Error;
use kisstime::simulate::Limits;
use kisstime::study::{
    Class, FirstContact, Result4, Sample, StudyConfig, Summary, Until, potted_as_called, wilson,
};

use super::draw::{
    ball_colour, circle_at, draw_table, encode_png, fonts, plot_error, table_area, view, view_range,
};
use super::shot_plot::record;

/// Picture size in pixels.
const SIZE: (u32, u32) = (1600, 1180);
/// Height of the table panel.
const TABLE_PANEL: u32 = 700;
/// Width of the table panel (the outcome column is to its right).
const TABLE_WIDTH: u32 = 1180;
/// Heat-map cell, m.
const CELL: f64 = 0.02;

const POT: RGBColor = RGBColor(60, 170, 255);
const MISS: RGBColor = RGBColor(255, 120, 0);
const SCRATCH: RGBColor = RGBColor(235, 40, 60);
const POT_SCRATCH: RGBColor = RGBColor(170, 60, 200);
const TEXT_GREY: RGBColor = RGBColor(70, 70, 70);

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;
type DrawResult = Result<(), Box<dyn std::error::Error + 'static>>;

/// The colour of an outcome.
fn colour(r: Result4) -> RGBColor {
    match r {
        Result4::Pot => POT,
        Result4::PotScratch => POT_SCRATCH,
        Result4::Scratch => SCRATCH,
        Result4::Miss => MISS,
    }
}

/// A ball's colour from its id (numbers as on the table, `cue` white).
fn id_colour(id: &str) -> RGBColor {
    ball_colour(
        id.parse::<i64>()
            .unwrap_or(if id == "cue" { 0 } else { 99 }),
    )
}

/// The picture as PNG bytes.
pub fn render_png(
    scenario: &StudyConfig,
    samples: &[Sample],
    summary: &Summary,
) -> Result<Vec<u8>, Error> {
    fonts();
    let (w, h) = SIZE;
    let mut rgb = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        draw(&root, scenario, samples, summary).map_err(plot_error)?;
        root.present().map_err(plot_error)?;
    }
    encode_png(&rgb, SIZE)
}

/// `k / n` as a percentage with its Wilson interval: `75.2% [73.3, 77.0]`.
fn share(k: usize, n: usize) -> String {
    let (lo, hi) = wilson(k, n);
    format!(
        "{:.1}% [{:.1}, {:.1}]",
        100.0 * k as f64 / n.max(1) as f64,
        100.0 * lo,
        100.0 * hi
    )
}

fn draw(root: &Area, c: &StudyConfig, samples: &[Sample], s: &Summary) -> DrawResult {
    let n = s.samples;
    let intended = c.intended_id();
    let title = if s.until == Until::Rest {
        let called = c.pocket_id().map_or(String::new(), |p| format!(" in {p}"));
        let pots = s.result(Result4::Pot) + s.result(Result4::PotScratch);
        format!(
            "Shot study, {n} samples to rest: ball {intended} potted{called} {}; cue ball \
             scratched {}",
            share(pots, n),
            share(s.scratches, n)
        )
    } else {
        format!(
            "Shot study, {n} samples to the first contact: ball {intended} hit first {}",
            share(s.count(Class::Ball(c.intended)), n)
        )
    };
    let (head, body) = root.split_vertically(50);
    head.draw(&Text::new(
        title,
        (20, 14),
        ("sans-serif", 24).into_font().style(FontStyle::Bold),
    ))?;
    let (top, bottom) = body.split_vertically(TABLE_PANEL);
    let (table_panel, side) = top.split_horizontally(TABLE_WIDTH);
    draw_table_panel(&table_panel, c, samples, s)?;
    draw_outcomes(&side, c, s)?;
    let (left, right) = bottom.split_horizontally(560);
    draw_first_contacts(&left, c, s)?;
    draw_histogram(&right, c, samples)?;
    Ok(())
}

fn draw_table_panel(area: &Area, c: &StudyConfig, samples: &[Sample], s: &Summary) -> DrawResult {
    let table = &c.table;
    let r = c.params.ball.r;
    let (pw, ph) = area.dim_in_pixel();
    let legend_h = 64;
    let (inner, left, ch) = table_area(area, table, (pw, ph - legend_h));
    let (xs, ys) = view_range(table);
    let mut chart = ChartBuilder::on(&inner).build_cartesian_2d(xs, ys)?;
    draw_table(&mut chart, table)?;

    // the heat map: where the cue ball stopped on the table, per cell, coloured by the
    // outcome most of that cell's samples had (with a game: the verdict, the table kept or
    // not), stronger where more samples stopped
    let judged = s.game.is_some();
    if s.until == Until::Rest {
        let mut cells: std::collections::HashMap<(i64, i64), [usize; 2]> =
            std::collections::HashMap::new();
        for smp in samples {
            if smp.pocket_of(c.cue).is_some() {
                continue;
            }
            let (x, y) = smp.cue_final;
            let key = ((x / CELL).floor() as i64, (y / CELL).floor() as i64);
            let slot = match smp.verdict {
                Some(v) if judged => usize::from(v.turn_over),
                _ => usize::from(!potted_as_called(c, smp)),
            };
            cells.entry(key).or_default()[slot] += 1;
        }
        let most = cells.values().map(|v| v[0] + v[1]).max().unwrap_or(1) as f64;
        let mut keys: Vec<_> = cells.keys().copied().collect();
        keys.sort_unstable();
        chart.draw_series(keys.iter().map(|&(i, j)| {
            let [pot, miss] = cells[&(i, j)];
            let colour = if pot >= miss { POT } else { MISS };
            let strength = 0.35 + 0.65 * ((pot + miss) as f64 / most).sqrt();
            let (x0, y0) = (i as f64 * CELL, j as f64 * CELL);
            Rectangle::new(
                [view((x0, y0)), view((x0 + CELL, y0 + CELL))],
                colour.mix(strength).filled(),
            )
        }))?;
    }

    // the target circle
    if let Some(t) = c.target {
        let mut ring = circle_at(view((t.x, t.y)), t.radius);
        ring.push(ring[0]);
        chart.draw_series([PathElement::new(ring, WHITE.stroke_width(2))])?;
        chart.draw_series([Text::new(
            "target",
            view((t.x - t.radius - 0.01, t.y)),
            ("sans-serif", 15)
                .into_font()
                .color(&WHITE)
                .pos(Pos::new(HPos::Center, VPos::Top)),
        )])?;
    }

    // the intended shot, simulated to rest: the cue ball's and the intended ball's paths
    let limits = Limits {
        max_events: 10_000,
        max_time: 600.0,
    };
    if let Ok(shot) = record(table, c.params, limits, &c.initial(), Some((c.cue, c.shot))) {
        for (k, style) in [
            (c.cue, WHITE.mix(0.85).stroke_width(2)),
            (c.intended, RGBColor(255, 220, 60).mix(0.9).stroke_width(2)),
        ] {
            let pts: Vec<(f64, f64)> = shot.traces[k].points.iter().map(|&p| view(p)).collect();
            if pts.len() > 1 {
                chart.draw_series([PathElement::new(pts, style)])?;
            }
        }
    }

    // the balls where they start
    for (k, b) in c.balls.iter().enumerate() {
        let at = view((b.x, b.y));
        chart.draw_series([Polygon::new(circle_at(at, r), id_colour(&b.id).filled())])?;
        let mut ring = circle_at(at, r);
        ring.push(ring[0]);
        let edge = if k == c.intended {
            RGBColor(255, 220, 60).stroke_width(3)
        } else {
            BLACK.stroke_width(1)
        };
        chart.draw_series([PathElement::new(ring, edge)])?;
        let label = if k == c.cue {
            String::new()
        } else {
            b.id.clone()
        };
        let ink = if b.id == "8" { WHITE } else { BLACK };
        chart.draw_series([Text::new(
            label,
            at,
            ("sans-serif", 13)
                .into_font()
                .style(FontStyle::Bold)
                .color(&ink)
                .pos(Pos::new(HPos::Center, VPos::Center)),
        )])?;
    }

    // scratches, at the pocket they went into
    if s.until == Until::Rest {
        let mut per_pocket = vec![0usize; table.pockets.len()];
        for smp in samples {
            if let Some(p) = smp.pocket_of(c.cue) {
                per_pocket[p] += 1;
            }
        }
        for (p, &k) in per_pocket.iter().enumerate() {
            if k == 0 {
                continue;
            }
            let centre = table.pockets[p].center;
            let at = view((centre.x, centre.y));
            chart.draw_series([Polygon::new(
                circle_at(at, table.pockets[p].radius * 0.8),
                SCRATCH.filled(),
            )])?;
            chart.draw_series([Text::new(
                format!("scratch {:.1}%", 100.0 * k as f64 / s.samples.max(1) as f64),
                (at.0, at.1 - table.pockets[p].radius - 0.01),
                ("sans-serif", 17)
                    .into_font()
                    .style(FontStyle::Bold)
                    .color(&WHITE)
                    .pos(Pos::new(HPos::Center, VPos::Top)),
            )])?;
        }
    }

    // legend, below the table
    let y = ch as i32 + 8;
    let x = left as i32;
    let font = ("sans-serif", 16).into_font();
    let mut at = x;
    let pocket = c.pocket_id().map_or(String::new(), |p| format!(" in {p}"));
    let intended = c.intended_id();
    let entries: Vec<(RGBColor, String)> = if let (Until::Rest, Some(g)) = (s.until, &s.game) {
        vec![
            (
                POT,
                format!("cue ball stopped here, the table kept ({})", g.rules.name()),
            ),
            (MISS, "stopped here, the turn passes".to_owned()),
            (SCRATCH, "scratch (cue ball potted)".to_owned()),
        ]
    } else if s.until == Until::Rest {
        vec![
            (
                POT,
                format!("cue ball stopped here, {intended} potted{pocket}"),
            ),
            (MISS, format!("stopped here, {intended} not potted")),
            (SCRATCH, "scratch (cue ball potted)".to_owned()),
        ]
    } else {
        Vec::new()
    };
    for (colour, label) in &entries {
        area.draw(&Rectangle::new(
            [(at, y + 3), (at + 14, y + 17)],
            colour.filled(),
        ))?;
        area.draw(&Text::new(label.clone(), (at + 20, y), font.clone()))?;
        at += 40 + 8 * label.chars().count() as i32;
    }
    area.draw(&Text::new(
        format!(
            "Heat map: {} cm cells, stronger where more samples stopped. White line: the cue \
             ball's path on the intended shot; yellow: ball {intended}'s.",
            CELL * 100.0
        ),
        (x, y + 24),
        font.color(&TEXT_GREY),
    ))?;
    Ok(())
}

/// Horizontal bars: label, fraction and its Wilson interval, in `colour`.
fn bars(area: &Area, title: &str, rows: &[(String, usize, RGBColor)], n: usize) -> DrawResult {
    let (w, _) = area.dim_in_pixel();
    area.draw(&Text::new(
        title.to_owned(),
        (10, 8),
        ("sans-serif", 19).into_font().style(FontStyle::Bold),
    ))?;
    let bar_x = 10;
    let bar_w = (w as i32 - 30).max(50);
    let mut y = 40;
    for (label, k, colour) in rows {
        let frac = *k as f64 / n.max(1) as f64;
        let (lo, hi) = wilson(*k, n);
        area.draw(&Text::new(
            format!("{label}: {}", share(*k, n)),
            (bar_x, y),
            ("sans-serif", 15).into_font(),
        ))?;
        let top = y + 20;
        area.draw(&Rectangle::new(
            [(bar_x, top), (bar_x + bar_w, top + 14)],
            RGBColor(230, 230, 230).filled(),
        ))?;
        let px = |f: f64| bar_x + (f * bar_w as f64).round() as i32;
        area.draw(&Rectangle::new(
            [(bar_x, top), (px(frac), top + 14)],
            colour.filled(),
        ))?;
        area.draw(&PathElement::new(
            vec![(px(lo), top + 7), (px(hi), top + 7)],
            BLACK.stroke_width(2),
        ))?;
        for f in [lo, hi] {
            area.draw(&PathElement::new(
                vec![(px(f), top + 2), (px(f), top + 12)],
                BLACK.stroke_width(2),
            ))?;
        }
        y += 46;
    }
    Ok(())
}

/// The outcome column: pot / pot + scratch / scratch / miss, and the position play.
fn draw_outcomes(area: &Area, c: &StudyConfig, s: &Summary) -> DrawResult {
    let n = s.samples;
    let intended = c.intended_id();
    let mut rows: Vec<(String, usize, RGBColor)> = Vec::new();
    if s.until == Until::Rest {
        for r in Result4::ALL {
            let label = match r {
                Result4::Pot => format!("pot ({intended} in)"),
                Result4::PotScratch => "pot + scratch".to_owned(),
                Result4::Scratch => "scratch only".to_owned(),
                Result4::Miss => "miss".to_owned(),
            };
            rows.push((label, s.result(r), colour(r)));
        }
        rows.push(("no ball hit (foul)".to_owned(), s.no_ball_hit, TEXT_GREY));
        for &(b, k) in &s.others_potted {
            rows.push((format!("ball {} potted", c.balls[b].id), k, TEXT_GREY));
        }
        if let Some(k) = s.in_target {
            rows.push((
                "cue ball in the target".to_owned(),
                k,
                RGBColor(40, 140, 90),
            ));
        }
        if let Some(g) = &s.game {
            let name = g.rules.name();
            rows.push((
                format!("legal shot ({name})"),
                g.legal,
                RGBColor(40, 140, 90),
            ));
            for (f, &k) in kisstime::game::Foul::ALL.iter().zip(&g.fouls) {
                if k > 0 {
                    rows.push((format!("foul: {}", f.code()), k, MISS));
                }
            }
            rows.push(("table kept".to_owned(), g.turn_kept, POT));
        }
        if s.cut > 0 {
            rows.push(("cut by a cap".to_owned(), s.cut, BLACK));
        }
    }
    let mut title = "Outcome (95% intervals)".to_owned();
    if s.until != Until::Rest {
        title = "Run to the first contact only".to_owned();
    }
    bars(area, &title, &rows, n)
}

/// The first contacts, as bars.
fn draw_first_contacts(area: &Area, c: &StudyConfig, s: &Summary) -> DrawResult {
    let rows: Vec<(String, usize, RGBColor)> = s
        .first
        .iter()
        .filter(|&&(class, k)| k > 0 || class == Class::Ball(c.intended))
        .map(|&(class, k)| {
            let (label, colour) = match class {
                Class::Ball(b) if b == c.intended => {
                    (format!("ball {} (intended)", c.balls[b].id), POT)
                }
                Class::Ball(b) => (format!("ball {}", c.balls[b].id), MISS),
                Class::Cushion => ("cushion".to_owned(), TEXT_GREY),
                Class::Pocket => ("pocket".to_owned(), SCRATCH),
                Class::Stopped => ("stopped".to_owned(), TEXT_GREY),
                Class::Nothing => ("nothing".to_owned(), TEXT_GREY),
            };
            (label, k, colour)
        })
        .collect();
    bars(area, "What the cue ball hit first", &rows, s.samples)
}

fn draw_histogram(area: &Area, c: &StudyConfig, samples: &[Sample]) -> DrawResult {
    let intended = c.intended_id();
    let hit = FirstContact::Ball(c.intended as u32);
    let mut cuts: Vec<(f64, bool)> = samples
        .iter()
        .filter(|s| s.first == hit && s.cut_angle.is_finite())
        .map(|s| (s.cut_angle, potted_as_called(c, s)))
        .collect();
    let caption = format!(
        "Cut angle on ball {intended} when it is hit first ({} of {} samples)",
        cuts.len(),
        samples.len()
    );
    if cuts.is_empty() {
        area.draw(&Text::new(
            format!("Ball {intended} is never hit first"),
            (40, 40),
            ("sans-serif", 20).into_font(),
        ))?;
        return Ok(());
    }
    cuts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut lo, mut hi) = (cuts[0].0, cuts[cuts.len() - 1].0);
    if hi - lo < 1e-6 {
        lo -= 0.5;
        hi += 0.5;
    }
    let bins = 48;
    let width = (hi - lo) / bins as f64;
    // per bin: potted, not potted (stacked)
    let mut counts = vec![[0usize; 2]; bins];
    for &(a, potted) in &cuts {
        let k = (((a - lo) / width) as usize).min(bins - 1);
        counts[k][usize::from(!potted)] += 1;
    }
    let top = counts.iter().map(|v| v[0] + v[1]).max().unwrap_or(1) as f64 * 1.15;
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 19))
        .margin(15)
        .x_label_area_size(60)
        .y_label_area_size(60)
        .build_cartesian_2d(lo..hi, 0.0..top)?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .light_line_style(WHITE)
        .y_labels(6)
        .y_label_formatter(&|v| format!("{v:.0}"))
        .x_label_formatter(&|v| format!("{v:.1}°"))
        .x_desc("cut angle (degrees; 0 = full ball, + = object ball goes left)")
        .y_desc("samples")
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()?;
    let pocket = c.pocket_id().map_or(String::new(), |p| format!(" in {p}"));
    chart
        .draw_series(counts.iter().enumerate().map(|(k, v)| {
            let x = lo + k as f64 * width;
            Rectangle::new([(x, 0.0), (x + width, v[0] as f64)], POT.filled())
        }))?
        .label(format!("{intended} potted{pocket}"))
        .legend(|(x, y)| Rectangle::new([(x, y - 6), (x + 14, y + 6)], POT.filled()));
    chart
        .draw_series(counts.iter().enumerate().map(|(k, v)| {
            let x = lo + k as f64 * width;
            Rectangle::new(
                [(x, v[0] as f64), (x + width, (v[0] + v[1]) as f64)],
                MISS.filled(),
            )
        }))?
        .label(format!("{intended} not potted"))
        .legend(|(x, y)| Rectangle::new([(x, y - 6), (x + 14, y + 6)], MISS.filled()));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font(("sans-serif", 15))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}
