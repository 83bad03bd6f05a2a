//! The `kisstime` binary end to end: `kisstime pairs FILE [-o OUT]` output against the
//! library, bad input and bad parameters (exit code 2, the message names the file, line,
//! table and ball, no output file left behind), unreadable input (exit code 1), atomic
//! `-o`, and thread-count independence of the output bytes.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use kisstime::{Params, Status};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;

const HEADER_IN: &str = "table,ball,state,x,y,vx,vy,wx,wy,wz";
const HEADER_OUT: &str = "table,i,j,t,status,horizon";

struct Run {
    code: Option<i32>,
    stdout: Vec<u8>,
    stderr: String,
}

impl Run {
    fn stdout_text(&self) -> String {
        String::from_utf8(self.stdout.clone()).expect("stdout is UTF-8")
    }
}

fn kisstime(args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_kisstime"))
        .args(args)
        .output()
        .expect("the kisstime binary runs");
    Run {
        code: out.status.code(),
        stdout: out.stdout,
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

fn s(p: &Path) -> &str {
    p.to_str().expect("temporary paths are UTF-8")
}

fn write(dir: &Path, name: &str, content: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, content).unwrap();
    path
}

/// Two tables (ids 7 and −2), their rows interleaved, ball ids not sorted, with hits,
/// misses, a touching pair, a pocketed ball and padded fields.
fn small_csv() -> String {
    let r = kisstime::model::DEFAULT_RADIUS;
    let rows = [
        // table 7: a rolling cue ball at a still ball, a sliding ball, a pocketed ball
        "7,5,rolling,0.3,0.5,2.0,0.0,0.0,69.99125109361329,0.0".to_owned(),
        "-2,9,stationary,1.0,0.6,0,0,0,0,0".to_owned(),
        "7,1,stationary,1.4,0.52,0,0,0,0,0".to_owned(),
        " -2 , 0 , rolling , 0.4 , 0.6 , 1.5 , 0.0 , 0.0 , 52.493438320209975 , 0.0 ".to_owned(),
        "7,10,pocketed,0,0,0,0,0,0,0".to_owned(),
        "7,3,sliding,2.0,1.0,-1.5,-0.8,20.0,-35.0,4.0".to_owned(),
        // table −2: ball 2 touching ball 9 and moving away; ball 0 rolls at ball 9
        format!(
            "-2,2,rolling,{},0.6,0.5,0.0,0.0,17.497812554680664,0.0",
            1.0 + 2.0 * r
        ),
    ];
    let mut s = String::from(HEADER_IN);
    s.push('\n');
    for row in rows {
        s.push_str(&row);
        s.push('\n');
    }
    s
}

/// One output row.
#[derive(Debug)]
struct OutRow {
    table: i64,
    i: i64,
    j: i64,
    t: f64,
    status: String,
    horizon: f64,
}

fn parse_time(text: &str) -> f64 {
    if text == "inf" {
        f64::INFINITY
    } else {
        text.parse().unwrap_or_else(|_| panic!("bad time {text:?}"))
    }
}

fn parse_output(text: &str) -> Vec<OutRow> {
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(HEADER_OUT), "output header");
    lines
        .map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            assert_eq!(f.len(), 6, "output row {line:?}");
            OutRow {
                table: f[0].parse().unwrap(),
                i: f[1].parse().unwrap(),
                j: f[2].parse().unwrap(),
                t: parse_time(f[3]),
                status: f[4].to_owned(),
                horizon: parse_time(f[5]),
            }
        })
        .collect()
}

