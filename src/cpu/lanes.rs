//! The ball–ball query's search for rule 4 ([`first_entry`]) for [`LANES`] pairs at once, in
//! lock step: CPU only, answers bit for bit those of [`first_entry`].
//!
//! One pair's search is a chain of dependent square roots and divisions (the inflection
//! points, the walk into the dip, the Taylor start, the Newton steps) that leaves the CPU
//! mostly waiting. Several pairs side by side, every operation on all of them at once ([`F2`], which
//! the compiler turns into SSE2 instructions, or AVX2 or AVX-512 ones where the CPU has
//! them) and every test computed for all and then selected, keep it busy without a branch
//! to mispredict. The common path of
//! [`first_entry`] — the first piece a convex dip, the walk ending inside the contact while
//! falling, then [`refine_from`](crate::query::ball_ball::refine_from) — is done here with
//! the same operations on the same numbers; a pair that leaves it (3 % of `worst`'s
//! pairs, ~20 % of `midshot`'s searched pairs) is handed back and solved by
//! [`first_entry`] itself. The GPU needs none of this: every thread there is a lane.

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use crate::model::{Vec2, norm};
use crate::motion::path::{BallPath, PATH_MOVES, PATH_POCKETED, pair_horizon};
use crate::query::ball_ball::{
    CONTACT_TOL, Contact, MAX_ITER, ROOT_ATOL, ROOT_RTOL, RelPath, WALK_STEPS, cannot_meet,
    first_contact, first_entry, passes_wide,
};
use crate::query::roots::NO_ROOT;

/// Pairs searched at once: one 512-bit register of f64s (AVX-512), two of AVX2.
pub(crate) const LANES: usize = 8;

/// [`crate::query::ball_ball::pair_contact`] up to [`first_entry`]'s search for rule 4:
/// `Ok` with the answer when it needs no search, else `Err` with the relative path and
/// horizon to search on; the answer is then `hit(t, h)` for `t ≥ 0`, else `none(h)`, as
/// in [`first_contact`].
pub(crate) fn pair_before_entry(
    p1: &BallPath,
    p2: &BallPath,
    radius: f64,
) -> Result<Contact, (RelPath, f64)> {
    let h = pair_horizon(p1, p2);
    // rule 1: a pocketed ball, or nothing moves
    if (p1.flags | p2.flags) & PATH_POCKETED != 0 || (p1.flags | p2.flags) & PATH_MOVES == 0 {
        return Ok(Contact::none(h));
    }
    let rel = RelPath::between(p1, p2);
    if passes_wide(&rel, radius, h) {
        return Ok(Contact::none(h));
    }
    if norm(rel.c) - 2.0 * radius <= CONTACT_TOL {
        // rules 2 and 3: rare, answered by first_contact itself
        return Ok(first_contact(&rel, radius, h));
    }
    if cannot_meet(&rel, radius, h) {
        return Ok(Contact::none(h));
    }
    Err((rel, h))
}

/// Pairs waiting for the search of rule 4, solved [`LANES`] at a time by
/// [`first_entry_lanes`], each answer then written to its slot.
pub(crate) struct EntryQueue {
    radius: f64,
    rel: [RelPath; LANES],
    h: [f64; LANES],
    slot: [usize; LANES],
    len: usize,
}

impl EntryQueue {
    /// An empty queue for balls of radius `radius`.
    pub(crate) fn new(radius: f64) -> EntryQueue {
        let still = RelPath {
            a: Vec2::ZERO,
            b: Vec2::ZERO,
            c: Vec2::ZERO,
        };
        EntryQueue {
            radius,
            rel: [still; LANES],
            h: [0.0; LANES],
            slot: [0; LANES],
            len: 0,
        }
    }

    /// Queues the pair with relative path `rel` and horizon `h` (as [`pair_before_entry`]
    /// gave them) for `out[slot]`; solves the queue when it is full.
    pub(crate) fn push(&mut self, rel: RelPath, h: f64, slot: usize, out: &mut [Contact]) {
        let l = self.len;
        (self.rel[l], self.h[l], self.slot[l]) = (rel, h, slot);
        self.len = l + 1;
        if self.len == LANES {
            self.flush(out);
        }
    }

