//! The snooker and carom tables with their own balls (issue 28): `data/snooker` (10
//! snooker breaks and 30 ordinary snooker shots) and `data/carom` (40 three-cushion shots)
//! are pooltool 0.6.0's own runs on `Table.from_game_type(SNOOKER | THREECUSHION)` with the
//! balls pooltool gives those games (`tools/games/tables_reference.py`, seeded). Each set's
//! table is kisstime's built-in `snooker`/`carom` table, its `physics.toml` is
//! `BallParams::snooker()`/`carom()`, and kisstime's replay passes the set's judge
//! (`check_fullshots.py --ref`) on every shot; with pool balls instead, most shots fail.
//! `kisstime simulate --table snooker|carom` without `--physics` plays those balls.

mod common;

use std::path::{Path, PathBuf};

use kisstime::io::physics::read_physics;
use kisstime::io::shot_set::read_table;
use kisstime::io::table_json::{default_ball_params, table_by_name};
use kisstime::simulate::{BallParams, SimParams};

fn set_dir(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data")
        .join(name)
}

fn check_set(name: &str, balls: BallParams, shots: usize) {
    let dir = set_dir(name);
    assert_eq!(read_table(&dir).unwrap(), table_by_name(name).unwrap());
    let params = read_physics(&dir.join("physics.toml")).unwrap();
    assert_eq!(
        params.ball, balls,
        "{name}: physics.toml is pooltool's balls for the game"
    );
    assert_eq!(default_ball_params(name), balls);
    let (n, events, verdict) = common::replay_and_judge(&dir, params);
    assert_eq!(n, shots);
    println!("{name}: {n} shots, {events} events");
    if let Some((passed, failed, text)) = verdict {
        assert_eq!((passed, failed), (shots, 0), "check_fullshots.py:\n{text}");
    }
    // with pool balls the same starts give other shots
    let (_, _, verdict) = common::replay_and_judge(&dir, SimParams::default());
    if let Some((passed, _, text)) = verdict {
        assert!(
            passed < shots / 2,
            "{name}: the balls should matter: {passed} of {shots} pass with pool balls\n{text}"
        );
    }
}

#[test]
fn snooker_shots_are_pooltools() {
    check_set("snooker", BallParams::snooker(), 40);
}

#[test]
fn carom_shots_are_pooltools() {
    check_set("carom", BallParams::carom(), 40);
}

fn kisstime(args: &[&str]) -> std::process::Output {
    common::run_kisstime(args, &[])
}

