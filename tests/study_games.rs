//! Shot studies judged by a game's rules (`[game]`, issue 28): every sample's verdict,
//! judged from the facts the study's watch kept as the events went by, is the verdict the
//! same shot gets when it is simulated again with its events recorded and judged from them
//! (`Rules::judge`, the path `kisstime simulate --rules` takes, whose verdicts equal
//! pooltool's on the reference sets: `tests/games.rs`). Checked for 8-ball, 9-ball,
//! snooker and three-cushion on noisy strikes; the summary's counts are the samples'; a bad `[game]`
//! names its key; `--until first-contact` is refused with a reason; the GPU gives the
//! CPU's counts (`tests/gpu_study.rs` compares the verdicts sample by sample).

mod common;

use kisstime::game::{Foul, Rules, Shot};
use kisstime::simulate::{BatchOptions, Limits, simulate_batch};
use kisstime::study::{RunOptions, StudyConfig, Summary, Until, run_study};

const STUDY: &str = include_str!("../examples/study.toml");
/// The `[game]` of `examples/snooker.toml`.
const SNOOKER_GAME: &str = "[game]\nrules = \"snooker\"\nhittable = [\"red_01\", \"red_02\"]\n";

fn config(game: &str) -> StudyConfig {
    StudyConfig::parse(&format!("{STUDY}\n{game}"), "study.toml", None).unwrap()
}

/// Runs `samples` noisy samples of `config` and checks each verdict against the replay's;
/// returns the samples' verdict counts (legal, turn kept).
fn check(config: &StudyConfig, samples: usize) -> (usize, usize) {
    let options = RunOptions {
        until: Until::Rest,
        limits: Limits::default(),
    };
    let run = run_study(config, &config.noise, samples, 11, &options, &mut |_, _| {}).unwrap();
    let game = config.game.as_ref().unwrap();
    let initial = config.initial();
    let input = |k: usize, balls: &mut Vec<_>| {
        balls.clear();
        balls.extend_from_slice(&initial);
        Ok(Some((config.cue, run[k].strike)))
    };
    let mut replayed = Vec::new();
    simulate_batch(
        &config.table,
        config.params,
        &BatchOptions::default(),
        samples,
        input,
        |chunk| {
            for t in chunk.iter() {
                let shot = Shot {
                    ids: &game.ids,
                    start: &initial,
                    events: t.events,
                };
                replayed.push(game.rules.judge(&shot, &game.context).unwrap());
            }
            Ok::<(), ()>(())
        },
    )
    .unwrap();
    for (k, (s, r)) in run.iter().zip(&replayed).enumerate() {
        assert_eq!(
            s.verdict,
            Some(*r),
            "sample {k}: the watch's verdict against the replay's"
        );
    }
    let summary = Summary::of(config, &run, Until::Rest);
    let g = summary.game.expect("a game's counts");
    let legal = replayed.iter().filter(|v| v.legal).count();
    let kept = replayed.iter().filter(|v| !v.turn_over).count();
    assert_eq!((g.legal, g.turn_kept), (legal, kept));
    assert_eq!(
        g.fouls.iter().sum::<usize>(),
        samples - legal,
        "every illegal shot has its foul"
    );
    (legal, kept)
}

#[test]
fn eight_ball_verdicts_of_a_study_are_the_replays() {
    let c = config(
        "[game]\nrules = \"8-ball\"\nhittable = [1, 2, 3, 4, 5, 7]\nball_call = 7\n\
         pocket_call = \"lb\"\n",
    );
    let (legal, kept) = check(&c, 3000);
    // the cut scratches in the side about a third of the time; the 7 drops in lb on half
    assert!((1500..2500).contains(&legal), "{legal} legal");
    assert!((1000..2300).contains(&kept), "{kept} kept the table");
    // an open call: the 7 into another pocket keeps nothing
    let other = config(
        "[game]\nrules = \"8-ball\"\nhittable = [1, 2, 3, 4, 5, 7]\nball_call = 7\n\
         pocket_call = \"rt\"\n",
    );
    let (_, kept) = check(&other, 500);
    assert_eq!(kept, 0, "the 7 never drops in rt");
}

