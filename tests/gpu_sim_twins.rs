//! The WGSL twins of the simulator's motion and detection (`shaders/motion/evolve.wgsl`,
//! `trajectory.wgsl`, `shaders/query/ball_cushion.wgsl`, `ball_circle.wgsl`,
//! `ball_pocket.wgsl`, `ball_ball.wgsl`'s simulator part, `bounds.wgsl`) run on the GPU in f64 and compared with their Rust twins on random
//! ball states of every motion state on the 9-ft table: the state after τ (`evolve`, τ up
//! to past the ball's rest), the next transition, the trajectory polynomial, and the time
//! to every straight cushion, jaw and pocket with the box tests that rule them out, and
//! the time until two balls collide with their boxes' test.
//!
//! The GPU's f64 need not round as the CPU does (Mesa's lavapipe rounds `fma` twice and
//! re-associates sums; the polyfills are within 2 ulp of std), so values are compared
//! with tolerances: states and paths to a relative 1e-12 (plus 1e-15 absolute), event
//! times to a relative 1e-9, "never" to "never". The largest differences are printed.
//!
//! Without an f64 adapter the test prints why it skips (`common::kernel`).

mod common;

use common::kernel::{F64Kernels, close, source};
use kisstime::MotionState;
use kisstime::model::ball_state::BallState;
use kisstime::model::sim_params::BallParams;
use kisstime::model::table::Table;
use kisstime::model::vec3::Vec3;
use kisstime::motion::evolve::{TransitionKind, evolve, next_transition};
use kisstime::motion::trajectory::trajectory;
use kisstime::query::ball_ball::ball_ball_time;
use kisstime::query::ball_circle::circle_crossing;
use kisstime::query::ball_cushion::ball_linear_cushion_time;
use kisstime::query::ball_pocket::ball_pocket_time;
use kisstime::query::bounds::{box_outside_circle, box_outside_extent, boxes_apart, path_box};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;

/// The twin files, in the order they build on each other.
const FILES: [&str; 16] = [
    "model/vec2.wgsl",
    "model/ball.wgsl",
    "model/params.wgsl",
    "model/vec3.wgsl",
    "model/sim_params.wgsl",
    "model/ball_state.wgsl",
    "model/table.wgsl",
    "motion/path.wgsl",
    "motion/evolve.wgsl",
    "motion/trajectory.wgsl",
    "query/roots.wgsl",
    "query/ball_ball.wgsl",
    "query/bounds.wgsl",
    "query/ball_circle.wgsl",
    "query/ball_cushion.wgsl",
    "query/ball_pocket.wgsl",
];

/// Reals per ball state in `xs`: r, v, w, s, t.
const STATE: usize = 11;
/// Reals per item in `xs`: kind (0 straight cushion, 1 jaw, 2 pocket), then a straight
/// cushion's p1, p2, direction, lx, ly, l0, or a circle's centre and radius (and depth).
const ITEM: usize = 11;

const ENTRY: &str = r#"
// pooltool's default ball parameters (BallParams::default()).
fn test_params() -> BallParams {
    let r: real = 0.028575;
    return BallParams(0.170097, r, 0.2, 0.01, 10.0 * 2.0 / 5.0 / 9.0 * r, 0.05, 0.95, 0.85, 0.2, 9.81);
}

fn load_state(at: u32) -> BallState {
    return BallState(
        real3(xs[at], xs[at + 1u], xs[at + 2u]),
        real3(xs[at + 3u], xs[at + 4u], xs[at + 5u]),
        real3(xs[at + 6u], xs[at + 7u], xs[at + 8u]),
        u32(xs[at + 9u]),
        xs[at + 10u],
    );
}

