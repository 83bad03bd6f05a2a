// The ball–ball query: the answer for one ball pair — when do the two balls first come
// into contact while approaching, within the time their current motions last? WGSL twin
// of src/query/ball_ball.rs: the same functions in the same order with the same comments;
// the contract and the method are documented there. Differences, all forced by WGSL: no
// NaN or ∞ (a missing root or time is NO_ROOT = −1, "no collision" has t = NEVER), structs
// instead of tuples, methods as functions (`RelPath::at` is `rel_at`), and the precision
// constants come from the real_f32/real_f64 prelude.

// The most iterations of one root refinement.
const MAX_ITER: u32 = 64u;
// At most this many steps of the walk into a convex dip before the critical point decides.
const WALK_STEPS: u32 = 8u;
// ROOT_RTOL (4 EPS) and APPROACH_BAND (64 EPS) are in the precision prelude: naga does not
// constant-evaluate arithmetic on f64 constants.

// The centre difference of a pair, ball 2 minus ball 1: C(t) = C + B t + A t².
struct RelPath {
    a: real2,
    b: real2,
    c: real2,
}

// The relative path of ball 2 seen from ball 1 (Rust: RelPath::between).
fn rel_between(p1: BallPath, p2: BallPath) -> RelPath {
    return RelPath(p2.a - p1.a, p2.b - p1.b, p2.c - p1.c);
}

// C(t), evaluated from the vectors (Rust: RelPath::at).
fn rel_at(rel: RelPath, t: real) -> real2 {
    return rel.c + t * (rel.b + t * rel.a);
}

// C'(t) = B + 2 t A, the relative velocity (Rust: RelPath::velocity_at).
fn rel_velocity_at(rel: RelPath, t: real) -> real2 {
    return rel.b + (2.0 * t) * rel.a;
}

// How a pair's answer came out (Rust: Status).
const STATUS_NONE: u32 = 0u;
const STATUS_HIT: u32 = 1u;
const STATUS_OVERLAP: u32 = 2u;

// The answer for one pair: time of first contact (NEVER for none), status, horizon.
struct Contact {
    t: real,
    status: u32,
    horizon: real,
}

fn contact_none(horizon: real) -> Contact {
    return Contact(NEVER, STATUS_NONE, horizon);
}

fn contact_hit(t: real, horizon: real) -> Contact {
    return Contact(t, STATUS_HIT, horizon);
}

fn contact_overlap(horizon: real) -> Contact {
    return Contact(0.0, STATUS_OVERLAP, horizon);
}


// f^(k)(t), f^(k+1)(t), f^(k+2)(t) for k = 0 or 1, where f(t) = |C(t)|² − 4R², evaluated
// from the vectors: f = Ct·Ct − 4R², f' = 2 Ct·Vt, f'' = 2(Vt·Vt + 2 A·Ct), f''' = 12 A·Vt.
fn contact_fn(rel: RelPath, four_r2: real, t: real, k: u32) -> vec3<real> {
    let ct = rel_at(rel, t);
    let vt = rel_velocity_at(rel, t);
    let f1 = 2.0 * dot2(ct, vt);
    let f2 = 2.0 * (dot2(vt, vt) + 2.0 * dot2(rel.a, ct));
    if k == 0u {
        let f0 = dot2(ct, ct) - four_r2;
        return vec3<real>(f0, f1, f2);
    }
    let f3 = 12.0 * dot2(rel.a, vt);
    return vec3<real>(f1, f2, f3);
}

// The root of g = f^(k) in the bracket [lo, hi], where g is monotone and g(lo) = g_lo,
// g(hi) = g_hi have opposite signs or g_hi = 0. Safeguarded Newton from a second-order
// Taylor step at the end with the smaller |g|; a Newton target within a few ulps of a
// bracket end means that end is the root.
fn refine_root(
    rel: RelPath,
    four_r2: real,
    k: u32,
    lo_in: real,
    hi_in: real,
    g_lo: real,
    g_hi: real,
) -> real {
    if g_hi == 0.0 {
        return hi_in;
    }
    if g_lo == 0.0 {
        return lo_in;
    }
    // start: a second-order Taylor step from the end where |g| is smaller
    let from_lo = abs(g_lo) <= abs(g_hi);
    var end = hi_in;
    if from_lo {
        end = lo_in;
    }
    let t = taylor_start(from_lo, contact_fn(rel, four_r2, end, k), lo_in, hi_in);
    return refine_from(rel, four_r2, k, lo_in, hi_in, g_lo > 0.0, t);
}

