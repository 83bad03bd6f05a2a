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
