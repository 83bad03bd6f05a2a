//! Table geometry (spec §6): straight cushion segments, circular cushion segments (the jaw
//! tips), and pockets, each kept in pooltool's dict order, which is the detection order
//! and so decides exact ties (spec §3).
//!
//! - [`Table::pocket_table`] builds pooltool's pocket table from [`PocketTableSpecs`] with
//!   the formulas of `objects/table/layout.py` (`create_pocket_table_cushion_segments`,
//!   `create_pocket_table_pockets`), restated in spec §6.2–6.4; [`Table::nine_foot`] is the
//!   9-ft one (`Table.from_table_specs(PocketTableSpecs(l=2.54, w=1.27))`).
//! - [`Table::rectangle`]: four rails and no pockets.
//! - [`Table::from_json`]: a table in the format of `data/fullshots/table.json`, checked.

use crate::error::SimError;
use crate::model::vec3::Vec3;
use std::f64::consts::PI;

/// The most segments or pockets of one kind a table may have (keeps the per-table caches
/// small and bounded; pooltool's pocket table has 18, 12 and 6).
pub const MAX_TABLE_ITEMS: usize = 256;

/// A straight cushion segment: endpoints at the cushion height, the line
/// `lx·x + ly·y + l0 = 0` through them (spec §6.1), and which side is checked
/// (`direction` 0 = SIDE1, the side where the line's value is < 0; 1 = SIDE2, > 0;
/// 2 = both).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearCushion {
    /// First endpoint (z = cushion height).
    pub p1: Vec3,
    /// Second endpoint.
    pub p2: Vec3,
    /// 0, 1 or 2 (see the type's docs).
    pub direction: u32,
    /// Line coefficient lx.
    pub lx: f64,
    /// Line coefficient ly.
    pub ly: f64,
    /// Line coefficient l0.
    pub l0: f64,
}

impl LinearCushion {
    /// The segment from `p1` to `p2` with pooltool's line coefficients
    /// (`LinearCushionSegment.lx/ly/l0`, spec §6.1): a vertical line (`p1.x == p2.x`) is
    /// `x − p1.x = 0`, otherwise with `k = Δy/Δx`: `−k x + y + (k p1.x − p1.y) = 0`.
    pub fn new(p1: Vec3, p2: Vec3, direction: u32) -> LinearCushion {
        let (lx, ly, l0) = if p2.x == p1.x {
            (1.0, 0.0, -p1.x)
        } else {
            let k = (p2.y - p1.y) / (p2.x - p1.x);
            (-k, 1.0, k * p1.x - p1.y)
        };
        LinearCushion {
            p1,
            p2,
            direction,
            lx,
            ly,
            l0,
        }
    }
}

/// A circular cushion segment (a jaw tip): centre at the cushion height, radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CircularCushion {
    /// Centre (z = cushion height).
    pub center: Vec3,
    /// Radius in m.
    pub radius: f64,
}

/// A pocket: a circle on the cloth (centre z = 0) the ball centre must enter, and the depth
/// a pocketed ball is stored at (spec §4.6, §5.5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pocket {
    /// Centre (a, b, 0).
    pub center: Vec3,
    /// Radius in m.
    pub radius: f64,
    /// Depth in m: a pocketed ball sits at z = −depth.
    pub depth: f64,
}

/// A table: the three kinds of boundary items in detection order, with their ids.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// Straight cushion segments.
    pub linear: Vec<LinearCushion>,
    /// Their ids (`"3"`, `"6"`, …), index for index.
    pub linear_ids: Vec<String>,
    /// Circular cushion segments.
    pub circular: Vec<CircularCushion>,
    /// Their ids (`"1t"`, …).
    pub circular_ids: Vec<String>,
    /// Pockets.
    pub pockets: Vec<Pocket>,
    /// Their ids (`"lb"`, …).
    pub pocket_ids: Vec<String>,
}