// Where a refinement of the bracket [lo, hi] starts: a second-order Taylor step into the
// bracket from lo (from_lo) or from hi, with e = (g, g', g'') there (a Newton step when the
// Taylor quadratic has no root ahead); the midpoint when the step leaves the bracket.
fn taylor_start(from_lo: bool, e: vec3<real>, lo: real, hi: real) -> real {
    var end = hi;
    var dir: real = -1.0;
    if from_lo {
        end = lo;
        dir = 1.0;
    }
    var step = smallest_positive_root(0.5 * e.z, dir * e.y, e.x);
    if step < 0.0 && e.y != 0.0 {
        step = -dir * e.x / e.y;
    }
    let t = end + dir * step;
    if t > lo && t < hi {
        return t;
    }
    return 0.5 * (lo + hi);
}

// refine_root's iteration from t_start in the bracket [lo_in, hi_in], where g is positive at
// lo_in when lo_positive (and of the other sign, or zero, at hi_in).
fn refine_from(
    rel: RelPath,
    four_r2: real,
    k: u32,
    lo_in: real,
    hi_in: real,
    lo_positive: bool,
    t_start: real,
) -> real {
    var lo = lo_in;
    var hi = hi_in;
    var t = t_start;
    for (var iter = 0u; iter < MAX_ITER; iter++) {
        let g = contact_fn(rel, four_r2, t, k);
        if g.x == 0.0 {
            return t;
        }
        // shrink the bracket
        if (g.x > 0.0) == lo_positive {
            lo = t;
        } else {
            hi = t;
        }
        // Newton step if it stays inside the bracket, else bisection
        var next = 0.5 * (lo + hi);
        if g.y != 0.0 {
            let newton = t - g.x / g.y;
            if newton > lo && newton < hi {
                next = newton;
            } else if abs(newton - lo) <= ROOT_RTOL * abs(lo) + ROOT_ATOL {
                // the root is at a bracket end, to rounding: bisecting towards it would
                // only crawl there linearly
                return lo;
            } else if abs(newton - hi) <= ROOT_RTOL * abs(hi) + ROOT_ATOL {
                return hi;
            }
        }
        if abs(next - t) <= ROOT_RTOL * abs(next) + ROOT_ATOL {
            return next;
        }
        t = next;
    }
    return t;
}

// The ends of the pieces of [0, h] on which f' is monotone, in time order: the inflection
// points of f in (0, h) (the roots of the quadratic f''/2 = 6|A|² t² + 6 A·B t + |B|² +
// 2 A·C), then h; and how many inflection points there are (0 to 2: knots[n] is h).
struct Knots {
    knots: array<real, 3>,
    n: u32,
}

fn inflection_knots(rel: RelPath, h: real) -> Knots {
    let a = rel.a;
    let b = rel.b;
    let c = rel.c;
    let s = quadratic_roots(6.0 * dot2(a, a), 6.0 * dot2(a, b), dot2(b, b) + 2.0 * dot2(a, c));
    var knots = array<real, 3>(h, h, h);
    var n_knots = 0u;
    if s.n >= 1u && s.r0 > 0.0 && s.r0 < h {
        knots[n_knots] = s.r0;
        n_knots += 1u;
    }
    if s.n == 2u && s.r1 > 0.0 && s.r1 < h && s.r1 > s.r0 {
        knots[n_knots] = s.r1;
        n_knots += 1u;
    }
    return Knots(knots, n_knots);
}

