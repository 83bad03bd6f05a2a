//! Shot studies (`kisstime shots`): every sample from the strike to rest on the event loop.
//! Reproducibility (seeds, threads, chunks, prefixes), the first-contact mode against the
//! full run, an independent replay of every sample through `kisstime::simulate::simulate`,
//! the built-in study's mix and the summary's bookkeeping, zero noise, bad scenario files,
//! and the command line (summary, JSON, CSV, PNG, strike files, bad input).

mod common;

use std::path::{Path, PathBuf};

use kisstime::Error;
use kisstime::model::table::Table;
use kisstime::simulate::{
    BallState, CueStrike, Cut, Event, EventKind, Limits, SimParams, simulate,
};
use kisstime::study::reference::{first_contact_word, potted_field};
use kisstime::study::{
    BUILTIN_TOML, CHUNK, FirstContact, Noise, Pot, Result4, RunOptions, Sample, StudyConfig,
    Summary, Until, noisy_strike, run_strikes, run_study, wilson,
};

// ---------------------------------------------------------------- helpers

const REST: RunOptions = RunOptions {
    until: Until::Rest,
    limits: Limits {
        max_events: 10_000,
        max_time: 600.0,
    },
};

const FIRST: RunOptions = RunOptions {
    until: Until::FirstContact,
    ..REST
};

fn study(
    config: &StudyConfig,
    sigma: &Noise,
    n: usize,
    seed: u64,
    options: &RunOptions,
) -> Vec<Sample> {
    run_study(config, sigma, n, seed, options, &mut |_, _| {}).unwrap()
}

/// Samples compared exactly: `Debug` prints every f64 so that it reads back bit for bit,
/// and NaN (no contact point, no cut angle) compares equal to NaN.
fn fingerprint(samples: &[Sample]) -> Vec<String> {
    samples.iter().map(|s| format!("{s:?}")).collect()
}

/// Equal as f64 bits: NaN matches NaN, 0.0 does not match -0.0.
fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits()
}

/// The built-in study's text with some of it replaced (each `from` must be there).
fn edited(replacements: &[(&str, &str)]) -> String {
    let mut text = BUILTIN_TOML.to_owned();
    for (from, to) in replacements {
        assert!(text.contains(from), "{from:?} is not in the built-in study");
        text = text.replacen(from, to, 1);
    }
    text
}

/// The built-in study with some of its text replaced.
fn variant(replacements: &[(&str, &str)]) -> StudyConfig {
    StudyConfig::parse(&edited(replacements), "variant.toml", None).unwrap()
}

fn studies(path: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/studies")).join(path)
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn path_str(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `SAMPLE_COLUMNS` as `src/cli/report.rs` documents it (the binary's, not the library's).
fn sample_columns() -> &'static str {
    let src = include_str!("../src/cli/report.rs");
    let start = src
        .find("pub const SAMPLE_COLUMNS: &str = \"")
        .expect("src/cli/report.rs defines SAMPLE_COLUMNS")
        + "pub const SAMPLE_COLUMNS: &str = \"".len();
    let len = src[start..].find('"').unwrap();
    &src[start..start + len]
}

/// A CSV of the CLI as (header, rows of fields).
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(true)
        .from_path(path)
        .unwrap();
    let header = rdr.headers().unwrap().iter().map(str::to_owned).collect();
    let rows = rdr
        .records()
        .map(|r| r.unwrap().iter().map(str::to_owned).collect())
        .collect();
    (header, rows)
}

// ---------------------------------------------------------------- reproducibility

#[test]
fn same_seed_same_samples_whatever_the_threads_chunks_and_length() {
    let config = StudyConfig::builtin();
    let sigma = config.sigma();
    let n = CHUNK + 10;
    let in_pool = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut calls = Vec::new();
            let samples =
                run_study(&config, &sigma, n, 5, &REST, &mut |d, t| calls.push((d, t))).unwrap();
            assert_eq!(calls, vec![(CHUNK, n), (n, n)], "{threads} threads");
            fingerprint(&samples)
        })
    };
    let one = in_pool(1);
    let two = in_pool(2);
    assert_eq!(one.len(), n);
    assert!(one == two, "1 and 2 threads give different samples");
    // sample i depends on (seed, i) only: a shorter study is a prefix of a longer one
    let short = fingerprint(&study(&config, &sigma, 100, 5, &REST));
    assert_eq!(short, one[..100]);
    // the samples past the first chunk are those of a study of that many
    let mut calls = Vec::new();
    let chunk_and_one = run_study(&config, &sigma, CHUNK + 1, 5, &REST, &mut |d, t| {
        calls.push((d, t))
    })
    .unwrap();
    assert_eq!(calls, vec![(CHUNK, CHUNK + 1), (CHUNK + 1, CHUNK + 1)]);
    assert_eq!(fingerprint(&chunk_and_one), one[..CHUNK + 1]);
    // another seed gives other samples, and the samples are not all alike
    assert_ne!(fingerprint(&study(&config, &sigma, 100, 6, &REST)), short);
    assert!(short.iter().any(|s| *s != short[0]));
    // the strikes are the noise's
    for (i, s) in chunk_and_one.iter().enumerate().step_by(997) {
        assert_eq!(s.strike, noisy_strike(&config, &sigma, 5, i as u64));
    }
}

/// Runs `n` samples to rest and to the first contact and checks they agree; returns the
/// distinct first contacts.
fn check_first_contact_mode(
    config: &StudyConfig,
    sigma: &Noise,
    n: usize,
    seed: u64,
) -> std::collections::HashSet<FirstContact> {
    let rest = study(config, sigma, n, seed, &REST);
    let first = study(config, sigma, n, seed, &FIRST);
    let mut seen = std::collections::HashSet::new();
    for (i, (r, f)) in rest.iter().zip(&first).enumerate() {
        assert_eq!(r.strike, f.strike, "sample {i}");
        assert_eq!(r.first, f.first, "sample {i}");
        assert!(same(r.first_t, f.first_t), "sample {i}: {r:?} vs {f:?}");
        for (a, b) in [
            (r.contact_cue.0, f.contact_cue.0),
            (r.contact_cue.1, f.contact_cue.1),
            (r.contact_speed, f.contact_speed),
            (r.contact_point.0, f.contact_point.0),
            (r.contact_point.1, f.contact_point.1),
            (r.cut_angle, f.cut_angle),
        ] {
            assert!(same(a, b), "sample {i}: {r:?} vs {f:?}");
        }
        assert!(f.n_events <= r.n_events, "sample {i}: {f:?} vs {r:?}");
        if matches!(
            f.first,
            FirstContact::Ball(_) | FirstContact::Cushion { .. }
        ) {
            // something always moves on after a contact: the run to rest goes further
            assert!(f.n_events < r.n_events, "sample {i}: {f:?} vs {r:?}");
        }
        match f.first {
            FirstContact::Pocket(p) => {
                assert_eq!(
                    f.potted,
                    vec![Pot {
                        ball: config.cue as u32,
                        pocket: p,
                        t: f.first_t
                    }],
                    "sample {i}"
                );
                assert_eq!(r.potted[0], f.potted[0], "sample {i}");
            }
            _ => assert!(f.potted.is_empty(), "sample {i}: {f:?}"),
        }
        if f.first != FirstContact::Nothing {
            // it stopped at the first contact
            assert!(same(f.duration, f.first_t), "sample {i}: {f:?}");
            assert!(f.cut.is_none(), "sample {i}: {f:?}");
        }
        seen.insert(f.first);
    }
    seen
}

