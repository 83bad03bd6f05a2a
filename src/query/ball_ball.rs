//! The ball–ball query: the answer for one ball pair — when do the two balls first come
//! into contact while approaching, within the time their current motions last?
//!
//! # Contract (rules 1–4; the ground-truth corpus follows them)
//! With `C(t) = C + B t + A t²` the centre difference (see [`RelPath`]),
//! `f(t) = |C(t)|² − 4R²` and `H` the pair's horizon:
//! 1. either ball pocketed, or neither ball translates: no collision ([`Status::None`]);
//! 2. `d0 = |C| − 2R < −CONTACT_TOL`: the balls overlap, time 0 ([`Status::Overlap`]);
//! 3. `|d0| ≤ CONTACT_TOL`, the balls touch: time 0 if they approach (the first clearly
//!    non-zero derivative of `f` at 0 is negative; when `f(0) > 0` the exact first root,
//!    a fraction of a nanometre of travel away); if they separate (they have just
//!    collided) the contact at 0 is ignored and the answer is the next entry into
//!    contact within `H`, if any;
//! 4. otherwise the first `t ∈ (0, H]` where `f` goes from `> 0` to `≤ 0`; a root past
//!    `H` is not a collision of these paths.
//!
//! # Method
//! Bracket, don't enumerate (see `docs/reference/numerics.md`). The real roots of `f''`
//! (a quadratic, solved with the stable formula) split `[0, H]` into pieces on which `f'`
//! is monotone; a sign change of `f'` on a piece brackets a critical point of `f`, found
//! by [`refine_root`]. Critical points and inflection points together split `[0, H]` into
//! pieces on which `f` is monotone, and the first piece with `f(lo) > 0 ≥ f(hi)` holds
//! the answer, again found by [`refine_root`]: a safeguarded Newton iteration (a step is
//! taken only inside the bracket, else the bracket is bisected) started from a
//! second-order Taylor step at the end of the bracket where `|f|` is smaller, which keeps
//! near-double roots (grazes, a ball that stops right beside another) quadratically
//! convergent. A zero or tiny leading coefficient (parallel rolling, identical motion)
//! needs no special case: the quadratics simply have fewer roots in `(0, H)`.
//!
//! `f` and its derivatives are always evaluated from the vectors (`C(t) = C + t(B + tA)`),
//! never from the expanded quartic, whose constant term `|C|² − 4R²` cancels badly.
//! The method only finds the *first* root; it never computes all four.
//!
//! For a pair, `C(t)` is the difference of the two paths (ball 2 minus ball 1, a
//! [`RelPath`]): the balls touch when `|C(t)| = 2R`, i.e. at a root of the quartic
//! `a t⁴ + b t³ + c t² + d t + e` whose coefficients [`RelPath::quartic`] gives (erratum 1
//! restores the linear term `d`).
//!
//! # Twin
//! `shaders/query/ball_ball.wgsl` is this file in WGSL, function for function and in the
//! same order. Both avoid NaN and ∞ inside the algorithm (WGSL may assume neither exists):
//! a missing root is `−1`, a time that never comes is `−1`, loops are bounded by
//! [`MAX_ITER`], and only `sqrt` and arithmetic are used.

use crate::model::MotionState;
use crate::model::ball_state::BallState;
use crate::model::sim_params::BallParams;
use crate::model::{Vec2, dot, norm, norm1, perp_dot};
use crate::motion::path::{BallPath, PATH_MOVES, PATH_POCKETED, pair_horizon};
use crate::motion::trajectory::{Path, trajectory};
use crate::query::roots::{NO_ROOT, quadratic_roots, smallest_positive_root};

/// Two centres closer than `2R` by at most this many metres (either way) touch.
pub const CONTACT_TOL: f64 = 1e-12;
/// The most iterations of one root refinement. Safeguarded Newton from a Taylor start
/// needs at most ~15 here; bisection alone would need ~60 in f64.
pub const MAX_ITER: u32 = 64;
/// At most this many steps of the walk into a convex dip before the critical point decides.
pub const WALK_STEPS: u32 = 8;
/// Relative step size at which a refinement has converged: a few ulps.
pub(crate) const ROOT_RTOL: f64 = 4.0 * f64::EPSILON;
/// Smallest absolute step size that still counts as progress.
pub(crate) const ROOT_ATOL: f64 = 1e-300;
/// A derivative of `f` at a touching contact counts as zero when it is within this
/// fraction of the magnitudes that formed it (rounding of the dot products).
const APPROACH_BAND: f64 = 64.0 * f64::EPSILON;
/// The slack of the prune test, relative to the path's length scale: far above the
/// rounding of the projections, far below any answer's conditioning.
const PRUNE_SLACK: f64 = 1e-9;

