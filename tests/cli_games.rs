//! `kisstime simulate --rules 9-ball|8-ball|snooker --context FILE --outcomes OUT`: the game
//! reference sets (`data/games/`, pooltool 0.6.0's own verdicts) turned into the
//! simulator's input files (balls, strikes, contexts) and judged through the command line:
//! every shot's verdict columns are pooltool's (on the shots whose event count is
//! pooltool's: all of 9-ball's and snooker's, all but a chaotic break of 8-ball's), the
//! points and the winner too; three-cushion's points on `data/carom`; bad contexts are
//! refused naming the file, the line and the table, with nothing written.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn data(game: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/games")).join(game)
}

/// A CSV file's rows as maps from column to cell (quoted cells may hold commas).
fn rows(text: &str) -> Vec<BTreeMap<String, String>> {
    let mut reader = csv::Reader::from_reader(text.as_bytes());
    let head: Vec<String> = reader
        .headers()
        .unwrap()
        .iter()
        .map(str::to_owned)
        .collect();
    reader
        .records()
        .map(|r| {
            head.iter()
                .cloned()
                .zip(r.unwrap().iter().map(str::to_owned))
                .collect()
        })
        .collect()
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap()
}

/// The set's shots as `simulate`'s input: (balls, strikes, contexts) files in `dir`, and
/// the shots whose context the command line cannot say (a group none of whose balls is on
/// the table: a context file lists only balls on the table, and an empty list is the open
/// table; an ordinary 8-ball shot that needs no call).
fn inputs(game: &str, dir: &Path) -> (PathBuf, PathBuf, PathBuf, Vec<String>) {
    let shots = rows(&read(&data(game).join("shots.csv")));
    let mut on_table: BTreeMap<String, Vec<String>> = BTreeMap::new();
    let mut balls = String::from("table,ball,state,x,y,vx,vy,wx,wy,wz\n");
    for b in rows(&read(&data(game).join("balls.csv"))) {
        on_table
            .entry(b["shot"].clone())
            .or_default()
            .push(b["ball"].clone());
        balls.push_str(&format!(
            "{},{},stationary,{},{},0,0,0,0,0\n",
            b["shot"], b["ball"], b["x"], b["y"]
        ));
    }
    let mut strikes = String::from("table,ball,V0,phi,theta,a,b\n");
    let scored = shots.first().is_some_and(|s| s.contains_key("score"));
    let mut contexts = String::from("table,break,hittable,ball_call,pocket_call");
    contexts.push_str(if scored {
        ",score,opponent_score\n"
    } else {
        "\n"
    });
    let mut unsaid = Vec::new();
    for s in &shots {
        strikes.push_str(&format!(
            "{},0,{},{},{},{},{}\n",
            s["shot"], s["v0"], s["phi"], s["theta"], s["a"], s["b"]
        ));
        let cell = |k: &str| s.get(k).cloned().unwrap_or_default();
        let (ball, pocket) = (cell("ball_call"), cell("pocket_call"));
        // 8-ball: the command line asks every shot but the break to be called, as
        // pooltool's game does; the set's few uncalled ordinary shots it cannot say
        if game == "eight_ball" && cell("call_shot") == "0" && s["break"] == "0" {
            unsaid.push(s["shot"].clone());
        }
        // the group's balls on the table (snooker's by number: pooltool's names, which the
        // context also takes, are left to ball_call)
        let here = &on_table[&s["shot"]];
        let group = cell("hittable");
        let hittable: Vec<String> = group
            .split(';')
            .map(|b| kisstime::game::snooker::id_of(b).map_or(b.to_owned(), |id| id.to_string()))
            .filter(|b| here.iter().any(|h| h == b))
            .collect();
        if !group.is_empty() && hittable.is_empty() {
            unsaid.push(s["shot"].clone());
        }
        let hittable = hittable.join(";");
        contexts.push_str(&format!(
            "{},{},{hittable},{ball},{pocket}",
            s["shot"], s["break"]
        ));
        if scored {
            contexts.push_str(&format!(",{},{}", s["score"], s["opponent_score"]));
        }
        contexts.push('\n');
    }
    let path = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    (
        path("balls.csv", &balls),
        path("strikes.csv", &strikes),
        path("contexts.csv", &contexts),
        unsaid,
    )
}

/// `kisstime simulate BALLS --strikes STRIKES --table TABLE --rules RULES --context
/// CONTEXT --outcomes OUT [extra]`, with `files` = [BALLS, STRIKES, CONTEXT, OUT], the
/// table `snooker` for snooker and `7ft` for the others.
fn judge_cli(files: [&Path; 4], rules: &str, extra: &[&str]) -> std::process::Output {
    let [balls, strikes, context, out] = files.map(|p| p.to_str().unwrap().to_owned());
    let table = if rules == "snooker" { "snooker" } else { "7ft" };
    let mut args = vec!["simulate", &balls, "--strikes", &strikes, "--table", table];
    args.extend(["--rules", rules, "--context", &context, "--outcomes", &out]);
    args.extend(extra);
    common::run_kisstime(&args, &[])
}

