//! Faults injected into the GPU event loop's real wgpu calls (the `testing` feature's
//! `GpuSimulator::inject_fault`): a failed dispatch and a lost device, at the first
//! dispatch and in the middle of a batch (after some dispatches have run). On the `gpu`
//! backend each is an `Error::Gpu`; on `auto` ([`ShotEngine`]) the batch or study is redone
//! on the CPU, bit for bit the CPU's result, with a note, and the CPU is used from then on.
//!
//! Without a GPU the tests print why they skip (`common::gpu_or_skip`'s convention).

mod common;

use kisstime::engine::{AutoRule, Backend, ShotEngine};
use kisstime::gpu::{Fault, GpuShot};
use kisstime::io::shot_set::{read_shots, read_table};
use kisstime::io::strikes::read_sample_strikes;
use kisstime::simulate::{BatchError, Limits, SimParams};
use kisstime::study::{self, RunOptions, Samples, StudyConfig, run_strikes};
use kisstime::{Error, Precision};

/// Ordinary shots of the reference set (they run for several short dispatches).
fn shots() -> (kisstime::simulate::Table, Vec<GpuShot>) {
    let dir = common::fullshots_dir();
    let params = SimParams::default();
    let table = read_table(&dir).unwrap();
    let shots = read_shots(&dir, params.ball.r).unwrap();
    let inputs = shots[100..130]
        .iter()
        .map(|s| GpuShot {
            balls: s.balls.clone(),
            strike: Some((s.cue, s.strike)),
        })
        .collect();
    (table, inputs)
}

fn engine(backend: Backend, test: &str) -> Option<ShotEngine> {
    common::gpu_or_skip(Precision::F64, test)?;
    // `auto` on any adapter (lavapipe too), so that its fallback is exercised
    Some(
        ShotEngine::with_rule(backend, Precision::F64, AutoRule::AnyGpu)
            .expect("the event loop builds"),
    )
}

const FAULTS: [Fault; 4] = [
    Fault::FailedDispatch,
    Fault::DeviceLost,
    Fault::FailedDispatchAfter(3),
    Fault::DeviceLostAfter(2),
];

#[test]
fn a_fault_in_the_event_loop_is_an_error_on_gpu_and_redone_on_the_cpu_in_auto() {
    let (table, inputs) = shots();
    let params = SimParams::default();
    let limits = Limits::default();
    let mut cpu = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let want = cpu
        .simulate(&table, params, limits, &inputs, true)
        .unwrap_or_else(|e| panic!("{e:?}"));
    for fault in FAULTS {
        let Some(mut gpu) = engine(Backend::Gpu, "event_loop_fault") else {
            return;
        };
        let g = gpu.gpu().expect("a GPU is there");
        g.events_per_dispatch = 4;
        g.inject_fault(fault);
        match gpu.simulate(&table, params, limits, &inputs, true) {
            Err(BatchError::Sink(Error::Gpu(_))) => {}
            Err(e) => panic!("{fault:?}: {e:?}"),
            Ok(_) => panic!("{fault:?}: no error"),
        }

        let mut auto = engine(Backend::Auto, "event_loop_fault").unwrap();
        let g = auto.gpu().expect("a GPU is there");
        g.events_per_dispatch = 4;
        g.inject_fault(fault);
        let got = auto
            .simulate(&table, params, limits, &inputs, true)
            .unwrap_or_else(|e| panic!("{fault:?}: {e:?}"));
        assert_eq!(got, want, "{fault:?}: redone on the CPU, bit for bit");
        let notes = auto.take_notes();
        assert!(
            notes.iter().any(|n| n.contains("redone on the CPU")),
            "{fault:?}: {notes:?}"
        );
        assert!(
            auto.gpu().is_none(),
            "{fault:?}: the CPU is used from then on"
        );
        assert!(
            auto.describe().starts_with("cpu f64"),
            "{}",
            auto.describe()
        );
    }
}

