//! The physics set (`data/physics`, 120 pooltool 0.6.0 shots — 100 ordinary, 20 breaks —
//! simulated with every ball's `BallParams` changed as `data/physics/physics.toml` says):
//! every shot is replayed through `kisstime::simulate` with the parameters that the
//! library's one parser (`kisstime::io::physics`) reads from that file, and the set's
//! judge (`data/fullshots/check_fullshots.py --ref data/physics`) must pass all 120. Then
//! the same shots with pooltool's default physics: a clear majority must fail (the set's
//! README: 0 of 120 pass), which shows that the parameters reach the simulation.

mod common;

use kisstime::io::physics::{read_physics, read_table_ball_params};
use kisstime::io::shot_set::read_table;
use kisstime::simulate::{SimParams, Table};

/// Replays the set with `params` and runs the judge: `Some((passed, failed, output))`,
/// `None` where python3 is missing.
fn replay_and_judge(params: SimParams) -> Option<(usize, usize, String)> {
    let (shots, events, verdict) = common::replay_and_judge(&common::physics_dir(), params);
    assert_eq!(shots, 120);
    println!("{shots} shots, {events} events");
    verdict
}

/// The set's parameters, read from its `physics.toml` by the library's parser.
fn set_params() -> SimParams {
    read_physics(&common::physics_dir().join("physics.toml")).unwrap()
}

#[test]
fn the_set_uses_the_nine_foot_table_and_its_table_json_carries_the_same_ball_params() {
    let dir = common::physics_dir();
    assert_eq!(read_table(&dir).unwrap(), Table::nine_foot());
    let params = set_params();
    assert_ne!(params.ball, SimParams::default().ball);
    assert_eq!(
        read_table_ball_params(&dir.join("table.json")).unwrap(),
        Some(params.ball)
    );
}

#[test]
fn every_shot_passes_the_checker_with_the_sets_physics() {
    let Some((passed, failed, text)) = replay_and_judge(set_params()) else {
        return;
    };
    println!("{text}");
    assert_eq!((passed, failed), (120, 0), "check_fullshots.py:\n{text}");
}

#[test]
fn with_default_physics_most_shots_fail() {
    let Some((passed, failed, text)) = replay_and_judge(SimParams::default()) else {
        return;
    };
    println!("with pooltool's default physics: {passed} passed, {failed} failed");
    assert_eq!(passed + failed, 120, "check_fullshots.py:\n{text}");
    assert!(
        failed >= 100,
        "the parameters should matter: {passed} of 120 pass with the defaults\n{text}"
    );
}
