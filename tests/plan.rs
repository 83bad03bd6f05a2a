//! The shot planner (issue 29, direct pots): on simple 8-ball and 9-ball positions it
//! chooses a pot of a ball the player may hit, the same plan for the same seed and sample
//! budget; the probabilities it reports are those of an independent study of the chosen
//! strike (another seed, the same call) within their intervals; the noise draws are common
//! to every candidate; `kisstime plan` prints the ranking, writes the chosen strike as
//! `simulate --strikes` reads it, and refuses bad input with a clear error, nothing
//! written.

mod common;

use kisstime::engine::{Backend, Precision, ShotEngine};
use kisstime::game::{Context, Rules};
use kisstime::io::context::default_context;
use kisstime::model::ball_state::BallState;
use kisstime::plan::{Budget, Kind, PlanOptions, context_of, plan, position};
use kisstime::simulate::{CueStrike, SimParams};
use kisstime::study::{Noise, RunOptions, Samples, StudyConfig, noisy_strike_of, run, wilson};

/// 9-ball: the cue ball, the 1 on a clear line to the left top corner, the 2 and the 9.
const NINE_BALL: &str = "table,ball,state,x,y,vx,vy,wx,wy,wz
0,0,stationary,0.635,0.9,0,0,0,0,0
0,1,stationary,0.4,1.9,0,0,0,0,0
0,2,stationary,0.9,1.6,0,0,0,0,0
0,9,stationary,0.8,2.2,0,0,0,0,0
";

fn nine_ball() -> StudyConfig {
    let r = SimParams::default().ball.r;
    let spots = [(0, 0.635, 0.9), (1, 0.4, 1.9), (2, 0.9, 1.6), (9, 0.8, 2.2)];
    let ids: Vec<i64> = spots.iter().map(|s| s.0).collect();
    let balls: Vec<BallState> = spots
        .iter()
        .map(|s| BallState::at_rest(s.1, s.2, r))
        .collect();
    let table = kisstime::simulate::Table::nine_foot();
    let rules = Rules::NineBall;
    position(
        &table,
        "9ft",
        SimParams::default(),
        (&ids, &balls),
        rules,
        default_context(rules),
    )
    .unwrap()
}

fn cpu() -> ShotEngine {
    ShotEngine::new(Backend::Cpu, Precision::F64).unwrap()
}

#[test]
fn the_plan_pots_the_ball_on_and_is_the_same_for_the_same_seed() {
    let config = nine_ball();
    let options = PlanOptions {
        budget: Budget::Samples(40_000),
        finalists: 3,
        ..PlanOptions::default()
    };
    let a = plan(&mut cpu(), &config, &options).unwrap();
    let best = &a.ranked[0];
    let Kind::Pot { ball, .. } = best.candidate.kind else {
        panic!("a pot: {:?}", best.candidate.kind);
    };
    assert_eq!(config.balls[ball].id, "1", "9-ball: the lowest ball");
    let (keep, _, _) = best.estimate.p_keep();
    assert!(keep > 0.6, "P(keep) {keep}");
    assert!(a.samples <= 40_000 + 3 * 64, "{} samples", a.samples);
    assert_eq!(a.ranked.len(), 3);
    for w in a.ranked.windows(2) {
        assert!(w[0].estimate.value() >= w[1].estimate.value());
    }
    let b = plan(&mut cpu(), &config, &options).unwrap();
    assert_eq!(
        a.ranked, b.ranked,
        "the same seed and sample budget, the same plan"
    );
    let c = plan(&mut cpu(), &config, &PlanOptions { seed: 2, ..options }).unwrap();
    assert_ne!(a.ranked[0].estimate, c.ranked[0].estimate);
}

