//! The per-table event loop (spec §3; `evolution/event_based/simulate.py: simulate`,
//! `_SimulationState.step`, `get_next_event`, `get_event_priority`; `cache.py`).
//!
//! Each step: gather one candidate per category (stick, transition, ball–ball, circular
//! cushion, linear cushion, pocket) from the caches, filling missing entries from the
//! current states first; take the earliest, breaking exact ties by (tier, −energy) and then
//! category order; evolve every ball to its time; resolve it; re-stamp and re-cache only
//! the balls involved. The caches are flat arrays allocated once per table ([`EventLoop`]);
//! nothing is allocated per event, and the loop is bounded by [`Limits`].
//!
//! pooltool's quirks copied here because event sequences depend on them: Q1 (the spacer,
//! in the resolvers), Q2 (the momentum fix), Q3 (overlap = now, in detection), Q9, Q10,
//! Q13 (in the resolvers and evolution), Q14 (ties), Q17 (a transition's agent is stamped
//! `t + (T − t)`).

use crate::error::{InputError, SimError};
use crate::model::ball_state::{BallState, ball_energy};
use crate::model::sim_params::SimParams;
use crate::model::table::Table;
#[cfg(test)]
use crate::model::vec3::Vec3;
use crate::model::{MotionState, Vec2};
use crate::motion::evolve::{TransitionKind, evolve, next_transition};
use crate::motion::trajectory::{Path, trajectory};
use crate::query::ball_ball::{RelPath, ball_ball_rules, ball_ball_time_on, cannot_meet};
use crate::query::ball_circle::circle_crossing;
use crate::query::ball_cushion::linear_cushion_time_on;
use crate::query::bounds::{
    PathBox, box_outside_circle, box_outside_extent, boxes_apart, path_box,
};
use crate::resolve::ball_ball::resolve_ball_ball;
use crate::resolve::ball_cushion::{resolve_circular_cushion, resolve_linear_cushion};
use crate::resolve::ball_pocket::resolve_pocket;
use crate::resolve::stick_ball::{CueStrike, cue_strike};
use crate::resolve::transition::resolve_transition;
use crate::simulate::cache::{
    RowBest, Slot, earliest, earliest_row, insertion_stamp, pair_at, pair_index,
};
use crate::simulate::events::{Cut, Event, EventKind, NO_AGENT, Outcome};

/// The most balls one table may hold (the caches grow with its square).
pub const MAX_BALLS: usize = 64;

/// Bounds on one table's simulation. The defaults never cut a real shot (the reference
/// set's longest has 1,108 events and lasts 17 s; pooltool has no bounds by default).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// The most events reported, the strike included.
    pub max_events: usize,
    /// The latest simulated time in s an event may have.
    pub max_time: f64,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_events: 200_000,
            max_time: 3600.0,
        }
    }
}

impl Limits {
    /// The limits a user asked for, checked by the one rule every entry point (the CLI's
    /// `--max-events`/`--max-time`, Python's `max_events=`/`max_time=`, a study) applies:
    /// `max_events` at least 1 (the strike is an event; a count beyond `usize` means no
    /// cap), `max_time` greater than 0 s — `inf` means no time limit, NaN is refused.
    ///
    /// The error names the value and the rule, in the same words for every entry point.
    pub fn new(max_events: u64, max_time: f64) -> Result<Limits, InputError> {
        let limits = Limits {
            max_events: usize::try_from(max_events).unwrap_or(usize::MAX),
            max_time,
        };
        limits.check()?;
        Ok(limits)
    }

    /// Checks these limits by [`Limits::new`]'s rule.
    pub fn check(&self) -> Result<(), InputError> {
        if self.max_events == 0 {
            return Err(InputError::new(
                "max_events 0: it must be at least 1 (the strike is an event)",
            ));
        }
        if self.max_time.is_nan() || self.max_time <= 0.0 {
            return Err(InputError::new(format!(
                "max_time {}: it must be greater than 0 s (inf: no time limit)",
                self.max_time
            )));
        }
        Ok(())
    }
}

/// Category order, which breaks ties of equal (tier, energy) (spec §3).
const CATEGORIES: usize = 6;

