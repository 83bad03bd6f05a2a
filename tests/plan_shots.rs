//! The planner's shots beyond the direct pot (issue 29): one-rail kicks where no ball on is
//! in straight reach (fouling far less than the blocked full hit every agent fell back
//! on), banks and combinations whose aims pot without noise, the refinement in the
//! continuous strike (playable strikes, the same plan for the same seed), the break
//! (from behind the head string, its reported P(keep the table) what an independent
//! study of it finds), and the value of a legal miss (less, the easier the shot it leaves
//! the opponent).

use kisstime::engine::{Backend, Precision, ShotEngine};
use kisstime::game::progress::HEAD_STRING_Y;
use kisstime::game::{Context, Foul, Rules, Verdict};
use kisstime::io::context::default_context;
use kisstime::model::ball_state::BallState;
use kisstime::plan::agents::fallback;
use kisstime::plan::breaks::{BREAK_SPOTS, BREAK_Y, plan_break};
use kisstime::plan::candidates::{banks, combos, kicks};
use kisstime::plan::evaluate::{Estimate, FOUL_COST, evaluate, judge_sample};
use kisstime::plan::in_hand::at;
use kisstime::plan::refine::{CHILDREN, GENERATIONS, LEADERS, MAX_TIP, V0_RANGE};
use kisstime::plan::{
    Budget, Candidate, Kind, PlanOptions, candidates_of, context_of, plan, position, screen,
};
use kisstime::simulate::{CueStrike, SimParams};
use kisstime::study::{Noise, RunOptions, Samples, StudyConfig, noisy_strike_of, run, wilson};

/// `kisstime plan INPUT --rules 9-ball ARGS… [PATH]` from the repository's root.
fn cli_plan(input: &str, args: &[&str], path: Option<&std::path::Path>) -> std::process::Output {
    let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_kisstime"));
    command
        .args(["plan", input, "--rules", "9-ball"])
        .args(args);
    if let Some(p) = path {
        command.arg(p);
    }
    command
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap()
}

fn cpu() -> ShotEngine {
    ShotEngine::new(Backend::Cpu, Precision::F64).unwrap()
}

/// A position of `rules` on the 9-ft table: `(id, x, y)`, the cue ball id 0; `context`
/// the game's default with `f` applied.
fn config_of(rules: Rules, spots: &[(i64, f64, f64)], f: impl Fn(&mut Context)) -> StudyConfig {
    let r = SimParams::default().ball.r;
    let ids: Vec<i64> = spots.iter().map(|s| s.0).collect();
    let balls: Vec<BallState> = spots
        .iter()
        .map(|s| BallState::at_rest(s.1, s.2, r))
        .collect();
    let mut context = default_context(rules);
    f(&mut context);
    position(
        &kisstime::simulate::Table::nine_foot(),
        "9ft",
        SimParams::default(),
        (&ids, &balls),
        rules,
        context,
    )
    .unwrap()
}

/// The counts of `candidates` each played `n` times under `noise` (seed 7).
fn played(config: &StudyConfig, candidates: &[Candidate], noise: &Noise, n: u64) -> Vec<Estimate> {
    let all: Vec<usize> = (0..candidates.len()).collect();
    let mut e = vec![Estimate::default(); candidates.len()];
    evaluate(
        &mut cpu(),
        config,
        candidates,
        &all,
        (noise, 7, 0..n),
        &mut e,
    )
    .unwrap();
    e
}

