//! What the pictures share (`kisstime shots --plot`, `kisstime simulate --plot`): the
//! compiled-in fonts, PNG encoding, the table drawn from above to scale — rails, cloth,
//! cushion segments, jaws and pockets, from the table's own items — and the ball colours.
//!
//! The table is turned a quarter turn clockwise so that its long side runs across the
//! picture: the head (small y) is on the left, and table +x points down ([`view`]).

use std::sync::Once;

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

use kisstime::Error;
use kisstime::model::Table;

/// The frame around the playing surface, in metres (rails and pockets).
const FRAME: f64 = 0.16;

pub(super) const CLOTH: RGBColor = RGBColor(38, 104, 74);
pub(super) const RAIL: RGBColor = RGBColor(92, 56, 32);
pub(super) const CUSHION: RGBColor = RGBColor(24, 70, 48);
pub(super) const POCKET: RGBColor = RGBColor(15, 15, 15);

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

/// A circle as a polygon in data coordinates.
pub(super) fn circle(x: f64, y: f64, r: f64) -> Vec<(f64, f64)> {
    (0..64)
        .map(|k| {
            let a = k as f64 / 64.0 * std::f64::consts::TAU;
            (x + r * a.cos(), y + r * a.sin())
        })
        .collect()
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

/// The colour of ball `id` (pool's usual colours: 0 the cue ball, 1–7 solids, 8 black,
/// 9–15 the stripes, drawn lighter).
pub(super) fn ball_colour(id: i64) -> RGBColor {
    const SOLIDS: [RGBColor; 8] = [
        RGBColor(250, 250, 245),
        RGBColor(245, 200, 20),
        RGBColor(30, 70, 200),
        RGBColor(210, 30, 30),
        RGBColor(110, 40, 150),
        RGBColor(245, 120, 20),
        RGBColor(20, 130, 60),
        RGBColor(130, 30, 40),
    ];
    match id {
        0..=7 => SOLIDS[id as usize],
        8 => RGBColor(20, 20, 20),
        9..=15 => {
            let c = SOLIDS[(id - 8) as usize];
            RGBColor(
                ((c.0 as u16 + 255) / 2) as u8,
                ((c.1 as u16 + 255) / 2) as u8,
                ((c.2 as u16 + 255) / 2) as u8,
            )
        }
        _ => RGBColor(200, 180, 140),
    }
}

/// Table coordinates turned a quarter turn clockwise: `(x, y) → (y, −x)`.
pub(super) fn view((x, y): (f64, f64)) -> (f64, f64) {
    (y, -x)
}

/// The table's extent in table coordinates: every cushion end, jaw and pocket, framed.
fn extent(table: &Table) -> (f64, f64, f64, f64) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    let mut take = |x: f64, y: f64, r: f64| {
        x0 = x0.min(x - r);
        x1 = x1.max(x + r);
        y0 = y0.min(y - r);
        y1 = y1.max(y + r);
    };
    for s in &table.linear {
        take(s.p1.x, s.p1.y, 0.0);
        take(s.p2.x, s.p2.y, 0.0);
    }
    for c in &table.circular {
        take(c.center.x, c.center.y, c.radius);
    }
    for p in &table.pockets {
        take(p.center.x, p.center.y, p.radius);
    }
    (x0 - FRAME, x1 + FRAME, y0 - FRAME, y1 + FRAME)
}

/// The cloth, turned for the picture: the convex hull of the straight cushions' ends (the
/// playing surface and the pocket throats between the jaws).
pub(super) fn cushion_outline(table: &Table) -> Vec<(f64, f64)> {
    let mut points: Vec<(f64, f64)> = table
        .linear
        .iter()
        .flat_map(|s| [(s.p1.x, s.p1.y), (s.p2.x, s.p2.y)])
        .collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    points.dedup();
    // Andrew's monotone chain: lower hull, then upper hull
    let turn = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut hull: Vec<(f64, f64)> = Vec::with_capacity(points.len() + 1);
    for pass in 0..2 {
        let start = hull.len();
        let ordered: Box<dyn Iterator<Item = &(f64, f64)>> = if pass == 0 {
            Box::new(points.iter())
        } else {
            Box::new(points.iter().rev())
        };
        for &p in ordered {
            while hull.len() >= start + 2
                && turn(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull.into_iter().map(view).collect()
}

/// A circle about `(x, y)` as a polygon.
pub(super) fn circle_at((x, y): (f64, f64), r: f64) -> Vec<(f64, f64)> {
    circle(x, y, r)
}

/// The range the turned table covers, in view coordinates (see [`view`]).
pub(super) fn view_range(table: &Table) -> (std::ops::Range<f64>, std::ops::Range<f64>) {
    let (x0, x1, y0, y1) = extent(table);
    (y0..y1, -x1..-x0)
}

/// The part of `area` (of `size` pixels, from its top left) that holds the turned table
/// at equal scales, centred across: the drawing area, its left offset and its height in
/// pixels.
pub(super) fn table_area<'a>(
    area: &DrawingArea<BitMapBackend<'a>, Shift>,
    table: &Table,
    size: (u32, u32),
) -> (DrawingArea<BitMapBackend<'a>, Shift>, u32, f64) {
    let (xs, ys) = view_range(table);
    let (bw, bh) = size;
    let scale = ((bw as f64 - 40.0) / (xs.end - xs.start)).min(bh as f64 / (ys.end - ys.start));
    let (cw, ch) = ((xs.end - xs.start) * scale, (ys.end - ys.start) * scale);
    let left = ((bw as f64 - cw) / 2.0).max(0.0) as u32;
    let inner = area
        .margin(0, 0, left, 0)
        .shrink((0, 0), (cw as u32, ch as u32));
    (inner, left, ch)
}

/// A chart in view coordinates.
pub(super) type TableChart<'a, 'b> =
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Draws the table: the rails, the cloth inside the cushion noses, the pockets, the
/// straight cushion segments and the jaw arcs.
pub(super) fn draw_table(
    chart: &mut TableChart<'_, '_>,
    table: &Table,
) -> Result<(), Box<dyn std::error::Error + 'static>> {
    let (xs, ys) = view_range(table);
    chart.draw_series([Rectangle::new(
        [(xs.start, ys.start), (xs.end, ys.end)],
        RAIL.filled(),
    )])?;
    chart.draw_series([Polygon::new(cushion_outline(table), CLOTH.filled())])?;
    for p in &table.pockets {
        chart.draw_series([Polygon::new(
            circle_at(view((p.center.x, p.center.y)), p.radius),
            POCKET.filled(),
        )])?;
    }
    for s in &table.linear {
        chart.draw_series([PathElement::new(
            vec![view((s.p1.x, s.p1.y)), view((s.p2.x, s.p2.y))],
            CUSHION.stroke_width(3),
        )])?;
    }
    for c in &table.circular {
        let mut ring = circle_at(view((c.center.x, c.center.y)), c.radius);
        ring.push(ring[0]);
        chart.draw_series([PathElement::new(ring, CUSHION.stroke_width(2))])?;
    }
    Ok(())
}