/// pooltool's `PocketTableSpecs` (`objects/table/specs.py`), lengths in m, angles in
/// degrees. The defaults are pooltool's, with the 9-ft playing surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PocketTableSpecs {
    /// Playing-surface length (along y).
    pub l: f64,
    /// Playing-surface width (along x).
    pub w: f64,
    /// Cushion width cw.
    pub cushion_width: f64,
    /// Cushion (nose) height h.
    pub cushion_height: f64,
    /// Corner pocket width.
    pub corner_pocket_width: f64,
    /// Corner pocket angle (deg).
    pub corner_pocket_angle: f64,
    /// Corner pocket depth (moves the pocket centre).
    pub corner_pocket_depth: f64,
    /// Corner pocket radius.
    pub corner_pocket_radius: f64,
    /// Corner jaw radius r_c.
    pub corner_jaw_radius: f64,
    /// Side pocket width sw.
    pub side_pocket_width: f64,
    /// Side pocket angle (deg).
    pub side_pocket_angle: f64,
    /// Side pocket depth (moves the pocket centre).
    pub side_pocket_depth: f64,
    /// Side pocket radius.
    pub side_pocket_radius: f64,
    /// Side jaw radius r_s.
    pub side_jaw_radius: f64,
}

impl Default for PocketTableSpecs {
    fn default() -> Self {
        PocketTableSpecs {
            l: 2.54,
            w: 1.27,
            cushion_width: 0.0508,
            cushion_height: 0.036576,
            corner_pocket_width: 0.118,
            corner_pocket_angle: 5.3,
            corner_pocket_depth: 0.0417,
            corner_pocket_radius: 0.062,
            corner_jaw_radius: 0.02095,
            side_pocket_width: 0.137,
            side_pocket_angle: 7.14,
            side_pocket_depth: 0.0685,
            side_pocket_radius: 0.0645,
            side_jaw_radius: 0.00795,
        }
    }
}

impl PocketTableSpecs {
    /// pooltool's default pocket table, `Table.default()` (its "7 Ft Showood", the table of
    /// its 8-ball and 9-ball games): the defaults with a 1.9812 × 0.9906 m playing surface,
    /// written as pooltool writes them (`objects/table/collection.py`).
    pub fn seven_foot() -> PocketTableSpecs {
        PocketTableSpecs {
            l: 1.9812,
            w: 1.9812 / 2.0,
            cushion_width: 2.0 * 2.54 / 100.0,
            cushion_height: 0.64 * 2.0 * 0.028575,
            ..PocketTableSpecs::default()
        }
    }
}

/// pooltool's `Pocket.depth` default (spec §1.4): the specs' depths only move the centre.
pub const POCKET_DEPTH: f64 = 0.08;

/// The quantities of spec §6 derived from the specs.
struct Derived {
    ca: f64,
    sa: f64,
    dc: f64,
    ds: f64,
    p: f64,
    y_lo: f64,
    y_hi: f64,
}

fn derive(s: &PocketTableSpecs) -> Derived {
    let ca = (s.corner_pocket_angle + 45.0) * PI / 180.0;
    let sa = s.side_pocket_angle * PI / 180.0;
    Derived {
        ca,
        sa,
        dc: s.corner_jaw_radius / ((PI / 2.0 + ca) / 2.0).tan(),
        ds: s.side_jaw_radius / ((PI / 2.0 + sa) / 2.0).tan(),
        p: s.corner_pocket_width * (PI / 4.0).cos(),
        y_lo: (s.l - s.side_pocket_width) / 2.0,
        y_hi: (s.l + s.side_pocket_width) / 2.0,
    }
}