/// `--table snooker` (and `carom`) without `--physics` simulates that game's balls: the
/// same result as `--physics` with the set's `physics.toml`, another than with pool balls.
#[test]
fn the_built_in_tables_play_their_own_balls() {
    let dir = tempfile::tempdir().unwrap();
    for (name, balls) in [
        (
            "snooker",
            "0,0,stationary,0.8,0.7,0,0,0,0,0\n0,1,stationary,0.9,1.9,0,0,0,0,0\n",
        ),
        (
            "carom",
            "0,0,stationary,0.7,0.5,0,0,0,0,0\n0,1,stationary,0.8,1.9,0,0,0,0,0\n",
        ),
    ] {
        let input = dir.path().join(format!("{name}.csv"));
        std::fs::write(
            &input,
            format!("table,ball,state,x,y,vx,vy,wx,wy,wz\n{balls}"),
        )
        .unwrap();
        let strikes = dir.path().join("strikes.csv");
        std::fs::write(
            &strikes,
            "table,ball,V0,phi,theta,a,b\n0,0,3,80,0,0.2,0.3\n",
        )
        .unwrap();
        let pool = dir.path().join("pool.toml");
        std::fs::write(&pool, "m = 0.170097\n").unwrap();
        let physics = set_dir(name).join("physics.toml");
        let run = |extra: &[&str]| {
            let mut args = vec![
                "simulate",
                input.to_str().unwrap(),
                "--strikes",
                strikes.to_str().unwrap(),
                "--table",
                name,
            ];
            args.extend_from_slice(extra);
            let out = kisstime(&args);
            assert!(
                out.status.success(),
                "{name}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            String::from_utf8(out.stdout).unwrap()
        };
        let plain = run(&[]);
        assert_eq!(
            plain,
            run(&["--physics", physics.to_str().unwrap()]),
            "{name}"
        );
        assert_ne!(plain, run(&["--physics", pool.to_str().unwrap()]), "{name}");
    }
}

/// The three-cushion judge on kisstime's replay of every `data/carom` shot gives pooltool's
/// own `three_cushion.is_point` (the set's `point` column), points and misses alike.
#[test]
fn three_cushion_points_are_pooltools() {
    use kisstime::game::{Context, Rules, Shot};
    use kisstime::io::shot_set::read_shots;
    use kisstime::simulate::{BatchOptions, simulate_batch};

    let dir = set_dir("carom");
    let params = read_physics(&dir.join("physics.toml")).unwrap();
    let table = read_table(&dir).unwrap();
    let shots = read_shots(&dir, params.ball.r).unwrap();
    let text = std::fs::read_to_string(dir.join("shots.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = head.iter().position(|h| *h == "point").unwrap();
    let points: Vec<bool> = lines.map(|l| l.split(',').nth(col) == Some("1")).collect();
    assert_eq!(points.len(), shots.len());
    let scored = points.iter().filter(|&&p| p).count();
    assert!(
        scored >= 5 && shots.len() - scored >= 5,
        "the set should hold points and misses: {scored} of {}",
        shots.len()
    );
    let input = |k: usize, balls: &mut Vec<_>| {
        balls.clear();
        balls.extend_from_slice(&shots[k].balls);
        Ok(Some((shots[k].cue, shots[k].strike)))
    };
    let mut verdicts = Vec::new();
    simulate_batch(
        &table,
        params,
        &BatchOptions::default(),
        shots.len(),
        input,
        |chunk| {
            for run in chunk.iter() {
                let start = &shots[verdicts.len()].balls;
                let ids: Vec<i64> = (0..start.len() as i64).collect();
                let shot = Shot {
                    ids: &ids,
                    start,
                    events: run.events,
                };
                verdicts.push(
                    Rules::ThreeCushion
                        .judge(&shot, &Context::default())
                        .unwrap(),
                );
            }
            Ok::<(), ()>(())
        },
    )
    .unwrap();
    for (k, (v, &point)) in verdicts.iter().zip(&points).enumerate() {
        assert!(
            v.legal && v.foul.is_none(),
            "shot {k}: three-cushion has no fouls"
        );
        assert_eq!(
            !v.turn_over, point,
            "shot {k}: kisstime's point against pooltool's"
        );
    }
}

/// A study on `kind = "snooker"` without `[physics]` plays snooker balls; with a
/// `[physics]` key, the rest are pooltool's class defaults, as `BallParams(...)` gives.
#[test]
fn a_study_on_the_snooker_table_plays_snooker_balls() {
    use kisstime::study::StudyConfig;
    let scenario = |physics: &str| {
        format!(
            "[table]\nkind = \"snooker\"\n{physics}\n\
             [[balls]]\nid = \"white\"\nx = 0.8\ny = 0.7\n\
             [[balls]]\nid = \"black\"\nx = 0.873\ny = 3.2\n\
             [shot]\ncue_ball = \"white\"\nobject_ball = \"black\"\npocket = \"lt\"\n\
             v0 = 2.0\nphi = 90.0\ntheta = 0.0\na = 0.0\nb = 0.0\n"
        )
    };
    let plain = StudyConfig::parse(&scenario(""), "snooker.toml", None).unwrap();
    assert_eq!(plain.params.ball, BallParams::snooker());
    let given = StudyConfig::parse(&scenario("[physics]\nu_r = 0.012\n"), "s.toml", None).unwrap();
    assert_eq!(
        given.params.ball,
        BallParams {
            u_r: 0.012,
            ..BallParams::default()
        }
    );
}
