//! Checks of a shot's starting layout that the event loop itself does not make: every
//! ball on the playing surface (not off the table, not inside a cushion) and no two balls
//! overlapping at rest. [`crate::simulate::simulate_batch`] runs them on every table
//! (unless told not to); they never panic and name the ball by its index in the table.
//!
//! "On the playing surface" is decided from the table's own items, so it holds for the
//! built-in tables and for any table read from JSON: the centre of a ball that is not
//! pocketed must be at least R − [`LAYOUT_TOLERANCE`] from every straight cushion segment
//! and from every jaw arc (not inside a cushion), and enclosed by the table: each of the
//! four rays from the centre along ±x and ±y must meet a cushion segment, a jaw or a pocket
//! circle (a ball behind a rail or away from the table has a ray that escapes), and not
//! over a pocket: a centre more than [`LAYOUT_TOLERANCE`] inside a pocket's circle is
//! refused (a ball there has fallen in: give it as pocketed; the `event_loop` fuzz
//! target's finding 8, FUZZING.md). A centre within the tolerance of the circle, where a
//! cushion's kiss can leave a ball mid-shot, is on the table: the event loop pockets it
//! where its path crosses the circle, as pooltool does (finding 32).

use crate::error::SimError;
use crate::model::MotionState;
use crate::model::ball_state::BallState;
use crate::model::table::Table;
use crate::model::vec3::Vec3;

/// How far (m) a ball may reach into a cushion or into another ball at rest before its
/// layout is refused: 10 µm, well above the ~1e-6 m overlaps pooltool's own simulations
/// leave behind (so its states read back), well below any real overlap.
pub const LAYOUT_TOLERANCE: f64 = 1e-5;

/// How far (m) two balls may overlap at the start when either moves: 0.1 mm. pooltool
/// resolves such an overlap at once (Q3), its kiss (Q1) pushing the two apart along the
/// line of centres without looking at the cushions; its own mid-shot states overlap by at
/// most ~20 µm (chatter), so they read back, while a deeper overlap, whose push could send
/// a ball centimetres into a cushion, is refused (FUZZING.md, finding 13).
pub const MOVING_OVERLAP_TOLERANCE: f64 = 1e-4;

/// Checks that every number of every ball is finite, that every ball that is not pocketed
/// lies on the playing surface of `table` (see the module docs), and that no two balls
/// overlap by more than [`LAYOUT_TOLERANCE`] when both are at rest (stationary or
/// spinning), or [`MOVING_OVERLAP_TOLERANCE`] when either moves. `radius` is the balls'
/// radius R.
///
/// ```
/// use kisstime::simulate::{BallState, Table, check_layout};
///
/// let table = Table::nine_foot();
/// let r = 0.028575;
/// let ok = [BallState::at_rest(0.6, 0.6, r), BallState::at_rest(0.6, 1.9, r)];
/// assert!(check_layout(&table, r, &ok).is_ok());
/// let off = [BallState::at_rest(0.6, 0.6, r), BallState::at_rest(2.0, 1.0, r)];
/// assert!(check_layout(&table, r, &off).unwrap_err().to_string().contains("ball 1"));
/// let overlap = [BallState::at_rest(0.6, 0.6, r), BallState::at_rest(0.6, 0.61, r)];
/// assert!(check_layout(&table, r, &overlap).is_err());
/// ```
pub fn check_layout(table: &Table, radius: f64, balls: &[BallState]) -> Result<(), SimError> {
    for (index, b) in balls.iter().enumerate() {
        if !(b.r.is_finite() && b.v.is_finite() && b.w.is_finite()) {
            return Err(SimError::Ball {
                index,
                reason: "non-finite position, velocity or spin".to_owned(),
            });
        }
        if b.s != MotionState::Pocketed {
            check_on_table(table, radius, b.r)
                .map_err(|reason| SimError::Ball { index, reason })?;
        }
    }
    let at_rest = |b: &BallState| matches!(b.s, MotionState::Stationary | MotionState::Spinning);
    for (j, bj) in balls.iter().enumerate() {
        if bj.s == MotionState::Pocketed {
            continue;
        }
        for (i, bi) in balls[..j].iter().enumerate() {
            if bi.s == MotionState::Pocketed {
                continue;
            }
            let tolerance = if at_rest(bi) && at_rest(bj) {
                LAYOUT_TOLERANCE
            } else {
                MOVING_OVERLAP_TOLERANCE
            };
            let (dx, dy) = (bj.r.x - bi.r.x, bj.r.y - bi.r.y);
            let depth = 2.0 * radius - (dx * dx + dy * dy).sqrt();
            if depth > tolerance {
                return Err(SimError::Overlap {
                    first: i,
                    second: j,
                    depth,
                });
            }
        }
    }
    Ok(())
}

