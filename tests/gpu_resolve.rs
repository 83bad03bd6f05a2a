//! The WGSL twins of the resolutions (`shaders/resolve/*.wgsl`) run on the GPU in f64 and
//! compared with their Rust twins (`src/resolve/*.rs`) over many inputs that cover the
//! physics' ranges and every branch: ball–ball (head-on, cuts, both balls moving, the
//! slip / no-slip / rejected-slip impulses, the kiss's root and its fallbacks, the
//! continually-touching fix firing and not), Stronge (each regime of `stronge_compliant`
//! and each `isclose` band), cushions (straight segments from both sides and both
//! directions along them, shallow hits, balls moving away, jaws), the pocket and every
//! transition. Each test counts the branches its inputs took (replaying the Rust twin's
//! conditions) and fails if one was never taken.
//!
//! # Tolerances
//! The results are not bit-identical and are compared with [`RTOL`] and [`ATOL`]: the f64
//! prelude's exp/sin/cos/acos are the polyfills of `shaders/model/fmath.wgsl` (within an
//! ulp or two of std's), lavapipe's `fma` is not fused and its compiler re-associates
//! sums, and the shader rotates by the unit components of r2 − r1 where Rust takes the
//! cosine and sine of an atan2. Each test prints the largest absolute and relative
//! differences it saw, and where. Measured on lavapipe (Mesa 22.3): kisses, normals,
//! the touching fix, the pocket and the transitions bit for bit; otherwise at most
//! 2.3e-13 absolute (on spins of some 600 rad/s), and relative (values ≥ 1e-6) at most
//! 4e-15 where nothing cancels, 9e-13 in Stronge's v_t,f near zero, 3e-11 in cushion
//! spins and 3e-8 in the ball–ball z-spins of ~1e-6 rad/s that cancellation leaves.
//!
//! Each shader is also built with the f32 prelude (compile only), to check that it
//! validates in f32 too.
//!
//! Without an f64 adapter the tests print why and skip (`common::kernel::F64Kernels::open`);
//! under `KISSTIME_REQUIRE_GPU=1` a missing adapter is a failure.

mod common;

use std::collections::BTreeMap;
use std::f64::consts::PI;

use common::kernel::{self, F64Kernels};
use common::rng::TestRng;
use kisstime::MotionState;
use kisstime::model::vec3::angle;
use kisstime::model::{BallParams, BallState, LinearCushion, Pocket, ResolverParams, Table, Vec3};
use kisstime::motion::TransitionKind;
use kisstime::query::roots::smallest_kiss_root;
use kisstime::resolve::ball_ball::{
    alciatore_friction, continually_touching, frictional_inelastic, make_kiss_ball_ball,
    resolve_ball_ball,
};
use kisstime::resolve::ball_cushion::{
    circular_normal, cushion_consts, linear_normal, make_kiss_circular, make_kiss_linear,
    resolve_circular_cushion, resolve_linear_cushion, stronge_cushion,
};
use kisstime::resolve::stronge::{StrongeConsts, isclose, stronge_compliant};
use kisstime::resolve::{resolve_pocket, resolve_transition};

/// Relative tolerance of a GPU result against its Rust twin.
const RTOL: f64 = 1e-12;
/// Absolute tolerance (SI units: m, m/s, rad/s, s).
const ATOL: f64 = 1e-12;
/// The printed relative differences leave out values below this (cancellation residues,
/// ~1e-12, that the absolute tolerance covers).
const REL_FLOOR: f64 = 1e-6;

/// The model files every ball resolution needs, in dependency order.
const MODEL: [&str; 6] = [
    "model/ball.wgsl",
    "model/vec3.wgsl",
    "model/sim_params.wgsl",
    "model/ball_state.wgsl",
    "model/table.wgsl",
    "query/roots.wgsl",
];

fn files(extra: &[&'static str]) -> Vec<&'static str> {
    MODEL.iter().copied().chain(extra.iter().copied()).collect()
}

/// Reading and writing the packed inputs and outputs: the parameters first (10 ball, 8
/// resolver reals), a ball state as 11 reals (r, v, w, the state code, t).
const IO: &str = r#"
const NP: u32 = 18u;
const NB: u32 = 11u;

fn load_ball_params() -> BallParams {
    return BallParams(xs[0], xs[1], xs[2], xs[3], xs[4], xs[5], xs[6], xs[7], xs[8], xs[9]);
}

fn load_resolver_params() -> ResolverParams {
    return ResolverParams(xs[10], xs[11], xs[12], xs[13], xs[14], xs[15], xs[16], xs[17]);
}

fn load3(o: u32) -> real3 {
    return real3(xs[o], xs[o + 1u], xs[o + 2u]);
}

fn load_ball(o: u32) -> BallState {
    return BallState(load3(o), load3(o + 3u), load3(o + 6u), u32(xs[o + 9u]), xs[o + 10u]);
}

fn store3(o: u32, v: real3) {
    ys[o] = v.x;
    ys[o + 1u] = v.y;
    ys[o + 2u] = v.z;
}

fn store_ball(o: u32, b: BallState) {
    store3(o, b.r);
    store3(o + 3u, b.v);
    store3(o + 6u, b.w);
    ys[o + 9u] = real(b.s);
    ys[o + 10u] = b.t;
}
"#;

/// Ball–ball: per case b1, b2 and a friction μ (23 reals) in; out the kiss (6), the
/// Alciatore μ at the inputs (1), frictional_inelastic(b1, b2, μ) (22),
/// continually_touching(b1, b2) (22), resolve_ball_ball (22).
const BB_IN: usize = 23;
const BB_OUT: usize = 73;
const BB_ENTRY: &str = r#"
@compute @workgroup_size(64)
fn ball_ball_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= (arrayLength(&xs) - NP) / 23u {
        return;
    }
    let p = load_ball_params();
    let rp = load_resolver_params();
    let at = NP + 23u * i;
    let b1 = load_ball(at);
    let b2 = load_ball(at + NB);
    let mu = xs[at + 22u];
    let o = 73u * i;
    let kiss = make_kiss_ball_ball(b1, b2, p, rp.spacer);
    store3(o, kiss.r1);
    store3(o + 3u, kiss.r2);
    ys[o + 6u] = alciatore_friction(b1, b2, p, rp);
    let fi = frictional_inelastic(b1, b2, mu, p);
    store_ball(o + 7u, fi.b1);
    store_ball(o + 18u, fi.b2);
    var t1 = b1;
    var t2 = b2;
    continually_touching(&t1, &t2);
    store_ball(o + 29u, t1);
    store_ball(o + 40u, t2);
    let out = resolve_ball_ball(b1, b2, p, rp);
    store_ball(o + 51u, out.b1);
    store_ball(o + 62u, out.b2);
}
"#;

/// Stronge: per case v_t0, v_n0 and the 7 constants in; v_t,f, v_n,f out.
const ST_IN: usize = 9;
const ST_ENTRY: &str = r#"
@compute @workgroup_size(64)
fn stronge_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&xs) / 9u {
        return;
    }
    let o = 9u * i;
    let k = StrongeConsts(xs[o + 2u], xs[o + 3u], xs[o + 4u], xs[o + 5u], xs[o + 6u], xs[o + 7u], xs[o + 8u]);
    let f = stronge_compliant(xs[o], xs[o + 1u], k);
    ys[2u * i] = f.x;
    ys[2u * i + 1u] = f.y;
}
"#;

