//! Property tests of the pair solver on random ball pairs: every answer is checked against
//! a dense sampling of the centre distance `|C(s)|` (an independent, brute-force look at the
//! same paths), the overlap rule, invariance under translation and under swapping the balls,
//! and thread-count independence of the batch driver.
//!
//! Pairs are drawn from a mix of generators: independent random balls on a 2.54 × 1.27 m
//! table; a ball aimed at the other (± a little more than the angle that still hits); pairs
//! placed at or within picometres to millimetres of contact; and a rolling ball that stops
//! just short of or just past a still one. `generator_gives_a_useful_mix` checks that the
//! mix really contains hits, misses, overlaps and touching pairs.

mod common;

use kisstime::model::{dot, norm};
use kisstime::motion::{PATH_MOVES, PATH_POCKETED};
use kisstime::query::RelPath;
use kisstime::{
    Ball, Batch, Contact, MotionState, Params, Status, ball_path, next_collisions, next_from_pairs,
    pair_contact, pair_times,
};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;

const TABLE_W: f64 = 2.54;
const TABLE_H: f64 = 1.27;
const MAX_SPEED: f64 = 6.0;
const MAX_SPIN: f64 = 200.0;
/// Distance tolerance of the dense-sampling checks, in metres.
const GAP_TOL: f64 = 1e-9;
/// Time tolerance of the invariance checks, in seconds.
const TIME_TOL: f64 = 1e-9;

fn params() -> Params {
    Params::default()
}

// ---------------------------------------------------------------- dense sampling

/// `|C(s)| − 2R`, from the vectors.
fn gap(rel: &RelPath, r: f64, s: f64) -> f64 {
    norm(rel.at(s)) - 2.0 * r
}

/// The gap over an interval, sampled densely.
#[derive(Debug)]
struct Profile {
    /// Smallest gap found (grid plus refined local minima).
    min: f64,
    /// Where it was found.
    argmin: f64,
    /// The refined interior local minima `(s, gap)`, at most a handful (the smallest).
    minima: Vec<(f64, f64)>,
}

/// Samples `gap` on `[lo, hi]`: a grid of at least 2000 points, fine enough that the balls
/// move at most R/8 relative to each other between samples (at most 400,000 points), then
/// golden-section refinement around the smallest grid local minima.
fn profile(rel: &RelPath, r: f64, lo: f64, hi: f64) -> Profile {
    assert!(hi.is_finite() && lo <= hi);
    let speed = norm(rel.b) + 2.0 * norm(rel.a) * hi.abs().max(lo.abs());
    let travel = speed * (hi - lo);
    let n = ((travel / (r / 8.0)).ceil() as usize).clamp(2000, 400_000);
    let step = (hi - lo) / n as f64;
    let at = |k: usize| if k == n { hi } else { lo + step * k as f64 };
    let mut vals = Vec::with_capacity(n + 1);
    for k in 0..=n {
        vals.push(gap(rel, r, at(k)));
    }
    let (mut min, mut argmin) = (vals[0], lo);
    for (k, &v) in vals.iter().enumerate() {
        if v < min {
            min = v;
            argmin = at(k);
        }
    }
    // interior grid local minima, smallest first
    let mut cands: Vec<usize> = (1..n)
        .filter(|&k| vals[k] < vals[k - 1] && vals[k] <= vals[k + 1])
        .collect();
    cands.sort_by(|&i, &j| vals[i].total_cmp(&vals[j]));
    cands.truncate(6);
    let mut minima = Vec::new();
    for k in cands {
        let (s, v) = golden_min(rel, r, at(k - 1), at(k + 1));
        minima.push((s, v));
        if v < min {
            min = v;
            argmin = s;
        }
    }
    Profile {
        min,
        argmin,
        minima,
    }
}

/// Golden-section search for the minimum of `gap` on `[a, b]` (unimodal there).
fn golden_min(rel: &RelPath, r: f64, mut a: f64, mut b: f64) -> (f64, f64) {
    let phi = 0.5 * (5f64.sqrt() - 1.0);
    let mut x1 = b - phi * (b - a);
    let mut x2 = a + phi * (b - a);
    let mut f1 = gap(rel, r, x1);
    let mut f2 = gap(rel, r, x2);
    for _ in 0..120 {
        if b - a <= 1e-15 * b.abs().max(1e-300) {
            break;
        }
        if f1 <= f2 {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - phi * (b - a);
            f1 = gap(rel, r, x1);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + phi * (b - a);
            f2 = gap(rel, r, x2);
        }
    }
    if f1 <= f2 { (x1, f1) } else { (x2, f2) }
}