#[test]
fn a_fault_mid_study_is_redone_on_the_cpu_in_auto() {
    let dir = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/studies"));
    let config = StudyConfig::read_reference(&dir.join("dev_scenario.json")).unwrap();
    let strikes: Vec<_> = read_sample_strikes(&dir.join("dev_strikes.csv")).unwrap()[..40]
        .iter()
        .map(|s| s.strike)
        .collect();
    let options = RunOptions::default();
    let want = run_strikes(&config, &strikes, &options, &mut |_, _| {}).unwrap();
    let given = Samples::Given(&strikes);
    for fault in [Fault::FailedDispatchAfter(2), Fault::DeviceLostAfter(1)] {
        let Some(mut gpu) = engine(Backend::Gpu, "study_fault") else {
            return;
        };
        // 2 events a dispatch: each batch of samples runs for several dispatches
        gpu.gpu().unwrap().events_per_dispatch = 2;
        gpu.gpu().unwrap().inject_fault(fault);
        let err =
            study::run(&mut gpu, &config, given.clone(), &options, &mut |_, _| {}).unwrap_err();
        assert!(matches!(err, Error::Gpu(_)), "{fault:?}: {err}");

        let mut auto = engine(Backend::Auto, "study_fault").unwrap();
        auto.gpu().unwrap().events_per_dispatch = 2;
        auto.gpu().unwrap().inject_fault(fault);
        let got = study::run(&mut auto, &config, given.clone(), &options, &mut |_, _| {}).unwrap();
        assert_eq!(got, want, "{fault:?}: the CPU's samples");
        assert!(
            auto.take_notes()
                .iter()
                .any(|n| n.contains("the study was redone on the CPU")),
            "{fault:?}"
        );
    }
}

#[test]
fn bad_tables_are_input_errors_on_every_backend_and_large_tables_run_on_the_gpu() {
    let (table, mut inputs) = shots();
    let params = SimParams::default();
    let limits = Limits::default();
    // a ball off the table in shot 5
    inputs[5].balls[1].r.x = -3.0;
    for backend in [Backend::Cpu, Backend::Gpu, Backend::Auto] {
        let mut e = if backend == Backend::Cpu {
            ShotEngine::new(backend, Precision::F64).unwrap()
        } else {
            let Some(e) = engine(backend, "bad_table") else {
                return;
            };
            e
        };
        match e.simulate(&table, params, limits, &inputs, false) {
            Err(BatchError::Table { table: 5, .. }) => {}
            other => panic!("{backend:?}: {other:?}"),
        }
        assert!(
            e.take_notes().is_empty(),
            "{backend:?}: no fallback for bad input"
        );
    }
    // 17 balls: the GPU's 32-ball build, no fallback; 65: more than any backend takes
    let (_, inputs) = shots();
    let grown = |n: usize| {
        let mut big = inputs[0].clone();
        let mut extra = big.balls[1];
        extra.r.x = 0.3;
        extra.r.y = 0.3;
        extra.v = kisstime::model::vec3::Vec3::new(0.0, 0.0, 0.0);
        extra.w = kisstime::model::vec3::Vec3::new(0.0, 0.0, 0.0);
        extra.s = kisstime::MotionState::Stationary;
        while big.balls.len() < n {
            let mut b = extra;
            let k = big.balls.len() - inputs[0].balls.len();
            b.r.x += 0.07 * (k % 12) as f64;
            b.r.y += 0.07 * (k / 12) as f64;
            big.balls.push(b);
        }
        big
    };
    let big = grown(17);
    let one = std::slice::from_ref(&big);
    let mut cpu = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let on_cpu = cpu.simulate(&table, params, limits, one, false).unwrap();
    for backend in [Backend::Gpu, Backend::Auto] {
        let mut e = engine(backend, "large_table").unwrap();
        let runs = e.simulate(&table, params, limits, one, false).unwrap();
        assert_eq!(runs[0].outcome.n_events, on_cpu[0].outcome.n_events);
        assert!(e.describe().starts_with("gpu"), "{}", e.describe());
        assert!(e.take_notes().is_empty(), "{backend:?}: no fallback");
    }
    let huge = grown(65);
    for backend in [Backend::Cpu, Backend::Gpu, Backend::Auto] {
        let mut e = if backend == Backend::Cpu {
            ShotEngine::new(backend, Precision::F64).unwrap()
        } else {
            engine(backend, "huge_table").unwrap()
        };
        match e.simulate(&table, params, limits, std::slice::from_ref(&huge), false) {
            Err(BatchError::Table { table: 0, error }) => {
                assert!(error.to_string().contains("at most 64"), "{error}")
            }
            other => panic!("{backend:?}: {other:?}"),
        }
    }
}