/// The centre difference of a pair, ball 2 minus ball 1: `C(t) = C + B t + A t²`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RelPath {
    /// Relative half-acceleration `A = a₂ − a₁`.
    pub a: Vec2,
    /// Relative velocity at `t = 0`, `B = b₂ − b₁`.
    pub b: Vec2,
    /// Centre difference at `t = 0`, `C = c₂ − c₁`.
    pub c: Vec2,
}

impl RelPath {
    /// The relative path of ball 2 seen from ball 1.
    pub fn between(p1: &BallPath, p2: &BallPath) -> RelPath {
        RelPath {
            a: p2.a - p1.a,
            b: p2.b - p1.b,
            c: p2.c - p1.c,
        }
    }

    /// `C(t)`, evaluated from the vectors (never from the expanded quartic).
    pub fn at(&self, t: f64) -> Vec2 {
        self.c + t * (self.b + t * self.a)
    }

    /// `C'(t) = B + 2 t A`, the relative velocity.
    pub fn velocity_at(&self, t: f64) -> Vec2 {
        self.b + (2.0 * t) * self.a
    }

    /// The coefficients `[a, b, c, d, e]` of `|C(t)|² − (2R)²` expanded in powers of `t`,
    /// highest first (erratum 1):
    /// `a = |A|²`, `b = 2 A·B`, `c = |B|² + 2 A·C`, `d = 2 B·C`, `e = |C|² − 4R²`.
    ///
    /// The solver never evaluates this form (cancellation in `e` costs accuracy, see
    /// `docs/reference/numerics.md`); it is here for inspection and tests.
    pub fn quartic(&self, radius: f64) -> [f64; 5] {
        let (a, b, c) = (self.a, self.b, self.c);
        [
            dot(a, a),
            2.0 * dot(a, b),
            dot(b, b) + 2.0 * dot(a, c),
            2.0 * dot(b, c),
            dot(c, c) - 4.0 * radius * radius,
        ]
    }
}

/// How a pair's answer came out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum Status {
    /// No collision within the horizon (time `∞`).
    None = 0,
    /// The balls come into contact at the time given.
    Hit = 1,
    /// The balls already overlap by more than [`CONTACT_TOL`] (time 0).
    Overlap = 2,
}

impl Status {
    /// The name used in output files: `none`, `hit`, `overlap`.
    pub fn name(self) -> &'static str {
        match self {
            Status::None => "none",
            Status::Hit => "hit",
            Status::Overlap => "overlap",
        }
    }

    /// Whether the pair is in contact at [`Contact::t`] (a hit or an overlap).
    pub fn is_contact(self) -> bool {
        self != Status::None
    }
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The answer for one pair: the time of first contact in seconds (`∞` for none), how it
/// came out, and the horizon it was sought within.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// Time of first contact in seconds from now; `f64::INFINITY` when there is none.
    pub t: f64,
    /// Hit, none or overlap.
    pub status: Status,
    /// The pair's horizon `H` (see [`pair_horizon`]); `∞` when neither ball moves.
    pub horizon: f64,
}

impl Contact {
    /// No collision within horizon `h`.
    pub fn none(horizon: f64) -> Contact {
        Contact {
            t: f64::INFINITY,
            status: Status::None,
            horizon,
        }
    }

    /// A collision at `t` within horizon `h`.
    pub fn hit(t: f64, horizon: f64) -> Contact {
        Contact {
            t,
            status: Status::Hit,
            horizon,
        }
    }

    /// Overlapping balls (time 0) within horizon `h`.
    pub fn overlap(horizon: f64) -> Contact {
        Contact {
            t: 0.0,
            status: Status::Overlap,
            horizon,
        }
    }
}

/// `f^(k)(t)`, `f^(k+1)(t)` and `f^(k+2)(t)` for `k = 0` or `k = 1`, where
/// `f(t) = |C(t)|² − 4R²`, evaluated from the vectors:
/// `f = Ct·Ct − 4R²`, `f' = 2 Ct·Vt`, `f'' = 2(Vt·Vt + 2 A·Ct)`, `f''' = 12 A·Vt`
/// with `Ct = C + t(B + tA)` and `Vt = B + 2tA`.
pub fn contact_fn(rel: &RelPath, four_r2: f64, t: f64, k: u32) -> (f64, f64, f64) {
    let ct = rel.at(t);
    let vt = rel.velocity_at(t);
    let f1 = 2.0 * dot(ct, vt);
    let f2 = 2.0 * (dot(vt, vt) + 2.0 * dot(rel.a, ct));
    if k == 0 {
        let f0 = dot(ct, ct) - four_r2;
        return (f0, f1, f2);
    }
    let f3 = 12.0 * dot(rel.a, vt);
    (f1, f2, f3)
}