/// A round's estimates are judged chunk by chunk as the samples come (`study::run_into`):
/// they are the samples of one `study::run` judged one by one and summed in order, per
/// candidate, bit for bit — over a round of several engine chunks whose boundary splits a
/// candidate's samples, with every candidate its own context.
#[test]
fn a_rounds_estimates_are_its_samples_judged_in_order() {
    let config = blocked();
    let candidates = candidates_of(&config).unwrap();
    let which: Vec<usize> = (0..candidates.len().min(5)).collect();
    let noise = Noise::preset("fastfiz").unwrap();
    // a round of more than one chunk, a chunk ending inside a candidate's samples
    let chunk = kisstime::study::CHUNK as u64;
    let per = (chunk + chunk / 4).div_ceil(which.len() as u64) + 1;
    assert!(which.len() as u64 * per > chunk && !chunk.is_multiple_of(per));
    let mut estimates = vec![Estimate::default(); candidates.len()];
    evaluate(
        &mut cpu(),
        &config,
        &candidates,
        &which,
        (&noise, 3, 100..100 + per),
        &mut estimates,
    )
    .unwrap();
    let r = config.params.ball.r;
    let (mut strikes, mut contexts) = (Vec::new(), Vec::new());
    for &c in &which {
        for i in 100..100 + per {
            strikes.push(noisy_strike_of(candidates[c].strike, r, &noise, 3, i));
            contexts.push(context_of(&config, &candidates[c]));
        }
    }
    let judged = Samples::Judged {
        strikes: &strikes,
        contexts: &contexts,
    };
    let samples = run(
        &mut cpu(),
        &config,
        judged,
        &RunOptions::default(),
        &mut |_, _| {},
    )
    .unwrap();
    for (k, &c) in which.iter().enumerate() {
        let mut e = Estimate::default();
        for s in &samples[k * per as usize..(k + 1) * per as usize] {
            e.add(&judge_sample(&config, s));
        }
        assert_eq!(estimates[c], e, "candidate {c}");
        assert_eq!(e.samples, per as usize);
    }
    assert!(
        which
            .iter()
            .any(|&c| estimates[c].fouls != estimates[which[0]].fouls),
        "the candidates play differently"
    );
}

/// 9-ball: the 1 straight up the table behind a wall of three balls.
fn blocked() -> StudyConfig {
    config_of(
        Rules::NineBall,
        &[
            (0, 0.635, 0.5),
            (1, 0.635, 1.5),
            (2, 0.635, 1.0),
            (3, 0.57, 1.0),
            (4, 0.70, 1.0),
        ],
        |_| {},
    )
}

#[test]
fn kicks_are_planned_where_no_ball_on_is_in_reach_and_foul_far_less() {
    let config = blocked();
    let kicked = kicks(&config).unwrap();
    assert!(!kicked.is_empty(), "a one-rail kick reaches the 1");
    let all = candidates_of(&config).unwrap();
    assert!(
        all.iter().all(|c| matches!(c.kind, Kind::Kick { .. })),
        "no direct pot, bank, combination or safety here: only kicks"
    );
    let noise = Noise::preset("fastfiz").unwrap();
    let options = PlanOptions {
        noise,
        budget: Budget::Samples(20_000),
        finalists: 3,
        ..PlanOptions::default()
    };
    let planned = plan(&mut cpu(), &config, &options).unwrap();
    let best = &planned.ranked[0];
    assert!(matches!(best.candidate.kind, Kind::Kick { .. }), "{best:?}");
    // the blocked full hit every agent fell back on before
    let f = fallback(&config);
    let fall = Candidate {
        kind: Kind::Safety {
            ball: best.candidate.kind.ball(),
            nearest: 0,
        },
        strike: f.strike,
        aim: best.candidate.aim,
    };
    let e = played(&config, &[fall], &noise, 1_000);
    let (p_fall, lo_fall, _) = e[0].p_foul();
    let (p_kick, _, hi_kick) = best.estimate.p_foul();
    assert!(
        hi_kick < lo_fall,
        "the kick fouls {p_kick:.3} of the time, the fallback {p_fall:.3}"
    );
}