/// How close the pair comes to deciding hit-or-miss, time-or-other-time by rounding: the
/// smallest `|gap|` at `0`, at `H`, and at every local minimum of the gap in `(0, H)`.
fn conditioning(rel: &RelPath, r: f64, h: f64) -> f64 {
    let prof = profile(rel, r, 0.0, h);
    let mut c = gap(rel, r, 0.0).abs().min(gap(rel, r, h).abs());
    for &(_, v) in &prof.minima {
        c = c.min(v.abs());
    }
    c
}

/// The normal (centre-to-centre) relative speed at `t`.
fn normal_speed(rel: &RelPath, t: f64) -> f64 {
    let ct = rel.at(t);
    (dot(ct, rel.velocity_at(t)) / norm(ct)).abs()
}

// ---------------------------------------------------------------- generators

#[derive(Clone, Copy, Debug)]
struct Pair {
    b1: Ball,
    b2: Ball,
}

impl Pair {
    fn paths(&self) -> (kisstime::BallPath, kisstime::BallPath) {
        let p = params();
        (ball_path(&self.b1, &p), ball_path(&self.b2, &p))
    }

    fn contact(&self) -> Contact {
        let (p1, p2) = self.paths();
        pair_contact(&p1, &p2, params().radius)
    }

    fn rel(&self) -> RelPath {
        let (p1, p2) = self.paths();
        RelPath::between(&p1, &p2)
    }

    /// `H = min(tmax₁, tmax₂)`.
    fn horizon(&self) -> f64 {
        let (p1, p2) = self.paths();
        p1.tmax.min(p2.tmax)
    }

    /// Rule 1: a pocketed ball, or neither ball moves.
    fn rule1(&self) -> bool {
        let (p1, p2) = self.paths();
        (p1.flags | p2.flags) & PATH_POCKETED != 0 || (p1.flags | p2.flags) & PATH_MOVES == 0
    }

    fn translated(&self, dx: f64, dy: f64) -> Pair {
        let mut q = *self;
        q.b1.x += dx;
        q.b1.y += dy;
        q.b2.x += dx;
        q.b2.y += dy;
        q
    }
}

/// A ball of `state` at `(x, y)` moving with `speed` in direction `dir`; `spin` is used
/// as the sliding ball's angular velocity, `wz` only for the others.
fn make_ball(
    state: MotionState,
    (x, y): (f64, f64),
    speed: f64,
    dir: f64,
    (wx, wy, wz): (f64, f64, f64),
) -> Ball {
    let r = params().radius;
    let (vx, vy) = (speed * dir.cos(), speed * dir.sin());
    match state {
        MotionState::Sliding => Ball::from_numbers(state, [x, y, vx, vy, wx, wy, wz]),
        MotionState::Rolling => Ball {
            wz,
            ..Ball::rolling(x, y, vx, vy, r)
        },
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
}

fn state() -> impl Strategy<Value = MotionState> {
    prop_oneof![
        3 => Just(MotionState::Sliding),
        3 => Just(MotionState::Rolling),
        1 => Just(MotionState::Stationary),
        1 => Just(MotionState::Spinning),
    ]
}

fn moving_state() -> impl Strategy<Value = MotionState> {
    prop_oneof![Just(MotionState::Sliding), Just(MotionState::Rolling)]
}

fn on_table() -> impl Strategy<Value = (f64, f64)> {
    let r = params().radius;
    (r..TABLE_W - r, r..TABLE_H - r)
}

fn speed() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => 0.01f64..MAX_SPEED,
        1 => 1e-5f64..0.01,
    ]
}

fn spin() -> impl Strategy<Value = (f64, f64, f64)> {
    prop_oneof![
        3 => (-MAX_SPIN..MAX_SPIN, -MAX_SPIN..MAX_SPIN, -MAX_SPIN..MAX_SPIN),
        // milder spins: gently curving paths
        1 => (-20.0f64..20.0, -20.0f64..20.0, -20.0f64..20.0),
        1 => Just((0.0, 0.0, 0.0)),
    ]
}

