//! Ball–cushion resolution (spec §5.3, §5.4; `physics/resolve/ball_cushion/core.py`,
//! `.../stronge_compliant/model.py: _solve`): the 1 µm make_kiss spacer, then Stronge's
//! compliant model along pooltool's tilted 3D contact normal, then v_z = 0 (Q7). The same
//! core serves straight and circular segments; only the spacer and the normal differ.

use crate::model::MotionState;
use crate::model::ball_state::BallState;
use crate::model::sim_params::{BallParams, ResolverParams};
use crate::model::table::{CircularCushion, LinearCushion};
use crate::model::vec3::Vec3;
use crate::query::roots::smallest_kiss_root;
use crate::resolve::stronge::{StrongeConsts, stronge_compliant};

/// The kissed position for a straight segment (§5.3): back along v until the centre is
/// `R + s` from the segment's line; fallback (non-translating ball, or a move over 5s,
/// i.e. incidence within ~11.5° of the cushion): along the line's normal from the closest
/// point of the infinite line.
pub fn make_kiss_linear(b: &BallState, seg: &LinearCushion, p: &BallParams, s: f64) -> Vec3 {
    if b.translating() {
        let mut n = Vec3::new(seg.lx, seg.ly, 0.0).unit();
        if n.dot(b.v) < 0.0 {
            n = -n;
        }
        let d0 = (b.r - seg.p1).dot(n);
        let vn = b.v.dot(n);
        let t1 = (p.r + s - d0) / vn;
        let t2 = (-(p.r + s) - d0) / vn;
        let tau = if t1.abs() < t2.abs() { t1 } else { t2 };
        let step = tau * b.v;
        if step.norm() <= 5.0 * s && tau.is_finite() {
            return b.r + step;
        }
    }
    let e = (seg.p2 - seg.p1).unit();
    let foot = seg.p1 + (b.r - seg.p1).dot(e) * e;
    let c = Vec3::new(foot.x, foot.y, b.r.z);
    c + (p.r + s) * (b.r - c).unit()
}

/// The kissed position for a circular segment (§5.3): back along v until the centre is
/// `R + r_c + s` from the arc's centre (root nearest 0); fallback radially.
pub fn make_kiss_circular(b: &BallState, seg: &CircularCushion, p: &BallParams, s: f64) -> Vec3 {
    let q = Vec3::new(seg.center.x, seg.center.y, b.r.z);
    let d = p.r + seg.radius + s;
    if b.translating() {
        let (dr, v) = ((b.r - q).xy(), b.v.xy());
        if let Some(tau) = smallest_kiss_root(v.dot(v), 2.0 * dr.dot(v), dr.dot(dr) - d * d) {
            let step = tau * b.v;
            if step.norm() <= 5.0 * s {
                return b.r + step;
            }
        }
    }
    q + d * (b.r - q).unit()
}

/// The contact normal of a straight segment at (kissed) centre r: from the nose line
/// (at the cushion height) to the centre, `unit(ρ − (ρ·ê)ê)`, ρ = r − p1 (3D, tilted).
pub fn linear_normal(r: Vec3, seg: &LinearCushion) -> Vec3 {
    let e = (seg.p2 - seg.p1).unit();
    let rho = r - seg.p1;
    (rho - rho.dot(e) * e).unit()
}

/// The contact normal of a circular segment: `unit(r − (a_c, b_c, h))` (3D, tilted).
pub fn circular_normal(r: Vec3, seg: &CircularCushion) -> Vec3 {
    (r - seg.center).unit()
}

/// The constants of Stronge's model for a ball on a cushion (§5.4): the cushion's friction
/// and restitution, the resolver's η², β_t, β_n and k_n, the ball's mass.
pub fn cushion_consts(p: &BallParams, rp: &ResolverParams) -> StrongeConsts {
    StrongeConsts {
        mu: p.f_c,
        e: p.e_c,
        eta2: rp.eta2(),
        beta_t: rp.beta_t,
        beta_n: rp.beta_n,
        k_n: rp.k_n,
        m: p.m,
    }
}

/// Stronge's model applied along contact normal `n` (§5.4 steps 1–7). The ball leaves
/// sliding with v_z = 0; its position is unchanged.
///
/// Deviation (Q16): pooltool asserts the contact point approaches the cushion
/// (`v_n0 < 0`); a ball that reaches the checked line moving away (it started behind
/// it) gets no impulse here, only the sliding label.
pub fn stronge_cushion(b: &BallState, n: Vec3, p: &BallParams, rp: &ResolverParams) -> BallState {
    let vc = b.v + b.w.cross(-p.r * n);
    let v_n0 = n.dot(vc);
    // not approaching (NaN included)
    if v_n0 >= 0.0 || v_n0.is_nan() {
        return BallState {
            s: MotionState::Sliding,
            ..*b
        };
    }
    let m_t = n.cross(vc);
    let v_t0 = -m_t.norm();
    let t_hat = if v_t0 == 0.0 {
        Vec3::ZERO
    } else {
        (1.0 / v_t0) * m_t.cross(n)
    };
    let (v_tf, v_nf) = stronge_compliant(v_t0, v_n0, &cushion_consts(p, rp));
    let dvn = (v_nf - v_n0) / rp.beta_n;
    let dvt = (v_tf - v_t0) / rp.beta_t;
    let v = b.v + dvn * n + dvt * t_hat;
    let w = b.w + (2.5 / p.r) * (-n).cross(dvt * t_hat);
    BallState {
        v: Vec3::new(v.x, v.y, 0.0),
        w,
        s: MotionState::Sliding,
        ..*b
    }
}

