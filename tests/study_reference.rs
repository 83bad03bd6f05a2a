//! The shot-study reference (`data/studies`: one scenario, 2,000 noisy strikes and
//! pooltool 0.6.0's full outcome for each): every strike is replayed through the same
//! code as `kisstime shots --strikes` and compared with pooltool's row, sample by sample.
//! pooltool's own sensitivity file flags no sample, so the target is every sample: the
//! same first contact, the same potted set, the cue ball's final position within 1 mm.
//! The documented example `replay_study` must write the same rows.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use kisstime::io::strikes::read_sample_strikes;
use kisstime::study::{
    REFERENCE_COLUMNS, RunOptions, StudyConfig, run_strikes, write_reference_csv,
};

fn dir() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/studies")).to_path_buf()
}

/// A CSV file's rows as maps from column to text.
fn rows(text: &str) -> Vec<std::collections::HashMap<String, String>> {
    let mut rd = csv::Reader::from_reader(text.as_bytes());
    let header: Vec<String> = rd.headers().unwrap().iter().map(str::to_owned).collect();
    rd.records()
        .map(|r| {
            let r = r.unwrap();
            header
                .iter()
                .cloned()
                .zip(r.iter().map(str::to_owned))
                .collect()
        })
        .collect()
}

/// Our rows for the reference's strikes, as `replay_study` writes them.
fn replay() -> String {
    let config = StudyConfig::read_reference(&dir().join("dev_scenario.json")).unwrap();
    let strikes = read_sample_strikes(&dir().join("dev_strikes.csv")).unwrap();
    let ids: Vec<i64> = strikes.iter().map(|s| s.sample).collect();
    let k: Vec<_> = strikes.iter().map(|s| s.strike).collect();
    let samples = run_strikes(&config, &k, &RunOptions::default(), &mut |_, _| {}).unwrap();
    let mut out = Vec::new();
    write_reference_csv(&mut out, &config, &ids, &samples).unwrap();
    String::from_utf8(out).unwrap()
}

#[test]
fn every_sample_matches_pooltool() {
    let ours = replay();
    assert_eq!(ours.lines().next(), Some(REFERENCE_COLUMNS));
    let reference = std::fs::read_to_string(dir().join("dev_full.csv")).unwrap();
    let (ours, theirs) = (rows(&ours), rows(&reference));
    assert_eq!(ours.len(), 2000);
    assert_eq!(ours.len(), theirs.len());
    let potted_set = |s: &str| -> BTreeSet<String> {
        s.split(';')
            .filter(|p| !p.is_empty())
            .map(str::to_owned)
            .collect()
    };
    let num = |s: &str| -> f64 { s.parse().unwrap() };
    let (mut bad, mut worst, mut same_events, mut same_order) = (Vec::new(), 0.0f64, 0, 0);
    let mut worst_t = 0.0f64;
    for (a, b) in ours.iter().zip(&theirs) {
        assert_eq!(a["sample"], b["sample"]);
        let d = (num(&a["cue_x"]) - num(&b["cue_x"])).hypot(num(&a["cue_y"]) - num(&b["cue_y"]));
        worst = worst.max(d);
        let first_same = a["first_contact"] == b["first_contact"];
        let potted_same = potted_set(&a["potted"]) == potted_set(&b["potted"]);
        if !(first_same && potted_same && d <= 1e-3) {
            bad.push(format!(
                "sample {}: first {} vs {}, potted {:?} vs {:?}, cue moved {d:.2e} m",
                a["sample"], a["first_contact"], b["first_contact"], a["potted"], b["potted"]
            ));
        }
        same_events += usize::from(a["n_events"] == b["n_events"]);
        same_order += usize::from(a["potted"] == b["potted"]);
        for col in ["intended_potted", "intended_pocket", "cue_potted"] {
            assert_eq!(a[col], b[col], "sample {}: {col}", a["sample"]);
        }
        worst_t = worst_t.max((num(&a["first_t"]) - num(&b["first_t"])).abs());
    }
    println!(
        "{} of 2000 samples differ; largest cue-ball distance {worst:.2e} m; n_events equal on \
         {same_events}, potted order on {same_order}; first_t within {worst_t:.1e} s",
        bad.len()
    );
    assert!(
        bad.is_empty(),
        "{} samples differ:\n{}",
        bad.len(),
        bad.join("\n")
    );
}

