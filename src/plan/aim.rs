//! Aiming: the ghost-ball aim of a direct pot, its cut angle, and whether a straight path
//! between two points is clear of the other balls — the geometry a player uses to choose
//! what to try. What then happens is the simulator's to say; these only propose.
//!
//! Method: the object ball goes where the cue ball's centre points at contact, along the
//! line of centres, so to send it from `O` towards a target `P` the cue ball's centre must
//! reach the *ghost ball* `G = O − 2R·(P − O)/|P − O|` (a ball touching `O` on the far side
//! from `P`). The cut angle is the angle between the cue ball's line `G − C` and the object
//! ball's line `P − O`: 0 is a full hit; towards 90° the object ball gets less and less of
//! the cue ball's speed (about `cos(cut)` of it, without throw). Spin, throw and squirt are
//! left out: the candidates' strikes then go through the simulator, which has them.
//! Source: the standard ghost-ball construction (Alciatore, *The Illustrated Principles of
//! Pool and Billiards*, 2004, ch. 3).
//!
//! Banks and kicks aim by the mirror: a ball rebounding off a rail as a light ray off a
//! mirror reaches a point `P` where it would reach `P` mirrored in the rail's line (the
//! line of the touching ball's centre, a radius off the cushion: [`Rail`]). Real rebounds
//! are not mirrors (the cushion's restitution and friction and the ball's spin turn them:
//! pooltool's Han (2005) model); the candidates therefore try a fan of aims around the
//! mirror's and let the simulation choose.

/// A direct pot's aim ([`ghost_ball`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aim {
    /// The stroke's azimuth, degrees counter-clockwise from +x in [0, 360) (pooltool's φ).
    pub phi: f64,
    /// The cut angle, degrees in [0, 180): 0 a full hit, 90 and more unplayable.
    pub cut: f64,
    /// The ghost ball's centre: where the cue ball's centre is at contact.
    pub ghost: (f64, f64),
    /// The cue ball's travel to the ghost ball, m.
    pub cue_travel: f64,
    /// The object ball's travel to the target, m.
    pub object_travel: f64,
}

/// The ghost-ball aim for the cue ball at `cue` to send the ball at `object` towards
/// `target` (balls of radius `r`): `None` where the object ball sits on the target, or the
/// cue ball on the ghost ball.
pub fn ghost_ball(cue: (f64, f64), object: (f64, f64), target: (f64, f64), r: f64) -> Option<Aim> {
    let (ux, uy) = (target.0 - object.0, target.1 - object.1);
    let object_travel = ux.hypot(uy);
    if object_travel <= 0.0 || !object_travel.is_finite() {
        return None;
    }
    let (ux, uy) = (ux / object_travel, uy / object_travel);
    let ghost = (object.0 - 2.0 * r * ux, object.1 - 2.0 * r * uy);
    let (dx, dy) = (ghost.0 - cue.0, ghost.1 - cue.1);
    let cue_travel = dx.hypot(dy);
    if cue_travel <= 0.0 {
        return None;
    }
    let cos_cut = ((dx * ux + dy * uy) / cue_travel).clamp(-1.0, 1.0);
    Some(Aim {
        phi: dy.atan2(dx).to_degrees().rem_euclid(360.0),
        cut: cos_cut.acos().to_degrees(),
        ghost,
        cue_travel,
        object_travel,
    })
}

