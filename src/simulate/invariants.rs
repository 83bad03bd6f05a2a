//! Invariants of one simulated shot, checked from the outside: given the balls a shot
//! started from, its strike, its recorded events ([`EventRecord`]s, as
//! [`crate::simulate::simulate_batch`] and [`crate::engine::ShotEngine`] record them), its
//! final balls and its [`Outcome`], [`check_shot`] says whether the run is physically and
//! logically sound, or names the first invariant it breaks with the ball and the event.
//! The fuzz target `event_loop` (`fuzz/`, see FUZZING.md) and the property tests
//! (`tests/invariants.rs`) both use it; nothing here runs during a simulation.
//!
//! The invariants ([`Invariant`] names each):
//! - **ball count** ([`Invariant::BallCount`]): as many final balls as starting ones, a
//!   pocketed ball stays pocketed, and each ball pocketed during the shot has exactly one
//!   `ball_pocket` event (on table + pocketed = all balls, always);
//! - **records** ([`Invariant::Record`]): every number finite, agents that exist (balls,
//!   cushion segments, jaws, pockets of `table`), no event for a ball after its pocketing,
//!   the strike first (and only first), the outcome's event count and end time those of the
//!   events, the limits kept; replaying the events (every ball evolved to each event, the
//!   involved balls replaced by their recorded states, as the loop does) gives the final
//!   balls within [`REPLAY_TOLERANCE`];
//! - **event times** ([`Invariant::EventTime`]): finite, ≥ 0, non-decreasing;
//! - **overlap** ([`Invariant::Overlap`]): no two unpocketed balls overlap at the end of a
//!   run that came to rest by more than [`END_OVERLAP_TOLERANCE`] (a pair that starts
//!   deeper and never moves keeps its depth: the layout check lets balls at rest overlap by
//!   up to [`crate::simulate::LAYOUT_TOLERANCE`]); a cut run ends mid-shot, where moving
//!   balls may overlap (pooltool resolves an overlap at once, Q3), and is not checked;
//! - **on the table** ([`Invariant::OffTable`]): every unpocketed ball ends on the playing
//!   surface ([`crate::simulate::check::check_in_play`]), and so does every ball an event
//!   leaves unpocketed;
//! - **energy** ([`Invariant::Energy`]): the total kinetic energy, translational and
//!   rotational (`½ m |v|² + ½ (2/5 m R²) |ω|²`, m and R from the parameters), never grows
//!   from one event to the next by more than [`ENERGY_REL_TOLERANCE`] of itself (plus
//!   [`ENERGY_ABS_TOLERANCE`]), except at the strike, and at a ball–ball collision by no
//!   more than pooltool's continually-touching fix can add ([`momentum_steal_energy`]:
//!   spec Q2 moves 10% of one ball's speed to the other, and that makes energy when two
//!   balls move together at nearly the same speed);
//! - **through a rail** ([`Invariant::RailTunnel`]): a ball off the table, or inside a
//!   straight cushion or a jaw, that had touched that cushion while moving into it is
//!   reported apart from [`Invariant::OffTable`]: pooltool 0.6.0 itself sends such a ball
//!   into or through the cushion (its detection accepts only roots τ > EPS, spec Q6), and
//!   kisstime reproduces it ([`touching_into_cushion`]; FUZZING.md, findings 7 and 30); so
//!   is a ball that the kiss of a ball–ball event (Q1) moved, by at most [`KISS_REACH`],
//!   from the playing surface into a cushion (findings 13 and 33);
//! - **rest** ([`Invariant::NotAtRest`]): a run that is not cut ([`Outcome::cut`] `None`)
//!   ends with every ball stationary (zero velocity and spin) or pocketed; one that is cut
//!   says why ([`Cut::MaxEvents`]: exactly `max_events` events; [`Cut::MaxTime`]: the
//!   simulation was stopped by the time limit) — a run is never cut silently.
//!
//! ```
//! use kisstime::simulate::invariants::{ShotRun, check_shot};
//! use kisstime::simulate::{
//!     BallState, CueStrike, EventRecord, Limits, SimParams, Table, simulate,
//! };
//!
//! let table = Table::nine_foot();
//! let p = SimParams::default();
//! let start = [
//!     BallState::at_rest(0.635, 0.6, p.ball.r),
//!     BallState::at_rest(0.635, 1.9, p.ball.r),
//! ];
//! let strike = Some((0, CueStrike { v0: 2.0, phi: 90.0, theta: 0.0, a: 0.0, b: 0.2 }));
//! let (mut events, mut end) = (Vec::new(), start.to_vec());
//! let limits = Limits::default();
//! let outcome = simulate(&table, p, limits, &start, strike, |e, balls| {
//!     events.push(EventRecord::new(*e, balls));
//!     end.copy_from_slice(balls);
//! })?;
//! let run = ShotRun { start: &start, strike, events: &events, end: &end, outcome, limits };
//! check_shot(&table, &p, &run).expect("a sound shot");
//! # Ok::<(), kisstime::error::SimError>(())
//! ```