/// One category's earliest candidate.
#[derive(Clone, Copy, Debug)]
struct Candidate {
    t: f64,
    tier: u32,
    energy: f64,
    event: Event,
}

/// The simulation state of one table: balls, caches, clock. Build it once per table
/// ([`EventLoop::new`]), start a shot with [`EventLoop::reset`], then call
/// [`EventLoop::step`] until it returns `None`.
#[derive(Clone, Debug)]
pub struct EventLoop<'a> {
    table: &'a Table,
    params: SimParams,
    limits: Limits,
    balls: Vec<BallState>,
    transitions: Vec<(f64, TransitionKind)>,
    pairs: Vec<Slot>,
    /// Per ball, the earliest of its straight-cushion entries (see [`RowBest`]).
    linear: Vec<RowBest>,
    /// Per ball, the earliest of its jaw entries.
    circular: Vec<RowBest>,
    /// Per ball, the earliest of its pocket entries.
    pockets: Vec<RowBest>,
    /// Each ball's path at the current time and its box, valid where `path_fresh` has
    /// the ball's bit (cleared when the clock moves or the ball changes).
    paths: Vec<(Path, PathBox)>,
    path_fresh: u64,
    strike: Option<(usize, CueStrike)>,
    stick: Slot,
    t: f64,
    n_events: usize,
    cut: Option<Cut>,
    done: bool,
}

impl<'a> EventLoop<'a> {
    /// A loop for up to `n_balls` balls on `table` (validates the parameters).
    pub fn new(
        table: &'a Table,
        params: SimParams,
        limits: Limits,
        n_balls: usize,
    ) -> Result<Self, SimError> {
        params.validate()?;
        if n_balls > MAX_BALLS {
            return Err(SimError::Ball {
                index: n_balls,
                reason: format!("at most {MAX_BALLS} balls per table"),
            });
        }
        let n = n_balls;
        Ok(EventLoop {
            table,
            params,
            limits,
            balls: Vec::with_capacity(n),
            transitions: Vec::with_capacity(n),
            pairs: Vec::with_capacity(n * n.saturating_sub(1) / 2),
            linear: Vec::with_capacity(n),
            circular: Vec::with_capacity(n),
            pockets: Vec::with_capacity(n),
            paths: Vec::with_capacity(n),
            path_fresh: 0,
            strike: None,
            stick: Slot::MISSING,
            t: 0.0,
            n_events: 0,
            cut: None,
            done: false,
        })
    }

    /// The checks [`EventLoop::reset`] makes of a shot's input, alone: at most
    /// [`MAX_BALLS`] balls, every number finite, and a valid strike on a ball that exists.
    /// (A host that lays tables out for the GPU runs them without a loop.)
    pub fn check_input(
        balls: &[BallState],
        strike: Option<(usize, CueStrike)>,
    ) -> Result<(), SimError> {
        check_balls(balls)?;
        if let Some((cue, s)) = strike {
            s.validate()?;
            if cue >= balls.len() {
                return Err(SimError::Strike(format!(
                    "cue ball index {cue} out of range"
                )));
            }
        }
        Ok(())
    }

    /// Replaces the parameters (for the next [`EventLoop::reset`]: a batch with per-table
    /// physics); checked as [`EventLoop::new`] checks them.
    pub fn set_params(&mut self, params: SimParams) -> Result<(), SimError> {
        if params != self.params {
            params.validate()?;
            self.params = params;
        }
        Ok(())
    }

    /// The parameters in use.
    pub fn params(&self) -> &SimParams {
        &self.params
    }

