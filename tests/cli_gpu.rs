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
    // (auto tries a GPU for the pair kernels only where told to: they are slower there)
    let env = [
        ("WGPU_ADAPTER_NAME", "no-such-adapter-anywhere"),
        ("KISSTIME_AUTO_GPU", "always"),
    ];
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
    // auto computes the pair kernels on the CPU (slower on the GPU end to end), saying so;
    // with KISSTIME_AUTO_GPU=always on the GPU
    let auto = kisstime(&["pairs", EXAMPLE, "--backend", "auto"], &[]);
    assert!(auto.status.success(), "{}", stderr(&auto));
    assert!(
        stderr(&auto).contains("pair kernels are slower"),
        "{}",
        stderr(&auto)
    );
    assert_eq!(auto.stdout, cpu.stdout);
    let any = [("KISSTIME_AUTO_GPU", "always")];
    let auto_gpu = kisstime(&["pairs", EXAMPLE, "--backend", "auto", "--verbose"], &any);
    assert!(auto_gpu.status.success(), "{}", stderr(&auto_gpu));
    assert!(
        stderr(&auto_gpu).contains("computing on gpu f32"),
        "{}",
        stderr(&auto_gpu)
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

const SIM_BALLS: &str = "table,ball,state,x,y,vx,vy,wx,wy,wz\n\
    1,0,stationary,0.635,0.6,0,0,0,0,0\n\
    1,1,stationary,0.635,1.905,0,0,0,0,0\n\
    2,0,stationary,0.635,0.6,0,0,0,0,0\n\
    2,5,stationary,0.3,1.905,0,0,0,0,0\n\
    2,6,stationary,1.0,1.2,0,0,0,0,0\n\
    3,2,rolling,0.3,0.3,0.5,1.0,-35.0,17.5,0\n\
    3,7,stationary,0.9,1.5,0,0,0,0,0\n";
const SIM_STRIKES: &str = "table,ball,V0,phi,theta,a,b\n1,0,2,90,0,0,0.2\n2,0,3,100,0,0.1,0\n";

/// The rows of a CSV file after its header, split at commas.
fn rows(path: &std::path::Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect()
}

/// Whether two rows hold the same words and numbers within 1e-9 (relative or absolute).
fn rows_agree(a: &[String], b: &[String]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(u), Ok(v)) => (u - v).abs() <= 1e-9 * u.abs().max(v.abs()).max(1.0),
                _ => x == y,
            })
}

#[test]
fn simulate_on_the_gpu_gives_the_cpus_events_and_final_states() {
    let name = "simulate --backend gpu";
    if common::gpu_or_skip(kisstime::Precision::F64, name).is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let balls = dir.path().join("balls.csv");
    let strikes = dir.path().join("strikes.csv");
    std::fs::write(&balls, SIM_BALLS).unwrap();
    std::fs::write(&strikes, SIM_STRIKES).unwrap();
    let mut outputs = Vec::new();
    for backend in ["cpu", "gpu"] {
        let ev = dir.path().join(format!("ev_{backend}.csv"));
        let fin = dir.path().join(format!("fin_{backend}.csv"));
        let oc = dir.path().join(format!("oc_{backend}.csv"));
        let out = kisstime(
            &[
                "simulate",
                balls.to_str().unwrap(),
                "--strikes",
                strikes.to_str().unwrap(),
                "-o",
                ev.to_str().unwrap(),
                "--final",
                fin.to_str().unwrap(),
                "--outcomes",
                oc.to_str().unwrap(),
                "--backend",
                backend,
                "--verbose",
            ],
            &[],
        );
        assert!(out.status.success(), "{backend}: {}", stderr(&out));
        if backend == "gpu" {
            assert!(stderr(&out).contains("on gpu f64: "), "{}", stderr(&out));
        }
        outputs.push((rows(&ev), rows(&fin), rows(&oc)));
    }
    let (cpu, gpu) = (&outputs[0], &outputs[1]);
    assert!(cpu.0.len() > 10, "the shots have events");
    for (what, a, b) in [
        ("events", &cpu.0, &gpu.0),
        ("final", &cpu.1, &gpu.1),
        ("outcomes", &cpu.2, &gpu.2),
    ] {
        assert_eq!(a.len(), b.len(), "{what}: rows");
        for (ra, rb) in a.iter().zip(b) {
            assert!(rows_agree(ra, rb), "{what}: CPU {ra:?}, GPU {rb:?}");
        }
    }
}