/// Every probability the plan reports is what a plain study of the chosen strike (other
/// noise draws, the same call) finds, within the two 95 % intervals.
#[test]
fn the_reported_probabilities_are_an_independent_studys() {
    let config = nine_ball();
    let options = PlanOptions {
        budget: Budget::Samples(40_000),
        finalists: 2,
        ..PlanOptions::default()
    };
    let planned = plan(&mut cpu(), &config, &options).unwrap();
    let best = &planned.ranked[0];
    let n = 6_000;
    let r = config.params.ball.r;
    let strikes: Vec<CueStrike> = (0..n as u64)
        .map(|i| noisy_strike_of(best.candidate.strike, r, &options.noise, 99, i))
        .collect();
    let contexts = vec![context_of(&config, &best.candidate); n];
    let samples = Samples::Judged {
        strikes: &strikes,
        contexts: &contexts,
    };
    let done = run(
        &mut cpu(),
        &config,
        samples,
        &RunOptions::default(),
        &mut |_, _| {},
    )
    .unwrap();
    let count = |f: &dyn Fn(&kisstime::study::Sample) -> bool| done.iter().filter(|s| f(s)).count();
    let kept = count(&|s| s.verdict.is_some_and(|v| v.legal && !v.turn_over));
    let fouls = count(&|s| s.verdict.is_some_and(|v| v.foul.is_some()));
    let scratches = count(&|s| s.pocket_of(config.cue).is_some());
    let e = &best.estimate;
    for (name, (p, lo, hi), k) in [
        ("keep", e.p_keep(), kept),
        ("foul", e.p_foul(), fouls),
        ("scratch", e.p_scratch(), scratches),
    ] {
        let (slo, shi) = wilson(k, n);
        let q = k as f64 / n as f64;
        assert!(
            lo <= shi && slo <= hi,
            "P({name}): the plan's {p:.4} [{lo:.4}, {hi:.4}], the study's {q:.4} [{slo:.4}, {shi:.4}]"
        );
    }
}

/// Sample i of every intended strike meets the same draw: the noisy strikes differ by
/// what the intended ones differ by (common random numbers).
#[test]
fn the_noise_draws_are_common_to_every_candidate() {
    let noise = Noise::preset("fastfiz").unwrap();
    let r = SimParams::default().ball.r;
    let s = |v0, phi| CueStrike {
        v0,
        phi,
        theta: 5.0,
        a: 0.0,
        b: 0.1,
    };
    for i in 0..200 {
        let (x, y) = (
            noisy_strike_of(s(2.0, 30.0), r, &noise, 5, i),
            noisy_strike_of(s(3.0, 100.0), r, &noise, 5, i),
        );
        assert!((y.v0 - x.v0 - 1.0).abs() < 1e-12);
        assert!((y.phi - x.phi - 70.0).abs() < 1e-9);
        assert_eq!((x.theta, x.a, x.b), (y.theta, y.a, y.b));
    }
    assert_eq!(Noise::preset("club").unwrap().phi, 2.0 * noise.phi);
    assert!(Noise::preset("nope").is_none());
}

/// 8-ball: only the group is tried, each candidate judged with its own call; with the
/// group down the 8 is the ball on.
#[test]
fn eight_ball_plans_the_group_and_then_the_eight() {
    let r = SimParams::default().ball.r;
    let table = kisstime::simulate::Table::nine_foot();
    let spots = [
        (0, 0.635, 0.9),
        (3, 0.4, 1.9),
        (8, 0.9, 1.6),
        (12, 0.8, 2.2),
    ];
    let ids: Vec<i64> = spots.iter().map(|s| s.0).collect();
    let balls: Vec<BallState> = spots
        .iter()
        .map(|s| BallState::at_rest(s.1, s.2, r))
        .collect();
    let solids = Context {
        hittable: Context::balls(1..=7),
        ..Context::default()
    };
    let options = PlanOptions {
        budget: Budget::Samples(30_000),
        finalists: 2,
        ..PlanOptions::default()
    };
    for (hittable, want) in [
        (solids, "3"),
        (
            Context {
                hittable: Context::balls([1, 2]),
                ..solids
            },
            "8",
        ),
    ] {
        let config = position(
            &table,
            "9ft",
            SimParams::default(),
            (&ids, &balls),
            Rules::EightBall,
            hittable,
        )
        .unwrap();
        let planned = plan(&mut cpu(), &config, &options).unwrap();
        for r in &planned.ranked {
            let Kind::Pot { ball, pocket } = r.candidate.kind else {
                panic!("a pot: {:?}", r.candidate.kind);
            };
            assert_eq!(config.balls[ball].id, want);
            let c = context_of(&config, &r.candidate);
            assert_eq!(
                (c.ball_call, c.pocket_call),
                (Some(ball_id(&config, ball)), Some(pocket))
            );
        }
    }
}

