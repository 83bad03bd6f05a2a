//! Named regressions: the degenerate pairs where ball-ball collision solvers go wrong
//! (pooltool 0.6.0 among them), each checked against a closed form or a rule of the
//! contract in `src/query/ball_ball.rs`.

use kisstime::model::{dot, norm};
use kisstime::query::RelPath;
use kisstime::{Ball, Contact, MotionState, Params, Status, ball_path, pair_contact};
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

fn p() -> Params {
    Params::default()
}

const R: f64 = kisstime::model::DEFAULT_RADIUS;

fn solve(b1: &Ball, b2: &Ball) -> Contact {
    let p = p();
    pair_contact(&ball_path(b1, &p), &ball_path(b2, &p), p.radius)
}

fn rel(b1: &Ball, b2: &Ball) -> RelPath {
    let p = p();
    RelPath::between(&ball_path(b1, &p), &ball_path(b2, &p))
}

/// `|C(t)| − 2R`.
fn gap_at(b1: &Ball, b2: &Ball, t: f64) -> f64 {
    norm(rel(b1, b2).at(t)) - 2.0 * R
}

/// `|C(0)| − 2R`.
fn gap0(b1: &Ball, b2: &Ball) -> f64 {
    gap_at(b1, b2, 0.0)
}

fn unit(angle: f64) -> (f64, f64) {
    (angle.cos(), angle.sin())
}

fn rolling(x: f64, y: f64, speed: f64, angle: f64) -> Ball {
    let (ux, uy) = unit(angle);
    Ball::rolling(x, y, speed * ux, speed * uy, R)
}

/// A sliding ball with no spin (a stun shot): the contact point moves with the centre.
fn stun(x: f64, y: f64, speed: f64, angle: f64) -> Ball {
    let (ux, uy) = unit(angle);
    Ball {
        state: MotionState::Sliding,
        vx: speed * ux,
        vy: speed * uy,
        ..Ball::at_rest(x, y)
    }
}

fn assert_none(c: &Contact, what: &str) {
    assert_eq!(c.status, Status::None, "{what}: expected none, got {c:?}");
    assert_eq!(c.t, f64::INFINITY, "{what}: {c:?}");
}

/// Positive smallest root of `s = v t − ½ a t²` (a ball decelerating at `a` from `v`
/// covering `s`), in the cancellation-free form.
fn travel_time(v: f64, a: f64, s: f64) -> f64 {
    let disc = v * v - 2.0 * a * s;
    assert!(disc >= 0.0, "the ball never gets that far");
    2.0 * s / (v + disc.sqrt())
}

const SPEEDS: [f64; 6] = [0.01, 0.3, 1.0, 2.5, 4.0, 6.0];
const ANGLES: [f64; 8] = [0.0, 0.3, FRAC_PI_4, FRAC_PI_2, 2.0, PI, -1.1, 5.5];

#[test]
fn parallel_rolling_balls_never_collide() {
    // pooltool 0.6.0 answers t = 0 here (its quartic degenerates to a constant).
    let gaps = [2.0 * R + 1e-3, 2.0 * R + 1e-2, 0.1, 0.25, 0.5, 1.0];
    let mut n = 0;
    for &speed in &SPEEDS {
        for &angle in &ANGLES {
            for &gap in &gaps {
                for side in [1.0, -1.0] {
                    // ball 2 beside ball 1, perpendicular to the common velocity
                    let (nx, ny) = unit(angle + side * FRAC_PI_2);
                    let (x1, y1) = (0.9, 0.6);
                    let b1 = rolling(x1, y1, speed, angle);
                    let b2 = rolling(x1 + gap * nx, y1 + gap * ny, speed, angle);
                    let what = format!("v={speed} angle={angle} gap={gap} side={side}");
                    let c = solve(&b1, &b2);
                    assert_none(&c, &what);
                    assert!(c.horizon.is_finite() && c.horizon > 0.0, "{what}: {c:?}");
                    assert_none(&solve(&b2, &b1), &format!("{what}, swapped"));
                    n += 1;
                }
            }
        }
    }
    assert_eq!(n, SPEEDS.len() * ANGLES.len() * gaps.len() * 2);
}

