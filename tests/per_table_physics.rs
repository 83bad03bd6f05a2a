//! Per-table physics (issue 25): one batch whose tables each have their own parameters
//! (`Physics::PerTable`) gives, table by table, exactly the runs of each table simulated
//! alone with its parameters — on the CPU, and on the GPU in f64 (where a GPU exists;
//! lavapipe in CI) — and a bad table's parameters are an error naming that table.

mod common;

use kisstime::Precision;
use kisstime::engine::{AutoRule, Backend, ShotEngine};
use kisstime::gpu::GpuShot;
use kisstime::io::shot_set::{read_shots, read_table};
use kisstime::simulate::{BallState, BatchError, Limits, Physics, SimParams, Table};

/// Ordinary shots of the reference set, each with parameters of its own: the cloth, the
/// cushions and the balls' restitution drawn in ±10 % of pooltool's defaults, and some with
/// another ball size (their balls' centres at the new height).
fn varied(range: std::ops::Range<usize>) -> (Table, Vec<GpuShot>, Vec<SimParams>) {
    let dir = common::fullshots_dir();
    let table = read_table(&dir).unwrap();
    let base = SimParams::default();
    let shots = read_shots(&dir, base.ball.r).unwrap();
    let mut params = Vec::new();
    let mut inputs = Vec::new();
    for (j, s) in shots[range].iter().enumerate() {
        let f = |k: usize| 1.0 + 0.1 * (((j * 7 + k * 3) % 11) as f64 / 5.0 - 1.0);
        let mut p = base;
        p.ball.u_r *= f(0);
        p.ball.u_s *= f(1);
        p.ball.e_c = (p.ball.e_c * f(2)).min(1.0);
        p.ball.e_b = (p.ball.e_b * f(3)).min(1.0);
        p.ball.f_c *= f(4);
        if j % 5 == 4 {
            // a slightly smaller ball: every ball's centre at its height
            p.ball.r *= 0.98;
            p.ball.u_sp *= 0.98;
        }
        let balls: Vec<BallState> = s
            .balls
            .iter()
            .map(|b| {
                let mut b = *b;
                b.r.z = p.ball.r;
                b
            })
            .collect();
        params.push(p);
        inputs.push(GpuShot {
            balls,
            strike: Some((s.cue, s.strike)),
        });
    }
    (table, inputs, params)
}

fn each_alone(
    engine: &mut ShotEngine,
    table: &Table,
    inputs: &[GpuShot],
    params: &[SimParams],
) -> Vec<kisstime::gpu::GpuRun> {
    inputs
        .iter()
        .zip(params)
        .map(|(shot, p)| {
            engine
                .simulate(
                    table,
                    *p,
                    Limits::default(),
                    std::slice::from_ref(shot),
                    true,
                )
                .unwrap()
                .remove(0)
        })
        .collect()
}

#[test]
fn per_table_physics_on_the_cpu_is_each_table_alone() {
    let (table, inputs, params) = varied(100..160);
    let mut cpu = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let batch = cpu
        .simulate(&table, &params, Limits::default(), &inputs, true)
        .unwrap();
    let alone = each_alone(&mut cpu, &table, &inputs, &params);
    assert_eq!(batch, alone);
    // and the parameters matter: with the defaults for all, other runs
    let shared = cpu
        .simulate(
            &table,
            SimParams::default(),
            Limits::default(),
            &inputs,
            true,
        )
        .unwrap();
    let differ = shared.iter().zip(&batch).filter(|(a, b)| a != b).count();
    assert!(
        differ > 50,
        "{differ} of 60 tables differ from the defaults'"
    );
}

#[test]
fn a_bad_tables_parameters_name_that_table() {
    let (table, inputs, mut params) = varied(100..110);
    params[3].ball.e_c = 1.5;
    let mut cpu = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    match cpu.simulate(&table, &params, Limits::default(), &inputs, false) {
        Err(BatchError::Table { table: 3, error }) => {
            assert!(error.to_string().contains("e_c"), "{error}")
        }
        other => panic!("{other:?}"),
    }
    // fewer sets than tables
    let few = &params[..2];
    match cpu.simulate(&table, few, Limits::default(), &inputs, false) {
        Err(BatchError::Table { table: 2, error }) => {
            assert!(error.to_string().contains("no physics"), "{error}")
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(
        Physics::from(&params).check(10).unwrap_err().0,
        3,
        "Physics::check names the first bad table"
    );
}

#[test]
fn per_table_physics_on_the_gpu_is_each_table_alone_and_the_cpus_sequence() {
    if common::gpu_or_skip(Precision::F64, "per-table physics on the GPU").is_none() {
        return;
    }
    let (table, inputs, params) = varied(100..124);
    let mut gpu = ShotEngine::with_rule(Backend::Gpu, Precision::F64, AutoRule::AnyGpu).unwrap();
    // small GPU chunks: the per-table blocks follow the chunks
    gpu.set_gpu_chunk_tables(Some(7));
    let batch = gpu
        .simulate(&table, &params, Limits::default(), &inputs, true)
        .unwrap();
    assert!(gpu.describe().starts_with("gpu"), "{}", gpu.describe());
    let alone = each_alone(&mut gpu, &table, &inputs, &params);
    for (k, (b, a)) in batch.iter().zip(&alone).enumerate() {
        assert!(
            b == a,
            "table {k}: the batch's run differs from the table alone"
        );
    }
    let mut cpu = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let on_cpu = cpu
        .simulate(&table, &params, Limits::default(), &inputs, true)
        .unwrap();
    for (k, (g, c)) in batch.iter().zip(&on_cpu).enumerate() {
        let seq = |r: &kisstime::gpu::GpuRun| {
            r.events
                .iter()
                .map(|e| (e.event.kind, e.event.ball, e.event.other))
                .collect::<Vec<_>>()
        };
        assert!(seq(g) == seq(c), "table {k}: other events than the CPU's");
        for (x, y) in g.events.iter().zip(&c.events) {
            assert!((x.event.t - y.event.t).abs() < 1e-9, "table {k}");
        }
    }
}