// Per case (STATE reals and τ in): the state after τ (r, v, w), the next transition
// (τ, kind), the trajectory (a, b, c, horizon): 18 reals out.
@compute @workgroup_size(64)
fn motion_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&xs) / 12u {
        return;
    }
    let b = load_state(12u * i);
    let tau = xs[12u * i + 11u];
    let p = test_params();
    let e = evolve(b, tau, p);
    let o = 18u * i;
    ys[o] = e.r.x; ys[o + 1u] = e.r.y; ys[o + 2u] = e.r.z;
    ys[o + 3u] = e.v.x; ys[o + 4u] = e.v.y; ys[o + 5u] = e.v.z;
    ys[o + 6u] = e.w.x; ys[o + 7u] = e.w.y; ys[o + 8u] = e.w.z;
    let n = next_transition(b, p);
    ys[o + 9u] = n.x; ys[o + 10u] = n.y;
    let path = trajectory(b, p);
    ys[o + 11u] = path.a.x; ys[o + 12u] = path.a.y;
    ys[o + 13u] = path.b.x; ys[o + 14u] = path.b.y;
    ys[o + 15u] = path.c.x; ys[o + 16u] = path.c.y;
    ys[o + 17u] = path.horizon;
}

// Per case (two STATEs in): ball_ball_time, the first ball's path box (lo, hi) and whether
// the two boxes are apart by more than 2R (1 or 0): 6 reals out.
@compute @workgroup_size(64)
fn pairs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&xs) / 22u {
        return;
    }
    let b1 = load_state(22u * i);
    let b2 = load_state(22u * i + 11u);
    let p = test_params();
    let o = 6u * i;
    ys[o] = ball_ball_time(b1, b2, p);
    let box1 = path_box(trajectory(b1, p));
    let box2 = path_box(trajectory(b2, p));
    ys[o + 1u] = box1.lo.x; ys[o + 2u] = box1.lo.y;
    ys[o + 3u] = box1.hi.x; ys[o + 4u] = box1.hi.y;
    ys[o + 5u] = select(real(0.0), real(1.0), boxes_apart(box1, box2, 2.0 * p.r));
}

// Per case (STATE + ITEM reals in): the time to the item, and whether the ball's path box
// is outside the item (box_outside_extent, or box_outside_circle with the radius the
// simulator uses: jaw + R, pocket) as 1 or 0: 2 reals out.
@compute @workgroup_size(64)
fn items_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&xs) / 22u {
        return;
    }
    let b = load_state(22u * i);
    let at = 22u * i + 11u;
    let p = test_params();
    let kind = u32(xs[at]);
    let bx = path_box(trajectory(b, p));
    if kind == 0u {
        let seg = LinearCushion(
            real3(xs[at + 1u], xs[at + 2u], xs[at + 3u]),
            real3(xs[at + 4u], xs[at + 5u], xs[at + 6u]),
            u32(xs[at + 7u]),
            xs[at + 8u], xs[at + 9u], xs[at + 10u],
        );
        ys[2u * i] = ball_linear_cushion_time(b, seg, p);
        ys[2u * i + 1u] = select(real(0.0), real(1.0), box_outside_extent(bx, seg));
    } else if kind == 1u {
        let seg = CircularCushion(real3(xs[at + 1u], xs[at + 2u], xs[at + 3u]), xs[at + 4u]);
        ys[2u * i] = ball_circular_cushion_time(b, seg, p);
        let c = real2(seg.center.x, seg.center.y);
        ys[2u * i + 1u] = select(real(0.0), real(1.0), box_outside_circle(bx, c, seg.radius + p.r));
    } else {
        let pocket = Pocket(real3(xs[at + 1u], xs[at + 2u], xs[at + 3u]), xs[at + 4u], xs[at + 5u]);
        ys[2u * i] = ball_pocket_time(b, pocket, p);
        let c = real2(pocket.center.x, pocket.center.y);
        ys[2u * i + 1u] = select(real(0.0), real(1.0), box_outside_circle(bx, c, pocket.radius));
    }
}
"#;

/// Random ball states of every motion state on the 9-ft table's surface.
fn random_states(n: usize, seed: u64) -> Vec<BallState> {
    let p = BallParams::default();
    let mut rng = Pcg64::seed_from_u64(seed);
    (0..n)
        .map(|k| {
            let x = rng.random_range(p.r..1.27 - p.r);
            let y = rng.random_range(p.r..2.54 - p.r);
            let speed = 10f64.powf(rng.random_range(-3.0..1.0));
            let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let v = Vec3::new(speed * a.cos(), speed * a.sin(), 0.0);
            let spin: [f64; 3] = std::array::from_fn(|_| rng.random_range(-150.0..150.0));
            let (s, v, w) = match k % 5 {
                0 | 1 => (
                    MotionState::Sliding,
                    v,
                    Vec3::new(spin[0], spin[1], spin[2]),
                ),
                2 => (
                    MotionState::Rolling,
                    v,
                    Vec3::new(-v.y / p.r, v.x / p.r, rng.random_range(-50.0..50.0)),
                ),
                3 => (
                    MotionState::Spinning,
                    Vec3::ZERO,
                    Vec3::new(0.0, 0.0, rng.random_range(-80.0..80.0)),
                ),
                _ => (MotionState::Stationary, Vec3::ZERO, Vec3::ZERO),
            };
            BallState {
                r: Vec3::new(x, y, p.r),
                v,
                w,
                s,
                t: rng.random_range(0.0..3.0),
            }
        })
        .collect()
}

