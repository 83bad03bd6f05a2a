//! The picture of one simulated shot (`kisstime simulate … --plot shot.png --table-id K`):
//! the table from above — rails, cushions, jaws and pockets to scale — every ball's path
//! from the strike to rest, event markers (ball–ball contacts, cushion hits, pots) and the
//! final positions.
//!
//! The paths are the simulator's own closed forms: between two consecutive events every
//! ball moves on [`evolve`] from its state after the earlier one, sampled densely enough
//! that a massé curve is drawn as the curve it is, not as straight segments between events.
//! The table is turned a quarter turn clockwise so that its long side runs across the
//! picture: the head (small y) is on the left, and table +x points down.

use plotters::prelude::*;
use plotters::style::FontStyle;

use kisstime::Error;
use kisstime::model::{BallState, MotionState, SimParams, Table};
use kisstime::motion::evolve;
use kisstime::resolve::CueStrike;
use kisstime::simulate::{EventKind, EventLoop, Limits};

use super::draw::{
    ball_colour, circle_at, draw_table, encode_png, fonts, plot_error, table_area, view, view_range,
};

/// Picture size in pixels.
const SIZE: (u32, u32) = (1600, 960);
const KISS: RGBColor = RGBColor(255, 255, 255);
const RAIL_HIT: RGBColor = RGBColor(255, 150, 40);
const POT: RGBColor = RGBColor(255, 60, 60);
const CLOUD: RGBColor = RGBColor(120, 220, 255);

/// One ball's drawn path: points in table coordinates.
pub(super) struct Trace {
    pub points: Vec<(f64, f64)>,
}

/// An event worth a marker: where, and what.
pub(super) struct Marker {
    pub at: (f64, f64),
    pub kind: EventKind,
}

/// What the picture shows of a simulated shot.
pub(super) struct Shot {
    pub traces: Vec<Trace>,
    pub markers: Vec<Marker>,
    pub start: Vec<BallState>,
    pub end: Vec<BallState>,
    pub events: usize,
    pub duration: f64,
    pub cut: bool,
}

/// Simulates the shot and records what the picture needs: every ball's path sampled
/// along the closed forms between consecutive events (about one point per 2 mm of travel,
/// at least 8 per stretch), and a marker for every collision and pot.
pub(super) fn record(
    table: &Table,
    params: SimParams,
    limits: Limits,
    balls: &[BallState],
    strike: Option<(usize, CueStrike)>,
) -> Result<Shot, Error> {
    let mut sim = EventLoop::new(table, params, limits, balls.len())?;
    sim.reset(balls, strike)?;
    let mut traces: Vec<Trace> = balls
        .iter()
        .map(|b| Trace {
            points: vec![(b.r.x, b.r.y)],
        })
        .collect();
    let mut markers = Vec::new();
    let mut prev: Vec<BallState> = sim.balls().to_vec();
    let mut prev_t = sim.time();
    while let Some(event) = sim.step() {
        let dt = event.t - prev_t;
        for (trace, b) in traces.iter_mut().zip(&prev) {
            if !matches!(b.s, MotionState::Sliding | MotionState::Rolling) || dt <= 0.0 {
                continue;
            }
            let length = b.v.norm() * dt;
            let n = ((length / 0.002).ceil() as usize).clamp(8, 2000);
            for k in 1..=n {
                let s = evolve(b, dt * k as f64 / n as f64, &params.ball);
                trace.points.push((s.r.x, s.r.y));
            }
        }
        let now = sim.balls();
        let i = event.ball as usize;
        let at = match event.kind {
            EventKind::BallBall => {
                let (a, b) = (now[i].r, now[event.other as usize].r);
                Some((0.5 * (a.x + b.x), 0.5 * (a.y + b.y)))
            }
            EventKind::BallLinearCushion | EventKind::BallCircularCushion => {
                Some((now[i].r.x, now[i].r.y))
            }
            EventKind::BallPocket => {
                let c = table.pockets[event.other as usize].center;
                Some((c.x, c.y))
            }
            _ => None,
        };
        if let Some(at) = at {
            markers.push(Marker {
                at,
                kind: event.kind,
            });
        }
        if event.kind == EventKind::BallPocket {
            // the path ends at the pocket's centre, where the ball is stored
            let c = table.pockets[event.other as usize].center;
            traces[i].points.push((c.x, c.y));
        }
        prev.clear();
        prev.extend_from_slice(now);
        prev_t = event.t;
    }
    let outcome = sim.outcome();
    Ok(Shot {
        traces,
        markers,
        start: balls.to_vec(),
        end: sim.balls().to_vec(),
        events: outcome.n_events,
        duration: outcome.t_end,
        cut: outcome.cut.is_some(),
    })
}

