//! The picture of a shot study (`kisstime shots --plot study.png`): the table seen from
//! above with the balls to scale and the intended path, where the cue ball was at its first
//! contact in every sample (coloured by what it touched), a close-up of the contacts around
//! the intended ball, and the histogram of the cut angle on it.
//!
//! Drawn with `plotters` into memory and written as PNG atomically; the text uses DejaVu
//! Sans compiled in from the `dejavu` crate, so no system font is needed.

use std::path::Path;
use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

use kisstime::Error;
use kisstime::motion::ball_path;
use kisstime::study::cue_ball::end_of_motion;
use kisstime::study::strike::cue_strike;
use kisstime::study::{Class, Outcome, Sample, StudyConfig, Summary, simulate_one};

/// Picture size in pixels.
const SIZE: (u32, u32) = (1600, 1150);
/// Height of the table panel.
const TABLE_PANEL: u32 = 640;

const CLOTH: RGBColor = RGBColor(38, 104, 74);
const RAIL: RGBColor = RGBColor(92, 56, 32);
const POCKET: RGBColor = RGBColor(20, 20, 20);
const OBJECT: RGBColor = RGBColor(235, 205, 120);
const INTENDED_FILL: RGBColor = RGBColor(255, 196, 0);
const INTENDED_HIT: RGBColor = RGBColor(70, 170, 255);
const OTHER_HIT: RGBColor = RGBColor(235, 45, 60);
const CUSHION_HIT: RGBColor = RGBColor(255, 140, 0);
const STOPPED: RGBColor = RGBColor(200, 200, 200);

static FONTS: Once = Once::new();

/// Registers the compiled-in fonts (once).
pub(super) fn fonts() {
    FONTS.call_once(|| {
        // the bytes are a valid font: failure would only mean missing text
        let _ = register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular());
        let _ = register_font("sans-serif", FontStyle::Bold, dejavu::sans::bold());
    });
}

/// A drawing failure as an I/O error of the picture.
pub(super) fn plot_error(e: impl std::fmt::Display) -> Error {
    Error::Io {
        path: String::new(),
        source: std::io::Error::other(format!("drawing the picture: {e}")),
    }
}

/// The colour of a sample's outcome.
fn colour(outcome: Outcome, intended: i64) -> RGBColor {
    match outcome {
        Outcome::Ball(id) if id == intended => INTENDED_HIT,
        Outcome::Ball(_) => OTHER_HIT,
        Outcome::Cushion(_) => CUSHION_HIT,
        Outcome::Stopped => STOPPED,
    }
}

/// A circle as a polygon in data coordinates.
pub(super) fn circle(x: f64, y: f64, r: f64) -> Vec<(f64, f64)> {
    (0..64)
        .map(|k| {
            let a = k as f64 / 64.0 * std::f64::consts::TAU;
            (x + r * a.cos(), y + r * a.sin())
        })
        .collect()
}

/// The intended shot's path (points of the cue ball's centre) up to its first event.
fn intended_path(scenario: &StudyConfig) -> Vec<(f64, f64)> {
    let p = &scenario.params;
    let end = simulate_one(scenario, &scenario.shot, 2.0 * p.radius);
    let start = scenario.cue_spot();
    let mut ball = cue_strike(start.x, start.y, &scenario.shot, p.radius, &scenario.masses);
    let mut points = vec![(ball.x, ball.y)];
    let mut t0 = 0.0;
    while ball.state.translates() && t0 < end.t {
        let path = ball_path(&ball, p);
        let span = path.tmax.min(end.t - t0);
        // a few points per motion: plotters rounds every segment to whole pixels
        for k in 1..=6 {
            let t = span * k as f64 / 6.0;
            let r = path.at(t);
            points.push((r.x, r.y));
        }
        let (next, dt) = end_of_motion(&ball, p);
        ball = next;
        t0 += dt;
    }
    points
}