    /// Starts a shot: the balls (in pooltool's ball order, reference time 0) and the cue
    /// strike on ball `strike.0`, if any. The strike happens at t = 0 only if every ball
    /// is at rest (zero energy) and V0 > 0, as in pooltool. Errors on a bad ball or strike
    /// or too many balls; nothing is allocated beyond the capacity given to `new` unless
    /// more balls come.
    pub fn reset(
        &mut self,
        balls: &[BallState],
        strike: Option<(usize, CueStrike)>,
    ) -> Result<(), SimError> {
        Self::check_input(balls, strike)?;
        let n = balls.len();
        self.balls.clear();
        self.balls
            .extend(balls.iter().map(|b| BallState { t: 0.0, ..*b }));
        self.transitions.clear();
        for b in &self.balls {
            let next = next_transition(b, &self.params.ball);
            let entry = next.map_or((f64::INFINITY, TransitionKind::SlidingRolling), |x| x);
            self.transitions.push(entry);
        }
        self.pairs.clear();
        self.pairs
            .resize(n * n.saturating_sub(1) / 2, Slot::MISSING);
        for rows in [&mut self.linear, &mut self.circular, &mut self.pockets] {
            rows.clear();
            rows.resize(n, RowBest::MISSING);
        }
        let still = (Path::still(Vec2::ZERO), path_box(&Path::still(Vec2::ZERO)));
        self.paths.clear();
        self.paths.resize(n, still);
        self.path_fresh = 0;
        self.strike = strike;
        self.stick = Slot::MISSING;
        self.t = 0.0;
        self.n_events = 0;
        self.cut = None;
        self.done = false;
        Ok(())
    }

    /// The balls' current states (at the time of the last event).
    pub fn balls(&self) -> &[BallState] {
        &self.balls
    }

    /// The current time: that of the last event.
    pub fn time(&self) -> f64 {
        self.t
    }

    /// How the simulation ended so far (meaningful once `step` returned `None`).
    pub fn outcome(&self) -> Outcome {
        Outcome {
            n_events: self.n_events,
            t_end: self.t,
            cut: self.cut,
        }
    }

    /// Runs one event: returns it, or `None` once every candidate is `∞` (every ball at
    /// rest or pocketed) or a limit was reached (see [`EventLoop::outcome`]).
    pub fn step(&mut self) -> Option<Event> {
        if self.done {
            return None;
        }
        if self.n_events >= self.limits.max_events {
            return self.stop(Some(Cut::MaxEvents));
        }
        let cands = self.candidates();
        let Some(winner) = choose(&cands) else {
            return self.stop(None);
        };
        if winner.t == f64::INFINITY {
            return self.stop(None);
        }
        if winner.t > self.limits.max_time {
            return self.stop(Some(Cut::MaxTime));
        }
        let ev = winner.event;
        self.advance(ev.t);
        self.resolve(&ev);
        self.n_events += 1;
        Some(ev)
    }

    fn stop(&mut self, cut: Option<Cut>) -> Option<Event> {
        self.done = true;
        self.cut = cut;
        None
    }

    /// Evolves every ball from the current time to `t_next` (closed forms, labels kept).
    fn advance(&mut self, t_next: f64) {
        let dt = t_next - self.t;
        let p = &self.params.ball;
        for b in &mut self.balls {
            *b = evolve(b, dt, p);
        }
        self.path_fresh = 0;
    }

    /// Ball `i`'s path from its current state and the box it stays in (computed once
    /// per ball and time).
    fn path(&mut self, i: usize) -> (Path, PathBox) {
        if self.path_fresh & (1 << i) == 0 {
            let path = trajectory(&self.balls[i], &self.params.ball);
            self.paths[i] = (path, path_box(&path));
            self.path_fresh |= 1 << i;
        }
        self.paths[i]
    }
}

/// Checks the balls a shot starts from: at most [`MAX_BALLS`], every number finite.
fn check_balls(balls: &[BallState]) -> Result<(), SimError> {
    if balls.len() > MAX_BALLS {
        return Err(SimError::Ball {
            index: balls.len(),
            reason: format!("at most {MAX_BALLS} balls per table"),
        });
    }
    for (index, b) in balls.iter().enumerate() {
        if !(b.r.is_finite() && b.v.is_finite() && b.w.is_finite()) {
            return Err(SimError::Ball {
                index,
                reason: "non-finite position, velocity or spin".to_owned(),
            });
        }
    }
    Ok(())
}

/// The winner among the categories' candidates (spec §3): the earliest time; of exact
/// ties the smallest (tier, −energy), then the earlier category.
fn choose(cands: &[Option<Candidate>; CATEGORIES]) -> Option<Candidate> {
    let mut best: Option<Candidate> = None;
    for c in cands.iter().flatten() {
        let better = match best {
            None => true,
            Some(b) => {
                c.t < b.t
                    || (c.t == b.t
                        && (c.tier < b.tier || (c.tier == b.tier && c.energy > b.energy)))
            }
        };
        if better {
            best = Some(*c);
        }
    }
    best
}