/// Draws the shot of table `label` and returns it as PNG bytes. `ids` are the balls' ids
/// (for colours and labels), in the order of `balls`; `cloud`, where the cue ball ended
/// over a study of the strike under noise (drawn as small dots; empty: none).
#[allow(clippy::too_many_arguments)]
pub fn render_shot_png(
    table: &Table,
    params: SimParams,
    limits: Limits,
    balls: &[BallState],
    ids: &[i64],
    strike: Option<(usize, CueStrike)>,
    label: &str,
    cloud: &[(f64, f64)],
) -> Result<Vec<u8>, Error> {
    let shot = record(table, params, limits, balls, strike)?;
    fonts();
    let (w, h) = SIZE;
    let mut rgb = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        draw(&root, table, params.ball.r, &shot, ids, label, cloud).map_err(plot_error)?;
        root.present().map_err(plot_error)?;
    }
    encode_png(&rgb, SIZE)
}

type DrawResult = Result<(), Box<dyn std::error::Error + 'static>>;

fn draw(
    root: &DrawingArea<BitMapBackend, plotters::coord::Shift>,
    table: &Table,
    radius: f64,
    shot: &Shot,
    ids: &[i64],
    label: &str,
    cloud: &[(f64, f64)],
) -> DrawResult {
    let pots: Vec<String> = shot
        .end
        .iter()
        .zip(ids)
        .filter(|(b, _)| b.s == MotionState::Pocketed)
        .map(|(_, id)| id.to_string())
        .collect();
    let title = format!(
        "{label}: {} events in {:.2} s{}; potted: {}",
        shot.events,
        shot.duration,
        if shot.cut { " (cut by a limit)" } else { "" },
        if pots.is_empty() {
            "none".to_owned()
        } else {
            pots.join(", ")
        }
    );
    let (head, body) = root.split_vertically(50);
    head.draw(&Text::new(
        title,
        (20, 14),
        ("sans-serif", 24).into_font().style(FontStyle::Bold),
    ))?;
    let (bw, bh) = body.dim_in_pixel();
    let legend_h = 40;
    let (area, left, ch) = table_area(&body, table, (bw, bh - legend_h));
    let mut chart =
        ChartBuilder::on(&area).build_cartesian_2d(view_range(table).0, view_range(table).1)?;
    draw_table(&mut chart, table)?;
    // where the balls started
    for b in &shot.start {
        let mut ring = circle_at(view((b.r.x, b.r.y)), radius);
        ring.push(ring[0]);
        chart.draw_series([PathElement::new(ring, WHITE.mix(0.45).stroke_width(1))])?;
    }
    // where the cue ball ended under noise
    chart.draw_series(
        cloud
            .iter()
            .map(|&p| Circle::new(view(p), 2, CLOUD.mix(0.55).filled())),
    )?;
    // the paths
    for (trace, &id) in shot.traces.iter().zip(ids) {
        if trace.points.len() < 2 {
            continue;
        }
        let points: Vec<(f64, f64)> = trace.points.iter().map(|&p| view(p)).collect();
        chart.draw_series([PathElement::new(
            points,
            ball_colour(id).mix(0.9).stroke_width(2),
        )])?;
    }
    // the events
    for m in &shot.markers {
        let at = view(m.at);
        match m.kind {
            EventKind::BallBall => {
                chart.draw_series([Circle::new(at, 5, KISS.stroke_width(2))])?;
            }
            EventKind::BallPocket => {
                chart.draw_series([Circle::new(at, 7, POT.filled())])?;
            }
            _ => {
                chart.draw_series([Cross::new(at, 5, RAIL_HIT.stroke_width(2))])?;
            }
        }
    }
    // where they came to rest (pocketed balls are not on the table)
    for (b, &id) in shot.end.iter().zip(ids) {
        if b.s == MotionState::Pocketed {
            continue;
        }
        let at = view((b.r.x, b.r.y));
        chart.draw_series([Polygon::new(
            circle_at(at, radius),
            ball_colour(id).filled(),
        )])?;
        let mut ring = circle_at(at, radius);
        ring.push(ring[0]);
        chart.draw_series([PathElement::new(ring, BLACK.stroke_width(1))])?;
        let text = if id == 0 {
            String::new()
        } else {
            id.to_string()
        };
        let colour = if id == 8 { WHITE } else { BLACK };
        let style = ("sans-serif", 13)
            .into_font()
            .style(FontStyle::Bold)
            .color(&colour)
            .pos(plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Center,
                plotters::style::text_anchor::VPos::Center,
            ));
        chart.draw_series([Text::new(text, at, style)])?;
    }
    // legend, below the table
    let y = (ch + 10.0) as i32 + 50;
    let font = ("sans-serif", 17).into_font();
    let x = left as i32;
    root.draw(&Circle::new((x + 8, y + 10), 7, BLACK.filled()))?;
    root.draw(&Circle::new((x + 8, y + 10), 5, KISS.stroke_width(2)))?;
    root.draw(&Text::new("ball–ball", (x + 22, y), font.clone()))?;
    root.draw(&Cross::new((x + 128, y + 10), 6, RAIL_HIT.stroke_width(2)))?;
    root.draw(&Text::new("cushion or jaw", (x + 142, y), font.clone()))?;
    root.draw(&Circle::new((x + 298, y + 10), 7, POT.filled()))?;
    root.draw(&Text::new("pot", (x + 312, y), font.clone()))?;
    let note = if cloud.is_empty() {
        "Lines: each ball's path from the strike to rest (exact closed forms). Faint rings: \
         where the balls started; filled: where they stopped."
            .to_owned()
    } else {
        format!(
            "Lines: the intended strike, without noise. Blue dots: where the cue ball \
             stopped in {} plays of it under the noise (pots left out).",
            cloud.len()
        )
    };
    root.draw(&Text::new(
        note,
        (x + 370, y),
        font.color(&RGBColor(70, 70, 70)),
    ))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_break_and_a_masse_shot_draw() {
        let table = Table::nine_foot();
        let p = SimParams::default();
        let r = p.ball.r;
        // a short rack of three and a cue ball
        let balls = [
            BallState::at_rest(0.635, 0.6, r),
            BallState::at_rest(0.635, 1.905, r),
            BallState::at_rest(0.635 - r - 1e-4, 1.905 + 1.75 * r, r),
            BallState::at_rest(0.635 + r + 1e-4, 1.905 + 1.75 * r, r),
        ];
        let ids = [0, 1, 2, 3];
        let hard = CueStrike {
            v0: 6.0,
            phi: 90.0,
            theta: 0.0,
            a: 0.0,
            b: 0.0,
        };
        let png = render_shot_png(
            &table,
            p,
            Limits::default(),
            &balls,
            &ids,
            Some((0, hard)),
            "t",
            &[(0.5, 0.5), (0.6, 0.7)],
        )
        .unwrap();
        assert_eq!(&png[1..4], b"PNG");
        let shot = record(&table, p, Limits::default(), &balls, Some((0, hard))).unwrap();
        assert!(shot.markers.iter().any(|m| m.kind == EventKind::BallBall));
        // a massé: the cue ball's path curves, so its sampled points leave the straight line
        let masse = CueStrike {
            v0: 2.0,
            phi: 80.0,
            theta: 60.0,
            a: 0.4,
            b: 0.0,
        };
        let shot = record(&table, p, Limits::default(), &balls[..1], Some((0, masse))).unwrap();
        let pts = &shot.traces[0].points;
        assert!(pts.len() > 50, "{} points", pts.len());
        let (a, b) = (pts[0], pts[pts.len() / 4]);
        let c = pts[pts.len() / 8];
        let cross = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
        assert!(cross.abs() > 1e-6, "the massé path is curved");
    }
}
