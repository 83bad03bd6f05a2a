//! `kisstime simulate` end to end: a shot's first events, the summary line, CSV and `.npy`
//! outputs agreeing, byte-identical outputs on 1 and 2 threads, a table cut by
//! `--max-events`, every bad input (exit 2, the message names the file, line, table and
//! ball, no output left behind), and the reference set's first shots giving the same event
//! sequences as `io::shot_set::replay`.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use kisstime::io::shot_set::{ReplayOut, read_shots, replay};
use kisstime::simulate::{Limits, SimParams, Table};

const BALLS: &str = "table,ball,state,x,y,vx,vy,wx,wy,wz\n\
    1,0,stationary,0.635,0.6,0,0,0,0,0\n\
    1,1,stationary,0.635,1.905,0,0,0,0,0\n\
    2,0,stationary,0.635,0.6,0,0,0,0,0\n\
    2,5,stationary,0.3,1.905,0,0,0,0,0\n\
    3,2,rolling,0.3,0.3,0.5,1.0,-35.0,17.5,0\n\
    3,7,stationary,0.9,1.5,0,0,0,0,0\n";
const STRIKES: &str = "table,ball,V0,phi,theta,a,b\n1,0,2,90,0,0,0.2\n2,0,3,100,0,0.1,0\n";