#[test]
fn some_bank_and_some_combination_pot_without_noise() {
    // 8-ball, solids, so that each bank is called (its ball, its pocket): the 1 a little
    // off the left rail, the cue ball below it
    let bank = config_of(
        Rules::EightBall,
        &[(0, 0.4, 0.9), (1, 0.25, 1.6), (8, 1.0, 2.3), (9, 1.1, 0.4)],
        |c| c.hittable = Context::balls([1]),
    );
    let banked = banks(&bank).unwrap();
    assert!(!banked.is_empty(), "a one-rail bank of the 1");
    assert!(banked.iter().all(|c| matches!(c.kind, Kind::Bank { .. })));
    let none = Noise::preset("none").unwrap();
    let e = played(&bank, &banked, &none, 1);
    assert!(
        e.iter().any(|e| e.kept == 1),
        "one of the banks' fans pots the 1 in the pocket it calls without noise"
    );
    // the screen keeps exactly those
    let mut kept = banked.clone();
    let played_once = screen(&mut cpu(), &bank, &mut kept, 1).unwrap();
    assert_eq!(played_once, banked.len());
    assert_eq!(kept.len(), e.iter().filter(|e| e.kept == 1).count());
    // 9-ball: the 1 on a line to the 9, the 9 on a line to the left top corner
    let combo = config_of(
        Rules::NineBall,
        &[(0, 0.7, 1.0), (1, 0.6, 1.6), (9, 0.4, 2.0)],
        |_| {},
    );
    let combined = combos(&combo).unwrap();
    assert!(!combined.is_empty(), "the 1-9 combination");
    assert!(
        combined
            .iter()
            .all(|c| matches!(c.kind, Kind::Combo { .. }) && c.kind.first() != c.kind.ball())
    );
    let e = played(&combo, &combined, &none, 1);
    assert!(
        e.iter().any(|e| e.won == 1),
        "a combination pots the 9 (the game won) without noise"
    );
}

#[test]
fn the_refinement_draws_playable_strikes_and_the_same_plan_for_the_same_seed() {
    let config = config_of(
        Rules::NineBall,
        &[(0, 0.635, 0.9), (1, 0.4, 1.9), (2, 0.9, 1.6), (9, 0.8, 2.2)],
        |_| {},
    );
    let options = PlanOptions {
        budget: Budget::Samples(30_000),
        finalists: 3,
        ..PlanOptions::default()
    };
    let a = plan(&mut cpu(), &config, &options).unwrap();
    assert_eq!(
        a.refined,
        LEADERS * CHILDREN * GENERATIONS,
        "every leader refined"
    );
    assert!(a.samples <= 30_000 + 3 * 64, "{} samples", a.samples);
    for r in &a.ranked {
        let s = r.candidate.strike;
        assert!((V0_RANGE.0..=V0_RANGE.1).contains(&s.v0), "{s:?}");
        assert!(s.a.hypot(s.b) <= MAX_TIP + 1e-12, "{s:?}");
        assert!((0.0..360.0).contains(&s.phi), "{s:?}");
    }
    let b = plan(&mut cpu(), &config, &options).unwrap();
    assert_eq!(a.ranked, b.ranked);
    let plain = plan(
        &mut cpu(),
        &config,
        &PlanOptions {
            refine: false,
            ..options.clone()
        },
    )
    .unwrap();
    assert_eq!(plain.refined, 0);
}

#[test]
fn the_break_is_planned_from_behind_the_head_string_and_its_figures_hold() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/nine_ball_rack.csv"
    ))
    .unwrap();
    let spots: Vec<(i64, f64, f64)> = text
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[1].parse().unwrap(),
                f[3].parse().unwrap(),
                f[4].parse().unwrap(),
            )
        })
        .collect();
    let config = config_of(Rules::NineBall, &spots, |c| c.break_shot = true);
    let options = PlanOptions {
        budget: Budget::Samples(6_000),
        finalists: 2,
        ..PlanOptions::default()
    };
    let planned = plan_break(&mut cpu(), &config, &options).unwrap();
    let (x, y) = planned.placement.expect("the break's spot");
    assert!(y < HEAD_STRING_Y && y == BREAK_Y, "{y}");
    assert!(BREAK_SPOTS.contains(&x), "{x}");
    let best = &planned.ranked[0];
    assert!(
        matches!(best.candidate.kind, Kind::Break { .. }),
        "{best:?}"
    );
    assert!(!best.candidate.kind.calls());
    let (keep, _, _) = best.estimate.p_keep();
    assert!(keep > 0.5, "P(keep the table) after the break {keep}");
    // an independent study of the chosen break from the chosen spot
    let placed = at(&config, (x, y));
    let n = 1_500;
    let r = config.params.ball.r;
    let strikes: Vec<CueStrike> = (0..n as u64)
        .map(|i| noisy_strike_of(best.candidate.strike, r, &options.noise, 99, i))
        .collect();
    let contexts = vec![context_of(&placed, &best.candidate); n];
    let done = run(
        &mut cpu(),
        &placed,
        Samples::Judged {
            strikes: &strikes,
            contexts: &contexts,
        },
        &RunOptions::default(),
        &mut |_, _| {},
    )
    .unwrap();
    let kept = done
        .iter()
        .filter(|s| s.verdict.is_some_and(|v| v.legal && !v.turn_over))
        .count();
    let (slo, shi) = wilson(kept, n);
    let (p, lo, hi) = best.estimate.p_keep();
    assert!(
        lo <= shi && slo <= hi,
        "P(keep): the plan's {p:.3} [{lo:.3}, {hi:.3}], the study's {:.3} [{slo:.3}, {shi:.3}]",
        kept as f64 / n as f64
    );
    // and the command line's --break
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("break.csv");
    let run = cli_plan(
        "examples/nine_ball_rack.csv",
        &["--break", "--budget", "3000", "-o"],
        Some(&out),
    );
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(stdout.starts_with("break from x = "), "{stdout}");
    assert!(stdout.contains("break at 1"), "{stdout}");
    assert!(
        std::fs::read_to_string(&out)
            .unwrap()
            .starts_with("table,ball,V0,phi,theta,a,b\n")
    );
    // --break and --ball-in-hand together: refused
    let both = cli_plan(
        "examples/nine_ball_rack.csv",
        &["--break", "--ball-in-hand", "anywhere"],
        None,
    );
    assert!(!both.status.success());
}