/// The root of `g = f^(k)` in the bracket `[lo, hi]`, where `g` is monotone and
/// `g(lo) = g_lo`, `g(hi) = g_hi` have opposite signs or `g_hi = 0`.
///
/// Safeguarded Newton: the bracket shrinks with every evaluation, a Newton step is taken
/// only when it lands strictly inside it, otherwise the bracket is bisected — unless the
/// Newton target lies within a few ulps of a bracket end, which is then the root. The start is
/// a second-order Taylor step from the end with the smaller `|g|` (a near-double root at
/// a bracket end then converges quadratically instead of linearly). Stops when a step is
/// below a few ulps of `t`, or after [`MAX_ITER`] steps. Returns a `t` in `[lo, hi]`.
pub fn refine_root(
    rel: &RelPath,
    four_r2: f64,
    k: u32,
    lo_in: f64,
    hi_in: f64,
    g_lo: f64,
    g_hi: f64,
) -> f64 {
    if g_hi == 0.0 {
        return hi_in;
    }
    if g_lo == 0.0 {
        return lo_in;
    }
    // start: a second-order Taylor step from the end where |g| is smaller
    let from_lo = g_lo.abs() <= g_hi.abs();
    let end = if from_lo { lo_in } else { hi_in };
    let t = taylor_start(from_lo, contact_fn(rel, four_r2, end, k), lo_in, hi_in);
    refine_from(rel, four_r2, k, lo_in, hi_in, g_lo > 0.0, t)
}

/// Where a refinement of the bracket `[lo, hi]` starts: a second-order Taylor step into the
/// bracket from `lo` (`from_lo`) or from `hi`, with `e = (g, g', g'')` there (a Newton step
/// when the Taylor quadratic has no root ahead); the midpoint when the step leaves the
/// bracket.
pub fn taylor_start(from_lo: bool, e: (f64, f64, f64), lo: f64, hi: f64) -> f64 {
    let (e0, e1, e2) = e;
    let (end, dir) = if from_lo { (lo, 1.0) } else { (hi, -1.0) };
    let mut step = smallest_positive_root(0.5 * e2, dir * e1, e0);
    if step < 0.0 && e1 != 0.0 {
        step = -dir * e0 / e1;
    }
    let t = end + dir * step;
    if t > lo && t < hi { t } else { 0.5 * (lo + hi) }
}

/// [`refine_root`]'s iteration from `t_start` in the bracket `[lo_in, hi_in]`, where `g`
/// is positive at `lo_in` when `lo_positive` (and of the other sign, or zero, at `hi_in`).
pub fn refine_from(
    rel: &RelPath,
    four_r2: f64,
    k: u32,
    lo_in: f64,
    hi_in: f64,
    lo_positive: bool,
    t_start: f64,
) -> f64 {
    let mut lo = lo_in;
    let mut hi = hi_in;
    let mut t = t_start;
    for _ in 0..MAX_ITER {
        let (g, g1, _) = contact_fn(rel, four_r2, t, k);
        if g == 0.0 {
            return t;
        }
        // shrink the bracket
        if (g > 0.0) == lo_positive {
            lo = t;
        } else {
            hi = t;
        }
        // Newton step if it stays inside the bracket, else bisection
        let mut next = 0.5 * (lo + hi);
        if g1 != 0.0 {
            let newton = t - g / g1;
            if newton > lo && newton < hi {
                next = newton;
            } else if (newton - lo).abs() <= ROOT_RTOL * lo.abs() + ROOT_ATOL {
                // the root is at a bracket end, to rounding: bisecting towards it would
                // only crawl there linearly
                return lo;
            } else if (newton - hi).abs() <= ROOT_RTOL * hi.abs() + ROOT_ATOL {
                return hi;
            }
        }
        if (next - t).abs() <= ROOT_RTOL * next.abs() + ROOT_ATOL {
            return next;
        }
        t = next;
    }
    t
}

/// The ends of the pieces of `[0, h]` on which `f'` is monotone, in time order: the
/// inflection points of `f` in `(0, h)` (the roots of the quadratic
/// `f''/2 = 6|A|² t² + 6 A·B t + |B|² + 2 A·C`), then `h`; and how many inflection points
/// there are (0 to 2: `knots[n]` is `h`).
pub fn inflection_knots(rel: &RelPath, h: f64) -> ([f64; 3], usize) {
    let (a, b, c) = (rel.a, rel.b, rel.c);
    let (n, s0, s1) = quadratic_roots(
        6.0 * dot(a, a),
        6.0 * dot(a, b),
        dot(b, b) + 2.0 * dot(a, c),
    );
    let mut knots = [h, h, h];
    let mut n_knots = 0;
    if n >= 1 && s0 > 0.0 && s0 < h {
        knots[n_knots] = s0;
        n_knots += 1;
    }
    if n == 2 && s1 > 0.0 && s1 < h && s1 > s0 {
        knots[n_knots] = s1;
        n_knots += 1;
    }
    (knots, n_knots)
}