#[test]
fn until_first_contact_agrees_with_the_full_run() {
    let config = StudyConfig::builtin();
    let sigma = config.sigma();
    // the study's own noise: the intended ball, and the screen when the hit is fuller
    let seen = check_first_contact_mode(&config, &sigma, 5000, 17);
    assert!(
        seen.contains(&FirstContact::Ball(config.intended as u32)),
        "{seen:?}"
    );
    assert!(seen.len() >= 2, "{seen:?}");
    // wide noise: cushions too
    let seen = check_first_contact_mode(&config, &sigma.scaled(30.0), 2000, 18);
    assert!(
        seen.iter()
            .any(|f| matches!(f, FirstContact::Cushion { .. })),
        "{seen:?}"
    );
}

// ---------------------------------------------------------------- independent replay

/// What the replay derives from the event list of one shot.
#[derive(Debug)]
struct Replay {
    first: FirstContact,
    first_t: f64,
    contact_cue: (f64, f64),
    potted: Vec<Pot>,
    cue_final: (f64, f64),
    n_events: usize,
    duration: f64,
    cut: Option<Cut>,
    strike_first: bool,
}

/// The cue ball's first contact by the rule of the reference: the first event after the
/// strike that involves the cue ball, other than its own sliding → rolling.
fn first_of(ev: &Event, cue: u32) -> Option<FirstContact> {
    let ball_ball = ev.kind == EventKind::BallBall;
    if ev.kind == EventKind::StickBall
        || ev.kind == EventKind::SlidingRolling
        || !(ev.ball == cue || ball_ball && ev.other == cue)
    {
        return None;
    }
    Some(match ev.kind {
        EventKind::BallBall => FirstContact::Ball(ev.ball + ev.other - cue),
        EventKind::BallLinearCushion => FirstContact::Cushion {
            circular: false,
            index: ev.other,
        },
        EventKind::BallCircularCushion => FirstContact::Cushion {
            circular: true,
            index: ev.other,
        },
        EventKind::BallPocket => FirstContact::Pocket(ev.other),
        _ => FirstContact::Stopped,
    })
}

fn replay(config: &StudyConfig, strike: CueStrike, limits: Limits) -> Replay {
    let balls: Vec<BallState> = config
        .balls
        .iter()
        .map(|b| BallState::at_rest(b.x, b.y, config.params.ball.r))
        .collect();
    let cue = config.cue;
    let mut r = Replay {
        first: FirstContact::Nothing,
        first_t: f64::NAN,
        contact_cue: (f64::NAN, f64::NAN),
        potted: Vec::new(),
        cue_final: (balls[cue].r.x, balls[cue].r.y),
        n_events: 0,
        duration: 0.0,
        cut: None,
        strike_first: false,
    };
    let mut seen = 0usize;
    let out = simulate(
        &config.table,
        config.params,
        limits,
        &balls,
        Some((cue, strike)),
        |ev, now| {
            if seen == 0 {
                r.strike_first = ev.kind == EventKind::StickBall && ev.ball == cue as u32;
            }
            seen += 1;
            if ev.kind == EventKind::BallPocket {
                r.potted.push(Pot {
                    ball: ev.ball,
                    pocket: ev.other,
                    t: ev.t,
                });
            }
            if r.first == FirstContact::Nothing
                && let Some(f) = first_of(ev, cue as u32)
            {
                r.first = f;
                r.first_t = ev.t;
                r.contact_cue = (now[cue].r.x, now[cue].r.y);
            }
            r.cue_final = (now[cue].r.x, now[cue].r.y);
            r.duration = ev.t;
        },
    )
    .unwrap();
    assert_eq!(out.n_events, seen);
    r.n_events = out.n_events;
    r.cut = out.cut;
    assert!(same(out.t_end, r.duration) || seen == 0);
    r
}

/// Checks every sample against its replay; returns the first contacts' kinds seen.
fn check_replays(config: &StudyConfig, samples: &[Sample], limits: Limits) -> Vec<String> {
    let r_ball = config.params.ball.r;
    let mut kinds = std::collections::BTreeSet::new();
    for (i, s) in samples.iter().enumerate() {
        let r = replay(config, s.strike, limits);
        let what = || format!("sample {i}: study {s:?}\nreplay {r:?}");
        assert!(r.strike_first || s.strike.v0 == 0.0, "{}", what());
        assert_eq!(s.potted, r.potted, "{}", what());
        assert!(same(s.cue_final.0, r.cue_final.0), "{}", what());
        assert!(same(s.cue_final.1, r.cue_final.1), "{}", what());
        assert_eq!(s.n_events, r.n_events, "{}", what());
        assert!(same(s.duration, r.duration), "{}", what());
        assert_eq!(s.cut, r.cut, "{}", what());
        assert_eq!(s.first, r.first, "{}", what());
        assert!(same(s.first_t, r.first_t), "{}", what());
        assert!(same(s.contact_cue.0, r.contact_cue.0), "{}", what());
        assert!(same(s.contact_cue.1, r.contact_cue.1), "{}", what());
        // the geometry of the contact
        let (cx, cy) = s.contact_cue;
        let (px, py) = s.contact_point;
        match s.first {
            FirstContact::Ball(k) => {
                assert_ne!(k as usize, config.cue, "{}", what());
                let d = (px - cx).hypot(py - cy);
                assert!((d - r_ball).abs() < 1e-6, "{d}: {}", what());
                assert!(s.cut_angle.abs() <= 90.0, "{}", what());
                assert!(s.contact_speed > 0.0, "{}", what());
            }
            FirstContact::Cushion { .. } => {
                let d = (px - cx).hypot(py - cy);
                assert!((d - r_ball).abs() < 1e-4, "{d}: {}", what());
                assert!(s.cut_angle.is_nan(), "{}", what());
                assert!(s.contact_speed > 0.0, "{}", what());
            }
            _ => {
                assert!(
                    px.is_nan() && py.is_nan() && s.cut_angle.is_nan(),
                    "{}",
                    what()
                );
            }
        }
        // a potted cue ball ends in its pocket
        if let Some(p) = s.pocket_of(config.cue) {
            let c = config.table.pockets[p].center;
            assert!(
                (s.cue_final.0 - c.x).hypot(s.cue_final.1 - c.y) < 1e-9,
                "{}",
                what()
            );
        }
        kinds.insert(match s.first {
            FirstContact::Ball(_) => "ball",
            FirstContact::Cushion { .. } => "cushion",
            FirstContact::Pocket(_) => "pocket",
            FirstContact::Stopped => "stopped",
            FirstContact::Nothing => "nothing",
        });
    }
    kinds.into_iter().map(str::to_owned).collect()
}

