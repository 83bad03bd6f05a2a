//! Ball–ball resolution (spec §5.1, §5.2): the 1 µm make_kiss spacer, then pooltool's
//! `frictional_inelastic` model with Alciatore's friction curve, then the
//! continually-touching momentum fix (`physics/resolve/ball_ball/core.py`,
//! `.../frictional_inelastic/__init__.py: _resolve_ball_ball`, `.../friction.py`).

use crate::model::MotionState;
use crate::model::ball_state::BallState;
use crate::model::fmath::exp_poly;
use crate::model::sim_params::{BallParams, EPS, ResolverParams};
use crate::model::vec3::Vec3;
use crate::query::roots::smallest_kiss_root;

/// The kissed positions `(r1, r2)`: both balls moved back along their velocities until
/// the centres are `2R + s` apart (3D; accelerations ignored), root nearest 0 (Q1).
///
/// Fallback, when both balls are non-translating or the midpoint would move by more than
/// 5s: push the centres apart symmetrically along the line of centres to `2R + s`.
/// Deviation: pooltool raises (argmin of an empty array) when no root exists (Δv = 0);
/// here the fallback is used.
pub fn make_kiss_ball_ball(b1: &BallState, b2: &BallState, p: &BallParams, s: f64) -> (Vec3, Vec3) {
    if b1.translating() || b2.translating() {
        let dr = b2.r - b1.r;
        let dv = b2.v - b1.v;
        let d = 2.0 * p.r + s;
        let root = smallest_kiss_root(dv.dot(dv), 2.0 * dr.dot(dv), dr.dot(dr) - d * d);
        if let Some(tau) = root {
            let (r1, r2) = (b1.r + tau * b1.v, b2.r + tau * b2.v);
            let mid_move = (0.5 * (tau * b1.v + tau * b2.v)).norm();
            if mid_move <= 5.0 * s {
                return (r1, r2);
            }
        }
    }
    let dr = b2.r - b1.r;
    let delta = 2.0 * p.r - dr.norm() + s;
    let n = dr.unit();
    (b1.r - (0.5 * delta) * n, b2.r + (0.5 * delta) * n)
}

/// Alciatore's ball–ball friction `μ_b = a + b·exp(−c·|v1c − v2c|)` from the contact
/// points' tangential velocities, `vic = vi − (vi·n)n ± ωi × (R n)` (§5.2 step 1); exp
/// is [`exp_poly`], the shader's (≤ 1 ulp).
pub fn alciatore_friction(
    b1: &BallState,
    b2: &BallState,
    p: &BallParams,
    rp: &ResolverParams,
) -> f64 {
    let n = (b2.r - b1.r).unit();
    let v1c = b1.v - b1.v.dot(n) * n + b1.w.cross(p.r * n);
    let v2c = b2.v - b2.v.dot(n) * n + b2.w.cross(-p.r * n);
    rp.alciatore_a + rp.alciatore_b * exp_poly(-rp.alciatore_c * (v1c - v2c).norm())
}

/// Velocities and spins of a pair in the line-of-centres frame.
#[derive(Clone, Copy)]
struct Pair {
    v1: Vec3,
    w1: Vec3,
    v2: Vec3,
    w2: Vec3,
}

/// The contact slip `w12 = (v1 + ω1 × R x̂) − (v2 + ω2 × (−R x̂))`.
fn contact_slip(q: &Pair, r: f64) -> Vec3 {
    let rx = Vec3::new(r, 0.0, 0.0);
    (q.v1 + q.w1.cross(rx)) - (q.v2 + q.w2.cross(-rx))
}

/// `q` with the impulse Δv on ball 1 (−Δv on ball 2) and Δω on both.
fn apply(q: &Pair, dv: Vec3, dw: Vec3) -> Pair {
    Pair {
        v1: q.v1 + dv,
        w1: q.w1 + dw,
        v2: q.v2 - dv,
        w2: q.w2 + dw,
    }
}