// The first time in (0, h] at which f goes from > 0 to ≤ 0, or −1 if none (rule 4). With
// start_inside, f(0) counts as ≤ 0 whatever its rounding (rule 3, separating).
fn first_entry(rel: RelPath, four_r2: real, h: real, start_inside: bool) -> real {
    let pieces = inflection_knots(rel, h);
    var knots = pieces.knots;
    let n_knots = pieces.n;
    // walk the pieces [lo, hi] on which f' is monotone, in time order
    var lo: real = 0.0;
    let e0 = contact_fn(rel, four_r2, lo, 0u);
    var f_lo = e0.x;
    var f1_lo = e0.y;
    var f2_lo = e0.z;
    if start_inside {
        f_lo = 0.0;
    }
    for (var piece = 0u; piece <= n_knots; piece++) {
        let hi = knots[piece];
        let e_hi = contact_fn(rel, four_r2, hi, 0u);
        let f_hi = e_hi.x;
        let f1_hi = e_hi.y;
        let f2_hi = e_hi.z;
        // a convex dip (f falls at lo and rises at hi, outside at both ends): walk in from
        // the left. On a convex f a Newton step stops short of the first entry and a
        // Taylor step may pass it; either way the point reached is still outside and
        // falling (a new lo), or inside and falling (the entry is bracketed on a monotone
        // stretch), or past the lowest point or the piece (the critical point below then
        // decides, as without the walk). Most meeting pairs end here.
        if f_lo > 0.0 && f1_lo < 0.0 && f1_hi > 0.0 {
            for (var walk = 0u; walk < WALK_STEPS; walk++) {
                var step = smallest_positive_root(0.5 * f2_lo, f1_lo, f_lo);
                if step <= 0.0 {
                    step = -f_lo / f1_lo;
                }
                let t = lo + step;
                if !(t < hi) {
                    break;
                }
                let e_t = contact_fn(rel, four_r2, t, 0u);
                if e_t.x <= 0.0 {
                    // inside and still falling: f is monotone on [lo, t]; refine from t,
                    // where f and its derivatives are known
                    if e_t.y <= 0.0 {
                        if e_t.x == 0.0 {
                            return t;
                        }
                        let start = taylor_start(false, e_t, lo, t);
                        return refine_from(rel, four_r2, 0u, lo, t, true, start);
                    }
                    break;
                }
                if !(e_t.y < 0.0) {
                    break;
                }
                lo = t;
                f_lo = e_t.x;
                f1_lo = e_t.y;
                f2_lo = e_t.z;
            }
        }
        // a critical point of f inside the piece splits it into two monotone halves
        if (f1_lo < 0.0 && f1_hi > 0.0) || (f1_lo > 0.0 && f1_hi < 0.0) {
            let tc = refine_root(rel, four_r2, 1u, lo, hi, f1_lo, f1_hi);
            let f_c = contact_fn(rel, four_r2, tc, 0u).x;
            if f_lo > 0.0 && f_c <= 0.0 {
                return refine_root(rel, four_r2, 0u, lo, tc, f_lo, f_c);
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
            return refine_root(rel, four_r2, 0u, lo, hi, f_lo, f_hi);
        }
        lo = hi;
        f_lo = f_hi;
        f1_lo = f1_hi;
        f2_lo = f2_hi;
    }
    return NO_ROOT;
}

// The first time in (0, h] at which f, negative at 0, reaches 0 (f goes from < 0 to ≥ 0:
// the path leaves the circle |C| = 2R it starts inside), or −1 if none.
//
// Method: the critical points of f split [0, h] into pieces on which f is monotone (each
// found by refine_root on f', which is monotone between the inflection points of f, the
// roots of the quadratic f''); the first piece whose ends straddle 0 brackets the exit,
// refined by refine_root on f. For a path that starts inside a circle this is the
// smallest positive root of pooltool's quartic (spec §4.5–4.6): its detection does not
// ask which way the path crosses.
fn first_exit(rel: RelPath, four_r2: real, h: real) -> real {
    let pieces = inflection_knots(rel, h);
    var knots = pieces.knots;
    let n_knots = pieces.n;
    // walk the pieces [lo, hi] on which f' is monotone, in time order
    var lo: real = 0.0;
    let e0 = contact_fn(rel, four_r2, lo, 0u);
    var f_lo = e0.x;
    var f1_lo = e0.y;
    for (var piece = 0u; piece <= n_knots; piece++) {
        let hi = knots[piece];
        let e_hi = contact_fn(rel, four_r2, hi, 0u);
        let f_hi = e_hi.x;
        let f1_hi = e_hi.y;
        // a critical point of f inside the piece splits it into two monotone halves
        if (f1_lo < 0.0 && f1_hi > 0.0) || (f1_lo > 0.0 && f1_hi < 0.0) {
            let tc = refine_root(rel, four_r2, 1u, lo, hi, f1_lo, f1_hi);
            let f_c = contact_fn(rel, four_r2, tc, 0u).x;
            if f_lo < 0.0 && f_c >= 0.0 {
                return refine_root(rel, four_r2, 0u, lo, tc, f_lo, f_c);
            }
            lo = tc;
            f_lo = f_c;
        }
        if f_lo < 0.0 && f_hi >= 0.0 {
            return refine_root(rel, four_r2, 0u, lo, hi, f_lo, f_hi);
        }
        lo = hi;
        f_lo = f_hi;
        f1_lo = f1_hi;
    }
    return NO_ROOT;
}

// The sign of the first clearly non-zero derivative of f at t = 0: negative when a touching
// pair approaches, positive when it separates, zero when nothing moves relative to anything.
//
// f'(0) = 2 B·C, f''(0) = 2(|B|² + 2 A·C), f'''(0) = 12 A·B, f''''(0) = 24 |A|²; each counts
// as zero within APPROACH_BAND of the magnitudes that formed it.
fn approach_sign(rel: RelPath) -> real {
    let a = rel.a;
    let b = rel.b;
    let c = rel.c;
    let d1 = dot2(b, c);
    if abs(d1) > APPROACH_BAND * norm(b) * norm(c) {
        return d1;
    }
    let d2 = dot2(b, b) + 2.0 * dot2(a, c);
    if abs(d2) > APPROACH_BAND * (dot2(b, b) + 2.0 * norm(a) * norm(c)) {
        return d2;
    }
    let d3 = dot2(a, b);
    if abs(d3) > APPROACH_BAND * norm(a) * norm(b) {
        return d3;
    }
    return dot2(a, a);
}

// Whether C(t) provably stays farther than 2R from the origin for t in [0, h], by a
// separating-axis test on the convex hull of the Bézier control points
// P0 = C, P1 = C + (h/2) B, P2 = C + h B + h² A: the initial centre line and the normal of
// B, both tested on squares. h must be finite.
fn cannot_meet(rel: RelPath, radius: real, h: real) -> bool {
    let reach = 2.0 * radius + PRUNE_SLACK * path_scale(rel, h);
    return wide_along_centres(rel, h, reach) || wide_sideways(rel, h, reach);
}

// Whether the pair provably passes wide of contact for t in [0, h], sideways of the
// relative velocity: cannot_meet's second axis, tried before anything else because it is
// this cheap. Its reach adds CONTACT_TOL so that no overlapping or touching pair is passed
// over.
fn passes_wide(rel: RelPath, radius: real, h: real) -> bool {
    let reach = 2.0 * radius + CONTACT_TOL + PRUNE_SLACK * path_scale(rel, h);
    return wide_sideways(rel, h, reach);
}

// An upper bound of the path's length scale |C| + |B| h + |A| h² (1-norms), for the
// prunes' slack.
fn path_scale(rel: RelPath, h: real) -> real {
    return norm1(rel.c) + norm1(rel.b) * h + norm1(rel.a) * h * h;
}

// Whether the projections of P0, P1, P2 on the initial centre line u = C/|C| all exceed
// reach: C·Pi > reach·|C|, compared as squares of the positive sides.
fn wide_along_centres(rel: RelPath, h: real, reach: real) -> bool {
    let cc = dot2(rel.c, rel.c);
    let q1 = dot2(rel.c, rel.c + (0.5 * h) * rel.b);
    let q2 = dot2(rel.c, rel.c + h * rel.b + (h * h) * rel.a);
    let bound = reach * reach * cc;
    return cc > reach * reach && q1 > 0.0 && q2 > 0.0 && q1 * q1 > bound && q2 * q2 > bound;
}

// Whether C(t) stays farther than reach from the line through the origin along B, on one
// side, for t in [0, h]. w(t) = B × C(t) = B × C + t² (B × A) is |B| times the signed
// distance, monotone on [0, h], so its ends decide; compared as squares.
fn wide_sideways(rel: RelPath, h: real, reach: real) -> bool {
    let w0 = perp_dot(rel.b, rel.c);
    let w_h = w0 + (h * h) * perp_dot(rel.b, rel.a);
    let bound = reach * reach * dot2(rel.b, rel.b);
    return w0 * w_h > 0.0 && w0 * w0 > bound && w_h * w_h > bound;
}

// The answer for a relative path that moves, within horizon h (rules 2–4).
fn first_contact(rel: RelPath, radius: real, h: real) -> Contact {
    // prune: the pair passes by, wide of contact (no rule applies)
    if passes_wide(rel, radius, h) {
        return contact_none(h);
    }
    let four_r2 = 4.0 * radius * radius;
    let d0 = norm(rel.c) - 2.0 * radius;
    // rule 2: overlap
    if d0 < -CONTACT_TOL {
        return contact_overlap(h);
    }
    // rule 3: touching
    if d0 <= CONTACT_TOL {
        if approach_sign(rel) < 0.0 {
            let f0 = contact_fn(rel, four_r2, 0.0, 0u).x;
            if f0 > 0.0 {
                let t = first_entry(rel, four_r2, h, false);
                if t > 0.0 {
                    return contact_hit(t, h);
                }
            }
            return contact_hit(0.0, h);
        }
        let t = first_entry(rel, four_r2, h, true);
        if t >= 0.0 {
            return contact_hit(t, h);
        }
        return contact_none(h);
    }
    // prune: the path provably stays out of contact within h
    if cannot_meet(rel, radius, h) {
        return contact_none(h);
    }
    // rule 4: the first entry into contact
    let t = first_entry(rel, four_r2, h, false);
    if t >= 0.0 {
        return contact_hit(t, h);
    }
    return contact_none(h);
}

// The answer for a pair of balls on their paths (rules 1–4).
fn pair_contact(p1: BallPath, p2: BallPath, radius: real) -> Contact {
    let h = pair_horizon(p1, p2);
    // rule 1: a pocketed ball, or nothing moves
    if ((p1.flags | p2.flags) & PATH_POCKETED) != 0u || ((p1.flags | p2.flags) & PATH_MOVES) == 0u {
        return contact_none(h);
    }
    return first_contact(rel_between(p1, p2), radius, h);
}

// The simulator's ball–ball detection (spec §4.2): τ until balls b1 and b2 collide. Rules,
// in pooltool's order: either ball pocketed → never; neither translating → never; centres
// closer than 2R (3D, strictly) → 0, "now" (Q3); centres exactly 2R apart in pooltool's
// arithmetic (its quartic's constant coefficient Δx² + Δy² − 4R² is 0) → 0, "now", even
// for balls moving apart (its root filter keeps τ = 0, §4.2); otherwise the first entry
// into contact of the relative path, by first_contact within the pair's horizon. The Rust twin's docs
// say how this differs from pooltool's quartic solver (Q5).
fn ball_ball_time(b1: BallState, b2: BallState, p: BallParams) -> real {
    let rule = ball_ball_rules(b1, b2, p.r);
    if rule >= 0.0 {
        return rule;
    }
    return ball_ball_time_on(trajectory(b1, p), trajectory(b2, p), p.r);
}

// The rules ball_ball_time applies before any path is computed: NEVER if either ball is
// pocketed or neither translates, 0 if the centres are closer than 2R (Q3) or exactly 2R
// apart as pooltool's quartic sees it (its constant coefficient is 0, and its root filter
// keeps the root τ = 0 even for balls moving apart); −1 (Rust: None) when the pair's paths
// must be solved.
fn ball_ball_rules(b1: BallState, b2: BallState, radius: real) -> real {
    if b1.s == STATE_POCKETED || b2.s == STATE_POCKETED {
        return NEVER;
    }
    if !ball_translating(b1) && !ball_translating(b2) {
        return NEVER;
    }
    if norm3(b2.r - b1.r) < 2.0 * radius {
        return 0.0;
    }
    // exactly touching in pooltool's arithmetic: its quartic's constant coefficient
    // e = Δx² + Δy² − 4R² (evaluated as it does) is 0, τ = 0 is a root and its filter keeps
    // it (§4.2): "now", even for a pair moving apart (FUZZING.md, finding 31)
    let dx = b2.r.x - b1.r.x;
    let dy = b2.r.y - b1.r.y;
    if dx * dx + dy * dy - 4.0 * radius * radius == 0.0 {
        return 0.0;
    }
    return -1.0;
}

// ball_ball_time after its rules, on the two balls' paths (computed once per ball).
fn ball_ball_time_on(p1: Path, p2: Path, radius: real) -> real {
    let rel = RelPath(p2.a - p1.a, p2.b - p1.b, p2.c - p1.c);
    let h = min(p1.horizon, p2.horizon);
    let contact = first_contact(rel, radius, h);
    if contact.status == STATUS_NONE {
        return NEVER;
    }
    return contact.t;
}