#[test]
fn every_sample_agrees_with_a_replay_through_simulate() {
    let config = StudyConfig::builtin();
    let sigma = config.sigma();
    let samples = study(&config, &sigma, 3000, 11, &REST);
    let kinds = check_replays(&config, &samples, REST.limits);
    assert!(kinds.contains(&"ball".to_owned()), "{kinds:?}");
    let pots = samples
        .iter()
        .filter(|s| s.pocket_of(config.intended).is_some())
        .count();
    let scratches = samples
        .iter()
        .filter(|s| s.pocket_of(config.cue).is_some())
        .count();
    assert!(
        pots > 0 && scratches > 0,
        "{pots} pots, {scratches} scratches"
    );

    // wide noise: other first contacts
    let wide = study(&config, &sigma.scaled(30.0), 1000, 12, &REST);
    let kinds = check_replays(&config, &wide, REST.limits);
    assert!(
        kinds.contains(&"ball".to_owned()) && kinds.contains(&"cushion".to_owned()),
        "{kinds:?}"
    );

    // slow: the cue ball stops before it reaches anything
    let slow = variant(&[("v0 = 1.5 ", "v0 = 0.1 ")]);
    let stopped = study(&slow, &slow.sigma(), 100, 13, &REST);
    let kinds = check_replays(&slow, &stopped, REST.limits);
    assert!(kinds.contains(&"stopped".to_owned()), "{kinds:?}");

    // caps: every sample cut after a few events, as the simulator cuts it
    let capped = RunOptions {
        until: Until::Rest,
        limits: Limits {
            max_events: 3,
            max_time: 600.0,
        },
    };
    let cut = study(&config, &sigma, 200, 14, &capped);
    check_replays(&config, &cut, capped.limits);
    assert!(
        cut.iter()
            .all(|s| s.cut == Some(Cut::MaxEvents) && s.n_events == 3)
    );
    let short = RunOptions {
        until: Until::Rest,
        limits: Limits {
            max_events: 10_000,
            max_time: 0.5,
        },
    };
    let cut = study(&config, &sigma, 200, 15, &short);
    check_replays(&config, &cut, short.limits);
    assert!(cut.iter().any(|s| s.cut == Some(Cut::MaxTime)));
    assert!(cut.iter().all(|s| s.duration <= 0.5));
}

// ---------------------------------------------------------------- the built-in study

#[test]
fn builtin_study_has_an_informative_mix_and_the_summary_adds_up() {
    let config = StudyConfig::builtin();
    let n = 4000;
    let samples = study(&config, &config.sigma(), n, 42, &REST);
    let s = Summary::of(&config, &samples, Until::Rest);
    assert_eq!(s.samples, n);
    for r in Result4::ALL {
        let k = s.result(r);
        assert!(k * 50 >= n, "{}: {k} of {n}", r.name());
        // the summary counts what Result4::of says of each sample
        let direct = samples
            .iter()
            .filter(|x| Result4::of(&config, x) == r)
            .count();
        assert_eq!(k, direct, "{}", r.name());
    }
    let intended = s.intended_potted();
    assert!(
        intended * 5 >= n && intended * 100 <= 95 * n,
        "intended potted {intended} of {n}"
    );
    assert_eq!(s.results.iter().sum::<usize>(), n);
    assert_eq!(s.first.iter().map(|c| c.1).sum::<usize>(), n);
    let potted_directly = samples
        .iter()
        .filter(|x| x.pocket_of(config.intended).is_some())
        .count();
    assert_eq!(intended, potted_directly);
    assert_eq!(
        s.scratches,
        s.result(Result4::PotScratch) + s.result(Result4::Scratch)
    );
    assert_eq!(
        s.scratch_pockets.iter().map(|p| p.1).sum::<usize>(),
        s.scratches
    );
    // a called pocket: pot and pot+scratch are the intended ball in that pocket
    let called = config.pocket.unwrap();
    let in_called = s
        .intended_pockets
        .iter()
        .find(|p| p.0 == called)
        .map_or(0, |p| p.1);
    assert_eq!(
        in_called,
        s.result(Result4::Pot) + s.result(Result4::PotScratch)
    );
    let in_target = s.in_target.expect("the built-in study has a target");
    assert!(in_target <= n - s.scratches);
    assert!(in_target > 0, "the cue ball never stops in the target");
    let (x, y) = s.cue_final.unwrap();
    assert_eq!((x.n, y.n), (n - s.scratches, n - s.scratches));
    assert_eq!(
        s.no_ball_hit,
        samples
            .iter()
            .filter(|x| !matches!(x.first, FirstContact::Ball(_)))
            .count()
    );
    assert_eq!(s.cut, 0);
    assert_eq!(s.events.unwrap().n, n);
    // the Wilson interval brackets each fraction
    for &(_, k) in &s.first {
        let (lo, hi) = wilson(k, n);
        let f = k as f64 / n as f64;
        assert!(lo <= f && f <= hi && hi - lo < 0.05, "{k}: [{lo}, {hi}]");
    }
    // the first-contact summary of the same samples run only to the first contact
    let first = study(&config, &config.sigma(), n, 42, &FIRST);
    let f = Summary::of(&config, &first, Until::FirstContact);
    assert_eq!(f.first, s.first);
    assert_eq!(f.results, [0; 4]);
}