impl EventLoop<'_> {
    /// One candidate per category, missing cache entries filled first.
    fn candidates(&mut self) -> [Option<Candidate>; CATEGORIES] {
        [
            self.stick_candidate(),
            self.transition_candidate(),
            self.ball_ball_candidate(),
            self.circular_candidate(),
            self.linear_candidate(),
            self.pocket_candidate(),
        ]
    }

    fn energy(&self, i: usize) -> f64 {
        ball_energy(&self.balls[i], &self.params.ball)
    }

    /// The insertion stamp of the entry at `index` of a category filled in this step:
    /// pooltool's dict order within the category (see [`crate::simulate::cache`]).
    fn stamp(&self, index: usize) -> u64 {
        insertion_stamp(self.n_events, index)
    }

    /// The stick–ball candidate: time 0 at t = 0 with the system at rest and V0 > 0,
    /// else ∞ (only offered at t = 0; tier 1, energy V0²).
    fn stick_candidate(&mut self) -> Option<Candidate> {
        let (cue, s) = self.strike?;
        if self.t != 0.0 {
            return None;
        }
        if self.stick.is_missing() {
            let at_rest = (0..self.balls.len()).all(|i| self.energy(i) == 0.0);
            let t = if at_rest && s.v0 > 0.0 {
                0.0
            } else {
                f64::INFINITY
            };
            let seq = self.stamp(0);
            self.stick = Slot { t, seq };
        }
        let event = Event {
            kind: EventKind::StickBall,
            t: self.stick.t,
            ball: cue as u32,
            other: NO_AGENT,
        };
        Some(Candidate {
            t: self.stick.t,
            tier: 1,
            energy: s.v0 * s.v0,
            event,
        })
    }

    /// The earliest transition (ties: ball order, as pooltool's dict keeps its keys).
    fn transition_candidate(&mut self) -> Option<Candidate> {
        let mut best: Option<usize> = None;
        for (i, (t, _)) in self.transitions.iter().enumerate() {
            if best.is_none_or(|b| *t < self.transitions[b].0) {
                best = Some(i);
            }
        }
        let i = best?;
        let (t, kind) = self.transitions[i];
        let kind = match kind {
            TransitionKind::SlidingRolling => EventKind::SlidingRolling,
            TransitionKind::RollingSpinning => EventKind::RollingSpinning,
            TransitionKind::RollingStationary => EventKind::RollingStationary,
            TransitionKind::SpinningStationary => EventKind::SpinningStationary,
        };
        let event = Event {
            kind,
            t,
            ball: i as u32,
            other: NO_AGENT,
        };
        Some(Candidate {
            t,
            tier: 2,
            energy: self.energy(i),
            event,
        })
    }
}

