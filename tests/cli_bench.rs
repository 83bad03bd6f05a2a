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

#[test]
fn sim_bench_reports_shots_and_events_per_second() {
    for (workload, balls) in [("ordinary", None), ("breaks", Some(50 * 16))] {
        let args = [
            "bench",
            "--sim",
            workload,
            "--tables",
            "50",
            "--reps",
            "1",
            "--json",
            "--backend",
            "cpu",
        ];
        let out = kisstime(&args, &[]);
        assert!(
            out.status.success(),
            "{workload}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("valid JSON");
        assert_eq!(json["mode"], "sim");
        assert_eq!(json["workload"], workload);
        assert_eq!(json["tables"], 50);
        assert_eq!(json["reps"], 1);
        if let Some(balls) = balls {
            assert_eq!(json["balls"], balls);
        }
        let cpu = &json["backends"][0];
        assert_eq!(cpu["backend"], "cpu", "{json}");
        assert_eq!(cpu["cut"], 0, "{json}");
        assert!(cpu["shots_per_s"].as_f64().unwrap() > 0.0, "{json}");
        assert!(cpu["events_per_s"].as_f64().unwrap() > 0.0, "{json}");
        assert!(json["threads"].as_u64().unwrap() >= 1);
        // a break has many more events than the strike and the cue ball's transitions
        let per_shot = cpu["events_per_shot"].as_f64().unwrap();
        assert!(
            per_shot > if balls.is_some() { 20.0 } else { 3.0 },
            "{json}"
        );
    }
    let out = kisstime(
        &[
            "bench",
            "--sim",
            "breaks",
            "--tables",
            "20",
            "--reps",
            "1",
            "--backend",
            "cpu",
        ],
        &[("RAYON_NUM_THREADS", "1")],
    );
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("breaks, 20 tables (320 balls)"), "{text}");
    assert!(
        text.contains("shots/s") && text.contains("events/s"),
        "{text}"
    );
}

#[test]
fn bench_refuses_bad_values_with_exit_code_2() {
    for args in [
        &["bench", "--sim", "ordinary", "--tables", "0"][..],
        &["bench", "--sim", "ordinary", "--reps", "0"],
        &["bench", "--sim", "breaks", "--tables", "-3"],
        &["bench", "--sim", "massé"],
        &["bench", "--sim", "breaks", "--balls", "8"],
        &["bench", "--sim", "breaks", "--scenario", "worst"],
        &["bench", "--tables", "0"],
        &["bench", "--reps", "0"],
    ] {
        let out = kisstime(args, &[]);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
    }
}

/// `bench --sim --backend all` on a GPU: the CPU's figures, then the GPU event loop's with
/// its split and its agreement with the CPU (f64 ordinary shots: the CPU's events).
#[test]
fn sim_bench_measures_the_gpu_event_loop_beside_the_cpu() {
    if common::gpu_or_skip(kisstime::Precision::F64, "sim_bench_gpu").is_none() {
        return;
    }
    let args = [
        "bench",
        "--sim",
        "ordinary",
        "--tables",
        "60",
        "--reps",
        "1",
        "--json",
        "--backend",
        "all",
        "--precision",
        "f64",
    ];
    let out = kisstime(&args, &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("valid JSON");
    let (cpu, gpu) = (&json["backends"][0], &json["backends"][1]);
    assert_eq!(
        (&cpu["backend"], &gpu["backend"]),
        (&"cpu".into(), &"gpu".into())
    );
    assert_eq!(gpu["precision"], "f64");
    assert_eq!(gpu["events"], cpu["events"], "{json}");
    assert_eq!(gpu["tables_differ"], serde_json::json!([0, 0]), "{json}");
    assert!(
        gpu["gpu_split"]["kernel_s"].as_f64().unwrap() > 0.0,
        "{json}"
    );
    assert!(gpu["dispatches"].as_u64().unwrap() >= 1, "{json}");
    assert!(gpu["kernel_shots_per_s"].as_f64().unwrap() > 0.0, "{json}");
}