use std::fmt;

use crate::model::MotionState;
use crate::model::Vec2;
use crate::model::ball_state::{BallState, ball_energy};
use crate::model::sim_params::SimParams;
use crate::model::table::Table;
use crate::motion::evolve::evolve;
use crate::motion::trajectory::trajectory;
use crate::query::CONTACT_TOL;
use crate::resolve::stick_ball::CueStrike;
use crate::simulate::batch::EventRecord;
use crate::simulate::check::check_in_play;
use crate::simulate::event_loop::Limits;
use crate::simulate::events::{Cut, EventKind, NO_AGENT, Outcome};

/// How deep (m) two unpocketed balls may overlap at the end of a shot: 1 µm. Balls come to
/// rest after a collision at most a few hundred nanometres inside each other in the
/// property tests (`tests/invariants.rs` prints the deepest it saw): the detection
/// accepts contacts within [`crate::CONTACT_TOL`] and pooltool's spacer (Q1) moves a
/// colliding pair only a little apart.
pub const END_OVERLAP_TOLERANCE: f64 = 1e-6;

/// The relative growth of the total kinetic energy allowed from one event to the next
/// (rounding of the resolvers: the momentum fix Q2, the spacer Q1, Stronge's cushion
/// model).
pub const ENERGY_REL_TOLERANCE: f64 = 1e-9;

/// The absolute growth of the total kinetic energy (J) allowed from one event to the next,
/// beside [`ENERGY_REL_TOLERANCE`]: rounding near rest.
pub const ENERGY_ABS_TOLERANCE: f64 = 1e-15;

/// The farthest (m) a ball–ball event's kiss (Q1) may move a ball for the checker to put
/// a ball it pushes into a cushion down to the kiss (as [`Invariant::RailTunnel`]): the
/// spacer moves a ball by at most 5 µm along its velocity, or along the line of centres
/// by half the pair's overlap; 1 mm is far beyond either.
pub const KISS_REACH: f64 = 1e-3;

/// How far (m, per coordinate; m/s and rad/s for velocities and spins, relative beyond
/// 1) the final balls may lie from those the recorded events replay to.
pub const REPLAY_TOLERANCE: f64 = 1e-9;