/// `study::summarize` counts each chunk's samples and drops them: its summary is
/// `Summary::of` on what `study::run` returns, bit for bit (means summed in the same
/// order, the same order statistics), to rest over several chunks, to the first contact,
/// with a physics spread, judged by a game with a score (snooker), and for given strikes;
/// its progress reaches every sample.
#[test]
fn the_summary_without_the_samples_is_the_summary_of_the_samples() {
    use kisstime::engine::{Backend, Precision, ShotEngine};
    use kisstime::study::{Samples, run, summarize};
    let builtin = StudyConfig::builtin();
    let spread = StudyConfig::parse(
        &format!("{BUILTIN_TOML}\n[noise.physics]\nu_r = 0.1\ne_c = [0.8, 0.9]\n"),
        "spread.toml",
        None,
    )
    .unwrap();
    let snooker = StudyConfig::parse(
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/examples/snooker.toml"
        ))
        .unwrap(),
        "snooker.toml",
        None,
    )
    .unwrap();
    let given: Vec<CueStrike> = (0..300)
        .map(|i| noisy_strike(&builtin, &builtin.sigma(), 5, i))
        .collect();
    let mut engine = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let cases: [(&str, &StudyConfig, usize, &RunOptions); 4] = [
        ("to rest over chunks", &builtin, CHUNK + 1500, &REST),
        ("to the first contact", &builtin, 3000, &FIRST),
        ("a physics spread", &spread, 1500, &REST),
        ("snooker's rules", &snooker, 1500, &REST),
    ];
    for (what, config, n, options) in cases {
        let sigma = config.sigma();
        let drawn = || Samples::Drawn {
            sigma: &sigma,
            seed: 77,
            range: 10..10 + n,
        };
        let samples = run(&mut engine, config, drawn(), options, &mut |_, _| {}).unwrap();
        let mut reached = 0;
        let summary = summarize(&mut engine, config, drawn(), options, &mut |done, total| {
            assert!(done > reached && total == n, "{what}: {done} of {total}");
            reached = done;
        })
        .unwrap();
        assert_eq!(reached, n, "{what}");
        assert_eq!(
            summary,
            Summary::of(config, &samples, options.until),
            "{what}"
        );
        assert!(summary.samples == n && summary.events.is_some(), "{what}");
    }
    let samples = run(
        &mut engine,
        &builtin,
        Samples::Given(&given),
        &REST,
        &mut |_, _| {},
    )
    .unwrap();
    let summary = summarize(
        &mut engine,
        &builtin,
        Samples::Given(&given),
        &REST,
        &mut |_, _| {},
    )
    .unwrap();
    assert_eq!(
        summary,
        Summary::of(&builtin, &samples, Until::Rest),
        "given strikes"
    );
    // the snooker case was judged and scored
    let snooker_summary = summarize(
        &mut engine,
        &snooker,
        Samples::Drawn {
            sigma: &snooker.sigma(),
            seed: 77,
            range: 0..200,
        },
        &REST,
        &mut |_, _| {},
    )
    .unwrap();
    let game = snooker_summary.game.expect("snooker's verdicts");
    assert!(game.points.is_some() && game.foul_points.is_some());
    // what no sample could run is refused before any work, by every driver
    let contexts = vec![snooker.game.as_ref().unwrap().context; given.len() - 1];
    let judged = || Samples::Judged {
        strikes: &given,
        contexts: &contexts,
    };
    let drawn = || Samples::Drawn {
        sigma: &builtin.noise,
        seed: 1,
        range: 0..10,
    };
    let why = |e: kisstime::Error| e.to_string();
    let refused = [
        summarize(&mut engine, &snooker, drawn(), &FIRST, &mut |_, _| {}).map(|_| ()),
        run(&mut engine, &snooker, drawn(), &FIRST, &mut |_, _| {}).map(|_| ()),
        summarize(&mut engine, &snooker, judged(), &REST, &mut |_, _| {}).map(|_| ()),
        run(&mut engine, &builtin, judged(), &REST, &mut |_, _| {}).map(|_| ()),
    ];
    let messages: Vec<String> = refused.into_iter().map(|r| why(r.unwrap_err())).collect();
    assert!(messages[0].contains("runs to rest") && messages[1].contains("runs to rest"));
    assert!(
        messages[2].contains("300 strikes but 299 contexts"),
        "{}",
        messages[2]
    );
    assert!(messages[3].contains("need a game"), "{}", messages[3]);
}

#[test]
fn zero_noise_replays_the_intended_shot() {
    let config = StudyConfig::builtin();
    let zero = Noise {
        v0: 0.0,
        phi: 0.0,
        theta: 0.0,
        a: 0.0,
        b: 0.0,
        physics: Default::default(),
    };
    assert_eq!(config.sigma().scaled(0.0), zero);
    let nominal = run_strikes(&config, &[config.shot], &REST, &mut |_, _| {}).unwrap();
    let nominal = fingerprint(&nominal).pop().unwrap();
    let samples = study(&config, &zero, 50, 3, &REST);
    assert!(samples.iter().all(|s| s.strike == config.shot));
    assert!(fingerprint(&samples).iter().all(|s| *s == nominal));
    // the intended shot hits the intended ball first and pots it in the called pocket
    assert_eq!(samples[0].first, FirstContact::Ball(config.intended as u32));
    assert_eq!(samples[0].pocket_of(config.intended), config.pocket);
}

// ---------------------------------------------------------------- bad scenario files

/// The error of the built-in study edited: an input error whose message starts with the
/// file's name.
fn bad(replacements: &[(&str, &str)]) -> String {
    bad_in(replacements, None)
}

fn bad_in(replacements: &[(&str, &str)], dir: Option<&Path>) -> String {
    match StudyConfig::parse(&edited(replacements), "bad.toml", dir) {
        Err(e @ Error::Input(_)) => {
            assert!(e.is_bad_input());
            let msg = e.to_string();
            assert!(msg.starts_with("bad.toml"), "{msg}");
            msg
        }
        other => panic!("expected an input error for {replacements:?}, got {other:?}"),
    }
}