impl EventLoop<'_> {
    /// Fills the missing pair entries (combinations order) as `t + τ`.
    fn fill_pairs(&mut self) {
        let n = self.balls.len();
        let mut k = 0;
        for i in 0..n {
            for j in i + 1..n {
                if self.pairs[k].is_missing() {
                    let tau = self.pair_time(i, j);
                    let seq = self.stamp(k);
                    self.pairs[k] = Slot {
                        t: self.t + tau,
                        seq,
                    };
                }
                k += 1;
            }
        }
    }

    /// τ until balls `i < j` collide ([`crate::query::ball_ball::ball_ball_time`]), with
    /// the paths computed once per ball and pairs whose boxes stay apart skipped.
    ///
    /// The box test comes before the overlap rule (Q3): boxes farther apart than `2R`
    /// hold centres farther apart than `2R` at τ = 0 too, so the rule would not fire.
    fn pair_time(&mut self, i: usize, j: usize) -> f64 {
        let r = self.params.ball.r;
        let (bi, bj) = (&self.balls[i], &self.balls[j]);
        let pocketed = bi.s == MotionState::Pocketed || bj.s == MotionState::Pocketed;
        if pocketed || !(bi.translating() || bj.translating()) {
            return f64::INFINITY;
        }
        let (pi, box_i) = self.path(i);
        let (pj, box_j) = self.path(j);
        if boxes_apart(&box_i, &box_j, 2.0 * r) {
            return f64::INFINITY;
        }
        match ball_ball_rules(&self.balls[i], &self.balls[j], r) {
            Some(tau) => tau,
            None => ball_ball_time_on(&pi, &pj, r),
        }
    }

    /// The earliest ball–ball collision (tier 3, energy |v1 − v2|²).
    fn ball_ball_candidate(&mut self) -> Option<Candidate> {
        self.fill_pairs();
        let (k, t) = earliest(&self.pairs)?;
        let (i, j) = pair_at(k, self.balls.len());
        let dv = self.balls[i].v - self.balls[j].v;
        let event = Event {
            kind: EventKind::BallBall,
            t,
            ball: i as u32,
            other: j as u32,
        };
        Some(Candidate {
            t,
            tier: 3,
            energy: dv.dot(dv),
            event,
        })
    }

    /// Fills the missing rows of one ball–table category: every item of the ball, in
    /// table order, gets its time `t + τ` and an insertion stamp; the row keeps the
    /// earliest (of equal times the first). A ball that does not translate meets nothing.
    /// (The shader's `fill_rows` and `merge_rows` split a row's items over the workgroup's
    /// threads and merge the parts, of equal times the lower item: the same rows.)
    fn fill_items(&mut self, which: Items) {
        let n_items = self.n_items(which);
        for i in 0..self.balls.len() {
            if !self.rows(which)[i].slot.is_missing() {
                continue;
            }
            let moving = self.balls[i].translating();
            let (path, bx) = if moving { self.path(i) } else { self.paths[i] };
            let mut best = RowBest::MISSING;
            for m in 0..n_items {
                let tau = match moving {
                    true => self.item_time(which, m, &path, &bx),
                    false => f64::INFINITY,
                };
                let slot = Slot {
                    t: self.t + tau,
                    seq: self.stamp(i * n_items + m),
                };
                if m == 0 || slot.t < best.slot.t {
                    best = RowBest {
                        slot,
                        item: m as u32,
                    };
                }
            }
            self.rows_mut(which)[i] = best;
        }
    }

    /// τ until a translating ball on `path` (box `bx`) meets item `m` of a category, or
    /// `∞`; items its box keeps clear of are skipped (see [`crate::query::bounds`]).
    fn item_time(&self, which: Items, m: usize, path: &Path, bx: &PathBox) -> f64 {
        let (r, tb) = (self.params.ball.r, self.table);
        let circle = |c: crate::model::vec3::Vec3, rho: f64| {
            let center = Vec2::new(c.x, c.y);
            if box_outside_circle(bx, center, rho) || circle_out_of_reach(path, center, rho) {
                return f64::INFINITY;
            }
            circle_crossing(path, center, rho)
        };
        match which {
            Items::Linear => match box_outside_extent(bx, &tb.linear[m]) {
                true => f64::INFINITY,
                false => linear_cushion_time_on(path, &tb.linear[m], r),
            },
            Items::Circular => circle(tb.circular[m].center, tb.circular[m].radius + r),
            Items::Pocket => circle(tb.pockets[m].center, tb.pockets[m].radius),
        }
    }

    fn n_items(&self, which: Items) -> usize {
        match which {
            Items::Linear => self.table.linear.len(),
            Items::Circular => self.table.circular.len(),
            Items::Pocket => self.table.pockets.len(),
        }
    }

    fn rows(&self, which: Items) -> &[RowBest] {
        match which {
            Items::Linear => &self.linear,
            Items::Circular => &self.circular,
            Items::Pocket => &self.pockets,
        }
    }

    fn rows_mut(&mut self, which: Items) -> &mut [RowBest] {
        match which {
            Items::Linear => &mut self.linear,
            Items::Circular => &mut self.circular,
            Items::Pocket => &mut self.pockets,
        }
    }

    /// The earliest event of one ball–table category, `(kind, tier)` as given.
    fn item_candidate(&mut self, which: Items, kind: EventKind, tier: u32) -> Option<Candidate> {
        if self.n_items(which) == 0 {
            return None;
        }
        self.fill_items(which);
        let (i, best) = earliest_row(self.rows(which))?;
        let t = best.slot.t;
        let event = Event {
            kind,
            t,
            ball: i as u32,
            other: best.item,
        };
        Some(Candidate {
            t,
            tier,
            energy: self.energy(i),
            event,
        })
    }

    fn circular_candidate(&mut self) -> Option<Candidate> {
        self.item_candidate(Items::Circular, EventKind::BallCircularCushion, 3)
    }

    fn linear_candidate(&mut self) -> Option<Candidate> {
        self.item_candidate(Items::Linear, EventKind::BallLinearCushion, 3)
    }

    fn pocket_candidate(&mut self) -> Option<Candidate> {
        self.item_candidate(Items::Pocket, EventKind::BallPocket, 2)
    }
}

