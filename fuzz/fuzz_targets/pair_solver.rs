//! The pair solver on arbitrary finite ball states and parameters, within physical ranges
//! and far outside them.
//!
//! Hard requirements, on every input: no panic; the time is never NaN; `none` has time
//! `∞`, `overlap` time `0`, `hit` a finite time in `[0, H]`; the horizon is `H` as
//! `pair_horizon` gives it and never NaN; `pair_times` on a one-table batch gives the same
//! answer as `pair_contact`.
//!
//! The contract (rules 1–4), wherever the paths are finite and `|A|`, `|B|`, `|C|`, `R` and
//! `H` are each 0 or within 1e±60 (the solver multiplies up to four of them; beyond that
//! products overflow or underflow into subnormals and f64 cannot decide): overlap iff
//! `|C| − 2R < −CONTACT_TOL`; a hit is in contact at `t` (|gap| within `tol`), approaching
//! (the normal speed is not clearly positive), with no contact deeper than `tol` in
//! `[0, t]`; a none has no contact deeper than `tol` in `[0, H]`. `tol = 1e-10 S + 2
//! CONTACT_TOL` with `S = |C| + |B| T + |A| T² + 2R` the length scale up to the end `T` of
//! the interval checked: grazes shallower than that are undecidable in f64 and excused.
//!
//! The checker is independent of the solver's code: the gap's minimum over an interval is
//! found from the critical points of `g(s) = |C(s)|²` (a quartic), each bracketed between
//! the roots of `g''` (where `g'` is monotone) and found by plain bisection, plus a grid
//! of samples; distances are taken with `hypot` (no overflow of squares).
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use kisstime::model::Vec2;
use kisstime::motion::{BallPath, PATH_MOVES, PATH_POCKETED};
use kisstime::query::CONTACT_TOL;
use kisstime::query::RelPath;
use kisstime::{Ball, Batch, MotionState, Params, Status, ball_path, pair_contact, pair_times};

/// Reads the fuzzer's bytes as a stream of choices (zeros once they run out).
struct Bytes<'a> {
    data: &'a [u8],
}