/// Steps 4–6 of §5.2 on the x-zeroed pair: a friction impulse `μ_b ΔV` against the slip
/// if it does not reverse the slip, else the no-slip impulse.
fn tangential_impulse(q: &Pair, mu: f64, dv_normal: f64, r: f64) -> Pair {
    let w12 = contact_slip(q, r);
    if w12.norm() > EPS {
        let dv = (-mu * dv_normal) * w12.unit();
        let dw = (5.0 / (2.0 * r)) * Vec3::X.cross(dv);
        let slipped = apply(q, dv, dw);
        if w12.dot(contact_slip(&slipped, r)) > 0.0 {
            return slipped;
        }
    }
    let rel = q.v1 - q.v2;
    let dv = (-1.0 / 7.0) * (rel + r * (q.w1 + q.w2).cross(Vec3::X));
    let dw = (-5.0 / 14.0) * ((1.0 / r) * Vec3::X.cross(rel) + q.w1 + q.w2);
    apply(q, dv, dw)
}

/// The pair after `frictional_inelastic` (§5.2 steps 2–7) at the (kissed) positions of
/// `b1`, `b2` with friction `mu`: normal components by restitution
/// `e = (e_b1 + e_b2)/2`, the tangential impulse with the post-collision normal speed
/// (Q9), x components restored, rotated back, v_z = 0, both labelled sliding (Q10).
///
/// The rotations by ∓θ, θ = angle(r2 − r1), take θ's cosine and sine as the unit
/// components of the horizontal r2 − r1, as the shader does (WGSL's f64 has no atan2);
/// pooltool computes θ with atan2 and rotates by its cosine and sine: the same to
/// rounding. Coincident centres give θ = 0, as atan2(0, 0) does.
pub fn frictional_inelastic(
    b1: &BallState,
    b2: &BallState,
    mu: f64,
    p: &BallParams,
) -> (BallState, BallState) {
    let e = 0.5 * (p.e_b + p.e_b);
    let d = b2.r - b1.r;
    let d_xy = d.xy().norm();
    let (c, s) = if d_xy > 0.0 {
        (d.x / d_xy, d.y / d_xy)
    } else {
        (1.0, 0.0)
    };
    let rot = |v: Vec3| v.rotate_z_cs(c, -s);
    let (v1, w1, v2, w2) = (rot(b1.v), rot(b1.w), rot(b2.v), rot(b2.w));
    let v1x = 0.5 * ((1.0 - e) * v1.x + (1.0 + e) * v2.x);
    let v2x = 0.5 * ((1.0 + e) * v1.x + (1.0 - e) * v2.x);
    let dv_normal = (v2x - v1x).abs();
    let zero_x = |v: Vec3| Vec3::new(0.0, v.y, v.z);
    let q = Pair {
        v1: zero_x(v1),
        w1: zero_x(w1),
        v2: zero_x(v2),
        w2: zero_x(w2),
    };
    let out = tangential_impulse(&q, mu, dv_normal, p.r);
    let back = |v: Vec3, x: f64| Vec3::new(x, v.y, v.z).rotate_z_cs(c, s);
    let flat = |v: Vec3| Vec3::new(v.x, v.y, 0.0);
    let n1 = BallState {
        v: flat(back(out.v1, v1x)),
        w: back(out.w1, w1.x),
        s: MotionState::Sliding,
        ..*b1
    };
    let n2 = BallState {
        v: flat(back(out.v2, v2x)),
        w: back(out.w2, w2.x),
        s: MotionState::Sliding,
        ..*b2
    };
    (n1, n2)
}

/// The continually-touching fix (§5.2 step 8, Q2): when both balls move, nearly along
/// each other (cos > 0.9) with line-of-centres speeds within 0.01 m/s, the chaser (larger
/// ℓ; ball 2 on a tie) hands 10% of its ℓ to the other. Only the n components change.
pub fn continually_touching(b1: &mut BallState, b2: &mut BallState) {
    let (s1, s2) = (b1.v.norm(), b2.v.norm());
    if !(s1 > 0.0 && s2 > 0.0) {
        return;
    }
    let n = (b2.r - b1.r).unit();
    let (l1, l2) = (b1.v.dot(n), b2.v.dot(n));
    let cos = b1.v.dot(b2.v) / (s1 * s2);
    if (l2 - l1).abs() < 0.01 && cos > 0.9 {
        let (chaser, other, l) = if l1 > l2 { (b1, b2, l1) } else { (b2, b1, l2) };
        let steal = 0.1 * l;
        chaser.v -= steal * n;
        other.v += steal * n;
    }
}