    /// Solves the queued pairs and writes their answers: [`first_contact`]'s rule 4,
    /// `hit(t, h)` for `t ≥ 0`, else `none(h)`.
    pub(crate) fn flush(&mut self, out: &mut [Contact]) {
        let n = self.len;
        if n == 0 {
            return;
        }
        let four_r2 = 4.0 * self.radius * self.radius;
        let mut t = [NO_ROOT; LANES];
        let mut ok = [false; LANES];
        if n >= 2 {
            // a queue flushed short: its empty lanes repeat its first pair (their answers
            // unused), which costs no more than searching the pairs one by one
            for l in n..LANES {
                (self.rel[l], self.h[l]) = (self.rel[0], self.h[0]);
            }
            (t, ok) = first_entry_lanes(&self.rel, four_r2, &self.h);
        }
        for l in 0..n {
            let (rel, h) = (&self.rel[l], self.h[l]);
            let t = if ok[l] {
                t[l]
            } else {
                first_entry(rel, four_r2, h, false)
            };
            out[self.slot[l]] = if t >= 0.0 {
                Contact::hit(t, h)
            } else {
                Contact::none(h)
            };
        }
        self.len = 0;
    }
}

/// [`LANES`] f64 lanes; every operation is the f64 operation on each lane.
#[derive(Clone, Copy)]
struct F2([f64; LANES]);

/// [`LANES`] lanes of a test: all bits set for true, none for false (a select is then bit
/// arithmetic, never a branch).
#[derive(Clone, Copy, PartialEq)]
struct B2([u64; LANES]);

impl F2 {
    #[inline(always)]
    fn splat(x: f64) -> F2 {
        F2([x; LANES])
    }

    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> F2 {
        F2(std::array::from_fn(|l| f(self.0[l])))
    }

    #[inline(always)]
    fn sqrt(self) -> F2 {
        self.map(f64::sqrt)
    }

    #[inline(always)]
    fn abs(self) -> F2 {
        self.map(f64::abs)
    }

    #[inline(always)]
    fn test(self, o: F2, f: impl Fn(f64, f64) -> bool) -> B2 {
        let mask = |t: bool| u64::from(t).wrapping_neg();
        B2(std::array::from_fn(|l| mask(f(self.0[l], o.0[l]))))
    }

    #[inline(always)]
    fn lt(self, o: F2) -> B2 {
        self.test(o, |x, y| x < y)
    }

    #[inline(always)]
    fn le(self, o: F2) -> B2 {
        self.test(o, |x, y| x <= y)
    }

    #[inline(always)]
    fn gt(self, o: F2) -> B2 {
        self.test(o, |x, y| x > y)
    }

    #[inline(always)]
    fn eq(self, o: F2) -> B2 {
        self.test(o, |x, y| x == y)
    }

    #[inline(always)]
    fn ne(self, o: F2) -> B2 {
        self.test(o, |x, y| x != y)
    }
}

impl B2 {
    const NONE: B2 = B2([0; LANES]);

    /// `if self { x } else { y }`, lane by lane.
    #[inline(always)]
    fn pick(self, x: F2, y: F2) -> F2 {
        let sel = |m: u64, x: f64, y: f64| f64::from_bits((x.to_bits() & m) | (y.to_bits() & !m));
        F2(std::array::from_fn(|l| sel(self.0[l], x.0[l], y.0[l])))
    }

    #[inline(always)]
    fn any(self) -> bool {
        self.0.iter().fold(0, |m, &x| m | x) != 0
    }
}

macro_rules! lanewise {
    ($($t:ident $trait:ident $f:ident $op:tt),*) => {$(
        impl $trait for $t {
            type Output = $t;
            #[inline(always)]
            fn $f(self, o: $t) -> $t {
                $t(std::array::from_fn(|l| self.0[l] $op o.0[l]))
            }
        }
    )*};
}
lanewise!(F2 Add add +, F2 Sub sub -, F2 Mul mul *, F2 Div div /, B2 BitAnd bitand &, B2 BitOr bitor |);

