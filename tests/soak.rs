//! Soak: 1,000,000 random tables through the CPU and the GPU, every table's next collision
//! compared under the tiers, with one engine of each kind reused throughout and memory held
//! flat after warm-up. Long (about two minutes on Mesa's software driver), so ignored by
//! default:
//!
//! ```sh
//! cargo test --release --test soak -- --ignored --nocapture
//! ```
//!
//! (with `VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json` and
//! `KISSTIME_REQUIRE_GPU=1` to run it on lavapipe, as in `.ci/run`).

mod common;

use common::gpu_or_skip;
use kisstime::compare::{next_disagreements, time_agrees};
use kisstime::workload::{Workload, generate};
use kisstime::{Params, Precision, RelPath, ball_path, next_collisions, pair_times};

/// Resident memory of this process in bytes (Linux), or 0 where unknown.
fn resident_bytes() -> u64 {
    std::fs::read_to_string("/proc/self/statm")
        .ok()
        .and_then(|s| s.split_whitespace().nth(1)?.parse::<u64>().ok())
        .map_or(0, |pages| pages * 4096)
}

#[test]
#[ignore = "long: 1e6 tables through CPU and GPU; run with --ignored"]
fn a_million_random_tables_agree_and_memory_stays_flat() {
    let Some(mut gpu) = gpu_or_skip(Precision::F32, "soak") else {
        return;
    };
    let params = Params::default();
    let scenarios = [
        Workload::Midshot,
        Workload::Spread,
        Workload::Rack,
        Workload::Worst,
    ];
    const ROUNDS: usize = 10;
    const TABLES: usize = 100_000;
    let mut warm = 0;
    let mut peak_after_warm = 0;
    let (mut tables, mut pairs, mut hits) = (0usize, 0usize, 0usize);
    let clock = std::time::Instant::now();
    for round in 0..ROUNDS {
        let scenario = scenarios[round % scenarios.len()];
        let batch = generate(scenario, TABLES, 16, 1000 + round as u64, &params);
        let ref_pairs = pair_times(&batch, &params).unwrap();
        let ref_next = next_collisions(&batch, &params).unwrap();
        let got = gpu.next_collisions(&batch, &params).unwrap();
        assert_eq!(got.len(), ref_next.len());
        let differ =
            next_disagreements(&batch, &params, Precision::F32, &ref_pairs, &ref_next, &got);
        assert_eq!(
            differ,
            0,
            "round {round} ({}): tables differ",
            scenario.name()
        );
        for (k, (r, g)) in ref_next.iter().zip(&got).enumerate() {
            assert!(!g.t.is_nan(), "table {k}: NaN");
            if let Some((i, j)) = r.pair
                && r.pair == g.pair
                && r.t > 0.0
            {
                let ids = batch.ball_ids(k);
                let at = |id| ids.iter().position(|&x| x == id).unwrap();
                let b = batch.balls(k);
                let rel = RelPath::between(
                    &ball_path(&b[at(i)], &params),
                    &ball_path(&b[at(j)], &params),
                );
                assert!(
                    time_agrees(&rel, r.t, g.t, Precision::F32),
                    "round {round} table {k}: {} vs {}",
                    r.t,
                    g.t
                );
                hits += 1;
            }
        }
        tables += batch.num_tables();
        pairs += batch.num_pairs();
        drop((batch, ref_pairs, ref_next, got));
        let rss = resident_bytes();
        if round == 1 {
            warm = rss;
        } else if round > 1 {
            peak_after_warm = peak_after_warm.max(rss);
        }
        println!(
            "soak round {round} ({}): ok, resident {:.0} MB, {:.0} s",
            scenario.name(),
            rss as f64 / 1e6,
            clock.elapsed().as_secs_f64()
        );
    }
    println!(
        "soak: {tables} tables, {pairs} pairs, {hits} next-collision times compared, \
         0 differ; resident after warm-up {:.0} MB, peak later {:.0} MB",
        warm as f64 / 1e6,
        peak_after_warm as f64 / 1e6
    );
    assert_eq!(tables, ROUNDS * TABLES);
    // flat: no growth beyond allocator noise once every buffer has reached its size
    if warm > 0 {
        assert!(
            peak_after_warm <= warm + warm / 10 + (64 << 20),
            "memory grew: {warm} after warm-up, {peak_after_warm} later"
        );
    }
}