/// The first time in `(0, h]` at which `f` goes from `> 0` to `≤ 0`, or `−1` if none
/// (rule 4). With `start_inside`, `f(0)` counts as `≤ 0` whatever its rounding: the pair
/// touches at 0 and separates, so only a later entry into contact counts (rule 3).
// `!(x < y)` rather than `x >= y` in the walk, as in the WGSL twin: it also stops on NaN
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub fn first_entry(rel: &RelPath, four_r2: f64, h: f64, start_inside: bool) -> f64 {
    let (knots, n_knots) = inflection_knots(rel, h);
    // walk the pieces [lo, hi] on which f' is monotone, in time order
    let mut lo = 0.0;
    let (mut f_lo, mut f1_lo, mut f2_lo) = contact_fn(rel, four_r2, lo, 0);
    if start_inside {
        f_lo = 0.0;
    }
    // an index loop, as in the WGSL twin
    #[allow(clippy::needless_range_loop)]
    for piece in 0..=n_knots {
        let hi = knots[piece];
        let (f_hi, f1_hi, f2_hi) = contact_fn(rel, four_r2, hi, 0);
        // a convex dip (f falls at lo and rises at hi, outside at both ends): walk in from
        // the left. On a convex f a Newton step stops short of the first entry and a
        // Taylor step may pass it; either way the point reached is still outside and
        // falling (a new lo), or inside and falling (the entry is bracketed on a monotone
        // stretch), or past the lowest point or the piece (the critical point below then
        // decides, as without the walk). Most meeting pairs end here.
        if f_lo > 0.0 && f1_lo < 0.0 && f1_hi > 0.0 {
            for _ in 0..WALK_STEPS {
                let mut step = smallest_positive_root(0.5 * f2_lo, f1_lo, f_lo);
                if step <= 0.0 {
                    step = -f_lo / f1_lo;
                }
                let t = lo + step;
                if !(t < hi) {
                    break;
                }
                let (f_t, f1_t, f2_t) = contact_fn(rel, four_r2, t, 0);
                if f_t <= 0.0 {
                    // inside and still falling: f is monotone on [lo, t]; refine from t,
                    // where f and its derivatives are known
                    if f1_t <= 0.0 {
                        if f_t == 0.0 {
                            return t;
                        }
                        let start = taylor_start(false, (f_t, f1_t, f2_t), lo, t);
                        return refine_from(rel, four_r2, 0, lo, t, true, start);
                    }
                    break;
                }
                if !(f1_t < 0.0) {
                    break;
                }
                lo = t;
                f_lo = f_t;
                f1_lo = f1_t;
                f2_lo = f2_t;
            }
        }
        // a critical point of f inside the piece splits it into two monotone halves
        if (f1_lo < 0.0 && f1_hi > 0.0) || (f1_lo > 0.0 && f1_hi < 0.0) {
            let tc = refine_root(rel, four_r2, 1, lo, hi, f1_lo, f1_hi);
            let (f_c, _, _) = contact_fn(rel, four_r2, tc, 0);
            if f_lo > 0.0 && f_c <= 0.0 {
                return refine_root(rel, four_r2, 0, lo, tc, f_lo, f_c);
            }
            // in contact at lo (only a touching pair that separates gets here: rule 3) and
            // still at the maximum of f: it turned back before it measurably left contact,
            // so it re-enters where it turns
            if f_lo <= 0.0 && f1_lo > 0.0 && f_c <= 0.0 {
                return tc;
            }
            lo = tc;
            f_lo = f_c;
        }
        if f_lo > 0.0 && f_hi <= 0.0 {
            return refine_root(rel, four_r2, 0, lo, hi, f_lo, f_hi);
        }
        lo = hi;
        f_lo = f_hi;
        f1_lo = f1_hi;
        f2_lo = f2_hi;
    }
    NO_ROOT
}