impl Neg for F2 {
    type Output = F2;
    #[inline(always)]
    fn neg(self) -> F2 {
        F2(std::array::from_fn(|l| -self.0[l]))
    }
}

impl Not for B2 {
    type Output = B2;
    #[inline(always)]
    fn not(self) -> B2 {
        B2(std::array::from_fn(|l| !self.0[l]))
    }
}

/// A [`Vec2`] in each lane.
#[derive(Clone, Copy)]
struct V2 {
    x: F2,
    y: F2,
}

impl V2 {
    #[inline(always)]
    fn add(self, o: V2) -> V2 {
        V2 {
            x: self.x + o.x,
            y: self.y + o.y,
        }
    }

    /// `s * self`, as `f64 * Vec2`.
    #[inline(always)]
    fn scaled(self, s: F2) -> V2 {
        V2 {
            x: s * self.x,
            y: s * self.y,
        }
    }

    #[inline(always)]
    fn dot(self, o: V2) -> F2 {
        self.x * o.x + self.y * o.y
    }
}

/// `(f, f', f'')` at `t` in each lane: `contact_fn(rel, four_r2, t, 0)`.
#[inline(always)]
fn eval(a: V2, b: V2, c: V2, four_r2: F2, t: F2) -> (F2, F2, F2) {
    // C(t) = C + t (B + t A), C'(t) = B + 2t A
    let ct = c.add(b.add(a.scaled(t)).scaled(t));
    let vt = b.add(a.scaled(F2::splat(2.0) * t));
    let two = F2::splat(2.0);
    let f1 = two * ct.dot(vt);
    let f2 = two * (vt.dot(vt) + two * a.dot(ct));
    let f0 = ct.dot(ct) - four_r2;
    (f0, f1, f2)
}

/// `quadratic_roots(a, b, c)` in each lane, without branches: `(n ≥ 1, n = 2, r0, r1)`.
/// One division gives the linear root `−c/b` or `q/a`, whichever is used.
#[inline(always)]
fn roots(a: F2, b: F2, c: F2) -> (B2, B2, F2, F2) {
    let zero = F2::splat(0.0);
    let linear = a.eq(zero);
    let disc = b * b - F2::splat(4.0) * a * c;
    let sign_b = b.lt(zero).pick(F2::splat(-1.0), F2::splat(1.0));
    let q = F2::splat(-0.5) * (b + sign_b * disc.sqrt());
    let r0 = linear.pick(-c, q) / linear.pick(b, a);
    let r1 = c / q;
    let ordered = r0.le(r1);
    let (q0, q1) = (ordered.pick(r0, r1), ordered.pick(r1, r0));
    let real = !linear & !disc.lt(zero);
    let double_zero = real & q.eq(zero);
    let one = (linear & b.ne(zero)) | real;
    let r0 = linear.pick(r0, double_zero.pick(zero, q0));
    let r1 = double_zero.pick(zero, q1);
    (one, real, r0, r1)
}

/// `smallest_positive_root(a, b, c)` in each lane, without branches.
#[inline(always)]
fn positive_root(a: F2, b: F2, c: F2) -> F2 {
    let (one, two, r0, r1) = roots(a, b, c);
    let zero = F2::splat(0.0);
    (one & r0.gt(zero)).pick(r0, (two & r1.gt(zero)).pick(r1, F2::splat(NO_ROOT)))
}

/// [`first_entry`] (`start_inside` false) for [`LANES`] pairs at once: the time of each
/// lane, and whether it is [`first_entry`]'s answer (else the caller runs [`first_entry`]).
///
/// On an x86-64 CPU with AVX-512 or AVX2 (checked once per call, at run time) the same
/// code is compiled for it, so that the lanes of a number are one 512-bit register, or
/// two 256-bit ones: the same IEEE operations in the same order (Rust never fuses a
/// multiply and an add), so the same bits, in a fraction of the instructions.
pub(crate) fn first_entry_lanes(
    rel: &[RelPath; LANES],
    four_r2: f64,
    h: &[f64; LANES],
) -> ([f64; LANES], [bool; LANES]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx512f") {
        // SAFETY: the CPU has AVX-512, checked just above
        return unsafe { first_entry_lanes_avx512(rel, four_r2, h) };
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked just above
        return unsafe { first_entry_lanes_avx2(rel, four_r2, h) };
    }
    first_entry_lanes_any(rel, four_r2, h)
}

