//! Seeded property tests of the whole-shot simulation: random valid tables and strikes
//! (seeded PCG from `tests/common/rng.rs`, so every case is reproducible from its seed), simulated
//! through the public entry point (`ShotEngine` on the CPU, events recorded), each run
//! checked by `kisstime::simulate::invariants::check_shot` (ball count, records, event
//! times, no overlap and every ball on the table at the end, no energy gained after the
//! strike, at rest unless cut). A ball that goes into or through a rail after touching it
//! while moving into it (`Invariant::RailTunnel`: pooltool's Q6, reproduced on purpose;
//! FUZZING.md, finding 7) is counted and printed, not failed. The short run is part of `cargo test`; the long one is
//! `#[ignore]`d, for by hand:
//!
//! ```sh
//! cargo test --release --test invariants -- --ignored --nocapture
//! ```
//!
//! A failure prints the seed and the shot's index; `shots_of(seed)` rebuilds the batch.
//! With a GPU (the adapter rule of the other GPU tests: `common::gpu_or_skip`), the same
//! shots also run on the GPU event loop in f64, whose runs must satisfy the invariants
//! too; how many of them give the CPU's events exactly is printed.

mod common;

use common::rng::TestRng;
use kisstime::MotionState;
use kisstime::engine::{Backend, Precision, ShotEngine};
use kisstime::gpu::{GpuRun, GpuShot, GpuSimulator};
use kisstime::simulate::invariants::{
    END_OVERLAP_TOLERANCE, Invariant, Margins, ShotRun, Violation, check_shot,
};
use kisstime::simulate::{BallState, CueStrike, Limits, SimParams, Table};

/// The table every generated shot is played on, its playing surface `w × l`.
fn table() -> (Table, f64, f64) {
    (Table::nine_foot(), 1.27, 2.54)
}

/// A random valid layout of 1 to 16 balls: each ball placed uniformly on the surface
/// (no overlap), frozen against an earlier one (centre distance exactly 2R, or 2R plus
/// 1e-12 to 1e-6 m), against a rail, or at a pocket's mouth; a position that overlaps
/// or leaves the surface is drawn again.
fn layout(rng: &mut TestRng, table: &Table, w: f64, l: f64, r: f64) -> Vec<BallState> {
    let n = 1 + rng.below(16);
    let mut balls: Vec<BallState> = Vec::with_capacity(n);
    while balls.len() < n {
        let (mut x, mut y) = (rng.range(r, w - r), rng.range(r, l - r));
        match rng.below(8) {
            0..=3 => {}
            4 | 5 if !balls.is_empty() => {
                let other = balls[rng.below(balls.len())];
                let gap = [0.0, 1e-12, 1e-9, 1e-6][rng.below(4)];
                let angle = std::f64::consts::TAU * rng.unit();
                x = other.r.x + (2.0 * r + gap) * angle.cos();
                y = other.r.y + (2.0 * r + gap) * angle.sin();
            }
            6 => match rng.below(4) {
                0 => x = r,
                1 => x = w - r,
                2 => y = r,
                _ => y = l - r,
            },
            _ => {
                let p = table.pockets[rng.below(table.pockets.len())];
                let angle = std::f64::consts::TAU * rng.unit();
                let d = (p.radius + r) * rng.unit().sqrt();
                x = p.center.x + d * angle.cos();
                y = p.center.y + d * angle.sin();
            }
        }
        let b = BallState::at_rest(x, y, r);
        let clear = balls.iter().all(|o| {
            let (dx, dy) = (o.r.x - x, o.r.y - y);
            (dx * dx + dy * dy).sqrt() >= 2.0 * r - 1e-12
        });
        let mut with = balls.clone();
        with.push(b);
        if clear && kisstime::simulate::check_layout(table, r, &with).is_ok() {
            balls.push(b);
        }
    }
    balls
}

/// A random valid strike: V0 in [0.2, 8] m/s, any aim, elevation 0–60°, the tip anywhere
/// within 0.9 R of the centre.
fn strike(rng: &mut TestRng, n: usize) -> (usize, CueStrike) {
    let rho = 0.9 * rng.unit().sqrt();
    let angle = std::f64::consts::TAU * rng.unit();
    let theta = if rng.below(3) == 0 {
        rng.range(0.0, 60.0)
    } else {
        rng.range(0.0, 5.0)
    };
    (
        rng.below(n),
        CueStrike {
            v0: rng.range(0.2, 8.0),
            phi: rng.range(0.0, 360.0),
            theta,
            a: rho * angle.cos(),
            b: rho * angle.sin(),
        },
    )
}