#[test]
fn the_example_writes_the_same_rows() {
    // cargo builds the examples for `cargo test`, next to the test binaries' folder
    let exe = std::env::current_exe().unwrap();
    let examples = exe.parent().unwrap().parent().unwrap().join("examples");
    let example = examples.join(format!("replay_study{}", std::env::consts::EXE_SUFFIX));
    if !example.exists() {
        // `cargo test` builds it; `cargo test --test study_reference` alone does not
        assert!(
            std::env::var_os("CI").is_none(),
            "{} is built by cargo test",
            example.display()
        );
        eprintln!(
            "{} is not built (run the whole `cargo test`): the example was not checked",
            example.display()
        );
        return;
    }
    let out = tempfile::tempdir().unwrap();
    let csv = out.path().join("out.csv");
    let run = std::process::Command::new(&example)
        .arg(dir().join("dev_scenario.json"))
        .arg(dir().join("dev_strikes.csv"))
        .arg(&csv)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let last = stdout.lines().last().unwrap_or("");
    assert!(
        last.starts_with("2000 samples in ") && last.ends_with(" samples/s"),
        "{last}"
    );
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), replay());
    // bad input: exit 2, a message naming the file, nothing written
    let bad = out.path().join("bad.csv");
    std::fs::write(&bad, "sample,V0,phi,theta,a,b\n0,1.5,90,5,0.9,0.9\n").unwrap();
    let none = out.path().join("none.csv");
    let run = std::process::Command::new(&example)
        .arg(dir().join("dev_scenario.json"))
        .arg(&bad)
        .arg(&none)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("bad.csv, line 2: sample 0: strike: a² + b² > 1"),
        "{stderr}"
    );
    assert!(!none.exists());
}

#[test]
fn the_reference_scenario_reads_as_pooltools_table_and_balls() {
    let config = StudyConfig::read_reference(&dir().join("dev_scenario.json")).unwrap();
    assert_eq!(config.table, kisstime::simulate::Table::nine_foot());
    assert_eq!(config.cue_id(), "cue");
    assert_eq!(config.intended_id(), "7");
    assert_eq!(config.pocket_id(), Some("lb"));
    assert_eq!(config.balls.len(), 8);
    // and the built-in study is the same layout and shot, in the simulator's frame
    let builtin = StudyConfig::builtin();
    assert_eq!(builtin.balls, config.balls);
    assert_eq!(builtin.shot, config.shot);
    assert_eq!(builtin.params, config.params);
    for (text, want) in [
        ("{", "line"),
        (
            r#"{"table": {"type": "round"}, "balls": [], "intended": "7", "nominal_shot": {"V0": 1, "phi": 0, "theta": 0, "a": 0, "b": 0}}"#,
            "table.type",
        ),
        (
            r#"{"table": {"type": "pocket"}, "balls": [{"id": "cue", "x": 0.5, "y": 0.5}, {"id": "7", "x": 0.5, "y": 0.51}], "intended": "7", "nominal_shot": {"V0": 1, "phi": 0, "theta": 0, "a": 0, "b": 0}}"#,
            "overlaps",
        ),
        (
            r#"{"table": {"type": "pocket"}, "balls": [{"id": "cue", "x": 0.5, "y": 0.5}, {"id": "7", "x": 0.5, "y": 1.5}], "intended": "9", "nominal_shot": {"V0": 1, "phi": 0, "theta": 0, "a": 0, "b": 0}}"#,
            "key `intended`",
        ),
        (
            r#"{"table": {"type": "pocket"}, "balls": [{"id": "cue", "x": 0.5, "y": 0.5}, {"id": "7", "x": 0.5, "y": 1.5}], "intended": "7", "target_pocket": "xx", "nominal_shot": {"V0": 1, "phi": 0, "theta": 0, "a": 0, "b": 0}}"#,
            "not a pocket",
        ),
    ] {
        let err = StudyConfig::parse_reference(text, "s.json").unwrap_err();
        assert!(err.is_bad_input());
        let msg = err.to_string();
        assert!(msg.starts_with("s.json") && msg.contains(want), "{msg}");
    }
}