#[test]
fn simulate_auto_falls_back_to_the_cpu_with_a_reason() {
    let dir = tempfile::tempdir().unwrap();
    let balls = dir.path().join("balls.csv");
    std::fs::write(&balls, SIM_BALLS).unwrap();
    let env = [("WGPU_ADAPTER_NAME", "no-such-adapter-anywhere")];
    let cpu = kisstime(&["simulate", balls.to_str().unwrap()], &[]);
    let auto = kisstime(
        &["simulate", balls.to_str().unwrap(), "--backend", "auto"],
        &env,
    );
    assert!(auto.status.success(), "{}", stderr(&auto));
    let err = stderr(&auto);
    assert!(
        err.contains("simulating on the CPU") && err.contains("no-such-adapter-anywhere"),
        "{err}"
    );
    assert_eq!(
        auto.stdout, cpu.stdout,
        "the fallback is the CPU path itself"
    );
    let gpu = kisstime(
        &["simulate", balls.to_str().unwrap(), "--backend", "gpu"],
        &env,
    );
    assert_eq!(gpu.status.code(), Some(1), "{}", stderr(&gpu));
    assert!(!stderr(&gpu).contains("panicked"), "{}", stderr(&gpu));
}

#[test]
fn simulate_on_the_cpu_in_f32_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let balls = dir.path().join("balls.csv");
    std::fs::write(&balls, SIM_BALLS).unwrap();
    let out = kisstime(
        &["simulate", balls.to_str().unwrap(), "--precision", "f32"],
        &[],
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("f64 only"), "{}", stderr(&out));
    // whole shots refuse f32 on every backend, before any device is opened
    for backend in ["gpu", "auto"] {
        for args in [
            vec!["simulate", balls.to_str().unwrap()],
            vec!["shots", "--samples", "10"],
        ] {
            let mut args = args.clone();
            args.extend(["--backend", backend, "--precision", "f32"]);
            let out = kisstime(&args, &[]);
            assert_ne!(out.status.code(), Some(0), "{args:?}");
            let err = stderr(&out);
            assert!(
                err.contains("f64 only") && err.contains("pooltool"),
                "{err}"
            );
            assert!(out.stdout.is_empty(), "{args:?}");
        }
    }
}

/// `kisstime shots --backend gpu` (f64) gives the CPU's study: the same counts, and the
/// same per-sample rows up to the last digits of the floats; `auto` without a matching
/// adapter says why and gives the CPU's summary; the CPU in f32 is refused.
#[test]
fn shots_on_the_gpu_give_the_cpus_study_and_auto_falls_back_with_a_reason() {
    if common::gpu_or_skip(kisstime::Precision::F64, "shots_gpu").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut summaries = Vec::new();
    let mut csvs = Vec::new();
    for backend in ["cpu", "gpu"] {
        let csv = dir.path().join(format!("{backend}.csv"));
        let out = kisstime(
            &[
                "shots",
                "--samples",
                "400",
                "--json",
                "--backend",
                backend,
                "-o",
                csv.to_str().unwrap(),
            ],
            &[],
        );
        assert!(out.status.success(), "{backend}: {}", stderr(&out));
        let mut v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let described = v["backend"].as_str().unwrap().to_owned();
        assert!(
            described.starts_with(&format!("{backend} f64")),
            "{described}"
        );
        for timing in ["backend", "seconds", "samples_per_s", "threads"] {
            v.as_object_mut().unwrap().remove(timing);
        }
        summaries.push(v);
        csvs.push(std::fs::read_to_string(&csv).unwrap());
    }
    // counts exactly; statistics to 1e-9 (the GPU's f64 sums may round differently)
    let (cpu, gpu) = (&summaries[0], &summaries[1]);
    for key in [
        "first_contact",
        "outcome",
        "intended_potted",
        "intended_pockets",
        "scratch",
        "scratch_pockets",
        "others_potted",
        "in_target",
        "no_ball_hit",
        "cut_by_cap",
    ] {
        assert_eq!(cpu[key], gpu[key], "{key}");
    }
    let (a, b) = (&csvs[0], &csvs[1]);
    assert_eq!(a.lines().count(), 401);
    let fields = |line: &str| -> Vec<String> { line.split(',').map(str::to_owned).collect() };
    for (ra, rb) in a.lines().zip(b.lines()) {
        assert!(rows_agree(&fields(ra), &fields(rb)), "CPU {ra}\nGPU {rb}");
    }

    let env = [("WGPU_ADAPTER_NAME", "no-such-adapter-anywhere")];
    let auto = kisstime(
        &["shots", "--samples", "50", "--json", "--backend", "auto"],
        &env,
    );
    assert!(auto.status.success(), "{}", stderr(&auto));
    let err = stderr(&auto);
    assert!(
        err.contains("simulating on the CPU") && err.contains("no-such-adapter-anywhere"),
        "{err}"
    );
    let v: serde_json::Value = serde_json::from_slice(&auto.stdout).unwrap();
    assert!(v["backend"].as_str().unwrap().starts_with("cpu f64"));
    let gpu = kisstime(&["shots", "--samples", "50", "--backend", "gpu"], &env);
    assert_eq!(gpu.status.code(), Some(1), "{}", stderr(&gpu));
    let f32_cpu = kisstime(&["shots", "--samples", "50", "--precision", "f32"], &[]);
    assert_eq!(f32_cpu.status.code(), Some(2), "{}", stderr(&f32_cpu));
    assert!(
        stderr(&f32_cpu).contains("f64 only"),
        "{}",
        stderr(&f32_cpu)
    );
}

