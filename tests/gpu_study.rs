//! Shot studies on the GPU event loop (`kisstime::study::run` on a `gpu` [`ShotEngine`])
//! against the CPU f64 study on the reference's 2,000 strikes (`data/studies`):
//! - every outcome fraction (the intended ball potted, the scratch, each first-contact
//!   class) lies within the 95 % Wilson interval of the CPU's fraction;
//! - every sample has the CPU's first contact and potted balls and ends within 1e-6 m of
//!   it; where the event loop runs as exact SPIR-V (Vulkan: CI's lavapipe), every sample
//!   is the CPU's bit for bit;
//! - the first-contact study ends each sample at its first contact as the CPU's does.
//!
//! Without a GPU the tests print why they skip (`common::gpu_or_skip`'s convention: with
//! `KISSTIME_REQUIRE_GPU=1`, as in CI on lavapipe, a missing adapter fails).

mod common;

use std::path::{Path, PathBuf};

use kisstime::Precision;
use kisstime::engine::{Backend, ShotEngine};
use kisstime::io::strikes::read_sample_strikes;
use kisstime::simulate::CueStrike;
use kisstime::study::{
    Class, RunOptions, Sample, Samples, StudyConfig, Summary, Until, run, run_strikes, summarize,
    wilson,
};

fn dir() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/studies")).to_path_buf()
}

fn reference() -> (StudyConfig, Vec<CueStrike>) {
    let config = StudyConfig::read_reference(&dir().join("dev_scenario.json")).unwrap();
    let strikes = read_sample_strikes(&dir().join("dev_strikes.csv")).unwrap();
    (config, strikes.iter().map(|s| s.strike).collect())
}

fn open(test: &str) -> Option<ShotEngine> {
    common::gpu_or_skip(Precision::F64, test)?;
    Some(ShotEngine::new(Backend::Gpu, Precision::F64).expect("the event loop builds"))
}