fn direction() -> impl Strategy<Value = f64> {
    0.0f64..std::f64::consts::TAU
}

fn random_ball() -> impl Strategy<Value = Ball> {
    (state(), on_table(), speed(), direction(), spin())
        .prop_map(|(s, pos, v, dir, w)| make_ball(s, pos, v, dir, w))
}

/// Two independent random balls.
fn random_pair() -> impl Strategy<Value = Pair> {
    (random_ball(), random_ball()).prop_map(|(b1, b2)| Pair { b1, b2 })
}

/// A ball that is mostly still (a target), sometimes moving.
fn target_ball() -> impl Strategy<Value = Ball> {
    prop_oneof![
        2 => (
            prop_oneof![Just(MotionState::Stationary), Just(MotionState::Spinning)],
            on_table(),
            spin(),
        )
            .prop_map(|(s, pos, w)| make_ball(s, pos, 0.0, 0.0, w)),
        1 => random_ball(),
    ]
}

/// Ball 2 aimed at ball 1 within ±1.3 times the half-angle that still hits.
fn aimed_pair() -> impl Strategy<Value = Pair> {
    (
        target_ball(),
        moving_state(),
        on_table(),
        speed(),
        -1.3f64..1.3,
        spin(),
    )
        .prop_map(|(b1, s2, pos2, v, frac, w)| {
            let r = params().radius;
            let (dx, dy) = (b1.x - pos2.0, b1.y - pos2.1);
            let dist = dx.hypot(dy);
            let half = (2.0 * r / dist).min(1.0).asin();
            let dir = dy.atan2(dx) + frac * half;
            Pair {
                b1,
                b2: make_ball(s2, pos2, v, dir, w),
            }
        })
}

/// Ball 2 placed at centre distance `2R + δ` from ball 1, δ from −1 mm to +1 mm with many
/// picometre values around the touching tolerance; ball 2 heads towards, away, sideways
/// or anywhere.
fn near_pair() -> impl Strategy<Value = Pair> {
    let deltas = prop::sample::select(vec![
        -1e-3, -1e-6, -1e-9, -2e-12, -1e-12, -5e-13, 0.0, 5e-13, 1e-12, 2e-12, 1e-9, 1e-6, 1e-3,
    ]);
    (
        random_ball(),
        state(),
        deltas,
        direction(),
        speed(),
        prop_oneof![
            Just(std::f64::consts::PI),
            Just(0.0),
            Just(std::f64::consts::FRAC_PI_2),
            -0.3f64..0.3,
            direction(),
        ],
        spin(),
    )
        .prop_map(|(b1, s2, delta, phi, v, rel_dir, w)| {
            let r = params().radius;
            let d = 2.0 * r + delta;
            let pos2 = (b1.x + d * phi.cos(), b1.y + d * phi.sin());
            // rel_dir = π: straight at ball 1; 0: straight away
            let dir = phi + rel_dir;
            Pair {
                b1,
                b2: make_ball(s2, pos2, v, dir, w),
            }
        })
}

/// A rolling ball heading at a still one with the speed that makes it stop `ε` past
/// (ε > 0) or short of (ε < 0) first contact; straight, or with a small lateral offset.
fn stop_pair() -> impl Strategy<Value = Pair> {
    let eps = prop::sample::select(vec![
        -1e-3, -1e-6, -1e-9, -1e-12, 0.0, 1e-12, 1e-9, 1e-6, 1e-3, 1e-2,
    ]);
    (
        on_table(),
        prop_oneof![Just(MotionState::Stationary), Just(MotionState::Spinning)],
        0.1f64..2.0,
        direction(),
        eps,
        prop_oneof![Just(0.0), -1.0f64..1.0],
    )
        .prop_map(|(pos1, s1, dist, phi, eps, offset)| {
            let p = params();
            let r = p.radius;
            let b1 = make_ball(s1, pos1, 0.0, 0.0, (0.0, 0.0, 7.0));
            let pos2 = (pos1.0 + dist * phi.cos(), pos1.1 + dist * phi.sin());
            // travel |v|²/(2 μr g) = dist − 2R + ε
            let travel = (dist - 2.0 * r + eps).max(0.0);
            let v = (2.0 * p.mu_r * p.g * travel).sqrt();
            let dir = phi + std::f64::consts::PI + offset * 1e-3;
            Pair {
                b1,
                b2: Ball::rolling(pos2.0, pos2.1, v * dir.cos(), v * dir.sin(), r),
            }
        })
}