#[test]
fn nine_ball_and_three_cushion_verdicts_of_a_study_are_the_replays() {
    // 9-ball: the 1 is on the table, so hitting the 7 first is a foul on every sample
    let (legal, _) = check(&config("[game]\nrules = \"9-ball\"\n"), 500);
    assert_eq!(legal, 0);
    let c = config("[game]\nrules = \"three-cushion\"\n");
    let run = run_study(
        &c,
        &c.noise,
        200,
        3,
        &RunOptions {
            until: Until::Rest,
            limits: Limits::default(),
        },
        &mut |_, _| {},
    )
    .unwrap();
    assert!(run.iter().all(|s| s.verdict.is_some_and(|v| v.legal)));
    check(&c, 300);
}

/// `examples/snooker.toml` (a snooker position on `--table snooker`: the white, two reds
/// and three colours by pooltool's names, the white aimed to pot `red_01` in `lt`) with
/// `game` for its `[game]`.
fn snooker_study(game: &str) -> String {
    let text = include_str!("../examples/snooker.toml");
    let (head, _) = text.split_once("\n[game]").unwrap();
    format!("{head}\n{game}")
}

#[test]
fn snooker_verdicts_of_a_study_are_the_replays() {
    let parse = |game: &str| StudyConfig::parse(&snooker_study(game), "snooker.toml", None);
    // the example as it ships
    let example = StudyConfig::parse(&snooker_study(SNOOKER_GAME), "snooker.toml", None).unwrap();
    assert_eq!(example.game.as_ref().unwrap().rules, Rules::Snooker);
    // on the reds: the red in lt scores 1 and keeps the table; the white may follow it
    let c = parse("[game]\nrules = \"snooker\"\nhittable = [\"red_01\", \"red_02\"]\n").unwrap();
    assert_eq!(c.game.as_ref().unwrap().ids, [0, 1, 2, 19, 20, 21]);
    let (legal, kept) = check(&c, 400);
    assert!(legal > 200 && kept > 100, "{legal} legal, {kept} kept");
    // no hittable: the reds, worked out from the table, give the same verdicts
    let worked_out = parse("[game]\nrules = \"snooker\"\n").unwrap();
    assert_eq!(check(&worked_out, 400), (legal, kept));
    // on the black (called): the red first is a foul worth 7 to the opponent on every sample
    let c = parse(
        "[game]\nrules = \"snooker\"\nhittable = [\"blue\", \"pink\", \"black\"]\n\
         ball_call = \"black\"\nscore = 40\nopponent_score = 12\n",
    )
    .unwrap();
    let (legal, kept) = check(&c, 200);
    assert_eq!((legal, kept), (0, 0));
    let run = run_study(
        &c,
        &c.noise,
        50,
        5,
        &RunOptions {
            until: Until::Rest,
            limits: Limits::default(),
        },
        &mut |_, _| {},
    )
    .unwrap();
    assert!(
        run.iter()
            .all(|s| s.verdict.is_some_and(|v| v.foul_points == 7))
    );
    let summary = Summary::of(&c, &run, Until::Rest);
    let g = summary.game.unwrap();
    assert_eq!(g.foul_points.map(|f| f.mean), Some(7.0));
    assert_eq!(g.points.map(|p| p.mean), Some(0.0));
    // what snooker cannot judge, by key
    for (game, want) in [
        (
            "hittable = [\"red_01\", \"black\"]",
            "reds or colours, not both",
        ),
        ("hittable = [\"pink\", \"black\"]", "call one"),
        ("hittable = [\"green\"]", "key `game.hittable[0]`"),
    ] {
        let e = parse(&format!("[game]\nrules = \"snooker\"\n{game}\n"))
            .unwrap_err()
            .to_string();
        assert!(e.contains(want), "{game}: {want:?} not in {e}");
    }
}

#[test]
fn a_bad_game_names_its_key() {
    let bad = |game: &str, want: &str| {
        let e = StudyConfig::parse(&format!("{STUDY}\n{game}"), "study.toml", None)
            .unwrap_err()
            .to_string();
        assert!(e.contains(want), "{want:?} not in {e}");
    };
    bad("[game]\nrules = \"pyramid\"\n", "key `game.rules`");
    bad(
        "[game]\nrules = \"8-ball\"\nhittable = [9]\n",
        "key `game.hittable[0]`",
    );
    bad(
        "[game]\nrules = \"8-ball\"\npocket_call = \"xx\"\n",
        "key `game.pocket_call`",
    );
    bad(
        "[game]\nrules = \"8-ball\"\nball_call = \"cue2\"\n",
        "key `game.ball_call`",
    );
    bad("[game]\nrules = \"8-ball\"\nbreaks = true\n", "breaks");
    let named = STUDY.replacen("id = 5 # the screen", "id = \"five\"", 1);
    assert_ne!(named, STUDY);
    let e = StudyConfig::parse(
        &format!("{named}\n[game]\nrules = \"9-ball\"\n"),
        "s.toml",
        None,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("key `balls[2].id`") && e.contains("1 to 15"),
        "{e}"
    );
    assert_eq!(Foul::ALL.len(), 8);
    assert_eq!(Rules::from_name("8-ball"), Ok(Rules::EightBall));
}

