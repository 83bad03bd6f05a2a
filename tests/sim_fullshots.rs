//! The full-shot reference set (`data/fullshots`, 300 pooltool 0.6.0 shots from the
//! strike to rest): every shot is replayed through `kisstime::simulate`, the checker's
//! `events.csv` and `final.csv` are written to a temporary folder, and the set's own
//! judge, `check_fullshots.py`, must report every shot passed.

mod common;

use kisstime::io::shot_set::{ReplayOut, read_shots, read_table, replay};
use kisstime::simulate::{Limits, SimParams, Table};
use std::io::{BufWriter, Write};

#[test]
fn the_set_uses_the_built_in_nine_foot_table() {
    assert_eq!(
        read_table(&common::fullshots_dir()).unwrap(),
        Table::nine_foot()
    );
}

#[test]
fn every_reference_shot_passes_the_checker() {
    let dir = common::fullshots_dir();
    let params = SimParams::default();
    let table = read_table(&dir).unwrap();
    let shots = read_shots(&dir, params.ball.r).unwrap();
    assert_eq!(shots.len(), 300);
    let out = tempfile::tempdir().unwrap();
    let (ev_path, fin_path) = (out.path().join("events.csv"), out.path().join("final.csv"));
    let mut events = BufWriter::new(std::fs::File::create(&ev_path).unwrap());
    let mut fin = BufWriter::new(std::fs::File::create(&fin_path).unwrap());
    let mut files = ReplayOut {
        events: &mut events,
        final_balls: &mut fin,
        event_balls: None,
    };
    let stats = replay(&shots, &table, params, Limits::default(), &mut files).unwrap();
    events.flush().unwrap();
    fin.flush().unwrap();
    assert_eq!(stats.cut, 0, "no shot may be cut by the default limits");
    println!(
        "{} shots, {} events (the reference has 26,936)",
        stats.shots, stats.events
    );
    let Some((passed, failed, text)) = common::check_fullshots(out.path()) else {
        return;
    };
    println!("{text}");
    assert_eq!((passed, failed), (300, 0), "check_fullshots.py:\n{text}");
}