/// Ball 2 a copy of ball 1 (state, velocity, spin) somewhere else, its velocity perturbed
/// by a relative 0 to 1e-3: parallel and near-parallel motion, where the quartic's leading
/// coefficients vanish or nearly so.
fn twin_pair() -> impl Strategy<Value = Pair> {
    let two_r = 2.0 * params().radius;
    (
        prop_oneof![
            (moving_state(), on_table(), speed(), direction(), spin())
                .prop_map(|(s, pos, v, dir, w)| make_ball(s, pos, v, dir, w)),
            random_ball(),
        ],
        prop_oneof![
            (two_r..1.0, direction()),
            // touching, or a nanometre apart
            (prop::sample::select(vec![two_r, two_r + 1e-9]), direction()),
        ],
        prop::sample::select(vec![0.0, 1e-12, 1e-9, 1e-6, 1e-3]),
        direction(),
    )
        .prop_map(|(b1, (d, phi), eps, psi)| {
            let speed = b1.vx.hypot(b1.vy);
            let b2 = Ball {
                x: b1.x + d * phi.cos(),
                y: b1.y + d * phi.sin(),
                vx: b1.vx + eps * speed * psi.cos(),
                vy: b1.vy + eps * speed * psi.sin(),
                ..b1
            };
            Pair { b1, b2 }
        })
}

/// A rolling ball passing a still one with its straight path's closest approach
/// `2R − δ`, δ from −1 mm to +1 mm (δ > 0 a hit, tiny δ a graze).
fn graze_pair() -> impl Strategy<Value = Pair> {
    let deltas = prop::sample::select(vec![
        -1e-3, -1e-6, -1e-9, -1e-10, 0.0, 1e-10, 1e-9, 1e-8, 1e-6, 1e-4, 1e-3,
    ]);
    (
        target_ball(),
        0.1f64..2.0,
        direction(),
        deltas,
        prop_oneof![Just(1.0), Just(-1.0)],
        1.05f64..3.0,
    )
        .prop_map(|(b1, dist, phi, delta, side, boost)| {
            let p = params();
            let r = p.radius;
            let (ux, uy) = (phi.cos(), phi.sin());
            let (nx, ny) = (-uy * side, ux * side);
            let off = 2.0 * r - delta;
            let (x2, y2) = (b1.x - dist * ux + off * nx, b1.y - dist * uy + off * ny);
            let v = (2.0 * p.mu_r * p.g * dist).sqrt() * boost;
            Pair {
                b1,
                b2: Ball::rolling(x2, y2, v * ux, v * uy, r),
            }
        })
}

/// The mix every pair property runs on.
fn any_pair() -> impl Strategy<Value = Pair> {
    prop_oneof![
        2 => random_pair(),
        6 => aimed_pair(),
        2 => near_pair(),
        1 => stop_pair(),
        1 => twin_pair(),
        1 => graze_pair(),
    ]
}

// ---------------------------------------------------------------- checks