impl Bytes<'_> {
    fn u8(&mut self) -> u8 {
        match self.data.split_first() {
            Some((&b, rest)) => {
                self.data = rest;
                b
            }
            None => 0,
        }
    }

    fn u64(&mut self) -> u64 {
        let mut v = 0u64;
        for _ in 0..8 {
            v = (v << 8) | self.u8() as u64;
        }
        v
    }

    /// A uniform number in `[0, 1)`.
    fn unit(&mut self) -> f64 {
        (self.u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A finite number for a field whose physical range is `[lo, hi]`: mostly inside it,
    /// often at edge values, sometimes anywhere in f64 (raw bits, log-uniform magnitudes).
    fn value(&mut self, lo: f64, hi: f64) -> f64 {
        match self.u8() % 16 {
            0 => {
                let v = f64::from_bits(self.u64());
                if v.is_finite() { v } else { 0.0 }
            }
            1 => {
                // log-uniform magnitude 10^[-320, 308], either sign
                let sign = if self.u8() & 1 == 0 { 1.0 } else { -1.0 };
                let e = -320.0 + 628.0 * self.unit();
                let v = sign * 10f64.powf(e);
                if v.is_finite() { v } else { sign * f64::MAX }
            }
            2 => 0.0,
            3 => {
                const SPECIAL: [f64; 16] = [
                    0.0,
                    -0.0,
                    1.0,
                    -1.0,
                    f64::MIN_POSITIVE,
                    -f64::MIN_POSITIVE,
                    5e-324,
                    -5e-324,
                    f64::MAX,
                    f64::MIN,
                    1e-12,
                    -1e-12,
                    1e150,
                    -1e150,
                    1e-150,
                    0.028575,
                ];
                SPECIAL[self.u8() as usize % 16]
            }
            4 => {
                // the physical range scaled by a power of ten, 10^[-20, 20]
                let k = (self.u8() % 41) as i32 - 20;
                (lo + (hi - lo) * self.unit()) * 10f64.powi(k)
            }
            _ => lo + (hi - lo) * self.unit(),
        }
    }

    /// A positive parameter around `typical` (often exactly it), sometimes anything.
    fn param(&mut self, typical: f64) -> f64 {
        match self.u8() % 4 {
            0 | 1 => typical,
            2 => self.value(0.5 * typical, 2.0 * typical).abs(),
            _ => self.value(0.1 * typical, 10.0 * typical).abs(),
        }
    }

    fn state(&mut self) -> MotionState {
        match self.u8() % 8 {
            0 => MotionState::Stationary,
            1 => MotionState::Spinning,
            2 => MotionState::Pocketed,
            3 | 4 | 5 => MotionState::Sliding,
            _ => MotionState::Rolling,
        }
    }

    fn ball(&mut self, radius: f64) -> Ball {
        let state = self.state();
        let x = self.value(0.0, 2.54);
        let y = self.value(0.0, 1.27);
        let vx = self.value(-6.0, 6.0);
        let vy = self.value(-6.0, 6.0);
        let wz = self.value(-200.0, 200.0);
        if state == MotionState::Rolling && self.u8() % 2 == 0 {
            // natural roll
            return Ball {
                wz,
                ..Ball::rolling(x, y, vx, vy, radius)
            };
        }
        let wx = self.value(-200.0, 200.0);
        let wy = self.value(-200.0, 200.0);
        Ball::from_numbers(state, [x, y, vx, vy, wx, wy, wz])
    }
}

/// The input: parameters and two balls, built from the bytes in one of a few layouts that
/// put the pair where the rules change (touching, aimed, twins, stopping short).
fn decode(data: &[u8]) -> (Params, Ball, Ball) {
    let mut b = Bytes { data };
    let layout = b.u8() % 8;
    let d = Params::default();
    let params = Params {
        radius: b.param(d.radius),
        mu_s: b.param(d.mu_s),
        mu_r: b.param(d.mu_r),
        mu_sp: b.param(d.mu_sp),
        g: b.param(d.g),
    };
    let r = params.radius;
    let b1 = b.ball(r);
    let mut b2 = b.ball(r);
    match layout {
        // ball 2 at centre distance 2R + δ from ball 1, in direction φ
        1 | 2 => {
            const DELTAS: [f64; 12] = [
                0.0, 1e-13, -1e-13, 5e-13, -5e-13, 1e-12, -1e-12, 2e-12, -2e-12, 1e-9, -1e-9, 1e-6,
            ];
            let delta = if b.u8() % 4 == 0 {
                b.value(-1e-3, 1e-3)
            } else {
                DELTAS[b.u8() as usize % DELTAS.len()]
            };
            let phi = std::f64::consts::TAU * b.unit();
            let dist = 2.0 * r + delta;
            b2.x = b1.x + dist * phi.cos();
            b2.y = b1.y + dist * phi.sin();
        }
        // ball 2 aimed at ball 1, within ±1.3 times the half-angle that still hits
        3 | 4 => {
            let (dx, dy) = (b1.x - b2.x, b1.y - b2.y);
            let dist = dx.hypot(dy);
            let half = if dist > 0.0 {
                (2.0 * r / dist).min(1.0).asin()
            } else {
                0.0
            };
            let dir = dy.atan2(dx) + (2.6 * b.unit() - 1.3) * half;
            let speed = b2.vx.hypot(b2.vy);
            b2.vx = speed * dir.cos();
            b2.vy = speed * dir.sin();
            if b2.state == MotionState::Rolling {
                b2.wx = -b2.vy / r;
                b2.wy = b2.vx / r;
            }
        }
        // ball 2 a copy of ball 1 elsewhere, its velocity perturbed a little
        5 => {
            let eps = [0.0, 1e-15, 1e-12, 1e-9, 1e-6][b.u8() as usize % 5];
            b2 = Ball {
                x: b2.x,
                y: b2.y,
                vx: b1.vx * (1.0 + eps),
                vy: b1.vy * (1.0 - eps),
                ..b1
            };
        }
        // a ball rolling straight at a still one, stopping ε short of or past contact
        6 => {
            let eps = [0.0, 1e-12, -1e-12, 1e-9, -1e-9, 1e-6, -1e-6][b.u8() as usize % 7];
            let (dx, dy) = (b1.x - b2.x, b1.y - b2.y);
            let dist = dx.hypot(dy);
            if dist > 0.0 && dist.is_finite() {
                let travel = (dist - 2.0 * r + eps).max(0.0);
                let v = (2.0 * params.mu_r * params.g * travel).sqrt();
                let (ux, uy) = (dx / dist, dy / dist);
                b2 = Ball::rolling(b2.x, b2.y, v * ux, v * uy, r);
            }
        }
        _ => {}
    }
    (params, sanitize(b1), sanitize(b2))
}

/// Non-finite numbers (from a layout's arithmetic on extreme values) become 0.
fn sanitize(mut b: Ball) -> Ball {
    for v in [
        &mut b.x, &mut b.y, &mut b.vx, &mut b.vy, &mut b.wx, &mut b.wy, &mut b.wz,
    ] {
        if !v.is_finite() {
            *v = 0.0;
        }
    }
    b
}

fn finite_path(p: &BallPath) -> bool {
    [p.a.x, p.a.y, p.b.x, p.b.y, p.c.x, p.c.y]
        .iter()
        .all(|v| v.is_finite())
}

fn len(v: Vec2) -> f64 {
    v.x.hypot(v.y)
}

/// `|C(s)| − 2R`, with `hypot` (no overflow of squares).
fn gap(rel: &RelPath, r: f64, s: f64) -> f64 {
    len(rel.at(s)) - 2.0 * r
}

/// `g'(s)/2 = C(s)·C'(s)`.
fn half_dg(rel: &RelPath, s: f64) -> f64 {
    let c = rel.at(s);
    let v = rel.velocity_at(s);
    c.x * v.x + c.y * v.y
}

/// The smallest gap on `[lo, hi]` and where: at the ends, at every critical point of
/// `|C(s)|²` (bisection on the pieces between the roots of its second derivative, where
/// the first derivative is monotone), and on a grid of 64 samples.
fn min_gap(rel: &RelPath, r: f64, lo: f64, hi: f64) -> (f64, f64) {
    let mut best = (gap(rel, r, lo), lo);
    let mut consider = |s: f64| {
        let g = gap(rel, r, s);
        if g < best.0 || g.is_nan() {
            best = (g, s);
        }
    };
    consider(hi);
    for k in 1..64 {
        consider(lo + (hi - lo) * (k as f64 / 64.0));
    }
    // g''/4 = |C'|²/2 + A·C = 3|A|² s² + 3 A·B s + (|B|²/2 + A·C)
    let (a, b, c) = (rel.a, rel.b, rel.c);
    let qa = 3.0 * (a.x * a.x + a.y * a.y);
    let qb = 3.0 * (a.x * b.x + a.y * b.y);
    let qc = 0.5 * (b.x * b.x + b.y * b.y) + (a.x * c.x + a.y * c.y);
    let mut knots = vec![lo, hi];
    if qa != 0.0 {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc >= 0.0 {
            let sq = disc.sqrt();
            knots.push((-qb - sq) / (2.0 * qa));
            knots.push((-qb + sq) / (2.0 * qa));
        }
    } else if qb != 0.0 {
        knots.push(-qc / qb);
    }
    knots.retain(|s| s.is_finite() && *s >= lo && *s <= hi);
    knots.sort_by(f64::total_cmp);
    for w in knots.windows(2) {
        let (mut x0, mut x1) = (w[0], w[1]);
        let (d0, d1) = (half_dg(rel, x0), half_dg(rel, x1));
        if !(d0 < 0.0 && d1 > 0.0) {
            continue; // a minimum needs g' going from − to +
        }
        for _ in 0..200 {
            let mid = 0.5 * (x0 + x1);
            if mid <= x0 || mid >= x1 {
                break;
            }
            if half_dg(rel, mid) < 0.0 {
                x0 = mid;
            } else {
                x1 = mid;
            }
        }
        consider(x0);
        consider(x1);
    }
    best
}

/// How the inputs were checked: invalid parameters, rule 1, hard requirements only (outside
/// the box), contract checked for a hit, a none, an overlap. With `PAIR_SOLVER_STATS` set
/// in the environment the counts are printed at every power of two of inputs.
static COUNTS: [AtomicU64; 6] = [const { AtomicU64::new(0) }; 6];
static TOTAL: AtomicU64 = AtomicU64::new(0);

fn count(k: usize) {
    COUNTS[k].fetch_add(1, Relaxed);
    let n = TOTAL.fetch_add(1, Relaxed) + 1;
    if n.is_power_of_two() && n >= 1 << 16 && std::env::var_os("PAIR_SOLVER_STATS").is_some() {
        let c: Vec<u64> = COUNTS.iter().map(|c| c.load(Relaxed)).collect();
        eprintln!(
            "stats after {n}: invalid params {}, rule 1 {}, hard only {}, contract hit {}, none {}, overlap {}",
            c[0], c[1], c[2], c[3], c[4], c[5]
        );
    }
}

fuzz_target!(|data: &[u8]| {
    let (params, b1, b2) = decode(data);
    let valid = params.validate().is_ok();

    // the batch driver: invalid parameters are an error, valid ones the same answer; a
    // ball beyond the physical range the batches answer for (|position| ≤ 1e4 m, |velocity|
    // ≤ 1e3 m/s, |spin| ≤ 1e5 rad/s) is refused by the batch, naming it (the solver's
    // contract covers the range the batch accepts: beyond it a path's horizon can be NaN)
    let mut batch = Batch::new();
    let batch_answer = match batch.push_table(0, [(0, b1), (1, b2)]) {
        Ok(()) => {
            let answer = pair_times(&batch, &params);
            assert_eq!(answer.is_ok(), valid, "{params:?}");
            if !valid {
                count(0);
                return;
            }
            answer.unwrap()[0]
        }
        Err(e) => {
            let message = e.to_string();
            assert!(
                message.contains("beyond the physical range"),
                "{message}\n{b1:?}\n{b2:?}"
            );
            count(if valid { 2 } else { 0 });
            return;
        }
    };

    let p1 = ball_path(&b1, &params);
    let p2 = ball_path(&b2, &params);
    let c = pair_contact(&p1, &p2, params.radius);
    let h = p1.tmax.min(p2.tmax);
    let ctx = || format!("{params:?}\n{b1:?}\n{b2:?}\n{p1:?}\n{p2:?}\n{c:?}");

    // hard requirements
    assert_eq!(
        c.t.to_bits(),
        batch_answer.t.to_bits(),
        "batch differs: {batch_answer:?}\n{}",
        ctx()
    );
    assert_eq!(c.status, batch_answer.status);
    assert!(!c.t.is_nan(), "NaN time\n{}", ctx());
    assert!(
        !c.horizon.is_nan() && c.horizon >= 0.0,
        "bad horizon\n{}",
        ctx()
    );
    assert_eq!(c.horizon.to_bits(), h.to_bits(), "horizon\n{}", ctx());
    match c.status {
        Status::None => assert_eq!(c.t, f64::INFINITY, "{}", ctx()),
        Status::Overlap => assert_eq!(c.t, 0.0, "{}", ctx()),
        Status::Hit => assert!(c.t.is_finite() && c.t >= 0.0 && c.t <= h, "{}", ctx()),
    }
    // rule 1
    let flags = p1.flags | p2.flags;
    if flags & PATH_POCKETED != 0 || flags & PATH_MOVES == 0 {
        assert_eq!(c.status, Status::None, "rule 1\n{}", ctx());
        count(1);
        return;
    }

    // the contract, where f64 can decide it
    if !(finite_path(&p1) && finite_path(&p2) && h.is_finite()) {
        count(2);
        return;
    }
    let rel = RelPath::between(&p1, &p2);
    if ![rel.a.x, rel.a.y, rel.b.x, rel.b.y, rel.c.x, rel.c.y]
        .iter()
        .all(|v| v.is_finite())
    {
        count(2);
        return;
    }
    let r = params.radius;
    // the box where f64 can decide the contract: every magnitude the solver multiplies
    // (the path's vectors, R, H) zero or within 1e±60, so that products of four of them
    // neither overflow nor lose precision to underflow
    let in_box = |x: f64| x == 0.0 || (1e-60..=1e60).contains(&x);
    if ![len(rel.a), len(rel.b), len(rel.c), r, h]
        .into_iter()
        .all(in_box)
    {
        count(2);
        return;
    }
    let end = if c.status == Status::Hit { c.t } else { h };
    let scale = len(rel.c) + len(rel.b) * end + len(rel.a) * end * end + 2.0 * r;
    let tol = 1e-10 * scale + 2.0 * CONTACT_TOL;
    // rule 2, decided exactly as documented
    let d0 = (rel.c.x * rel.c.x + rel.c.y * rel.c.y).sqrt() - 2.0 * r;
    assert_eq!(
        c.status == Status::Overlap,
        d0 < -CONTACT_TOL,
        "overlap iff d0 < -CONTACT_TOL, d0 = {d0:e}\n{}",
        ctx()
    );
    count(match c.status {
        Status::Hit => 3,
        Status::None => 4,
        Status::Overlap => 5,
    });
    match c.status {
        Status::Overlap => {}
        Status::Hit => {
            let gt = gap(&rel, r, c.t);
            assert!(
                gt.abs() <= tol,
                "not in contact at t: gap {gt:e}, tol {tol:e}\n{}",
                ctx()
            );
            // touching at 0, to the contact tolerance or the rounding of |C| at the pair's
            // scale (at R = 1e16 m one ulp of |C| is 4 m: finding 36)
            if c.t == 0.0 {
                assert!(
                    d0.abs() <= tol,
                    "t = 0 but not touching: {d0:e}, tol {tol:e}\n{}",
                    ctx()
                );
            }
            // approaching: the normal speed is not clearly positive
            let ct = rel.at(c.t);
            let vt = rel.velocity_at(c.t);
            let vn = (ct.x * vt.x + ct.y * vt.y) / len(ct).max(f64::MIN_POSITIVE);
            // (plus the rounding of `C'(t)` itself, for a ball that stops right there)
            let band = len(vt) * (1e-6 + 2.0 * (tol / (2.0 * r)).sqrt())
                + 1e-12 * (len(rel.b) + 2.0 * len(rel.a) * c.t);
            assert!(
                vn <= band,
                "separating at t: vn {vn:e}, band {band:e}\n{}",
                ctx()
            );
            let (m, at) = min_gap(&rel, r, 0.0, c.t);
            assert!(
                m > -tol,
                "contact before t: gap {m:e} at {at}, tol {tol:e}\n{}",
                ctx()
            );
        }
        Status::None => {
            let (m, at) = min_gap(&rel, r, 0.0, h);
            assert!(
                m > -tol,
                "none, but a contact: gap {m:e} at {at}, tol {tol:e}\n{}",
                ctx()
            );
        }
    }
});