/// The 18 straight segments of spec §6.2, in pooltool's order, as `(id, x1, y1, x2, y2,
/// direction)`.
fn pocket_table_lines(s: &PocketTableSpecs) -> [(&'static str, f64, f64, f64, f64, u32); 18] {
    let d = derive(s);
    let (l, w, cw) = (s.l, s.w, s.cushion_width);
    let (pc, cjx, cjy) = (
        d.p - cw * d.ca.tan(),
        d.p - d.dc * d.ca.sin(),
        d.dc * d.ca.cos(),
    );
    let (sjy, sjx, sjy2) = (cw * d.sa.sin(), d.ds * d.sa.cos(), d.ds * d.sa.sin());
    let (y7, y7b) = (-d.p + cw * d.ca.tan() + l, -d.p + l + d.dc * d.ca.sin());
    [
        ("3", 0.0, d.p + d.dc, 0.0, d.y_lo - d.ds, 1),
        ("6", 0.0, d.y_hi + d.ds, 0.0, l - d.p - d.dc, 1),
        ("15", w, d.p + d.dc, w, d.y_lo - d.ds, 0),
        ("12", w, d.y_hi + d.ds, w, l - d.p - d.dc, 0),
        ("18", d.p + d.dc, 0.0, w - d.p - d.dc, 0.0, 1),
        ("9", d.p + d.dc, l, w - d.p - d.dc, l, 0),
        ("5", -cw, d.y_hi - sjy, -sjx, d.y_hi - sjy2, 0),
        ("4", -cw, d.y_lo + sjy, -sjx, d.y_lo + sjy2, 1),
        ("13", w + cw, d.y_hi - sjy, w + sjx, d.y_hi - sjy2, 0),
        ("14", w + cw, d.y_lo + sjy, w + sjx, d.y_lo + sjy2, 1),
        ("1", pc, -cw, cjx, -cjy, 1),
        ("2", -cw, pc, -cjy, cjx, 0),
        ("8", pc, l + cw, cjx, l + cjy, 0),
        // in pooltool's order of operations (`-p + cw tan(ca) + l`, `-p + l + dc sin(ca)`),
        // which the 7-ft table's rounding tells from `l - pc`, `l - cjx`
        ("7", -cw, y7, -cjy, y7b, 1),
        ("11", w + cw, y7, w + cjy, y7b, 1),
        (
            "10",
            w - pc,
            l + cw,
            w - d.p + d.dc * d.ca.sin(),
            l + cjy,
            0,
        ),
        ("16", w + cw, pc, w + cjy, cjx, 0),
        ("17", w - pc, -cw, w - d.p + d.dc * d.ca.sin(), -cjy, 1),
    ]
}

/// The 12 jaw arcs of spec §6.3 as `(id, x, y, radius)`.
fn pocket_table_arcs(s: &PocketTableSpecs) -> [(&'static str, f64, f64, f64); 12] {
    let d = derive(s);
    let (l, w, rc, rs) = (s.l, s.w, s.corner_jaw_radius, s.side_jaw_radius);
    let (sw, pd) = (s.side_pocket_width, d.p + d.dc);
    [
        ("1t", pd, -rc, rc),
        ("2t", -rc, pd, rc),
        ("4t", -rs, l / 2.0 - sw / 2.0 - d.ds, rs),
        ("5t", -rs, l / 2.0 + sw / 2.0 + d.ds, rs),
        ("7t", -rc, l - pd, rc),
        ("8t", pd, l + rc, rc),
        ("10t", w - pd, l + rc, rc),
        ("11t", w + rc, l - pd, rc),
        ("13t", w + rs, l / 2.0 + sw / 2.0 + d.ds, rs),
        ("14t", w + rs, l / 2.0 - sw / 2.0 - d.ds, rs),
        ("16t", w + rc, pd, rc),
        ("17t", w - pd, -rc, rc),
    ]
}

/// The 6 pockets of spec §6.4 as `(id, x, y, radius)`.
fn pocket_table_pockets(s: &PocketTableSpecs) -> [(&'static str, f64, f64, f64); 6] {
    let (l, w) = (s.l, s.w);
    let cd = s.corner_pocket_depth / 2f64.sqrt();
    let sd = s.side_pocket_depth;
    let (cr, sr) = (s.corner_pocket_radius, s.side_pocket_radius);
    [
        ("lb", -cd, -cd, cr),
        ("lc", -sd, l / 2.0, sr),
        ("lt", -cd, l + cd, cr),
        ("rb", w + cd, -cd, cr),
        ("rc", w + sd, l / 2.0, sr),
        ("rt", w + cd, l + cd, cr),
    ]
}

impl Table {
    /// pooltool's pocket table for `specs` (spec §6).
    pub fn pocket_table(specs: &PocketTableSpecs) -> Table {
        let h = specs.cushion_height;
        let mut t = Table::empty();
        for (id, x1, y1, x2, y2, dir) in pocket_table_lines(specs) {
            let seg = LinearCushion::new(Vec3::new(x1, y1, h), Vec3::new(x2, y2, h), dir);
            t.linear.push(seg);
            t.linear_ids.push(id.to_owned());
        }
        for (id, x, y, radius) in pocket_table_arcs(specs) {
            let center = Vec3::new(x, y, h);
            t.circular.push(CircularCushion { center, radius });
            t.circular_ids.push(id.to_owned());
        }
        for (id, x, y, radius) in pocket_table_pockets(specs) {
            let center = Vec3::new(x, y, 0.0);
            let depth = POCKET_DEPTH;
            t.pockets.push(Pocket {
                center,
                radius,
                depth,
            });
            t.pocket_ids.push(id.to_owned());
        }
        t
    }

    /// The 9-ft pocket table of the reference set (`PocketTableSpecs(l=2.54, w=1.27)`).
    pub fn nine_foot() -> Table {
        Table::pocket_table(&PocketTableSpecs::default())
    }

    /// pooltool's default pocket table, `pt.Table.default()` ([`PocketTableSpecs::seven_foot`];
    /// bit-identical to `data/tables/7ft.json`, which pooltool's own table gives).
    pub fn seven_foot() -> Table {
        Table::pocket_table(&PocketTableSpecs::seven_foot())
    }

    /// A table with no cushions and no pockets (what the readers fill).
    pub fn empty() -> Table {
        Table {
            linear: Vec::new(),
            linear_ids: Vec::new(),
            circular: Vec::new(),
            circular_ids: Vec::new(),
            pockets: Vec::new(),
            pocket_ids: Vec::new(),
        }
    }

    /// A pocketless rectangle `[0, w] × [0, l]`: four rails at cushion height `h`, checked
    /// from inside (ids `left`, `right`, `bottom`, `top`). Errors unless `w`, `l` and `h`
    /// are finite and positive.
    pub fn rectangle(w: f64, l: f64, h: f64) -> Result<Table, SimError> {
        for (name, v) in [("w", w), ("l", l), ("cushion height", h)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(SimError::Table(format!("rectangle {name} = {v}")));
            }
        }
        let mut t = Table::empty();
        let rails = [
            ("left", (0.0, 0.0), (0.0, l), 1),
            ("right", (w, 0.0), (w, l), 0),
            ("bottom", (0.0, 0.0), (w, 0.0), 1),
            ("top", (0.0, l), (w, l), 0),
        ];
        for (id, a, b, dir) in rails {
            let seg = LinearCushion::new(Vec3::new(a.0, a.1, h), Vec3::new(b.0, b.1, h), dir);
            t.linear.push(seg);
            t.linear_ids.push(id.to_owned());
        }
        Ok(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spec_line_coefficients() {
        let t = Table::nine_foot();
        let five = &t.linear[6];
        assert_eq!(t.linear_ids[6], "5");
        assert!((five.lx + 0.12413996110140721).abs() < 1e-15);
        assert!((five.l0 + 1.338492163396652).abs() < 1e-14);
        assert_eq!(t.linear_ids[0], "3");
        assert_eq!((t.linear[0].lx, t.linear[0].ly), (1.0, 0.0));
    }

    #[test]
    fn rectangle_checks_its_sizes() {
        let r = Table::rectangle(1.0, 2.0, 0.03).unwrap();
        assert_eq!(r.linear.len(), 4);
        assert!(r.pockets.is_empty());
        assert!(Table::rectangle(-1.0, 2.0, 0.03).is_err());
    }
}