/// Checks the output of `input` against the library, bit for bit; returns the number of
/// hits.
fn check_against_library(input: &Path, stdout: &str) -> usize {
    let rows = parse_output(stdout);
    // the expected pairs from the input itself: ids per table, sorted
    let text = std::fs::read_to_string(input).unwrap();
    let mut ids: BTreeMap<i64, Vec<i64>> = BTreeMap::new();
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        ids.entry(f[0].parse().unwrap())
            .or_default()
            .push(f[1].parse().unwrap());
    }
    let mut expected_keys = Vec::new();
    for (table, mut balls) in ids {
        balls.sort();
        for a in 0..balls.len() {
            for b in a + 1..balls.len() {
                expected_keys.push((table, balls[a], balls[b]));
            }
        }
    }
    let keys: Vec<(i64, i64, i64)> = rows.iter().map(|r| (r.table, r.i, r.j)).collect();
    assert_eq!(
        keys, expected_keys,
        "one row per pair, by table then i then j, i < j"
    );
    for r in &rows {
        assert!(r.i < r.j, "{r:?}");
    }

    // the library on the same file
    let batch = kisstime::io::read_batch_csv_path(input).unwrap();
    let contacts = kisstime::pair_times(&batch, &Params::default()).unwrap();
    assert_eq!(contacts.len(), rows.len());
    let mut at = 0;
    let mut hits = 0;
    for k in 0..batch.num_tables() {
        let bids = batch.ball_ids(k);
        for a in 0..bids.len() {
            for b in a + 1..bids.len() {
                let (row, c) = (&rows[at], &contacts[at]);
                assert_eq!(
                    (row.table, row.i, row.j),
                    (batch.table_id(k), bids[a], bids[b])
                );
                assert_eq!(
                    row.t.to_bits(),
                    c.t.to_bits(),
                    "t of {row:?} vs library {c:?}"
                );
                assert_eq!(
                    row.horizon.to_bits(),
                    c.horizon.to_bits(),
                    "horizon of {row:?} vs library {c:?}"
                );
                assert_eq!(row.status, c.status.name(), "{row:?} vs {c:?}");
                if c.status == Status::Hit {
                    hits += 1;
                }
                at += 1;
            }
        }
    }
    hits
}

#[test]
fn small_file_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "tables.csv", &small_csv());
    let run = kisstime(&["pairs", s(&input)]);
    assert_eq!(run.code, Some(0), "stderr: {}", run.stderr);
    let out = run.stdout_text();
    assert!(out.starts_with(&format!("{HEADER_OUT}\n")), "{out}");
    // 4 balls in table 7, 3 in table −2
    assert_eq!(out.lines().count(), 1 + 4 * 3 / 2 + 3 * 2 / 2, "{out}");
    let hits = check_against_library(&input, &out);
    assert!(hits >= 2, "the file has hits: {out}");
    // table −2 comes first (ascending ids), and its just-collided pair (2, 9) is no hit
    let rows = parse_output(&out);
    assert_eq!(rows[0].table, -2);
    let touching = rows
        .iter()
        .find(|r| (r.table, r.i, r.j) == (-2, 2, 9))
        .unwrap();
    assert_eq!(touching.status, "none", "{touching:?}");
    // the pocketed ball never collides
    for r in rows.iter().filter(|r| r.table == 7 && r.j == 10) {
        assert_eq!((r.status.as_str(), r.t), ("none", f64::INFINITY), "{r:?}");
    }

    // -o writes the same bytes, and nothing to stdout
    let out_path = dir.path().join("out.csv");
    let run_o = kisstime(&["pairs", s(&input), "-o", s(&out_path)]);
    assert_eq!(run_o.code, Some(0), "stderr: {}", run_o.stderr);
    assert!(run_o.stdout.is_empty());
    assert_eq!(std::fs::read(&out_path).unwrap(), run.stdout);
    // and over an existing file
    std::fs::write(&out_path, "old content\n").unwrap();
    let run_o = kisstime(&["pairs", s(&input), "--output", s(&out_path)]);
    assert_eq!(run_o.code, Some(0), "stderr: {}", run_o.stderr);
    assert_eq!(std::fs::read(&out_path).unwrap(), run.stdout);
}