fn push_state(xs: &mut Vec<f64>, b: &BallState) {
    xs.extend([
        b.r.x, b.r.y, b.r.z, b.v.x, b.v.y, b.v.z, b.w.x, b.w.y, b.w.z,
    ]);
    xs.extend([b.s as u32 as f64, b.t]);
}

fn transition_code(k: TransitionKind) -> f64 {
    match k {
        TransitionKind::SlidingRolling => 0.0,
        TransitionKind::RollingSpinning => 1.0,
        TransitionKind::RollingStationary => 2.0,
        TransitionKind::SpinningStationary => 3.0,
    }
}

/// The GPU's "never" for the CPU's ∞.
fn same_time(gpu: f64, cpu: f64, rtol: f64) -> bool {
    if cpu.is_infinite() {
        gpu >= 1e300
    } else {
        close(gpu, cpu, rtol, 1e-15)
    }
}

#[test]
fn motion_twins_match_the_rust_twins() {
    let name = "gpu_sim_twins::motion";
    let Some(k) = F64Kernels::open(name) else {
        return;
    };
    let p = BallParams::default();
    k.pipeline(&source("f32", &FILES, ENTRY), "motion_main", "f32 motion");
    let pipe = k.pipeline(&source("f64", &FILES, ENTRY), "motion_main", "f64 motion");
    let states = random_states(4000, 17);
    let mut rng = Pcg64::seed_from_u64(3);
    let mut xs = Vec::new();
    let mut taus = Vec::new();
    for b in &states {
        push_state(&mut xs, b);
        // within the first phase, across transitions, past the rest, and 0
        let end = next_transition(b, &p).map_or(1.0, |(t, _)| t);
        let tau = match rng.random_range(0..4) {
            0 => 0.0,
            1 => end * rng.random_range(0.0..1.0),
            2 => end * rng.random_range(1.0..3.0),
            _ => rng.random_range(0.0..40.0),
        };
        xs.push(tau);
        taus.push(tau);
    }
    let ys = k.run(&pipe, &xs, 18 * states.len(), states.len());
    let mut problems = Vec::new();
    let mut worst = 0f64;
    for (i, (b, &tau)) in states.iter().zip(&taus).enumerate() {
        let e = evolve(b, tau, &p);
        let path = trajectory(b, &p);
        let (t_next, kind) =
            next_transition(b, &p).map_or((f64::INFINITY, 0.0), |(t, k)| (t, transition_code(k)));
        let cpu = [
            e.r.x,
            e.r.y,
            e.r.z,
            e.v.x,
            e.v.y,
            e.v.z,
            e.w.x,
            e.w.y,
            e.w.z,
            t_next,
            kind,
            path.a.x,
            path.a.y,
            path.b.x,
            path.b.y,
            path.c.x,
            path.c.y,
            path.horizon,
        ];
        let gpu = &ys[18 * i..18 * i + 18];
        for (c, (&g, &want)) in gpu.iter().zip(&cpu).enumerate() {
            let ok = if c == 9 || c == 17 {
                same_time(g, want, 1e-12)
            } else {
                close(g, want, 1e-12, 1e-15)
            };
            if want.is_finite() {
                worst = worst.max((g - want).abs() / want.abs().max(1e-3));
            }
            if !ok && problems.len() < 20 {
                problems.push(format!(
                    "case {i} ({:?}, τ = {tau}): value {c}: GPU {g:e}, Rust {want:e}",
                    b.s
                ));
            }
        }
    }
    println!(
        "{name}: {} states; largest difference {worst:.2e} (relative, or absolute below 1e-3)",
        states.len()
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn detection_twins_match_the_rust_twins() {
    let name = "gpu_sim_twins::detection";
    let Some(k) = F64Kernels::open(name) else {
        return;
    };
    let p = BallParams::default();
    let table = Table::nine_foot();
    k.pipeline(&source("f32", &FILES, ENTRY), "items_main", "f32 detection");
    let pipe = k.pipeline(&source("f64", &FILES, ENTRY), "items_main", "f64 detection");
    let mut states = random_states(600, 29);
    // balls inside each pocket's circle, moving out of it (finding 32: the first crossing
    // is the exit, found by first_exit)
    for pk in &table.pockets {
        let (dx, dy) = (0.635 - pk.center.x, 1.27 - pk.center.y);
        let norm = (dx * dx + dy * dy).sqrt();
        let (ux, uy) = (dx / norm, dy / norm);
        states.push(BallState {
            r: Vec3::new(
                pk.center.x + 0.5 * pk.radius * ux,
                pk.center.y + 0.5 * pk.radius * uy,
                p.r,
            ),
            v: Vec3::new(1.5 * ux - 0.3 * uy, 1.5 * uy + 0.3 * ux, 0.0),
            w: Vec3::new(20.0, -10.0, 5.0),
            s: MotionState::Sliding,
            t: 0.0,
        });
    }
    let mut xs = Vec::new();
    let mut cpu = Vec::new();
    for b in &states {
        let bx = path_box(&trajectory(b, &p));
        for seg in &table.linear {
            push_state(&mut xs, b);
            xs.extend([
                0.0, seg.p1.x, seg.p1.y, seg.p1.z, seg.p2.x, seg.p2.y, seg.p2.z,
            ]);
            xs.extend([seg.direction as f64, seg.lx, seg.ly, seg.l0]);
            let outside = box_outside_extent(&bx, seg);
            cpu.push(("cushion", ball_linear_cushion_time(b, seg, &p), outside));
        }
        for jaw in &table.circular {
            push_state(&mut xs, b);
            xs.extend([1.0, jaw.center.x, jaw.center.y, jaw.center.z, jaw.radius]);
            xs.extend([0.0; 6]);
            let t = if b.translating() {
                let c = kisstime::model::Vec2::new(jaw.center.x, jaw.center.y);
                circle_crossing(&trajectory(b, &p), c, jaw.radius + p.r)
            } else {
                f64::INFINITY
            };
            let c = kisstime::model::Vec2::new(jaw.center.x, jaw.center.y);
            cpu.push(("jaw", t, box_outside_circle(&bx, c, jaw.radius + p.r)));
        }
        for pk in &table.pockets {
            push_state(&mut xs, b);
            xs.extend([
                2.0,
                pk.center.x,
                pk.center.y,
                pk.center.z,
                pk.radius,
                pk.depth,
            ]);
            xs.extend([0.0; 5]);
            let c = kisstime::model::Vec2::new(pk.center.x, pk.center.y);
            cpu.push((
                "pocket",
                ball_pocket_time(b, pk, &p),
                box_outside_circle(&bx, c, pk.radius),
            ));
        }
    }
    assert_eq!(xs.len(), cpu.len() * (STATE + ITEM));
    let ys = k.run(&pipe, &xs, 2 * cpu.len(), cpu.len());
    let mut problems = Vec::new();
    let (mut hits, mut worst, mut outside) = (0, 0f64, 0);
    for (i, &(what, want, out)) in cpu.iter().enumerate() {
        let g = ys[2 * i];
        outside += usize::from(out);
        if (ys[2 * i + 1] == 1.0) != out && problems.len() < 20 {
            problems.push(format!(
                "ball {} {what} {}: box test GPU {}, Rust {out}",
                i / 36,
                i % 36,
                ys[2 * i + 1]
            ));
        }
        if want.is_finite() {
            hits += 1;
            worst = worst.max((g - want).abs() / want.max(1e-3));
        }
        if !same_time(g, want, 1e-9) && problems.len() < 20 {
            problems.push(format!(
                "ball {} {what} {}: GPU {g:e}, Rust {want:e}",
                i / 36,
                i % 36
            ));
        }
    }
    println!(
        "{name}: {} ball-item pairs, {hits} with a time, {outside} ruled out by the box; largest difference {worst:.2e}",
        cpu.len()
    );
    let exits = cpu[cpu.len() - 6 * 36..]
        .iter()
        .filter(|&&(what, t, _)| what == "pocket" && t.is_finite())
        .count();
    assert!(
        exits >= 6,
        "every ball inside a pocket's circle leaves it: {exits}"
    );
    assert!(outside > cpu.len() / 2, "the box tests rule most items out");
    assert!(hits > 300, "the cases reach cushions, jaws and pockets");
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn pair_twins_match_the_rust_twins() {
    let name = "gpu_sim_twins::pairs";
    let Some(k) = F64Kernels::open(name) else {
        return;
    };
    let p = BallParams::default();
    k.pipeline(&source("f32", &FILES, ENTRY), "pairs_main", "f32 pairs");
    let pipe = k.pipeline(&source("f64", &FILES, ENTRY), "pairs_main", "f64 pairs");
    // the second ball 0 to 0.3 m beyond touching the first (one in ten overlapping it), in
    // any state
    let firsts = random_states(3000, 41);
    let seconds = random_states(3000, 43);
    let mut rng = Pcg64::seed_from_u64(5);
    let mut pairs = Vec::new();
    let mut xs = Vec::new();
    for (n, (b1, b2)) in firsts.iter().zip(&seconds).enumerate() {
        let d = match n % 10 {
            0 => 2.0 * p.r - rng.random_range(1e-7..1e-4),
            _ => 2.0 * p.r + rng.random_range(0.0..0.3),
        };
        let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
        let b2 = BallState {
            r: Vec3::new(b1.r.x + d * a.cos(), b1.r.y + d * a.sin(), p.r),
            ..*b2
        };
        push_state(&mut xs, b1);
        push_state(&mut xs, &b2);
        pairs.push((*b1, b2));
    }
    // exactly touching as pooltool computes it (FUZZING.md, finding 31), the struck ball
    // moving apart: "now" on both
    let touching = BallState::at_rest(0.28262233721207614, 0.23412908741139543, p.r);
    let struck = BallState {
        v: Vec3::new(-3.3026151662877387e-10, -2.5942644950186135e-10, 0.0),
        w: Vec3::new(1e-8, -1e-8, 5e-9),
        s: MotionState::Sliding,
        ..BallState::at_rest(0.2363870159835479, 0.2005371602428806, p.r)
    };
    assert_eq!(ball_ball_time(&touching, &struck, &p), 0.0);
    push_state(&mut xs, &touching);
    push_state(&mut xs, &struck);
    pairs.push((touching, struck));
    let ys = k.run(&pipe, &xs, 6 * pairs.len(), pairs.len());
    let mut problems = Vec::new();
    let (mut hits, mut now, mut apart, mut worst) = (0, 0, 0, 0f64);
    for (i, (b1, b2)) in pairs.iter().enumerate() {
        let g = &ys[6 * i..6 * i + 6];
        let t = ball_ball_time(b1, b2, &p);
        let (box1, box2) = (path_box(&trajectory(b1, &p)), path_box(&trajectory(b2, &p)));
        let far = boxes_apart(&box1, &box2, 2.0 * p.r);
        hits += usize::from(t.is_finite() && t > 0.0);
        now += usize::from(t == 0.0);
        apart += usize::from(far);
        if t.is_finite() {
            worst = worst.max((g[0] - t).abs() / t.max(1e-3));
        }
        let cpu_box = [box1.lo.x, box1.lo.y, box1.hi.x, box1.hi.y];
        let box_ok = g[1..5]
            .iter()
            .zip(&cpu_box)
            .all(|(&a, &b)| close(a, b, 1e-12, 1e-15));
        if (!same_time(g[0], t, 1e-9) || !box_ok || (g[5] == 1.0) != far) && problems.len() < 20 {
            problems.push(format!(
                "pair {i} ({:?}, {:?}): GPU {:?}, Rust {t:e} {cpu_box:?} {far}",
                b1.s, b2.s, g
            ));
        }
    }
    println!(
        "{name}: {} pairs, {hits} collide later, {now} now, {apart} with boxes apart; largest time difference {worst:.2e}",
        pairs.len()
    );
    assert!(
        hits > 100 && now > 10 && apart > 100,
        "the cases cover every branch"
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