fn ball_id(config: &StudyConfig, k: usize) -> i64 {
    config.balls[k].id.parse().unwrap()
}

fn write(dir: &std::path::Path, name: &str, text: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

#[test]
fn cli_plan_prints_the_ranking_and_writes_a_strike_simulate_replays() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "pos.csv", &NINE_BALL.replace("\n0,", "\n4,"));
    let out = dir.path().join("chosen.csv");
    let args = [
        "plan",
        input.to_str().unwrap(),
        "--rules",
        "9-ball",
        "--budget",
        "30000",
        "--top",
        "3",
        "-o",
        out.to_str().unwrap(),
    ];
    let run = common::run_kisstime(&args, &[]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let stdout = text(&run.stdout);
    assert!(
        stdout.contains("P(keep)") && stdout.contains("1 -> "),
        "{stdout}"
    );
    assert_eq!(
        stdout
            .lines()
            .filter(|l| l.starts_with(['1', '2', '3']))
            .count(),
        3
    );
    assert!(
        text(&run.stderr).contains("candidates"),
        "{}",
        text(&run.stderr)
    );
    let chosen = std::fs::read_to_string(&out).unwrap();
    assert!(
        chosen.starts_with("table,ball,V0,phi,theta,a,b\n4,0,"),
        "{chosen}"
    );
    // the same plan again: the same strike
    let again = common::run_kisstime(&args, &[]);
    assert!(again.status.success());
    assert_eq!(std::fs::read_to_string(&out).unwrap(), chosen);
    // simulate replays it
    let outcomes = dir.path().join("o.csv");
    let sim = common::run_kisstime(
        &[
            "simulate",
            input.to_str().unwrap(),
            "--strikes",
            out.to_str().unwrap(),
            "--rules",
            "9-ball",
            "--outcomes",
            outcomes.to_str().unwrap(),
        ],
        &[],
    );
    assert!(sim.status.success(), "{}", text(&sim.stderr));
    let o = std::fs::read_to_string(&outcomes).unwrap();
    assert_eq!(o.lines().count(), 2, "{o}");
    // JSON
    let json = common::run_kisstime(&[&args[..8], &["--json"]].concat(), &[]);
    assert!(json.status.success());
    let v: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(v["rules"], "9-ball");
    assert_eq!(v["ranked"].as_array().unwrap().len(), 3);
    assert_eq!(v["ranked"][0]["ball"], "1");
}

