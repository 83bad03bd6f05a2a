//! The command line's GPU backends: `gpu` and `auto` work, `auto` falls back to the CPU
//! with one line on stderr saying why, `gpu` without an adapter is a clear error, and a bad
//! `WGPU_ADAPTER_NAME` never panics.

mod common;

use std::process::Output;

const EXAMPLE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/tables.csv");

fn kisstime(args: &[&str], env: &[(&str, &str)]) -> Output {
    common::run_kisstime(args, env)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn auto_falls_back_to_the_cpu_with_a_reason_when_no_adapter_matches() {
    let cpu = kisstime(&["pairs", EXAMPLE], &[]);
    assert!(cpu.status.success(), "{}", stderr(&cpu));
    let env = [("WGPU_ADAPTER_NAME", "no-such-adapter-anywhere")];
    let auto = kisstime(&["pairs", EXAMPLE, "--backend", "auto"], &env);
    assert!(auto.status.success(), "{}", stderr(&auto));
    let err = stderr(&auto);
    assert!(
        err.contains("no usable GPU") && err.contains("no-such-adapter-anywhere"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(
        auto.stdout, cpu.stdout,
        "the fallback is the CPU path itself"
    );
}

#[test]
fn gpu_without_a_matching_adapter_is_a_clear_error() {
    let env = [("WGPU_ADAPTER_NAME", "no-such-adapter-anywhere")];
    let out = kisstime(&["pairs", EXAMPLE, "--backend", "gpu"], &env);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(
        err.contains("WGPU_ADAPTER_NAME") && !err.contains("panicked"),
        "{err}"
    );
    assert!(out.stdout.is_empty());
}

#[test]
fn cpu_in_f32_is_refused() {
    let out = kisstime(
        &["pairs", EXAMPLE, "--backend", "cpu", "--precision", "f32"],
        &[],
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("f64 only"), "{}", stderr(&out));
}

#[test]
fn gpu_and_auto_answer_like_the_cpu() {
    if common::gpu_or_skip(kisstime::Precision::F32, "cli_gpu").is_none() {
        return;
    }
    let cpu = kisstime(&["pairs", EXAMPLE], &[]);
    let gpu32 = kisstime(
        &[
            "pairs",
            EXAMPLE,
            "--backend",
            "gpu",
            "--precision",
            "f32",
            "--verbose",
        ],
        &[],
    );
    assert!(gpu32.status.success(), "{}", stderr(&gpu32));
    assert!(
        stderr(&gpu32).contains("computing on gpu f32"),
        "{}",
        stderr(&gpu32)
    );
    let auto = kisstime(&["pairs", EXAMPLE, "--backend", "auto"], &[]);
    assert!(auto.status.success(), "{}", stderr(&auto));
    assert!(
        !stderr(&auto).contains("no usable GPU"),
        "{}",
        stderr(&auto)
    );
    // same rows, same statuses; f32 times within the f32 tier of the f64 ones
    let rows = |o: &Output| -> Vec<Vec<String>> {
        String::from_utf8_lossy(&o.stdout)
            .lines()
            .map(|l| l.split(',').map(str::to_owned).collect())
            .collect()
    };
    let (c, g) = (rows(&cpu), rows(&gpu32));
    assert_eq!(c.len(), g.len());
    for (rc, rg) in c.iter().zip(&g).skip(1) {
        assert_eq!(rc[..3], rg[..3]);
        assert_eq!(rc[4], rg[4], "status of {rc:?} vs {rg:?}");
        assert_eq!(rc[5], rg[5], "horizons are f64 on the host");
        if rc[3] != "inf" {
            let (tc, tg): (f64, f64) = (rc[3].parse().unwrap(), rg[3].parse().unwrap());
            assert!((tc - tg).abs() <= 1e-6 + 1e-6 * tc, "{rc:?} vs {rg:?}");
        }
    }
    if common::gpu_or_skip(kisstime::Precision::F64, "cli_gpu_f64").is_some() {
        let gpu64 = kisstime(
            &["pairs", EXAMPLE, "--backend", "gpu", "--precision", "f64"],
            &[],
        );
        assert!(gpu64.status.success(), "{}", stderr(&gpu64));
        let g64 = rows(&gpu64);
        assert_eq!(g64.len(), c.len());
        for (rc, rg) in c.iter().zip(&g64).skip(1) {
            assert_eq!(rc[..3], rg[..3]);
            assert_eq!(rc[4], rg[4], "status of {rc:?} vs {rg:?}");
            if rc[3] != "inf" {
                let (tc, tg): (f64, f64) = (rc[3].parse().unwrap(), rg[3].parse().unwrap());
                assert!((tc - tg).abs() <= 1e-12 + 1e-9 * tc, "{rc:?} vs {rg:?}");
            }
        }
    }
}