/// Draws the study and writes it as a PNG to `path` (atomically).
pub fn write_study_png(
    path: &Path,
    scenario: &StudyConfig,
    samples: &[Sample],
    summary: &Summary,
) -> Result<(), Error> {
    let png = render_png(scenario, samples, summary)?;
    kisstime::io::write_output(Some(path), |w| {
        w.write_all(&png).map_err(kisstime::io::output_error)
    })
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

/// RGB pixels of a `size` picture as PNG bytes.
pub(super) fn encode_png(rgb: &[u8], size: (u32, u32)) -> Result<Vec<u8>, Error> {
    let (w, h) = size;
    let mut png = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut png, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header().map_err(plot_error)?;
        writer.write_image_data(rgb).map_err(plot_error)?;
    }
    Ok(png)
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;
type DrawResult = Result<(), Box<dyn std::error::Error + 'static>>;

fn draw(root: &Area, scenario: &StudyConfig, samples: &[Sample], summary: &Summary) -> DrawResult {
    let n = samples.len();
    let pct = |class: Class| 100.0 * summary.count(class) as f64 / n.max(1) as f64;
    let mut title = format!(
        "Shot study: {n} noisy strikes. First contact: ball {} (intended) {:.1}%",
        scenario.object_ball,
        pct(Class::Ball(scenario.object_ball))
    );
    for &(class, k) in &summary.counts {
        if k == 0 {
            continue;
        }
        match class {
            Class::Ball(id) if id != scenario.object_ball => {
                title += &format!(", ball {id} {:.1}%", pct(class));
            }
            Class::Cushion => title += &format!(", cushion {:.1}%", pct(class)),
            Class::Stopped => title += &format!(", stopped {:.1}%", pct(class)),
            _ => {}
        }
    }
    let (head, body) = root.split_vertically(46);
    head.draw(&Text::new(
        title,
        (20, 12),
        ("sans-serif", 24).into_font().style(FontStyle::Bold),
    ))?;
    let (top, bottom) = body.split_vertically(TABLE_PANEL);
    draw_table(&top, scenario, samples)?;
    let (left, right) = bottom.split_horizontally(760);
    draw_closeup(&left, scenario, samples)?;
    draw_histogram(&right, scenario, samples)?;
    Ok(())
}

/// The legend entries: colour and label.
fn legend(scenario: &StudyConfig) -> Vec<(RGBColor, String)> {
    vec![
        (
            INTENDED_HIT,
            format!("hit ball {} first (intended)", scenario.object_ball),
        ),
        (OTHER_HIT, "hit another ball first".to_owned()),
        (CUSHION_HIT, "reached a cushion first".to_owned()),
        (STOPPED, "stopped".to_owned()),
    ]
}

fn draw_table(area: &Area, scenario: &StudyConfig, samples: &[Sample]) -> DrawResult {
    let t = scenario.table;
    let r = scenario.params.radius;
    let rail = 0.09;
    // equal scales: fit the table and its rails into the panel
    let (pw, ph) = area.dim_in_pixel();
    let (x0, x1) = (-rail, t.length + rail);
    let (y0, y1) = (-rail, t.width + rail);
    let margin = 30.0;
    let scale = ((pw as f64 - 2.0 * margin) / (x1 - x0)).min((ph as f64 - 60.0) / (y1 - y0));
    let (cw, ch) = ((x1 - x0) * scale, (y1 - y0) * scale);
    let left = ((pw as f64 - cw) / 2.0) as i32;
    let inner = area.margin(10, 0, left.max(0) as u32, 0);
    let inner = inner.shrink((0, 0), (cw as u32, ch as u32));
    let mut chart = ChartBuilder::on(&inner).build_cartesian_2d(x0..x1, y0..y1)?;
    // rails, cloth, pockets
    chart.draw_series([Rectangle::new([(x0, y0), (x1, y1)], RAIL.filled())])?;
    chart.draw_series([Rectangle::new(
        [(0.0, 0.0), (t.length, t.width)],
        CLOTH.filled(),
    )])?;
    let pockets = [
        (0.0, 0.0),
        (t.length / 2.0, 0.0),
        (t.length, 0.0),
        (0.0, t.width),
        (t.length / 2.0, t.width),
        (t.length, t.width),
    ];
    chart.draw_series(
        pockets
            .iter()
            .map(|&(x, y)| Polygon::new(circle(x, y, 0.055), POCKET.filled())),
    )?;
    // the cushion lines the cue ball's centre cannot cross
    chart.draw_series([PathElement::new(
        vec![
            (r, r),
            (t.length - r, r),
            (t.length - r, t.width - r),
            (r, t.width - r),
            (r, r),
        ],
        RGBColor(90, 150, 115).stroke_width(1),
    )])?;
    // the intended path
    chart.draw_series([PathElement::new(
        intended_path(scenario),
        WHITE.mix(0.7).stroke_width(2),
    )])?;
    draw_balls(&mut chart, scenario, 15)?;
    // every sample's cue-ball centre at its first event
    chart.draw_series(samples.iter().map(|s| {
        Circle::new(
            (s.cue.x, s.cue.y),
            2,
            colour(s.outcome, scenario.object_ball).filled(),
        )
    }))?;
    // legend, below the table
    let font = ("sans-serif", 17).into_font();
    let y = 10 + (ch + 12.0) as i32;
    let mut x = left;
    for (c, label) in legend(scenario) {
        area.draw(&Circle::new((x + 8, y + 10), 7, c.filled()))?;
        area.draw(&Text::new(label.clone(), (x + 22, y), font.clone()))?;
        x += 40 + 9 * label.chars().count() as i32;
    }
    area.draw(&Text::new(
        "Dots: the cue ball's centre at its first contact in each sample. \
         White line: the intended shot.",
        (left, y + 26),
        font.color(&RGBColor(70, 70, 70)),
    ))?;
    Ok(())
}

type Chart<'a, 'b> = ChartContext<
    'a,
    BitMapBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// The balls to scale, labelled; `font` is the label size in pixels.
fn draw_balls(chart: &mut Chart, scenario: &StudyConfig, font: u32) -> DrawResult {
    let r = scenario.params.radius;
    let (xs, ys) = (chart.x_range(), chart.y_range());
    for b in &scenario.balls {
        if b.x + r < xs.start || b.x - r > xs.end || b.y + r < ys.start || b.y - r > ys.end {
            continue;
        }
        let (fill, label) = if b.id == scenario.cue_ball {
            (WHITE, String::new())
        } else if b.id == scenario.object_ball {
            (INTENDED_FILL, b.id.to_string())
        } else {
            (OBJECT, b.id.to_string())
        };
        chart.draw_series([Polygon::new(circle(b.x, b.y, r), fill.filled())])?;
        let mut outline = circle(b.x, b.y, r);
        outline.push(outline[0]);
        chart.draw_series([PathElement::new(outline, BLACK.stroke_width(1))])?;
        let style = ("sans-serif", font)
            .into_font()
            .style(FontStyle::Bold)
            .color(&BLACK)
            .pos(plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Center,
                plotters::style::text_anchor::VPos::Center,
            ));
        if b.id == scenario.cue_ball {
            // "cue ball" under the ball: it does not fit inside
            let below = style.clone().color(&WHITE);
            chart.draw_series([Text::new("cue ball", (b.x, b.y - 2.2 * r), below)])?;
        } else {
            chart.draw_series([Text::new(label, (b.x, b.y), style)])?;
        }
    }
    Ok(())
}

