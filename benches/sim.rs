//! Whole-shot simulation throughput on the full-shot reference set
//! (`data/fullshots`: shots 0–99 are breaks, 100–299 ordinary shots).
//!
//! `cargo bench --bench sim`. For breaks and for ordinary shots separately:
//! - `1 thread`: every shot of the group in turn through one [`EventLoop`];
//! - `2 threads`: [`COPIES`] copies of the group over a 2-thread Rayon pool, one
//!   `EventLoop` per worker (`par_iter().map_init`).
//!
//! Criterion's "elem/s" are shots/s; the events per shot of each group are printed once
//! at the start, so events/s = shots/s × events per shot. pooltool 0.6.0 on this 2-core
//! machine: ~30 ordinary shots/s, ~3.7 breaks/s (issue 13). Targets: ≥ 10,000 ordinary
//! shots/s and ≥ 1,000 breaks/s on 2 cores.
//!
//! `study/*`: the built-in shot study ([`StudyConfig::builtin`], 8 balls, ~12.6 events a
//! sample), [`STUDY_SAMPLES`] noisy samples to rest and to the first contact, on 1 and 2
//! threads; "elem/s" are samples/s. pooltool 0.6.0 runs the same shot at 193 samples/s to
//! rest (`data/studies/README.md`). Target (issue 14): ≥ 20,000 samples/s on 2 threads.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use kisstime::io::shot_set::{Shot, read_shots, read_table};
use kisstime::simulate::{EventLoop, Limits, SimParams, Table};
use kisstime::study::{RunOptions, StudyConfig, Until, run_study};
use rayon::prelude::*;
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

/// How many copies of a group the 2-thread batch simulates.
const COPIES: usize = 8;

/// Runs one shot to rest in `lp`; returns its number of events.
fn run_shot(lp: &mut EventLoop, s: &Shot) -> usize {
    lp.reset(&s.balls, Some((s.cue, s.strike))).unwrap();
    let mut n = 0;
    while lp.step().is_some() {
        n += 1;
    }
    n
}

/// Every shot in turn through one loop: the total number of events.
fn serial(table: &Table, params: SimParams, shots: &[Shot]) -> usize {
    let mut lp = EventLoop::new(table, params, Limits::default(), 16).unwrap();
    shots.iter().map(|s| run_shot(&mut lp, s)).sum()
}

/// The shots on the current Rayon pool, one loop per worker: the total number of events.
fn parallel(table: &Table, params: SimParams, shots: &[&Shot]) -> usize {
    shots
        .par_iter()
        .map_init(
            || EventLoop::new(table, params, Limits::default(), 16).unwrap(),
            |lp, s| run_shot(lp, s),
        )
        .sum()
}

fn sim(c: &mut Criterion) {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/fullshots"));
    let params = SimParams::default();
    let table = read_table(dir).unwrap();
    let shots = read_shots(dir, params.ball.r).unwrap();
    let (breaks, ordinary): (Vec<Shot>, Vec<Shot>) = shots.into_iter().partition(|s| s.shot < 100);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    for (name, group_shots) in [("breaks", &breaks), ("ordinary", &ordinary)] {
        let events = serial(&table, params, group_shots);
        let n = group_shots.len();
        eprintln!(
            "sim/{name}: {n} shots, {events} events, {:.1} events per shot",
            events as f64 / n as f64
        );
        let mut group = c.benchmark_group(format!("sim/{name}"));
        group.sample_size(10);
        group.measurement_time(Duration::from_secs(4));
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function("1 thread", |b| {
            b.iter(|| serial(&table, params, black_box(group_shots)))
        });
        let copies: Vec<&Shot> = (0..COPIES).flat_map(|_| group_shots.iter()).collect();
        group.throughput(Throughput::Elements(copies.len() as u64));
        group.bench_function("2 threads", |b| {
            b.iter(|| pool.install(|| parallel(&table, params, black_box(&copies))))
        });
        group.finish();
    }
}

/// Samples per run of the study benchmark.
const STUDY_SAMPLES: usize = 4_000;

fn study(c: &mut Criterion) {
    let config = StudyConfig::builtin();
    let sigma = config.sigma();
    let mut group = c.benchmark_group("study");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(4));
    group.throughput(Throughput::Elements(STUDY_SAMPLES as u64));
    for (until, name) in [
        (Until::Rest, "to rest"),
        (Until::FirstContact, "first contact"),
    ] {
        let options = RunOptions {
            until,
            ..RunOptions::default()
        };
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let label = format!(
                "{name}, {threads} thread{}",
                if threads > 1 { "s" } else { "" }
            );
            group.bench_function(label, |b| {
                b.iter(|| {
                    pool.install(|| {
                        run_study(&config, &sigma, STUDY_SAMPLES, 42, &options, &mut |_, _| {})
                            .unwrap()
                            .len()
                    })
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, sim, study);
criterion_main!(benches);
