//! The seed worksheet (`docs/reference/quartic-derivation.txt`, read with its `ERRATA.md`),
//! implemented literally — rotated ball frame, `cos`/`sin`/`atan2` and all — as an
//! independent derivation of the path and quartic coefficients, checked against the
//! library's trigonometry-free table-frame form (`ball_path`, `RelPath::between`,
//! `RelPath::quartic`) on thousands of random ball states and parameter sets.
//!
//! Errata applied: μs (not μr) throughout the sliding case (erratum 2); the pair vector is
//! `A t² + B t + C` and the quartic has the linear term `d = 2(Bx Cx + By Cy)` (erratum 1);
//! motion times `2|u|/(7 μs g)` sliding, `|v|/(μr g)` rolling (erratum 4).

mod common;

use kisstime::motion::{PATH_MOVES, PATH_POCKETED};
use kisstime::{Ball, BallPath, MotionState, Params, RelPath, ball_path};
use proptest::prelude::*;

/// Relative tolerance of the comparisons (the trigonometric round trip costs a few ulps).
const RTOL: f64 = 1e-12;

/// The worksheet's six coefficients of one ball, plus its motion time.
#[derive(Clone, Copy, Debug)]
struct Sheet {
    ax: f64,
    ay: f64,
    bx: f64,
    by: f64,
    cx: f64,
    cy: f64,
    /// Erratum 4 (`∞` for a ball that does not move).
    tmax: f64,
}

/// The worksheet, case by case, in the rotated ball frame.
fn worksheet(ball: &Ball, p: &Params) -> Sheet {
    let (rx, ry) = (ball.x, ball.y);
    let (vx, vy) = (ball.vx, ball.vy);
    // direction of travel and the ball frame: V_B = (|v|, 0)
    let theta = vy.atan2(vx);
    let (sin_t, cos_t) = theta.sin_cos();
    let v0 = vx.hypot(vy);
    let (v_bx, v_by) = (v0, 0.0);
    match ball.state {
        MotionState::Sliding => {
            // contact-point velocity u = v + R (ẑ × ω); ẑ × ω = (−wy, wx, 0)
            let (zx_w_x, zx_w_y) = (-ball.wy, ball.wx);
            let ux = vx + p.radius * zx_w_x;
            let uy = vy + p.radius * zx_w_y;
            let u_len = ux.hypot(uy);
            let (uhx, uhy) = if u_len > 0.0 {
                (ux / u_len, uy / u_len)
            } else {
                (0.0, 0.0)
            };
            // û rotated by −θ into the ball frame
            let u_bx = cos_t * uhx + sin_t * uhy;
            let u_by = -sin_t * uhx + cos_t * uhy;
            let mu_s = p.mu_s;
            let g = p.g;
            Sheet {
                ax: -0.5 * mu_s * g * (u_bx * cos_t - u_by * sin_t),
                ay: -0.5 * mu_s * g * (u_bx * sin_t + u_by * cos_t),
                bx: v_bx * cos_t - sin_t * v_by,
                by: sin_t * v_bx + cos_t * v_by,
                cx: rx,
                cy: ry,
                tmax: 2.0 * u_len / (7.0 * mu_s * g),
            }
        }
        MotionState::Rolling => {
            let mu_r = p.mu_r;
            let g = p.g;
            let (ax, ay) = if v0 > 0.0 {
                (-0.5 * mu_r * g * cos_t, -0.5 * mu_r * g * sin_t)
            } else {
                (0.0, 0.0)
            };
            Sheet {
                ax,
                ay,
                bx: v0 * cos_t,
                by: v0 * sin_t,
                cx: rx,
                cy: ry,
                tmax: v0 / (mu_r * g),
            }
        }
        MotionState::Stationary | MotionState::Spinning | MotionState::Pocketed => Sheet {
            ax: 0.0,
            ay: 0.0,
            bx: 0.0,
            by: 0.0,
            cx: rx,
            cy: ry,
            tmax: f64::INFINITY,
        },
    }
}