#[test]
fn chase_at_equal_deceleration() {
    let (x0, y0) = (0.7, 0.4);
    // in line, same speed: the gap never changes
    for &speed in &SPEEDS {
        for &angle in &ANGLES {
            for gap in [2.0 * R + 1e-3, 4.0 * R, 0.3, 1.0] {
                let (ux, uy) = unit(angle);
                let (x2, y2) = (x0 + gap * ux, y0 + gap * uy);
                let what = format!("same speed {speed}, angle {angle}, gap {gap}");
                assert_none(
                    &solve(
                        &rolling(x0, y0, speed, angle),
                        &rolling(x2, y2, speed, angle),
                    ),
                    &format!("rolling, {what}"),
                );
                assert_none(
                    &solve(&stun(x0, y0, speed, angle), &stun(x2, y2, speed, angle)),
                    &format!("sliding, {what}"),
                );
            }
        }
    }

    // the case: 2 m/s behind 1 m/s, centres 4R apart, both rolling the same way.
    // Both decelerate by μr g along the same direction, so the relative motion is uniform
    // at 1 m/s and the gap 4R − 2R closes at t = 2R / 1.
    let expected = (4.0 * R - 2.0 * R) / (2.0 - 1.0);
    for &angle in &ANGLES {
        let (ux, uy) = unit(angle);
        let (x2, y2) = (x0 + 4.0 * R * ux, y0 + 4.0 * R * uy);
        for (state, behind, ahead) in [
            (
                "rolling",
                rolling(x0, y0, 2.0, angle),
                rolling(x2, y2, 1.0, angle),
            ),
            (
                "sliding, no spin",
                stun(x0, y0, 2.0, angle),
                stun(x2, y2, 1.0, angle),
            ),
        ] {
            let c = solve(&behind, &ahead);
            let what = format!("{state} chase at angle {angle}: {c:?}");
            assert_eq!(c.status, Status::Hit, "{what}");
            assert!(c.t <= c.horizon, "{what}");
            assert!(
                (c.t - expected).abs() <= 1e-12,
                "{what}: expected t = 2R = {expected}, |Δt| = {:e}",
                (c.t - expected).abs()
            );
            assert!(gap_at(&behind, &ahead, c.t).abs() <= 1e-12, "{what}");
            // swapped: the same answer
            let s = solve(&ahead, &behind);
            assert_eq!((s.status, s.t), (c.status, c.t), "{what}, swapped");
            // the faster ball ahead: they separate
            let (x3, y3) = (x0 - 4.0 * R * ux, y0 - 4.0 * R * uy);
            let (slow_behind, fast_ahead) = if state == "rolling" {
                (rolling(x3, y3, 1.0, angle), rolling(x0, y0, 2.0, angle))
            } else {
                (stun(x3, y3, 1.0, angle), stun(x0, y0, 2.0, angle))
            };
            assert_none(
                &solve(&slow_behind, &fast_ahead),
                &format!("{state}, faster ball ahead, angle {angle}"),
            );
        }
    }
}