/// Whether a translating path provably stays farther than `rho` from `center` within its
/// horizon: the pair solver's hull test ([`cannot_meet`]) on the path relative to the
/// circle's centre, with the reach `2 · (rho/2)`. Conservative, as for ball pairs.
fn circle_out_of_reach(path: &Path, center: Vec2, rho: f64) -> bool {
    let rel = RelPath {
        a: path.a,
        b: path.b,
        c: path.c - center,
    };
    cannot_meet(&rel, 0.5 * rho, path.horizon)
}

/// The three ball–table categories.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Items {
    Linear,
    Circular,
    Pocket,
}

impl EventLoop<'_> {
    /// Applies event `ev` (the balls already evolved to its time), then re-stamps,
    /// re-caches the transitions of, and invalidates the entries of the balls involved.
    fn resolve(&mut self, ev: &Event) {
        let (p, rp, tb) = (&self.params.ball, &self.params.resolver, self.table);
        let i = ev.ball as usize;
        let m = ev.other as usize;
        let b = self.balls[i];
        // Q17: a transition's agent is stamped t + (T − t), a collision's T
        let stamp = if ev.kind.is_transition() {
            self.t + (ev.t - self.t)
        } else {
            ev.t
        };
        let new = match ev.kind {
            EventKind::StickBall => {
                // the strike happens once: a V0 so small (1e-300 m/s) that the struck
                // ball's energy rounds to 0 left the table "at rest" at t = 0, and the
                // strike was offered again and again to the event cap (the `event_loop`
                // fuzz target's finding 14, FUZZING.md; the GPU's host strikes once too)
                let s = self.strike.take().map(|(_, s)| s);
                s.map_or(b, |s| cue_strike(&b, &s, p, &self.params.cue))
            }
            EventKind::BallBall => {
                let (n1, n2) = resolve_ball_ball(&b, &self.balls[m], p, rp);
                self.balls[m] = BallState { t: stamp, ..n2 };
                n1
            }
            EventKind::BallLinearCushion => resolve_linear_cushion(&b, &tb.linear[m], p, rp),
            EventKind::BallCircularCushion => resolve_circular_cushion(&b, &tb.circular[m], p, rp),
            EventKind::BallPocket => resolve_pocket(&b, &tb.pockets[m]),
            _ => resolve_transition(&b, self.transitions[i].1),
        };
        self.balls[i] = BallState { t: stamp, ..new };
        self.t = ev.t;
        self.involve(i);
        if ev.kind == EventKind::BallBall {
            self.involve(m);
        }
    }

    /// Ball `i` took part in the last event: its next transition is recomputed from its
    /// new state and every cached entry that names it is deleted.
    fn involve(&mut self, i: usize) {
        let b = &self.balls[i];
        let next = next_transition(b, &self.params.ball);
        self.transitions[i] = next.map_or(
            (f64::INFINITY, TransitionKind::SlidingRolling),
            |(tau, k)| (b.t + tau, k),
        );
        let n = self.balls.len();
        for j in 0..n {
            if j != i {
                let k = pair_index(i.min(j), i.max(j), n);
                self.pairs[k] = Slot::MISSING;
            }
        }
        for rows in [&mut self.linear, &mut self.circular, &mut self.pockets] {
            rows[i] = RowBest::MISSING;
        }
        self.path_fresh &= !(1 << i);
        if self.strike.is_some_and(|(cue, _)| cue == i) {
            self.stick = Slot::MISSING;
        }
    }
}