#[test]
fn the_cli_reports_the_game_and_refuses_what_it_cannot_judge() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("s.toml");
    std::fs::write(
        &scenario,
        format!(
            "{}\n[game]\nrules = \"8-ball\"\nhittable = [1, 2, 3, 4, 5, 7]\nball_call = 7\n\
             pocket_call = \"lb\"\n",
            STUDY
        ),
    )
    .unwrap();
    let s = scenario.to_str().unwrap();
    let samples = dir.path().join("samples.csv");
    let out = common::run_kisstime(
        &[
            "shots",
            s,
            "--samples",
            "400",
            "-o",
            samples.to_str().unwrap(),
        ],
        &[],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("game (the rules' verdict)"), "{text}");
    assert!(text.contains("legal shot (8-ball)"), "{text}");
    let csv = std::fs::read_to_string(&samples).unwrap();
    let head = csv.lines().next().unwrap();
    assert!(
        head.ends_with(",cut,legal,foul,turn_over,game_over,won,points,foul_points"),
        "{head}"
    );
    assert_eq!(csv.lines().count(), 401);
    // JSON
    let out = common::run_kisstime(&["shots", s, "--samples", "100", "--json"], &[]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["game"]["rules"], "8-ball");
    let legal = v["game"]["legal"]["count"].as_u64().unwrap();
    let fouls: u64 = v["game"]["fouls"]
        .as_object()
        .unwrap()
        .values()
        .map(|f| f["count"].as_u64().unwrap())
        .sum();
    assert_eq!(legal + fouls, 100);
    // what cannot be judged is refused with a reason
    let out = common::run_kisstime(
        &["shots", s, "--samples", "10", "--until", "first-contact"],
        &[],
    );
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("runs to rest"));
    // on the GPU (where one opens; CI's lavapipe does) the same verdicts as on the CPU
    if std::env::var("KISSTIME_REQUIRE_GPU").as_deref() == Ok("1") {
        let json = |backend: &str| {
            let out = common::run_kisstime(
                &[
                    "shots",
                    s,
                    "--samples",
                    "200",
                    "--json",
                    "--backend",
                    backend,
                ],
                &[],
            );
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
            v["game"].clone()
        };
        assert_eq!(json("gpu"), json("cpu"));
    }
    let out = common::run_kisstime(
        &["shots", s, "--samples", "10", "--backend", "auto"],
        &[("KISSTIME_AUTO_GPU", "always")],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// With a game, `--plot` colours the heat map by the verdict (the table kept or not) and
/// adds the verdict's bars: the picture differs from the same study's without a game.
#[test]
fn the_picture_shows_the_verdict() {
    let dir = tempfile::tempdir().unwrap();
    let mut pictures = Vec::new();
    for (name, game) in [
        ("plain", ""),
        (
            "game",
            "[game]\nrules = \"8-ball\"\nhittable = [1, 2, 3, 4, 5, 7]\nball_call = 7\n\
             pocket_call = \"rt\"\n",
        ),
    ] {
        let scenario = dir.path().join(format!("{name}.toml"));
        std::fs::write(&scenario, format!("{STUDY}\n{game}")).unwrap();
        let png = dir.path().join(format!("{name}.png"));
        let out = common::run_kisstime(
            &[
                "shots",
                scenario.to_str().unwrap(),
                "--samples",
                "2000",
                "--plot",
                png.to_str().unwrap(),
            ],
            &[],
        );
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let bytes = std::fs::read(&png).unwrap();
        assert!(bytes.starts_with(b"\x89PNG"), "{name}: a PNG");
        pictures.push(bytes);
    }
    assert_ne!(pictures[0], pictures[1], "the verdict shows in the picture");
}