#[test]
fn bad_scenarios_are_input_errors_naming_the_file_key_and_ball() {
    let has = |m: &str, needles: &[&str]| {
        for n in needles {
            assert!(m.contains(n), "{n:?} missing in: {m}");
        }
    };
    // syntax and schema: located at their line ("line N" of the edited text)
    let at = |edits: &[(&str, &str)], starts: &str| {
        let text = edited(edits);
        let n = text.lines().position(|l| l.starts_with(starts)).unwrap() + 1;
        format!("line {n}:")
    };
    let edits = [("b = 0.2 ", "spin = 3\nb = 0.2 ")];
    has(&bad(&edits), &["spin", &at(&edits, "spin = 3")]);
    let edits = [("[physics]", "[physic]")];
    has(&bad(&edits), &["physic", &at(&edits, "[physic]")]);
    let edits = [("x = 0.35", "x = \"left\"")];
    has(&bad(&edits), &["left", &at(&edits, "x = \"left\"")]);
    let edits = [("v0 = 1.5        # cue speed, m/s", "")];
    has(&bad(&edits), &["v0", "missing", &at(&edits, "[shot]")]);
    // values
    let m = bad(&[("v0 = 1.5 ", "v0 = -1.5 ")]);
    has(&m, &["shot.v0", "-1.5"]);
    let m = bad(&[("x = 0.20", "x = nan")]);
    has(&m, &["balls[7].x", "\"8\"", "finite"]);
    // ball 8 (balls[7]) moved past the foot rail
    let m = bad(&[("y = 2.40", "y = 2.60")]);
    has(&m, &["balls[7]", "\"8\""]);
    // ball 4 (balls[6]) put on ball 1 (balls[3])
    let m = bad(&[("x = 0.85\ny = 1.65", "x = 0.95\ny = 2.21")]);
    has(&m, &["balls[6]", "\"4\"", "overlaps", "\"1\"", "balls[3]"]);
    let m = bad(&[("object_ball = 7", "object_ball = 9")]);
    has(&m, &["shot.object_ball", "\"9\""]);
    let m = bad(&[("object_ball = 7", "object_ball = \"cue\"")]);
    has(&m, &["shot.object_ball", "cue ball"]);
    let m = bad(&[("id = 8", "id = 3")]);
    has(&m, &["balls[7].id", "\"3\"", "balls[5]"]);
    let m = bad(&[("pocket = \"lb\"", "pocket = \"zz\"")]);
    has(&m, &["shot.pocket", "\"zz\""]);
    let nine_foot = Table::nine_foot();
    assert!(!nine_foot.pocket_ids.is_empty());
    has(
        &m,
        &nine_foot
            .pocket_ids
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
    );
    let m = bad(&[("theta = 5.0 ", "theta = 90.0 ")]);
    has(&m, &["shot.theta", "90"]);
    let m = bad(&[("a = 0.0 ", "a = 0.8 "), ("b = 0.2 ", "b = 0.7 ")]);
    has(&m, &["shot.a", "shot.b"]);
    let m = bad(&[("R = 0.028575", "R = 0")]);
    has(
        &m,
        &["physics.R", "greater than 0", &at(&[], "R = 0.028575")],
    );
    // kisstime's former names are refused with pooltool's
    let edits = [("R = 0.028575", "radius = 0.028575")];
    has(
        &bad(&edits),
        &["physics.radius", "`R`", &at(&edits, "radius = ")],
    );
    let m = bad(&[("M = 0.567", "mass = 0.567")]);
    has(&m, &["physics.cue.mass", "`M`"]);
    let m = bad(&[("e_c = 0.85", "e_c = 1.5")]);
    has(&m, &["physics.e_c", "1.5"]);
    let m = bad(&[("phi = 0.125", "phi = -0.125")]);
    has(&m, &["noise.phi", "-0.125"]);
    let m = bad(&[("factor = 1.0", "factor = -2")]);
    has(&m, &["noise.factor"]);
    let m = bad(&[("radius = 0.25", "radius = -0.25")]);
    has(&m, &["target.radius"]);
    // a table file that is not there, looked for in the scenario's folder
    let dir = tempfile::tempdir().unwrap();
    let m = bad_in(
        &[("kind = \"9ft\"", "kind = \"no_such_table.json\"")],
        Some(dir.path()),
    );
    has(&m, &["table.kind", "no_such_table.json"]);
    // the same file, there, is read
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/data/fullshots/table.json"),
        dir.path().join("no_such_table.json"),
    )
    .unwrap();
    let text = edited(&[("kind = \"9ft\"", "kind = \"no_such_table.json\"")]);
    let s = StudyConfig::parse(&text, "ok.toml", Some(dir.path())).unwrap();
    assert_eq!(s.table.pocket_ids.len(), 6);
}

#[test]
fn example_file_is_the_builtin_study_and_sections_are_optional() {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/study.toml"));
    assert_eq!(std::fs::read_to_string(path).unwrap(), BUILTIN_TOML);
    let file = StudyConfig::read(path).unwrap();
    let builtin = StudyConfig::builtin();
    assert_ne!(file.source, builtin.source);
    assert!(file.source.ends_with("study.toml"), "{}", file.source);
    assert_eq!(
        StudyConfig {
            source: builtin.source.clone(),
            ..file
        },
        builtin
    );
    // its [physics] spells out pooltool's defaults in pooltool's names: bit for bit
    assert_eq!(builtin.params, SimParams::default());
    assert_eq!(builtin.cue_id(), "cue");
    assert_eq!(builtin.intended_id(), "7");
    assert_eq!(builtin.pocket_id(), Some("lb"));
    assert_eq!(builtin.balls.len(), 8);

    // just the balls and the shot: every other section takes its default
    let minimal = "[[balls]]\nid = 0\nx = 0.635\ny = 0.6\n\
                   [[balls]]\nid = 1\nx = 0.635\ny = 1.6\n\
                   [shot]\ncue_ball = 0\nobject_ball = 1\nv0 = 1.5\nphi = 90\ntheta = 0\n\
                   a = 0\nb = 0\n";
    let s = StudyConfig::parse(minimal, "minimal.toml", None).unwrap();
    assert_eq!(s.params, SimParams::default());
    assert_eq!(s.table_name, "9ft");
    assert_eq!(s.table, Table::nine_foot());
    assert_eq!(s.noise, Noise::default());
    assert_eq!(s.noise_factor, 1.0);
    assert_eq!((s.target, s.pocket), (None, None));
    assert_eq!((s.cue, s.intended), (0, 1));
    // a straight centre-ball shot at a ball 1 m away hits it full
    let hit = run_strikes(&s, &[s.shot], &REST, &mut |_, _| {}).unwrap();
    assert_eq!(hit[0].first, FirstContact::Ball(1));
    assert!(hit[0].cut_angle.abs() < 1e-9, "{:?}", hit[0]);
    // every built-in table by its name, pooltool's 7-ft default table among them
    let on = |kind: &str| {
        let text = format!("[table]\nkind = \"{kind}\"\n{minimal}");
        StudyConfig::parse(&text, "on.toml", None)
    };
    let seven = on("7ft").unwrap();
    assert_eq!(
        (seven.table_name.as_str(), &seven.table),
        ("7ft", &Table::seven_foot())
    );
    assert_ne!(seven.table, Table::nine_foot());
    assert_eq!(on("rectangle").unwrap().table.pockets.len(), 0);
    // a built-in table of another size (as the JSON scenario's `table.l`, `table.w`)
    let sized = |kind: &str, size: &str| {
        let text = format!("[table]\nkind = \"{kind}\"\n{size}\n{minimal}");
        StudyConfig::parse(&text, "sized.toml", None)
    };
    let small = sized("9ft", "l = 2.2\nw = 1.1").unwrap();
    let specs = kisstime::model::PocketTableSpecs {
        l: 2.2,
        w: 1.1,
        ..Default::default()
    };
    assert_eq!(small.table, Table::pocket_table(&specs));
    assert_ne!(small.table, Table::nine_foot());
    let e = sized("9ft", "l = -1").unwrap_err().to_string();
    assert!(e.contains("table.l") && e.contains("greater than 0"), "{e}");
    let e = sized("my_table.json", "w = 1").unwrap_err().to_string();
    assert!(e.contains("own size"), "{e}");
    let unknown = on("8ft").unwrap_err().to_string();
    for name in ["8ft", "9ft", "7ft", "rectangle", "JSON table file"] {
        assert!(unknown.contains(name), "{unknown}");
    }
    // a reference-format scenario of the same layout gives the same study
    let reference = studies("dev_scenario.json");
    let r = StudyConfig::read_reference(&reference).unwrap();
    assert_eq!(r.balls, builtin.balls);
    assert_eq!(r.table, builtin.table);
    assert_eq!(
        (r.cue, r.intended, r.pocket),
        (builtin.cue, builtin.intended, builtin.pocket)
    );
    assert_eq!(r.shot, builtin.shot);
    let text = std::fs::read_to_string(&reference).unwrap();
    assert_eq!(
        StudyConfig::parse_reference(&text, "dev_scenario.json").unwrap(),
        StudyConfig {
            source: "dev_scenario.json".into(),
            ..r
        }
    );
}

