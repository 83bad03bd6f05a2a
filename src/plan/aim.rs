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
}