/// The shots of one seed.
fn shots_of(seed: u64, count: usize) -> Vec<GpuShot> {
    let (table, w, l) = table();
    let r = SimParams::default().ball.r;
    let mut rng = TestRng::new(seed);
    (0..count)
        .map(|_| {
            let balls = layout(&mut rng, &table, w, l, r);
            let s = strike(&mut rng, balls.len());
            GpuShot {
                balls,
                strike: Some(s),
            }
        })
        .collect()
}

/// The limits of the property runs: the defaults would never cut these shots, and a
/// bound keeps a pathological one from hanging the test.
const LIMITS: Limits = Limits {
    max_events: 20_000,
    max_time: 600.0,
};

fn check(
    table: &Table,
    params: &SimParams,
    shot: &GpuShot,
    run: &GpuRun,
) -> Result<Margins, Violation> {
    check_shot(
        table,
        params,
        &ShotRun {
            start: &shot.balls,
            strike: shot.strike,
            events: &run.events,
            end: &run.balls,
            outcome: run.outcome,
            limits: LIMITS,
        },
    )
}

/// Simulates `count` shots of each seed on the CPU and checks every run; returns the
/// deepest end overlap, the largest energy growth and replay error seen, the events, and
/// the runs that were cut.
fn run_seeds(seeds: std::ops::Range<u64>, count: usize) -> (Margins, usize, usize, usize) {
    let (table, _, _) = table();
    let params = SimParams::default();
    let mut engine = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let mut worst = Margins::default();
    let (mut events, mut cut, mut tunnels) = (0, 0, 0);
    for seed in seeds {
        let shots = shots_of(seed, count);
        let runs = engine
            .simulate(&table, params, LIMITS, &shots, true)
            .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        for (k, (shot, run)) in shots.iter().zip(&runs).enumerate() {
            let m = match check(&table, &params, shot, run) {
                Ok(m) => m,
                // finding 7, pooltool's Q6 reproduced on purpose: counted, not failed
                Err(v) if v.invariant == Invariant::RailTunnel => {
                    tunnels += 1;
                    continue;
                }
                Err(v) => panic!("seed {seed}, shot {k}: {v}\n{shot:?}"),
            };
            worst.deepest_overlap = worst.deepest_overlap.max(m.deepest_overlap);
            worst.energy_growth = worst.energy_growth.max(m.energy_growth);
            worst.replay_error = worst.replay_error.max(m.replay_error);
            events += run.events.len();
            cut += usize::from(run.outcome.cut.is_some());
        }
    }
    (worst, events, cut, tunnels)
}

#[test]
fn random_shots_keep_every_invariant() {
    let (worst, events, cut, tunnels) = run_seeds(0..4, 100);
    eprintln!(
        "400 shots, {events} events, {cut} cut, {tunnels} through a rail (Q6); deepest end \
         overlap {:e} m, largest energy growth {:e}, replay error {:e}",
        worst.deepest_overlap, worst.energy_growth, worst.replay_error
    );
    assert!(worst.deepest_overlap <= END_OVERLAP_TOLERANCE);
    assert_eq!(cut, 0);
}

/// The long run, by hand: 100 seeds of 200 shots (20,000 shots).
#[test]
#[ignore]
fn random_shots_keep_every_invariant_long() {
    let (worst, events, cut, tunnels) = run_seeds(1000..1100, 200);
    eprintln!(
        "20,000 shots, {events} events, {cut} cut, {tunnels} through a rail (Q6); deepest \
         end overlap {:e} m, largest energy growth {:e}, replay error {:e}",
        worst.deepest_overlap, worst.energy_growth, worst.replay_error
    );
}

/// A pocketed ball at the start stays pocketed and never takes part: a layout with some
/// balls already down (as in a game) keeps every invariant.
#[test]
fn shots_with_balls_already_pocketed_keep_every_invariant() {
    let (table, _, _) = table();
    let params = SimParams::default();
    let mut engine = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let mut shots = shots_of(77, 60);
    let mut rng = TestRng::new(78);
    for shot in &mut shots {
        let cue = shot.strike.map_or(0, |s| s.0);
        for (i, b) in shot.balls.iter_mut().enumerate() {
            if i != cue && rng.below(3) == 0 {
                let p = table.pockets[rng.below(table.pockets.len())];
                b.r = p.center;
                b.r.z = -p.depth;
                b.s = MotionState::Pocketed;
            }
        }
    }
    let runs = engine
        .simulate(&table, params, LIMITS, &shots, true)
        .unwrap();
    for (k, (shot, run)) in shots.iter().zip(&runs).enumerate() {
        if let Err(v) = check(&table, &params, shot, run)
            && v.invariant != Invariant::RailTunnel
        {
            panic!("shot {k}: {v}\n{shot:?}");
        }
    }
}