#[test]
fn physics_replaces_the_scenarios_and_json_scenarios_take_ball_params() {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/physics"));
    let params = kisstime::io::physics::read_physics(&dir.join("physics.toml")).unwrap();
    // --physics / physics=: the whole parameter set replaced, the rest of the study kept
    let builtin = StudyConfig::builtin();
    let with = builtin
        .clone()
        .with_physics(params, "physics.toml")
        .unwrap();
    assert_eq!(with.params, params);
    assert_eq!(
        StudyConfig {
            params: builtin.params,
            ..with.clone()
        },
        builtin
    );
    let a = study(&builtin, &builtin.sigma(), 64, 3, &REST);
    let b = study(&with, &with.sigma(), 64, 3, &REST);
    assert_ne!(
        fingerprint(&a),
        fingerprint(&b),
        "the parameters change the samples"
    );
    // the same as the scenario's own [physics] in the same names
    let own = edited(&[("u_s = 0.2", "u_s = 0.17"), ("u_r = 0.01", "u_r = 0.008")]);
    let own = own
        .replacen(
            "u_sp_proportionality = 0.4444444444444444",
            "u_sp_proportionality = 0.38",
            1,
        )
        .replacen("e_b = 0.95", "e_b = 0.97", 1)
        .replacen("e_c = 0.85", "e_c = 0.9", 1)
        .replacen("f_c = 0.2", "f_c = 0.25", 1);
    assert_eq!(
        StudyConfig::parse(&own, "own.toml", None).unwrap().params,
        params
    );
    // a radius that puts the balls into one another is refused, naming where R came from
    let big = SimParams {
        ball: kisstime::model::BallParams {
            r: 0.5,
            ..params.ball
        },
        ..params
    };
    let e = builtin
        .with_physics(big, "big.toml")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("key `balls[") && e.contains("R = 0.5 from big.toml"),
        "{e}"
    );

    // a .json scenario's ball_params, pooltool's names (a table JSON's, u_sp and note too)
    let text = std::fs::read_to_string(studies("dev_scenario.json")).unwrap();
    let table: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("table.json")).unwrap()).unwrap();
    let mut scenario: serde_json::Value = serde_json::from_str(&text).unwrap();
    scenario["ball_params"] = table["ball_params"].clone();
    let r = StudyConfig::parse_reference(&scenario.to_string(), "s.json").unwrap();
    assert_eq!(r.params.ball, params.ball);
    scenario["ball_params"] = serde_json::json!({"radius": 0.03});
    let e = StudyConfig::parse_reference(&scenario.to_string(), "s.json")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("s.json: unknown key `ball_params.radius`") && e.contains("`R`"),
        "{e}"
    );
}

// ---------------------------------------------------------------- the command

#[test]
fn cli_shots_prints_the_summary_and_writes_csv_and_png() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("samples.csv");
    let png = dir.path().join("study.png");
    let out = common::run_kisstime(
        &[
            "shots",
            "--samples",
            "2000",
            "-o",
            path_str(&csv),
            "--plot",
            path_str(&png),
        ],
        &[],
    );
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", text(&out.stderr));
    for needle in [
        "built-in study",
        "2000 samples, seed 42",
        "first contact",
        "ball 7 (intended)",
        "outcome (every ball at rest)",
        "balls potted",
        "position play",
        "95% confidence interval",
        "samples/s",
    ] {
        assert!(stdout.contains(needle), "{needle:?} missing in\n{stdout}");
    }
    let (header, rows) = read_csv(&csv);
    assert_eq!(header.join(","), sample_columns());
    assert_eq!(rows.len(), 2000);
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let mut counts = std::collections::HashMap::new();
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r.len(), header.len(), "row {i}");
        assert_eq!(r[col("sample")], i.to_string());
        let result = r[col("result")].as_str();
        assert!(
            ["pot", "pot+scratch", "scratch", "miss"].contains(&result),
            "row {i}: {result:?}"
        );
        *counts.entry(result.to_owned()).or_insert(0usize) += 1;
    }
    let bytes = std::fs::read(&png).unwrap();
    assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n") && bytes.len() > 1000);

    // the same study as JSON: its counts are the CSV's
    let out = common::run_kisstime(&["shots", "--samples", "2000", "--json"], &[]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["samples"], 2000);
    assert_eq!(v["seed"], 42);
    assert_eq!(v["until"], "rest");
    let check_count = |c: &serde_json::Value| -> u64 {
        let k = c["count"].as_u64().unwrap();
        let f = c["fraction"].as_f64().unwrap();
        assert_eq!(f, k as f64 / 2000.0, "{c}");
        let (lo, hi) = (
            c["ci95"][0].as_f64().unwrap(),
            c["ci95"][1].as_f64().unwrap(),
        );
        assert!(lo <= f && f <= hi, "{c}");
        k
    };
    let outcome = v["outcome"].as_object().unwrap();
    assert_eq!(outcome.len(), 4);
    let mut total = 0;
    for (name, c) in outcome {
        let k = check_count(c);
        assert_eq!(k as usize, counts.get(name).copied().unwrap_or(0), "{name}");
        total += k;
    }
    assert_eq!(total, 2000);
    let first: u64 = v["first_contact"]
        .as_object()
        .unwrap()
        .values()
        .map(check_count)
        .sum();
    assert_eq!(first, 2000);
    check_count(&v["intended_potted"]);
    check_count(&v["scratch"]);
    // nothing else on standard output
    assert_eq!(text(&out.stdout).trim().lines().count(), 1);
}

#[test]
fn cli_shots_with_no_arguments_runs_the_builtin_study() {
    let out = common::run_kisstime(&["shots"], &[]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}{}", text(&out.stderr));
    assert!(
        stdout.contains("built-in study") && stdout.contains("100000 samples, seed 42"),
        "{stdout}"
    );
}