/// Whether a ball of radius `r` going straight from `from` to `to` passes every ball of
/// `others` (their centres) without touching it: each stays more than `2r` from the
/// segment.
pub fn path_clear(
    from: (f64, f64),
    to: (f64, f64),
    r: f64,
    others: impl IntoIterator<Item = (f64, f64)>,
) -> bool {
    let (dx, dy) = (to.0 - from.0, to.1 - from.1);
    let len2 = dx * dx + dy * dy;
    let reach2 = 4.0 * r * r;
    others.into_iter().all(|(x, y)| {
        let (px, py) = (x - from.0, y - from.1);
        // the nearest point of the segment to the ball
        let t = if len2 > 0.0 {
            ((px * dx + py * dy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (ex, ey) = (px - t * dx, py - t * dy);
        ex * ex + ey * ey > reach2
    })
}

/// A straight stretch of cushion as a ball's centre meets it: the line
/// `coordinate[axis] = at` on which the centre of a ball touching the cushion lies, over
/// the stretch `lo..hi` of the other coordinate (the cushion segment's own extent). Only
/// the axis-aligned segments of a table are rails here (the jaws' angled segments and the
/// circular jaw tips are left out): what a player banks from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rail {
    /// 0: the rail is a line of constant x; 1: of constant y.
    pub axis: usize,
    /// The constant coordinate of a touching ball's centre, m.
    pub at: f64,
    /// The stretch of the other coordinate the cushion covers, m (`lo < hi`).
    pub lo: f64,
    /// See [`Rail::lo`].
    pub hi: f64,
    /// The cushion segment's index in the table's straight cushions (`Table::linear`).
    pub segment: usize,
}

impl Rail {
    /// `p` mirrored in the rail's line: the point a ball aimed at from the table's side
    /// reaches, after an ideal (mirror) rebound, where it would have reached `p`.
    pub fn mirror(&self, p: (f64, f64)) -> (f64, f64) {
        if self.axis == 0 {
            (2.0 * self.at - p.0, p.1)
        } else {
            (p.0, 2.0 * self.at - p.1)
        }
    }

    /// Where the straight path from `from` to `to` (a mirrored point: the far side of the
    /// rail's line from `from`) crosses the rail's line, if it crosses it on the stretch
    /// at least `margin` from either end.
    pub fn bounce(&self, from: (f64, f64), to: (f64, f64), margin: f64) -> Option<(f64, f64)> {
        let (f, t) = if self.axis == 0 {
            ((from.0, from.1), (to.0, to.1))
        } else {
            ((from.1, from.0), (to.1, to.0))
        };
        let (da, db) = (self.at - f.0, t.0 - self.at);
        // `from` and `to` strictly on either side of the line
        if da * db <= 0.0 || da.is_nan() || db.is_nan() {
            return None;
        }
        let s = da / (t.0 - f.0);
        let along = f.1 + s * (t.1 - f.1);
        if !(along >= self.lo + margin && along <= self.hi - margin) {
            return None;
        }
        Some(if self.axis == 0 {
            (self.at, along)
        } else {
            (along, self.at)
        })
    }
}

/// The rails of `table` for balls of radius `r` ([`Rail`]): each axis-aligned straight
/// cushion segment, its line moved `r` towards the middle of the table (the centre of
/// its cushions' endpoints).
pub fn rails(table: &crate::model::table::Table, r: f64) -> Vec<Rail> {
    let n = (table.linear.len() * 2).max(1) as f64;
    let mid = table.linear.iter().fold((0.0, 0.0), |m, s| {
        (m.0 + (s.p1.x + s.p2.x) / n, m.1 + (s.p1.y + s.p2.y) / n)
    });
    let mut out = Vec::new();
    for (segment, s) in table.linear.iter().enumerate() {
        let (axis, c, a, b) = if s.p1.x == s.p2.x {
            (0, s.p1.x, s.p1.y, s.p2.y)
        } else if s.p1.y == s.p2.y {
            (1, s.p1.y, s.p1.x, s.p2.x)
        } else {
            continue;
        };
        let m = if axis == 0 { mid.0 } else { mid.1 };
        if a == b || c == m {
            continue;
        }
        out.push(Rail {
            axis,
            at: c + r * (m - c).signum(),
            lo: a.min(b),
            hi: a.max(b),
            segment,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const R: f64 = 0.028575;

    #[test]
    fn a_straight_shot_is_a_full_hit_along_the_line() {
        let aim = ghost_ball((0.5, 0.5), (0.5, 1.0), (0.5, 2.0), R).unwrap();
        assert!((aim.phi - 90.0).abs() < 1e-12);
        assert!(aim.cut.abs() < 1e-6);
        assert!((aim.ghost.1 - (1.0 - 2.0 * R)).abs() < 1e-15);
        assert!((aim.cue_travel - (0.5 - 2.0 * R)).abs() < 1e-12);
        assert!((aim.object_travel - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_cut_shot_has_its_angle() {
        // the object ball goes along +y; the cue ball comes from below-left at 30°
        let object = (1.0, 1.0);
        let ghost = (1.0, 1.0 - 2.0 * R);
        let c = 30f64.to_radians();
        let cue = (ghost.0 - 0.4 * c.sin(), ghost.1 - 0.4 * c.cos());
        let aim = ghost_ball(cue, object, (1.0, 2.0), R).unwrap();
        assert!((aim.cut - 30.0).abs() < 1e-9, "{}", aim.cut);
        assert!((aim.phi - 60.0).abs() < 1e-9, "{}", aim.phi);
        // behind the object ball: the cut is past 90°
        let back = ghost_ball((1.0, 1.5), object, (1.0, 2.0), R).unwrap();
        assert!(back.cut > 90.0);
        // degenerate: the object ball on the target, the cue ball on the ghost ball
        assert!(ghost_ball(cue, object, object, R).is_none());
        assert!(ghost_ball(ghost, object, (1.0, 2.0), R).is_none());
    }

    #[test]
    fn a_path_is_blocked_by_a_ball_within_two_radii() {
        let (a, b) = ((0.0, 0.0), (1.0, 0.0));
        assert!(path_clear(a, b, R, []));
        assert!(path_clear(a, b, R, [(0.5, 2.0 * R + 1e-9)]));
        assert!(!path_clear(a, b, R, [(0.5, 2.0 * R - 1e-9)]));
        // beyond the end: only the distance to the end counts
        assert!(path_clear(a, b, R, [(1.0 + 2.0 * R + 1e-9, 0.0)]));
        assert!(!path_clear(a, b, R, [(1.0 + R, 0.0)]));
        assert!(!path_clear(a, b, R, [(0.7, 0.01), (3.0, 3.0)]));
    }

    #[test]
    fn a_rail_mirrors_and_finds_the_bounce_point() {
        let table = crate::model::table::Table::nine_foot();
        let rails = rails(&table, R);
        // the 9-ft table: two stretches on each long rail, one on each short rail
        assert_eq!(rails.len(), 6, "{rails:?}");
        let left = rails
            .iter()
            .find(|r| r.axis == 0 && r.at < 0.5)
            .expect("a left rail");
        assert!((left.at - R).abs() < 1e-12);
        assert_eq!(left.mirror((0.3, 0.7)), (2.0 * R - 0.3, 0.7));
        // from (0.3, 0.4) to (0.3, 0.8) off the left rail: the bounce half-way up
        let b = left
            .bounce((0.3, 0.4), left.mirror((0.3, 0.8)), 0.0)
            .unwrap();
        assert!(
            (b.0 - R).abs() < 1e-12 && (b.1 - 0.6).abs() < 1e-12,
            "{b:?}"
        );
        // not across the line, or past the stretch's end
        assert!(left.bounce((0.3, 0.4), (0.2, 0.8), 0.0).is_none());
        assert!(
            left.bounce((0.3, 0.4), left.mirror((0.3, 5.0)), 0.0)
                .is_none()
        );
    }
}
