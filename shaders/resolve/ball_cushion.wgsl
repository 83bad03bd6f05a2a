// Ball–cushion resolution (spec §5.3, §5.4; `physics/resolve/ball_cushion/core.py`,
// `.../stronge_compliant/model.py: _solve`): the 1 µm make_kiss spacer, then Stronge's
// compliant model along pooltool's tilted 3D contact normal, then v_z = 0 (Q7). The same
// core serves straight and circular segments; only the spacer and the normal differ. WGSL
// twin of src/resolve/ball_cushion.rs: the same functions in the same order with the same
// comments. Differences, all forced by WGSL: no NaN or ∞ to test for (noted where the
// Rust twin tests), methods as functions (`rp.eta2()` is `eta2(rp)`).
//
// Needs (before it): the precision prelude, model/ball.wgsl, model/vec3.wgsl,
// model/sim_params.wgsl, model/ball_state.wgsl, model/table.wgsl, query/roots.wgsl,
// resolve/ball_ball.wgsl (smallest_kiss_root, for now), resolve/stronge.wgsl.

// The kissed position for a straight segment (§5.3): back along v until the centre is
// `R + s` from the segment's line; fallback (non-translating ball, or a move over 5s,
// i.e. incidence within ~11.5° of the cushion): along the line's normal from the closest
// point of the infinite line.
//
// The Rust twin also falls back when τ is not finite; WGSL has no ∞ (its division by 0
// gives an indeterminate value), and τ is finite exactly when v_n ≠ 0 (short of an
// overflow, which the 5s test refuses too), so v_n ≠ 0 is tested before dividing.
fn make_kiss_linear(b: BallState, seg: LinearCushion, p: BallParams, s: real) -> real3 {
    if ball_translating(b) {
        var n = unit3(real3(seg.lx, seg.ly, 0.0));
        if dot3(n, b.v) < 0.0 {
            n = -n;
        }
        let d0 = dot3(b.r - seg.p1, n);
        let vn = dot3(b.v, n);
        if vn != 0.0 {
            let t1 = (p.r + s - d0) / vn;
            let t2 = (-(p.r + s) - d0) / vn;
            let tau = select(t2, t1, abs(t1) < abs(t2));
            let step = tau * b.v;
            if norm3(step) <= 5.0 * s {
                return b.r + step;
            }
        }
    }
    let e = unit3(seg.p2 - seg.p1);
    let foot = seg.p1 + dot3(b.r - seg.p1, e) * e;
    let c = real3(foot.x, foot.y, b.r.z);
    return c + (p.r + s) * unit3(b.r - c);
}

// The kissed position for a circular segment (§5.3): back along v until the centre is
// `R + r_c + s` from the arc's centre (root nearest 0); fallback radially.
fn make_kiss_circular(b: BallState, seg: CircularCushion, p: BallParams, s: real) -> real3 {
    let q = real3(seg.center.x, seg.center.y, b.r.z);
    let d = p.r + seg.radius + s;
    if ball_translating(b) {
        let dr = xy3(b.r - q);
        let v = xy3(b.v);
        let root = smallest_kiss_root(dot3(v, v), 2.0 * dot3(dr, v), dot3(dr, dr) - d * d);
        if root.found {
            let step = root.tau * b.v;
            if norm3(step) <= 5.0 * s {
                return b.r + step;
            }
        }
    }
    return q + d * unit3(b.r - q);
}

// The contact normal of a straight segment at (kissed) centre r: from the nose line
// (at the cushion height) to the centre, `unit(ρ − (ρ·ê)ê)`, ρ = r − p1 (3D, tilted).
fn linear_normal(r: real3, seg: LinearCushion) -> real3 {
    let e = unit3(seg.p2 - seg.p1);
    let rho = r - seg.p1;
    return unit3(rho - dot3(rho, e) * e);
}

// The contact normal of a circular segment: `unit(r − (a_c, b_c, h))` (3D, tilted).
fn circular_normal(r: real3, seg: CircularCushion) -> real3 {
    return unit3(r - seg.center);
}

// The constants of Stronge's model for a ball on a cushion (§5.4): the cushion's friction
// and restitution, the resolver's η², β_t, β_n and k_n, the ball's mass.
fn cushion_consts(p: BallParams, rp: ResolverParams) -> StrongeConsts {
    return StrongeConsts(p.f_c, p.e_c, eta2(rp), rp.beta_t, rp.beta_n, rp.k_n, p.m);
}

// Stronge's model applied along contact normal `n` (§5.4 steps 1–7). The ball leaves
// sliding with v_z = 0; its position is unchanged.
//
// Deviation (Q16): pooltool asserts the contact point approaches the cushion
// (`v_n0 < 0`); a ball that reaches the checked line moving away (it started behind
// it) gets no impulse here, only the sliding label.
fn stronge_cushion(b: BallState, n: real3, p: BallParams, rp: ResolverParams) -> BallState {
    let vc = b.v + cross3(b.w, -p.r * n);
    let v_n0 = dot3(n, vc);
    // not approaching (the Rust twin also tests for NaN, which WGSL cannot see)
    if !(v_n0 < 0.0) {
        return BallState(b.r, b.v, b.w, STATE_SLIDING, b.t);
    }
    let m_t = cross3(n, vc);
    let v_t0 = -norm3(m_t);
    var t_hat = real3(0.0, 0.0, 0.0);
    if v_t0 != 0.0 {
        t_hat = (1.0 / v_t0) * cross3(m_t, n);
    }
    let f = stronge_compliant(v_t0, v_n0, cushion_consts(p, rp));
    let v_tf = f.x;
    let v_nf = f.y;
    let dvn = (v_nf - v_n0) / rp.beta_n;
    let dvt = (v_tf - v_t0) / rp.beta_t;
    let v = b.v + dvn * n + dvt * t_hat;
    let w = b.w + (2.5 / p.r) * cross3(-n, dvt * t_hat);
    return BallState(b.r, real3(v.x, v.y, 0.0), w, STATE_SLIDING, b.t);
}

// A ball hitting a straight segment: kiss, then Stronge along the segment's normal.
fn resolve_linear_cushion(b: BallState, seg: LinearCushion, p: BallParams, rp: ResolverParams) -> BallState {
    let r = make_kiss_linear(b, seg, p, rp.spacer);
    let kissed = BallState(r, b.v, b.w, b.s, b.t);
    return stronge_cushion(kissed, linear_normal(r, seg), p, rp);
}

// A ball hitting a circular segment: kiss, then Stronge along the arc's normal.
fn resolve_circular_cushion(b: BallState, seg: CircularCushion, p: BallParams, rp: ResolverParams) -> BallState {
    let r = make_kiss_circular(b, seg, p, rp.spacer);
    let kissed = BallState(r, b.v, b.w, b.s, b.t);
    return stronge_cushion(kissed, circular_normal(r, seg), p, rp);
}