#[test]
fn a_legal_miss_is_worth_less_the_easier_the_shot_it_leaves_the_opponent() {
    // 9-ball: the 1 by the left top corner; one sample of any strike to fill in
    let config = config_of(
        Rules::NineBall,
        &[(0, 0.635, 0.5), (1, 0.15, 2.3), (2, 1.0, 1.2)],
        |_| {},
    );
    let strikes = [CueStrike {
        v0: 0.5,
        phi: 0.0,
        theta: 5.0,
        a: 0.0,
        b: 0.0,
    }];
    let contexts = [default_context(Rules::NineBall)];
    let mut sample = run(
        &mut cpu(),
        &config,
        Samples::Judged {
            strikes: &strikes,
            contexts: &contexts,
        },
        &RunOptions::default(),
        &mut |_, _| {},
    )
    .unwrap()
    .remove(0);
    let miss = Verdict {
        legal: true,
        foul: None,
        turn_over: true,
        game_over: false,
        won: false,
        points: 0,
        foul_points: 0,
    };
    sample.verdict = Some(miss);
    sample.potted.clear();
    // the cue ball left straight behind the 1 on its line to the corner: a sitter
    sample.cue_final = (0.35, 2.1);
    let hanger = judge_sample(&config, &sample);
    // far from it, the 2 between: nothing
    sample.cue_final = (1.1, 0.9);
    let safe = judge_sample(&config, &sample);
    assert_eq!((hanger.passed, safe.passed), (1, 1));
    assert!(hanger.opponent() > 0.5, "{hanger:?}");
    assert!(safe.opponent() < hanger.opponent(), "{safe:?} {hanger:?}");
    assert!(safe.value() > hanger.value());
    // a foul costs more than any legal miss
    sample.verdict = Some(Verdict {
        legal: false,
        foul: Some(Foul::ALL[0]),
        ..miss
    });
    let foul = judge_sample(&config, &sample);
    assert_eq!(foul.value(), -FOUL_COST);
    assert!(foul.value() < hanger.value());
}

#[test]
fn cli_plan_plot_draws_the_chosen_shot_and_refuses_another_format() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("plan.png");
    let position = "examples/nine_ball_position.csv";
    let run = cli_plan(position, &["--budget", "5000", "--plot"], Some(&png));
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let bytes = std::fs::read(&png).unwrap();
    assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n") && bytes.len() > 10_000);
    // a name that is not .png: refused before planning, nothing written
    let jpg = dir.path().join("plan.jpg");
    let bad = cli_plan(position, &["--budget", "5000", "--plot"], Some(&jpg));
    assert_eq!(bad.status.code(), Some(2), "bad usage");
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--plot"));
    assert!(!jpg.exists());
}