/// Cushions: per case the ball and the segment in (linear: p1, p2, direction, lx, ly, l0;
/// circular: centre, radius); out the kiss (3), the normal there (3), stronge_cushion at
/// the kiss along it (11), the whole resolution (11).
const LIN_IN: usize = 21;
const CIRC_IN: usize = 15;
const CU_OUT: usize = 28;
const CU_ENTRY: &str = r#"
@compute @workgroup_size(64)
fn linear_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= (arrayLength(&xs) - NP) / 21u {
        return;
    }
    let p = load_ball_params();
    let rp = load_resolver_params();
    let at = NP + 21u * i;
    let b = load_ball(at);
    let s = at + NB;
    let seg = LinearCushion(load3(s), load3(s + 3u), u32(xs[s + 6u]), xs[s + 7u], xs[s + 8u], xs[s + 9u]);
    let o = 28u * i;
    let r = make_kiss_linear(b, seg, p, rp.spacer);
    let n = linear_normal(r, seg);
    store3(o, r);
    store3(o + 3u, n);
    store_ball(o + 6u, stronge_cushion(BallState(r, b.v, b.w, b.s, b.t), n, p, rp));
    store_ball(o + 17u, resolve_linear_cushion(b, seg, p, rp));
}

@compute @workgroup_size(64)
fn circular_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= (arrayLength(&xs) - NP) / 15u {
        return;
    }
    let p = load_ball_params();
    let rp = load_resolver_params();
    let at = NP + 15u * i;
    let b = load_ball(at);
    let seg = CircularCushion(load3(at + NB), xs[at + NB + 3u]);
    let o = 28u * i;
    let r = make_kiss_circular(b, seg, p, rp.spacer);
    let n = circular_normal(r, seg);
    store3(o, r);
    store3(o + 3u, n);
    store_ball(o + 6u, stronge_cushion(BallState(r, b.v, b.w, b.s, b.t), n, p, rp));
    store_ball(o + 17u, resolve_circular_cushion(b, seg, p, rp));
}
"#;

/// Pocket: per case the ball and the pocket (centre, radius, depth) in, the ball out.
const PO_IN: usize = 16;
const PO_ENTRY: &str = r#"
@compute @workgroup_size(64)
fn pocket_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&xs) / 16u {
        return;
    }
    let at = 16u * i;
    let pocket = Pocket(load3(at + NB), xs[at + NB + 3u], xs[at + NB + 4u]);
    store_ball(NB * i, resolve_pocket(load_ball(at), pocket));
}
"#;

/// Transition: per case the ball and the TRANSITION_* code in, the ball out.
const TR_IN: usize = 12;
const TR_ENTRY: &str = r#"
@compute @workgroup_size(64)
fn transition_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&xs) / 12u {
        return;
    }
    let at = 12u * i;
    store_ball(NB * i, resolve_transition(load_ball(at), u32(xs[at + NB])));
}
"#;

// ---------------------------------------------------------------------------------------
// Inputs, comparison

/// A vector with components uniform in [−a, a).
fn rand_vec(rng: &mut TestRng, a: f64) -> Vec3 {
    v3(rng.range(-a, a), rng.range(-a, a), rng.range(-a, a))
}

fn v3(x: f64, y: f64, z: f64) -> Vec3 {
    Vec3::new(x, y, z)
}

fn state_code(s: MotionState) -> f64 {
    f64::from(s as u8)
}

fn push_ball(xs: &mut Vec<f64>, b: &BallState) {
    xs.extend([
        b.r.x,
        b.r.y,
        b.r.z,
        b.v.x,
        b.v.y,
        b.v.z,
        b.w.x,
        b.w.y,
        b.w.z,
        state_code(b.s),
        b.t,
    ]);
}

fn push_params(xs: &mut Vec<f64>, p: &BallParams, rp: &ResolverParams) {
    xs.extend([
        p.m, p.r, p.u_s, p.u_r, p.u_sp, p.u_b, p.e_b, p.e_c, p.f_c, p.g,
    ]);
    xs.extend([
        rp.alciatore_a,
        rp.alciatore_b,
        rp.alciatore_c,
        rp.omega_ratio,
        rp.beta_t,
        rp.beta_n,
        rp.k_n,
        rp.spacer,
    ]);
}

const BALL_FIELDS: [&str; 11] = [
    "r.x", "r.y", "r.z", "v.x", "v.y", "v.z", "w.x", "w.y", "w.z", "s", "t",
];

/// The largest differences of one resolution's outputs, and the cases out of tolerance.
struct Report {
    name: String,
    values: usize,
    max_abs: (f64, String),
    max_rel: (f64, String),
    bad: Vec<String>,
    bad_count: usize,
}

impl Report {
    fn new(name: &str) -> Report {
        Report {
            name: name.to_owned(),
            values: 0,
            max_abs: (0.0, String::new()),
            max_rel: (0.0, String::new()),
            bad: Vec::new(),
            bad_count: 0,
        }
    }

    fn fail(&mut self, msg: String) {
        self.bad_count += 1;
        if self.bad.len() < 12 {
            self.bad.push(msg);
        }
    }

