//! Built-in workloads: reproducible batches of realistic (and deliberately hard) tables for
//! benchmarks, examples and cross-checks.
//!
//! Every scenario is a pure function of `(tables, balls, seed)`: the same arguments give
//! the same batch on every machine (PCG-64 from `rand_pcg`). Balls never overlap at the
//! start. The table is a 9-ft playing area, [`TABLE_LENGTH`] × [`TABLE_WIDTH`].

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;

use crate::batch::Batch;
use crate::model::{Ball, MotionState, Params};

/// Playing-area length of a 9-ft table in metres.
pub const TABLE_LENGTH: f64 = 2.54;
/// Playing-area width of a 9-ft table in metres.
pub const TABLE_WIDTH: f64 = 1.27;

/// A built-in workload.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Workload {
    /// The break: a racked 15-ball pyramid and the cue ball struck at it (16 balls;
    /// `balls` is ignored).
    Rack,
    /// Mid-shot: a few balls moving (one sliding, two rolling), the rest still, spread over
    /// the table. The common case of an event loop.
    Midshot,
    /// Every ball moving at random over the whole table.
    Spread,
    /// Every ball moving on a circle towards its centre, so that the cheap bound rules out
    /// (almost) no pair and every pair needs the full solve.
    Worst,
}

impl Workload {
    /// Every scenario.
    pub const ALL: [Workload; 4] = [
        Workload::Rack,
        Workload::Midshot,
        Workload::Spread,
        Workload::Worst,
    ];

    /// The scenario's name (`rack`, `midshot`, `spread`, `worst`).
    pub fn name(self) -> &'static str {
        match self {
            Workload::Rack => "rack",
            Workload::Midshot => "midshot",
            Workload::Spread => "spread",
            Workload::Worst => "worst",
        }
    }
}

/// Random positions for `n` balls in the rectangle `[x0, x1] × [y0, y1]`, at least
/// `2R + gap` apart (rejection sampling; the rectangle must have room).
fn place(
    rng: &mut Pcg64Mcg,
    n: usize,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    min_dist: f64,
) -> Vec<(f64, f64)> {
    let mut pts: Vec<(f64, f64)> = Vec::with_capacity(n);
    while pts.len() < n {
        let p = (rng.random_range(x0..x1), rng.random_range(y0..y1));
        if pts
            .iter()
            .all(|q| (p.0 - q.0).powi(2) + (p.1 - q.1).powi(2) >= min_dist * min_dist)
        {
            pts.push(p);
        }
    }
    pts
}

/// A moving ball at `(x, y)`: rolling, or sliding with random side, top or back spin.
fn mover(rng: &mut Pcg64Mcg, x: f64, y: f64, sliding: bool, params: &Params) -> Ball {
    let speed = rng.random_range(0.3..4.0);
    let angle = rng.random_range(0.0..std::f64::consts::TAU);
    let (vx, vy) = (speed * angle.cos(), speed * angle.sin());
    let r = params.radius;
    if !sliding {
        return Ball::rolling(x, y, vx, vy, r);
    }
    // spin around the natural roll: draw/follow k and side english
    let k = rng.random_range(-2.0..2.0);
    Ball {
        state: MotionState::Sliding,
        x,
        y,
        vx,
        vy,
        wx: -k * vy / r,
        wy: k * vx / r,
        wz: rng.random_range(-50.0..50.0),
    }
}

