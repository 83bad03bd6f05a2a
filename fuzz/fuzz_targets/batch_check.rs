//! Shared by the reader targets: what a batch that a reader accepted must satisfy, and
//! that writing it out and reading it back gives the same batch.

use kisstime::motion::path::PATH_MOVES;
use kisstime::{Ball, Batch, Params, ball_path};

/// Every invariant a reader's batch promises: tables in strictly ascending id order, each
/// with at least 2 balls in strictly ascending id order, every number finite and within
/// the documented physical range ([`Ball::MAX_POSITION`], [`Ball::MAX_SPEED`],
/// [`Ball::MAX_SPIN`]), every ball's path keeping its own contract (finite coefficients; a
/// moving ball's motion ends at a finite, positive time — what broke for `vx = 1e160`),
/// pair counts `n(n−1)/2`.
pub fn check_batch(batch: &Batch) {
    let mut pairs = 0;
    for k in 0..batch.num_tables() {
        if k > 0 {
            assert!(
                batch.table_id(k - 1) < batch.table_id(k),
                "tables out of order"
            );
        }
        let ids = batch.ball_ids(k);
        let balls = batch.balls(k);
        assert_eq!(ids.len(), balls.len());
        assert!(ids.len() >= 2, "a table with fewer than 2 balls");
        assert!(
            ids.windows(2).all(|w| w[0] < w[1]),
            "ball ids not ascending"
        );
        for b in balls {
            assert!(
                b.numbers().iter().all(|v| v.is_finite()),
                "a non-finite number"
            );
            let n = b.numbers();
            assert!(n[0].abs() <= Ball::MAX_POSITION && n[1].abs() <= Ball::MAX_POSITION);
            assert!(
                n[2].abs() <= Ball::MAX_SPEED && n[3].abs() <= Ball::MAX_SPEED,
                "a speed beyond the range"
            );
            assert!(
                n[4..].iter().all(|w| w.abs() <= Ball::MAX_SPIN),
                "a spin beyond the range"
            );
            let p = ball_path(b, &Params::default());
            let coeffs = [p.a.x, p.a.y, p.b.x, p.b.y, p.c.x, p.c.y];
            assert!(
                coeffs.iter().all(|v| v.is_finite()),
                "a path that is not finite"
            );
            if p.flags & PATH_MOVES != 0 {
                assert!(
                    p.tmax.is_finite() && p.tmax >= 0.0,
                    "a moving path without an end"
                );
            }
        }
        let n = ids.len();
        assert_eq!(batch.pair_range(k).len(), n * (n - 1) / 2);
        pairs += n * (n - 1) / 2;
    }
    assert_eq!(batch.num_pairs(), pairs);
}

/// The same tables, balls and numbers (bit for bit; `-0` and `0` differ).
pub fn same_batch(a: &Batch, b: &Batch) {
    assert_eq!(a.num_tables(), b.num_tables());
    for k in 0..a.num_tables() {
        assert_eq!(a.table_id(k), b.table_id(k));
        assert_eq!(a.ball_ids(k), b.ball_ids(k));
        for (x, y) in a.balls(k).iter().zip(b.balls(k)) {
            assert_eq!(x.state, y.state);
            let (xn, yn) = (x.numbers(), y.numbers());
            for i in 0..7 {
                assert_eq!(
                    xn[i].to_bits(),
                    yn[i].to_bits(),
                    "number {i} changed in a round trip"
                );
            }
        }
    }
}

/// Written as CSV and as NPY and read back, the batch is unchanged.
pub fn check_round_trips(batch: &Batch) {
    let mut csv = Vec::new();
    kisstime::io::write_batch_csv(&mut csv, batch).expect("write csv");
    let back = kisstime::io::read_batch_csv(&csv[..], "round-trip.csv").expect("read back csv");
    same_batch(batch, &back);
    let mut npy = Vec::new();
    kisstime::io::npy::write_batch_npy(&mut npy, batch).expect("write npy");
    let back =
        kisstime::io::npy::read_batch_npy(&npy[..], "round-trip.npy").expect("read back npy");
    same_batch(batch, &back);
}