#[test]
fn cli_plan_refuses_bad_input_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let good = write(dir.path(), "pos.csv", NINE_BALL);
    let overlap = write(
        dir.path(),
        "overlap.csv",
        &NINE_BALL.replace("0,2,stationary,0.9,1.6", "0,2,stationary,0.41,1.9"),
    );
    let moving = write(
        dir.path(),
        "moving.csv",
        &NINE_BALL.replace("0,2,stationary,0.9,1.6,0", "0,2,rolling,0.9,1.6,1"),
    );
    let no_cue = write(
        dir.path(),
        "nocue.csv",
        &NINE_BALL.replace("0,0,stationary", "0,7,stationary"),
    );
    let two = write(
        dir.path(),
        "two.csv",
        &format!("{NINE_BALL}1,0,stationary,0.5,0.5,0,0,0,0,0\n1,1,stationary,0.5,1.5,0,0,0,0,0\n"),
    );
    let out = dir.path().join("chosen.csv");
    let o = out.to_str().unwrap();
    let g = good.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec![g, "--rules", "9-ball", "--noise", "wild"],
            "not a preset",
        ),
        (vec![g, "--rules", "9-ball", "--budget", "0"], "budget"),
        (vec![g, "--rules", "9-ball", "--budget", "0s"], "budget"),
        (
            vec![g, "--rules", "9-ball", "--budget", "soon"],
            "--budget soon",
        ),
        (vec![g, "--rules", "9-ball", "--budget", "10"], "too small"),
        (
            vec![g, "--rules", "8-ball", "--hittable", "4;5"],
            "ball 4 is not",
        ),
        (vec![g, "--rules", "snooker"], "8-ball and 9-ball"),
        (
            vec![g, "--rules", "9-ball", "--noise-scale", "-1"],
            "--noise-scale",
        ),
        (
            vec![overlap.to_str().unwrap(), "--rules", "9-ball"],
            "balls 1 and 2 overlap",
        ),
        (
            vec![moving.to_str().unwrap(), "--rules", "9-ball"],
            "ball 2",
        ),
        (
            vec![no_cue.to_str().unwrap(), "--rules", "9-ball"],
            "no cue ball",
        ),
        (
            vec![two.to_str().unwrap(), "--rules", "9-ball"],
            "--table-id",
        ),
        (
            vec![
                two.to_str().unwrap(),
                "--rules",
                "9-ball",
                "--table-id",
                "5",
            ],
            "no table 5",
        ),
    ];
    for (args, want) in cases {
        let full = [&["plan"][..], &args, &["-o", o]].concat();
        let run = common::run_kisstime(&full, &[]);
        let err = text(&run.stderr);
        assert!(!run.status.success(), "{args:?} should fail");
        assert!(err.contains(want), "{args:?}: {err}");
        assert!(run.stdout.is_empty(), "{args:?}: nothing on stdout");
        assert!(!out.exists(), "{args:?}: nothing written");
    }
}

/// Self-play: whole games end (won or drawn at the cap), every figure adds up, the same
/// seed plays the same games, and the agents are the ones named.
#[test]
fn self_play_plays_whole_games_the_same_for_the_same_seed() {
    use kisstime::plan::agents::Agent;
    use kisstime::plan::play::{PlayOptions, play};
    for (rules, agents) in [
        (Rules::NineBall, [Agent::Greedy, Agent::Sampler]),
        (Rules::EightBall, [Agent::Planner, Agent::Greedy]),
    ] {
        let options = PlayOptions {
            rules,
            games: 2,
            agents,
            noise: Noise::default(),
            seed: 3,
            budget: Budget::Samples(8_000),
            max_shots: 60,
        };
        let mut done = Vec::new();
        let a = play(&mut cpu(), &options, &mut |g| done.push(g)).unwrap();
        assert_eq!(done, [1, 2]);
        assert_eq!(a.games, 2);
        let wins: usize = a.players.iter().map(|p| p.wins).sum();
        assert_eq!(wins + a.draws, 2, "{rules:?}: every game won or drawn");
        assert_eq!(
            a.players[0].breaks + a.players[1].breaks,
            2,
            "breaks alternate"
        );
        assert!(a.players.iter().all(|p| p.visits >= 1));
        let potted: usize = a.players.iter().map(|p| p.potted).sum();
        assert!(potted > 0, "{rules:?}: balls were potted");
        // greedy simulates nothing: its decisions are quick; the others' are timed too
        for (p, agent) in a.players.iter().zip(agents) {
            if agent == Agent::Greedy {
                assert!(p.decisions.iter().all(|&t| t < 0.05), "{:?}", p.decisions);
            }
        }
        let b = play(&mut cpu(), &options, &mut |_| {}).unwrap();
        let strip = |r: &kisstime::plan::play::PlayReport| {
            r.players
                .iter()
                .map(|p| (p.wins, p.visits, p.potted, p.fouls, p.decisions.len()))
                .collect::<Vec<_>>()
        };
        assert_eq!(
            strip(&a),
            strip(&b),
            "{rules:?}: the same seed, the same games"
        );
    }
    let bad = PlayOptions {
        rules: Rules::Snooker,
        games: 1,
        agents: [Agent::Greedy, Agent::Greedy],
        noise: Noise::default(),
        seed: 1,
        budget: Budget::Samples(8_000),
        max_shots: 10,
    };
    assert!(play(&mut cpu(), &bad, &mut |_| {}).is_err());
    assert!(
        play(
            &mut cpu(),
            &PlayOptions {
                rules: Rules::NineBall,
                games: 0,
                ..bad
            },
            &mut |_| {}
        )
        .is_err()
    );
}

