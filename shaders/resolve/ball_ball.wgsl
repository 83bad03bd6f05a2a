// Ball–ball resolution (spec §5.1, §5.2): the 1 µm make_kiss spacer, then pooltool's
// `frictional_inelastic` model with Alciatore's friction curve, then the
// continually-touching momentum fix (`physics/resolve/ball_ball/core.py`,
// `.../frictional_inelastic/__init__.py: _resolve_ball_ball`, `.../friction.py`). WGSL twin
// of src/resolve/ball_ball.rs: the same functions in the same order with the same
// comments. Differences, all forced by WGSL: structs instead of tuples and Option, a
// pointer pair instead of `&mut`, exp from the precision prelude (real_exp: in f64 the
// Rust twin's exp_poly).
//
// Needs (before it): the precision prelude, model/ball.wgsl, model/vec3.wgsl,
// model/sim_params.wgsl, model/ball_state.wgsl, query/roots.wgsl (smallest_kiss_root).

// The kissed positions of a pair (Rust: the tuple (r1, r2)).
struct KissedPair {
    r1: real3,
    r2: real3,
}

// The kissed positions `(r1, r2)`: both balls moved back along their velocities until
// the centres are `2R + s` apart (3D; accelerations ignored), root nearest 0 (Q1).
//
// Fallback, when both balls are non-translating or the midpoint would move by more than
// 5s: push the centres apart symmetrically along the line of centres to `2R + s`.
// Deviation: pooltool raises (argmin of an empty array) when no root exists (Δv = 0);
// here the fallback is used.
fn make_kiss_ball_ball(b1: BallState, b2: BallState, p: BallParams, s: real) -> KissedPair {
    if ball_translating(b1) || ball_translating(b2) {
        let dr = b2.r - b1.r;
        let dv = b2.v - b1.v;
        let d = 2.0 * p.r + s;
        let root = smallest_kiss_root(dot3(dv, dv), 2.0 * dot3(dr, dv), dot3(dr, dr) - d * d);
        if root.found {
            let tau = root.tau;
            let r1 = b1.r + tau * b1.v;
            let r2 = b2.r + tau * b2.v;
            let mid_move = norm3(0.5 * (tau * b1.v + tau * b2.v));
            if mid_move <= 5.0 * s {
                return KissedPair(r1, r2);
            }
        }
    }
    let dr = b2.r - b1.r;
    let delta = 2.0 * p.r - norm3(dr) + s;
    let n = unit3(dr);
    return KissedPair(b1.r - (0.5 * delta) * n, b2.r + (0.5 * delta) * n);
}

// Alciatore's ball–ball friction `μ_b = a + b·exp(−c·|v1c − v2c|)` from the contact
// points' tangential velocities, `vic = vi − (vi·n)n ± ωi × (R n)` (§5.2 step 1).
fn alciatore_friction(b1: BallState, b2: BallState, p: BallParams, rp: ResolverParams) -> real {
    let n = unit3(b2.r - b1.r);
    let v1c = b1.v - dot3(b1.v, n) * n + cross3(b1.w, p.r * n);
    let v2c = b2.v - dot3(b2.v, n) * n + cross3(b2.w, -p.r * n);
    return rp.alciatore_a + rp.alciatore_b * real_exp(-rp.alciatore_c * norm3(v1c - v2c));
}

// Velocities and spins of a pair in the line-of-centres frame.
struct Pair {
    v1: real3,
    w1: real3,
    v2: real3,
    w2: real3,
}

// The contact slip `w12 = (v1 + ω1 × R x̂) − (v2 + ω2 × (−R x̂))`.
fn contact_slip(q: Pair, r: real) -> real3 {
    let rx = real3(r, 0.0, 0.0);
    return (q.v1 + cross3(q.w1, rx)) - (q.v2 + cross3(q.w2, -rx));
}

// `q` with the impulse Δv on ball 1 (−Δv on ball 2) and Δω on both.
fn apply(q: Pair, dv: real3, dw: real3) -> Pair {
    return Pair(q.v1 + dv, q.w1 + dw, q.v2 - dv, q.w2 + dw);
}

// Steps 4–6 of §5.2 on the x-zeroed pair: a friction impulse `μ_b ΔV` against the slip
// if it does not reverse the slip, else the no-slip impulse.
fn tangential_impulse(q: Pair, mu: real, dv_normal: real, r: real) -> Pair {
    let x_hat = real3(1.0, 0.0, 0.0);
    let w12 = contact_slip(q, r);
    if norm3(w12) > SIM_EPS {
        let dv = (-mu * dv_normal) * unit3(w12);
        let dw = (5.0 / (2.0 * r)) * cross3(x_hat, dv);
        let slipped = apply(q, dv, dw);
        if dot3(w12, contact_slip(slipped, r)) > 0.0 {
            return slipped;
        }
    }
    let rel = q.v1 - q.v2;
    let dv = (-1.0 / 7.0) * (rel + r * cross3(q.w1 + q.w2, x_hat));
    let dw = (-5.0 / 14.0) * ((1.0 / r) * cross3(x_hat, rel) + q.w1 + q.w2);
    return apply(q, dv, dw);
}