/// Which invariant a shot broke (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Invariant {
    /// Balls appeared, vanished, or came back from a pocket.
    BallCount,
    /// A record that does not hold together (agents, order, outcome, limits, replay).
    Record,
    /// An event time that is not finite, negative, or earlier than the one before.
    EventTime,
    /// Two unpocketed balls overlap at the end.
    Overlap,
    /// An unpocketed ball off the playing surface or inside a cushion.
    OffTable,
    /// The total kinetic energy grew at an event other than the strike.
    Energy,
    /// A run that was not cut ended with a ball still moving.
    NotAtRest,
    /// A ball went into a straight cushion or a jaw, or through it off the table, after it
    /// touched the cushion while moving into it: pooltool 0.6.0's detection accepts only
    /// roots τ > EPS (spec Q6), so such a ball gets no cushion event at all. Reproduced
    /// faithfully (pooltool does the same: `tests/sim_properties.rs`,
    /// `chatter_pushes_a_ball_through_the_rail_as_in_pooltool`, and
    /// `tests/fuzz_regressions.rs`, `a_ball_pressed_into_a_jaw_goes_in_as_in_pooltool`), so
    /// it is told apart from [`Invariant::OffTable`]: FUZZING.md, findings 7 and 30.
    RailTunnel,
}

impl Invariant {
    /// A short name (`ball count`, `overlap`, …).
    pub fn name(self) -> &'static str {
        match self {
            Invariant::BallCount => "ball count",
            Invariant::Record => "record",
            Invariant::EventTime => "event time",
            Invariant::Overlap => "overlap",
            Invariant::OffTable => "on the table",
            Invariant::Energy => "energy",
            Invariant::NotAtRest => "at rest",
            Invariant::RailTunnel => "through a rail (pooltool's Q6)",
        }
    }
}

/// A broken invariant: which, the ball and the event concerned (where one is), and what
/// was seen.
#[derive(Clone, Debug, PartialEq)]
pub struct Violation {
    /// The invariant.
    pub invariant: Invariant,
    /// The ball's index in the table, where one ball is concerned.
    pub ball: Option<usize>,
    /// The event's index in the shot's events (0: the strike), where one is concerned.
    pub event: Option<usize>,
    /// What was seen.
    pub detail: String,
}

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "invariant {} broken", self.invariant.name())?;
        if let Some(b) = self.ball {
            write!(f, ", ball {b}")?;
        }
        if let Some(e) = self.event {
            write!(f, ", event {e}")?;
        }
        write!(f, ": {}", self.detail)
    }
}

impl std::error::Error for Violation {}

/// How close a sound shot came to the tolerances ([`check_shot`]'s answer): to measure
/// them, as `tests/invariants.rs` does.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Margins {
    /// The deepest overlap (m) of two unpocketed balls at the end (0 when none overlap).
    pub deepest_overlap: f64,
    /// The largest relative growth of the total kinetic energy from one event to the next
    /// after the strike (0 when it never grew).
    pub energy_growth: f64,
    /// The largest difference of the final balls from the replay of the events (m, m/s,
    /// rad/s).
    pub replay_error: f64,
}

/// One simulated shot, as [`check_shot`] takes it.
#[derive(Clone, Copy, Debug)]
pub struct ShotRun<'a> {
    /// The balls it started from (pooltool's ball order).
    pub start: &'a [BallState],
    /// The strike (ball index, strike), if any.
    pub strike: Option<(usize, CueStrike)>,
    /// Every event, in order (the strike first where there was one).
    pub events: &'a [EventRecord],
    /// The balls at the end (at the time of the last event).
    pub end: &'a [BallState],
    /// How the run ended.
    pub outcome: Outcome,
    /// The limits it ran under.
    pub limits: Limits,
}

fn violation(
    invariant: Invariant,
    ball: Option<usize>,
    event: Option<usize>,
    detail: String,
) -> Violation {
    Violation {
        invariant,
        ball,
        event,
        detail,
    }
}

fn finite(b: &BallState) -> bool {
    b.r.is_finite() && b.v.is_finite() && b.w.is_finite() && b.t.is_finite()
}

/// The total kinetic energy of `balls` (J).
pub fn total_energy(balls: &[BallState], params: &SimParams) -> f64 {
    balls.iter().map(|b| ball_energy(b, &params.ball)).sum()
}