#[test]
fn identical_motion_never_collides() {
    let motions = [
        ("rolling", rolling(0.0, 0.0, 1.7, 0.4)),
        ("stun", stun(0.0, 0.0, 3.0, -2.0)),
        (
            "sliding with spin",
            Ball {
                state: MotionState::Sliding,
                vx: 1.2,
                vy: -0.4,
                wx: 35.0,
                wy: -80.0,
                wz: 150.0,
                ..Ball::at_rest(0.0, 0.0)
            },
        ),
        (
            "sliding, spin only",
            Ball {
                state: MotionState::Sliding,
                wx: 10.0,
                wy: 60.0,
                ..Ball::at_rest(0.0, 0.0)
            },
        ),
        (
            "spinning",
            Ball {
                state: MotionState::Spinning,
                wz: 40.0,
                ..Ball::at_rest(0.0, 0.0)
            },
        ),
        ("stationary", Ball::at_rest(0.0, 0.0)),
    ];
    let placements = [
        // apart
        ((0.5, 0.5), (1.5, 0.9)),
        ((0.3, 0.3), (0.3 + 2.0 * R + 1e-6, 0.3)),
        ((2.0, 1.0), (2.0 - 0.1, 1.0 + 0.2)),
        // touching, centres exactly 2R apart
        ((0.0, 0.0), (2.0 * R, 0.0)),
        ((0.0, 0.0), (0.0, -2.0 * R)),
        ((0.5, 0.5), (0.5 + 2.0 * R, 0.5)),
        (
            (1.0, 0.6),
            (
                1.0 + 2.0 * R * FRAC_PI_4.cos(),
                0.6 + 2.0 * R * FRAC_PI_4.sin(),
            ),
        ),
    ];
    for (name, m) in motions {
        for ((x1, y1), (x2, y2)) in placements {
            let b1 = Ball { x: x1, y: y1, ..m };
            let b2 = Ball { x: x2, y: y2, ..m };
            let what = format!("{name} at ({x1}, {y1}) and ({x2}, {y2})");
            assert!(gap0(&b1, &b2) > -1e-12, "{what}: test setup overlaps");
            assert_none(&solve(&b1, &b2), &what);
            assert_none(&solve(&b2, &b1), &format!("{what}, swapped"));
        }
    }
}

#[test]
fn just_collided_touching_pair_reports_no_t0() {
    let (x1, y1) = (1.0, 0.5);
    let still = Ball::at_rest(x1, y1);
    // line of centres along +x from ball 1 to ball 2
    let touching = (x1 + 2.0 * R, y1);
    assert!(gap0(&still, &Ball::at_rest(touching.0, touching.1)).abs() <= 1e-12);

    // moving straight away, or obliquely away: nothing brings them back within H
    for (what, b2) in [
        (
            "rolling head-on away",
            rolling(touching.0, touching.1, 1.0, 0.0),
        ),
        ("stun head-on away", stun(touching.0, touching.1, 2.0, 0.0)),
        (
            "rolling 45° away",
            rolling(touching.0, touching.1, 1.5, FRAC_PI_4),
        ),
        (
            "stun 45° away",
            stun(touching.0, touching.1, 1.5, -FRAC_PI_4),
        ),
        (
            "rolling 80° away",
            rolling(touching.0, touching.1, 0.5, 1.4),
        ),
        (
            "slow rolling away",
            rolling(touching.0, touching.1, 1e-4, 0.0),
        ),
    ] {
        let c = solve(&still, &b2);
        assert!(
            !(c.status == Status::Hit && c.t == 0.0),
            "{what}: a just-collided pair must not collide at t = 0: {c:?}"
        );
        assert_none(&c, what);
        assert_none(&solve(&b2, &still), &format!("{what}, swapped"));
    }

    // a cut shot just after impact: the object ball (2) leaves along the line of centres,
    // the cue ball (1) along the tangent line
    let cue = stun(x1, y1, 1.2, FRAC_PI_2);
    let object = rolling(touching.0, touching.1, 0.8, 0.0);
    assert_none(&solve(&cue, &object), "cut shot, just after impact");
    assert_none(
        &solve(&object, &cue),
        "cut shot, just after impact, swapped",
    );

    // draw-back: ball 2 leaves sliding with strong backspin, stops and comes back into
    // ball 1 while still sliding. x(t) = 2R + v t − ½ μs g t² is back at 2R at
    // t = 2v/(μs g); sliding lasts 2|u|/(7 μs g) with |u| = v + R|wy|, long enough
    // when R|wy| > 6 v.
    let pp = p();
    let mu_s_g = pp.mu_s * pp.g;
    for &angle in &[0.0, 0.7, FRAC_PI_2, 2.9, -2.2] {
        let (ux, uy) = unit(angle);
        let b2_pos = (x1 + 2.0 * R * ux, y1 + 2.0 * R * uy);
        let v = 0.1;
        for (backspin, comes_back) in [(1.0, true), (0.3, false)] {
            // contact-point velocity u = v + R ẑ×ω = (v + backspin) along the direction
            let w_along = -backspin / R; // spin about the axis ẑ × direction
            let b2 = Ball {
                state: MotionState::Sliding,
                x: b2_pos.0,
                y: b2_pos.1,
                vx: v * ux,
                vy: v * uy,
                // ω = w_along · (−uy, ux, 0): R ẑ × ω = R w_along · (−ux, −uy)
                wx: -w_along * uy,
                wy: w_along * ux,
                wz: 0.0,
            };
            let path = ball_path(&b2, &pp);
            let h = 2.0 * (v + backspin) / (7.0 * mu_s_g);
            assert!((path.tmax - h).abs() <= 1e-12, "setup: tmax {}", path.tmax);
            let c = solve(&still, &b2);
            let what = format!("draw-back, backspin {backspin} m/s, angle {angle}: {c:?}");
            if comes_back {
                let expected = 2.0 * v / mu_s_g;
                assert!(expected < h);
                assert_eq!(c.status, Status::Hit, "{what}");
                assert!(c.t > 0.0, "{what}");
                assert!(
                    (c.t - expected).abs() <= 1e-12,
                    "{what}: expected t = 2v/(μs g) = {expected}"
                );
                assert!(gap_at(&still, &b2, c.t).abs() <= 1e-12, "{what}");
                let s = solve(&b2, &still);
                assert_eq!((s.status, s.t), (c.status, c.t), "{what}, swapped");
            } else {
                assert!(2.0 * v / mu_s_g > h);
                assert_none(&c, &what);
            }
        }
    }
}