#[test]
fn cli_play_reports_each_agent_and_refuses_bad_input() {
    let run = common::run_kisstime(
        &[
            "play",
            "--game",
            "9-ball",
            "--games",
            "2",
            "--agents",
            "greedy,greedy",
            "--json",
        ],
        &[],
    );
    assert!(run.status.success(), "{}", text(&run.stderr));
    let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(v["games"], 2);
    assert_eq!(v["players"].as_array().unwrap().len(), 2);
    assert!(
        v["players"][0]["agent"]
            .as_str()
            .unwrap()
            .starts_with("greedy")
    );
    for (args, want) in [
        (
            vec!["--game", "9-ball", "--agents", "planner"],
            "two agents",
        ),
        (
            vec!["--game", "9-ball", "--agents", "planner,shark"],
            "unknown agent",
        ),
        (vec!["--game", "snooker"], "8-ball and 9-ball"),
        (vec!["--game", "9-ball", "--games", "0"], "0 games"),
        (vec!["--game", "9-ball", "--noise", "wild"], "not a preset"),
    ] {
        let run = common::run_kisstime(&[&["play"][..], &args].concat(), &[]);
        assert!(!run.status.success(), "{args:?}");
        assert!(
            text(&run.stderr).contains(want),
            "{args:?}: {}",
            text(&run.stderr)
        );
        assert!(run.stdout.is_empty(), "{args:?}");
    }
}

#[test]
fn ball_in_hand_places_the_cue_ball_clear_and_plays_at_least_as_well_as_a_bad_spot() {
    use kisstime::plan::in_hand::{InHand, plan_in_hand};
    let config = nine_ball();
    let mut engine = cpu();
    let options = PlanOptions {
        noise: Noise::preset("fastfiz").unwrap(),
        budget: Budget::Samples(60_000),
        ..PlanOptions::default()
    };
    let from_there = plan(&mut engine, &config, &options).unwrap();
    for region in [InHand::Anywhere, InHand::Kitchen] {
        let placed = plan_in_hand(&mut engine, &config, &options, region).unwrap();
        let (x, y) = placed.placement.expect("a placement");
        let r = config.params.ball.r;
        for (k, b) in config.balls.iter().enumerate() {
            if k != config.cue {
                assert!(
                    (b.x - x).hypot(b.y - y) > 2.0 * r,
                    "{region:?}: on ball {}",
                    b.id
                );
            }
        }
        if region == InHand::Kitchen {
            assert!(y < kisstime::game::progress::HEAD_STRING_Y, "{y}");
        } else {
            // free to go anywhere, it does no worse than where the cue ball stood
            let (best, there) = (&placed.ranked[0].estimate, &from_there.ranked[0].estimate);
            assert!(
                best.p_keep().2 >= there.p_keep().1,
                "in hand {:?}, from the cue ball's spot {:?}",
                best.p_keep(),
                there.p_keep()
            );
        }
    }
}
