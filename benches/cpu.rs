//! CPU (Rayon, f64) throughput in ball pairs per second, on the built-in workloads.
//!
//! `cargo bench --bench cpu`. Criterion reports "elements/s": each element is one ball pair.
//! - `midshot`: 10,000 16-ball tables, a few balls moving and the rest still;
//! - `worst`: 10,000 16-ball tables with every ball moving inside a small square, so every
//!   pair needs the full solve.
//!
//! For each: `pair_times` (every pair's answer, written to an array) and
//! `next_collisions` (the per-table minimum, nothing per pair kept).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use kisstime::workload::{Workload, generate};
use kisstime::{Params, next_collisions, pair_times};
use std::hint::black_box;
use std::time::Duration;

fn cpu(c: &mut Criterion) {
    let params = Params::default();
    for scenario in [Workload::Midshot, Workload::Worst] {
        let batch = generate(scenario, 10_000, 16, 42, &params);
        let mut group = c.benchmark_group(format!("cpu_f64/{}", scenario.name()));
        group.throughput(Throughput::Elements(batch.num_pairs() as u64));
        group.sample_size(10);
        group.measurement_time(Duration::from_secs(3));
        group.bench_function("pair_times", |b| {
            b.iter(|| pair_times(black_box(&batch), &params).unwrap())
        });
        group.bench_function("next_collisions", |b| {
            b.iter(|| next_collisions(black_box(&batch), &params).unwrap())
        });
        group.finish();
    }
}

criterion_group!(benches, cpu);
criterion_main!(benches);