    /// One real: GPU against Rust.
    fn real(&mut self, case: usize, field: &str, gpu: f64, cpu: f64) {
        self.values += 1;
        let abs = (gpu - cpu).abs();
        let scale = gpu.abs().max(cpu.abs());
        let rel = if scale >= REL_FLOOR { abs / scale } else { 0.0 };
        let at = || format!("case {case} {field}: gpu {gpu:e}, rust {cpu:e}");
        if abs > self.max_abs.0 {
            self.max_abs = (abs, at());
        }
        if rel > self.max_rel.0 {
            self.max_rel = (rel, at());
        }
        if !(gpu.is_finite() && kernel::close(gpu, cpu, RTOL, ATOL)) {
            self.fail(format!("{}: {}", self.name, at()));
        }
    }

    fn vec(&mut self, case: usize, what: &str, gpu: &[f64], cpu: Vec3) {
        for (k, (g, c)) in gpu.iter().zip([cpu.x, cpu.y, cpu.z]).enumerate() {
            self.real(case, &format!("{what}.{}", ["x", "y", "z"][k]), *g, c);
        }
    }

    /// A ball state: the reals within tolerance, the state code exactly.
    fn ball(&mut self, case: usize, what: &str, gpu: &[f64], cpu: &BallState) {
        let want = {
            let mut v = Vec::new();
            push_ball(&mut v, cpu);
            v
        };
        for (k, (g, c)) in gpu.iter().zip(&want).enumerate() {
            let field = format!("{what} {}", BALL_FIELDS[k]);
            if k == 9 {
                if g != c {
                    self.fail(format!(
                        "{}: case {case} {field}: gpu {g}, rust {c}",
                        self.name
                    ));
                }
            } else {
                self.real(case, &field, *g, *c);
            }
        }
    }

    /// Prints the largest differences; returns the failures.
    fn finish(self) -> Vec<String> {
        eprintln!(
            "{}: {} values; largest |Δ| {:.3e} ({}); largest relative (|x| ≥ {REL_FLOOR:e}) {:.3e} ({}); {} out of tolerance",
            self.name,
            self.values,
            self.max_abs.0,
            self.max_abs.1,
            self.max_rel.0,
            self.max_rel.1,
            self.bad_count
        );
        let mut out = self.bad;
        if self.bad_count > out.len() {
            out.push(format!(
                "{}: … and {} more",
                self.name,
                self.bad_count - out.len()
            ));
        }
        out
    }
}