#[test]
fn touching_and_approaching_is_zero() {
    // exact geometry: C = (2R, 0), f(0) = 0 exactly
    let b1 = Ball::at_rest(0.0, 0.0);
    for (what, b2) in [
        ("rolling head-on", rolling(2.0 * R, 0.0, 1.0, PI)),
        ("stun head-on", stun(2.0 * R, 0.0, 3.0, PI)),
        ("rolling oblique", rolling(2.0 * R, 0.0, 2.0, PI - 1.2)),
        ("slow rolling", rolling(2.0 * R, 0.0, 1e-6, PI)),
    ] {
        let c = solve(&b1, &b2);
        assert_eq!(c.status, Status::Hit, "{what}: {c:?}");
        assert_eq!(c.t, 0.0, "{what}: {c:?}");
        let s = solve(&b2, &b1);
        assert_eq!((s.status, s.t), (Status::Hit, 0.0), "{what}, swapped");
    }
    // both moving towards each other
    let c = solve(&rolling(0.0, 0.0, 1.0, 0.0), &stun(2.0 * R, 0.0, 1.0, PI));
    assert_eq!(
        (c.status, c.t),
        (Status::Hit, 0.0),
        "both approaching: {c:?}"
    );

    // rounded geometry (|C| = 2R only to an ulp or so): a hit at 0, or the exact first
    // root a fraction of a picometre of travel away
    for &angle in &ANGLES {
        for &speed in &[0.05, 1.0, 5.0] {
            let (ux, uy) = unit(angle);
            let b1 = Ball::at_rest(1.3, 0.7);
            let b2 = rolling(1.3 + 2.0 * R * ux, 0.7 + 2.0 * R * uy, speed, angle + PI);
            assert!(gap0(&b1, &b2).abs() <= 1e-12);
            let c = solve(&b1, &b2);
            let what = format!("angle {angle}, speed {speed}: {c:?}");
            assert_eq!(c.status, Status::Hit, "{what}");
            assert!(c.t >= 0.0 && c.t * speed <= 1e-12, "{what}");
        }
    }

    // touching, moving tangentially, but curving into the other ball: the first non-zero
    // derivative of f at 0 is f'' = 2(|B|² + 2 A·C) < 0, so the pair approaches
    let curving = Ball {
        state: MotionState::Sliding,
        x: 2.0 * R,
        y: 0.0,
        vx: 0.0,
        vy: 0.2,
        // u = (vx − R wy, vy + R wx) = (1, 0): friction pushes the ball towards −x
        wx: -0.2 / R,
        wy: -1.0 / R,
        wz: 0.0,
    };
    let r = rel(&b1, &curving);
    assert_eq!(dot(r.b, r.c), 0.0);
    assert!(dot(r.b, r.b) + 2.0 * dot(r.a, r.c) < 0.0);
    let c = solve(&b1, &curving);
    assert_eq!(
        (c.status, c.t),
        (Status::Hit, 0.0),
        "tangential, curving in: {c:?}"
    );
    // … and curving away: separates, none
    let away = Ball {
        wy: 1.0 / R,
        ..curving
    };
    assert_none(&solve(&b1, &away), "tangential, curving away");
}

