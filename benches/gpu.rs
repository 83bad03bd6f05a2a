//! GPU throughput in ball pairs per second, beside the CPU benches (`benches/cpu.rs`).
//!
//! `cargo bench --bench gpu`. For each precision the adapter offers and each workload
//! (`midshot`, `worst`; `KISSTIME_BENCH_TABLES` tables of 16 balls, default 10,000):
//! - `*_kernel`: the compute kernel alone, data resident on the device;
//! - `*_end_to_end`: upload, kernel, readback and conversion, as a caller sees it;
//!
//! for per-pair times (`pair_times`) and per-table next collision (`next_collisions`).
//! With no usable GPU it prints why and measures nothing. Mesa's software driver
//! (lavapipe) runs the kernels on the CPU: its figures say little about a real GPU.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use kisstime::Params;
use kisstime::Precision;
use kisstime::gpu::{GpuEngine, Kernel};
use kisstime::workload::{Workload, generate};
use std::hint::black_box;
use std::time::Duration;

fn gpu(c: &mut Criterion) {
    let params = Params::default();
    let tables: usize = std::env::var("KISSTIME_BENCH_TABLES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(10_000);
    for precision in [Precision::F32, Precision::F64] {
        let mut engine = match GpuEngine::new(precision) {
            Ok(e) => e,
            Err(e) => {
                eprintln!("gpu bench {}: skipped: {e}", precision.name());
                continue;
            }
        };
        eprintln!("gpu bench {}: {}", precision.name(), engine.adapter());
        for scenario in [Workload::Midshot, Workload::Worst] {
            let batch = generate(scenario, tables, 16, 42, &params);
            let mut group =
                c.benchmark_group(format!("gpu_{}/{}", precision.name(), scenario.name()));
            group.throughput(Throughput::Elements(batch.num_pairs() as u64));
            group.sample_size(10);
            group.measurement_time(Duration::from_secs(3));
            for (name, kernel) in [
                ("pair_times_kernel", Kernel::PairTimes),
                ("next_collisions_kernel", Kernel::NextCollisions),
            ] {
                group.bench_function(name, |b| {
                    b.iter_custom(|iters| {
                        engine.time_kernel(&batch, &params, kernel, iters).unwrap()
                    })
                });
            }
            group.bench_function("pair_times_end_to_end", |b| {
                b.iter(|| engine.pair_times(black_box(&batch), &params).unwrap())
            });
            group.bench_function("next_collisions_end_to_end", |b| {
                b.iter(|| engine.next_collisions(black_box(&batch), &params).unwrap())
            });
            group.finish();
        }
    }
}

criterion_group!(benches, gpu);
criterion_main!(benches);