/// The answer agrees with rules 1–4 as seen by dense sampling of the gap.
fn check_answer(pair: &Pair) -> Result<(), TestCaseError> {
    let r = params().radius;
    let c = pair.contact();
    let h = pair.horizon();
    let rel = pair.rel();
    prop_assert_eq!(c.horizon.to_bits(), h.to_bits(), "horizon");
    if pair.rule1() || h.is_infinite() {
        prop_assert!(pair.rule1(), "an infinite horizon means nothing moves");
        prop_assert_eq!(c.status, Status::None, "rule 1");
        prop_assert_eq!(c.t, f64::INFINITY);
        return Ok(());
    }
    let d0 = gap(&rel, r, 0.0);
    prop_assert_eq!(
        c.status == Status::Overlap,
        d0 < -1e-12,
        "overlap iff |C(0)| − 2R < −1e-12 (d0 = {:e}), got {:?}",
        d0,
        c
    );
    match c.status {
        Status::Overlap => {
            prop_assert_eq!(c.t, 0.0);
        }
        Status::Hit => {
            prop_assert!(c.t >= 0.0 && c.t <= h, "t = {} outside [0, H = {}]", c.t, h);
            let gt = gap(&rel, r, c.t);
            prop_assert!(
                gt.abs() <= GAP_TOL,
                "not in contact at the reported time: |C(t)| − 2R = {:e} at t = {}",
                gt,
                c.t
            );
            if c.t == 0.0 {
                prop_assert!(d0.abs() <= 1e-12, "t = 0 but not touching, d0 = {:e}", d0);
            } else {
                let before = profile(&rel, r, 0.0, c.t);
                prop_assert!(
                    before.min > -GAP_TOL,
                    "contact before the reported time {}: gap {:e} at s = {}",
                    c.t,
                    before.min,
                    before.argmin
                );
            }
        }
        Status::None => {
            prop_assert_eq!(c.t, f64::INFINITY);
            // s = 0 itself is left out for touching pairs that separate (rule 3)
            let lo = if d0.abs() <= 1e-12 {
                f64::MIN_POSITIVE.min(h)
            } else {
                0.0
            };
            let prof = profile(&rel, r, lo, h);
            prop_assert!(
                prof.min > -GAP_TOL,
                "answer none, but the balls overlap by {:e} m at s = {} (H = {})",
                -prof.min,
                prof.argmin,
                h
            );
        }
    }
    Ok(())
}

/// `a` and `b` are the same answer: same status, times within [`TIME_TOL`] or their gap
/// error within [`GAP_TOL`].
fn same_answer(rel: &RelPath, a: &Contact, b: &Contact) -> Result<(), String> {
    if a.status != b.status {
        return Err(format!("status {} vs {}", a.status, b.status));
    }
    if a.status == Status::Hit {
        let dt = (a.t - b.t).abs();
        if !(dt <= TIME_TOL || dt * normal_speed(rel, a.t) <= GAP_TOL) {
            return Err(format!("t {} vs {} (|Δt| = {dt:e})", a.t, b.t));
        }
    }
    Ok(())
}

fn check_translation(pair: &Pair, dx: f64, dy: f64) -> Result<(), TestCaseError> {
    let moved = pair.translated(dx, dy);
    let a = pair.contact();
    let b = moved.contact();
    prop_assert_eq!(a.horizon.to_bits(), b.horizon.to_bits());
    if let Err(why) = same_answer(&pair.rel(), &a, &b) {
        // excused only where the answer hangs on sub-nanometre rounding
        let h = pair.horizon();
        let cond = if h.is_finite() {
            conditioning(&pair.rel(), params().radius, h)
        } else {
            f64::INFINITY
        };
        prop_assert!(
            cond < GAP_TOL,
            "moved by ({}, {}): {} (closest-to-graze gap {:e} m)",
            dx,
            dy,
            why,
            cond
        );
    }
    Ok(())
}

fn check_swap(pair: &Pair) -> Result<(), TestCaseError> {
    let (p1, p2) = pair.paths();
    let r = params().radius;
    let a = pair_contact(&p1, &p2, r);
    let b = pair_contact(&p2, &p1, r);
    prop_assert_eq!(a.status, b.status, "swapped: {:?} vs {:?}", a, b);
    prop_assert_eq!(a.horizon.to_bits(), b.horizon.to_bits());
    if a.status == Status::Hit {
        prop_assert!(
            (a.t - b.t).abs() <= TIME_TOL,
            "swapped: t {} vs {}",
            a.t,
            b.t
        );
    }
    Ok(())
}

// ---------------------------------------------------------------- pair properties

proptest! {
    #![proptest_config(common::proptest_config(0x0b1e_55ed, 40000))]

    /// A hit is a contact within the horizon with no contact before it; a none has no
    /// contact within the horizon; overlap iff the balls start overlapping.
    #[test]
    fn answers_agree_with_dense_sampling(pair in any_pair()) {
        check_answer(&pair)?;
    }
}