/// The first time in `(0, h]` at which `f`, negative at 0, reaches 0 (`f` goes from `< 0`
/// to `≥ 0`: the path leaves the circle `|C| = 2R` it starts inside), or [`NO_ROOT`] if
/// none.
///
/// Method: the critical points of `f` split `[0, h]` into pieces on which `f` is monotone
/// (each found by [`refine_root`] on `f'`, which is monotone between the inflection points
/// of `f`, the roots of the quadratic `f''`); the first piece whose ends straddle 0
/// brackets the exit, refined by [`refine_root`] on `f`. For a path that starts inside a
/// circle this is the smallest positive root of pooltool's quartic (spec §4.5–4.6): its
/// detection does not ask which way the path crosses.
pub fn first_exit(rel: &RelPath, four_r2: f64, h: f64) -> f64 {
    let (knots, n_knots) = inflection_knots(rel, h);
    // walk the pieces [lo, hi] on which f' is monotone, in time order
    let mut lo = 0.0;
    let (mut f_lo, mut f1_lo, _) = contact_fn(rel, four_r2, lo, 0);
    // an index loop, as in the WGSL twin
    #[allow(clippy::needless_range_loop)]
    for piece in 0..=n_knots {
        let hi = knots[piece];
        let (f_hi, f1_hi, _) = contact_fn(rel, four_r2, hi, 0);
        // a critical point of f inside the piece splits it into two monotone halves
        if (f1_lo < 0.0 && f1_hi > 0.0) || (f1_lo > 0.0 && f1_hi < 0.0) {
            let tc = refine_root(rel, four_r2, 1, lo, hi, f1_lo, f1_hi);
            let (f_c, _, _) = contact_fn(rel, four_r2, tc, 0);
            if f_lo < 0.0 && f_c >= 0.0 {
                return refine_root(rel, four_r2, 0, lo, tc, f_lo, f_c);
            }
            lo = tc;
            f_lo = f_c;
        }
        if f_lo < 0.0 && f_hi >= 0.0 {
            return refine_root(rel, four_r2, 0, lo, hi, f_lo, f_hi);
        }
        lo = hi;
        f_lo = f_hi;
        f1_lo = f1_hi;
    }
    NO_ROOT
}

/// The sign of the first clearly non-zero derivative of `f` at `t = 0`: negative when a
/// touching pair approaches, positive when it separates, zero when nothing moves
/// relative to anything.
///
/// `f'(0) = 2 B·C`, `f''(0) = 2(|B|² + 2 A·C)`, `f'''(0) = 12 A·B`, `f''''(0) = 24 |A|²`;
/// each counts as zero within `APPROACH_BAND` of the magnitudes that formed it.
pub fn approach_sign(rel: &RelPath) -> f64 {
    let (a, b, c) = (rel.a, rel.b, rel.c);
    let d1 = dot(b, c);
    if d1.abs() > APPROACH_BAND * norm(b) * norm(c) {
        return d1;
    }
    let d2 = dot(b, b) + 2.0 * dot(a, c);
    if d2.abs() > APPROACH_BAND * (dot(b, b) + 2.0 * norm(a) * norm(c)) {
        return d2;
    }
    let d3 = dot(a, b);
    if d3.abs() > APPROACH_BAND * norm(a) * norm(b) {
        return d3;
    }
    dot(a, a)
}

/// Whether `C(t)` provably stays farther than `2R` from the origin for `t ∈ [0, h]`, by a
/// separating-axis test on the path's convex hull.
///
/// Over `[0, h]` the path is the quadratic Bézier curve with control points
/// `P0 = C`, `P1 = C + (h/2) B`, `P2 = C + h B + h² A`, so it lies in their triangle. If
/// the projections of all three points onto a unit axis `u` exceed `2R` (or all fall
/// below `−2R`), so does `u·C(t)`, and `|C(t)| ≥ |u·C(t)| > 2R`: no contact. Two axes are
/// tried: the initial centre line `C/|C|` (pairs moving apart, or too slow to close the
/// gap, [`wide_along_centres`]) and the normal of the relative velocity `B` (pairs passing
/// each other by, [`wide_sideways`]). The test is exact up to `PRUNE_SLACK` of the
/// path's length scale, so it never changes an answer; it only spares the root finding.
/// Both axes are tested on squares, without a square root or a division. `h` must be
/// finite.
pub fn cannot_meet(rel: &RelPath, radius: f64, h: f64) -> bool {
    let reach = 2.0 * radius + PRUNE_SLACK * path_scale(rel, h);
    wide_along_centres(rel, h, reach) || wide_sideways(rel, h, reach)
}

/// Whether the pair provably passes wide of contact for `t ∈ [0, h]`, sideways of the
/// relative velocity: [`cannot_meet`]'s second axis, tried before anything else because it
/// is this cheap. Its reach adds [`CONTACT_TOL`], so a pair passed over is neither
/// overlapping nor touching (rules 2 and 3) and has no entry into contact (rule 4): the
/// test never changes an answer.
pub fn passes_wide(rel: &RelPath, radius: f64, h: f64) -> bool {
    let reach = 2.0 * radius + CONTACT_TOL + PRUNE_SLACK * path_scale(rel, h);
    wide_sideways(rel, h, reach)
}

/// An upper bound of the path's length scale `|C| + |B| h + |A| h²` (1-norms), for the
/// prunes' slack.
pub fn path_scale(rel: &RelPath, h: f64) -> f64 {
    norm1(rel.c) + norm1(rel.b) * h + norm1(rel.a) * h * h
}

