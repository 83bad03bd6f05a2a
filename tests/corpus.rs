//! The ground-truth corpus (`tests/data/dev.csv`, 50-digit reference times) through the
//! f64 CPU path: every case must pass the f64 tier of `tests/data/README.md`, on the table
//! and with the whole table moved ±1000 m from the origin.

mod common;

use common::{Case, Tier, corpus};
use kisstime::{Batch, pair_contact, pair_times};

fn run_case(case: &Case) -> kisstime::Contact {
    let p1 = kisstime::ball_path(&case.b1, &case.params);
    let p2 = kisstime::ball_path(&case.b2, &case.params);
    pair_contact(&p1, &p2, case.params.radius)
}

fn check_all(cases: &[Case], what: &str) {
    let mut failures = Vec::new();
    for case in cases {
        let got = run_case(case);
        if let Err(why) = case.check(got.t, got.status, Tier::F64) {
            failures.push(format!(
                "{} [{}, {}]: {why}",
                case.id, case.category, case.label
            ));
        }
    }
    println!(
        "corpus {what}: {} of {} cases pass the f64 tier",
        cases.len() - failures.len(),
        cases.len()
    );
    assert!(
        failures.is_empty(),
        "{} corpus failures ({what}):\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn corpus_passes_the_f64_tier() {
    let cases = corpus();
    assert_eq!(cases.len(), 1600, "the corpus has 1,600 cases");
    check_all(&cases, "on the table");
}

#[test]
fn corpus_passes_the_f64_tier_far_from_the_origin() {
    let cases = corpus();
    for (dx, dy) in [
        (1000.0, 1000.0),
        (-1000.0, 1000.0),
        (1000.0, -1000.0),
        (-1000.0, -1000.0),
    ] {
        let moved: Vec<Case> = cases.iter().map(|c| c.translated(dx, dy)).collect();
        check_all(&moved, &format!("moved by ({dx}, {dy}) m"));
    }
}

#[test]
fn corpus_horizons_match() {
    for case in corpus() {
        let got = run_case(&case).horizon;
        let want = case.horizon;
        assert!(
            got == want || (got - want).abs() <= 1e-12 * want.abs(),
            "{}: horizon {got} vs {want}",
            case.id
        );
    }
}

#[test]
fn corpus_through_the_batch_driver_gives_the_same_answers() {
    let cases = corpus();
    let params = cases[0].params;
    let mut batch = Batch::new();
    for (k, case) in cases.iter().enumerate() {
        assert_eq!(case.params, params, "one parameter set in the corpus");
        batch
            .push_table(k as i64, [(1, case.b1), (2, case.b2)])
            .unwrap();
    }
    let pairs = pair_times(&batch, &params).unwrap();
    for (case, got) in cases.iter().zip(&pairs) {
        assert_eq!(*got, run_case(case), "{}", case.id);
    }
}

#[test]
fn the_prune_never_discards_a_corpus_collision() {
    let mut pruned = 0;
    for case in corpus() {
        let p1 = kisstime::ball_path(&case.b1, &case.params);
        let p2 = kisstime::ball_path(&case.b2, &case.params);
        let h = kisstime::motion::pair_horizon(&p1, &p2);
        if !h.is_finite() {
            continue;
        }
        let rel = kisstime::RelPath::between(&p1, &p2);
        if kisstime::query::ball_ball::cannot_meet(&rel, case.params.radius, h) {
            pruned += 1;
            assert!(
                !case.expected_t.is_finite(),
                "{}: pruned, but the truth is a collision at {}",
                case.id,
                case.expected_t
            );
        }
    }
    println!("the prune rules out {pruned} of 1600 corpus pairs");
    assert!(
        pruned > 100,
        "the prune should rule out many pairs, it ruled out {pruned}"
    );
}