/// Simulates one shot from `balls` with `strike` on `table` to the end, calling
/// `on_event` with every event and the balls' states right after it. Returns how the
/// table ended. Convenience over [`EventLoop`] (one loop per call).
pub fn simulate(
    table: &Table,
    params: SimParams,
    limits: Limits,
    balls: &[BallState],
    strike: Option<(usize, CueStrike)>,
    mut on_event: impl FnMut(&Event, &[BallState]),
) -> Result<Outcome, SimError> {
    let mut lp = EventLoop::new(table, params, limits, balls.len())?;
    lp.reset(balls, strike)?;
    while let Some(ev) = lp.step() {
        on_event(&ev, lp.balls());
    }
    Ok(lp.outcome())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg64Mcg;

    fn run(
        balls: &[BallState],
        strike: CueStrike,
        limits: Limits,
    ) -> (Vec<Event>, Outcome, Vec<BallState>) {
        let table = Table::nine_foot();
        let mut lp = EventLoop::new(&table, SimParams::default(), limits, balls.len()).unwrap();
        lp.reset(balls, Some((0, strike))).unwrap();
        let mut events = Vec::new();
        while let Some(e) = lp.step() {
            events.push(e);
        }
        (events, lp.outcome(), lp.balls().to_vec())
    }

    fn straight(v0: f64, b: f64) -> CueStrike {
        CueStrike {
            v0,
            phi: 90.0,
            theta: 0.0,
            a: 0.0,
            b,
        }
    }

    #[test]
    fn stun_shot_into_a_ball_stops_the_cue_ball() {
        let r = SimParams::default().ball.r;
        let balls = [
            BallState::at_rest(0.635, 0.6, r),
            BallState::at_rest(0.635, 0.9, r),
        ];
        let (events, out, end) = run(&balls, straight(1.0, 0.0), Limits::default());
        let kinds: Vec<_> = events.iter().map(|e| e.kind).collect();
        assert_eq!(kinds[0], EventKind::StickBall);
        // the cue ball (1.54 m/s) is still sliding when it meets the object ball
        assert_eq!(
            (kinds[1], events[1].ball, events[1].other),
            (EventKind::BallBall, 0, 1)
        );
        // the object ball goes on to the foot rail (segment "9", index 5)
        let rail = events
            .iter()
            .find(|e| e.kind == EventKind::BallLinearCushion)
            .unwrap();
        assert_eq!((rail.ball, rail.other), (1, 5));
        assert!(out.cut.is_none());
        assert!(
            end.iter()
                .all(|b| matches!(b.s, MotionState::Stationary | MotionState::Pocketed))
        );
        // times never decrease
        assert!(events.windows(2).all(|w| w[0].t <= w[1].t));
        assert_eq!(out.t_end, events.last().unwrap().t);
    }

    #[test]
    fn a_shot_down_the_rail_is_pocketed() {
        let r = SimParams::default().ball.r;
        // along the left rail's centre line into the top-left corner pocket... aimed at it
        let start = (0.3, 2.2);
        let pocket = Table::nine_foot().pockets[2].center;
        let phi = (pocket.y - start.1).atan2(pocket.x - start.0).to_degrees();
        let strike = CueStrike {
            v0: 2.0,
            phi,
            theta: 0.0,
            a: 0.0,
            b: 0.0,
        };
        let (events, _, end) = run(
            &[BallState::at_rest(start.0, start.1, r)],
            strike,
            Limits::default(),
        );
        let last_collision = events
            .iter()
            .rev()
            .find(|e| !e.kind.is_transition())
            .unwrap();
        assert_eq!(last_collision.kind, EventKind::BallPocket);
        assert_eq!(end[0].s, MotionState::Pocketed);
        assert_eq!(end[0].r.z, -0.08);
    }

    #[test]
    fn limits_cut_a_table_and_say_so() {
        let r = SimParams::default().ball.r;
        let balls = [
            BallState::at_rest(0.635, 0.6, r),
            BallState::at_rest(0.635, 0.9, r),
        ];
        let few = Limits {
            max_events: 3,
            ..Limits::default()
        };
        let (events, out, _) = run(&balls, straight(2.0, 0.3), few);
        assert_eq!((events.len(), out.cut), (3, Some(Cut::MaxEvents)));
        let short = Limits {
            max_time: 0.05,
            ..Limits::default()
        };
        let (events, out, _) = run(&balls, straight(2.0, 0.3), short);
        assert_eq!(out.cut, Some(Cut::MaxTime));
        assert!(events.iter().all(|e| e.t <= 0.05));
    }

    #[test]
    fn equal_transition_times_go_to_the_first_ball() {
        // two identical rolling balls far apart: their transitions tie exactly
        let r = SimParams::default().ball.r;
        let roll = |x: f64| BallState {
            v: Vec3::new(0.0, 0.5, 0.0),
            w: Vec3::new(-0.5 / r, 0.0, 0.0),
            s: MotionState::Rolling,
            ..BallState::at_rest(x, 0.5, r)
        };
        let table = Table::nine_foot();
        let mut lp = EventLoop::new(&table, SimParams::default(), Limits::default(), 2).unwrap();
        lp.reset(&[roll(0.3), roll(0.9)], None).unwrap();
        let first = lp.step().unwrap();
        let second = lp.step().unwrap();
        assert_eq!((first.kind, first.ball), (EventKind::RollingStationary, 0));
        assert_eq!((second.ball, second.t), (1, first.t));
        assert!(lp.step().is_none());
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        let table = Table::nine_foot();
        let r = SimParams::default().ball.r;
        assert!(
            EventLoop::new(
                &table,
                SimParams::default(),
                Limits::default(),
                MAX_BALLS + 1
            )
            .is_err()
        );
        let mut lp = EventLoop::new(&table, SimParams::default(), Limits::default(), 1).unwrap();
        let nan = BallState::at_rest(f64::NAN, 0.5, r);
        assert!(lp.reset(&[nan], None).is_err());
        let ok = BallState::at_rest(0.5, 0.5, r);
        assert!(lp.reset(&[ok], Some((3, straight(1.0, 0.0)))).is_err());
        assert!(lp.reset(&[ok], Some((0, straight(1.0, 1.5)))).is_err());
        let mut bad = SimParams::default();
        bad.ball.g = 0.0;
        assert!(EventLoop::new(&table, bad, Limits::default(), 1).is_err());
    }

    /// Random racks and strikes, touching pairs included: every table ends at rest,
    /// uncut, with finite states.
    #[test]
    fn random_shots_end_at_rest() {
        let p = SimParams::default();
        let r = p.ball.r;
        let table = Table::nine_foot();
        let mut rng = Pcg64Mcg::seed_from_u64(0x9e37_79b9_7f4a_7c15);
        let mut lp = EventLoop::new(&table, p, Limits::default(), 12).unwrap();
        for _ in 0..60 {
            let mut balls: Vec<BallState> = Vec::new();
            while balls.len() < 12 {
                let (x, y) = if balls.is_empty() || rng.random_bool(0.7) {
                    (
                        rng.random_range(r + 1e-3..1.27 - r - 1e-3),
                        rng.random_range(r + 1e-3..2.54 - r - 1e-3),
                    )
                } else {
                    // right beside an existing ball, a tiny gap away
                    let o = balls[balls.len() - 1].r;
                    let a: f64 = rng.random_range(0.0..6.3);
                    let d = 2.0 * r + 10f64.powf(rng.random_range(-9.0..-3.0));
                    (o.x + d * a.cos(), o.y + d * a.sin())
                };
                let inside = x > r && x < 1.27 - r && y > r && y < 2.54 - r;
                let clear = balls.iter().all(|b| (b.r.x - x).hypot(b.r.y - y) > 2.0 * r);
                if inside && clear {
                    balls.push(BallState::at_rest(x, y, r));
                }
            }
            let strike = CueStrike {
                v0: rng.random_range(0.5..8.0),
                phi: rng.random_range(0.0..360.0),
                theta: rng.random_range(0.0..30.0),
                a: rng.random_range(-0.5..0.5),
                b: rng.random_range(-0.5..0.5),
            };
            lp.reset(&balls, Some((0, strike))).unwrap();
            let mut n = 0;
            while lp.step().is_some() {
                n += 1;
            }
            assert!(n >= 1);
            assert_eq!(lp.outcome().cut, None);
            for b in lp.balls() {
                assert!(b.r.is_finite() && b.v.is_finite() && b.w.is_finite());
                assert!(matches!(
                    b.s,
                    MotionState::Stationary | MotionState::Pocketed
                ));
            }
        }
    }
}