/// How often each branch was taken; fails if one of `expected` never was.
#[derive(Default)]
struct Branches(BTreeMap<&'static str, usize>);

impl Branches {
    fn hit(&mut self, name: &'static str) {
        *self.0.entry(name).or_default() += 1;
    }

    fn check(&self, test: &str, expected: &[&str]) {
        eprintln!("{test}: branches {:?}", self.0);
        for name in expected {
            assert!(
                self.0.get(name).is_some_and(|&n| n > 0),
                "{test}: no input took the branch `{name}` ({:?})",
                self.0
            );
        }
    }
}

fn assert_clean(test: &str, failures: Vec<String>) {
    assert!(
        failures.is_empty(),
        "{test}: GPU and Rust differ beyond rtol {RTOL:e}, atol {ATOL:e}:\n{}",
        failures.join("\n")
    );
}

/// The f64 and (compile only) the f32 pipeline of `entry`.
fn pipelines(
    k: &F64Kernels,
    files: &[&str],
    entry_text: &str,
    entry: &str,
) -> wgpu::ComputePipeline {
    let text = format!("{IO}\n{entry_text}");
    let f32_source = kernel::source("f32", files, &text);
    k.pipeline(&f32_source, entry, &format!("{entry} (f32)"));
    k.pipeline(&kernel::source("f64", files, &text), entry, entry)
}

fn rolling_spin(v: Vec3, r: f64) -> Vec3 {
    v3(-v.y / r, v.x / r, 0.0)
}

/// Parameter sets: pooltool's defaults and a second, different table and ball.
fn param_sets() -> Vec<(BallParams, ResolverParams)> {
    let p = BallParams::default();
    let rp = ResolverParams::default();
    let r2 = 0.02625;
    let p2 = BallParams {
        m: 0.1406,
        r: r2,
        u_sp: 10.0 * 2.0 / 5.0 / 9.0 * r2,
        e_b: 0.9,
        e_c: 0.75,
        f_c: 0.3,
        ..p
    };
    let rp2 = ResolverParams {
        omega_ratio: 1.6,
        k_n: 2500.0,
        ..rp
    };
    vec![(p, rp), (p2, rp2)]
}

// ---------------------------------------------------------------------------------------
// Ball–ball

/// A ball with velocity `v` and a spin of `kind`: rolling, sliding with random spin, or
/// stunned (no spin).
fn moving_ball(rng: &mut TestRng, r: Vec3, v: Vec3, radius: f64) -> BallState {
    let (w, s) = match rng.below(3) {
        0 => (
            rolling_spin(v, radius) + v3(0.0, 0.0, rng.range(-60.0, 60.0)),
            MotionState::Rolling,
        ),
        1 => (
            rng.range(-3.0, 3.0) * rolling_spin(v, radius) + rand_vec(rng, 60.0),
            MotionState::Sliding,
        ),
        _ => (Vec3::ZERO, MotionState::Sliding),
    };
    BallState {
        r,
        v,
        w,
        s,
        t: rng.range(0.0, 10.0),
    }
}

/// A unit horizontal vector at angle `a`.
fn dir(a: f64) -> Vec3 {
    v3(a.cos(), a.sin(), 0.0)
}

/// The ball–ball cases: (category, b1, b2).
fn ball_ball_cases(rng: &mut TestRng, p: &BallParams) -> Vec<(&'static str, BallState, BallState)> {
    let radius = p.r;
    let mut cases = Vec::new();
    for i in 0..6000 {
        let r1 = v3(rng.range(0.1, 1.1), rng.range(0.1, 2.4), radius);
        let psi = rng.range(0.0, 2.0 * PI);
        // at the detected contact: 2R apart, to rounding or a little inside
        let dist = 2.0 * radius
            - if rng.coin() {
                rng.range(0.0, 1e-9)
            } else {
                0.0
            };
        let speed = rng.range(0.02, 6.0);
        let still = |rng: &mut TestRng, r: Vec3| BallState {
            w: if rng.coin() {
                v3(0.0, 0.0, rng.range(-40.0, 40.0))
            } else {
                Vec3::ZERO
            },
            s: MotionState::Stationary,
            t: rng.range(0.0, 10.0),
            ..BallState::at_rest(r.x, r.y, radius)
        };
        let (cat, b1, b2) = match i % 8 {
            // head-on on a still ball
            0 => {
                let b1 = moving_ball(rng, r1, speed * dir(psi), radius);
                let b2 = still(rng, r1 + dist * dir(psi));
                ("head-on", b1, b2)
            }
            // a cut on a still ball
            1 | 2 => {
                let cut = rng.range(-1.5, 1.5);
                let b1 = moving_ball(rng, r1, speed * dir(psi), radius);
                let b2 = still(rng, r1 + dist * dir(psi + cut));
                ("cut", b1, b2)
            }
            // both moving, approaching along the line of centres
            3 | 4 => {
                let n = dir(psi);
                let mut v1 = rng.range(0.0, 4.0) * dir(rng.range(0.0, 2.0 * PI));
                let mut v2 = rng.range(0.0, 4.0) * dir(rng.range(0.0, 2.0 * PI));
                if (v1 - v2).dot(n) < 0.0 {
                    std::mem::swap(&mut v1, &mut v2);
                }
                let b1 = moving_ball(rng, r1, v1, radius);
                let b2 = moving_ball(rng, r1 + dist * n, v2, radius);
                ("both moving", b1, b2)
            }
            // a chaser catching a ball moving the same way: the touching fix
            5 => {
                let n = dir(psi);
                let s = rng.range(0.05, 3.0);
                let ds = rng.range(0.0005, 0.02);
                let v1 = s * dir(psi + rng.range(-0.05, 0.05));
                let v2 = (s - ds) * dir(psi + rng.range(-0.02, 0.02));
                let b1 = moving_ball(rng, r1, v1, radius);
                let b2 = moving_ball(rng, r1 + dist * n, v2, radius);
                ("chasing", b1, b2)
            }
            // a stunned ball dead straight on a still one, with a tiny spin or none:
            // no slip, or a slip impulse that would reverse it
            6 => {
                let tiny = if rng.coin() {
                    0.0
                } else {
                    10f64.powf(rng.range(-15.0, -2.0)) / radius
                };
                let b1 = BallState {
                    w: tiny * rand_vec(rng, 1.0),
                    ..moving_ball(rng, r1, speed * dir(psi), radius)
                };
                let b1 = BallState {
                    s: MotionState::Sliding,
                    ..b1
                };
                let b2 = BallState {
                    w: Vec3::ZERO,
                    ..still(rng, r1 + dist * dir(psi))
                };
                ("no slip", b1, b2)
            }
            // the kiss's fallbacks: nothing translates (overlapping or apart), or the
            // balls move together (no root; ℓ1 = ℓ2 when along the line of centres)
            _ => {
                let gap = rng.range(-1e-4, 1e-4);
                if rng.coin() {
                    let b1 = still(rng, r1);
                    let b2 = BallState {
                        s: if rng.coin() {
                            MotionState::Spinning
                        } else {
                            MotionState::Stationary
                        },
                        ..still(rng, r1 + (2.0 * radius + gap) * dir(psi))
                    };
                    ("fallback: at rest", b1, b2)
                } else {
                    let v = if rng.coin() {
                        speed * dir(psi)
                    } else {
                        speed * dir(rng.range(0.0, 2.0 * PI))
                    };
                    let b1 = moving_ball(rng, r1, v, radius);
                    let b2 = BallState {
                        r: r1 + (2.0 * radius + gap) * dir(psi),
                        ..moving_ball(rng, r1, v, radius)
                    };
                    ("fallback: same velocity", b1, b2)
                }
            }
        };
        cases.push((cat, b1, b2));
    }
    cases
}

/// Which kiss the Rust twin takes (its conditions replayed).
fn kiss_branch(b1: &BallState, b2: &BallState, p: &BallParams, s: f64) -> &'static str {
    if !(b1.translating() || b2.translating()) {
        return "kiss: fallback, nothing translates";
    }
    let (dr, dv) = (b2.r - b1.r, b2.v - b1.v);
    let d = 2.0 * p.r + s;
    match smallest_kiss_root(dv.dot(dv), 2.0 * dr.dot(dv), dr.dot(dr) - d * d) {
        None => "kiss: fallback, no root",
        Some(tau) if (0.5 * (tau * b1.v + tau * b2.v)).norm() <= 5.0 * s => "kiss: root",
        Some(_) => "kiss: fallback, moved over 5s",
    }
}

/// Which tangential impulse `frictional_inelastic` applies (steps 4–6 replayed).
fn slip_branch(b1: &BallState, b2: &BallState, mu: f64, p: &BallParams) -> &'static str {
    let e = 0.5 * (p.e_b + p.e_b);
    let theta = angle(b2.r - b1.r);
    let rot = |v: Vec3| v.rotate_z(-theta);
    let (v1, w1, v2, w2) = (rot(b1.v), rot(b1.w), rot(b2.v), rot(b2.w));
    let dvn = (0.5 * ((1.0 + e) * v1.x + (1.0 - e) * v2.x)
        - 0.5 * ((1.0 - e) * v1.x + (1.0 + e) * v2.x))
        .abs();
    let zx = |v: Vec3| v3(0.0, v.y, v.z);
    let rx = v3(p.r, 0.0, 0.0);
    let slip = |v1: Vec3, w1: Vec3, v2: Vec3, w2: Vec3| (v1 + w1.cross(rx)) - (v2 + w2.cross(-rx));
    let (v1, w1, v2, w2) = (zx(v1), zx(w1), zx(v2), zx(w2));
    let w12 = slip(v1, w1, v2, w2);
    if w12.norm() <= kisstime::model::sim_params::EPS {
        return "impulse: no slip (|w12| ≤ EPS)";
    }
    let dv = (-mu * dvn) * w12.unit();
    let dw = (5.0 / (2.0 * p.r)) * Vec3::X.cross(dv);
    let after = slip(v1 + dv, w1 + dw, v2 - dv, w2 + dw);
    if w12.dot(after) > 0.0 {
        "impulse: slip"
    } else {
        "impulse: slip rejected, no slip"
    }
}

