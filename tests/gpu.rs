//! The GPU path: the corpus at the f32 tier (and the f64 tier where the adapter offers
//! `SHADER_F64`), GPU against CPU on large random batches, chunking, and the fallback.
//! Without a GPU these tests print why they skip; with `KISSTIME_REQUIRE_GPU=1` (CI, on
//! Mesa's lavapipe) a missing adapter is a failure.

mod common;

use common::{Tier, corpus, corpus_batch, gpu_or_skip};
use kisstime::Precision;

fn corpus_on_gpu(precision: Precision, tier: Tier, offset: (f64, f64)) {
    let name = format!("corpus_{}_offset_{:?}", precision.name(), offset);
    let Some(mut gpu) = gpu_or_skip(precision, &name) else {
        return;
    };
    let cases: Vec<_> = corpus()
        .iter()
        .map(|c| c.translated(offset.0, offset.1))
        .collect();
    let (batch, params) = corpus_batch(&cases);
    let got = gpu.pair_times(&batch, &params).unwrap();
    assert_eq!(got.len(), cases.len());
    let mut failures = Vec::new();
    let mut excused = 0;
    for (case, c) in cases.iter().zip(&got) {
        if case.margin.abs() < 1e-5 {
            excused += 1;
        }
        if let Err(why) = case.check(c.t, c.status, tier) {
            failures.push(format!(
                "{} [{}, {}]: {why}",
                case.id, case.category, case.label
            ));
        }
    }
    println!(
        "{name}: {} of {} pass the {tier:?} tier ({excused} with margin < 1e-5 m)",
        cases.len() - failures.len(),
        cases.len()
    );
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn corpus_gpu_f32_passes_the_f32_tier() {
    corpus_on_gpu(Precision::F32, Tier::F32, (0.0, 0.0));
}

#[test]
fn corpus_gpu_f32_passes_the_f32_tier_far_from_the_origin() {
    corpus_on_gpu(Precision::F32, Tier::F32, (1000.0, -1000.0));
    corpus_on_gpu(Precision::F32, Tier::F32, (-1000.0, 1000.0));
}

#[test]
fn corpus_gpu_f64_passes_the_f64_tier() {
    corpus_on_gpu(Precision::F64, Tier::F64, (0.0, 0.0));
    corpus_on_gpu(Precision::F64, Tier::F64, (1000.0, 1000.0));
}

use kisstime::compare::{compare_pairs, next_disagreements, time_agrees};
use kisstime::gpu::Fault;
use kisstime::workload::{Workload, generate};
use kisstime::{
    AutoRule, Backend, Batch, Engine, Error, GpuEngine, Params, RelPath, Status, ball_path,
    next_from_pairs,
};

/// The large random batches: ~120k pairs of realistic and hard tables.
fn random_batches(params: &Params) -> Vec<(Workload, Batch)> {
    vec![
        (
            Workload::Midshot,
            generate(Workload::Midshot, 300, 16, 11, params),
        ),
        (
            Workload::Spread,
            generate(Workload::Spread, 300, 16, 12, params),
        ),
        (
            Workload::Worst,
            generate(Workload::Worst, 300, 16, 13, params),
        ),
        (
            Workload::Rack,
            generate(Workload::Rack, 100, 16, 14, params),
        ),
    ]
}

fn gpu_matches_cpu_on_random_batches(precision: Precision) {
    let name = format!("gpu_vs_cpu_{}", precision.name());
    let Some(mut gpu) = gpu_or_skip(precision, &name) else {
        return;
    };
    let params = Params::default();
    for (scenario, batch) in random_batches(&params) {
        let cpu = kisstime::pair_times(&batch, &params).unwrap();
        let got = gpu.pair_times(&batch, &params).unwrap();
        assert_eq!(got.len(), cpu.len());
        let mut bad = Vec::new();
        let agreement = compare_pairs(&batch, &params, &cpu, &got, precision, |k, i, j, c, g| {
            bad.push(format!(
                "table {} pair ({i},{j}): cpu {c:?} vs gpu {g:?}",
                batch.table_id(k)
            ))
        });
        let hits = cpu.iter().filter(|c| c.status == Status::Hit).count();
        println!(
            "{name} {}: {} pairs ({hits} hits), {} outside the tier, {} excused as grazes",
            scenario.name(),
            agreement.pairs,
            agreement.outside_tier,
            agreement.excused
        );
        assert_eq!(agreement.pairs, cpu.len());
        assert!(bad.is_empty(), "{}:\n{}", scenario.name(), bad.join("\n"));

        // next collision: the GPU reduction equals the GPU pairs' minimum exactly, and
        // agrees with the CPU in pair (or picks a pair tied within the tier) and time
        let next_gpu = gpu.next_collisions(&batch, &params).unwrap();
        assert_eq!(
            next_gpu,
            next_from_pairs(&batch, &got),
            "{}",
            scenario.name()
        );
        let next_cpu = kisstime::next_collisions(&batch, &params).unwrap();
        // the horizon is the host's f64 on both
        for (c, g) in next_cpu.iter().zip(&next_gpu) {
            assert_eq!(c.horizon, g.horizon, "table {}", c.table);
        }
        let unexplained =
            next_disagreements(&batch, &params, precision, &cpu, &next_cpu, &next_gpu);
        assert_eq!(
            unexplained,
            0,
            "{}: next collisions differ",
            scenario.name()
        );
        for (k, (c, g)) in next_cpu.iter().zip(&next_gpu).enumerate() {
            if c.pair == g.pair && c.status == Status::Hit && g.status == Status::Hit {
                let ids = batch.ball_ids(k);
                let (i, j) = c.pair.unwrap();
                let i = ids.iter().position(|&b| b == i).unwrap();
                let j = ids.iter().position(|&b| b == j).unwrap();
                let b = batch.balls(k);
                let rel = RelPath::between(&ball_path(&b[i], &params), &ball_path(&b[j], &params));
                assert!(
                    time_agrees(&rel, c.t, g.t, precision),
                    "table {k}: {c:?} vs {g:?}"
                );
            }
        }
    }
}

#[test]
fn gpu_f32_matches_cpu_on_random_batches() {
    gpu_matches_cpu_on_random_batches(Precision::F32);
}

#[test]
fn gpu_f64_matches_cpu_on_random_batches() {
    gpu_matches_cpu_on_random_batches(Precision::F64);
}

#[test]
fn chunked_batches_give_the_same_answers_as_one_chunk() {
    let Some(mut gpu) = gpu_or_skip(Precision::F32, "chunking") else {
        return;
    };
    let params = Params::default();
    // tables of different sizes, one larger than the workgroup's path cache
    let mut batch = generate(Workload::Spread, 50, 9, 3, &params);
    let extra = generate(Workload::Midshot, 20, 40, 4, &params);
    for k in 0..extra.num_tables() {
        let balls = extra
            .ball_ids(k)
            .iter()
            .copied()
            .zip(extra.balls(k).iter().copied());
        batch.push_table(1000 + k as i64, balls).unwrap();
    }
    let big = generate(Workload::Worst, 1, 150, 5, &params);
    batch
        .push_table(
            5000,
            big.ball_ids(0)
                .iter()
                .copied()
                .zip(big.balls(0).iter().copied()),
        )
        .unwrap();
    let whole_pairs = gpu.pair_times(&batch, &params).unwrap();
    let whole_next = gpu.next_collisions(&batch, &params).unwrap();
    let limits = gpu.chunk_limits();
    gpu.set_chunk_limits(kisstime::gpu::ChunkLimits {
        tables: 7,
        balls: 200,
        pairs: 11_500,
    });
    assert_eq!(gpu.chunk_limits().tables, 7);
    let chunked_pairs = gpu.pair_times(&batch, &params).unwrap();
    let chunked_next = gpu.next_collisions(&batch, &params).unwrap();
    assert_eq!(whole_pairs, chunked_pairs);
    assert_eq!(whole_next, chunked_next);
    assert!(limits.tables > 7);
    // the CPU agrees on the large table's next collision pair
    let cpu_next = kisstime::next_collisions(&batch, &params).unwrap();
    assert_eq!(cpu_next.len(), whole_next.len());
}

#[test]
fn a_failed_dispatch_is_an_error_on_gpu_and_redone_on_the_cpu_in_auto() {
    let params = Params::default();
    let batch = generate(Workload::Midshot, 40, 16, 8, &params);
    let cpu = kisstime::pair_times(&batch, &params).unwrap();
    let Some(mut gpu) = gpu_or_skip(Precision::F32, "failed_dispatch") else {
        return;
    };
    gpu.inject_fault(Fault::FailedDispatch);
    let err = gpu.pair_times(&batch, &params).unwrap_err();
    assert!(matches!(err, Error::Gpu(_)), "{err}");
    // the engine recovers for the next call
    let again = gpu.pair_times(&batch, &params).unwrap();
    assert_eq!(again.len(), cpu.len());

    let mut auto = Engine::with_rule(Backend::Auto, Precision::F32, AutoRule::AnyGpu).unwrap();
    auto.gpu()
        .expect("a GPU is there")
        .inject_fault(Fault::FailedDispatch);
    let got = auto.pair_times(&batch, &params).unwrap();
    assert_eq!(got, cpu, "redone on the CPU: bit-identical to the CPU");
    let notes = auto.take_notes();
    assert!(
        notes.iter().any(|n| n.contains("redone on the CPU")),
        "{notes:?}"
    );
}

#[test]
fn a_lost_device_is_an_error_on_gpu_and_redone_on_the_cpu_in_auto() {
    let params = Params::default();
    let batch = generate(Workload::Spread, 30, 8, 9, &params);
    let cpu_next = kisstime::next_collisions(&batch, &params).unwrap();
    let Some(mut gpu) = gpu_or_skip(Precision::F32, "device_lost") else {
        return;
    };
    gpu.inject_fault(Fault::DeviceLost);
    assert!(matches!(
        gpu.next_collisions(&batch, &params),
        Err(Error::Gpu(_))
    ));
    let mut auto = Engine::with_rule(Backend::Auto, Precision::F32, AutoRule::AnyGpu).unwrap();
    auto.gpu()
        .expect("a GPU is there")
        .inject_fault(Fault::DeviceLost);
    assert_eq!(auto.next_collisions(&batch, &params).unwrap(), cpu_next);
    assert!(!auto.take_notes().is_empty());
    assert!(auto.gpu().is_none(), "the CPU is used from then on");
}

/// A fault in the middle of a batch (chunks before it already answered): `gpu` reports an
/// error, `auto` redoes the whole batch on the CPU, bit-identical, and says so.
#[test]
fn a_fault_mid_batch_is_an_error_on_gpu_and_redone_on_the_cpu_in_auto() {
    let params = Params::default();
    let batch = generate(Workload::Spread, 60, 10, 12, &params);
    let cpu_pairs = kisstime::pair_times(&batch, &params).unwrap();
    let cpu_next = kisstime::next_collisions(&batch, &params).unwrap();
    let small = kisstime::gpu::ChunkLimits {
        tables: 10,
        balls: 1000,
        pairs: 1000,
    };
    for fault in [Fault::FailedDispatchAfter(2), Fault::DeviceLostAfter(3)] {
        let Some(mut gpu) = gpu_or_skip(Precision::F32, "fault_mid_batch") else {
            return;
        };
        gpu.set_chunk_limits(small);
        gpu.inject_fault(fault);
        let err = gpu.next_collisions(&batch, &params).unwrap_err();
        assert!(matches!(err, Error::Gpu(_)), "{fault:?}: {err}");

        let mut auto = Engine::with_rule(Backend::Auto, Precision::F32, AutoRule::AnyGpu).unwrap();
        let g = auto.gpu().expect("a GPU is there");
        g.set_chunk_limits(small);
        g.inject_fault(fault);
        assert_eq!(
            auto.pair_times(&batch, &params).unwrap(),
            cpu_pairs,
            "{fault:?}"
        );
        let notes = auto.take_notes();
        assert!(
            notes.iter().any(|n| n.contains("redone on the CPU")),
            "{fault:?}: {notes:?}"
        );
        assert!(auto.gpu().is_none(), "the CPU is used from then on");
        assert_eq!(auto.next_collisions(&batch, &params).unwrap(), cpu_next);
    }
}

#[test]
fn the_engine_is_reused_across_many_calls_and_buffers_grow() {
    let Some(mut gpu) = gpu_or_skip(Precision::F32, "reuse") else {
        return;
    };
    let params = Params::default();
    for (n, seed) in [(5, 1), (50, 2), (3, 3), (200, 4)] {
        let batch = generate(Workload::Midshot, n, 16, seed, &params);
        let got = gpu.next_collisions(&batch, &params).unwrap();
        let pairs = gpu.pair_times(&batch, &params).unwrap();
        assert_eq!(got, next_from_pairs(&batch, &pairs));
    }
    let _: &GpuEngine = &gpu;
}

/// 1,000,000 tables of 16 balls (120 M pairs) through the GPU's next collision, several
/// chunks deep, checked against the CPU on every 997th table. Long on a software driver:
/// `cargo test --release --test gpu -- --ignored million`.
#[test]
#[ignore = "long: 120 M pairs; run with --ignored"]
fn a_million_tables_of_16_balls() {
    let Some(mut gpu) = gpu_or_skip(Precision::F32, "million") else {
        return;
    };
    let params = Params::default();
    let batch = generate(Workload::Midshot, 1_000_000, 16, 99, &params);
    assert_eq!(batch.num_pairs(), 120_000_000);
    let clock = std::time::Instant::now();
    let next = gpu.next_collisions(&batch, &params).unwrap();
    let secs = clock.elapsed().as_secs_f64();
    println!(
        "million: {} tables, {:.1} s on the GPU ({:.2e} pairs/s), timings {:?}",
        next.len(),
        secs,
        120e6 / secs,
        gpu.timings()
    );
    assert_eq!(next.len(), 1_000_000);
    let mut sample = Batch::new();
    let mut picked = Vec::new();
    for k in (0..batch.num_tables()).step_by(997) {
        let balls = batch
            .ball_ids(k)
            .iter()
            .copied()
            .zip(batch.balls(k).iter().copied());
        sample.push_table(batch.table_id(k), balls).unwrap();
        picked.push(k);
    }
    let cpu = kisstime::next_collisions(&sample, &params).unwrap();
    for (c, &k) in cpu.iter().zip(&picked) {
        let g = next[k];
        assert_eq!(c.table, g.table);
        assert_eq!(c.pair, g.pair, "table {k}");
        assert!(
            (c.t - g.t).abs() <= 1e-5 + 1e-5 * c.t || c.pair.is_none(),
            "table {k}: {c:?} vs {g:?}"
        );
    }
}