/// The one entry point, `ShotEngine::simulate_with`, streams the GPU's runs in chunks: in
/// table order, each chunk at most the chunk size, the same runs as the CPU's stream
/// (events and final states); a bad table stops the stream there, the chunks before it
/// delivered, the same error on both backends.
#[test]
fn the_stream_is_the_same_on_both_backends() {
    use kisstime::simulate::{BallState, BatchOptions, SimError};
    let Some(mut gpu) = engine(Backend::Gpu, "the stream") else {
        return;
    };
    gpu.set_gpu_chunk_tables(Some(8));
    let mut cpu = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let (table, inputs) = shots();
    let params = SimParams::default();
    let options = BatchOptions {
        chunk_tables: 5,
        ..BatchOptions::default()
    };
    // table 21 gets a ball off the table
    let input = |bad: bool| {
        let inputs = &inputs;
        move |k: usize, balls: &mut Vec<BallState>| -> Result<_, SimError> {
            balls.clear();
            balls.extend_from_slice(&inputs[k].balls);
            if bad && k == 21 {
                balls[1].r.x = -5.0;
            }
            Ok(inputs[k].strike)
        }
    };
    let mut runs = [Vec::new(), Vec::new()];
    for (side, e) in [&mut gpu, &mut cpu].into_iter().enumerate() {
        let mut next = 0;
        let stats = e
            .simulate_with(&table, params, &options, inputs.len(), input(false), |c| {
                assert_eq!(c.tables().start, next, "chunks in table order");
                assert!(
                    c.len() <= if side == 0 { 8 } else { 5 },
                    "{} tables",
                    c.len()
                );
                next = c.tables().end;
                runs[side].extend(c.iter().map(|r| (r.events.to_vec(), r.balls.to_vec())));
                Ok::<(), Error>(())
            })
            .unwrap();
        assert_eq!((stats.tables, next), (inputs.len(), inputs.len()));
    }
    assert!(gpu.describe().starts_with("gpu"), "{}", gpu.describe());
    assert!(cpu.describe().starts_with("cpu"), "{}", cpu.describe());
    assert_eq!(runs[0].len(), 30);
    // the GPU's stream is its whole batch, bit for bit ...
    let whole = gpu
        .gpu()
        .unwrap()
        .simulate(&table, params, Limits::default(), &inputs, true)
        .unwrap();
    for (k, (s, w)) in runs[0].iter().zip(&whole).enumerate() {
        assert!(
            s.0 == w.events && s.1 == w.balls,
            "table {k}: the stream differs"
        );
    }
    // ... and the CPU's event sequence (the f64 polyfills differ in the last ulps)
    for (k, (g, c)) in runs[0].iter().zip(&runs[1]).enumerate() {
        let kinds = |r: &Vec<kisstime::simulate::EventRecord>| {
            r.iter()
                .map(|e| (e.event.kind, e.event.ball, e.event.other))
                .collect::<Vec<_>>()
        };
        assert!(kinds(&g.0) == kinds(&c.0), "table {k}: other events");
        let far = g.1.iter().zip(&c.1).any(|(a, b)| (a.r - b.r).norm() > 1e-9);
        assert!(!far, "table {k}: other final positions");
    }
    for e in [&mut gpu, &mut cpu] {
        let mut seen = 0;
        let err = e
            .simulate_with(&table, params, &options, inputs.len(), input(true), |c| {
                seen = c.tables().end;
                Ok::<(), Error>(())
            })
            .unwrap_err();
        match err {
            BatchError::Table { table: 21, error } => {
                assert!(error.to_string().contains("ball"), "{error}")
            }
            other => panic!("{other}"),
        }
        assert!(
            (15..=21).contains(&seen),
            "chunks before the bad table: {seen}"
        );
    }
}