/// A bad input: exit code 2, stderr names the file and each of `expect`, stdout is
/// empty, and with `-o` no output file is created.
fn assert_bad_input(name: &str, content: &str, expect: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), name, content);
    let out_path = dir.path().join("out.csv");
    let run = kisstime(&["pairs", s(&input), "-o", s(&out_path)]);
    assert_eq!(
        run.code,
        Some(2),
        "{name}: exit code; stderr: {}",
        run.stderr
    );
    assert!(
        run.stderr.contains(s(&input)),
        "{name}: stderr must name the file {}: {}",
        input.display(),
        run.stderr
    );
    for e in expect {
        assert!(
            run.stderr.contains(e),
            "{name}: stderr must mention {e:?}: {}",
            run.stderr
        );
    }
    assert!(
        run.stdout.is_empty(),
        "{name}: stdout {:?}",
        run.stdout_text()
    );
    assert!(!out_path.exists(), "{name}: an output file was left behind");
    // no temporary files left behind in the output folder either
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .filter(|n| n.to_str() != Some(name))
        .collect();
    assert!(left.is_empty(), "{name}: files left behind: {left:?}");
    // without -o: the same exit code, nothing on stdout
    let run = kisstime(&["pairs", s(&input)]);
    assert_eq!(run.code, Some(2), "{name} (stdout): {}", run.stderr);
    assert!(
        run.stdout.is_empty(),
        "{name}: stdout {:?}",
        run.stdout_text()
    );
}

const GOOD_ROW_1: &str = "1,1,rolling,0.5,0.5,1,0,0,35,0";
const GOOD_ROW_2: &str = "1,2,stationary,1.5,0.5,0,0,0,0,0";

#[test]
fn missing_column() {
    assert_bad_input(
        "missing.csv",
        "table,ball,state,x,y,vx,vy,wx,wy\n1,1,rolling,0.5,0.5,1,0,0,35\n",
        &["line 1", "wz"],
    );
}

#[test]
fn extra_column() {
    assert_bad_input(
        "extra.csv",
        &format!("{HEADER_IN},colour\n{GOOD_ROW_1},red\n{GOOD_ROW_2},white\n"),
        &["line 1", "colour"],
    );
}

#[test]
fn row_with_too_few_fields() {
    assert_bad_input(
        "short.csv",
        &format!("{HEADER_IN}\n{GOOD_ROW_1}\n1,2,stationary,1.5,0.5,0,0,0,0\n"),
        &["line 3"],
    );
}

#[test]
fn unknown_state() {
    assert_bad_input(
        "state.csv",
        &format!("{HEADER_IN}\n{GOOD_ROW_1}\n{GOOD_ROW_2}\n1,3,rollin,1.5,0.9,0,0,0,0,0\n"),
        &["line 4", "table 1", "ball 3", "rollin"],
    );
}

#[test]
fn nan_number() {
    assert_bad_input(
        "nan.csv",
        &format!("{HEADER_IN}\n{GOOD_ROW_1}\n1,2,rolling,1.5,0.5,NaN,0,0,0,0\n"),
        &["line 3", "table 1", "ball 2", "vx"],
    );
}

#[test]
fn inf_number() {
    assert_bad_input(
        "inf.csv",
        &format!("{HEADER_IN}\n1,1,rolling,0.5,inf,1,0,0,35,0\n{GOOD_ROW_2}\n"),
        &["line 2", "table 1", "ball 1", "y"],
    );
}

#[test]
fn non_integer_table_id() {
    assert_bad_input(
        "table_id.csv",
        &format!("{HEADER_IN}\n{GOOD_ROW_1}\n{GOOD_ROW_2}\n1.5,3,stationary,2,1,0,0,0,0,0\n"),
        &["line 4", "1.5"],
    );
}

#[test]
fn table_with_one_ball() {
    assert_bad_input(
        "lonely.csv",
        &format!("{HEADER_IN}\n{GOOD_ROW_1}\n{GOOD_ROW_2}\n4,8,stationary,2,1,0,0,0,0,0\n"),
        &["line 4", "table 4", "ball 8"],
    );
}

#[test]
fn duplicate_ball_id() {
    assert_bad_input(
        "duplicate.csv",
        &format!(
            "{HEADER_IN}\n{GOOD_ROW_1}\n{GOOD_ROW_2}\n2,1,stationary,2,1,0,0,0,0,0\n\
             1,1,stationary,2,1,0,0,0,0,0\n2,2,stationary,1,1,0,0,0,0,0\n"
        ),
        &["line 5", "table 1", "ball 1", "duplicate"],
    );
}