#[test]
fn ball_ball_twin_matches_rust() {
    let test = "ball_ball_twin_matches_rust";
    let Some(k) = F64Kernels::open(test) else {
        return;
    };
    let pipeline = pipelines(
        &k,
        &files(&["resolve/ball_ball.wgsl"]),
        BB_ENTRY,
        "ball_ball_main",
    );
    let mut rng = TestRng::new(17);
    let mut branches = Branches::default();
    let mut failures = Vec::new();
    for (set, (p, rp)) in param_sets().iter().enumerate() {
        let cases = ball_ball_cases(&mut rng, p);
        let mut xs = Vec::new();
        push_params(&mut xs, p, rp);
        let mut mus = Vec::new();
        for (_, b1, b2) in &cases {
            push_ball(&mut xs, b1);
            push_ball(&mut xs, b2);
            // a friction coefficient in the curve's range
            let mu = alciatore_friction(b1, b2, p, rp);
            xs.push(mu);
            mus.push(mu);
        }
        assert_eq!(xs.len(), 18 + BB_IN * cases.len());
        let ys = k.run(&pipeline, &xs, BB_OUT * cases.len(), cases.len());
        let mut reports = [
            "make_kiss_ball_ball",
            "alciatore_friction",
            "frictional_inelastic",
            "continually_touching",
            "resolve_ball_ball",
        ]
        .map(|n| Report::new(&format!("{n} (params {set})")));
        for (i, ((cat, b1, b2), mu)) in cases.iter().zip(&mus).enumerate() {
            let y = &ys[BB_OUT * i..BB_OUT * (i + 1)];
            branches.hit(cat);
            branches.hit(kiss_branch(b1, b2, p, rp.spacer));
            branches.hit(slip_branch(b1, b2, *mu, p));
            let (r1, r2) = make_kiss_ball_ball(b1, b2, p, rp.spacer);
            reports[0].vec(i, "r1", &y[0..3], r1);
            reports[0].vec(i, "r2", &y[3..6], r2);
            reports[1].real(i, "mu", y[6], alciatore_friction(b1, b2, p, rp));
            let (f1, f2) = frictional_inelastic(b1, b2, *mu, p);
            reports[2].ball(i, "b1", &y[7..18], &f1);
            reports[2].ball(i, "b2", &y[18..29], &f2);
            let (mut t1, mut t2) = (*b1, *b2);
            continually_touching(&mut t1, &mut t2);
            branches.hit(if (t1, t2) == (*b1, *b2) {
                "touching fix: not on the inputs"
            } else {
                "touching fix: fires on the inputs"
            });
            reports[3].ball(i, "b1", &y[29..40], &t1);
            reports[3].ball(i, "b2", &y[40..51], &t2);
            let (n1, n2) = resolve_ball_ball(b1, b2, p, rp);
            let k1 = BallState { r: r1, ..*b1 };
            let k2 = BallState { r: r2, ..*b2 };
            let (u1, u2) = frictional_inelastic(&k1, &k2, alciatore_friction(&k1, &k2, p, rp), p);
            branches.hit(if (u1, u2) == (n1, n2) {
                "touching fix: not after the collision"
            } else {
                "touching fix: fires after the collision"
            });
            reports[4].ball(i, "b1", &y[51..62], &n1);
            reports[4].ball(i, "b2", &y[62..73], &n2);
        }
        for r in reports {
            failures.extend(r.finish());
        }
    }
    branches.check(
        test,
        &[
            "head-on",
            "cut",
            "both moving",
            "chasing",
            "no slip",
            "fallback: at rest",
            "fallback: same velocity",
            "kiss: root",
            "kiss: fallback, nothing translates",
            "kiss: fallback, no root",
            "kiss: fallback, moved over 5s",
            "impulse: slip",
            "impulse: no slip (|w12| ≤ EPS)",
            "impulse: slip rejected, no slip",
            "touching fix: not on the inputs",
            "touching fix: fires on the inputs",
            "touching fix: not after the collision",
            "touching fix: fires after the collision",
        ],
    );
    assert_clean(test, failures);
}

// ---------------------------------------------------------------------------------------
// Stronge

/// The branch of `stronge_compliant` the Rust twin takes for `r` (its conditions
/// replayed).
fn stronge_branch(r: f64, k: &StrongeConsts) -> &'static str {
    let rho = k.beta_t / k.beta_n;
    let big_l = k.mu * k.eta2;
    let big_h = k.mu * ((1.0 + k.e) * rho - k.eta2 / k.e);
    if r > big_h {
        "gross slip"
    } else if r < big_l {
        if isclose(r, 0.0) {
            "stick-slip: r ≈ 0"
        } else if isclose(r, big_l) {
            "stick-slip: r ≈ L"
        } else {
            "stick-slip: root"
        }
    } else {
        let onset = if r <= k.mu * rho { "r ≤ M" } else { "r > M" };
        match (isclose(r, big_l), isclose(r, big_h), onset) {
            (true, _, _) => "slip-stick-slip: r ≈ L",
            (false, true, _) => "slip-stick-slip: r ≈ H",
            (false, false, "r ≤ M") => "slip-stick-slip: root, r ≤ M",
            _ => "slip-stick-slip: root, r > M",
        }
    }
}

/// How `bracketed_root`'s bracket [t_c, t_f] starts for the root the Rust twin looks for
/// (the functions f and g of `stick_slip` and `slip_stick_slip` replayed), or `None` when
/// the branch finds no root.
fn bracket_start(r: f64, v_n0: f64, k: &StrongeConsts) -> Option<&'static str> {
    let (mu, e, eta2) = (k.mu, k.e, k.eta2);
    let rho = k.beta_t / k.beta_n;
    let w_n = (k.beta_n * k.k_n / k.m).sqrt();
    let w_t = w_n * (rho / eta2).sqrt();
    let t_c = PI / (2.0 * w_n);
    let t_f = (1.0 + e) * t_c;
    let sigma = (PI / 2.0) * (1.0 - 1.0 / e);
    let phase = |t: f64| w_n * t / e + sigma;
    let f: Box<dyn Fn(f64) -> f64> = match stronge_branch(r, k) {
        "stick-slip: root" => Box::new(move |t: f64| {
            (r * (w_t * t).sin()).abs() - mu * eta2 * (w_t / w_n) * phase(t).sin()
        }),
        b if b.starts_with("slip-stick-slip: root") => {
            let tau_star = if r <= mu * rho {
                (2.0 / PI) * ((r / mu - rho) / (eta2 - rho)).clamp(-1.0, 1.0).acos()
            } else {
                let x = ((r / mu - rho) / (eta2 / e - e * rho)).clamp(-1.0, 1.0);
                (2.0 / PI) * (x.acos() - sigma) * e
            };
            let t_st = t_c * tau_star;
            let (u_st, v_st) = if t_st <= t_c {
                (
                    -mu * v_n0 * eta2 / w_n * (w_n * t_st).sin(),
                    r * v_n0 - mu * rho * v_n0 * (1.0 - (w_n * t_st).cos()),
                )
            } else {
                (
                    -mu * v_n0 * eta2 / w_n * phase(t_st).sin(),
                    r * v_n0 - mu * rho * v_n0 * (1.0 - e * phase(t_st).cos()),
                )
            };
            Box::new(move |t: f64| {
                let d = w_t * (t - t_st);
                let inner = u_st * d.cos() - (v_st / w_t) * d.sin();
                ((w_n / (mu * v_n0)) * inner).abs() - eta2 * phase(t).sin()
            })
        }
        _ => return None,
    };
    let (fa, fb) = (f(t_c), f(t_f));
    Some(if fa == 0.0 || fb == 0.0 {
        "bracket: an end is a root"
    } else if (fa > 0.0) == (fb > 0.0) {
        "bracket: same signs (the end with the smaller |f|)"
    } else {
        "bracket: sign change (bisection)"
    })
}