/// A fault after chunks have reached the sink (chunks of 8 tables, several dispatches
/// each): `auto` starts the whole call over on the CPU where the caller can start over
/// (`ShotEngine::simulate`, `simulate_restartable`, a study), so that every result is the
/// CPU's bit for bit; `simulate_with` finishes on the CPU and says which tables ran where;
/// `gpu` is an error.
#[test]
fn a_fault_after_chunks_were_delivered_starts_the_call_over_on_the_cpu_in_auto() {
    let (table, inputs) = shots();
    let params = SimParams::default();
    let limits = Limits::default();
    let mut cpu = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let want = cpu.simulate(&table, params, limits, &inputs, true).unwrap();
    let mut restarted = 0;
    for fault in [Fault::FailedDispatchAfter(12), Fault::DeviceLostAfter(30)] {
        let open = |backend| {
            let mut e = engine(backend, "fault_after_chunks")?;
            e.set_gpu_chunk_tables(Some(8));
            let g = e.gpu().expect("a GPU is there");
            g.events_per_dispatch = 4;
            g.inject_fault(fault);
            Some(e)
        };
        if matches!(fault, Fault::DeviceLostAfter(_)) {
            let Some(mut gpu) = open(Backend::Gpu) else {
                return;
            };
            match gpu.simulate(&table, params, limits, &inputs, true) {
                Err(BatchError::Sink(Error::Gpu(_))) => {}
                other => panic!("{fault:?}: {:?}", other.map(|r| r.len())),
            }
        }
        // collected: restarted, the CPU's runs bit for bit
        let Some(mut auto) = open(Backend::Auto) else {
            return;
        };
        let got = auto
            .simulate(&table, params, limits, &inputs, true)
            .unwrap();
        assert_eq!(got, want, "{fault:?}: the CPU's runs");
        let notes = auto.take_notes();
        assert_eq!(notes.len(), 1, "{fault:?}: {notes:?}");
        if notes[0].contains("from its first table") {
            restarted += 1;
            assert!(notes[0].contains(" of 30 tables"), "{}", notes[0]);
        } else {
            // the fault came in the first chunk: nothing had been delivered
            assert!(notes[0].contains("redone on the CPU"), "{}", notes[0]);
        }
        assert!(auto.gpu().is_none() && auto.describe().starts_with("cpu"));

        // streamed without a restart: the first chunks are the GPU's, the rest the CPU's
        let mut auto = open(Backend::Auto).unwrap();
        let mut tables = 0;
        let options = kisstime::simulate::BatchOptions::default();
        let input = |k: usize, balls: &mut Vec<kisstime::simulate::BallState>| {
            balls.clear();
            balls.extend_from_slice(&inputs[k].balls);
            Ok(inputs[k].strike)
        };
        auto.simulate_with(&table, params, &options, inputs.len(), input, |c| {
            assert_eq!(c.tables().start, tables, "in order, each table once");
            tables = c.tables().end;
            Ok::<(), Error>(())
        })
        .unwrap();
        assert_eq!(tables, 30);
        let notes = auto.take_notes();
        assert!(
            notes
                .iter()
                .any(|n| n.contains("on the GPU") || n.contains("redone on the CPU")),
            "{fault:?}: {notes:?}"
        );
    }
    assert!(restarted > 0, "no fault came after a chunk was delivered");

    // a study whose samples come back in chunks: started over, the CPU's samples
    let dir = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/studies"));
    let config = StudyConfig::read_reference(&dir.join("dev_scenario.json")).unwrap();
    let strikes: Vec<_> = read_sample_strikes(&dir.join("dev_strikes.csv")).unwrap()[..40]
        .iter()
        .map(|s| s.strike)
        .collect();
    let options = RunOptions::default();
    let want = run_strikes(&config, &strikes, &options, &mut |_, _| {}).unwrap();
    let mut auto = engine(Backend::Auto, "study_fault_after_chunks").unwrap();
    auto.set_gpu_chunk_tables(Some(8));
    auto.gpu().unwrap().events_per_dispatch = 2;
    auto.gpu().unwrap().inject_fault(Fault::DeviceLostAfter(15));
    let mut seen = Vec::new();
    let got = study::run(
        &mut auto,
        &config,
        Samples::Given(&strikes),
        &options,
        &mut |done, _| seen.push(done),
    )
    .unwrap();
    assert_eq!(got, want, "the CPU's samples");
    let notes = auto.take_notes();
    assert!(
        notes.iter().any(|n| n.contains("the study was redone")),
        "{notes:?}"
    );
}