/// Whether the projections of `P0, P1, P2` on the initial centre line `u = C/|C|` all
/// exceed `reach`: `C·Pᵢ > reach·|C|`, compared as squares of the positive sides.
pub fn wide_along_centres(rel: &RelPath, h: f64, reach: f64) -> bool {
    let cc = dot(rel.c, rel.c);
    let q1 = dot(rel.c, rel.c + (0.5 * h) * rel.b);
    let q2 = dot(rel.c, rel.c + h * rel.b + (h * h) * rel.a);
    let bound = reach * reach * cc;
    cc > reach * reach && q1 > 0.0 && q2 > 0.0 && q1 * q1 > bound && q2 * q2 > bound
}

/// Whether `C(t)` stays farther than `reach` from the line through the origin along `B`, on
/// one side, for `t ∈ [0, h]`. `w(t) = B × C(t) = B × C + t² (B × A)` is `|B|` times the
/// signed distance, monotone on `[0, h]`, so its ends decide; compared as squares. On
/// overflow the comparisons come out false or hold exactly as they would unrounded.
pub fn wide_sideways(rel: &RelPath, h: f64, reach: f64) -> bool {
    let w0 = perp_dot(rel.b, rel.c);
    let w_h = w0 + (h * h) * perp_dot(rel.b, rel.a);
    let bound = reach * reach * dot(rel.b, rel.b);
    w0 * w_h > 0.0 && w0 * w0 > bound && w_h * w_h > bound
}

/// The answer for a relative path that moves, within horizon `h` (rules 2–4).
///
/// `h` must be finite and `≥ 0`. [`passes_wide`] and [`cannot_meet`] run before any root
/// finding. The CPU drivers repeat these steps up to [`first_entry`] in
/// `src/cpu/lanes.rs` (`pair_before_entry`, then several searches at once): a change here
/// goes there too (its tests compare the two).
pub fn first_contact(rel: &RelPath, radius: f64, h: f64) -> Contact {
    // prune: the pair passes by, wide of contact (no rule applies)
    if passes_wide(rel, radius, h) {
        return Contact::none(h);
    }
    let four_r2 = 4.0 * radius * radius;
    let d0 = norm(rel.c) - 2.0 * radius;
    // rule 2: overlap
    if d0 < -CONTACT_TOL {
        return Contact::overlap(h);
    }
    // rule 3: touching
    if d0 <= CONTACT_TOL {
        if approach_sign(rel) < 0.0 {
            let (f0, _, _) = contact_fn(rel, four_r2, 0.0, 0);
            if f0 > 0.0 {
                let t = first_entry(rel, four_r2, h, false);
                if t > 0.0 {
                    return Contact::hit(t, h);
                }
            }
            return Contact::hit(0.0, h);
        }
        let t = first_entry(rel, four_r2, h, true);
        return if t >= 0.0 {
            Contact::hit(t, h)
        } else {
            Contact::none(h)
        };
    }
    // prune: the path provably stays out of contact within h
    if cannot_meet(rel, radius, h) {
        return Contact::none(h);
    }
    // rule 4: the first entry into contact
    let t = first_entry(rel, four_r2, h, false);
    if t >= 0.0 {
        Contact::hit(t, h)
    } else {
        Contact::none(h)
    }
}

/// The answer for a pair of balls on their paths (rules 1–4).
pub fn pair_contact(p1: &BallPath, p2: &BallPath, radius: f64) -> Contact {
    let h = pair_horizon(p1, p2);
    // rule 1: a pocketed ball, or nothing moves
    if (p1.flags | p2.flags) & PATH_POCKETED != 0 || (p1.flags | p2.flags) & PATH_MOVES == 0 {
        return Contact::none(h);
    }
    first_contact(&RelPath::between(p1, p2), radius, h)
}

/// τ until balls 1 and 2 first touch (`|Δp(τ)| = 2R`), or `∞`.
///
/// Rules, in pooltool's order: either ball pocketed → `∞`; neither translating → `∞`;
/// centres closer than 2R (3D, strictly) → `0`, "now" (Q3); centres exactly 2R apart in
/// pooltool's arithmetic (its quartic's constant coefficient `Δx² + Δy² − 4R²` is 0) →
/// `0`, "now", even for balls moving apart (its root filter keeps τ = 0, §4.2); otherwise
/// the first entry into contact of the relative path `Δp(τ) = Δa τ² + Δb τ + Δc`.
///
/// Method: the crate's exact solver ([`crate::query::ball_ball::first_contact`]) on the relative
/// path, within the pair's horizon (the earlier of the two balls' transitions, widened
/// as [`crate::motion::trajectory::horizon_margin`] says). pooltool solves the expanded quartic with
/// Algorithm 1010 and its root filter (§4.2); the smallest positive root it keeps is this
/// first entry. Deviation (Q5): where pooltool's quartic has a leading coefficient of
/// exactly 0 (bit-identical accelerations) it reports "now" and later raises in
/// make_kiss; here the path is solved as it is (lower degree).
pub fn ball_ball_time(b1: &BallState, b2: &BallState, p: &BallParams) -> f64 {
    if let Some(t) = ball_ball_rules(b1, b2, p.r) {
        return t;
    }
    ball_ball_time_on(&trajectory(b1, p), &trajectory(b2, p), p.r)
}