fn draw_closeup(area: &Area, scenario: &StudyConfig, samples: &[Sample]) -> DrawResult {
    let r = scenario.params.radius;
    // frame the balls that were hit first and the contacts on them
    let hits: Vec<&Sample> = samples
        .iter()
        .filter(|s| matches!(s.outcome, Outcome::Ball(_)))
        .collect();
    let intended = scenario
        .balls
        .iter()
        .find(|b| b.id == scenario.object_ball)
        .expect("validated");
    let (mut lo_x, mut hi_x, mut lo_y, mut hi_y) = (intended.x, intended.x, intended.y, intended.y);
    for s in &hits {
        lo_x = lo_x.min(s.cue.x);
        hi_x = hi_x.max(s.cue.x);
        lo_y = lo_y.min(s.cue.y);
        hi_y = hi_y.max(s.cue.y);
        if let Outcome::Ball(id) = s.outcome
            && let Some(b) = scenario.balls.iter().find(|b| b.id == id)
        {
            lo_x = lo_x.min(b.x);
            hi_x = hi_x.max(b.x);
            lo_y = lo_y.min(b.y);
            hi_y = hi_y.max(b.y);
        }
    }
    let pad = 2.0 * r;
    let (cx, cy) = (0.5 * (lo_x + hi_x), 0.5 * (lo_y + hi_y));
    let (cap, body) = area.split_vertically(36);
    cap.draw(&Text::new(
        "Close-up: the cue ball's centre at contact (\"ghost ball\")",
        (cap.dim_in_pixel().0 as i32 / 2, 12),
        ("sans-serif", 20)
            .into_font()
            .color(&BLACK)
            .pos(plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Center,
                plotters::style::text_anchor::VPos::Top,
            )),
    ))?;
    // equal scales: the plotting area is the body less the margins and label areas
    let (margin, x_labels, y_labels) = (15u32, 40u32, 60u32);
    let (pw, ph) = body.dim_in_pixel();
    let plot_w = f64::from(pw - 2 * margin - y_labels);
    let plot_h = f64::from(ph - 2 * margin - x_labels);
    let half_w = (0.5 * (hi_x - lo_x) + pad).max((0.5 * (hi_y - lo_y) + pad) * plot_w / plot_h);
    let half_h = half_w * plot_h / plot_w;
    let mut chart = ChartBuilder::on(&body)
        .margin(margin)
        .x_label_area_size(x_labels)
        .y_label_area_size(y_labels)
        .build_cartesian_2d(cx - half_w..cx + half_w, cy - half_h..cy + half_h)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("x (m)")
        .y_desc("y (m)")
        .label_style(("sans-serif", 14))
        .x_labels(6)
        .y_labels(5)
        .draw()?;
    chart.draw_series([Rectangle::new(
        [(cx - half_w, cy - half_h), (cx + half_w, cy + half_h)],
        CLOTH.filled(),
    )])?;
    draw_balls(&mut chart, scenario, 22)?;
    // ghost-ball outlines of a few contacts, then every contact centre
    let ghost = WHITE.mix(0.08);
    for s in hits.iter().step_by((hits.len() / 60).max(1)) {
        let mut o = circle(s.cue.x, s.cue.y, r);
        o.push(o[0]);
        chart.draw_series([PathElement::new(o, ghost.stroke_width(1))])?;
    }
    chart.draw_series(hits.iter().map(|s| {
        Circle::new(
            (s.cue.x, s.cue.y),
            2,
            colour(s.outcome, scenario.object_ball).filled(),
        )
    }))?;
    Ok(())
}