/// The checker itself catches what it is for: a ball moved off the table, a lost ball,
/// energy made at a collision, an event out of order, a run that stops while moving.
#[test]
fn the_checker_catches_broken_runs() {
    let (table, _, _) = table();
    let params = SimParams::default();
    let mut engine = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let shots = shots_of(5, 40);
    let runs = engine
        .simulate(&table, params, LIMITS, &shots, true)
        .unwrap();
    let (k, shot, run) = shots
        .iter()
        .zip(&runs)
        .enumerate()
        .map(|(k, (s, r))| (k, s, r))
        .find(|(_, _, r)| {
            r.events.len() > 4
                && r.events
                    .iter()
                    .any(|e| e.event.kind == kisstime::simulate::EventKind::BallBall)
        })
        .expect("a shot with a collision");
    check(&table, &params, shot, run).unwrap_or_else(|v| panic!("shot {k}: {v}"));
    let broken = |edit: &dyn Fn(&mut GpuRun)| {
        let mut bad = run.clone();
        edit(&mut bad);
        check(&table, &params, shot, &bad).unwrap_err()
    };
    let off = broken(&|r| {
        r.balls[0].r.x = 5.6;
        r.balls[0].r.y = -3.4;
        r.balls[0].s = MotionState::Stationary;
    });
    assert!(
        matches!(
            off.invariant,
            Invariant::Record | Invariant::OffTable | Invariant::RailTunnel
        ),
        "{off}"
    );
    let lost = broken(&|r| {
        r.balls.pop();
    });
    assert_eq!(lost.invariant, Invariant::BallCount, "{lost}");
    let b = run
        .events
        .iter()
        .position(|e| e.event.kind == kisstime::simulate::EventKind::BallBall)
        .unwrap();
    let energy = broken(&|r| {
        r.events[b].states[0].v = r.events[b].states[0].v * 3.0;
    });
    assert_eq!(energy.invariant, Invariant::Energy, "{energy}");
    assert_eq!(energy.event, Some(b), "{energy}");
    let order = broken(&|r| r.events[2].event.t = r.events[1].event.t - 1e-6);
    assert_eq!(
        (order.invariant, order.event),
        (Invariant::EventTime, Some(2)),
        "{order}"
    );
    let moving = broken(&|r| {
        r.balls[shot.strike.unwrap().0].v.x = 1.0;
    });
    assert!(
        matches!(moving.invariant, Invariant::Record | Invariant::NotAtRest),
        "{moving}"
    );
    // a run cut at the event limit says so; the same run claiming it was not cut does not
    // pass
    let limits = Limits {
        max_events: 3,
        max_time: 600.0,
    };
    let cut_runs = engine
        .simulate(&table, params, limits, std::slice::from_ref(shot), true)
        .unwrap();
    let mut cut = cut_runs[0].clone();
    fn as_run<'a>(shot: &'a GpuShot, r: &'a GpuRun, limits: Limits) -> ShotRun<'a> {
        ShotRun {
            start: &shot.balls,
            strike: shot.strike,
            events: &r.events,
            end: &r.balls,
            outcome: r.outcome,
            limits,
        }
    }
    check_shot(&table, &params, &as_run(shot, &cut, limits)).unwrap();
    cut.outcome.cut = None;
    let silent = check_shot(&table, &params, &as_run(shot, &cut, limits)).unwrap_err();
    assert_eq!(silent.invariant, Invariant::NotAtRest, "{silent}");
}

/// The GPU event loop in f64 on the same shots: its runs keep every invariant too; how
/// many give exactly the CPU's event sequence is printed (frozen balls make some breaks
/// chaotic, and a software GPU's f64 rounds differently in the last bits).
#[test]
fn gpu_runs_of_random_shots_keep_every_invariant() {
    let test = "gpu_runs_of_random_shots_keep_every_invariant";
    if common::gpu_or_skip(Precision::F64, test).is_none() {
        return;
    }
    let (table, _, _) = table();
    let params = SimParams::default();
    let shots = shots_of(11, 100);
    let mut cpu = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let cpu_runs = cpu.simulate(&table, params, LIMITS, &shots, true).unwrap();
    let mut gpu = GpuSimulator::new(Precision::F64).expect("the event loop builds");
    let gpu_runs = gpu
        .simulate(&table, params, LIMITS, &shots, true)
        .expect("the GPU runs");
    let mut same = 0;
    for (k, (shot, (g, c))) in shots.iter().zip(gpu_runs.iter().zip(&cpu_runs)).enumerate() {
        if let Err(v) = check(&table, &params, shot, g)
            && v.invariant != Invariant::RailTunnel
        {
            panic!("GPU, shot {k}: {v}");
        }
        let key = |r: &GpuRun| -> Vec<_> {
            r.events
                .iter()
                .map(|e| (e.event.kind, e.event.ball, e.event.other))
                .collect()
        };
        same += usize::from(key(g) == key(c));
    }
    eprintln!(
        "{test}: {same} of {} shots with the CPU's events",
        shots.len()
    );
}
