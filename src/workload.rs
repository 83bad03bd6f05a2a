//! Built-in workloads: reproducible batches of realistic (and deliberately hard) tables for
//! benchmarks, examples and cross-checks.
//!
//! Every scenario is a pure function of `(tables, balls, seed)`: the same arguments give
//! the same batch on every machine (PCG-64 from `rand_pcg`). Balls never overlap at the
//! start. The table is a 9-ft playing area, [`TABLE_LENGTH`] × [`TABLE_WIDTH`], in the frame
//! of pooltool's table that every command uses: x across the table (0 to [`TABLE_WIDTH`]),
//! y along it (0 to [`TABLE_LENGTH`]), so that `kisstime gen`'s tables can be simulated.

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;

use crate::batch::Batch;
use crate::model::ball_state::BallState;
use crate::model::table::Table;
use crate::model::vec3::Vec3;
use crate::model::{Ball, MotionState, Params};
use crate::resolve::stick_ball::CueStrike;
use crate::simulate::check::check_on_table;

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
    // pooltool's frame: x across the table, y along it
    let full = (
        (margin, TABLE_WIDTH - margin),
        (margin, TABLE_LENGTH - margin),
    );
    match scenario {
        Workload::Rack => {
            let mut out = Vec::with_capacity(16);
            let d = 2.0 * r + 1e-4;
            // the apex on the foot spot, the rows towards the foot rail (+y)
            let (ax, ay) = (0.5 * TABLE_WIDTH, 0.75 * TABLE_LENGTH);
            let mut id = 1;
            for row in 0..5 {
                for i in 0..=row {
                    let x = ax + (i as f64 - row as f64 / 2.0) * d;
                    let y = ay + row as f64 * d * 3f64.sqrt() / 2.0;
                    out.push((id, Ball::at_rest(x, y)));
                    id += 1;
                }
            }
            // the cue ball from the head string, aimed at the apex with a little noise
            let (cx, cy) = (
                0.5 * TABLE_WIDTH + rng.random_range(-0.1..0.1),
                0.25 * TABLE_LENGTH,
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
            let (cx, cy) = (0.5 * TABLE_WIDTH, 0.5 * TABLE_LENGTH);
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

/// A built-in workload of whole shots for the simulator ([`generate_shots`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShotWorkload {
    /// The break: a 15-ball triangle rack on the foot spot and the cue ball struck from
    /// behind the head string at the apex, hard (16 balls).
    Breaks,
    /// Ordinary shots: 6 to 16 balls anywhere on the table, the cue ball struck towards
    /// one of them at a moderate speed.
    Ordinary,
}

impl ShotWorkload {
    /// Both workloads.
    pub const ALL: [ShotWorkload; 2] = [ShotWorkload::Breaks, ShotWorkload::Ordinary];

    /// The workload's name (`breaks`, `ordinary`).
    pub fn name(self) -> &'static str {
        match self {
            ShotWorkload::Breaks => "breaks",
            ShotWorkload::Ordinary => "ordinary",
        }
    }
}

/// One generated whole-shot table: the balls (ball 0 is the cue ball) and its strike.
#[derive(Clone, Debug, PartialEq)]
pub struct ShotTable {
    /// Every ball at rest at t = 0, in the order that decides exact ties.
    pub balls: Vec<BallState>,
    /// The index of the struck ball (always 0, the cue ball).
    pub cue: usize,
    /// The cue strike.
    pub strike: CueStrike,
}

impl ShotTable {
    /// The strike as [`crate::simulate::simulate_batch`]'s input closure returns it.
    pub fn strike(&self) -> Option<(usize, CueStrike)> {
        Some((self.cue, self.strike))
    }
}

/// The foot spot and the head string of the 9-ft table in the simulator's frame (x across
/// the table, 0 to 1.27 m; y along it, 0 to 2.54 m): the games' ([`crate::game::progress`]).
pub use crate::game::progress::{FOOT_SPOT, HEAD_STRING_Y};

/// The aim direction in degrees (counter-clockwise from +x, in [0, 360)) from `from` to `to`.
fn aim_degrees(from: (f64, f64), to: (f64, f64)) -> f64 {
    (to.1 - from.1)
        .atan2(to.0 - from.0)
        .to_degrees()
        .rem_euclid(360.0)
}

/// A point drawn uniformly in `[x0, x1] × [y0, y1]` until it lies on the playing surface of
/// `table` and at least `min_dist` from every point of `taken`.
fn free_spot(
    rng: &mut Pcg64Mcg,
    table: &Table,
    radius: f64,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    min_dist: f64,
    taken: &[(f64, f64)],
) -> (f64, f64) {
    loop {
        let p = (rng.random_range(x0..x1), rng.random_range(y0..y1));
        let clear = taken
            .iter()
            .all(|q| (p.0 - q.0).powi(2) + (p.1 - q.1).powi(2) >= min_dist * min_dist);
        if clear && check_on_table(table, radius, Vec3::new(p.0, p.1, radius)).is_ok() {
            return p;
        }
    }
}

/// One table of `kind` on the 9-ft table (see [`generate_shots`]).
fn shot_table(kind: ShotWorkload, rng: &mut Pcg64Mcg, table: &Table, r: f64) -> ShotTable {
    // centres at least R + 1 mm from the cushion noses
    let margin = r + 1e-3;
    let xs = (margin, TABLE_WIDTH - margin);
    let ys = (margin, TABLE_LENGTH - margin);
    match kind {
        ShotWorkload::Breaks => {
            // ball 0 the cue ball behind the head string, then the rack: rows of 1 to 5
            // towards the foot rail, the apex on the foot spot, neighbours 2R + 1 µm apart
            // and each ball jittered by at most ±0.25 µm (touching, never overlapping)
            let d = 2.0 * r + 1e-6;
            let cue = free_spot(rng, table, r, xs, (0.3, HEAD_STRING_Y - r), 0.0, &[]);
            let mut balls = vec![BallState::at_rest(cue.0, cue.1, r)];
            for row in 0..5 {
                for i in 0..=row {
                    let x = FOOT_SPOT.0 + (i as f64 - row as f64 / 2.0) * d;
                    let y = FOOT_SPOT.1 + row as f64 * d * 3f64.sqrt() / 2.0;
                    let jx = rng.random_range(-0.25e-6..0.25e-6);
                    let jy = rng.random_range(-0.25e-6..0.25e-6);
                    balls.push(BallState::at_rest(x + jx, y + jy, r));
                }
            }
            let strike = CueStrike {
                v0: rng.random_range(6.0..=9.0),
                phi: aim_degrees(cue, FOOT_SPOT),
                theta: rng.random_range(0.0..=5.0),
                a: rng.random_range(-0.1..=0.1),
                b: rng.random_range(-0.1..=0.1),
            };
            ShotTable {
                balls,
                cue: 0,
                strike,
            }
        }
        ShotWorkload::Ordinary => {
            let n = rng.random_range(6..=16usize);
            let mut spots: Vec<(f64, f64)> = Vec::with_capacity(n);
            while spots.len() < n {
                let p = free_spot(rng, table, r, xs, ys, 2.0 * r + 1e-3, &spots);
                spots.push(p);
            }
            let target = rng.random_range(1..n);
            // the tip's offset: uniform in the disc of radius 0.5
            let (a, b) = loop {
                let (a, b) = (rng.random_range(-0.5..=0.5), rng.random_range(-0.5..=0.5));
                if a * a + b * b <= 0.25 {
                    break (a, b);
                }
            };
            let strike = CueStrike {
                v0: rng.random_range(0.5..=4.0),
                phi: aim_degrees(spots[0], spots[target]),
                theta: rng.random_range(0.0..=20.0),
                a,
                b,
            };
            ShotTable {
                balls: spots
                    .into_iter()
                    .map(|(x, y)| BallState::at_rest(x, y, r))
                    .collect(),
                cue: 0,
                strike,
            }
        }
    }
}

/// `tables` whole-shot tables of `kind` on pooltool's 9-ft table ([`Table::nine_foot`],
/// balls of radius `radius`), reproducible from `seed` (the same tables on every machine),
/// every one passing [`crate::simulate::check_layout`]:
///
/// - [`ShotWorkload::Breaks`]: a 15-ball triangle rack (neighbours 1 µm apart) with its
///   apex on the foot spot, the cue ball behind the head string at a random spot, struck at
///   the apex with V0 uniform in [6, 9] m/s, a and b in [−0.1, 0.1], θ in [0°, 5°];
/// - [`ShotWorkload::Ordinary`]: 6 to 16 balls at random spots at least 1 mm apart and
///   their centres at least R + 1 mm from the cushion noses, the cue ball (ball 0) struck
///   towards a random object ball with V0 uniform in [0.5, 4] m/s, (a, b) uniform in the
///   disc of radius 0.5, θ in [0°, 20°].
pub fn generate_shots(kind: ShotWorkload, tables: usize, seed: u64, radius: f64) -> Vec<ShotTable> {
    let table = Table::nine_foot();
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    (0..tables)
        .map(|_| shot_table(kind, &mut rng, &table, radius))
        .collect()
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

    #[test]
    fn generated_shots_are_reproducible_and_pass_the_layout_check() {
        let r = crate::simulate::SimParams::default().ball.r;
        let table = Table::nine_foot();
        for kind in ShotWorkload::ALL {
            let a = generate_shots(kind, 200, 11, r);
            assert_eq!(a, generate_shots(kind, 200, 11, r), "{kind:?}");
            assert_ne!(a, generate_shots(kind, 200, 12, r), "{kind:?}");
            for (k, t) in a.iter().enumerate() {
                crate::simulate::check_layout(&table, r, &t.balls)
                    .unwrap_or_else(|e| panic!("{kind:?} table {k}: {e}"));
                t.strike.validate().unwrap();
                match kind {
                    ShotWorkload::Breaks => {
                        assert_eq!(t.balls.len(), 16);
                        assert!(t.balls[0].r.y < HEAD_STRING_Y);
                        assert!((6.0..=9.0).contains(&t.strike.v0));
                    }
                    ShotWorkload::Ordinary => {
                        assert!((6..=16).contains(&t.balls.len()));
                        assert!((0.5..=4.0).contains(&t.strike.v0));
                        assert!(t.strike.a.hypot(t.strike.b) <= 0.5);
                    }
                }
            }
        }
    }
}