#[test]
fn overlap_is_reported() {
    for &angle in &ANGLES {
        let (ux, uy) = unit(angle);
        let d = 2.0 * R - 1e-6;
        let (x1, y1) = (1.1, 0.55);
        let (x2, y2) = (x1 + d * ux, y1 + d * uy);
        for (what, b1, b2) in [
            (
                "still + rolling towards",
                Ball::at_rest(x1, y1),
                rolling(x2, y2, 1.0, angle + PI),
            ),
            (
                "still + rolling away",
                Ball::at_rest(x1, y1),
                rolling(x2, y2, 1.0, angle),
            ),
            (
                "rolling + spinning",
                rolling(x1, y1, 0.5, 1.0),
                Ball {
                    state: MotionState::Spinning,
                    wz: 9.0,
                    ..Ball::at_rest(x2, y2)
                },
            ),
            (
                "sliding + sliding",
                stun(x1, y1, 2.0, 0.3),
                stun(x2, y2, 2.0, 0.3),
            ),
            (
                "parallel rolling",
                rolling(x1, y1, 1.0, angle + FRAC_PI_2),
                rolling(x2, y2, 1.0, angle + FRAC_PI_2),
            ),
        ] {
            let c = solve(&b1, &b2);
            let what = format!("{what}, angle {angle}: {c:?}");
            assert_eq!(c.status, Status::Overlap, "{what}");
            assert_eq!(c.t, 0.0, "{what}");
            assert!(c.status.is_contact());
            let s = solve(&b2, &b1);
            assert_eq!((s.status, s.t), (Status::Overlap, 0.0), "{what}, swapped");
        }
    }
    // the boundary of the touching band, with exact geometry on the x axis
    let b1 = Ball::at_rest(0.0, 0.0);
    let b2 = |d: f64| rolling(d, 0.0, 1.0, 0.0); // moving away
    assert_eq!(solve(&b1, &b2(2.0 * R - 2e-12)).status, Status::Overlap);
    assert_eq!(solve(&b1, &b2(2.0 * R - 0.5e-12)).status, Status::None);
    assert_eq!(solve(&b1, &b2(2.0 * R + 0.5e-12)).status, Status::None);
}