proptest! {
    #![proptest_config(common::proptest_config(0x0b1e_55ed, 10000))]

    #[test]
    fn aimed_answers_agree_with_dense_sampling(pair in aimed_pair()) {
        check_answer(&pair)?;
    }

    #[test]
    fn near_contact_answers_agree_with_dense_sampling(
        pair in prop_oneof![near_pair(), stop_pair(), graze_pair(), twin_pair()],
    ) {
        check_answer(&pair)?;
    }

    #[test]
    fn overlap_iff_the_balls_start_overlapping(pair in near_pair()) {
        let c = pair.contact();
        let d0 = gap(&pair.rel(), params().radius, 0.0);
        if pair.rule1() {
            prop_assert_eq!(c.status, Status::None);
        } else {
            prop_assert_eq!(c.status == Status::Overlap, d0 < -1e-12, "d0 = {:e}, {:?}", d0, c);
        }
    }

    #[test]
    fn answer_is_invariant_under_translation(
        pair in any_pair(),
        (dx, dy) in prop_oneof![
            (-1000.0f64..1000.0, -1000.0f64..1000.0),
            prop::sample::select(vec![
                (1000.0, 1000.0), (-1000.0, 1000.0), (1000.0, -1000.0), (-1000.0, -1000.0),
            ]),
        ],
    ) {
        check_translation(&pair, dx, dy)?;
    }

    #[test]
    fn answer_is_invariant_under_swapping_the_balls(pair in any_pair()) {
        check_swap(&pair)?;
    }
}

proptest! {
    #![proptest_config(common::proptest_config(0x0b1e_55ed, 40000))]

    /// The prunes only ever pass over pairs that the rules answer `none` without them:
    /// neither overlapping nor touching, and no entry into contact within the horizon.
    #[test]
    fn prunes_never_change_an_answer(pair in any_pair()) {
        use kisstime::query::ball_ball::{cannot_meet, first_entry, passes_wide};
        if pair.rule1() {
            return Ok(()); // nothing moves or a ball is pocketed: no prune is asked
        }
        let r = params().radius;
        let (rel, h) = (pair.rel(), pair.horizon());
        let wide = passes_wide(&rel, r, h);
        let cannot = cannot_meet(&rel, r, h);
        if wide || cannot {
            let d0 = gap(&rel, r, 0.0);
            prop_assert!(d0 > kisstime::CONTACT_TOL, "pruned at d0 = {:e}", d0);
            prop_assert!(first_entry(&rel, 4.0 * r * r, h, false) < 0.0, "pruned a hit");
            prop_assert_eq!(pair.contact().status, Status::None);
        }
    }
}

/// The generator really produces hits, misses, overlaps, touching pairs and hits at `t = 0`
/// (otherwise the properties above would be vacuous).
#[test]
fn generator_gives_a_useful_mix() {
    let mut runner = TestRunner::new(common::proptest_config(0x0b1e_55ed, 1));
    let strat = any_pair();
    let (mut hits, mut nones, mut overlaps, mut zero_hits, mut late_hits) = (0, 0, 0, 0, 0);
    let n = 4000;
    for _ in 0..n {
        let pair = strat.new_tree(&mut runner).unwrap().current();
        let c = pair.contact();
        match c.status {
            Status::Hit => {
                hits += 1;
                if c.t == 0.0 {
                    zero_hits += 1;
                }
                if c.t > 0.5 * c.horizon {
                    late_hits += 1;
                }
            }
            Status::None => nones += 1,
            Status::Overlap => overlaps += 1,
        }
    }
    println!(
        "{n} pairs: {hits} hits ({zero_hits} at t = 0, {late_hits} in the second half of H), \
         {nones} none, {overlaps} overlap"
    );
    assert!(hits * 5 > n, "too few hits: {hits} of {n}");
    assert!(nones * 4 > n, "too few nones: {nones} of {n}");
    assert!(overlaps * 50 > n, "too few overlaps: {overlaps} of {n}");
    assert!(
        zero_hits * 200 > n,
        "too few hits at t = 0: {zero_hits} of {n}"
    );
    assert!(late_hits * 100 > n, "too few late hits: {late_hits} of {n}");
}

// ---------------------------------------------------------------- batch determinism