/// The most kinetic energy (J) pooltool's continually-touching fix (Q2,
/// [`crate::resolve::ball_ball::continually_touching`]) can have added to a ball–ball
/// collision whose balls left in `states`: the fix moves 10% of the chaser's speed along
/// the line of centres `n` to the other ball, which adds `0.1 m ℓ_c (ℓ_o − 0.9 ℓ_c)` when
/// the other ball's `ℓ_o` is above `0.9 ℓ_c` (two balls moving together, nearly at the
/// same speed). Worked back from the states after the fix, for either ball as the
/// chaser, the larger; 0 where neither would have added any. The one place the energy
/// invariant gives way, because pooltool does (spec Q2: copied so that breaks match).
pub fn momentum_steal_energy(states: &[BallState; 2], params: &SimParams) -> f64 {
    let [b1, b2] = states;
    let d = b2.r - b1.r;
    let len = d.norm();
    let positive = |x: f64| x > 0.0;
    if !(positive(len) && positive(b1.v.norm()) && positive(b2.v.norm())) {
        return 0.0;
    }
    let n = (1.0 / len) * d;
    let (l1, l2) = (b1.v.dot(n), b2.v.dot(n));
    let gain = |lc_after: f64, lo_after: f64| {
        let lc = lc_after / 0.9;
        let lo = lo_after - 0.1 * lc;
        0.5 * params.ball.m * (lc_after * lc_after + lo_after * lo_after - lc * lc - lo * lo)
    };
    gain(l1, l2).max(gain(l2, l1)).max(0.0)
}

/// A cushion of a table: a straight segment or a jaw (its index in `table.linear` or
/// `table.circular`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cushion {
    /// A straight cushion segment.
    Segment(usize),
    /// A jaw (a circular cushion segment).
    Jaw(usize),
}

impl Cushion {
    /// The cushion in words, by its id in `table` ("cushion segment 3", "the jaw 11t").
    pub fn describe(self, table: &Table) -> String {
        let id = |ids: &[String], k: usize| ids.get(k).map_or("?", String::as_str).to_owned();
        match self {
            Cushion::Segment(k) => format!("cushion segment {}", id(&table.linear_ids, k)),
            Cushion::Jaw(k) => format!("the jaw {}", id(&table.circular_ids, k)),
        }
    }
}

/// The cushion that ball `b` touches while moving into it, if any. A straight segment:
/// the ball's centre on the segment's checked line (the line `R` from the segment on its
/// checked side) or inside it (up to the segment itself), within the segment's extent. A
/// jaw: its centre on the circle `r_jaw + R` about the jaw's centre or inside it (up to
/// the arc itself). And its path heading into the cushion (its velocity, or its
/// acceleration: a ball the kiss (Q1) left a micrometre inside the line, moving out slowly
/// while its spin curves it in, never crosses the line from outside). pooltool's detection
/// finds no root τ > EPS for such a ball (Q6): no cushion event comes, and the ball goes
/// into the cushion. (A ball that does leave the line and comes back meets the cushion
/// as usual, and its flag is cleared at that event.) A ball–ball kiss (Q1) puts a ball
/// there when it presses the ball into a cushion: findings 7 (segments) and 30 (jaws) in
/// FUZZING.md.
pub fn touching_into_cushion(table: &Table, params: &SimParams, b: &BallState) -> Option<Cushion> {
    if b.s == MotionState::Pocketed || !b.translating() {
        return None;
    }
    let path = trajectory(b, &params.ball);
    let r = params.ball.r;
    // depth past the contact surface, and speed and acceleration into it: touching moving in
    let touching_in = |depth: f64, v_in: f64, a_in: f64| {
        (-CONTACT_TOL..=r).contains(&depth) && (v_in > 0.0 || a_in > 0.0)
    };
    let segment = table.linear.iter().position(|seg| {
        let norm = (seg.lx * seg.lx + seg.ly * seg.ly).sqrt();
        let (d, e) = (seg.p2 - seg.p1, path.c - Vec2::new(seg.p1.x, seg.p1.y));
        let along = (e.x * d.x + e.y * d.y) / (d.x * d.x + d.y * d.y);
        if !(norm > 0.0 && (0.0..=1.0).contains(&along)) {
            return false;
        }
        let value = (seg.l0 + seg.lx * path.c.x + seg.ly * path.c.y) / norm;
        let speed = (seg.lx * path.b.x + seg.ly * path.b.y) / norm;
        let accel = (seg.lx * path.a.x + seg.ly * path.a.y) / norm;
        let sides: &[f64] = match seg.direction {
            0 => &[1.0],
            1 => &[-1.0],
            _ => &[1.0, -1.0],
        };
        sides
            .iter()
            .any(|&inward| touching_in(inward * value + r, inward * speed, inward * accel))
    });
    if let Some(k) = segment {
        return Some(Cushion::Segment(k));
    }
    table
        .circular
        .iter()
        .position(|jaw| {
            // the unit vector from the ball's centre to the jaw's centre: inward
            let (dx, dy) = (jaw.center.x - path.c.x, jaw.center.y - path.c.y);
            let dist = (dx * dx + dy * dy).sqrt();
            if dist <= 0.0 {
                return false;
            }
            let (nx, ny) = (dx / dist, dy / dist);
            touching_in(
                jaw.radius + r - dist,
                nx * path.b.x + ny * path.b.y,
                nx * path.a.x + ny * path.a.y,
            )
        })
        .map(Cushion::Jaw)
}