#[test]
fn cli_shots_same_seed_same_csv_whatever_the_threads_and_noise_flags() {
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str, extra: &[&str]| {
        let path = dir.path().join(name);
        let mut args = vec!["shots", "--samples", "500", "-o", path_str(&path)];
        args.extend_from_slice(extra);
        let out = common::run_kisstime(&args, &[]);
        assert!(out.status.success(), "{extra:?}: {}", text(&out.stderr));
        let (_, rows) = read_csv(&path);
        (rows, text(&out.stderr))
    };
    let (a, err) = run("a.csv", &["--seed", "3", "--threads", "1", "-v"]);
    assert!(err.contains("(1 thread)"), "{err}");
    let (b, _) = run("b.csv", &["--seed", "3", "--threads", "2"]);
    assert_eq!(a, b);
    let (c, _) = run("c.csv", &["--seed", "4"]);
    assert_ne!(a, c);
    // no noise: every row is the intended shot
    let config = StudyConfig::builtin();
    let (d, _) = run("d.csv", &["--noise", "0"]);
    assert!(d.iter().all(|r| r[1..] == d[0][1..]));
    assert!(num_field(&d[0][1], config.shot.v0) && num_field(&d[0][2], config.shot.phi));
    // one σ alone: only phi varies
    let (e, _) = run("e.csv", &["--noise", "0", "--sigma-phi", "0.5"]);
    assert!(e.iter().all(|r| r[1] == d[0][1] && r[3..6] == d[0][3..6]));
    assert!(e.iter().any(|r| r[2] != e[0][2]));
}

/// The first `n` rows of the reference strikes, as text and as parsed strikes.
fn dev_strikes(n: usize) -> (String, Vec<(i64, CueStrike)>) {
    let all = std::fs::read_to_string(studies("dev_strikes.csv")).unwrap();
    let lines: Vec<&str> = all.lines().take(n + 1).collect();
    assert_eq!(lines[0], "sample,V0,phi,theta,a,b");
    let strikes = lines[1..]
        .iter()
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let x = |k: usize| f[k].parse::<f64>().unwrap();
            (
                f[0].parse().unwrap(),
                CueStrike {
                    v0: x(1),
                    phi: x(2),
                    theta: x(3),
                    a: x(4),
                    b: x(5),
                },
            )
        })
        .collect();
    (lines.join("\n") + "\n", strikes)
}

/// A numeric CSV field against a value: empty for a value that is not finite, else the
/// same f64.
fn num_field(field: &str, v: f64) -> bool {
    if v.is_finite() {
        field.parse::<f64>().is_ok_and(|x| same(x, v))
    } else {
        field.is_empty()
    }
}

/// Checks one row of the CLI's per-sample CSV against a sample run to rest.
fn check_row(config: &StudyConfig, header: &[String], row: &[String], id: i64, s: &Sample) {
    let f = |name: &str| row[header.iter().position(|h| h == name).unwrap()].as_str();
    let what = format!("sample {id}: {row:?} vs {s:?}");
    assert_eq!(f("sample"), id.to_string(), "{what}");
    let k = s.strike;
    for (name, v) in [
        ("V0", k.v0),
        ("phi", k.phi),
        ("theta", k.theta),
        ("a", k.a),
        ("b", k.b),
        ("first_t", s.first_t),
        ("contact_cue_x", s.contact_cue.0),
        ("contact_cue_y", s.contact_cue.1),
        ("speed", s.contact_speed),
        ("contact_x", s.contact_point.0),
        ("contact_y", s.contact_point.1),
        ("cut_angle", s.cut_angle),
        ("cue_x", s.cue_final.0),
        ("cue_y", s.cue_final.1),
        ("duration", s.duration),
    ] {
        assert!(num_field(f(name), v), "{name}: {what}");
    }
    let (kind, cushion) = match s.first {
        FirstContact::Ball(_) => ("ball", String::new()),
        FirstContact::Cushion {
            circular: false,
            index,
        } => ("cushion", config.table.linear_ids[index as usize].clone()),
        FirstContact::Cushion {
            circular: true,
            index,
        } => ("cushion", config.table.circular_ids[index as usize].clone()),
        FirstContact::Pocket(p) => ("pocket", config.table.pocket_ids[p as usize].clone()),
        FirstContact::Stopped => ("stopped", String::new()),
        FirstContact::Nothing => ("nothing", String::new()),
    };
    assert_eq!(f("first_contact"), kind, "{what}");
    assert_eq!(f("first_cushion"), cushion, "{what}");
    let ball = match s.first {
        FirstContact::Ball(_) => first_contact_word(config, &s.first),
        _ => "",
    };
    assert_eq!(f("first_ball"), ball, "{what}");
    assert_eq!(f("result"), Result4::of(config, s).name(), "{what}");
    let intended = s.pocket_of(config.intended);
    assert_eq!(
        f("intended_potted"),
        if intended.is_some() { "1" } else { "0" },
        "{what}"
    );
    assert_eq!(
        f("intended_pocket"),
        intended.map_or("", |p| config.table.pocket_ids[p].as_str()),
        "{what}"
    );
    let cue = s.pocket_of(config.cue).is_some();
    assert_eq!(f("cue_potted"), if cue { "1" } else { "0" }, "{what}");
    assert_eq!(f("potted"), potted_field(config, s), "{what}");
    let in_target = match config.target {
        None => "",
        Some(t) if !cue && t.contains(s.cue_final.0, s.cue_final.1) => "1",
        Some(_) => "0",
    };
    assert_eq!(f("in_target"), in_target, "{what}");
    assert_eq!(f("n_events"), s.n_events.to_string(), "{what}");
    let cut = match s.cut {
        Some(Cut::MaxEvents) => "max_events",
        Some(Cut::MaxTime) => "max_time",
        None => "",
    };
    assert_eq!(f("cut"), cut, "{what}");
}