/// `|got − want| ≤ RTOL · scale` (and exact equality of infinities).
fn close(got: f64, want: f64, scale: f64) -> bool {
    if got == want {
        return true;
    }
    (got - want).abs() <= RTOL * scale
}

fn check_ball(ball: &Ball, p: &Params) -> Result<(), TestCaseError> {
    let s = worksheet(ball, p);
    let path: BallPath = ball_path(ball, p);
    let a_scale = s.ax.hypot(s.ay).max(path.a.x.hypot(path.a.y));
    let b_scale = ball.vx.hypot(ball.vy);
    prop_assert!(
        close(path.a.x, s.ax, a_scale) && close(path.a.y, s.ay, a_scale),
        "a: library ({}, {}) vs worksheet ({}, {}) for {:?}",
        path.a.x,
        path.a.y,
        s.ax,
        s.ay,
        ball
    );
    prop_assert!(
        close(path.b.x, s.bx, b_scale) && close(path.b.y, s.by, b_scale),
        "b: library ({}, {}) vs worksheet ({}, {}) for {:?}",
        path.b.x,
        path.b.y,
        s.bx,
        s.by,
        ball
    );
    prop_assert!(
        path.c.x == s.cx && path.c.y == s.cy,
        "c: library {:?} vs worksheet ({}, {})",
        path.c,
        s.cx,
        s.cy
    );
    prop_assert!(
        close(path.tmax, s.tmax, s.tmax),
        "tmax: library {} vs erratum 4 {} for {:?}",
        path.tmax,
        s.tmax,
        ball
    );
    let moves = ball.state.translates();
    prop_assert_eq!(path.flags & PATH_MOVES != 0, moves);
    prop_assert_eq!(
        path.flags & PATH_POCKETED != 0,
        ball.state == MotionState::Pocketed
    );
    Ok(())
}

/// The pair coefficients and the quartic from the worksheet + errata, checked against
/// `RelPath::between(..)` and `RelPath::quartic(R)`.
fn check_pair(b1: &Ball, b2: &Ball, p: &Params) -> Result<(), TestCaseError> {
    let s1 = worksheet(b1, p);
    let s2 = worksheet(b2, p);
    // the worksheet's six pair coefficients
    let ax = s2.ax - s1.ax;
    let ay = s2.ay - s1.ay;
    let bx = s2.bx - s1.bx;
    let by = s2.by - s1.by;
    let cx = s2.cx - s1.cx;
    let cy = s2.cy - s1.cy;
    // erratum 1: the quartic of |A t² + B t + C|² − 4 Rad²
    let rad = p.radius;
    let qa = ax * ax + ay * ay;
    let qb = 2.0 * ax * bx + 2.0 * ay * by;
    let qc = bx * bx + 2.0 * ax * cx + 2.0 * ay * cy + by * by;
    let qd = 2.0 * (bx * cx + by * cy);
    let qe = cx * cx + cy * cy - 4.0 * rad * rad;

    let rel = RelPath::between(&ball_path(b1, p), &ball_path(b2, p));
    // magnitudes the coefficients are formed from
    let ma = s1.ax.hypot(s1.ay) + s2.ax.hypot(s2.ay);
    let mb = s1.bx.hypot(s1.by) + s2.bx.hypot(s2.by);
    let mc = cx.hypot(cy);
    prop_assert!(
        close(rel.a.x, ax, ma) && close(rel.a.y, ay, ma),
        "A: library {:?} vs worksheet ({ax}, {ay})",
        rel.a
    );
    prop_assert!(
        close(rel.b.x, bx, mb) && close(rel.b.y, by, mb),
        "B: library {:?} vs worksheet ({bx}, {by})",
        rel.b
    );
    prop_assert!(
        rel.c.x == cx && rel.c.y == cy,
        "C: library {:?} vs worksheet ({cx}, {cy})",
        rel.c
    );
    let q = rel.quartic(rad);
    let scales = [
        ma * ma,
        2.0 * ma * mb,
        mb * mb + 2.0 * ma * mc,
        2.0 * mb * mc,
        mc * mc + 4.0 * rad * rad,
    ];
    let want = [qa, qb, qc, qd, qe];
    for k in 0..5 {
        prop_assert!(
            close(q[k], want[k], scales[k]),
            "quartic coefficient {} ({}): library {} vs worksheet {} (scale {}); {:?} {:?}",
            k,
            ["a", "b", "c", "d", "e"][k],
            q[k],
            want[k],
            scales[k],
            b1,
            b2
        );
    }
    // and the quartic is |C(t)|² − 4R² (the errata's linear term included) at a few times
    for t in [0.0, 0.01, 0.3, 1.7] {
        let x = (ax * t + bx) * t + cx;
        let y = (ay * t + by) * t + cy;
        let direct = x * x + y * y - 4.0 * rad * rad;
        let poly = (((qa * t + qb) * t + qc) * t + qd) * t + qe;
        let t_scale = scales[0] * t.powi(4)
            + scales[1] * t.powi(3)
            + scales[2] * t * t
            + scales[3] * t
            + scales[4];
        prop_assert!(
            (poly - direct).abs() <= 1e-11 * t_scale,
            "t = {t}: quartic {poly} vs |C(t)|² − 4R² {direct}"
        );
    }
    Ok(())
}

