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