/// pooltool's reason for a foul code, per game.
fn reason(game: &str, code: &str) -> &'static str {
    use kisstime::game::{Foul, eight_ball, nine_ball, snooker};
    let foul = Foul::ALL.into_iter().find(|f| f.code() == code).unwrap();
    match game {
        "eight_ball" => eight_ball::pooltool_reason(foul),
        "snooker" => snooker::pooltool_reason(foul),
        _ => nine_ball::pooltool_reason(foul),
    }
}

/// The set of `game` judged by `--rules rules`; at least `percent` % of its shots must be
/// judged (the rest: the event counts differ, or the command line cannot say the context).
fn judged_through_the_cli(game: &str, rules: &str, percent: usize) {
    let dir = tempfile::tempdir().unwrap();
    let (balls, strikes, contexts, unsaid) = inputs(game, dir.path());
    let out = dir.path().join("outcomes.csv");
    let r = judge_cli([&balls, &strikes, &contexts, &out], rules, &[]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let mine = rows(&read(&out));
    let theirs = rows(&read(&data(game).join("shots.csv")));
    assert_eq!(mine.len(), theirs.len());
    let mut judged = 0;
    for (m, t) in mine.iter().zip(&theirs) {
        assert_eq!(m["table"], t["shot"]);
        if m["events"] != t["n_events"] || unsaid.contains(&t["shot"]) {
            continue;
        }
        judged += 1;
        let why = if m["foul"].is_empty() {
            ""
        } else {
            reason(game, &m["foul"])
        };
        let mut want = vec![(t["legal"].as_str(), m["legal"].as_str())];
        want.push((t["turn_over"].as_str(), m["turn_over"].as_str()));
        want.push((t["game_over"].as_str(), m["game_over"].as_str()));
        assert!(
            want.iter().all(|(a, b)| a == b),
            "shot {}: {m:?} vs {t:?}",
            t["shot"]
        );
        assert_eq!(why, t["reason"], "shot {}", t["shot"]);
        if let Some(won) = t.get("won") {
            assert_eq!(&m["won"], won, "shot {}", t["shot"]);
        }
        for points in ["points", "foul_points"] {
            let want = t.get(points).map_or("0", |p| p.as_str());
            assert_eq!(m[points], want, "shot {}: {points}", t["shot"]);
        }
    }
    println!(
        "{judged} of {} shots judged as pooltool judged them",
        mine.len()
    );
    assert!(
        judged * 100 >= mine.len() * percent,
        "{judged} of {} judged",
        mine.len()
    );
}

#[test]
fn nine_ball_through_the_cli() {
    judged_through_the_cli("nine_ball", "9-ball", 99);
}

#[test]
fn eight_ball_through_the_cli() {
    judged_through_the_cli("eight_ball", "8-ball", 85);
}

/// Snooker on `--table snooker`: the context's hittable balls by number, the call by
/// pooltool's name, the score columns; every verdict, the points and the winner pooltool's.
#[test]
fn snooker_through_the_cli() {
    judged_through_the_cli("snooker", "snooker", 99);
}

#[test]
fn bad_contexts_and_rules_are_refused_naming_the_file_line_and_table() {
    let dir = tempfile::tempdir().unwrap();
    let (balls, strikes, _, _) = inputs("nine_ball", dir.path());
    let out = dir.path().join("o.csv");
    let s = |p: &Path| p.to_str().unwrap().to_owned();
    let run = |rules: &str, context: &str| {
        let c = dir.path().join("c.csv");
        std::fs::write(
            &c,
            format!("table,break,hittable,ball_call,pocket_call\n{context}\n"),
        )
        .unwrap();
        judge_cli([&balls, &strikes, &c, &out], rules, &[])
    };
    for (context, words) in [
        (
            "9999,0,,,",
            &["c.csv", "line 2", "table 9999", "not in the input"][..],
        ),
        (
            "5,0,,,zz",
            &["line 2", "table 5", "pocket_call \"zz\"", "lb"],
        ),
        ("5,0,15,,", &["table 5", "hittable ball 15", "no such ball"]),
    ] {
        let r = run("8-ball", context);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{context}: {err}");
        for w in words {
            assert!(err.contains(w), "{context}: {w} not in {err}");
        }
        assert!(!out.exists(), "{context}: an output was written");
    }
    let r = run("pyramid", "5,0,,,");
    assert_eq!(r.status.code(), Some(2));
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(err.contains("9-ball") && err.contains("snooker"), "{err}");
    // the rules need the outcomes to write the verdict to
    let r = common::run_kisstime(&["simulate", &s(&balls), "--rules", "9-ball"], &[]);
    assert_eq!(r.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&r.stderr).contains("--outcomes"));
}