/// A ball hitting a straight segment: kiss, then Stronge along the segment's normal.
pub fn resolve_linear_cushion(
    b: &BallState,
    seg: &LinearCushion,
    p: &BallParams,
    rp: &ResolverParams,
) -> BallState {
    let r = make_kiss_linear(b, seg, p, rp.spacer);
    let kissed = BallState { r, ..*b };
    stronge_cushion(&kissed, linear_normal(r, seg), p, rp)
}

/// A ball hitting a circular segment: kiss, then Stronge along the arc's normal.
pub fn resolve_circular_cushion(
    b: &BallState,
    seg: &CircularCushion,
    p: &BallParams,
    rp: &ResolverParams,
) -> BallState {
    let r = make_kiss_circular(b, seg, p, rp.spacer);
    let kissed = BallState { r, ..*b };
    stronge_cushion(&kissed, circular_normal(r, seg), p, rp)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::table::Table;

    fn close(got: f64, want: f64) -> bool {
        (got - want).abs() <= 1e-12 * want.abs().max(1.0)
    }

    fn at_rail9(v: Vec3, w: Vec3, s: MotionState) -> BallState {
        let r = BallParams::default().r;
        BallState {
            v,
            w,
            s,
            ..BallState::at_rest(0.6, 2.54 - r, r)
        }
    }

    fn rail9() -> LinearCushion {
        let t = Table::nine_foot();
        assert_eq!(t.linear_ids[5], "9");
        t.linear[5]
    }

    /// Spec §8, test vector C.
    #[test]
    fn vector_c_square_hits() {
        let (p, rp) = (BallParams::default(), ResolverParams::default());
        let b = at_rail9(Vec3::new(0.0, 1.0, 0.0), Vec3::ZERO, MotionState::Sliding);
        let out = resolve_linear_cushion(&b, &rail9(), &p, &rp);
        assert!((out.r.y - 2.511424).abs() < 1e-12, "{}", out.r.y);
        assert!(close(out.v.y, -0.738773122523598), "{}", out.v.y);
        assert!(close(out.w.x, 7.547591950371055), "{}", out.w.x);
        assert!(out.v.x.abs() < 1e-15 && out.v.z == 0.0);
        let rolling = at_rail9(
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(-1.0 / p.r, 0.0, 0.0),
            MotionState::Rolling,
        );
        let out = resolve_linear_cushion(&rolling, &rail9(), &p, &rp);
        assert!(close(out.v.y, -0.811578555970696), "{}", out.v.y);
        assert!(close(out.w.x, -3.823482612647911), "{}", out.w.x);
        assert_eq!(out.s, MotionState::Sliding);
    }

    /// Spec §8, test vector D: rolling at 45° with side spin.
    #[test]
    fn vector_d_angled_hit_with_spin() {
        let (p, rp) = (BallParams::default(), ResolverParams::default());
        let s = 1.5 / 2f64.sqrt();
        let b = at_rail9(
            Vec3::new(s, s, 0.0),
            Vec3::new(-s / p.r, s / p.r, 20.0),
            MotionState::Rolling,
        );
        let out = resolve_linear_cushion(&b, &rail9(), &p, &rp);
        for (got, want) in [
            (out.v.x, 0.868305421827376),
            (out.v.y, -0.846622456421515),
            (out.w.x, -8.658807275613675),
            (out.w.y, 32.5810284196731),
            (out.w.z, 36.20570205292431),
        ] {
            assert!(close(got, want), "{got} vs {want}");
        }
    }

    /// Spec §8, test vector E: jaw 8t.
    #[test]
    fn vector_e_jaw_arc() {
        let (p, rp) = (BallParams::default(), ResolverParams::default());
        let t = Table::nine_foot();
        let jaw = t.circular[5];
        assert_eq!(t.circular_ids[5], "8t");
        let d = Vec3::new(0.3, 1.0, 0.0).unit();
        let b = BallState {
            v: d,
            w: Vec3::new(-d.y / p.r, d.x / p.r, 0.0),
            s: MotionState::Rolling,
            ..BallState::at_rest(0.076770818755108, 2.513513653224423, p.r)
        };
        let out = resolve_circular_cushion(&b, &jaw, &p, &rp);
        assert!((out.r.x - 0.076770531407223).abs() < 1e-14, "{}", out.r.x);
        assert!((out.r.y - 2.513512695398137).abs() < 1e-14, "{}", out.r.y);
        for (got, want) in [
            (out.v.x, -0.247463664210329),
            (out.v.y, -0.824878880701096),
            (out.w.x, -2.910836126349011),
            (out.w.y, 0.8732508379046973),
        ] {
            assert!(close(got, want), "{got} vs {want}");
        }
        assert!(out.w.z.abs() < 1e-12, "{}", out.w.z);
    }

    #[test]
    fn shallow_hit_uses_the_normal_fallback() {
        let (p, rp) = (BallParams::default(), ResolverParams::default());
        let b = at_rail9(Vec3::new(1.0, 0.05, 0.0), Vec3::ZERO, MotionState::Sliding);
        let r = make_kiss_linear(&b, &rail9(), &p, rp.spacer);
        assert!((r.y - (2.54 - p.r - 1e-6)).abs() < 1e-15);
        assert_eq!(r.x, b.r.x);
    }
}