/// The rules [`ball_ball_time`] applies before any path is computed: `∞` if either ball
/// is pocketed or neither translates, `0` if the centres are closer than `2R` (Q3) or
/// exactly `2R` apart as pooltool's quartic sees it (its constant coefficient is 0, and its
/// root filter keeps the root τ = 0 even for balls moving apart); `None` when the pair's
/// paths must be solved.
pub fn ball_ball_rules(b1: &BallState, b2: &BallState, radius: f64) -> Option<f64> {
    if b1.s == MotionState::Pocketed || b2.s == MotionState::Pocketed {
        return Some(f64::INFINITY);
    }
    if !b1.translating() && !b2.translating() {
        return Some(f64::INFINITY);
    }
    if (b2.r - b1.r).norm() < 2.0 * radius {
        return Some(0.0);
    }
    // exactly touching in pooltool's arithmetic: its quartic's constant coefficient
    // e = Δx² + Δy² − 4R² (evaluated as it does) is 0, τ = 0 is a root and its filter keeps
    // it (§4.2): "now", even for a pair moving apart (FUZZING.md, finding 31)
    let (dx, dy) = (b2.r.x - b1.r.x, b2.r.y - b1.r.y);
    if dx * dx + dy * dy - 4.0 * radius * radius == 0.0 {
        return Some(0.0);
    }
    None
}