// A pair of ball states (Rust: the tuple (BallState, BallState)).
struct BallPair {
    b1: BallState,
    b2: BallState,
}

// The pair after `frictional_inelastic` (§5.2 steps 2–7) at the (kissed) positions of
// `b1`, `b2` with friction `mu`: normal components by restitution
// `e = (e_b1 + e_b2)/2`, the tangential impulse with the post-collision normal speed
// (Q9), x components restored, rotated back, v_z = 0, both labelled sliding (Q10).
//
// The rotations by ∓θ, θ = angle(r2 − r1), take θ's cosine and sine as the unit
// components of the horizontal r2 − r1 (rotate_z_cs), as the Rust twin does (WGSL's f64
// has no atan2; pooltool's atan2, cosine and sine give the same to rounding). Coincident
// centres (no horizontal offset) give θ = 0, as atan2(0, 0) does.
fn frictional_inelastic(b1: BallState, b2: BallState, mu: real, p: BallParams) -> BallPair {
    let e = 0.5 * (p.e_b + p.e_b);
    let d = b2.r - b1.r;
    let d_xy = norm3(xy3(d));
    var c: real = 1.0;
    var s: real = 0.0;
    if d_xy > 0.0 {
        c = d.x / d_xy;
        s = d.y / d_xy;
    }
    let v1 = rotate_z_cs(b1.v, c, -s);
    let w1 = rotate_z_cs(b1.w, c, -s);
    let v2 = rotate_z_cs(b2.v, c, -s);
    let w2 = rotate_z_cs(b2.w, c, -s);
    let v1x = 0.5 * ((1.0 - e) * v1.x + (1.0 + e) * v2.x);
    let v2x = 0.5 * ((1.0 + e) * v1.x + (1.0 - e) * v2.x);
    let dv_normal = abs(v2x - v1x);
    let q = Pair(
        real3(0.0, v1.y, v1.z),
        real3(0.0, w1.y, w1.z),
        real3(0.0, v2.y, v2.z),
        real3(0.0, w2.y, w2.z),
    );
    let out = tangential_impulse(q, mu, dv_normal, p.r);
    let nv1 = rotate_z_cs(real3(v1x, out.v1.y, out.v1.z), c, s);
    let nw1 = rotate_z_cs(real3(w1.x, out.w1.y, out.w1.z), c, s);
    let nv2 = rotate_z_cs(real3(v2x, out.v2.y, out.v2.z), c, s);
    let nw2 = rotate_z_cs(real3(w2.x, out.w2.y, out.w2.z), c, s);
    let n1 = BallState(b1.r, real3(nv1.x, nv1.y, 0.0), nw1, STATE_SLIDING, b1.t);
    let n2 = BallState(b2.r, real3(nv2.x, nv2.y, 0.0), nw2, STATE_SLIDING, b2.t);
    return BallPair(n1, n2);
}

// The continually-touching fix (§5.2 step 8, Q2): when both balls move, nearly along
// each other (cos > 0.9) with line-of-centres speeds within 0.01 m/s, the chaser (larger
// ℓ; ball 2 on a tie) hands 10% of its ℓ to the other. Only the n components change.
fn continually_touching(b1: ptr<function, BallState>, b2: ptr<function, BallState>) {
    let s1 = norm3((*b1).v);
    let s2 = norm3((*b2).v);
    if !(s1 > 0.0 && s2 > 0.0) {
        return;
    }
    let n = unit3((*b2).r - (*b1).r);
    let l1 = dot3((*b1).v, n);
    let l2 = dot3((*b2).v, n);
    let cosine = dot3((*b1).v, (*b2).v) / (s1 * s2);
    if abs(l2 - l1) < 0.01 && cosine > 0.9 {
        // the chaser, the other and ℓ (WGSL cannot choose between pointers: two arms)
        if l1 > l2 {
            let steal = 0.1 * l1;
            (*b1).v -= steal * n;
            (*b2).v += steal * n;
        } else {
            let steal = 0.1 * l2;
            (*b2).v -= steal * n;
            (*b1).v += steal * n;
        }
    }
}

// The whole ball–ball resolution (§5.1 then §5.2): kiss, friction, collision, fix.
fn resolve_ball_ball(b1: BallState, b2: BallState, p: BallParams, rp: ResolverParams) -> BallPair {
    let kiss = make_kiss_ball_ball(b1, b2, p, rp.spacer);
    let k1 = BallState(kiss.r1, b1.v, b1.w, b1.s, b1.t);
    let k2 = BallState(kiss.r2, b2.v, b2.w, b2.s, b2.t);
    let mu = alciatore_friction(k1, k2, p, rp);
    let out = frictional_inelastic(k1, k2, mu, p);
    var n1 = out.b1;
    var n2 = out.b2;
    continually_touching(&n1, &n2);
    return BallPair(n1, n2);
}