#[test]
fn empty_file() {
    assert_bad_input("empty.csv", "", &["line 1", "empty"]);
}

/// A bad parameter: exit code 2, the parameter named on stderr, no output file.
fn assert_bad_param(args: &[&str], names: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "ok.csv", &small_csv());
    let out_path = dir.path().join("out.csv");
    let mut all = vec!["pairs", s(&input), "-o", s(&out_path)];
    all.extend_from_slice(args);
    let run = kisstime(&all);
    assert_eq!(run.code, Some(2), "{args:?}: stderr: {}", run.stderr);
    assert!(
        names.iter().any(|n| run.stderr.contains(n)),
        "{args:?}: stderr must name the parameter (one of {names:?}): {}",
        run.stderr
    );
    assert!(
        !out_path.exists(),
        "{args:?}: an output file was left behind"
    );
}

#[test]
fn bad_parameters_exit_2_and_name_the_parameter() {
    assert_bad_param(&["--radius", "0"], &["radius"]);
    assert_bad_param(&["--radius=-0.01"], &["radius"]);
    assert_bad_param(&["--mu-r=-1"], &["mu_r", "mu-r"]);
    assert_bad_param(&["--mu-s", "0"], &["mu_s", "mu-s"]);
    assert_bad_param(&["--g", "nan"], &["parameter g", "--g"]);
    assert_bad_param(&["--g", "inf"], &["parameter g", "--g"]);
    assert_bad_param(&["--mu-sp", "0"], &["mu_sp", "mu-sp"]);
}

/// KNOWN BUG (reported, not fixed here): `--mu-r -1` (value after a space) is taken by
/// clap as an unknown flag `-1`; the exit code is 2 but the message ("unexpected argument
/// '-1' found") does not name the parameter. `--mu-r=-1` works. A fix would be
/// `allow_negative_numbers` (or `allow_hyphen_values`) on the numeric physics options.
#[test]
fn negative_parameter_after_a_space_names_the_parameter() {
    assert_bad_param(&["--mu-r", "-1"], &["mu_r", "mu-r"]);
    assert_bad_param(&["--radius", "-0.01"], &["radius"]);
}

#[test]
fn nonexistent_input_exits_1() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("no-such-file.csv");
    let out_path = dir.path().join("out.csv");
    let run = kisstime(&["pairs", s(&missing), "-o", s(&out_path)]);
    assert_eq!(run.code, Some(1), "stderr: {}", run.stderr);
    assert!(run.stderr.contains(s(&missing)), "{}", run.stderr);
    assert!(!out_path.exists());
    let run = kisstime(&["pairs", s(&missing)]);
    assert_eq!(run.code, Some(1), "stderr: {}", run.stderr);
    assert!(run.stdout.is_empty());
}

#[test]
fn failed_run_leaves_an_existing_output_file_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let out_path = write(dir.path(), "out.csv", "precious,data\n1,2\n");
    let bad = write(
        dir.path(),
        "bad.csv",
        &format!("{HEADER_IN}\n{GOOD_ROW_1}\n1,2,rolling,1.5,0.5,nan,0,0,0,0\n"),
    );
    let good = write(dir.path(), "good.csv", &small_csv());
    let missing = dir.path().join("missing.csv");
    for (what, args, code) in [
        ("bad input", vec!["pairs", s(&bad), "-o", s(&out_path)], 2),
        (
            "bad parameter",
            vec!["pairs", s(&good), "-o", s(&out_path), "--radius", "0"],
            2,
        ),
        (
            "missing input",
            vec!["pairs", s(&missing), "-o", s(&out_path)],
            1,
        ),
    ] {
        let run = kisstime(&args);
        assert_eq!(run.code, Some(code), "{what}: {}", run.stderr);
        assert_eq!(
            std::fs::read_to_string(&out_path).unwrap(),
            "precious,data\n1,2\n",
            "{what}: the existing output file was changed"
        );
    }
    // only the three files we wrote
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 3);
}