/// `strikes` on `gpu`, with `progress`.
fn run_strikes_gpu(
    gpu: &mut ShotEngine,
    config: &StudyConfig,
    strikes: &[CueStrike],
    options: &RunOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<Sample>, kisstime::Error> {
    run(gpu, config, Samples::Given(strikes), options, progress)
}

/// The study's fractions, each as (name, count): the intended ball potted, the scratch,
/// and each first-contact class.
fn counts(config: &StudyConfig, samples: &[Sample]) -> Vec<(String, usize)> {
    let s = Summary::of(config, samples, Until::Rest);
    let mut out = vec![
        ("intended potted".to_owned(), s.intended_potted()),
        ("scratch".to_owned(), s.scratches),
    ];
    for (class, n) in &s.first {
        let name = match class {
            Class::Ball(k) => format!("first contact ball {}", config.balls[*k].id),
            other => format!("first contact {other:?}"),
        };
        out.push((name, *n));
    }
    out
}

#[test]
fn gpu_studies_lie_within_the_cpu_f64_studys_wilson_intervals() {
    let (config, strikes) = reference();
    let options = RunOptions::default();
    let cpu = run_strikes(&config, &strikes, &options, &mut |_, _| {}).unwrap();
    let n = cpu.len();
    let cpu_counts = counts(&config, &cpu);
    // whole shots and studies are f64 only (the engine refuses f32: F32_WHOLE_SHOTS)
    for precision in [Precision::F64] {
        let Some(mut gpu) = open("gpu_study") else {
            return;
        };
        let started = std::time::Instant::now();
        let got = run_strikes_gpu(&mut gpu, &config, &strikes, &options, &mut |_, _| {}).unwrap();
        let secs = started.elapsed().as_secs_f64();
        assert_eq!(got.len(), n);
        let mut outside = Vec::new();
        for ((name, k_cpu), (_, k_gpu)) in cpu_counts.iter().zip(counts(&config, &got)) {
            let (lo, hi) = wilson(*k_cpu, n);
            let p = k_gpu as f64 / n as f64;
            println!(
                "{}: {name}: GPU {k_gpu}, CPU {k_cpu} (95 % interval {:.4}..{:.4})",
                precision.name(),
                lo,
                hi
            );
            if !(lo..=hi).contains(&p) {
                outside.push(format!("{name}: GPU {p:.4}, CPU interval {lo:.4}..{hi:.4}"));
            }
        }
        assert!(outside.is_empty(), "{}: {outside:?}", precision.name());
        // sample by sample
        let (mut first, mut potted, mut near) = (0, 0, 0);
        let mut worst = 0.0f64;
        for (g, c) in got.iter().zip(&cpu) {
            first += usize::from(g.first == c.first);
            potted += usize::from(
                g.potted
                    .iter()
                    .map(|p| (p.ball, p.pocket))
                    .eq(c.potted.iter().map(|p| (p.ball, p.pocket))),
            );
            let d = (g.cue_final.0 - c.cue_final.0).hypot(g.cue_final.1 - c.cue_final.1);
            worst = worst.max(d);
            near += usize::from(d <= 1e-6);
        }
        let events: usize = got.iter().map(|s| s.n_events).sum();
        let identical = got.iter().zip(&cpu).filter(|(g, c)| g == c).count();
        let exact = gpu.gpu().is_some_and(|g| g.exact());
        println!(
            "{}: {n} samples, {events} events in {secs:.2} s; the CPU's first contact {first}, \
             potted balls {potted}, cue ball within 1e-6 m {near} (farthest {worst:.2e} m); \
             {identical} bit for bit (exact SPIR-V: {exact})",
            precision.name()
        );
        assert_eq!((first, potted, near), (n, n, n), "f64 samples differ");
        if exact {
            assert_eq!(identical, n, "samples the CPU's bit for bit");
        }
    }
}

#[test]
fn the_first_contact_study_ends_each_sample_at_its_first_contact_as_on_the_cpu() {
    let (config, strikes) = reference();
    let strikes = &strikes[..300];
    let options = RunOptions {
        until: Until::FirstContact,
        ..RunOptions::default()
    };
    let cpu = run_strikes(&config, strikes, &options, &mut |_, _| {}).unwrap();
    let Some(mut gpu) = open("gpu_study_first_contact") else {
        return;
    };
    let mut progress = Vec::new();
    let got = run_strikes_gpu(&mut gpu, &config, strikes, &options, &mut |d, n| {
        progress.push((d, n))
    })
    .unwrap();
    assert_eq!(progress.last(), Some(&(300, 300)));
    for (k, (g, c)) in got.iter().zip(&cpu).enumerate() {
        // every number bit for bit (`{:?}` writes each f64 exactly): the device's watch
        // keeps the cue ball's state and the clock before the contact as the CPU sees them
        assert_eq!(format!("{g:?}"), format!("{c:?}"), "sample {k}");
        assert_eq!(g.first, c.first, "sample {k}");
        assert_eq!(g.n_events, c.n_events, "sample {k}");
        assert_eq!(g.cut, c.cut, "sample {k}");
        assert_eq!(
            g.potted.iter().map(|p| p.ball).collect::<Vec<_>>(),
            c.potted.iter().map(|p| p.ball).collect::<Vec<_>>(),
            "sample {k}"
        );
        for (a, b) in [
            (g.first_t, c.first_t),
            (g.duration, c.duration),
            (g.cue_final.0, c.cue_final.0),
            (g.cue_final.1, c.cue_final.1),
            (g.contact_speed, c.contact_speed),
        ] {
            assert!(
                (a - b).abs() <= 1e-9 || (a.is_nan() && b.is_nan()),
                "sample {k}: GPU {a}, CPU {b}"
            );
        }
        assert!(
            (g.cut_angle - c.cut_angle).abs() <= 1e-6
                || (g.cut_angle.is_nan() && c.cut_angle.is_nan()),
            "sample {k}: cut angle GPU {}, CPU {}",
            g.cut_angle,
            c.cut_angle
        );
    }
}

#[test]
fn a_refused_strike_is_the_error_of_its_sample() {
    let (config, strikes) = reference();
    let mut strikes = strikes[..5].to_vec();
    strikes[3].a = 0.9;
    strikes[3].b = 0.9;
    let Some(mut gpu) = open("gpu_study_bad_strike") else {
        return;
    };
    let err = run_strikes_gpu(
        &mut gpu,
        &config,
        &strikes,
        &RunOptions::default(),
        &mut |_, _| {},
    )
    .unwrap_err();
    assert!(
        matches!(err, kisstime::Error::Input(_)) && err.to_string().contains("sample 3"),
        "{err}"
    );
}

/// The watch itself (`ShotEngine::simulate_with` with `BatchOptions::watch`) is the same on
/// both backends: every first contact (its number and event, the cue ball's state and the
/// clock before it, the centres after it), every pot, the watched ball's final state and
/// the outcome, to rest and stopping at the first contact; the counts and agents exactly,
/// the numbers within 1e-9 (lavapipe's f64 rounds a few of them differently after many
/// events).
#[test]
fn the_watch_is_the_same_on_both_backends() {
    use kisstime::simulate::{BallState, BatchOptions, Watch, WatchOptions};
    let (config, strikes) = reference();
    let strikes = &strikes[..300];
    let Some(mut gpu) = open("gpu_watch") else {
        return;
    };
    let mut cpu = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let initial = config.initial();
    for stop in [false, true] {
        let options = BatchOptions {
            check_layout: false,
            watch: Some(WatchOptions {
                cue: config.cue,
                stop_at_first_contact: stop,
                // to rest, the rules' facts too
                facts: !stop,
            }),
            ..BatchOptions::default()
        };
        let input = |k: usize, balls: &mut Vec<BallState>| {
            balls.clear();
            balls.extend_from_slice(&initial);
            Ok(Some((config.cue, strikes[k])))
        };
        let mut both = Vec::new();
        for engine in [&mut cpu, &mut gpu] {
            let mut runs = Vec::new();
            engine
                .simulate_with(
                    &config.table,
                    config.params,
                    &options,
                    300,
                    input,
                    |chunk| {
                        for t in chunk.iter() {
                            let w = t.watch.expect("watched");
                            let watch = Watch {
                                first: w.first,
                                pots: w.pots.to_vec(),
                                facts: w.facts.copied(),
                            };
                            runs.push((watch, t.balls.to_vec(), t.outcome));
                        }
                        Ok::<(), kisstime::Error>(())
                    },
                )
                .unwrap();
            both.push(runs);
        }
        let (c, g) = (&both[0], &both[1]);
        assert_eq!(c.len(), 300);
        let contacts = c.iter().filter(|r| r.0.first.is_some()).count();
        assert!(contacts > 250, "{contacts} first contacts");
        for (k, (a, b)) in c.iter().zip(g).enumerate() {
            let at = format!("stop {stop}: table {k}");
            let agents = |w: &Watch| {
                let first = w
                    .first
                    .map(|f| (f.number, f.event.kind, f.event.ball, f.event.other));
                let pots: Vec<_> = w.pots.iter().map(|(n, e)| (*n, e.ball, e.other)).collect();
                (first, pots)
            };
            assert_eq!(agents(&a.0), agents(&b.0), "{at}");
            // the rules' facts: every count and ball exactly, the times within 1e-9
            assert_eq!(a.0.facts.is_some(), !stop, "{at}");
            if let (Some(x), Some(y)) = (a.0.facts, b.0.facts) {
                let discrete = |f: &kisstime::simulate::ShotFacts| {
                    (
                        f.any_ball_ball,
                        f.first_ball.map(|b| b.1),
                        f.cushion_after_first,
                        f.at_cushion,
                        f.pocketed,
                        f.pocket_of,
                        f.second_ball_t.is_some(),
                        f.cue_cushions,
                    )
                };
                assert_eq!(discrete(&x), discrete(&y), "{at}: the rules' facts");
                let times = |f: &kisstime::simulate::ShotFacts| {
                    [
                        f.first_ball.map_or(0.0, |b| b.0),
                        f.second_ball_t.unwrap_or(0.0),
                    ]
                };
                for (s, t) in times(&x).into_iter().zip(times(&y)) {
                    assert!((s - t).abs() <= 1e-9, "{at}: fact times CPU {s}, GPU {t}");
                }
            } else {
                assert_eq!(b.0.facts.is_some(), !stop, "{at}: GPU facts");
            }
            assert_eq!((a.2.n_events, a.2.cut), (b.2.n_events, b.2.cut), "{at}");
            let reals = |r: &(Watch, Vec<BallState>, kisstime::simulate::Outcome)| {
                let mut v = vec![r.2.t_end, r.1[0].r.x, r.1[0].r.y];
                if let Some(f) = r.0.first {
                    let before = f.cue_before;
                    v.extend([f.event.t, f.t0, f.cue_after.x, f.cue_after.y]);
                    v.extend([f.other_after.x, f.other_after.y, before.r.x, before.v.y]);
                }
                v.extend(r.0.pots.iter().map(|(_, e)| e.t));
                v
            };
            for (x, y) in reals(a).into_iter().zip(reals(b)) {
                assert!((x - y).abs() <= 1e-9, "{at}: CPU {x}, GPU {y}");
            }
        }
    }
}

/// A study judged by a game's rules (`[game]`) on the GPU: the GPU's watch keeps the
/// rules' facts (its `observe_facts`, the twin of `ShotFacts::observe`), so every sample's
/// verdict equals the CPU's: 8-ball with a call on the reference strikes, and
/// three-cushion on `data/carom`'s shots (points and misses, pooltool's own `is_point`).
#[test]
fn game_verdicts_on_the_gpu_are_the_cpus() {
    let Some(mut gpu) = open("gpu_game_study") else {
        return;
    };
    let (config, strikes) = reference();
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/study.toml"))
        .unwrap();
    let game = StudyConfig::parse(
        &format!(
            "{text}\n[game]\nrules = \"8-ball\"\nhittable = [1, 2, 3, 4, 5, 7]\nball_call = 7\n\
             pocket_call = \"lb\"\n"
        ),
        "study.toml",
        None,
    )
    .unwrap();
    let _ = config;
    let options = RunOptions {
        until: Until::Rest,
        limits: kisstime::simulate::Limits::default(),
    };
    let strikes = &strikes[..400];
    let on_gpu = run_strikes_gpu(&mut gpu, &game, strikes, &options, &mut |_, _| {}).unwrap();
    let mut cpu = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let on_cpu = run(
        &mut cpu,
        &game,
        Samples::Given(strikes),
        &options,
        &mut |_, _| {},
    )
    .unwrap();
    let verdicts = |s: &[Sample]| s.iter().map(|s| s.verdict).collect::<Vec<_>>();
    assert!(on_cpu.iter().all(|s| s.verdict.is_some()));
    assert_eq!(verdicts(&on_gpu), verdicts(&on_cpu), "8-ball verdicts");
    let kept = on_cpu
        .iter()
        .filter(|s| s.verdict.is_some_and(|v| !v.turn_over))
        .count();
    assert!(kept > 100 && kept < 350, "{kept} kept the table");
}

/// Three-cushion on the GPU: `data/carom`'s 40 shots (pooltool's own points and misses)
/// watched with the rules' facts on the GPU score exactly where pooltool's `is_point` did.
#[test]
fn three_cushion_points_on_the_gpu_are_pooltools() {
    use kisstime::game::{Context, Played, Rules};
    use kisstime::io::shot_set::{read_shots, read_table};
    use kisstime::simulate::{BatchOptions, WatchOptions};
    let Some(mut gpu) = open("gpu_three_cushion") else {
        return;
    };
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/carom");
    let params = kisstime::io::physics::read_physics(&dir.join("physics.toml")).unwrap();
    let table = read_table(&dir).unwrap();
    let shots = read_shots(&dir, params.ball.r).unwrap();
    let text = std::fs::read_to_string(dir.join("shots.csv")).unwrap();
    let mut lines = text.lines();
    let col = lines
        .next()
        .unwrap()
        .split(',')
        .position(|h| h == "point")
        .unwrap();
    let points: Vec<bool> = lines.map(|l| l.split(',').nth(col) == Some("1")).collect();
    assert!(
        shots.iter().all(|s| s.cue == 0),
        "the white is every shot's first ball"
    );
    let options = BatchOptions {
        watch: Some(WatchOptions {
            cue: 0,
            stop_at_first_contact: false,
            facts: true,
        }),
        ..BatchOptions::default()
    };
    let input = |k: usize, balls: &mut Vec<kisstime::simulate::BallState>| {
        balls.clear();
        balls.extend_from_slice(&shots[k].balls);
        Ok(Some((0, shots[k].strike)))
    };
    let ids = [0i64, 1, 2];
    let mut scored = Vec::new();
    gpu.simulate_with(&table, params, &options, shots.len(), input, |chunk| {
        for t in chunk.iter() {
            let facts = t
                .watch
                .and_then(|w| w.facts)
                .expect("the GPU kept the facts");
            let played = Played {
                ids: &ids,
                start: &shots[t.table].balls,
                cue: 0,
                facts,
            };
            let v = Rules::ThreeCushion
                .judge_played(&played, &Context::default())
                .unwrap();
            scored.push(!v.turn_over);
        }
        Ok::<(), kisstime::Error>(())
    })
    .unwrap();
    assert_eq!(scored, points);
    assert!(points.iter().filter(|&&p| p).count() >= 5);
}

/// Snooker on the GPU: `examples/snooker.toml` (on the reds, six balls of the snooker
/// table), 300 noisy samples judged from the GPU watch's facts — every verdict, points and
/// foul points included, is the CPU's; and called on the black, every sample a foul worth
/// 7 on both.
#[test]
fn snooker_verdicts_on_the_gpu_are_the_cpus() {
    let Some(mut gpu) = open("gpu_snooker_study") else {
        return;
    };
    let text = include_str!("../examples/snooker.toml");
    let (head, _) = text.split_once("\n[game]").unwrap();
    let options = RunOptions {
        until: Until::Rest,
        limits: kisstime::simulate::Limits::default(),
    };
    let mut cpu = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    for (game, samples) in [
        (&text[head.len()..], 300),
        (
            "[game]\nrules = \"snooker\"\nhittable = [\"pink\", \"black\"]\nball_call = \"black\"\n",
            60,
        ),
    ] {
        let config = StudyConfig::parse(&format!("{head}\n{game}"), "snooker.toml", None).unwrap();
        let drawn = || Samples::Drawn {
            sigma: &config.noise,
            seed: 9,
            range: 0..samples,
        };
        let on_gpu = run(&mut gpu, &config, drawn(), &options, &mut |_, _| {}).unwrap();
        let on_cpu = run(&mut cpu, &config, drawn(), &options, &mut |_, _| {}).unwrap();
        let verdicts = |s: &[Sample]| s.iter().map(|s| s.verdict.unwrap()).collect::<Vec<_>>();
        let (g, c) = (verdicts(&on_gpu), verdicts(&on_cpu));
        assert_eq!(g, c, "{game}");
        let points: u32 = c.iter().map(|v| v.points).sum();
        let fouls: u32 = c.iter().map(|v| v.foul_points).sum();
        println!("{game}: {points} points scored, {fouls} foul points");
        if game.contains("ball_call") {
            assert!(c.iter().all(|v| v.foul_points == 7), "{c:?}");
        } else {
            assert!(
                points > 100,
                "{points} points: the red drops on most samples"
            );
        }
    }
}

/// One position struck many ways (`CheckedTables::one_position`, a study's chunks): the
/// chunk crosses the bus as the position's block and each table's strike block, and the
/// shader's `expand_tables` lays the tables out; the runs are the whole blocks' bit for
/// bit — watched (with the rules' facts) and final states alone, shared and per-table
/// physics, strikes not played (V0 = 0) and tables cut before their first event. A chunk
/// whose tables differ (a ball moved, another ball struck) is packed whole, with the same
/// runs.
#[test]
fn one_position_chunks_laid_out_on_the_device_give_the_whole_blocks_runs() {
    use kisstime::gpu::{CheckedTables, GpuOutput};
    use kisstime::simulate::{BallState, Limits, Physics, WatchOptions};
    let (config, strikes) = reference();
    let Some(mut engine) = open("gpu_one_position") else {
        return;
    };
    let gpu = engine.gpu().expect("a GPU engine");
    gpu.max_tables_per_chunk = 128;
    let n = 600;
    let mut strikes = strikes[..n].to_vec();
    strikes[5].v0 = 0.0;
    let initial = config.initial();
    let cue = config.cue;
    let mut params: Vec<_> = (0..n).map(|_| config.params).collect();
    for (k, p) in params.iter_mut().enumerate() {
        p.ball.u_r *= 1.0 + 0.1 * (k % 7) as f64 / 7.0;
    }
    // table 300's position differs (a ball moved), table 450 strikes another ball
    let mut moved = initial.clone();
    let last = moved.len() - 1;
    moved[last].r.x += 0.05;
    let other = (cue + 1) % initial.len();
    let (moved, initial_ref, strikes) = (&moved, &initial, &strikes);
    let fill = |mixed: bool| {
        move |k: usize, balls: &mut Vec<BallState>| {
            balls.clear();
            balls.extend_from_slice(if mixed && k == 300 {
                moved
            } else {
                initial_ref
            });
            let ball = if mixed && k == 450 { other } else { cue };
            Ok(Some((ball, strikes[k])))
        }
    };
    let watch = WatchOptions {
        cue,
        stop_at_first_contact: false,
        facts: true,
    };
    for (mixed, max_events) in [(false, 5_000), (true, 5_000), (false, 0)] {
        let limits = Limits {
            max_events,
            ..Limits::default()
        };
        let fill = fill(mixed);
        for per_table in [false, true] {
            let physics = if per_table {
                Physics::PerTable(&params)
            } else {
                Physics::Shared(config.params)
            };
            let mut results = Vec::new();
            for one_position in [false, true] {
                let tables = CheckedTables {
                    fill: &fill,
                    n_tables: n,
                    max_balls: initial.len(),
                    one_position,
                    drawn: None,
                };
                let watched = gpu
                    .simulate_checked(
                        &config.table,
                        physics,
                        limits,
                        tables,
                        GpuOutput::Watch(watch),
                    )
                    .unwrap()
                    .1;
                let expanded_watched = gpu.expanded_chunks();
                let finals = gpu
                    .simulate_checked(&config.table, physics, limits, tables, GpuOutput::Finals)
                    .unwrap()
                    .0;
                let expanded = (expanded_watched, gpu.expanded_chunks());
                results.push((watched, finals, expanded));
            }
            let at =
                format!("mixed {mixed}, max_events {max_events}, per-table physics {per_table}");
            let (whole, laid) = (&results[0], &results[1]);
            assert_eq!(whole.2, (0, 0), "{at}: nothing expanded without the hint");
            // 5 chunks of 128 tables; with a moved ball and another ball struck, two of
            // them are packed whole
            let want = if mixed { 3 } else { 5 };
            assert_eq!(laid.2, (want, want), "{at}: chunks laid out on the device");
            assert_eq!(whole.0.len(), n);
            assert_eq!(whole.1.len(), n);
            for k in 0..n {
                assert_eq!(
                    format!("{:?}", whole.0[k]),
                    format!("{:?}", laid.0[k]),
                    "{at}: table {k}'s watched run"
                );
                assert_eq!(
                    format!("{:?}", whole.1[k]),
                    format!("{:?}", laid.1[k]),
                    "{at}: table {k}'s final states"
                );
            }
            // a chunk of one table: one block and its strike block fill more than its
            // I/O block would
            let mut one = |one_position| {
                let tables = CheckedTables {
                    fill: &fill,
                    n_tables: 1,
                    max_balls: initial.len(),
                    one_position,
                    drawn: None,
                };
                let run =
                    gpu.simulate_checked(&config.table, physics, limits, tables, GpuOutput::Finals);
                (format!("{:?}", run.unwrap().0), gpu.expanded_chunks())
            };
            let (a, b) = (one(false), one(true));
            assert_eq!((a.0, a.1, b.1), (b.0, 0, 1), "{at}: a chunk of one table");
            let events: usize = laid.1.iter().map(|r| r.outcome.n_events).sum();
            if max_events == 0 {
                assert!(
                    laid.1.iter().all(|r| r.outcome.cut.is_some()),
                    "{at}: all cut"
                );
            } else {
                assert!(events > 10 * n, "{at}: {events} events");
                assert_eq!(
                    laid.1[5].outcome.n_events, 0,
                    "{at}: V0 = 0 plays no strike"
                );
            }
        }
    }
}

/// Several tables a workgroup (4 of 64 threads: each table's watch written by its own
/// thread 0) give the one-table workgroups' samples bit for bit, to rest and to the first
/// contact: 301 reference strikes (the last workgroup has empty slots).
#[test]
fn several_tables_a_workgroup_watch_as_one_table_does() {
    let (config, strikes) = reference();
    let strikes = &strikes[..301];
    let Some(mut engine) = open("gpu_study tables a workgroup") else {
        return;
    };
    for until in [Until::Rest, Until::FirstContact] {
        let options = RunOptions {
            until,
            ..RunOptions::default()
        };
        let mut runs = Vec::new();
        for tables in [1, 4] {
            let gpu = engine.gpu().expect("a GPU engine");
            gpu.set_tables_per_group(tables).unwrap();
            assert_eq!(gpu.tables_per_group(16).unwrap(), tables);
            let samples =
                run_strikes_gpu(&mut engine, &config, strikes, &options, &mut |_, _| {}).unwrap();
            // every number bit for bit (`{:?}` writes each f64 exactly; NaN included)
            runs.push(format!("{samples:?}"));
        }
        assert!(runs[0] == runs[1], "{until:?}: 4 tables a workgroup differ");
    }
}

/// A study's samples drawn on the device (`BatchOptions::drawn`: `study::run` of
/// `Samples::Drawn`, the shader's `expand_drawn` drawing each sample's noisy strike from
/// Philox and playing it) are the CPU study's — bit for bit where the event loop runs as
/// exact SPIR-V (Vulkan: CI's lavapipe), else the same first contacts and pots — to rest
/// and to the first contact, over several engine chunks and device chunks, and over a
/// range of sample ids that crosses 2³² (the id's high word). Every chunk was drawn on
/// the device.
#[test]
fn a_study_drawn_on_the_device_is_the_cpus_sample_for_sample() {
    let config = StudyConfig::builtin();
    let Some(mut gpu) = open("gpu_drawn_study") else {
        return;
    };
    gpu.set_gpu_chunk_tables(Some(400));
    gpu.gpu().expect("a GPU engine").max_tables_per_chunk = 128;
    let exact = gpu.gpu().is_some_and(|g| g.exact());
    let mut cpu = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let edge = 1usize << 32;
    for (until, range) in [
        (Until::Rest, 1000..2000),
        (Until::FirstContact, 0..700),
        (Until::Rest, edge - 300..edge + 300),
    ] {
        let options = RunOptions {
            until,
            ..RunOptions::default()
        };
        let drawn = || Samples::Drawn {
            sigma: &config.noise,
            seed: 0x1234_5678_9abc_def0,
            range: range.clone(),
        };
        let on_gpu = run(&mut gpu, &config, drawn(), &options, &mut |_, _| {}).unwrap();
        let drawn_chunks = gpu.gpu().expect("a GPU engine").drawn_chunks();
        let on_cpu = run(&mut cpu, &config, drawn(), &options, &mut |_, _| {}).unwrap();
        let at = format!("{until:?}, samples {range:?}");
        assert_eq!(on_gpu.len(), range.len(), "{at}");
        // the last engine chunk's device chunks were all drawn
        assert!(drawn_chunks >= 1, "{at}: {drawn_chunks} chunks drawn");
        let mut differ = 0;
        for (k, (g, c)) in on_gpu.iter().zip(&on_cpu).enumerate() {
            assert_eq!(g.strike, c.strike, "{at}: sample {k}'s strike");
            assert_eq!(
                (g.first, g.potted.len()),
                (c.first, c.potted.len()),
                "{at}: sample {k}"
            );
            differ += usize::from(format!("{g:?}") != format!("{c:?}"));
        }
        println!(
            "{at}: {differ} of {} samples differ (exact: {exact})",
            range.len()
        );
        if exact {
            assert_eq!(differ, 0, "{at}: exact SPIR-V gives the CPU's samples");
            // the summary counted chunk by chunk, no sample kept, is the CPU samples'
            let summary = summarize(&mut gpu, &config, drawn(), &options, &mut |_, _| {});
            assert_eq!(
                summary.unwrap(),
                Summary::of(&config, &on_cpu, until),
                "{at}: the summary without the samples"
            );
        }
        // the strikes were played: most samples hit a ball
        let hit = on_gpu
            .iter()
            .filter(|s| matches!(s.first, kisstime::study::FirstContact::Ball(_)))
            .count();
        assert!(hit * 10 > range.len() * 9, "{at}: {hit} hit a ball");
    }
}

/// `BatchOptions::drawn` is a description the engine checks: where the input gives other
/// strikes than the rule (here the reference's strikes, or the rule's strikes for every
/// table but the chunks' last ones), or physics that varies per table, no chunk is drawn
/// on the device and the runs are the input's, the same as without the description; where
/// it gives the rule's, the chunks are drawn on the device with the same runs, watched and
/// final states alike.
#[test]
fn a_drawn_description_the_input_does_not_match_is_not_used() {
    use kisstime::simulate::{BallState, BatchOptions, Physics, WatchOptions};
    use kisstime::study::noise::drawn;
    let (config, strikes) = reference();
    let Some(mut gpu) = open("gpu_drawn_mismatch") else {
        return;
    };
    gpu.set_gpu_chunk_tables(Some(100));
    let exact = gpu.gpu().is_some_and(|g| g.exact());
    let n = 300;
    let initial = config.initial();
    let description = drawn(&config, &config.noise, 5, 0).expect("drawn");
    let r = config.params.ball.r;
    let params: Vec<_> = (0..n).map(|_| config.params).collect();
    let run_with = |gpu: &mut ShotEngine,
                    (drawn_on, watched): (bool, bool),
                    per_table: bool,
                    strike: &(dyn Fn(usize) -> CueStrike + Sync)| {
        let options = BatchOptions {
            check_layout: false,
            record_events: false,
            watch: watched.then_some(WatchOptions {
                cue: config.cue,
                stop_at_first_contact: false,
                facts: false,
            }),
            one_position: true,
            drawn: drawn_on.then_some(description),
            ..BatchOptions::default()
        };
        let input = |k: usize, balls: &mut Vec<BallState>| {
            balls.clear();
            balls.extend_from_slice(&initial);
            Ok(Some((config.cue, strike(k))))
        };
        let physics = if per_table {
            Physics::PerTable(&params)
        } else {
            Physics::Shared(config.params)
        };
        let mut out = Vec::new();
        gpu.simulate_with(&config.table, physics, &options, n, input, |chunk| {
            for t in chunk.iter() {
                out.push(format!("{:?} {:?}", t.balls, t.outcome));
            }
            Ok::<(), kisstime::Error>(())
        })
        .unwrap();
        let drawn_chunks = gpu.gpu().expect("a GPU engine").drawn_chunks();
        (out, drawn_chunks)
    };
    let given = |k: usize| strikes[k];
    let rule_but_last = |k: usize| {
        if k % 100 == 99 {
            strikes[k]
        } else {
            description.strike(r, k)
        }
    };
    let rule = |k: usize| description.strike(r, k);
    for (name, strike, per_table, drawn_used) in [
        (
            "the reference's strikes",
            &given as &(dyn Fn(usize) -> CueStrike + Sync),
            false,
            false,
        ),
        (
            "the rule but each chunk's last table",
            &rule_but_last,
            false,
            false,
        ),
        ("the rule, per-table physics", &rule, true, false),
        ("the rule", &rule, false, true),
    ] {
        // watched (a study's) and final states alone
        for watched in [true, false] {
            let name = format!("{name}, watched {watched}");
            let (with, chunks) = run_with(&mut gpu, (true, watched), per_table, strike);
            let (without, none) = run_with(&mut gpu, (false, watched), per_table, strike);
            assert_eq!(none, 0, "{name}: nothing drawn without a description");
            assert_eq!(chunks > 0, drawn_used, "{name}: {chunks} chunks drawn");
            assert_eq!(with.len(), n);
            // the device's draws round as the host's only as exact SPIR-V
            if exact || !drawn_used {
                for (k, (a, b)) in with.iter().zip(&without).enumerate() {
                    assert_eq!(a, b, "{name}: table {k}");
                }
            }
        }
    }
}