/// `auto` never takes a software (CPU-type) adapter for whole shots and studies: on
/// lavapipe it says so and runs on the CPU, and every summary names what ran; with
/// KISSTIME_AUTO_GPU=always it runs on the adapter.
#[test]
fn auto_never_picks_a_software_adapter_and_summaries_name_what_ran() {
    let Some(gpu) = common::gpu_or_skip(kisstime::Precision::F64, "cli_gpu auto") else {
        return;
    };
    let adapter = gpu.adapter().clone();
    drop(gpu);
    let software = adapter.is_software();
    let run = |args: &[&str], always: bool| {
        let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_kisstime"));
        cmd.args(args).env_remove("KISSTIME_AUTO_GPU");
        if always {
            cmd.env("KISSTIME_AUTO_GPU", "always");
        }
        cmd.output().unwrap()
    };
    let study = ["shots", "--samples", "50", "--json", "--backend", "auto"];
    let measured = run(&study, false);
    assert!(measured.status.success(), "{}", stderr(&measured));
    let v: serde_json::Value = serde_json::from_slice(&measured.stdout).unwrap();
    let backend = v["backend"].as_str().unwrap().to_owned();
    if software {
        assert!(
            stderr(&measured).contains("software (CPU-type)"),
            "{}",
            stderr(&measured)
        );
        assert!(backend.starts_with("cpu f64"), "{backend}");
    }
    let always = run(&study, true);
    assert!(always.status.success(), "{}", stderr(&always));
    let v: serde_json::Value = serde_json::from_slice(&always.stdout).unwrap();
    let backend = v["backend"].as_str().unwrap();
    assert!(
        backend.starts_with("gpu f64: ") && backend.contains(&adapter.name),
        "{backend}"
    );
    // simulate's summary line names the backend and the device
    let dir = tempfile::tempdir().unwrap();
    let balls = dir.path().join("balls.csv");
    std::fs::write(&balls, SIM_BALLS).unwrap();
    let sim = ["simulate", balls.to_str().unwrap(), "--backend", "auto"];
    let measured = run(&sim, false);
    assert!(measured.status.success(), "{}", stderr(&measured));
    let summary = stderr(&measured);
    let summary = summary.lines().find(|l| l.contains(" tables/s, ")).unwrap();
    if software {
        assert!(summary.contains("on cpu f64"), "{summary}");
    }
    let always = run(&sim, true);
    let summary = stderr(&always);
    let summary = summary.lines().find(|l| l.contains(" tables/s, ")).unwrap();
    assert!(summary.contains("on gpu f64: "), "{summary}");
}

/// The measuring knobs of the GPU event loop (`KISSTIME_EVENT_LOOP_THREADS`,
/// `KISSTIME_GPU_PIPELINE_CHUNKS`, `KISSTIME_GPU_ROW_THREADS`, `KISSTIME_GPU_EXACT`,
/// `KISSTIME_GPU_TABLES_PER_GROUP`) with a bad value: `gpu` is a clear error naming the
/// variable, with nothing on standard output; `auto` says why and runs on the CPU, its
/// output the CPU's. Checked before any device is opened, so no GPU is needed.
#[test]
fn a_bad_gpu_knob_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let balls = dir.path().join("balls.csv");
    std::fs::write(&balls, SIM_BALLS).unwrap();
    let balls = balls.to_str().unwrap();
    let cpu = kisstime(&["simulate", balls], &[]);
    assert!(cpu.status.success(), "{}", stderr(&cpu));
    for (var, value) in [
        ("KISSTIME_EVENT_LOOP_THREADS", "12"),
        ("KISSTIME_GPU_PIPELINE_CHUNKS", "0"),
        ("KISSTIME_GPU_PIPELINE_CHUNKS", "many"),
        ("KISSTIME_GPU_ROW_THREADS", "0"),
        ("KISSTIME_GPU_ROW_THREADS", "65"),
        ("KISSTIME_GPU_EXACT", "2"),
        ("KISSTIME_GPU_DRAWS", "yes"),
        ("KISSTIME_GPU_TABLES_PER_GROUP", "3"),
        ("KISSTIME_GPU_TABLES_PER_GROUP", "32"),
    ] {
        let env = [(var, value)];
        let gpu = kisstime(&["simulate", balls, "--backend", "gpu"], &env);
        let err = stderr(&gpu);
        assert!(!gpu.status.success(), "{var}={value}: {err}");
        assert!(
            err.contains(var) && err.contains(value) && !err.contains("panicked"),
            "{var}={value}: {err}"
        );
        assert!(gpu.stdout.is_empty(), "{var}={value}");
        let auto = kisstime(&["simulate", balls, "--backend", "auto"], &env);
        let err = stderr(&auto);
        assert!(auto.status.success(), "{var}={value}: {err}");
        assert!(err.contains(var), "{var}={value}: {err}");
        assert_eq!(auto.stdout, cpu.stdout, "{var}={value}: the CPU's output");
    }
}