/// [`first_entry_lanes`] compiled with AVX2.
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn first_entry_lanes_avx2(
    rel: &[RelPath; LANES],
    four_r2: f64,
    h: &[f64; LANES],
) -> ([f64; LANES], [bool; LANES]) {
    first_entry_lanes_any(rel, four_r2, h)
}

/// [`first_entry_lanes`] compiled with AVX-512.
///
/// # Safety
/// The CPU must have AVX-512 (its foundation, `avx512f`).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn first_entry_lanes_avx512(
    rel: &[RelPath; LANES],
    four_r2: f64,
    h: &[f64; LANES],
) -> ([f64; LANES], [bool; LANES]) {
    first_entry_lanes_any(rel, four_r2, h)
}

/// [`first_entry_lanes`] for whatever the compiler targets (inlined into each version).
#[inline(always)]
fn first_entry_lanes_any(
    rel: &[RelPath; LANES],
    four_r2: f64,
    h: &[f64; LANES],
) -> ([f64; LANES], [bool; LANES]) {
    // the lanes of each coefficient (plain loops: they inline into every version)
    let lanes = |which: usize| {
        let mut v = V2 {
            x: F2::splat(0.0),
            y: F2::splat(0.0),
        };
        for (l, r) in rel.iter().enumerate() {
            let p: Vec2 = [r.a, r.b, r.c][which];
            (v.x.0[l], v.y.0[l]) = (p.x, p.y);
        }
        v
    };
    let (a, b, c) = (lanes(0), lanes(1), lanes(2));
    let h = F2(*h);
    let four_r2 = F2::splat(four_r2);
    let (zero, half) = (F2::splat(0.0), F2::splat(0.5));
    // the first piece ends at the first inflection point in (0, h), else at h
    let six = F2::splat(6.0);
    let (one, two, s0, s1) = roots(
        six * a.dot(a),
        six * a.dot(b),
        b.dot(b) + F2::splat(2.0) * a.dot(c),
    );
    let first = one & s0.gt(zero) & s0.lt(h);
    let second = two & s1.gt(zero) & s1.lt(h) & s1.gt(s0);
    let hi = first.pick(s0, second.pick(s1, h));
    let mut lo = zero;
    let (mut f_lo, mut f1_lo, mut f2_lo) = eval(a, b, c, four_r2, lo);
    let (_, f1_hi, _) = eval(a, b, c, four_r2, hi);
    // lanes: walking, refining, done (answer in t_out), or off the common path
    let mut walking = f_lo.gt(zero) & f1_lo.lt(zero) & f1_hi.gt(zero);
    let mut off = !walking;
    let mut refining = B2::NONE;
    let mut t_out = zero;
    // where the walk entered: the bracket and (f, f', f'') at its right end
    let (mut r_lo, mut r_hi) = (zero, zero);
    let (mut e0, mut e1, mut e2) = (zero, zero, zero);
    for _ in 0..WALK_STEPS {
        if !walking.any() {
            break;
        }
        let mut step = positive_root(half * f2_lo, f1_lo, f_lo);
        let newton = step.le(zero);
        if newton.any() {
            // the Newton step where the Taylor quadratic has no root ahead
            step = newton.pick(-f_lo / f1_lo, step);
        }
        let t = lo + step;
        let (f_t, f1_t, f2_t) = eval(a, b, c, four_r2, t);
        let past = !t.lt(hi);
        let inside = f_t.le(zero);
        let enters = !past & inside & f1_t.le(zero);
        let exact = enters & f_t.eq(zero);
        let goes_on = !past & !inside & f1_t.lt(zero);
        let refine = walking & enters & !exact;
        t_out = (walking & exact).pick(t, t_out);
        r_lo = refine.pick(lo, r_lo);
        r_hi = refine.pick(t, r_hi);
        e0 = refine.pick(f_t, e0);
        e1 = refine.pick(f1_t, e1);
        e2 = refine.pick(f2_t, e2);
        refining = refining | refine;
        off = off | (walking & !enters & !goes_on);
        walking = walking & goes_on;
        lo = walking.pick(t, lo);
        f_lo = walking.pick(f_t, f_lo);
        f1_lo = walking.pick(f1_t, f1_lo);
        f2_lo = walking.pick(f2_t, f2_lo);
    }
    off = off | walking;
    // taylor_start(false, (e0, e1, e2), r_lo, r_hi)
    let dir = F2::splat(-1.0);
    let mut step = positive_root(half * e2, dir * e1, e0);
    let newton = step.lt(zero) & e1.ne(zero);
    if newton.any() {
        step = newton.pick(-dir * e0 / e1, step);
    }
    let ts = r_hi + dir * step;
    let mut t = (ts.gt(r_lo) & ts.lt(r_hi)).pick(ts, half * (r_lo + r_hi));
    // refine_from(rel, four_r2, 0, r_lo, r_hi, true, t)
    let (rtol, atol) = (F2::splat(ROOT_RTOL), F2::splat(ROOT_ATOL));
    for _ in 0..MAX_ITER {
        if !refining.any() {
            break;
        }
        let (g, g1, _) = eval(a, b, c, four_r2, t);
        let at_zero = g.eq(zero);
        let up = g.gt(zero);
        let lo_n = up.pick(t, r_lo);
        let hi_n = up.pick(r_hi, t);
        let mid = half * (lo_n + hi_n);
        let newton = t - g / g1;
        let slope = g1.ne(zero);
        let inside = slope & newton.gt(lo_n) & newton.lt(hi_n);
        let at_lo = slope & !inside & (newton - lo_n).abs().le(rtol * lo_n.abs() + atol);
        let at_hi = slope & !inside & !at_lo & (newton - hi_n).abs().le(rtol * hi_n.abs() + atol);
        let next = inside.pick(newton, mid);
        let small = (next - t).abs().le(rtol * next.abs() + atol);
        let result = at_zero.pick(t, at_lo.pick(lo_n, at_hi.pick(hi_n, next)));
        t_out = refining.pick(result, t_out);
        r_lo = refining.pick(lo_n, r_lo);
        r_hi = refining.pick(hi_n, r_hi);
        t = refining.pick(next, t);
        refining = refining & !(at_zero | at_lo | at_hi | small);
    }
    // still refining after MAX_ITER steps: refine_from returns its last t
    t_out = refining.pick(t, t_out);
    (t_out.0, off.0.map(|m| m == 0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg64Mcg;

    const R: f64 = 0.028575;

    /// A relative path and horizon: mostly closing in, with degenerate coefficients mixed in.
    fn random_pair(rng: &mut Pcg64Mcg) -> (RelPath, f64) {
        let mut v = |scale: f64| {
            Vec2::new(
                rng.random_range(-scale..scale),
                rng.random_range(-scale..scale),
            )
        };
        let (mut a, mut b, c) = (v(0.3), v(4.0), v(1.5));
        let kind = rng.random_range(0..8);
        if kind == 0 {
            a = Vec2::ZERO;
        }
        if kind == 1 {
            b = Vec2::ZERO;
        }
        if kind >= 2 {
            // aimed at the other ball, give or take
            let k = rng.random_range(0.5..3.0);
            b = Vec2::new(-k * c.x + 0.1 * b.x, -k * c.y + 0.1 * b.y);
        }
        let h = match rng.random_range(0..4) {
            0 => 0.0,
            1 => rng.random_range(0.0..0.01),
            _ => rng.random_range(0.0..3.0),
        };
        (RelPath { a, b, c }, h)
    }

    #[test]
    fn lanes_give_first_entrys_answers_bit_for_bit() {
        let mut rng = Pcg64Mcg::seed_from_u64(16);
        let four_r2 = 4.0 * R * R;
        let (mut solved, mut handed_back) = (0, 0);
        // the portable version always; AVX2's and AVX-512's where the CPU has them
        let mut versions = [true, false, false];
        for _ in 0..100_000 {
            // pairs as the drivers queue them: past every prune
            let pairs: [(RelPath, f64); LANES] = std::array::from_fn(|_| {
                loop {
                    let (rel, h) = random_pair(&mut rng);
                    if pair_before_entry_rel(&rel, h).is_none() {
                        break (rel, h);
                    }
                }
            });
            let rel = pairs.map(|(r, _)| r);
            let h = pairs.map(|(_, h)| h);
            let (t, ok) = first_entry_lanes(&rel, four_r2, &h);
            // every version this CPU can run gives the same bits
            let bits = |(t, ok): ([f64; LANES], [bool; LANES])| (t.map(f64::to_bits), ok);
            assert_eq!(
                bits((t, ok)),
                bits(first_entry_lanes_any(&rel, four_r2, &h))
            );
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU has AVX2
                let avx2 = unsafe { first_entry_lanes_avx2(&rel, four_r2, &h) };
                assert_eq!(bits((t, ok)), bits(avx2));
                versions[1] = true;
            }
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx512f") {
                // SAFETY: the CPU has AVX-512
                let avx512 = unsafe { first_entry_lanes_avx512(&rel, four_r2, &h) };
                assert_eq!(bits((t, ok)), bits(avx512));
                versions[2] = true;
            }
            for l in 0..LANES {
                if ok[l] {
                    let want = first_entry(&rel[l], four_r2, h[l], false);
                    assert_eq!(t[l].to_bits(), want.to_bits(), "{:?} h {}", rel[l], h[l]);
                    solved += 1;
                } else {
                    handed_back += 1;
                }
            }
        }
        // many take the common path (the rest are checked by the drivers' tests)
        assert!(
            solved > 100_000,
            "{solved} solved, {handed_back} handed back"
        );
        println!("versions compared (portable, AVX2, AVX-512): {versions:?}");
    }

    #[test]
    fn the_queue_answers_as_first_contact() {
        let mut rng = Pcg64Mcg::seed_from_u64(17);
        let pairs: Vec<(RelPath, f64)> = (0..1001).map(|_| random_pair(&mut rng)).collect();
        let mut out = vec![Contact::none(0.0); pairs.len()];
        let mut queue = EntryQueue::new(R);
        for (k, &(rel, h)) in pairs.iter().enumerate() {
            match pair_before_entry_rel(&rel, h) {
                Some(c) => out[k] = c,
                None => queue.push(rel, h, k, &mut out),
            }
        }
        queue.flush(&mut out);
        for (k, &(rel, h)) in pairs.iter().enumerate() {
            assert_eq!(out[k], first_contact(&rel, R, h), "{rel:?} h {h}");
        }
    }

    #[test]
    fn a_queue_flushed_short_answers_as_first_contact() {
        let mut rng = Pcg64Mcg::seed_from_u64(18);
        for n in 1..=LANES {
            for _ in 0..2_000 {
                // n pairs that need the search, then a flush with n < LANES queued
                let pairs: Vec<(RelPath, f64)> = (0..n)
                    .map(|_| {
                        loop {
                            let (rel, h) = random_pair(&mut rng);
                            if pair_before_entry_rel(&rel, h).is_none() {
                                break (rel, h);
                            }
                        }
                    })
                    .collect();
                let mut out = vec![Contact::none(0.0); n];
                let mut queue = EntryQueue::new(R);
                for (k, &(rel, h)) in pairs.iter().enumerate() {
                    queue.push(rel, h, k, &mut out);
                }
                queue.flush(&mut out);
                for (k, &(rel, h)) in pairs.iter().enumerate() {
                    assert_eq!(out[k], first_contact(&rel, R, h), "n {n}: {rel:?} h {h}");
                }
            }
        }
    }

    /// [`pair_before_entry`] on a relative path (ball 1 still at the origin).
    fn pair_before_entry_rel(rel: &RelPath, h: f64) -> Option<Contact> {
        let p1 = BallPath {
            a: Vec2::ZERO,
            b: Vec2::ZERO,
            c: Vec2::ZERO,
            tmax: f64::INFINITY,
            flags: 0,
        };
        let p2 = BallPath {
            a: rel.a,
            b: rel.b,
            c: rel.c,
            tmax: h,
            flags: PATH_MOVES,
        };
        pair_before_entry(&p1, &p2, R).ok()
    }
}