/// The rules judge the GPU's events as the CPU's: the 9-ball set's first 200 shots through
/// `--backend gpu` (lavapipe in CI) give the CPU's verdict columns, row for row.
#[test]
fn the_gpu_s_shots_are_judged_as_the_cpu_s() {
    if common::gpu_or_skip(kisstime::Precision::F64, "games on the GPU").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (balls, strikes, contexts, _) = inputs("nine_ball", dir.path());
    // the first 200 tables only
    let keep = |path: &Path, name: &str| {
        let text = read(path);
        let mut lines = text.lines();
        let mut out = format!("{}\n", lines.next().unwrap());
        for l in lines {
            let table: usize = l.split(',').next().unwrap().parse().unwrap();
            if table < 200 {
                out.push_str(l);
                out.push('\n');
            }
        }
        let p = dir.path().join(name);
        std::fs::write(&p, out).unwrap();
        p
    };
    let (balls, strikes) = (keep(&balls, "b200.csv"), keep(&strikes, "s200.csv"));
    let contexts = keep(&contexts, "c200.csv");
    let mut verdicts = Vec::new();
    for backend in ["cpu", "gpu"] {
        let out = dir.path().join(format!("{backend}.csv"));
        let r = judge_cli(
            [&balls, &strikes, &contexts, &out],
            "9-ball",
            &["--backend", backend],
        );
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let cols = [
            "table",
            "events",
            "legal",
            "foul",
            "turn_over",
            "game_over",
            "won",
        ];
        let rows: Vec<Vec<String>> = rows(&read(&out))
            .iter()
            .map(|m| cols.iter().map(|c| m[*c].clone()).collect())
            .collect();
        verdicts.push(rows);
    }
    assert_eq!(verdicts[0].len(), 200);
    assert_eq!(verdicts[0], verdicts[1]);
}

/// `--table carom --rules three-cushion`: the `data/carom` shots written as the
/// simulator's input files (ball ids 0, 1, 2 for white, yellow, red; the carom balls come
/// with the table) score exactly where pooltool's `three_cushion.is_point` did (the set's
/// `point` column): `turn_over` 0 on a point, every shot legal.
#[test]
fn three_cushion_points_through_the_cli() {
    let set = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/carom"));
    let shots = rows(&read(&set.join("shots.csv")));
    let mut balls = String::from("table,ball,state,x,y,vx,vy,wx,wy,wz\n");
    for r in rows(&read(&set.join("initial.csv"))) {
        balls += &format!(
            "{},{},stationary,{},{},0,0,0,0,0\n",
            r["shot"], r["ball"], r["x"], r["y"]
        );
    }
    let mut strikes = String::from("table,ball,V0,phi,theta,a,b\n");
    for r in &shots {
        assert_eq!(r["cue_ball_id"], "white");
        strikes += &format!(
            "{},0,{},{},{},{},{}\n",
            r["shot"], r["V0"], r["phi"], r["theta"], r["a"], r["b"]
        );
    }
    let dir = tempfile::tempdir().unwrap();
    let (b, s, o) = (
        dir.path().join("balls.csv"),
        dir.path().join("strikes.csv"),
        dir.path().join("outcomes.csv"),
    );
    std::fs::write(&b, balls).unwrap();
    std::fs::write(&s, strikes).unwrap();
    let out = common::run_kisstime(
        &[
            "simulate",
            b.to_str().unwrap(),
            "--strikes",
            s.to_str().unwrap(),
            "--table",
            "carom",
            "--rules",
            "three-cushion",
            "--outcomes",
            o.to_str().unwrap(),
        ],
        &[],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let judged = rows(&read(&o));
    assert_eq!(judged.len(), shots.len());
    let mut points = 0;
    for (v, r) in judged.iter().zip(&shots) {
        assert_eq!((v["legal"].as_str(), v["foul"].as_str()), ("1", ""));
        let point = r["point"] == "1";
        points += usize::from(point);
        assert_eq!(v["turn_over"] == "0", point, "shot {}", r["shot"]);
        assert_eq!(
            v["points"],
            if point { "1" } else { "0" },
            "shot {}",
            r["shot"]
        );
        // no score given: one point wins no game
        assert_eq!((v["game_over"].as_str(), v["won"].as_str()), ("0", "0"));
    }
    assert!(points >= 5, "{points} points");
}
