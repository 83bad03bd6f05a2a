//! The full-shot reference set (`data/fullshots`, 300 pooltool 0.6.0 shots from the
//! strike to rest): every shot is replayed through `kisstime::simulate`, the checker's
//! `events.csv` and `final.csv` are written to a temporary folder, and the set's own
//! judge, `check_fullshots.py`, must report every shot passed.

mod common;

use kisstime::io::shot_set::read_table;
use kisstime::simulate::{SimParams, Table};

#[test]
fn the_set_uses_the_built_in_nine_foot_table() {
    assert_eq!(
        read_table(&common::fullshots_dir()).unwrap(),
        Table::nine_foot()
    );
}

#[test]
fn every_reference_shot_passes_the_checker() {
    let (shots, events, verdict) =
        common::replay_and_judge(&common::fullshots_dir(), SimParams::default());
    assert_eq!(shots, 300);
    println!("{shots} shots, {events} events (the reference has 26,936)");
    let Some((passed, failed, text)) = verdict else {
        return;
    };
    println!("{text}");
    assert_eq!((passed, failed), (300, 0), "check_fullshots.py:\n{text}");
}