/// Many random tables (a fixed simple generator), some balls aimed at others.
fn big_csv() -> String {
    let mut rng = Pcg64Mcg::seed_from_u64(0x9e37_79b9_7f4a_7c15);
    let mut next = move || rng.random::<f64>();
    let r = kisstime::model::DEFAULT_RADIUS;
    let mut s = String::from(HEADER_IN);
    s.push('\n');
    for table in 0..400 {
        let n = 2 + (next() * 19.0) as usize;
        let mut pos: Vec<(f64, f64)> = Vec::new();
        for ball in 0..n {
            let (x, y) = (r + next() * (2.54 - 2.0 * r), r + next() * (1.27 - 2.0 * r));
            let speed = next() * 6.0;
            let mut dir = next() * std::f64::consts::TAU;
            if !pos.is_empty() && next() < 0.5 {
                let (tx, ty) = pos[(next() * pos.len() as f64) as usize];
                dir = (ty - y).atan2(tx - x);
            }
            let (vx, vy) = (speed * dir.cos(), speed * dir.sin());
            let k = next();
            let row = if k < 0.35 {
                format!("rolling,{x},{y},{vx},{vy},{},{},0", -vy / r, vx / r)
            } else if k < 0.7 {
                let w = |u: f64| (u - 0.5) * 400.0;
                format!(
                    "sliding,{x},{y},{vx},{vy},{},{},{}",
                    w(next()),
                    w(next()),
                    w(next())
                )
            } else if k < 0.85 {
                format!("stationary,{x},{y},0,0,0,0,0")
            } else if k < 0.97 {
                format!("spinning,{x},{y},0,0,0,0,{}", (next() - 0.5) * 100.0)
            } else {
                format!("pocketed,{x},{y},0,0,0,0,0")
            };
            // ids not in row order
            s.push_str(&format!(
                "{},{},{row}\n",
                1000 - table,
                (ball * 7 + 3) % 1000
            ));
            pos.push((x, y));
        }
    }
    s
}

#[test]
fn thread_count_does_not_change_the_output() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "big.csv", &big_csv());
    let default = kisstime(&["pairs", s(&input)]);
    assert_eq!(default.code, Some(0), "stderr: {}", default.stderr);
    let hits = check_against_library(&input, &default.stdout_text());
    assert!(hits > 100, "the big file has hits: {hits}");
    for threads in ["1", "2", "3"] {
        let run = kisstime(&["pairs", s(&input), "--threads", threads]);
        assert_eq!(run.code, Some(0), "--threads {threads}: {}", run.stderr);
        assert!(
            run.stdout == default.stdout,
            "--threads {threads} changes the output bytes"
        );
    }
}

#[test]
fn absurd_speeds_and_spins_are_refused_naming_the_ball() {
    // 1e160 m/s once answered `none` with an infinite horizon (its square overflows)
    for (vx, wz, what) in [
        ("1e160", "0", "vx is 1e160"),
        ("1e150", "0", "vx is 1e150"),
        ("2", "1e9", "wz is 1e9"),
    ] {
        let content = format!(
            "{HEADER_IN}\n0,0,stationary,1,0.5,0,0,0,0,0\n0,1,sliding,0.5,0.5,{vx},0,0,0,{wz}\n"
        );
        assert_bad_input(
            "absurd.csv",
            &content,
            &["table 0", "ball 1", what, "physical range"],
        );
    }
    // the largest accepted values still answer
    let dir = tempfile::tempdir().unwrap();
    let input = write(
        dir.path(),
        "fast.csv",
        &format!(
            "{HEADER_IN}\n0,0,stationary,1,0.5,0,0,0,0,0\n0,1,sliding,0.5,0.5,1000,0,0,0,1e5\n"
        ),
    );
    let run = kisstime(&["pairs", s(&input)]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    assert!(run.stdout_text().contains(",hit,"), "{}", run.stdout_text());
}
