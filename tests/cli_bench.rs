//! `kisstime bench`: the readable report and the JSON report, per backend.

mod common;

use std::process::Output;

fn kisstime(args: &[&str], env: &[(&str, &str)]) -> Output {
    common::run_kisstime(args, env)
}

#[test]
fn cpu_bench_reports_pairs_per_second_as_text_and_json() {
    let out = kisstime(
        &[
            "bench",
            "--backend",
            "cpu",
            "--tables",
            "300",
            "--reps",
            "1",
        ],
        &[],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("300 tables x 16 balls = 36000 pairs"),
        "{text}"
    );
    assert!(
        text.contains("cpu f64") && text.contains("M pairs/s"),
        "{text}"
    );

    let out = kisstime(
        &[
            "bench",
            "--backend",
            "cpu",
            "--tables",
            "200",
            "--scenario",
            "worst",
            "--json",
            "--reps",
            "1",
        ],
        &[],
    );
    assert!(out.status.success());
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("valid JSON");
    assert_eq!(json["scenario"], "worst");
    assert_eq!(json["pairs"], 200 * 120);
    let cpu = &json["backends"][0];
    assert_eq!(cpu["backend"], "cpu");
    assert!(cpu["pair_times_pairs_per_s"].as_f64().unwrap() > 0.0);
    assert!(cpu["next_collisions_pairs_per_s"].as_f64().unwrap() > 0.0);
}

#[test]
fn all_backends_agree_and_the_gpu_split_is_reported() {
    if common::gpu_or_skip(kisstime::Precision::F32, "cli_bench").is_none() {
        return;
    }
    let out = kisstime(&["bench", "--tables", "300", "--json", "--reps", "1"], &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let backends = json["backends"].as_array().unwrap();
    assert_eq!(backends.len(), 2, "{json}");
    let gpu = &backends[1];
    assert_eq!(gpu["backend"], "gpu");
    assert_eq!(gpu["agreement"]["pairs_outside_tier"], 0);
    assert_eq!(gpu["agreement"]["tables_next_differ"], 0);
    assert!(gpu["pair_times_gpu_split"]["kernel_s"].as_f64().unwrap() > 0.0);
}

#[test]
fn gpu_bench_without_a_gpu_is_an_error_and_all_skips_it() {
    let env = [("WGPU_ADAPTER_NAME", "no-such-adapter-anywhere")];
    let out = kisstime(&["bench", "--backend", "gpu", "--tables", "50"], &env);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no-such-adapter-anywhere"));
    let out = kisstime(&["bench", "--tables", "50", "--reps", "1"], &env);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("skipped: gpu f32"), "{text}");
}