fn default_consts() -> StrongeConsts {
    cushion_consts(&BallParams::default(), &ResolverParams::default())
}

#[test]
fn stronge_twin_matches_rust() {
    let test = "stronge_twin_matches_rust";
    let Some(k) = F64Kernels::open(test) else {
        return;
    };
    let stronge_files = ["resolve/stronge.wgsl"];
    k.pipeline(
        &kernel::source("f32", &stronge_files, ST_ENTRY),
        "stronge_main",
        "stronge (f32)",
    );
    let pipeline = k.pipeline(
        &kernel::source("f64", &stronge_files, ST_ENTRY),
        "stronge_main",
        "stronge",
    );
    let mut rng = TestRng::new(5);
    let mut cases: Vec<(f64, f64, StrongeConsts)> = Vec::new();
    for set in 0..44 {
        let k = if set == 0 {
            default_consts()
        } else if set >= 40 {
            // ω_t t_f = 2π (omega_ratio (1 + e) = 4): stick–slip's f vanishes at t_f, to
            // rounding, so its bracket can start with equal signs
            let e = [0.85, 0.9, 0.95, 0.82][set - 40];
            let omega_ratio = 4.0 / (1.0 + e);
            StrongeConsts {
                e,
                eta2: 3.5 / (omega_ratio * omega_ratio),
                ..default_consts()
            }
        } else {
            let beta_t = rng.range(2.5, 4.5);
            let beta_n = rng.range(0.8, 1.2);
            let omega_ratio = rng.range(1.5, 2.2);
            StrongeConsts {
                mu: rng.range(0.05, 0.4),
                e: rng.range(0.5, 0.98),
                eta2: (beta_t / beta_n) / (omega_ratio * omega_ratio),
                beta_t,
                beta_n,
                k_n: rng.range(500.0, 5000.0),
                m: rng.range(0.1, 0.2),
            }
        };
        let rho = k.beta_t / k.beta_n;
        let (big_l, big_m) = (k.mu * k.eta2, k.mu * rho);
        let big_h = k.mu * ((1.0 + k.e) * rho - k.eta2 / k.e);
        let band = |x: f64| 1e-8 + 1e-5 * x.abs();
        let mut rs = vec![
            0.0,
            4e-9,
            big_l,
            big_l * (1.0 - 1e-7),
            big_l * (1.0 + 1e-7),
            big_l - 2.0 * band(big_l),
            big_l + 2.0 * band(big_l),
            big_m,
            big_m * (1.0 - 1e-9),
            big_m * (1.0 + 1e-9),
            big_h,
            big_h * (1.0 - 1e-7),
            big_h * (1.0 + 1e-7),
            big_h - 2.0 * band(big_h),
            big_h + 2.0 * band(big_h),
            1.32,
        ];
        let n = if set == 0 { 3000 } else { 250 };
        rs.extend((0..n).map(|_| rng.range(0.0, 1.4 * big_h)));
        rs.extend((0..n / 10).map(|_| rng.range(0.0, 1.1 * big_l)));
        for r in rs {
            let v_n0 = -rng.range(0.01, 6.0);
            cases.push((r * v_n0, v_n0, k));
        }
    }
    let mut xs = Vec::new();
    for (vt, vn, k) in &cases {
        xs.extend([*vt, *vn, k.mu, k.e, k.eta2, k.beta_t, k.beta_n, k.k_n, k.m]);
    }
    assert_eq!(xs.len(), ST_IN * cases.len());
    let ys = k.run(&pipeline, &xs, 2 * cases.len(), cases.len());
    let mut branches = Branches::default();
    let mut reports: BTreeMap<&str, Report> = BTreeMap::new();
    for (i, (vt, vn, k)) in cases.iter().enumerate() {
        let branch = stronge_branch(vt / vn, k);
        branches.hit(branch);
        if let Some(start) = bracket_start(vt / vn, *vn, k) {
            branches.hit(start);
        }
        let (tf, nf) = stronge_compliant(*vt, *vn, k);
        let rep = reports
            .entry(branch)
            .or_insert_with(|| Report::new(&format!("stronge_compliant, {branch}")));
        rep.real(i, "v_tf", ys[2 * i], tf);
        rep.real(i, "v_nf", ys[2 * i + 1], nf);
    }
    let failures: Vec<String> = reports.into_values().flat_map(Report::finish).collect();
    branches.check(
        test,
        &[
            "gross slip",
            "stick-slip: r ≈ 0",
            "stick-slip: r ≈ L",
            "stick-slip: root",
            "slip-stick-slip: r ≈ L",
            "slip-stick-slip: r ≈ H",
            "slip-stick-slip: root, r ≤ M",
            "slip-stick-slip: root, r > M",
            "bracket: sign change (bisection)",
            "bracket: same signs (the end with the smaller |f|)",
            "bracket: an end is a root",
        ],
    );
    assert_clean(test, failures);
}

// ---------------------------------------------------------------------------------------
// Cushions