fn draw_histogram(area: &Area, scenario: &StudyConfig, samples: &[Sample]) -> DrawResult {
    let mut cuts: Vec<f64> = samples
        .iter()
        .filter(|s| s.outcome == Outcome::Ball(scenario.object_ball))
        .map(|s| s.cut)
        .collect();
    let caption = format!(
        "Cut angle on ball {} when it is hit first ({} of {} samples)",
        scenario.object_ball,
        cuts.len(),
        samples.len()
    );
    if cuts.is_empty() {
        area.draw(&Text::new(
            format!("Ball {} is never hit first", scenario.object_ball),
            (40, 40),
            ("sans-serif", 20).into_font(),
        ))?;
        return Ok(());
    }
    cuts.sort_by(f64::total_cmp);
    let q = |p: f64| cuts[((cuts.len() - 1) as f64 * p).round() as usize];
    let (mut lo, mut hi) = (cuts[0], cuts[cuts.len() - 1]);
    if hi - lo < 1e-6 {
        lo -= 0.5;
        hi += 0.5;
    }
    let bins = 40;
    let width = (hi - lo) / bins as f64;
    let mut counts = vec![0usize; bins];
    for &c in &cuts {
        if c >= lo && c <= hi {
            counts[(((c - lo) / width) as usize).min(bins - 1)] += 1;
        }
    }
    let top = *counts.iter().max().unwrap_or(&1) as f64 * 1.1;
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 20))
        .margin(15)
        .x_label_area_size(70)
        .y_label_area_size(70)
        .build_cartesian_2d(lo..hi, 0.0..top)?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .light_line_style(WHITE)
        .y_labels(6)
        .y_label_formatter(&|v| format!("{v:.0}"))
        .x_label_formatter(&|v| format!("{v:.0}°"))
        .x_desc("cut angle (degrees; 0 = full ball, + = object ball goes left)")
        .y_desc("samples")
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()?;
    chart.draw_series(counts.iter().enumerate().map(|(k, &c)| {
        let x = lo + k as f64 * width;
        Rectangle::new([(x, 0.0), (x + width, c as f64)], INTENDED_HIT.filled())
    }))?;
    // the intended shot's cut angle and the central 90 %
    let intended = simulate_one(scenario, &scenario.shot, 2.0 * scenario.params.radius);
    if intended.outcome == Outcome::Ball(scenario.object_ball) && intended.cut.is_finite() {
        chart
            .draw_series([PathElement::new(
                vec![(intended.cut, 0.0), (intended.cut, top)],
                BLACK.stroke_width(2),
            )])?
            .label(format!("intended shot: {:.2}°", intended.cut))
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2)));
    }
    let (p5, p95) = (q(0.05), q(0.95));
    chart
        .draw_series([
            PathElement::new(vec![(p5, 0.0), (p5, top)], OTHER_HIT.stroke_width(1)),
            PathElement::new(vec![(p95, 0.0), (p95, top)], OTHER_HIT.stroke_width(1)),
        ])?
        .label(format!("5th and 95th percentiles: {p5:.1}° and {p95:.1}°"))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], OTHER_HIT.stroke_width(1)));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font(("sans-serif", 15))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}