/// The balls of one table of `scenario`, as `(ball id, ball)`.
fn table(
    scenario: Workload,
    balls: usize,
    rng: &mut Pcg64Mcg,
    params: &Params,
) -> Vec<(i64, Ball)> {
    let r = params.radius;
    let margin = r + 1e-3;
    let full = (
        (margin, TABLE_LENGTH - margin),
        (margin, TABLE_WIDTH - margin),
    );
    match scenario {
        Workload::Rack => {
            let mut out = Vec::with_capacity(16);
            let d = 2.0 * r + 1e-4;
            let (ax, ay) = (0.75 * TABLE_LENGTH, 0.5 * TABLE_WIDTH);
            let mut id = 1;
            for row in 0..5 {
                for i in 0..=row {
                    let x = ax + row as f64 * d * 3f64.sqrt() / 2.0;
                    let y = ay + (i as f64 - row as f64 / 2.0) * d;
                    out.push((id, Ball::at_rest(x, y)));
                    id += 1;
                }
            }
            // the cue ball from the head string, aimed at the apex with a little noise
            let (cx, cy) = (
                0.25 * TABLE_LENGTH,
                0.5 * TABLE_WIDTH + rng.random_range(-0.1..0.1),
            );
            let speed = rng.random_range(6.0..10.0);
            let aim = (ay - cy).atan2(ax - cx) + rng.random_range(-0.005..0.005);
            let (vx, vy) = (speed * aim.cos(), speed * aim.sin());
            let k = rng.random_range(-0.5..0.5);
            out.push((
                0,
                Ball {
                    state: MotionState::Sliding,
                    x: cx,
                    y: cy,
                    vx,
                    vy,
                    wx: -k * vy / r,
                    wy: k * vx / r,
                    wz: 0.0,
                },
            ));
            out
        }
        Workload::Midshot => {
            let pts = place(rng, balls, full.0, full.1, 2.0 * r + 1e-3);
            pts.into_iter()
                .enumerate()
                .map(|(i, (x, y))| {
                    let b = match i {
                        0 => mover(rng, x, y, true, params),
                        1 | 2 => mover(rng, x, y, false, params),
                        _ => Ball::at_rest(x, y),
                    };
                    (i as i64, b)
                })
                .collect()
        }
        Workload::Spread => {
            let pts = place(rng, balls, full.0, full.1, 2.0 * r + 1e-3);
            pts.into_iter()
                .enumerate()
                .map(|(i, (x, y))| (i as i64, mover(rng, x, y, i % 2 == 0, params)))
                .collect()
        }
        Workload::Worst => {
            // balls on a circle, every one aimed at its centre (± 0.05 rad) at similar
            // speeds: every pair closes in, so no pair can be ruled out cheaply. Two balls
            // slide with strong draw and side spin (curved paths); the rest roll.
            let (cx, cy) = (0.5 * TABLE_LENGTH, 0.5 * TABLE_WIDTH);
            let ring = (balls as f64 * 3.0 * r / std::f64::consts::PI).max(0.25);
            (0..balls)
                .map(|i| {
                    let around = std::f64::consts::TAU * (i as f64 + rng.random_range(-0.2..0.2))
                        / balls as f64;
                    let (x, y) = (cx + ring * around.cos(), cy + ring * around.sin());
                    let aim = (cy - y).atan2(cx - x) + rng.random_range(-0.05..0.05);
                    let speed = rng.random_range(2.0..2.5);
                    let (vx, vy) = (speed * aim.cos(), speed * aim.sin());
                    let ball = if i < 2 {
                        // draw k along v and side spin m across it
                        let k = rng.random_range(-3.0..-1.0);
                        let m = rng.random_range(-1.0..1.0);
                        Ball {
                            state: MotionState::Sliding,
                            x,
                            y,
                            vx,
                            vy,
                            wx: (-k * vy + m * vx) / r,
                            wy: (k * vx + m * vy) / r,
                            wz: rng.random_range(-30.0..30.0),
                        }
                    } else {
                        Ball::rolling(x, y, vx, vy, r)
                    };
                    (i as i64, ball)
                })
                .collect()
        }
    }
}

/// A batch of `tables` tables of `scenario` with `balls` balls each (2 to 64; the rack
/// always has 16), table ids `0..tables`, reproducible from `seed`.
pub fn generate(
    scenario: Workload,
    tables: usize,
    balls: usize,
    seed: u64,
    params: &Params,
) -> Batch {
    let balls = balls.clamp(2, 64);
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let mut batch = Batch::new();
    for k in 0..tables {
        let t = table(scenario, balls, &mut rng, params);
        batch
            .push_table(k as i64, t)
            .expect("generated tables are valid");
    }
    batch
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::query::Status;

    #[test]
    fn generated_batches_are_reproducible_and_valid() {
        let p = Params::default();
        for s in Workload::ALL {
            let a = generate(s, 20, 16, 7, &p);
            let b = generate(s, 20, 16, 7, &p);
            assert_eq!(a.num_pairs(), 20 * 120, "{s:?}");
            let ta = crate::pair_times(&a, &p).unwrap();
            let tb = crate::pair_times(&b, &p).unwrap();
            assert_eq!(ta, tb);
            // no overlaps at the start
            assert!(ta.iter().all(|c| c.status != Status::Overlap), "{s:?}");
        }
    }

    #[test]
    fn the_break_hits_the_rack() {
        let p = Params::default();
        let batch = generate(Workload::Rack, 10, 16, 1, &p);
        let next = crate::next_collisions(&batch, &p).unwrap();
        assert!(
            next.iter()
                .all(|n| n.status == Status::Hit && n.pair.unwrap().0 == 0)
        );
    }
}