struct Run {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

fn kisstime(args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_kisstime"))
        .args(args)
        .output()
        .expect("the kisstime binary runs");
    Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

fn s(p: &Path) -> &str {
    p.to_str().expect("temporary paths are UTF-8")
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn csv_rows(text: &str) -> Vec<Vec<String>> {
    text.lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect()
}

#[test]
fn a_shot_gives_the_expected_first_events_and_a_summary() {
    let dir = tempfile::tempdir().unwrap();
    let balls = write(dir.path(), "balls.csv", BALLS);
    let strikes = write(dir.path(), "strikes.csv", STRIKES);
    let ev = dir.path().join("ev.csv");
    let r = kisstime(&[
        "simulate",
        s(&balls),
        "--strikes",
        s(&strikes),
        "-o",
        s(&ev),
    ]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    // with -o and no --final, nothing on stdout
    assert!(r.stdout.is_empty());
    let summary = r.stderr.lines().last().unwrap();
    assert!(
        summary.starts_with("3 tables, ")
            && summary.contains(" events in ")
            && summary.contains(" tables/s, ")
            && summary.contains(" events/s on cpu f64 ("),
        "{summary}"
    );
    let text = std::fs::read_to_string(&ev).unwrap();
    assert_eq!(
        text.lines().next().unwrap(),
        "table,k,t,type,agent_a,agent_b,ball,state,x,y,vx,vy,wx,wy,wz"
    );
    let rows = csv_rows(&text);
    let t1: Vec<&Vec<String>> = rows.iter().filter(|r| r[0] == "1").collect();
    assert_eq!(&t1[0][1..4], ["0", "0.0", "stick_ball"]);
    assert_eq!((t1[0][4].as_str(), t1[0][7].as_str()), ("0", "sliding"));
    assert_eq!(t1[1][3], "sliding_rolling");
    // then the cue ball hits ball 1: two rows, one per ball
    let first_bb = t1.iter().find(|r| r[3] == "ball_ball").unwrap();
    let bb: Vec<_> = t1.iter().filter(|r| r[1] == first_bb[1]).collect();
    assert_eq!(bb.len(), 2);
    assert_eq!((bb[0][4].as_str(), bb[0][5].as_str()), ("0", "1"));
    assert_eq!((bb[0][6].as_str(), bb[1][6].as_str()), ("0", "1"));
    // table 3 has no strike: its rolling ball simply rolls (its first event a transition
    // or a cushion), no stick_ball
    let t3: Vec<_> = rows.iter().filter(|r| r[0] == "3").collect();
    assert!(!t3.is_empty() && t3.iter().all(|r| r[3] != "stick_ball"));
    // without -o and --final: the final states on stdout
    let r = kisstime(&["simulate", s(&balls), "--strikes", s(&strikes)]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let mut lines = r.stdout.lines();
    assert_eq!(
        lines.next(),
        Some("table,ball,state,x,y,vx,vy,wx,wy,wz,pocket")
    );
    assert_eq!(r.stdout.lines().count(), 7);
    assert!(r.stdout.lines().skip(1).all(|l| l.contains(",stationary,")));
}

/// Reads one of our structured `.npy` outputs: its column names and its rows (every field
/// is 8 bytes: `<i8` as i64, `<f8` as f64, both returned as f64 where exact).
fn read_npy(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
    let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
    assert_eq!((10 + len) % 64, 0);
    let mut names = Vec::new();
    let mut ints = Vec::new();
    for part in header.split("('").skip(1) {
        let mut it = part.split('\'');
        let name = it.next().unwrap().to_owned();
        let ty = it.nth(1).unwrap();
        ints.push(ty == "<i8");
        names.push(name);
    }
    let n: usize = header
        .split("'shape': (")
        .nth(1)
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let data = &bytes[10 + len..];
    assert_eq!(data.len(), n * 8 * names.len());
    let rows = data
        .chunks_exact(8 * names.len())
        .map(|row| {
            row.chunks_exact(8)
                .zip(&ints)
                .map(|(b, &int)| {
                    let b: [u8; 8] = b.try_into().unwrap();
                    if int {
                        i64::from_le_bytes(b) as f64
                    } else {
                        f64::from_le_bytes(b)
                    }
                })
                .collect()
        })
        .collect();
    (names, rows)
}

const TYPES: [&str; 9] = [
    "stick_ball",
    "ball_ball",
    "ball_linear_cushion",
    "ball_circular_cushion",
    "ball_pocket",
    "sliding_rolling",
    "rolling_spinning",
    "rolling_stationary",
    "spinning_stationary",
];
const STATES: [&str; 5] = ["stationary", "spinning", "sliding", "rolling", "pocketed"];

/// A CSV cell as the `.npy` output codes it.
fn code(column: &str, text: &str, kind: &str, table: &Table) -> f64 {
    let index = |ids: &[String]| ids.iter().position(|i| i == text).unwrap() as f64;
    match column {
        "type" => TYPES.iter().position(|t| *t == text).unwrap() as f64,
        "state" => STATES.iter().position(|t| *t == text).unwrap() as f64,
        "cut" => ["none", "max_events", "max_time"]
            .iter()
            .position(|t| *t == text)
            .unwrap() as f64,
        "pocket" if text.is_empty() => -1.0,
        "pocket" => index(&table.pocket_ids),
        "agent_b" => match (kind, text) {
            (_, "") => -1.0,
            ("ball_linear_cushion", _) => index(&table.linear_ids),
            ("ball_circular_cushion", _) => index(&table.circular_ids),
            ("ball_pocket", _) => index(&table.pocket_ids),
            _ => text.parse().unwrap(),
        },
        _ => text.parse().unwrap(),
    }
}

/// A break-like batch: many tables with a rack, struck in different ways (pots, cushions,
/// jaws), to exercise every kind of event.
fn rack_batch(dir: &Path, tables: usize) -> (PathBuf, PathBuf) {
    let set = concat!(env!("CARGO_MANIFEST_DIR"), "/data/fullshots");
    let shots = read_shots(Path::new(set), SimParams::default().ball.r).unwrap();
    let (mut balls, mut strikes) = (
        String::from("table,ball,state,x,y,vx,vy,wx,wy,wz\n"),
        String::from("table,ball,V0,phi,theta,a,b\n"),
    );
    for t in 0..tables {
        let shot = &shots[t % shots.len()];
        for (i, b) in shot.balls.iter().enumerate() {
            balls.push_str(&format!(
                "{t},{i},stationary,{:?},{:?},0,0,0,0,0\n",
                b.r.x, b.r.y
            ));
        }
        let st = shot.strike;
        strikes.push_str(&format!(
            "{t},{},{:?},{:?},{:?},{:?},{:?}\n",
            shot.cue, st.v0, st.phi, st.theta, st.a, st.b
        ));
    }
    (
        write(dir, "rack.csv", &balls),
        write(dir, "rack_strikes.csv", &strikes),
    )
}

#[test]
fn csv_and_npy_outputs_agree_and_threads_do_not_matter() {
    let dir = tempfile::tempdir().unwrap();
    let (balls, strikes) = rack_batch(dir.path(), 12);
    let out = |name: &str| dir.path().join(name);
    let run = |ext: &str, threads: &str| {
        let (ev, fin, oc) = (
            out(&format!("ev{threads}.{ext}")),
            out(&format!("fin{threads}.{ext}")),
            out(&format!("oc{threads}.{ext}")),
        );
        let r = kisstime(&[
            "simulate",
            s(&balls),
            "--strikes",
            s(&strikes),
            "-o",
            s(&ev),
            "--final",
            s(&fin),
            "--outcomes",
            s(&oc),
            "--threads",
            threads,
        ]);
        assert_eq!(r.code, Some(0), "{}", r.stderr);
        (ev, fin, oc)
    };
    let csv1 = run("csv", "1");
    let csv2 = run("csv", "2");
    let npy1 = run("npy", "1");
    let npy2 = run("npy", "2");
    for (a, b) in [
        (&csv1.0, &csv2.0),
        (&csv1.1, &csv2.1),
        (&csv1.2, &csv2.2),
        (&npy1.0, &npy2.0),
        (&npy1.1, &npy2.1),
        (&npy1.2, &npy2.2),
    ] {
        assert_eq!(
            std::fs::read(a).unwrap(),
            std::fs::read(b).unwrap(),
            "{a:?}"
        );
    }
    let table = Table::nine_foot();
    let mut kinds = std::collections::HashSet::new();
    for (c, n) in [(&csv1.0, &npy1.0), (&csv1.1, &npy1.1), (&csv1.2, &npy1.2)] {
        let text = std::fs::read_to_string(c).unwrap();
        let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
        let rows = csv_rows(&text);
        let (names, npy_rows) = read_npy(n);
        assert_eq!(names, header);
        assert_eq!(rows.len(), npy_rows.len());
        for (r, q) in rows.iter().zip(&npy_rows) {
            let kind = if header[3] == "type" {
                r[3].as_str()
            } else {
                ""
            };
            kinds.insert(kind.to_owned());
            for ((col, text), v) in header.iter().zip(r).zip(q) {
                let want = code(col, text, kind, &table);
                assert!(
                    want.to_bits() == v.to_bits() || (want == 0.0 && *v == 0.0),
                    "{col}: {text} vs {v}"
                );
            }
        }
    }
    for k in [
        "ball_ball",
        "ball_linear_cushion",
        "ball_pocket",
        "stick_ball",
    ] {
        assert!(kinds.contains(k), "{k} missing from {kinds:?}");
    }
}

#[test]
fn a_table_cut_by_the_event_cap_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let balls = write(dir.path(), "balls.csv", BALLS);
    let strikes = write(dir.path(), "strikes.csv", STRIKES);
    let (ev, oc) = (dir.path().join("ev.csv"), dir.path().join("oc.csv"));
    let r = kisstime(&[
        "simulate",
        s(&balls),
        "--strikes",
        s(&strikes),
        "--max-events",
        "4",
        "-o",
        s(&ev),
        "--outcomes",
        s(&oc),
    ]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert!(r.stderr.contains("were cut"), "{}", r.stderr);
    let outcomes = std::fs::read_to_string(&oc).unwrap();
    let rows = csv_rows(&outcomes);
    assert_eq!(rows[0][0..2], ["1", "4"]);
    assert_eq!(rows[0][3], "max_events");
    let events = csv_rows(&std::fs::read_to_string(&ev).unwrap());
    assert_eq!(
        events
            .iter()
            .filter(|r| r[0] == "1")
            .map(|r| r[1].clone())
            .max(),
        Some("3".to_owned())
    );
    let r = kisstime(&[
        "simulate",
        s(&balls),
        "--strikes",
        s(&strikes),
        "--max-time",
        "0.3",
        "--outcomes",
        s(&oc),
        "--final",
        s(&dir.path().join("f.csv")),
    ]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let outcomes = std::fs::read_to_string(&oc).unwrap();
    assert!(outcomes.lines().nth(1).unwrap().ends_with(",max_time"));
}

#[test]
fn bad_input_exits_2_names_the_place_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let good_strikes = write(dir.path(), "strikes.csv", STRIKES);
    let ev = dir.path().join("ev.csv");
    let fin = dir.path().join("fin.npy");
    let check = |balls: &str, strikes: &Path, extra: &[&str], code: i32, want: &[&str]| {
        let input = write(dir.path(), "in.csv", balls);
        let mut args = vec![
            "simulate",
            s(&input),
            "--strikes",
            s(strikes),
            "-o",
            s(&ev),
            "--final",
            s(&fin),
        ];
        args.extend_from_slice(extra);
        let r = kisstime(&args);
        assert_eq!(r.code, Some(code), "{want:?}: {}", r.stderr);
        for w in want {
            assert!(r.stderr.contains(w), "{w:?} not in {}", r.stderr);
        }
        assert!(
            !ev.exists() && !fin.exists(),
            "{want:?}: an output was left"
        );
        let left: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().starts_with(".kisstime"))
            .collect();
        assert!(left.is_empty(), "temporary files left: {left:?}");
    };
    let with = |line: &str| BALLS.replace("2,5,stationary,0.3,1.905,0,0,0,0,0", line);
    // a ball off the table, inside a cushion, inside a jaw, overlapping at rest
    check(
        &with("2,5,stationary,1.5,1.905,0,0,0,0,0"),
        &good_strikes,
        &[],
        2,
        &["in.csv", "line 5", "table 2", "ball 5", "off the table"],
    );
    check(
        &with("2,5,stationary,0.01,1.0,0,0,0,0,0"),
        &good_strikes,
        &[],
        2,
        &[
            "in.csv",
            "line 5",
            "table 2",
            "ball 5",
            "inside cushion segment 3",
        ],
    );
    check(
        &with("2,5,stationary,0.635,0.63,0,0,0,0,0"),
        &good_strikes,
        &[],
        2,
        &["in.csv", "line 5", "table 2", "ball 5", "overlaps ball 0"],
    );
    check(
        &with("2,5,stationary,inf,1.0,0,0,0,0,0"),
        &good_strikes,
        &[],
        2,
        &["in.csv", "line 5", "table 2", "ball 5", "finite"],
    );
    // strikes: a missing ball, a missing table, two for one table, a² + b² > 1, NaN
    let strike = |rows: &str| {
        write(
            dir.path(),
            "bad_strikes.csv",
            &format!("table,ball,V0,phi,theta,a,b\n{rows}"),
        )
    };
    let bad_strikes = dir.path().join("bad_strikes.csv");
    let cases: [(&str, &[&str]); 5] = [
        (
            "1,4,2,90,0,0,0\n",
            &["line 2", "table 1", "ball 4", "no such ball"],
        ),
        ("9,0,2,90,0,0,0\n", &["line 2", "table 9", "no such table"]),
        (
            "1,0,2,90,0,0,0\n2,0,1,0,0,0,0\n1,1,2,90,0,0,0\n",
            &["line 4", "table 1", "ball 1", "second strike", "line 2"],
        ),
        (
            "1,0,2,90,0,0.9,0.5\n",
            &["line 2", "table 1", "ball 0", "a² + b² > 1"],
        ),
        (
            "1,0,NaN,90,0,0,0\n",
            &["line 2", "table 1", "ball 0", "non-finite"],
        ),
    ];
    for (rows, want) in cases {
        strike(rows);
        let mut want = want.to_vec();
        want.push("bad_strikes.csv");
        check(BALLS, &bad_strikes, &[], 2, &want);
    }
    // a bad table file (named), a missing one (I/O: exit 1)
    let bad_table = write(dir.path(), "table.json", "{\"table\": {\"pockets\": 3");
    check(
        BALLS,
        &good_strikes,
        &["--table", s(&bad_table)],
        2,
        &["table.json", "bad JSON"],
    );
    let missing = dir.path().join("nope.json");
    check(
        BALLS,
        &good_strikes,
        &["--table", s(&missing)],
        1,
        &["nope.json"],
    );
    // more balls than the simulator takes
    let mut many = String::from("table,ball,state,x,y,vx,vy,wx,wy,wz\n");
    for i in 0..65 {
        many.push_str(&format!(
            "4,{i},stationary,{},{},0,0,0,0,0\n",
            0.1 + 0.1 * (i % 10) as f64,
            0.1 + 0.3 * (i / 10) as f64
        ));
    }
    let no_strikes = strike("");
    check(
        &many,
        &no_strikes,
        &[],
        2,
        &["in.csv", "table 4", "at most 64"],
    );
    // the limits, by the one rule every entry point applies (Limits::new)
    check(
        BALLS,
        &good_strikes,
        &["--max-time", "0"],
        2,
        &["max_time 0: it must be greater than 0 s"],
    );
    check(
        BALLS,
        &good_strikes,
        &["--max-time", "nan"],
        2,
        &["max_time NaN: it must be greater than 0 s"],
    );
    check(
        BALLS,
        &good_strikes,
        &["--max-events", "0"],
        2,
        &["max_events 0: it must be at least 1"],
    );
}

#[test]
fn the_reference_set_gives_the_replays_event_sequences() {
    let set = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/fullshots"));
    // breaks first in the set, then ordinary shots: take some of each
    let picked: Vec<usize> = (0..6).chain(100..110).collect();
    same_events_as_the_replay(set, &picked, None);
}

#[test]
fn the_physics_set_with_physics_gives_the_replays_event_sequences() {
    let set = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/physics"));
    // 100 ordinary shots, then 20 breaks: take some of each
    let picked: Vec<usize> = (0..10).chain(100..103).collect();
    same_events_as_the_replay(set, &picked, Some(&set.join("physics.toml")));
}

/// `kisstime simulate` (with `--physics FILE` when given) on the shots `picked` of the
/// reference set `set` gives, bit for bit, the events of `io::shot_set::replay` with the
/// parameters the library's parser reads from that file (pooltool's defaults without).
fn same_events_as_the_replay(set: &Path, picked: &[usize], physics: Option<&Path>) {
    let params = kisstime::io::physics::read_physics_or_default(physics).unwrap();
    let mut shots = read_shots(set, params.ball.r).unwrap();
    shots = picked.iter().map(|&k| shots[k].clone()).collect();
    let dir = tempfile::tempdir().unwrap();
    // convert: ball ids are pooltool's ball order (its `ball` column), so that ascending
    // id order is pooltool's order, which decides exact ties
    let set_initial = std::fs::read_to_string(set.join("initial.csv")).unwrap();
    let set_shots = std::fs::read_to_string(set.join("shots.csv")).unwrap();
    let mut names: HashMap<(usize, i64), String> = HashMap::new();
    let mut balls = String::from("table,ball,state,x,y,vx,vy,wx,wy,wz\n");
    for row in csv_rows(&set_initial) {
        let shot: usize = row[0].parse().unwrap();
        if picked.contains(&shot) {
            let ball: i64 = row[1].parse().unwrap();
            names.insert((shot, ball), row[2].clone());
            balls.push_str(&format!(
                "{shot},{ball},stationary,{},{},0,0,0,0,0\n",
                row[3], row[4]
            ));
        }
    }
    let header: Vec<String> = set_shots
        .lines()
        .next()
        .unwrap()
        .split(',')
        .map(str::to_owned)
        .collect();
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let mut strikes = String::from("table,ball,V0,phi,theta,a,b\n");
    for row in csv_rows(&set_shots) {
        let shot: usize = row[0].parse().unwrap();
        if picked.contains(&shot) {
            let cue = names
                .iter()
                .find(|((s, _), n)| *s == shot && **n == row[col("cue_ball_id")])
                .map(|((_, b), _)| *b)
                .unwrap();
            strikes.push_str(&format!(
                "{shot},{cue},{},{},{},{},{}\n",
                row[col("V0")],
                row[col("phi")],
                row[col("theta")],
                row[col("a")],
                row[col("b")]
            ));
        }
    }
    let balls = write(dir.path(), "balls.csv", &balls);
    let strikes = write(dir.path(), "strikes.csv", &strikes);
    let ev = dir.path().join("ev.csv");
    let table_json = set.join("table.json");
    let mut args = vec![
        "simulate",
        s(&balls),
        "--strikes",
        s(&strikes),
        "--table",
        s(&table_json),
        "-o",
        s(&ev),
    ];
    if let Some(p) = physics {
        args.extend(["--physics", s(p)]);
    }
    let r = kisstime(&args);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let table = kisstime::io::shot_set::read_table(set).unwrap();
    // ours, as (shot, k, t, type, agents) with pooltool's names, one row per event
    let mut ours = Vec::new();
    for row in csv_rows(&std::fs::read_to_string(&ev).unwrap()) {
        if row[6] != row[4] {
            continue; // the second ball of a ball-ball event
        }
        let shot: usize = row[0].parse().unwrap();
        let name = |id: &str| names[&(shot, id.parse::<i64>().unwrap())].clone();
        let agents = match row[3].as_str() {
            "stick_ball" => format!("cue_stick;{}", name(&row[4])),
            "ball_ball" => format!("{};{}", name(&row[4]), name(&row[5])),
            t if t.starts_with("ball_") => format!("{};{}", name(&row[4]), row[5]),
            _ => name(&row[4]),
        };
        let t: f64 = row[2].parse().unwrap();
        ours.push((shot, row[1].clone(), t.to_bits(), row[3].clone(), agents));
    }
    // the replay's
    let (mut events, mut fin) = (Vec::new(), Vec::new());
    let mut out = ReplayOut {
        events: &mut events,
        final_balls: &mut fin,
        event_balls: None,
    };
    let stats = replay(&shots, &table, params, Limits::default(), &mut out).unwrap();
    let mut theirs = Vec::new();
    for row in csv_rows(&String::from_utf8(events).unwrap()) {
        let shot: usize = row[0].parse().unwrap();
        let t: f64 = row[2].parse().unwrap();
        theirs.push((
            shot,
            row[1].clone(),
            t.to_bits(),
            row[3].clone(),
            row[4].clone(),
        ));
    }
    theirs.sort_by_key(|r| (r.0, r.1.parse::<usize>().unwrap()));
    assert_eq!(theirs.len(), stats.events);
    assert_eq!(ours.len(), theirs.len());
    for (a, b) in ours.iter().zip(&theirs) {
        assert_eq!(a, b);
    }
}

#[test]
fn plot_draws_one_table_and_its_path_is_checked_first() {
    let dir = tempfile::tempdir().unwrap();
    let balls = write(dir.path(), "balls.csv", BALLS);
    let strikes = write(dir.path(), "strikes.csv", STRIKES);
    let png = dir.path().join("shot.png");
    let run = kisstime(&[
        "simulate",
        s(&balls),
        "--strikes",
        s(&strikes),
        "--plot",
        s(&png),
        "--table-id",
        "2",
    ]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    assert!(
        bytes.len() > 10_000,
        "a real picture: {} bytes",
        bytes.len()
    );
    // refused before anything is computed or written
    // (a missing folder cannot be written: exit 1; the others are bad usage: exit 2)
    for (args, code, expect) in [
        (
            vec!["--plot", "shot.jpg", "--table-id", "2"],
            2,
            "written as .png",
        ),
        (
            vec!["--plot", "missing/shot.png", "--table-id", "2"],
            1,
            "does not exist",
        ),
        (vec!["--plot", "shot.png"], 2, "--table-id"),
        (
            vec!["--plot", "shot.png", "--table-id", "9"],
            2,
            "no such table",
        ),
    ] {
        let out = dir.path().join("final.csv");
        let mut all = vec!["simulate", s(&balls), "--final", s(&out)];
        all.extend(args.iter().copied());
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_kisstime"))
            .args(&all)
            .current_dir(dir.path())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(code), "{args:?}: {err}");
        assert!(err.contains(expect), "{args:?}: {err}");
        assert!(!out.exists(), "{args:?}: nothing is written");
    }
}

#[test]
fn a_bad_ball_in_npy_input_is_named_by_its_row() {
    use kisstime::{Ball, Batch};
    let dir = tempfile::tempdir().unwrap();
    let mut batch = Batch::new();
    batch
        .push_table(
            4,
            [
                (0, Ball::at_rest(0.635, 0.6)),
                (1, Ball::at_rest(0.635, 1.9)),
            ],
        )
        .unwrap();
    // ball 3 of table 7 lies off the table: row 3 of the file (0-based)
    batch
        .push_table(
            7,
            [(2, Ball::at_rest(0.635, 0.6)), (3, Ball::at_rest(3.0, 1.9))],
        )
        .unwrap();
    let path = dir.path().join("balls.npy");
    let mut bytes = Vec::new();
    kisstime::io::npy::write_batch_npy(&mut bytes, &batch).unwrap();
    std::fs::write(&path, bytes).unwrap();
    let run = kisstime(&["simulate", s(&path)]);
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    for part in ["balls.npy", "row 3", "table 7", "ball 3"] {
        assert!(run.stderr.contains(part), "{part}: {}", run.stderr);
    }
}

#[test]
fn the_readme_break_example_runs() {
    let dir = tempfile::tempdir().unwrap();
    let root = env!("CARGO_MANIFEST_DIR");
    let (events, fin, png) = (
        dir.path().join("events.csv"),
        dir.path().join("final.csv"),
        dir.path().join("break.png"),
    );
    let run = kisstime(&[
        "simulate",
        &format!("{root}/examples/break.csv"),
        "--strikes",
        &format!("{root}/examples/break_strike.csv"),
        "-o",
        s(&events),
        "--final",
        s(&fin),
        "--plot",
        s(&png),
    ]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    let ev = csv_rows(&std::fs::read_to_string(&events).unwrap());
    assert_eq!(ev[0][3], "stick_ball");
    assert!(ev.iter().any(|r| r[3] == "ball_ball"));
    let fin = csv_rows(&std::fs::read_to_string(&fin).unwrap());
    assert_eq!(fin.len(), 16, "every ball of the rack and the cue ball");
    assert!(
        fin.iter()
            .all(|r| r[2] == "stationary" || r[2] == "pocketed")
    );
    assert_eq!(&std::fs::read(&png).unwrap()[1..4], b"PNG");
}

#[test]
fn physics_changes_the_result_and_defaults_written_out_do_not() {
    let dir = tempfile::tempdir().unwrap();
    let balls = write(dir.path(), "balls.csv", BALLS);
    let strikes = write(dir.path(), "strikes.csv", STRIKES);
    let final_with = |physics: Option<&Path>, name: &str| {
        let out = dir.path().join(name);
        let mut args = vec![
            "simulate",
            s(&balls),
            "--strikes",
            s(&strikes),
            "--final",
            s(&out),
        ];
        if let Some(p) = physics {
            args.extend(["--physics", s(p)]);
        }
        let r = kisstime(&args);
        assert_eq!(r.code, Some(0), "{}", r.stderr);
        std::fs::read_to_string(out).unwrap()
    };
    let plain = final_with(None, "plain.csv");
    // pooltool's defaults spelled out (and an empty file) change nothing, bit for bit
    let defaults = write(
        dir.path(),
        "defaults.toml",
        &kisstime::io::physics::physics_toml(&SimParams::default()),
    );
    assert!(defaults.exists());
    assert_eq!(final_with(Some(&defaults), "defaults.csv"), plain);
    let empty = write(dir.path(), "empty.toml", "# nothing\n");
    assert_eq!(final_with(Some(&empty), "empty.csv"), plain);
    // the reference set's parameters move every struck ball's final position
    let set = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/physics/physics.toml"
    ));
    let changed = final_with(Some(set), "changed.csv");
    let rows = |t: &str| csv_rows(t);
    let (a, b) = (rows(&plain), rows(&changed));
    assert_eq!(a.len(), b.len());
    let moved = a.iter().zip(&b).filter(|(x, y)| x != y).count();
    assert!(moved >= 3, "{moved} balls moved:\n{plain}\n{changed}");
    // R is the balls' radius everywhere: with R = 0.4 m the balls at x = 0.3 are in the
    // cushions, refused by the layout check
    let big = write(dir.path(), "big.toml", "R = 0.4\n");
    let r = kisstime(&[
        "simulate",
        s(&balls),
        "--strikes",
        s(&strikes),
        "--physics",
        s(&big),
    ]);
    assert_eq!(r.code, Some(2), "{}", r.stderr);
    assert!(r.stderr.contains("R = 0.4"), "{}", r.stderr);
}

#[test]
fn bad_physics_files_exit_2_naming_the_file_and_key() {
    let dir = tempfile::tempdir().unwrap();
    let balls = write(dir.path(), "balls.csv", BALLS);
    let out = dir.path().join("final.csv");
    for (text, needles) in [
        (
            "u_s = 0.2\nfoo = 1\n",
            &["line 2", "unknown key `foo`", "u_sp_proportionality"][..],
        ),
        (
            "R = -0.03\n",
            &["line 1", "key `R` is -0.03", "greater than 0"][..],
        ),
        ("e_c = 1.5\n", &["key `e_c` is 1.5", "(0, 1]"][..]),
        (
            "u_sp_proportionality = 0\n",
            &["key `u_sp_proportionality` is 0"][..],
        ),
        ("radius = 0.03\n", &["unknown key `radius`", "`R`"][..]),
        (
            "mu_sp = 0.0127\n",
            &["unknown key `mu_sp`", "`u_sp_proportionality`"][..],
        ),
        ("[cue]\nM = 0\n", &["line 2", "key `cue.M` is 0"][..]),
        ("g = \"earth\"\n", &["key `g` is a string"][..]),
        ("R = = 1\n", &["line 1"][..]),
    ] {
        let physics = write(dir.path(), "physics.toml", text);
        let r = kisstime(&[
            "simulate",
            s(&balls),
            "--physics",
            s(&physics),
            "--final",
            s(&out),
        ]);
        assert_eq!(r.code, Some(2), "{text}: {}", r.stderr);
        let first = r
            .stderr
            .lines()
            .find(|l| l.contains("physics.toml"))
            .unwrap_or("");
        for n in needles {
            assert!(first.contains(n), "{text}: {n:?} missing in {}", r.stderr);
        }
        assert!(!out.exists(), "{text}: an output was left");
    }
    let missing = dir.path().join("no_such.toml");
    let r = kisstime(&["simulate", s(&balls), "--physics", s(&missing)]);
    assert_eq!(r.code, Some(1), "{}", r.stderr);
    assert!(r.stderr.contains("no_such.toml"), "{}", r.stderr);
}

/// `--physics FILE.csv`: one parameter set per table (pooltool's names, the cue's as
/// `cue.M`); each table's final states are those of the table simulated alone with a TOML
/// file of its row's values; a table without a row, a row for no table, an unknown column
/// or a bad number exits 2 naming the file, the line and the table.
#[test]
fn per_table_physics_from_a_csv_is_each_table_alone() {
    let dir = tempfile::tempdir().unwrap();
    let (balls, strikes) = rack_batch(dir.path(), 4);
    let rows = [
        (0, 0.008, 0.8, 0.6),
        (1, 0.010, 0.85, 0.567),
        (2, 0.012, 0.9, 0.5),
        (3, 0.011, 0.95, 0.7),
    ];
    let mut csv = String::from("table,u_r,e_c,cue.M\n");
    for (t, u_r, e_c, m) in rows {
        csv.push_str(&format!("{t},{u_r},{e_c},{m}\n"));
    }
    let per_table = write(dir.path(), "physics.csv", &csv);
    // `kisstime simulate BALLS --strikes STRIKES --physics FILE [--final OUT]`
    let with_physics = |physics: &Path, out: Option<&Path>| {
        let mut args = vec!["simulate", s(&balls), "--strikes", s(&strikes)];
        args.extend(["--physics", s(physics)]);
        if let Some(out) = out {
            args.extend(["--final", s(out)]);
        }
        kisstime(&args)
    };
    let fin = dir.path().join("final.csv");
    let r = with_physics(&per_table, Some(&fin));
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let all = csv_rows(&std::fs::read_to_string(&fin).unwrap());
    let mut differ = 0;
    for (t, u_r, e_c, m) in rows {
        let toml = write(
            dir.path(),
            &format!("t{t}.toml"),
            &format!("u_r = {u_r}\ne_c = {e_c}\n[cue]\nM = {m}\n"),
        );
        let one_fin = dir.path().join(format!("f{t}.csv"));
        let r = with_physics(&toml, Some(&one_fin));
        assert_eq!(r.code, Some(0), "{}", r.stderr);
        let alone = csv_rows(&std::fs::read_to_string(&one_fin).unwrap());
        let mine = |rows: &[Vec<String>]| {
            rows.iter()
                .filter(|row| row[0] == t.to_string())
                .cloned()
                .collect::<Vec<_>>()
        };
        assert!(!mine(&all).is_empty());
        assert_eq!(mine(&all), mine(&alone), "table {t}");
        // and the others' rows under this table's physics are not theirs
        if all != alone {
            differ += 1;
        }
    }
    assert_eq!(differ, 4, "each table's physics matters");
    // bad files
    let bad = |name: &str, text: &str, words: &[&str]| {
        let f = write(dir.path(), name, text);
        let r = with_physics(&f, None);
        assert_eq!(r.code, Some(2), "{name}: {}", r.stderr);
        for w in words {
            assert!(r.stderr.contains(w), "{name}: {w} not in {}", r.stderr);
        }
    };
    bad(
        "missing.csv",
        "table,u_r\n0,0.01\n1,0.01\n2,0.01\n",
        &["missing.csv", "table 3", "no row"],
    );
    bad(
        "extra.csv",
        "table,u_r\n0,0.01\n1,0.01\n2,0.01\n3,0.01\n9,0.01\n",
        &["line 6", "table 9", "not in the input"],
    );
    bad(
        "key.csv",
        "table,mu_r\n0,0.01\n1,0.01\n2,0.01\n3,0.01\n",
        &["key.csv", "mu_r", "u_r"],
    );
    bad(
        "range.csv",
        "table,e_c\n0,0.5\n1,1.5\n2,0.5\n3,0.5\n",
        &["range.csv", "line 3", "table 1", "e_c"],
    );
    bad(
        "number.csv",
        "table,u_r\n0,x\n",
        &["number.csv", "line 2", "u_r"],
    );
}

/// One frame everywhere: every `kisstime gen` scenario (written in pooltool's frame, x
/// across the table) is a valid `simulate` input on the default 9-ft table, and every table
/// runs to rest.
#[test]
fn every_gen_scenario_simulates() {
    let dir = tempfile::tempdir().unwrap();
    for scenario in ["rack", "midshot", "spread", "worst"] {
        let input = dir.path().join(format!("{scenario}.csv"));
        let made = kisstime(&[
            "gen",
            "--scenario",
            scenario,
            "--tables",
            "40",
            "-o",
            s(&input),
        ]);
        assert_eq!(made.code, Some(0), "gen {scenario}: {}", made.stderr);
        let out = dir.path().join(format!("{scenario}_outcomes.csv"));
        let run = kisstime(&["simulate", s(&input), "--outcomes", s(&out), "--final", "-"]);
        assert_eq!(run.code, Some(0), "simulate {scenario}: {}", run.stderr);
        let rows = csv_rows(&std::fs::read_to_string(&out).unwrap());
        assert_eq!(rows.len(), 40, "{scenario}: one outcome a table");
        assert!(
            rows.iter().all(|r| r[3] == "none"),
            "{scenario}: a table was cut"
        );
    }
    // the hand-made example of `pairs` is in the same frame
    let example = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/tables.csv");
    let run = kisstime(&["simulate", example, "--final", "-"]);
    assert_eq!(
        run.code,
        Some(0),
        "simulate examples/tables.csv: {}",
        run.stderr
    );
}

/// A run refused on its first table prints nothing on standard output, not even a header.
#[test]
fn a_refused_run_prints_nothing_on_stdout() {
    let dir = tempfile::tempdir().unwrap();
    let bad = write(
        dir.path(),
        "bad.csv",
        "table,ball,state,x,y,vx,vy,wx,wy,wz\n0,0,stationary,5,5,0,0,0,0,0\n\
         0,1,stationary,0.5,0.5,0,0,0,0,0\n",
    );
    let run = kisstime(&["simulate", s(&bad)]);
    assert_eq!(run.code, Some(2));
    assert!(run.stderr.contains("off the table"), "{}", run.stderr);
    assert_eq!(run.stdout, "", "nothing on stdout");
}