#[test]
fn cli_shots_evaluates_given_strikes_csv_and_npy() {
    let dir = tempfile::tempdir().unwrap();
    let n = 50;
    let (csv_text, strikes) = dev_strikes(n);
    let strikes_csv = dir.path().join("strikes.csv");
    std::fs::write(&strikes_csv, &csv_text).unwrap();
    let scenario = studies("dev_scenario.json");
    let out_csv = dir.path().join("out.csv");
    let out = common::run_kisstime(
        &[
            "shots",
            path_str(&scenario),
            "--strikes",
            path_str(&strikes_csv),
            "-o",
            path_str(&out_csv),
        ],
        &[],
    );
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", text(&out.stderr));
    assert!(
        stdout.contains(&format!("{n} strikes from")) && stdout.contains("no noise"),
        "{stdout}"
    );
    let (header, rows) = read_csv(&out_csv);
    assert_eq!(header.join(","), sample_columns());
    assert_eq!(rows.len(), n);
    // the file's sample ids and strikes, exactly
    for (row, (id, s)) in rows.iter().zip(&strikes) {
        assert_eq!(row[0], id.to_string());
        for (k, v) in [s.v0, s.phi, s.theta, s.a, s.b].into_iter().enumerate() {
            assert!(num_field(&row[1 + k], v), "{row:?} vs {s:?}");
        }
    }
    // the same strikes through the library give the same rows
    let config = StudyConfig::read_reference(&scenario).unwrap();
    let only: Vec<CueStrike> = strikes.iter().map(|s| s.1).collect();
    let mut calls = Vec::new();
    let samples = run_strikes(&config, &only, &REST, &mut |d, t| calls.push((d, t))).unwrap();
    assert_eq!(calls, vec![(n, n)]);
    for ((row, (id, _)), s) in rows.iter().zip(&strikes).zip(&samples) {
        check_row(&config, &header, row, *id, s);
    }
    assert!(
        samples
            .iter()
            .any(|s| s.pocket_of(config.intended).is_some())
    );

    // the same strikes as a (N, 6) float64 .npy
    let values: Vec<f64> = strikes
        .iter()
        .flat_map(|(id, s)| [*id as f64, s.v0, s.phi, s.theta, s.a, s.b])
        .collect();
    let strikes_npy = dir.path().join("strikes.npy");
    std::fs::write(
        &strikes_npy,
        common::plain_array_npy(&[n as u64, 6], &values),
    )
    .unwrap();
    let out_npy = dir.path().join("out_npy.csv");
    let out = common::run_kisstime(
        &[
            "shots",
            path_str(&scenario),
            "--strikes",
            path_str(&strikes_npy),
            "-o",
            path_str(&out_npy),
        ],
        &[],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(
        std::fs::read_to_string(&out_npy).unwrap(),
        std::fs::read_to_string(&out_csv).unwrap()
    );

    // to the first contact only: the same first contacts, no outcome columns
    let out_first = dir.path().join("out_first.csv");
    let out = common::run_kisstime(
        &[
            "shots",
            path_str(&scenario),
            "--strikes",
            path_str(&strikes_csv),
            "--until",
            "first-contact",
            "-o",
            path_str(&out_first),
        ],
        &[],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let (h, first_rows) = read_csv(&out_first);
    assert_eq!(h, header);
    let col = |name: &str| header.iter().position(|x| x == name).unwrap();
    for (a, b) in rows.iter().zip(&first_rows) {
        for name in [
            "sample",
            "first_contact",
            "first_ball",
            "first_cushion",
            "first_t",
        ] {
            assert_eq!(a[col(name)], b[col(name)], "{name}");
        }
        assert_eq!(b[col("result")], "");
    }
}

#[test]
fn cli_shots_bad_input_exits_2_and_leaves_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let out_csv = dir.path().join("out.csv");
    let out_png = dir.path().join("out.png");
    let scenario = studies("dev_scenario.json");
    let files_before = |extra: &[&Path]| {
        let mut names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        let mut want: Vec<String> = extra
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        want.sort();
        assert_eq!(names, want, "files left behind");
    };
    let fails = |args: &[&str], code: i32, needles: &[&str]| {
        let mut all = vec!["shots"];
        all.extend_from_slice(args);
        all.extend_from_slice(&["-o", path_str(&out_csv), "--plot", path_str(&out_png)]);
        let out = common::run_kisstime(&all, &[]);
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{args:?}: {err}");
        for n in needles {
            assert!(err.contains(n), "{args:?}: {n:?} missing in {err}");
        }
        assert!(out.stdout.is_empty(), "{args:?}: {}", text(&out.stdout));
        assert!(
            !out_csv.exists() && !out_png.exists(),
            "{args:?} left output"
        );
    };

    // a strike off the ball
    let off = dir.path().join("off.csv");
    std::fs::write(&off, "sample,V0,phi,theta,a,b\n7,1.5,201.75,5.0,0.9,0.9\n").unwrap();
    fails(
        &[path_str(&scenario), "--strikes", path_str(&off)],
        2,
        &["off.csv", "line 2", "sample 7"],
    );
    // a bad header
    let header = dir.path().join("header.csv");
    std::fs::write(&header, "sample,V0,phi,theta,a\n0,1.5,201.75,5.0,0.0\n").unwrap();
    fails(
        &["--strikes", path_str(&header)],
        2,
        &["header.csv", "line 1", "header"],
    );
    // a repeated sample id
    let twice = dir.path().join("twice.csv");
    std::fs::write(
        &twice,
        "sample,V0,phi,theta,a,b\n3,1.5,201.75,5.0,0,0.2\n3,1.5,201.75,5.0,0,0.2\n",
    )
    .unwrap();
    fails(
        &["--strikes", path_str(&twice)],
        2,
        &["twice.csv", "line 3", "sample 3"],
    );
    // a bad scenario file
    let study = dir.path().join("study.toml");
    std::fs::write(&study, edited(&[("v0 = 1.5 ", "v0 = -1 ")])).unwrap();
    fails(
        &[path_str(&study), "--samples", "10"],
        2,
        &["study.toml", "shot.v0"],
    );
    // a missing scenario file: an I/O error (exit 1, src/error.rs), naming the file
    let missing = dir.path().join("missing.toml");
    fails(
        &[path_str(&missing), "--samples", "10"],
        1,
        &["missing.toml"],
    );
    // bad noise
    fails(&["--samples", "10", "--noise", "-1"], 2, &["--noise"]);
    fails(&["--samples", "10", "--sigma-a", "nan"], 2, &["--sigma-a"]);
    fails(
        &["--samples", "10", "--max-time", "0"],
        2,
        &["max_time 0: it must be greater than 0 s"],
    );
    fails(
        &["--samples", "10", "--max-events", "0"],
        2,
        &["max_events 0: it must be at least 1"],
    );
    // clap: --strikes with --samples, no samples
    fails(
        &["--strikes", path_str(&off), "--samples", "10"],
        2,
        &["--strikes", "--samples"],
    );
    fails(&["--samples", "0"], 2, &["--samples", "must be at least 1"]);
    files_before(&[&off, &header, &twice, &study]);

    // a failed run keeps an existing output as it was
    std::fs::write(&out_csv, "old\n").unwrap();
    let out = common::run_kisstime(
        &[
            "shots",
            "--strikes",
            path_str(&off),
            "-o",
            path_str(&out_csv),
        ],
        &[],
    );
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(std::fs::read_to_string(&out_csv).unwrap(), "old\n");
    files_before(&[&off, &header, &twice, &study, &out_csv]);
}

/// A run that fails writing its picture must not leave its CSV behind either.
#[test]
fn cli_shots_failing_plot_leaves_no_csv() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("out.csv");
    // a folder where the picture should go: writing it fails after the study
    let png = dir.path().join("out.png");
    std::fs::create_dir(&png).unwrap();
    let out = common::run_kisstime(
        &[
            "shots",
            "--samples",
            "10",
            "-o",
            path_str(&csv),
            "--plot",
            path_str(&png),
        ],
        &[],
    );
    assert!(!out.status.success());
    assert!(!csv.exists(), "a failed run left {}", csv.display());
}