/// A ball near a cushion (`r`, `n_out` the horizontal normal pointing from the cushion to
/// the ball, `along` a horizontal tangent) with a velocity of `kind` and a spin.
fn cushion_ball(
    rng: &mut TestRng,
    r: Vec3,
    n_out: Vec3,
    along: Vec3,
    radius: f64,
) -> (&'static str, BallState) {
    let speed = rng.range(0.02, 6.0);
    let (cat, a, away) = match rng.below(10) {
        0 => ("shallow", rng.sign() * rng.range(1.40, 1.5706), false),
        1 => ("moving away", rng.range(-1.5, 1.5), true),
        2 => ("square", 0.0, false),
        _ => ("angled", rng.range(-1.4, 1.4), false),
    };
    let toward = if away { n_out } else { -n_out };
    let v = speed * (a.cos() * toward + a.sin() * along);
    let mut b = moving_ball(rng, r, v, radius);
    match rng.below(12) {
        // at rest, or spinning in place: the kiss's fallback, no impulse
        0 => {
            b.v = Vec3::ZERO;
            b.w = v3(0.0, 0.0, rng.range(-40.0, 40.0));
            b.s = MotionState::Spinning;
            return ("at rest", b);
        }
        // labelled at rest but moving: the kiss's fallback with an impulse
        1 => {
            b.s = MotionState::Stationary;
            return ("fallback label", b);
        }
        // strong spin: every Stronge regime
        2 | 3 => b.w = rand_vec(rng, 250.0),
        _ => {}
    }
    (cat, b)
}

/// The Rust twin's branches for a cushion hit at kissed centre `r` along `n`.
fn cushion_branches(b: &BallState, n: Vec3, p: &BallParams, rp: &ResolverParams) -> &'static str {
    let vc = b.v + b.w.cross(-p.r * n);
    let v_n0 = n.dot(vc);
    if v_n0 >= 0.0 || v_n0.is_nan() {
        return "stronge: not approaching";
    }
    let v_t0 = -n.cross(vc).norm();
    match stronge_branch(v_t0 / v_n0, &cushion_consts(p, rp)) {
        "gross slip" => "stronge: gross slip",
        s if s.starts_with("stick") => "stronge: stick-slip",
        _ => "stronge: slip-stick-slip",
    }
}

fn push_linear(xs: &mut Vec<f64>, s: &LinearCushion) {
    xs.extend([
        s.p1.x,
        s.p1.y,
        s.p1.z,
        s.p2.x,
        s.p2.y,
        s.p2.z,
        f64::from(s.direction),
        s.lx,
        s.ly,
        s.l0,
    ]);
}

#[test]
fn cushion_twins_match_rust() {
    let test = "cushion_twins_match_rust";
    let Some(k) = F64Kernels::open(test) else {
        return;
    };
    let cushion_files = files(&[
        "resolve/ball_ball.wgsl",
        "resolve/stronge.wgsl",
        "resolve/ball_cushion.wgsl",
    ]);
    let linear_pipeline = pipelines(&k, &cushion_files, CU_ENTRY, "linear_main");
    let circular_pipeline = pipelines(&k, &cushion_files, CU_ENTRY, "circular_main");
    let table = Table::nine_foot();
    let mut rng = TestRng::new(99);
    let mut branches = Branches::default();
    let mut failures = Vec::new();
    for (set, (p, rp)) in param_sets().iter().enumerate() {
        let radius = p.r;
        // straight segments
        let mut cases = Vec::new();
        for i in 0..8000 {
            let seg = table.linear[i % table.linear.len()];
            let e = (seg.p2 - seg.p1).unit();
            let nh = v3(seg.lx, seg.ly, 0.0).unit();
            let side = rng.sign();
            let foot = seg.p1 + rng.range(0.02, 0.98) * (seg.p2 - seg.p1);
            let gap = radius + rng.range(-1e-9, 1e-9);
            let c = v3(foot.x, foot.y, 0.0) + (side * gap) * nh;
            let along = rng.sign() * e;
            let (cat, b) = cushion_ball(&mut rng, v3(c.x, c.y, radius), side * nh, along, radius);
            cases.push((cat, b, seg));
        }
        let mut xs = Vec::new();
        push_params(&mut xs, p, rp);
        for (_, b, seg) in &cases {
            push_ball(&mut xs, b);
            push_linear(&mut xs, seg);
        }
        assert_eq!(xs.len(), 18 + LIN_IN * cases.len());
        let ys = k.run(&linear_pipeline, &xs, CU_OUT * cases.len(), cases.len());
        let mut reports = [
            "make_kiss_linear",
            "linear_normal",
            "stronge_cushion (straight)",
            "resolve_linear_cushion",
        ]
        .map(|n| Report::new(&format!("{n} (params {set})")));
        for (i, (cat, b, seg)) in cases.iter().enumerate() {
            let y = &ys[CU_OUT * i..CU_OUT * (i + 1)];
            branches.hit(cat);
            let line = seg.lx * b.r.x + seg.ly * b.r.y + seg.l0;
            let e = seg.p2 - seg.p1;
            branches.hit(match (line < 0.0, b.v.dot(e) >= 0.0) {
                (true, true) => "straight: side 1, along p1→p2",
                (true, false) => "straight: side 1, along p2→p1",
                (false, true) => "straight: side 2, along p1→p2",
                (false, false) => "straight: side 2, along p2→p1",
            });
            let r = make_kiss_linear(b, seg, p, rp.spacer);
            branches.hit(if b.translating() && (r - b.r).cross(b.v).norm() <= 1e-12 {
                "straight kiss: back along v"
            } else {
                "straight kiss: fallback"
            });
            let n = linear_normal(r, seg);
            let kissed = BallState { r, ..*b };
            branches.hit(cushion_branches(&kissed, n, p, rp));
            reports[0].vec(i, "r", &y[0..3], r);
            reports[1].vec(i, "n", &y[3..6], n);
            reports[2].ball(i, "b", &y[6..17], &stronge_cushion(&kissed, n, p, rp));
            reports[3].ball(i, "b", &y[17..28], &resolve_linear_cushion(b, seg, p, rp));
        }
        for r in reports {
            failures.extend(r.finish());
        }
        // circular segments (the jaws)
        let mut cases = Vec::new();
        for i in 0..6000 {
            let seg = table.circular[i % table.circular.len()];
            let u = dir(rng.range(0.0, 2.0 * PI));
            let gap = radius + seg.radius + rng.range(-1e-9, 1e-9);
            let c = v3(seg.center.x, seg.center.y, 0.0) + gap * u;
            let along = rng.sign() * v3(-u.y, u.x, 0.0);
            let (cat, b) = cushion_ball(&mut rng, v3(c.x, c.y, radius), u, along, radius);
            cases.push((cat, b, seg));
        }
        let mut xs = Vec::new();
        push_params(&mut xs, p, rp);
        for (_, b, seg) in &cases {
            push_ball(&mut xs, b);
            xs.extend([seg.center.x, seg.center.y, seg.center.z, seg.radius]);
        }
        assert_eq!(xs.len(), 18 + CIRC_IN * cases.len());
        let ys = k.run(&circular_pipeline, &xs, CU_OUT * cases.len(), cases.len());
        let mut reports = [
            "make_kiss_circular",
            "circular_normal",
            "stronge_cushion (circular)",
            "resolve_circular_cushion",
        ]
        .map(|n| Report::new(&format!("{n} (params {set})")));
        for (i, (cat, b, seg)) in cases.iter().enumerate() {
            let y = &ys[CU_OUT * i..CU_OUT * (i + 1)];
            branches.hit(match *cat {
                "shallow" => "circular: shallow",
                "moving away" => "circular: moving away",
                "at rest" | "fallback label" => "circular: not translating",
                _ => "circular: towards",
            });
            let r = make_kiss_circular(b, seg, p, rp.spacer);
            branches.hit(if b.translating() && (r - b.r).cross(b.v).norm() <= 1e-12 {
                "circular kiss: back along v"
            } else {
                "circular kiss: fallback"
            });
            let n = circular_normal(r, seg);
            let kissed = BallState { r, ..*b };
            branches.hit(match cushion_branches(&kissed, n, p, rp) {
                "stronge: not approaching" => "circular stronge: not approaching",
                "stronge: gross slip" => "circular stronge: gross slip",
                "stronge: stick-slip" => "circular stronge: stick-slip",
                _ => "circular stronge: slip-stick-slip",
            });
            reports[0].vec(i, "r", &y[0..3], r);
            reports[1].vec(i, "n", &y[3..6], n);
            reports[2].ball(i, "b", &y[6..17], &stronge_cushion(&kissed, n, p, rp));
            reports[3].ball(i, "b", &y[17..28], &resolve_circular_cushion(b, seg, p, rp));
        }
        for r in reports {
            failures.extend(r.finish());
        }
    }
    branches.check(
        test,
        &[
            "shallow",
            "moving away",
            "square",
            "angled",
            "at rest",
            "fallback label",
            "straight: side 1, along p1→p2",
            "straight: side 1, along p2→p1",
            "straight: side 2, along p1→p2",
            "straight: side 2, along p2→p1",
            "straight kiss: back along v",
            "straight kiss: fallback",
            "stronge: not approaching",
            "stronge: gross slip",
            "stronge: stick-slip",
            "stronge: slip-stick-slip",
            "circular: shallow",
            "circular: moving away",
            "circular: not translating",
            "circular: towards",
            "circular kiss: back along v",
            "circular kiss: fallback",
            "circular stronge: not approaching",
            "circular stronge: gross slip",
            "circular stronge: stick-slip",
            "circular stronge: slip-stick-slip",
        ],
    );
    assert_clean(test, failures);
}