// ---------------------------------------------------------------- strategies

fn params() -> impl Strategy<Value = Params> {
    prop_oneof![
        Just(Params::default()),
        (0.01f64..0.05, 0.05f64..0.6, 0.002f64..0.05, 1.0f64..25.0).prop_map(
            |(radius, mu_s, mu_r, g)| Params {
                radius,
                mu_s,
                mu_r,
                mu_sp: 0.444 * radius,
                g,
            }
        ),
    ]
}

fn position() -> impl Strategy<Value = (f64, f64)> {
    prop_oneof![
        4 => (0.0f64..2.54, 0.0f64..1.27),
        1 => (-1000.0f64..1000.0, -1000.0f64..1000.0),
    ]
}

fn spin() -> impl Strategy<Value = (f64, f64, f64)> {
    (-200.0f64..200.0, -200.0f64..200.0, -200.0f64..200.0)
}

/// A ball in `state`; sliding balls get random spin, rolling balls a non-zero speed.
fn ball_in(state: MotionState) -> BoxedStrategy<Ball> {
    let speed = match state {
        MotionState::Rolling => prop_oneof![1e-6f64..6.0, 1e-9f64..1e-3].boxed(),
        MotionState::Sliding => prop_oneof![8 => 0.0f64..6.0, 1 => Just(0.0)].boxed(),
        _ => Just(0.0).boxed(),
    };
    (position(), speed, 0.0f64..std::f64::consts::TAU, spin())
        .prop_map(move |((x, y), speed, dir, (wx, wy, wz))| {
            let (vx, vy) = (speed * dir.cos(), speed * dir.sin());
            match state {
                MotionState::Sliding | MotionState::Rolling => {
                    Ball::from_numbers(state, [x, y, vx, vy, wx, wy, wz])
                }
                MotionState::Spinning => Ball {
                    state,
                    wz,
                    ..Ball::at_rest(x, y)
                },
                _ => Ball {
                    state,
                    ..Ball::at_rest(x, y)
                },
            }
        })
        .boxed()
}

fn any_ball() -> impl Strategy<Value = Ball> {
    prop_oneof![
        4 => ball_in(MotionState::Sliding),
        4 => ball_in(MotionState::Rolling),
        1 => ball_in(MotionState::Stationary),
        1 => ball_in(MotionState::Spinning),
        1 => ball_in(MotionState::Pocketed),
    ]
}

// ---------------------------------------------------------------- tests

proptest! {
    #![proptest_config(common::proptest_config(0x5eed_f0e4, 3000))]

    #[test]
    fn ball_coefficients_match_the_worksheet(ball in any_ball(), p in params()) {
        check_ball(&ball, &p)?;
    }

    #[test]
    fn pair_coefficients_and_quartic_match_the_worksheet(
        b1 in any_ball(),
        b2 in any_ball(),
        p in params(),
    ) {
        check_pair(&b1, &b2, &p)?;
    }
}