/// [`ball_ball_time`] after its rules, on the two balls' paths (computed once per ball).
pub fn ball_ball_time_on(p1: &Path, p2: &Path, radius: f64) -> f64 {
    let rel = RelPath {
        a: p2.a - p1.a,
        b: p2.b - p1.b,
        c: p2.c - p1.c,
    };
    let h = p1.horizon.min(p2.horizon);
    let contact = first_contact(&rel, radius, h);
    match contact.status {
        Status::None => f64::INFINITY,
        Status::Hit | Status::Overlap => contact.t,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::vec3::Vec3;

    const R: f64 = 0.028575;

    fn rel(a: (f64, f64), b: (f64, f64), c: (f64, f64)) -> RelPath {
        RelPath {
            a: Vec2::new(a.0, a.1),
            b: Vec2::new(b.0, b.1),
            c: Vec2::new(c.0, c.1),
        }
    }

    #[test]
    fn head_on_straight_line_hits_at_gap_over_speed() {
        // ball 2 approaches ball 1 at 1 m/s from 1 m away, no acceleration
        let r = rel((0.0, 0.0), (-1.0, 0.0), (1.0, 0.0));
        let c = first_contact(&r, R, 10.0);
        assert_eq!(c.status, Status::Hit);
        assert!((c.t - (1.0 - 2.0 * R)).abs() < 1e-15, "{}", c.t);
    }

    #[test]
    fn a_root_past_the_horizon_is_no_collision() {
        let r = rel((0.0, 0.0), (-1.0, 0.0), (1.0, 0.0));
        assert_eq!(first_contact(&r, R, 0.9).status, Status::None);
        // a root right at the horizon counts; just past it does not
        let t_hit = 1.0 - 2.0 * R;
        assert_eq!(
            first_contact(&r, R, t_hit * (1.0 + 1e-12)).status,
            Status::Hit
        );
        assert_eq!(
            first_contact(&r, R, t_hit * (1.0 - 1e-9)).status,
            Status::None
        );
    }

    #[test]
    fn overlap_and_touching_rules() {
        let overlap = rel((0.0, 0.0), (1.0, 0.0), (2.0 * R - 1e-9, 0.0));
        assert_eq!(first_contact(&overlap, R, 1.0).status, Status::Overlap);
        // touching and approaching: 0
        let approach = rel((0.0, 0.0), (-1.0, 0.0), (2.0 * R, 0.0));
        assert_eq!(first_contact(&approach, R, 1.0), Contact::hit(0.0, 1.0));
        // touching and separating: no collision at 0
        let separate = rel((0.0, 0.0), (1.0, 0.0), (2.0 * R, 0.0));
        assert_eq!(first_contact(&separate, R, 1.0), Contact::none(1.0));
        // separating but decelerating back into contact (a draw-back): the re-entry counts
        let recollide = rel((-1.0, 0.0), (1.0, 0.0), (2.0 * R, 0.0));
        let c = first_contact(&recollide, R, 2.0);
        assert_eq!(c.status, Status::Hit);
        assert!((c.t - 1.0).abs() < 1e-12, "{}", c.t);
        // tangential touch, straight relative motion: separates
        let tangent = rel((0.0, 0.0), (0.0, 1.0), (2.0 * R, 0.0));
        assert_eq!(first_contact(&tangent, R, 1.0), Contact::none(1.0));
    }

    #[test]
    fn refine_root_handles_a_near_double_root_at_the_bracket_end() {
        // f has a minimum of −ε at t = 1: a graze 1e-12 m deep
        let depth = 1e-12;
        let r = rel((0.0, 0.0), (1.0, 0.0), (-1.0, 2.0 * R - depth));
        let four_r2 = 4.0 * R * R;
        let (f_lo, _, _) = contact_fn(&r, four_r2, 0.0, 0);
        let (f_hi, _, _) = contact_fn(&r, four_r2, 1.0, 0);
        assert!(f_lo > 0.0 && f_hi < 0.0);
        let t = refine_root(&r, four_r2, 0, 0.0, 1.0, f_lo, f_hi);
        // exact root: 1 − sqrt((2R)² − (2R − depth)²)
        let y = 2.0 * R - depth;
        let exact = 1.0 - (4.0 * R * R - y * y).sqrt();
        assert!((t - exact).abs() < 1e-12, "{t} vs {exact}");
    }

    #[test]
    fn first_contact_is_invariant_under_translation() {
        let base = rel((0.3, -0.1), (-2.0, -0.2), (0.5, 0.05));
        let c = first_contact(&base, R, 1.0);
        assert_eq!(c.status, Status::Hit);
        // the relative path is the same wherever the table is; the solver sees only it
        let moved = RelPath {
            c: Vec2::new((1000.0 + 0.5) - 1000.0, (-1000.0 + 0.05) + 1000.0),
            ..base
        };
        let m = first_contact(&moved, R, 1.0);
        assert!((m.t - c.t).abs() < 1e-12);
    }

    #[test]
    fn quartic_matches_vector_form() {
        let rel = RelPath {
            a: Vec2::new(0.3, -0.2),
            b: Vec2::new(-1.5, 0.7),
            c: Vec2::new(0.4, 0.1),
        };
        let r = 0.028575;
        let q = rel.quartic(r);
        for t in [0.0, 0.1, 0.7, 2.5] {
            let poly = (((q[0] * t + q[1]) * t + q[2]) * t + q[3]) * t + q[4];
            let ct = rel.at(t);
            let direct = dot(ct, ct) - 4.0 * r * r;
            assert!(
                (poly - direct).abs() < 1e-12 * (1.0 + direct.abs()),
                "t={t}"
            );
        }
    }

    fn rolling_state(x: f64, y: f64, vx: f64, vy: f64) -> BallState {
        let r = BallParams::default().r;
        BallState {
            v: Vec3::new(vx, vy, 0.0),
            w: Vec3::new(-vy / r, vx / r, 0.0),
            s: MotionState::Rolling,
            ..BallState::at_rest(x, y, r)
        }
    }

    #[test]
    fn head_on_hit_time() {
        let p = BallParams::default();
        let cue = rolling_state(0.5, 0.5, 0.0, 1.0);
        let obj = BallState::at_rest(0.5, 1.0, p.r);
        let t = ball_ball_time(&cue, &obj, &p);
        // gap 0.5 − 2R travelled at 1 m/s decelerating at μ_r g
        let gap = 0.5 - 2.0 * p.r;
        let k = 0.5 * 0.01 * 9.81;
        let expect = (1.0 - (1.0 - 4.0 * k * gap).sqrt()) / (2.0 * k);
        assert!((t - expect).abs() < 1e-12, "{t} {expect}");
        assert_eq!(ball_ball_time(&obj, &cue, &p), t);
    }

    #[test]
    fn rules_before_the_solver() {
        let p = BallParams::default();
        let a = BallState::at_rest(0.5, 0.5, p.r);
        let b = BallState::at_rest(0.5, 0.5 + 1.9 * p.r, p.r);
        assert_eq!(
            ball_ball_time(&a, &b, &p),
            f64::INFINITY,
            "still overlap ignored"
        );
        let moving = rolling_state(0.5, 0.5, 1.0, 0.0);
        assert_eq!(ball_ball_time(&moving, &b, &p), 0.0, "overlap is now");
        let gone = BallState {
            s: MotionState::Pocketed,
            ..b
        };
        assert_eq!(ball_ball_time(&moving, &gone, &p), f64::INFINITY);
        // moving apart: never
        let away = rolling_state(0.5, 0.5 + 2.0 * p.r + 1e-6, 0.0, 1.0);
        assert_eq!(ball_ball_time(&a, &away, &p), f64::INFINITY);
    }
}
