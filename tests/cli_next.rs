//! `kisstime next` and `kisstime gen`: the next collision agrees with the minimum of the
//! per-pair output (same tie rule), and generated files read back as the generated batch.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

use kisstime::Params;
use kisstime::workload::{Workload, generate};

fn kisstime(args: &[&str]) -> std::process::Output {
    let out = Command::new(env!("CARGO_BIN_EXE_kisstime"))
        .args(args)
        .output()
        .expect("the binary runs");
    assert!(
        out.status.success(),
        "kisstime {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A table's next collision as read from output: time, pair, status.
type Next = (f64, Option<(i64, i64)>, String);

/// Each table's minimum over `pairs` output: earliest hit or overlap, ties to the first
/// row (rows come in pair order).
fn min_of_pairs(csv: &str) -> BTreeMap<i64, Next> {
    let mut best: BTreeMap<i64, Next> = BTreeMap::new();
    for line in csv.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let table: i64 = f[0].parse().unwrap();
        let entry = best
            .entry(table)
            .or_insert((f64::INFINITY, None, "none".into()));
        if f[4] == "none" {
            continue;
        }
        let t: f64 = f[3].parse().unwrap();
        if entry.1.is_none() || t < entry.0 {
            *entry = (
                t,
                Some((f[1].parse().unwrap(), f[2].parse().unwrap())),
                f[4].into(),
            );
        }
    }
    best
}

fn check_next_against_pairs(input: &Path) -> usize {
    let pairs = String::from_utf8(kisstime(&["pairs", s(input)]).stdout).unwrap();
    let next = String::from_utf8(kisstime(&["next", s(input)]).stdout).unwrap();
    let want = min_of_pairs(&pairs);
    let mut lines = next.lines();
    assert_eq!(lines.next(), Some("table,t,i,j,status"));
    let mut n = 0;
    for (line, (table, (t, pair, status))) in lines.zip(&want) {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f[0].parse::<i64>().unwrap(), *table);
        assert_eq!(f[4], status, "{line}");
        match pair {
            Some((i, j)) => {
                assert_eq!(f[1].parse::<f64>().unwrap(), *t, "{line}");
                assert_eq!(
                    (f[2].parse::<i64>().unwrap(), f[3].parse::<i64>().unwrap()),
                    (*i, *j)
                );
            }
            None => assert_eq!((f[1], f[2], f[3]), ("inf", "", ""), "{line}"),
        }
        n += 1;
    }
    assert_eq!(n, want.len());
    n
}

#[test]
fn next_is_the_minimum_of_the_pairs_on_random_batches() {
    let dir = tempfile::tempdir().unwrap();
    for (scenario, tables) in [
        ("midshot", "400"),
        ("worst", "150"),
        ("rack", "100"),
        ("spread", "300"),
    ] {
        let file = dir.path().join(format!("{scenario}.csv"));
        kisstime(&[
            "gen",
            "--scenario",
            scenario,
            "--tables",
            tables,
            "--seed",
            "3",
            "-o",
            s(&file),
        ]);
        assert_eq!(check_next_against_pairs(&file).to_string(), tables);
    }
}

#[test]
fn next_is_the_minimum_of_the_pairs_on_the_example_and_the_corpus() {
    let example = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/tables.csv"));
    check_next_against_pairs(example);
    // the corpus as one 2-ball table per case
    let corpus =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/dev.csv"))
            .unwrap();
    let mut csv = String::from("table,ball,state,x,y,vx,vy,wx,wy,wz\n");
    for (k, line) in corpus.lines().skip(1).enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        csv += &format!(
            "{k},1,{}\n{k},2,{}\n",
            f[6..14].join(","),
            f[14..22].join(",")
        );
    }
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("corpus.csv");
    std::fs::write(&file, csv).unwrap();
    assert_eq!(check_next_against_pairs(&file), 1600);
}

#[test]
fn generated_files_read_back_as_the_generated_batch() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("g.csv");
    kisstime(&[
        "gen",
        "--scenario",
        "spread",
        "--tables",
        "50",
        "--balls",
        "7",
        "--seed",
        "9",
        "-o",
        s(&file),
    ]);
    let read = kisstime::io::read_batch_csv_path(&file).unwrap();
    let made = generate(Workload::Spread, 50, 7, 9, &Params::default());
    assert_eq!(read.num_tables(), made.num_tables());
    for k in 0..made.num_tables() {
        assert_eq!(read.table_id(k), made.table_id(k));
        assert_eq!(read.ball_ids(k), made.ball_ids(k));
        assert_eq!(read.balls(k), made.balls(k), "bit-identical numbers");
    }
}