/// Whether `a` and `b` agree within [`REPLAY_TOLERANCE`] (relative beyond 1).
fn near(a: f64, b: f64) -> bool {
    (a - b).abs() <= REPLAY_TOLERANCE * a.abs().max(b.abs()).max(1.0)
}

/// Checks one simulated shot against every invariant of the module docs; the first broken
/// one is the error; a sound shot's answer is how close it came to the tolerances.
/// `params` are the parameters it ran under (m and R for the energy and the overlaps).
/// Never panics, whatever the inputs (a malformed record is a [`Invariant::Record`]
/// violation).
pub fn check_shot(
    table: &Table,
    params: &SimParams,
    run: &ShotRun<'_>,
) -> Result<Margins, Violation> {
    let mut margins = Margins::default();
    let n = run.start.len();
    let r = params.ball.r;
    let rec = |ball, event, detail| Err(violation(Invariant::Record, ball, event, detail));
    // (a) ball count
    if run.end.len() != n {
        return Err(violation(
            Invariant::BallCount,
            None,
            None,
            format!("{n} balls at the start, {} at the end", run.end.len()),
        ));
    }
    for (i, b) in run.start.iter().chain(run.end).enumerate() {
        if !finite(b) {
            let when = if i < n { "start" } else { "end" };
            return rec(
                Some(i % n),
                None,
                format!("non-finite state at the {when}: {b:?}"),
            );
        }
    }
    // the outcome and the limits
    if run.outcome.n_events != run.events.len() {
        return rec(
            None,
            None,
            format!(
                "the outcome counts {} events, {} recorded",
                run.outcome.n_events,
                run.events.len()
            ),
        );
    }
    let t_last = run.events.last().map_or(0.0, |e| e.event.t);
    if run.outcome.t_end != t_last {
        return rec(
            None,
            None,
            format!(
                "the outcome ends at {} s, the last event at {t_last} s",
                run.outcome.t_end
            ),
        );
    }
    if run.events.len() > run.limits.max_events {
        return rec(
            None,
            None,
            format!(
                "{} events, more than the limit {}",
                run.events.len(),
                run.limits.max_events
            ),
        );
    }
    // replay the events: agents, times, energy, pocketing
    let mut cur: Vec<BallState> = run.start.to_vec();
    let mut t_cur = 0.0;
    let mut energy = total_energy(&cur, params);
    let mut pocketed: Vec<bool> = run
        .start
        .iter()
        .map(|b| b.s == MotionState::Pocketed)
        .collect();
    let mut pocket_events = vec![0usize; n];
    // per ball, the cushion it touched moving into it (Q6) and when (None: at the start)
    let mut tunnel: Vec<Option<(Cushion, Option<usize>)>> = run
        .start
        .iter()
        .map(|b| touching_into_cushion(table, params, b).map(|c| (c, None)))
        .collect();
    let off_table =
        |i: usize, tunnel: &[Option<(Cushion, Option<usize>)>], at, why: String| match tunnel
            .get(i)
            .copied()
            .flatten()
        {
            Some((cushion, when)) => violation(
                Invariant::RailTunnel,
                Some(i),
                at,
                format!(
                    "{why}; the ball touched {} moving into it {}, and \
                     pooltool's detection (roots τ > EPS only, Q6) gives no cushion event",
                    cushion.describe(table),
                    when.map_or("at the start".to_owned(), |k| format!("after event {k}"))
                ),
            ),
            None => violation(Invariant::OffTable, Some(i), at, why),
        };
    for (k, record) in run.events.iter().enumerate() {
        let e = record.event;
        let ball = e.ball as usize;
        let at = Some(k);
        // (d) times
        if !(e.t.is_finite() && e.t >= 0.0) {
            return Err(violation(
                Invariant::EventTime,
                Some(ball),
                at,
                format!("time {} s", e.t),
            ));
        }
        if e.t < t_cur {
            return Err(violation(
                Invariant::EventTime,
                Some(ball),
                at,
                format!("time {} s before the previous event's {t_cur} s", e.t),
            ));
        }
        if e.t > run.limits.max_time {
            return rec(
                Some(ball),
                at,
                format!("time {} s past the limit {} s", e.t, run.limits.max_time),
            );
        }
        // agents
        if ball >= n {
            return rec(None, at, format!("{e:?}: ball {ball} of {n}"));
        }
        if pocketed[ball] {
            return rec(Some(ball), at, format!("{e:?} for a ball already pocketed"));
        }
        let other = e.other as usize;
        let items = match e.kind {
            EventKind::BallBall => n,
            EventKind::BallLinearCushion => table.linear.len(),
            EventKind::BallCircularCushion => table.circular.len(),
            EventKind::BallPocket => table.pockets.len(),
            _ => 0,
        };
        if items == 0 && e.other != NO_AGENT {
            return rec(Some(ball), at, format!("{e:?}: a second agent"));
        }
        if items > 0 && other >= items {
            return rec(Some(ball), at, format!("{e:?}: agent {other} of {items}"));
        }
        if e.kind == EventKind::BallBall && (other == ball || pocketed[other]) {
            return rec(
                Some(ball),
                at,
                format!("{e:?}: a ball against itself or a pocketed ball"),
            );
        }
        let is_strike = e.kind == EventKind::StickBall;
        let struck = run.strike.is_some_and(|(cue, _)| cue == ball);
        let strike_due = k == 0 && run.strike.is_some_and(|(_, s)| s.v0 > 0.0) && energy == 0.0;
        if (is_strike && !(k == 0 && struck)) || (strike_due && !is_strike) {
            return rec(
                Some(ball),
                at,
                format!("{e:?}: the strike must be the first event, on the struck ball"),
            );
        }
        // evolve everything to the event, then take the involved balls' recorded states
        let dt = e.t - t_cur;
        for b in &mut cur {
            *b = evolve(b, dt, &params.ball);
        }
        t_cur = e.t;
        let before = total_energy(&cur, params);
        let involved_before: Vec<BallState> = record
            .balls()
            .filter_map(|(i, _)| cur.get(i).copied())
            .collect();
        for (i, s) in record.balls() {
            if i >= n {
                return rec(None, at, format!("{e:?}: a state for ball {i} of {n}"));
            }
            if !finite(s) {
                return rec(Some(i), at, format!("non-finite state {s:?}"));
            }
            cur[i] = *s;
        }
        if e.kind == EventKind::BallPocket {
            if cur[ball].s != MotionState::Pocketed {
                return Err(violation(
                    Invariant::BallCount,
                    Some(ball),
                    at,
                    "a ball_pocket event leaves the ball unpocketed".to_owned(),
                ));
            }
            pocketed[ball] = true;
            pocket_events[ball] += 1;
        }
        for (k_ball, (i, s)) in record.balls().enumerate() {
            if s.s == MotionState::Pocketed && !pocketed[i] {
                return Err(violation(
                    Invariant::BallCount,
                    Some(i),
                    at,
                    format!("{e:?} pockets the ball without a ball_pocket event"),
                ));
            }
            if s.s != MotionState::Pocketed
                && let Err(why) = check_in_play(table, r, s.r)
            {
                let why = format!("after {}: {why}", e.kind.name());
                // the kiss (Q1) of a ball–ball event pushed a ball that was in play into
                // a cushion: pooltool's make_kiss moves the pair apart without looking at
                // the cushions (FUZZING.md, findings 13 and 33)
                if e.kind == EventKind::BallBall
                    && let Some(before) = involved_before.get(k_ball)
                    && check_in_play(table, r, before.r).is_ok()
                    && (s.r - before.r).norm() <= KISS_REACH
                {
                    return Err(violation(
                        Invariant::RailTunnel,
                        Some(i),
                        at,
                        format!(
                            "{why}; the kiss of this ball–ball event (Q1: pooltool's \
                             make_kiss moves the pair apart without looking at the \
                             cushions) moved it {:.3e} m, from where it was in play into \
                             the cushion",
                            (s.r - before.r).norm()
                        ),
                    ));
                }
                return Err(off_table(i, &tunnel, at, why));
            }
        }
        // a ball back off a cushion is no longer going through one; a ball that touches
        // one moving into it is (Q6)
        for (i, s) in record.balls() {
            let cushion = matches!(
                e.kind,
                EventKind::BallLinearCushion | EventKind::BallCircularCushion
            );
            if cushion && i == ball {
                tunnel[i] = None;
            }
            if tunnel[i].is_none() {
                tunnel[i] = touching_into_cushion(table, params, s).map(|c| (c, Some(k)));
            }
        }
        // (e) energy
        let after = total_energy(&cur, params);
        if !is_strike && after > energy {
            margins.energy_growth = margins.energy_growth.max((after - energy) / energy);
        }
        if !is_strike {
            let q2 = if e.kind == EventKind::BallBall {
                momentum_steal_energy(&record.states, params)
            } else {
                0.0
            };
            let allowed = energy * (1.0 + ENERGY_REL_TOLERANCE) + ENERGY_ABS_TOLERANCE + q2;
            if after > allowed || !after.is_finite() {
                return Err(violation(
                    Invariant::Energy,
                    Some(ball),
                    at,
                    format!(
                        "{}: total kinetic energy {after:e} J after it, {energy:e} J after \
                         the previous event ({before:e} J just before it; relative growth \
                         {:e}); the balls involved before it {involved_before:?}, after it \
                         {:?}",
                        e.kind.name(),
                        (after - energy) / energy,
                        record.states
                    ),
                ));
            }
        }
        energy = after;
    }
    // the replay gives the final balls
    for (i, (replayed, end)) in cur.iter().zip(run.end).enumerate() {
        let pairs = [
            (replayed.r.x, end.r.x),
            (replayed.r.y, end.r.y),
            (replayed.v.x, end.v.x),
            (replayed.v.y, end.v.y),
            (replayed.w.x, end.w.x),
            (replayed.w.y, end.w.y),
            (replayed.w.z, end.w.z),
        ];
        for (a, b) in pairs {
            margins.replay_error = margins.replay_error.max((a - b).abs());
        }
        let same = replayed.s == end.s && pairs.iter().all(|&(a, b)| near(a, b));
        if !same {
            return rec(
                Some(i),
                None,
                format!("the events replay to {replayed:?}, the run ends with {end:?}"),
            );
        }
    }
    // (a) pockets: each ball pocketed during the shot by exactly one event
    for (i, ((start, end), &count)) in run
        .start
        .iter()
        .zip(run.end)
        .zip(&pocket_events)
        .enumerate()
    {
        let was = start.s == MotionState::Pocketed;
        let is = end.s == MotionState::Pocketed;
        if was && !is {
            return Err(violation(
                Invariant::BallCount,
                Some(i),
                None,
                "pocketed at the start, back on the table at the end".to_owned(),
            ));
        }
        if is != (was || count == 1) || count > 1 {
            return Err(violation(
                Invariant::BallCount,
                Some(i),
                None,
                format!("{count} ball_pocket events; pocketed at the start {was}, at the end {is}"),
            ));
        }
    }
    // (c) on the table at the end
    for (i, b) in run.end.iter().enumerate() {
        if b.s != MotionState::Pocketed
            && let Err(why) = check_in_play(table, r, b.r)
        {
            return Err(off_table(i, &tunnel, None, format!("at the end: {why}")));
        }
    }
    // (b) no overlap at the end of a run that came to rest (a cut run ends mid-shot, where
    // moving balls may overlap: pooltool resolves an overlap at once, Q3; the `event_loop`
    // target saw 3.6 µm in a chattering cluster cut at its event cap)
    let depth = |a: &BallState, b: &BallState| {
        let (dx, dy) = (a.r.x - b.r.x, a.r.y - b.r.y);
        2.0 * r - (dx * dx + dy * dy).sqrt()
    };
    for j in 0..n {
        for i in 0..j {
            let (a, b) = (&run.end[i], &run.end[j]);
            if a.s == MotionState::Pocketed || b.s == MotionState::Pocketed {
                continue;
            }
            let d = depth(a, b);
            if run.outcome.cut.is_some() {
                continue;
            }
            margins.deepest_overlap = margins.deepest_overlap.max(d);
            if d <= END_OVERLAP_TOLERANCE {
                continue;
            }
            // a pair that never moved keeps the overlap it started with
            let still = a.r == run.start[i].r && b.r == run.start[j].r;
            if still && d <= depth(&run.start[i], &run.start[j]) {
                continue;
            }
            return Err(violation(
                Invariant::Overlap,
                Some(j),
                None,
                format!("balls {i} and {j} overlap by {d:e} m at the end"),
            ));
        }
    }
    // (f) at rest, or cut and saying why
    match run.outcome.cut {
        None => {
            for (i, b) in run.end.iter().enumerate() {
                let rest = b.s == MotionState::Pocketed
                    || (b.s == MotionState::Stationary
                        && b.v.dot(b.v) == 0.0
                        && b.w.dot(b.w) == 0.0);
                if !rest {
                    return Err(violation(
                        Invariant::NotAtRest,
                        Some(i),
                        None,
                        format!("the run was not cut, but the ball ends as {b:?}"),
                    ));
                }
            }
        }
        Some(Cut::MaxEvents) => {
            if run.events.len() != run.limits.max_events {
                return rec(
                    None,
                    None,
                    format!(
                        "cut at the event limit {} after {} events",
                        run.limits.max_events,
                        run.events.len()
                    ),
                );
            }
        }
        Some(Cut::MaxTime) => {
            if !run.limits.max_time.is_finite() {
                return rec(
                    None,
                    None,
                    "cut at the time limit, but there is none".to_owned(),
                );
            }
        }
    }
    Ok(margins)
}