/// `kisstime simulate` with the GPU failing mid-run (the `testing` feature's
/// `KISSTIME_TEST_GPU_FAULT` hook): `--backend auto` writes the CPU's outputs, bit for bit,
/// with a warning; `--backend gpu` fails with a clear error and writes nothing (a previous
/// file stays as it was); `auto` writing to standard output cannot take back what it
/// wrote and fails clearly instead.
#[test]
fn simulate_with_the_gpu_lost_mid_run() {
    if common::gpu_or_skip(Precision::F64, "simulate_gpu_lost").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let s = |p: &std::path::Path| p.to_str().unwrap().to_owned();
    let input = dir.path().join("in.npy");
    let generated = common::run_kisstime(
        &[
            "gen",
            "--scenario",
            "midshot",
            "--tables",
            "48",
            "--balls",
            "6",
            "-o",
            &s(&input),
        ],
        &[],
    );
    assert!(generated.status.success());
    let run = |backend: &str, fault: Option<&str>, out: &std::path::Path| {
        let mut env = vec![("KISSTIME_AUTO_GPU", "always")];
        if let Some(f) = fault {
            env.push(("KISSTIME_TEST_GPU_FAULT", f));
        }
        let args = [
            "simulate".to_owned(),
            s(&input),
            "--backend".into(),
            backend.into(),
            "-o".into(),
            s(&out.join("events.npy")),
            "--final".into(),
            s(&out.join("final.csv")),
        ];
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        common::run_kisstime(&args, &env)
    };
    let read = |out: &std::path::Path| {
        ["events.npy", "final.csv"].map(|n| std::fs::read(out.join(n)).unwrap())
    };
    let cpu_dir = dir.path().join("cpu");
    std::fs::create_dir(&cpu_dir).unwrap();
    assert!(run("cpu", None, &cpu_dir).status.success());
    let want = read(&cpu_dir);
    let mut restarted = 0;
    for fault in ["dispatch-after:2", "lost-after:40"] {
        let out = dir.path().join(fault.replace(':', "-"));
        std::fs::create_dir(&out).unwrap();
        let auto = run("auto", Some(fault), &out);
        let err = String::from_utf8_lossy(&auto.stderr);
        assert!(auto.status.success(), "{fault}: {err}");
        assert!(err.contains("the CPU"), "{fault}: no warning: {err}");
        if err.contains("written again from the first table") {
            restarted += 1;
        }
        assert!(read(&out) == want, "{fault}: not the CPU's outputs");
        assert!(err.contains("on cpu f64"), "{err}");

        let gpu_dir = dir.path().join(format!("gpu-{}", fault.replace(':', "-")));
        std::fs::create_dir(&gpu_dir).unwrap();
        std::fs::write(gpu_dir.join("events.npy"), b"previous").unwrap();
        let gpu = run("gpu", Some(fault), &gpu_dir);
        let err = String::from_utf8_lossy(&gpu.stderr);
        assert_eq!(gpu.status.code(), Some(1), "{fault}: {err}");
        assert!(err.contains("kisstime: error: GPU"), "{fault}: {err}");
        assert_eq!(
            std::fs::read(gpu_dir.join("events.npy")).unwrap(),
            b"previous"
        );
        let mut left: Vec<_> = std::fs::read_dir(&gpu_dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        left.sort();
        assert_eq!(left, vec!["events.npy"], "{fault}: written or left behind");
    }
    assert!(restarted > 0, "no fault came after tables were written");
    // standard output: what was written cannot be taken back
    let out = common::run_kisstime(
        &["simulate", &s(&input), "--backend", "auto"],
        &[
            ("KISSTIME_AUTO_GPU", "always"),
            ("KISSTIME_TEST_GPU_FAULT", "lost-after:40"),
        ],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("cannot be taken back"), "{err}");
}

/// A batch in several chunks runs each chunk on the device while the host unpacks the one
/// before and packs the one after. A failed dispatch or a lost device in a later chunk,
/// and a bad table in the chunk packed during a run, are errors that name what failed;
/// nothing is left mapped: after a failed dispatch or a bad table the same simulator runs
/// the batch again, bit for bit the runs of one chunk.
#[test]
fn a_failure_in_a_later_chunk_while_the_host_works_on_its_neighbours() {
    let (table, inputs) = shots();
    let params = SimParams::default();
    let limits = Limits::default();
    let Some(mut whole) = engine(Backend::Gpu, "pipelined_chunk_fault") else {
        return;
    };
    let want = whole
        .gpu()
        .unwrap()
        .simulate(&table, params, limits, &inputs, false)
        .unwrap();
    // the dispatches of the first chunk alone (7 tables, 4 events a dispatch)
    let first_chunk = {
        let g = whole.gpu().unwrap();
        g.events_per_dispatch = 4;
        g.simulate(&table, params, limits, &inputs[..7], false)
            .unwrap();
        g.dispatches() as u32
    };
    // 30 tables in chunks of 7 (five chunks): the fault comes in the second chunk, while
    // the host unpacks the first and packs the third
    for fault in [
        Fault::FailedDispatchAfter(first_chunk + 2),
        Fault::DeviceLostAfter(first_chunk + 2),
    ] {
        let mut engine = engine(Backend::Gpu, "pipelined_chunk_fault").unwrap();
        let g = engine.gpu().unwrap();
        g.max_tables_per_chunk = 7;
        g.events_per_dispatch = 4;
        let runs = g.simulate(&table, params, limits, &inputs, false).unwrap();
        assert_eq!(runs, want, "in chunks");
        assert!(
            g.dispatches() > u64::from(first_chunk) + 4,
            "{}",
            g.dispatches()
        );
        g.inject_fault(fault);
        match g.simulate(&table, params, limits, &inputs, false) {
            Err(Error::Gpu(_)) => {}
            other => panic!("{fault:?}: {other:?}"),
        }
        if matches!(fault, Fault::FailedDispatchAfter(_)) {
            let again = g.simulate(&table, params, limits, &inputs, false).unwrap();
            assert_eq!(again, want, "{fault:?}: the same simulator again");
        }
    }
    // a ball off the table in table 17 (the third chunk, packed while the second runs)
    let mut bad = inputs.clone();
    bad[17].balls[0].r.x = -5.0;
    let mut engine = engine(Backend::Gpu, "pipelined_chunk_fault").unwrap();
    let g = engine.gpu().unwrap();
    g.max_tables_per_chunk = 7;
    match g.simulate(&table, params, limits, &bad, false) {
        Err(Error::Input(e)) => assert!(e.to_string().contains("table 17"), "{e}"),
        other => panic!("{other:?}"),
    }
    let again = g.simulate(&table, params, limits, &inputs, false).unwrap();
    assert_eq!(again, want, "after the bad table");
}

/// From its second chunk on, `simulate_with` on the GPU runs a chunk while the host hands
/// the chunk before to the sink and checks the chunk after: a sink that fails stops the
/// stream there (it is not called again, and the error is the sink's), and the engine
/// then streams the same batch again, the runs of the first time.
#[test]
fn a_failing_sink_stops_the_stream_while_the_device_runs_the_next_chunk() {
    use kisstime::simulate::{BallState, BatchOptions, SimError};
    let Some(mut gpu) = engine(Backend::Gpu, "the failing sink") else {
        return;
    };
    gpu.set_gpu_chunk_tables(Some(6));
    let (table, inputs) = shots();
    let params = SimParams::default();
    let options = BatchOptions::default();
    let input = |k: usize, balls: &mut Vec<BallState>| -> Result<_, SimError> {
        balls.clear();
        balls.extend_from_slice(&inputs[k].balls);
        Ok(inputs[k].strike)
    };
    let stream = |gpu: &mut ShotEngine, fail_at: Option<usize>| {
        let mut seen = Vec::new();
        let got = gpu.simulate_with(&table, params, &options, inputs.len(), input, |c| {
            seen.push(c.tables().start);
            if Some(c.tables().start) == fail_at {
                return Err(Error::Unsupported("the sink is full".into()));
            }
            Ok(())
        });
        (got, seen)
    };
    let (got, seen) = stream(&mut gpu, Some(12));
    match got {
        Err(BatchError::Sink(Error::Unsupported(m))) => assert_eq!(m, "the sink is full"),
        other => panic!("{other:?}"),
    }
    assert_eq!(seen, [0, 6, 12], "the sink is not called after it failed");
    let (got, seen) = stream(&mut gpu, None);
    assert_eq!(got.unwrap().tables, 30);
    assert_eq!(seen, [0, 6, 12, 18, 24]);
    assert!(gpu.describe().starts_with("gpu"), "{}", gpu.describe());
}