proptest! {
    #![proptest_config(common::proptest_config(0x5eed_f0e4, 2000))]

    /// Two moving balls (the case where every coefficient of the quartic is in play).
    #[test]
    fn moving_pairs_match_the_worksheet(
        b1 in prop_oneof![ball_in(MotionState::Sliding), ball_in(MotionState::Rolling)],
        b2 in prop_oneof![ball_in(MotionState::Sliding), ball_in(MotionState::Rolling)],
        p in params(),
    ) {
        check_ball(&b1, &p)?;
        check_ball(&b2, &p)?;
        check_pair(&b1, &b2, &p)?;
    }
}

/// Hand-picked states where the angle θ is at a quadrant boundary or the spin cancels the
/// velocity, compared the same way.
#[test]
fn special_states_match_the_worksheet() {
    let p = Params::default();
    let r = p.radius;
    let mut balls = Vec::new();
    for (vx, vy) in [
        (1.0, 0.0),
        (-1.0, 0.0),
        (0.0, 1.0),
        (0.0, -1.0),
        (-2.0, -0.0),
        (3.0, -4.0),
        (-1e-150, 1e-150),
    ] {
        balls.push(Ball::rolling(0.4, 0.7, vx, vy, r));
        // stun: no spin, u = v
        balls.push(Ball {
            state: MotionState::Sliding,
            vx,
            vy,
            ..Ball::at_rest(0.4, 0.7)
        });
        // backspin: u opposite-ish to v
        balls.push(Ball {
            state: MotionState::Sliding,
            vx,
            vy,
            wx: 3.0 * vy / r,
            wy: -3.0 * vx / r,
            ..Ball::at_rest(0.4, 0.7)
        });
        // natural-roll spin as a sliding ball: u = 0, the state is over (tmax 0, a 0)
        balls.push(Ball {
            state: MotionState::Sliding,
            ..Ball::rolling(0.4, 0.7, vx, vy, r)
        });
    }
    // pure spin sliding in place (v = 0, θ = atan2(0, 0) = 0)
    balls.push(Ball {
        state: MotionState::Sliding,
        wx: 10.0,
        wy: -4.0,
        wz: 1.0,
        ..Ball::at_rest(1.0, 1.0)
    });
    for b in &balls {
        check_ball(b, &p).unwrap_or_else(|e| panic!("{e}"));
        for b2 in &balls {
            check_pair(b, b2, &p).unwrap_or_else(|e| panic!("{e}"));
        }
    }
    // the natural-roll sliding ball really has u = 0
    let over = ball_path(
        &Ball {
            state: MotionState::Sliding,
            ..Ball::rolling(0.0, 0.0, 2.0, 0.0, r)
        },
        &p,
    );
    assert_eq!(over.tmax, 0.0);
}

/// The worksheet as printed, without the errata, is *not* what the library computes: the
/// missing linear term and μr in the sliding case would both be visible. (Guards against
/// the test above silently comparing two copies of the same slip.)
#[test]
fn the_printed_slips_would_be_detected() {
    let p = Params::default();
    let b1 = Ball {
        state: MotionState::Sliding,
        vx: 2.0,
        vy: 0.5,
        wy: 20.0,
        ..Ball::at_rest(0.3, 0.3)
    };
    let b2 = Ball::rolling(1.2, 0.4, -1.0, 0.2, p.radius);
    let rel = RelPath::between(&ball_path(&b1, &p), &ball_path(&b2, &p));
    let q = rel.quartic(p.radius);
    // the printed quartic (7) has no linear term; this pair's d is far from 0
    assert!(q[3].abs() > 0.1, "d = {}", q[3]);
    // μr in place of μs would scale the sliding deceleration by μr/μs = 0.05
    let s1 = worksheet(&b1, &p);
    let path = ball_path(&b1, &p);
    let printed_ax = s1.ax * p.mu_r / p.mu_s;
    assert!((path.a.x - s1.ax).abs() < 1e-12);
    assert!((path.a.x - printed_ax).abs() > 0.1);
}