#[test]
fn ball_stopping_short_and_just_at() {
    let pp = p();
    let decel = pp.mu_r * pp.g;
    let mut hits = 0;
    for &speed in &[0.3, 1.0, 2.0, 4.0] {
        for &angle in &[0.0, 0.7, FRAC_PI_2, 2.5, -2.0] {
            let (ux, uy) = unit(angle);
            let tmax = speed / decel;
            let travel = speed * speed / (2.0 * decel);
            let (x0, y0) = (0.4, 0.3);
            let mover = rolling(x0, y0, speed, angle);
            assert!((ball_path(&mover, &pp).tmax - tmax).abs() <= 1e-12 * tmax);
            for (beyond, tol) in [(1e-3, 1e-10), (1e-6, 1e-9)] {
                for (what, d) in [
                    ("stops short", travel + 2.0 * R + beyond),
                    ("stops past", travel + 2.0 * R - beyond),
                ] {
                    let target = Ball::at_rest(x0 + d * ux, y0 + d * uy);
                    let c = solve(&target, &mover);
                    let what = format!("{what} by {beyond} m, v {speed}, angle {angle}: {c:?}");
                    assert!(c.horizon == ball_path(&mover, &pp).tmax, "{what}: horizon");
                    // the gap the mover must close, from the doubles as given
                    let s = gap0(&target, &mover);
                    if s > travel {
                        assert_none(&c, &what);
                    } else {
                        let expected = travel_time(speed, decel, s);
                        assert_eq!(c.status, Status::Hit, "{what}");
                        let dt = (c.t - expected).abs();
                        let r = rel(&target, &mover);
                        let ct = r.at(expected);
                        let vn = (dot(ct, r.velocity_at(expected)) / norm(ct)).abs();
                        assert!(
                            dt <= tol || dt * vn <= 1e-12,
                            "{what}: expected t = {expected}, |Δt| = {dt:e}"
                        );
                        assert!(c.t <= c.horizon, "{what}");
                        hits += 1;
                    }
                    // the other order
                    let sw = solve(&mover, &target);
                    assert_eq!(sw.status, c.status, "{what}, swapped");
                    assert!(
                        sw.t == c.t || (sw.t - c.t).abs() <= 1e-12,
                        "{what}, swapped"
                    );
                }
            }
        }
    }
    assert_eq!(hits, 4 * 5 * 2, "every 'stops past' case is a hit");

    // tiny speeds, picometres to a nanometre beyond touching: no panic, a sensible answer
    for &(x0, y0) in &[(0.0, 0.0), (1.2, 0.6)] {
        for &speed in &[1e-7, 1e-5] {
            let travel = speed * speed / (2.0 * decel);
            for &delta in &[1e-12, 3e-12, 1e-11, 1e-10, 1e-9] {
                for &angle in &[0.0, 1.0] {
                    let (ux, uy) = unit(angle);
                    let d = 2.0 * R + delta;
                    let target = Ball::at_rest(x0 + d * ux, y0 + d * uy);
                    let mover = rolling(x0, y0, speed, angle);
                    let c = solve(&target, &mover);
                    let s = gap0(&target, &mover);
                    let what = format!(
                        "v {speed}, δ {delta} (gap {s:e}, travel {travel:e}) at ({x0}, {y0}), \
                         angle {angle}: {c:?}"
                    );
                    assert!(c.t >= 0.0, "{what}");
                    if s.abs() <= 1e-12 {
                        // touching and approaching (rule 3)
                        assert_eq!(c.status, Status::Hit, "{what}");
                        assert!(c.t <= c.horizon, "{what}");
                        assert!(gap_at(&target, &mover, c.t).abs() <= 1e-12, "{what}");
                    } else if s >= travel * (1.0 + 1e-6) {
                        assert_none(&c, &what);
                    } else if s <= travel * (1.0 - 1e-6) {
                        assert_eq!(c.status, Status::Hit, "{what}");
                        let expected = travel_time(speed, decel, s);
                        // the gap itself is known to ~1e-17 m, so compare the gap error
                        let dt = (c.t - expected).abs();
                        assert!(
                            dt <= 1e-6 * expected || dt * speed <= 1e-15,
                            "{what}: expected {expected}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn far_from_origin() {
    let chase = (rolling(0.0, 0.0, 2.0, 0.0), rolling(4.0 * R, 0.0, 1.0, 0.0));
    let sliding_chase = (stun(0.0, 0.0, 2.0, 0.9), {
        let (ux, uy) = unit(0.9);
        stun(4.0 * R * ux, 4.0 * R * uy, 1.0, 0.9)
    });
    // glancing: a rolling ball passes a still one with its centre line 1.5R off
    let glance = (Ball::at_rest(0.0, 0.0), rolling(-0.8, 1.5 * R, 1.5, 0.0));
    // closed form for the glance: contact when x = −R√1.75, i.e. after travel 0.8 − R√1.75
    let pp = p();
    let glance_t = travel_time(1.5, pp.mu_r * pp.g, 0.8 - R * 1.75f64.sqrt());
    let base_glance = solve(&glance.0, &glance.1);
    assert_eq!(base_glance.status, Status::Hit);
    assert!(
        (base_glance.t - glance_t).abs() <= 1e-12,
        "glance at the origin: {} vs closed form {glance_t}",
        base_glance.t
    );
    for (name, (b1, b2), expected) in [
        ("chase", chase, Some(2.0 * R)),
        ("sliding chase", sliding_chase, Some(2.0 * R)),
        ("glance", glance, Some(glance_t)),
    ] {
        let base = solve(&b1, &b2);
        assert_eq!(base.status, Status::Hit, "{name}: {base:?}");
        if let Some(e) = expected {
            assert!((base.t - e).abs() <= 1e-12, "{name}: {} vs {e}", base.t);
        }
        for (dx, dy) in [
            (1000.0, 1000.0),
            (-1000.0, 1000.0),
            (1000.0, -1000.0),
            (-1000.0, -1000.0),
        ] {
            let m1 = Ball {
                x: b1.x + dx,
                y: b1.y + dy,
                ..b1
            };
            let m2 = Ball {
                x: b2.x + dx,
                y: b2.y + dy,
                ..b2
            };
            let c = solve(&m1, &m2);
            let what = format!("{name} moved by ({dx}, {dy}): {c:?} vs {base:?}");
            assert_eq!(c.status, base.status, "{what}");
            assert_eq!(c.horizon, base.horizon, "{what}");
            assert!((c.t - base.t).abs() <= 1e-9, "{what}");
        }
    }
}

#[test]
fn pocketed_and_still_never_collide() {
    let pocketed = |x: f64, y: f64| Ball {
        state: MotionState::Pocketed,
        ..Ball::at_rest(x, y)
    };
    let (x1, y1) = (0.8, 0.4);
    let others = |x: f64, y: f64| {
        [
            Ball::at_rest(x, y),
            Ball {
                state: MotionState::Spinning,
                wz: 30.0,
                ..Ball::at_rest(x, y)
            },
            // aimed straight at the pocketed ball
            Ball::rolling(x, y, x1 - x, y1 - y, R),
            Ball {
                state: MotionState::Sliding,
                vx: 2.0 * (x1 - x),
                vy: 2.0 * (y1 - y),
                wx: 10.0,
                ..Ball::at_rest(x, y)
            },
            pocketed(x, y),
        ]
    };
    // apart, touching, overlapping, coincident
    for (x, y) in [
        (x1 + 0.5, y1 + 0.2),
        (x1 + 2.0 * R, y1),
        (x1 + R, y1),
        (x1, y1),
    ] {
        for other in others(x, y) {
            let pk = pocketed(x1, y1);
            assert_none(&solve(&pk, &other), &format!("pocketed + {other:?}"));
            assert_none(&solve(&other, &pk), &format!("{other:?} + pocketed"));
        }
    }

    // two balls that do not move never collide, even overlapping (rule 1 before rule 2)
    let spinning = |x: f64, y: f64, wz: f64| Ball {
        state: MotionState::Spinning,
        wz,
        ..Ball::at_rest(x, y)
    };
    for (x, y) in [
        (x1 + 0.5, y1 + 0.2),
        (x1 + 2.0 * R, y1),
        (x1 + 2.0 * R - 1e-6, y1),
        (x1 + R, y1),
        (x1, y1),
    ] {
        for (b1, b2) in [
            (Ball::at_rest(x1, y1), Ball::at_rest(x, y)),
            (Ball::at_rest(x1, y1), spinning(x, y, -12.0)),
            (spinning(x1, y1, 5.0), spinning(x, y, 50.0)),
        ] {
            let c = solve(&b1, &b2);
            let what = format!("{b1:?} + {b2:?}");
            assert_none(&c, &what);
            assert_eq!(c.horizon, f64::INFINITY, "{what}");
            assert_none(&solve(&b2, &b1), &format!("{what}, swapped"));
        }
    }
}