/// The whole ball–ball resolution (§5.1 then §5.2): kiss, friction, collision, fix.
pub fn resolve_ball_ball(
    b1: &BallState,
    b2: &BallState,
    p: &BallParams,
    rp: &ResolverParams,
) -> (BallState, BallState) {
    let (r1, r2) = make_kiss_ball_ball(b1, b2, p, rp.spacer);
    let k1 = BallState { r: r1, ..*b1 };
    let k2 = BallState { r: r2, ..*b2 };
    let mu = alciatore_friction(&k1, &k2, p, rp);
    let (mut n1, mut n2) = frictional_inelastic(&k1, &k2, mu, p);
    continually_touching(&mut n1, &mut n2);
    (n1, n2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    /// Spec §8, test vector F: a rolling cue ball, 30° cut on a still ball.
    #[test]
    fn vector_f_thirty_degree_cut() {
        let p = BallParams::default();
        let r = p.r;
        let cue = BallState {
            v: Vec3::new(0.0, 2.0, 0.0),
            w: Vec3::new(-2.0 / r, 0.0, 0.0),
            s: MotionState::Rolling,
            ..BallState::at_rest(0.6, 1.0, r)
        };
        let a = 60f64.to_radians();
        let obj = BallState::at_rest(0.6 + 2.0 * r * a.cos(), 1.0 + 2.0 * r * a.sin(), r);
        let (c, o) = resolve_ball_ball(&cue, &obj, &p, &ResolverParams::default());
        let tol = 1e-12;
        assert!(close(c.r.y, 0.999998845302829, 1e-14), "{}", c.r.y);
        for (got, want) in [
            (c.v.x, -0.828541514059083),
            (c.v.y, 0.528347506162533),
            (c.w.x, -67.59338752708385),
            (c.w.y, -1.384374877666749),
            (c.w.z, -1.5985290932448),
            (o.v.x, 0.828541514059083),
            (o.v.y, 1.471652493837467),
            (o.w.x, 2.397863566529455),
            (o.w.y, -1.384374877666743),
            (o.w.z, -1.5985290932448),
        ] {
            assert!(
                close(got, want, tol * want.abs().max(1.0)),
                "{got} vs {want}"
            );
        }
        assert_eq!((c.v.z, o.v.z), (0.0, 0.0));
        assert_eq!((c.s, o.s), (MotionState::Sliding, MotionState::Sliding));
    }

    #[test]
    fn kiss_fallback_when_nothing_moves() {
        let p = BallParams::default();
        let a = BallState::at_rest(0.5, 0.5, p.r);
        let b = BallState::at_rest(0.5, 0.5 + 1.5 * p.r, p.r);
        let (r1, r2) = make_kiss_ball_ball(&a, &b, &p, 1e-6);
        assert!(close((r2 - r1).norm(), 2.0 * p.r + 1e-6, 1e-15));
        assert!(close(0.5 * (r1.y + r2.y), b.r.y * 0.5 + 0.25, 1e-15));
    }

    #[test]
    fn chaser_hands_over_momentum() {
        let r = 0.028575;
        let mut b1 = BallState {
            v: Vec3::new(0.0, 1.005, 0.0),
            ..BallState::at_rest(0.5, 0.5, r)
        };
        let mut b2 = BallState {
            v: Vec3::new(0.0, 1.0, 0.0),
            ..BallState::at_rest(0.5, 0.5 + 2.0 * r, r)
        };
        continually_touching(&mut b1, &mut b2);
        assert!(close(b1.v.y, 1.005 - 0.1005, 1e-15));
        assert!(close(b2.v.y, 1.0 + 0.1005, 1e-15));
    }
}