/// Why a ball centred at `p` is not on the playing surface of `table`, if it is not: for a
/// ball given at rest (a layout), so a centre over a pocket counts as off (see the module
/// docs); [`check_in_play`] is the same test without that clause.
pub fn check_on_table(table: &Table, radius: f64, p: Vec3) -> Result<(), String> {
    check_in_play(table, radius, p)?;
    for (k, q) in table.pockets.iter().enumerate() {
        let d = ((p.x - q.center.x).powi(2) + (p.y - q.center.y).powi(2)).sqrt();
        if d < q.radius - LAYOUT_TOLERANCE {
            return Err(format!(
                "over pocket {} (centre {d:.6} m from the pocket's centre, inside its radius {}): a ball there has fallen in; give it as pocketed",
                table.pocket_ids[k], q.radius
            ));
        }
    }
    Ok(())
}

/// Why a ball centred at `p` is not in play on `table` mid-shot, if it is not: inside a
/// cushion or a jaw, or off the table, as [`check_on_table`] says, but a centre over a
/// pocket's circle is in play. A shot can put it there without its path entering the
/// circle (a cushion's kiss, Q1, that ends inside it), and pooltool, as the event loop,
/// pockets such a ball where its path leaves the circle (FUZZING.md, finding 32).
pub fn check_in_play(table: &Table, radius: f64, p: Vec3) -> Result<(), String> {
    let reach = radius - LAYOUT_TOLERANCE;
    for (k, seg) in table.linear.iter().enumerate() {
        let Some(d) = distance_within_extent(p, seg.p1, seg.p2) else {
            continue;
        };
        if d < reach {
            return Err(format!(
                "inside cushion segment {} (centre {d:.6} m from it, less than R = {radius})",
                table.linear_ids[k]
            ));
        }
    }
    for (k, arc) in table.circular.iter().enumerate() {
        let d = ((p.x - arc.center.x).powi(2) + (p.y - arc.center.y).powi(2)).sqrt();
        if d < arc.radius + reach {
            return Err(format!(
                "inside the jaw {} (centre {d:.6} m from the arc's centre)",
                table.circular_ids[k]
            ));
        }
    }
    for (dx, dy) in [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)] {
        let hits_segment = table
            .linear
            .iter()
            .any(|s| ray_meets_segment(p, (dx, dy), s.p1, s.p2));
        let hits_circle = || {
            let arcs = table.circular.iter().map(|c| (c.center, c.radius));
            let pockets = table.pockets.iter().map(|q| (q.center, q.radius));
            arcs.chain(pockets)
                .any(|(c, rad)| ray_meets_circle(p, (dx, dy), c, rad))
        };
        if !hits_segment && !hits_circle() {
            return Err(format!(
                "off the table: ({}, {}) is outside the playing surface",
                p.x, p.y
            ));
        }
    }
    Ok(())
}

/// The distance in the xy-plane from `p` to the line of the segment `a`–`b`, where `p`
/// lies within the segment's extent (its projection on the segment between `a` and `b`);
/// `None` beyond the ends. That is pooltool's straight cushion (§4.4): the ball meets it
/// only where its centre projects inside the segment, never at a bare end (jaws cover the
/// ends at pocket mouths; a ball passing the deep end of a throat segment on its way into
/// the pocket clips it, in pooltool as here: FUZZING.md, finding 34).
fn distance_within_extent(p: Vec3, a: Vec3, b: Vec3) -> Option<f64> {
    let (ex, ey) = (b.x - a.x, b.y - a.y);
    let (wx, wy) = (p.x - a.x, p.y - a.y);
    let len2 = ex * ex + ey * ey;
    if len2 <= 0.0 {
        return Some((wx * wx + wy * wy).sqrt());
    }
    let u = (wx * ex + wy * ey) / len2;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    Some(((wx - u * ex).powi(2) + (wy - u * ey).powi(2)).sqrt())
}

/// Whether the ray from `p` along the unit axis `d` meets the segment `a`–`b` (xy-plane).
fn ray_meets_segment(p: Vec3, d: (f64, f64), a: Vec3, b: Vec3) -> bool {
    let (ex, ey) = (b.x - a.x, b.y - a.y);
    let (wx, wy) = (a.x - p.x, a.y - p.y);
    // p + s d = a + u e  ⇔  s d − u e = w
    let den = d.0 * (-ey) - d.1 * (-ex);
    if den == 0.0 {
        return false;
    }
    let s = (wx * (-ey) - wy * (-ex)) / den;
    let u = (d.0 * wy - d.1 * wx) / den;
    s >= 0.0 && (0.0..=1.0).contains(&u)
}