// ---------------------------------------------------------------------------------------
// Pocket, transitions

fn random_ball(rng: &mut TestRng) -> BallState {
    BallState {
        r: v3(rng.range(-0.1, 1.4), rng.range(-0.1, 2.6), 0.028575),
        v: rand_vec(rng, 5.0),
        w: rand_vec(rng, 200.0),
        s: MotionState::ALL[rng.below(5)],
        t: rng.range(0.0, 30.0),
    }
}

#[test]
fn pocket_and_transition_twins_match_rust() {
    let test = "pocket_and_transition_twins_match_rust";
    let Some(k) = F64Kernels::open(test) else {
        return;
    };
    let mut rng = TestRng::new(3);
    let mut failures = Vec::new();

    let pocket = pipelines(
        &k,
        &files(&["resolve/ball_pocket.wgsl"]),
        PO_ENTRY,
        "pocket_main",
    );
    let table = Table::nine_foot();
    let cases: Vec<(BallState, Pocket)> = (0..2000)
        .map(|i| {
            let mut pk = table.pockets[i % table.pockets.len()];
            if i % 2 == 1 {
                pk.depth = rng.range(0.02, 0.2);
            }
            (random_ball(&mut rng), pk)
        })
        .collect();
    let mut xs = Vec::new();
    for (b, pk) in &cases {
        push_ball(&mut xs, b);
        xs.extend([pk.center.x, pk.center.y, pk.center.z, pk.radius, pk.depth]);
    }
    assert_eq!(xs.len(), PO_IN * cases.len());
    let ys = k.run(&pocket, &xs, 11 * cases.len(), cases.len());
    let mut rep = Report::new("resolve_pocket");
    for (i, (b, pk)) in cases.iter().enumerate() {
        rep.ball(i, "b", &ys[11 * i..11 * (i + 1)], &resolve_pocket(b, pk));
    }
    failures.extend(rep.finish());

    let transition = pipelines(
        &k,
        &files(&["motion/evolve.wgsl", "resolve/transition.wgsl"]),
        TR_ENTRY,
        "transition_main",
    );
    let kinds = [
        TransitionKind::SlidingRolling,
        TransitionKind::RollingSpinning,
        TransitionKind::RollingStationary,
        TransitionKind::SpinningStationary,
    ];
    // the codes of shaders/motion/evolve.wgsl, in this order
    let cases: Vec<(BallState, usize)> =
        (0..2000).map(|i| (random_ball(&mut rng), i % 4)).collect();
    let mut xs = Vec::new();
    for (b, kind) in &cases {
        push_ball(&mut xs, b);
        xs.push(*kind as f64);
    }
    assert_eq!(xs.len(), TR_IN * cases.len());
    let ys = k.run(&transition, &xs, 11 * cases.len(), cases.len());
    let mut reps = kinds.map(|kind| Report::new(&format!("resolve_transition, {kind:?}")));
    for (i, (b, kind)) in cases.iter().enumerate() {
        let want = resolve_transition(b, kinds[*kind]);
        reps[*kind].ball(i, "b", &ys[11 * i..11 * (i + 1)], &want);
    }
    for rep in reps {
        failures.extend(rep.finish());
    }
    assert_clean(test, failures);
}