/// A table of 2..=20 balls: random balls, some of them aimed at an earlier ball.
fn table() -> impl Strategy<Value = Vec<Ball>> {
    prop::collection::vec(
        (random_ball(), any::<bool>(), any::<prop::sample::Index>()),
        2..=20,
    )
    .prop_map(|specs| {
        let r = params().radius;
        let mut balls: Vec<Ball> = Vec::with_capacity(specs.len());
        for (ball, aim, target) in specs {
            let mut b = ball;
            if aim && !balls.is_empty() && b.state.translates() {
                let t = balls[target.index(balls.len())];
                let speed = b.vx.hypot(b.vy);
                let (dx, dy) = (t.x - b.x, t.y - b.y);
                let dist = dx.hypot(dy).max(1e-9);
                b = match b.state {
                    MotionState::Rolling => {
                        Ball::rolling(b.x, b.y, speed * dx / dist, speed * dy / dist, r)
                    }
                    _ => Ball {
                        vx: speed * dx / dist,
                        vy: speed * dy / dist,
                        ..b
                    },
                };
            }
            balls.push(b);
        }
        balls
    })
}

fn batch_of(tables: &[Vec<Ball>]) -> Batch {
    let mut batch = Batch::new();
    for (k, balls) in tables.iter().enumerate() {
        // ball ids deliberately not in push order
        let n = balls.len() as i64;
        batch
            .push_table(
                1000 - 3 * k as i64,
                balls
                    .iter()
                    .enumerate()
                    .map(|(i, b)| (3 * (n - i as i64) - 1, *b)),
            )
            .unwrap();
    }
    batch
}

fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

fn bits(c: &Contact) -> (u64, Status, u64) {
    (c.t.to_bits(), c.status, c.horizon.to_bits())
}

/// `pair_times` and `next_collisions` give bit-identical results in pools of 1, 2 and 4
/// threads, and the same as answering every pair directly in pair order.
fn check_thread_independence(tables: &[Vec<Ball>]) -> Result<(), TestCaseError> {
    let p = params();
    let batch = batch_of(tables);
    // the driver hands out groups of ≥ 4096 pairs: make sure there are several
    prop_assert!(
        batch.num_pairs() > 3 * 4096,
        "want several tasks: {} pairs",
        batch.num_pairs()
    );
    let one = in_pool(1, || pair_times(&batch, &p).unwrap());
    let two = in_pool(2, || pair_times(&batch, &p).unwrap());
    let four = in_pool(4, || pair_times(&batch, &p).unwrap());
    prop_assert_eq!(one.len(), batch.num_pairs());
    prop_assert_eq!(two.len(), batch.num_pairs());
    prop_assert_eq!(four.len(), batch.num_pairs());
    // the sequential reference: every pair of every table in pair order
    let mut reference = Vec::new();
    for k in 0..batch.num_tables() {
        let paths: Vec<_> = batch.balls(k).iter().map(|b| ball_path(b, &p)).collect();
        for (i, pi) in paths.iter().enumerate() {
            for pj in &paths[i + 1..] {
                reference.push(pair_contact(pi, pj, p.radius));
            }
        }
    }
    prop_assert_eq!(reference.len(), batch.num_pairs());
    for (idx, (((a, b), c), r)) in one.iter().zip(&two).zip(&four).zip(&reference).enumerate() {
        prop_assert_eq!(bits(a), bits(b), "pair {}: 1 vs 2 threads", idx);
        prop_assert_eq!(bits(a), bits(c), "pair {}: 1 vs 4 threads", idx);
        prop_assert_eq!(bits(a), bits(r), "pair {}: batch vs direct", idx);
    }
    // the per-table reductions agree too
    let n1 = in_pool(1, || next_collisions(&batch, &p).unwrap());
    let n2 = in_pool(2, || next_collisions(&batch, &p).unwrap());
    let from_pairs = next_from_pairs(&batch, &one);
    prop_assert_eq!(n1.len(), batch.num_tables());
    prop_assert_eq!(n2.len(), batch.num_tables());
    for ((x, y), z) in n1.iter().zip(&n2).zip(&from_pairs) {
        prop_assert_eq!((x.table, x.pair, x.status), (y.table, y.pair, y.status));
        prop_assert_eq!(x.t.to_bits(), y.t.to_bits());
        prop_assert_eq!((x.table, x.pair, x.status), (z.table, z.pair, z.status));
        prop_assert_eq!(x.t.to_bits(), z.t.to_bits());
    }
    Ok(())
}

proptest! {
    #![proptest_config(common::proptest_config(0x0b1e_55ed, 6))]

    #[test]
    fn pair_times_do_not_depend_on_the_thread_count(
        tables in prop::collection::vec(table(), 200..500),
    ) {
        check_thread_independence(&tables)?;
    }
}