/// Whether the ray from `p` along the unit axis `d` meets the circle (centre `c`, radius
/// `rad`) in the xy-plane.
fn ray_meets_circle(p: Vec3, d: (f64, f64), c: Vec3, rad: f64) -> bool {
    let (wx, wy) = (c.x - p.x, c.y - p.y);
    let s0 = wx * d.0 + wy * d.1;
    let off2 = wx * wx + wy * wy - s0 * s0;
    off2 <= rad * rad && s0 + (rad * rad - off2).max(0.0).sqrt() >= 0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::sim_params::SimParams;

    const R: f64 = 0.028575;

    #[test]
    fn the_whole_playing_surface_is_on_the_table_and_outside_is_not() {
        let table = Table::nine_foot();
        let (w, l) = (1.27, 2.54);
        let steps = 60;
        for i in 0..=steps {
            for j in 0..=2 * steps {
                let x = R + (w - 2.0 * R) * i as f64 / steps as f64;
                let y = R + (l - 2.0 * R) * j as f64 / (2 * steps) as f64;
                let p = Vec3::new(x, y, R);
                // near a pocket mouth a ball may touch a jaw: skip those few points
                let near_jaw = table.circular.iter().any(|c| {
                    ((x - c.center.x).powi(2) + (y - c.center.y).powi(2)).sqrt() < c.radius + R
                });
                if !near_jaw {
                    assert!(check_on_table(&table, R, p).is_ok(), "({x}, {y})");
                }
            }
        }
        for (x, y) in [
            (-0.2, 1.0),
            (1.5, 1.0),
            (0.6, -0.3),
            (0.6, 2.9),
            (5.0, 5.0),
            (-0.04, 0.6),
        ] {
            let err = check_on_table(&table, R, Vec3::new(x, y, R)).unwrap_err();
            assert!(err.contains("off the table"), "({x}, {y}): {err}");
        }
        // touching a rail is fine, into it is not
        assert!(check_on_table(&table, R, Vec3::new(R, 0.6, R)).is_ok());
        let err = check_on_table(&table, R, Vec3::new(R - 1e-3, 0.6, R)).unwrap_err();
        assert!(err.contains("inside cushion segment 3"), "{err}");
        // in a pocket's mouth, short of the pocket's circle (lc: centre x = −0.0685,
        // radius 0.0645); over it, the ball has fallen in
        assert!(check_on_table(&table, R, Vec3::new(-0.003, 1.27, R)).is_ok());
        let err = check_on_table(&table, R, Vec3::new(-0.01, 1.27, R)).unwrap_err();
        assert!(err.contains("over pocket lc"), "{err}");
    }

    #[test]
    fn the_reference_racks_pass_and_overlaps_at_rest_do_not() {
        let table = Table::nine_foot();
        let rect = Table::rectangle(1.27, 2.54, 0.036576).unwrap();
        let a = BallState::at_rest(0.5, 0.5, R);
        let b = BallState::at_rest(0.5, 0.5 + 2.0 * R - 1e-6, R);
        assert!(check_layout(&table, R, &[a, b]).is_ok());
        let c = BallState::at_rest(0.5, 0.5 + 2.0 * R - 1e-4, R);
        let err = check_layout(&table, R, &[a, b, c]).unwrap_err();
        assert!(
            matches!(
                err,
                SimError::Overlap {
                    first: 0,
                    second: 2,
                    ..
                }
            ),
            "{err}"
        );
        // a moving ball may overlap a little (pooltool resolves it at once, Q3), not deeply
        let moving = BallState {
            s: MotionState::Rolling,
            v: Vec3::new(0.0, 1.0, 0.0),
            ..c
        };
        assert!(check_layout(&rect, R, &[a, moving]).is_ok());
        let deep = BallState {
            r: Vec3::new(0.5, 0.5 + 2.0 * R - 1e-3, R),
            ..moving
        };
        let err = check_layout(&rect, R, &[a, deep]).unwrap_err();
        assert!(matches!(err, SimError::Overlap { .. }), "{err}");
        let pocketed = BallState {
            s: MotionState::Pocketed,
            r: Vec3::new(-9.0, -9.0, -0.08),
            ..a
        };
        assert!(check_layout(&table, R, &[a, pocketed]).is_ok());
        let nan = BallState {
            w: Vec3::new(f64::NAN, 0.0, 0.0),
            ..a
        };
        assert!(matches!(
            check_layout(&table, R, &[a, nan]),
            Err(SimError::Ball { index: 1, .. })
        ));
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/data/fullshots");
        if let Ok(shots) =
            crate::io::shot_set::read_shots(std::path::Path::new(dir), SimParams::default().ball.r)
        {
            for s in &shots {
                check_layout(&table, R, &s.balls).unwrap();
            }
        }
    }
}
