//! `examples/pipeline_stats.rs` on this machine's Vulkan device: the event loop's SPIR-V,
//! written as wgpu's Vulkan backend writes it, builds in the driver for each build asked
//! for, and each gets its line — the driver's statistics where it reports them
//! (`VK_KHR_pipeline_executable_properties`), else a line saying so. The example is built
//! by `cargo test` (with `cargo test --test pipeline_stats` alone, build it first:
//! `cargo build --example pipeline_stats`).

use std::path::PathBuf;
use std::process::Command;

fn example() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let dir = exe.parent().unwrap().parent().unwrap().join("examples");
    dir.join(format!("pipeline_stats{}", std::env::consts::EXE_SUFFIX))
}

#[test]
fn the_event_loops_pipelines_build_in_the_driver_with_their_statistics() {
    let exe = example();
    assert!(
        exe.exists(),
        "{} is missing: `cargo build --example pipeline_stats`",
        exe.display()
    );
    let builds = ["16:64:64", "16:16:1:unchecked", "16:16:64:4"];
    let out = Command::new(&exe).args(builds).output().unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    if !out.status.success() && stderr.contains("no Vulkan") {
        let required = std::env::var("KISSTIME_REQUIRE_GPU").is_ok_and(|v| v == "1");
        assert!(!required, "KISSTIME_REQUIRE_GPU=1 but: {stderr}");
        eprintln!("pipeline_stats: SKIPPED, no Vulkan device: {stderr}");
        return;
    }
    assert!(out.status.success(), "{stdout}\n{stderr}");
    println!("{stdout}");
    let device = stdout.lines().next().unwrap_or_default();
    assert!(device.starts_with("device: "), "{stdout}");
    if stdout.contains("has no f64 in shaders") {
        eprintln!("pipeline_stats: SKIPPED, the device has no f64: {stdout}");
        return;
    }
    let without = stdout.contains("has no VK_KHR_pipeline_executable_properties");
    for label in [
        "event loop f64, 16 balls, 64 threads a table, a row over at most 64, one table a workgroup: ",
        "event loop f64, 16 balls, 16 threads a table, a row over at most 1, one table a workgroup, without wgpu's runtime checks: ",
        "event loop f64, 16 balls, 16 threads a table, a row over at most 64, 4 tables a workgroup: ",
    ] {
        let line = stdout
            .lines()
            .find(|l| l.starts_with(label))
            .unwrap_or_else(|| panic!("no line for {label:?}: {stdout}"));
        match without {
            true => assert!(line.ends_with(", no statistics"), "{line}"),
            false => assert!(!line.contains("no statistics"), "{line}"),
        }
    }
    // a build that is not one is refused, naming it
    for spec in [
        "17:64:64",
        "16:64:64:fast",
        "16:64",
        "16:64:64:3",
        "16:64:64:2:1",
    ] {
        let bad = Command::new(&exe).arg(spec).output().unwrap();
        assert_eq!(bad.status.code(), Some(1), "{spec}");
        let err = String::from_utf8_lossy(&bad.stderr);
        assert!(err.contains(&format!("{spec:?}")), "{spec}: {err}");
    }
}
