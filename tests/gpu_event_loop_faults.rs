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
use kisstime::study::{RunOptions, StudyConfig, run_strikes};
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
    for fault in [Fault::FailedDispatchAfter(2), Fault::DeviceLostAfter(1)] {
        let Some(mut gpu) = engine(Backend::Gpu, "study_fault") else {
            return;
        };
        // 2 events a dispatch: each batch of samples runs for several dispatches
        gpu.gpu().unwrap().events_per_dispatch = 2;
        gpu.gpu().unwrap().inject_fault(fault);
        let err = gpu
            .run_strikes(&config, &strikes, &options, &mut |_, _| {})
            .unwrap_err();
        assert!(matches!(err, Error::Gpu(_)), "{fault:?}: {err}");

        let mut auto = engine(Backend::Auto, "study_fault").unwrap();
        auto.gpu().unwrap().events_per_dispatch = 2;
        auto.gpu().unwrap().inject_fault(fault);
        let got = auto
            .run_strikes(&config, &strikes, &options, &mut |_, _| {})
            .unwrap();
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
fn bad_tables_are_input_errors_on_every_backend_and_large_tables_go_to_the_cpu_in_auto() {
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
    // 17 balls: more than the GPU event loop takes
    let (_, inputs) = shots();
    let mut big = inputs[0].clone();
    let mut extra = big.balls[1];
    extra.r.x = 0.3;
    extra.r.y = 0.3;
    extra.v = kisstime::model::vec3::Vec3::new(0.0, 0.0, 0.0);
    extra.w = kisstime::model::vec3::Vec3::new(0.0, 0.0, 0.0);
    extra.s = kisstime::MotionState::Stationary;
    while big.balls.len() < 17 {
        let mut b = extra;
        b.r.y += 0.06 * big.balls.len() as f64;
        big.balls.push(b);
    }
    let Some(mut gpu) = engine(Backend::Gpu, "large_table") else {
        return;
    };
    let err = gpu
        .simulate(&table, params, limits, std::slice::from_ref(&big), false)
        .unwrap_err();
    assert!(
        matches!(&err, BatchError::Sink(Error::Unsupported(m)) if m.contains("at most 16")),
        "{err:?}"
    );
    let mut auto = engine(Backend::Auto, "large_table").unwrap();
    let mut cpu = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let one = std::slice::from_ref(&big);
    assert_eq!(
        auto.simulate(&table, params, limits, one, false).unwrap(),
        cpu.simulate(&table, params, limits, one, false).unwrap()
    );
    assert!(auto.take_notes().iter().any(|n| n.contains("17 balls")));
    assert!(auto.gpu().is_some(), "the GPU stays for later batches");
}
