//! The study's driver: every sample from its strike to rest (or to the cue ball's first
//! contact) on the simulator's event loop ([`EventLoop`], pooltool 0.6.0's physics), Rayon
//! over samples, one loop per worker, and what each sample came to ([`Sample`]).
//!
//! Per sample the loop runs as `kisstime simulate` runs a table; the driver only watches
//! the events go by: the cue ball's first contact (the first event after the strike that
//! involves it, other than its own sliding → rolling), every `ball_pocket` in order, and
//! the end (the cue ball's final position, the event count, the last event's time, a cut
//! by the event or time cap). With [`Until::FirstContact`] the loop stops at that first
//! contact: the cheaper study of what the cue ball meets first, on the same code.

use rayon::prelude::*;

use super::config::{Noise, StudyConfig};
use super::noise::{noisy_strike, sample_physics};
use crate::error::{Error, InputError, SimError};
use crate::model::sim_params::{BallParams, SimParams};
use crate::motion::evolve::evolve;
use crate::resolve::stick_ball::CueStrike;
use crate::simulate::event_loop::{EventLoop, Limits};
use crate::simulate::events::{Cut, Event, EventKind, Outcome};

/// Samples simulated between two progress reports (memory stays bounded by the results).
pub const CHUNK: usize = 16_384;

/// How far each sample runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Until {
    /// Every ball at rest (or a cap): the full outcome.
    #[default]
    Rest,
    /// The cue ball's first contact: only [`Sample::first`] and what goes with it.
    FirstContact,
}

/// What the cue ball met first (the reference's `first_contact`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FirstContact {
    /// A ball: its index in the study's balls.
    Ball(u32),
    /// A cushion: a straight segment (`circular` false) or a jaw arc, its index in the
    /// table's list.
    Cushion {
        /// Whether it is a jaw arc.
        circular: bool,
        /// The segment's or arc's index.
        index: u32,
    },
    /// A pocket, its index.
    Pocket(u32),
    /// The cue ball stopped (rolling → spinning or stationary, spinning → stationary)
    /// before touching anything.
    Stopped,
    /// No event after the strike involved the cue ball (V0 = 0, or a cap came first).
    Nothing,
}

/// A ball that went into a pocket.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pot {
    /// The ball's index in the study's balls.
    pub ball: u32,
    /// The pocket's index in the table's pockets.
    pub pocket: u32,
    /// When, s after the strike.
    pub t: f64,
}

/// What one sample came to.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    /// The strike it was given.
    pub strike: CueStrike,
    /// What the cue ball met first.
    pub first: FirstContact,
    /// When, s after the strike (NaN for [`FirstContact::Nothing`]).
    pub first_t: f64,
    /// The cue ball's centre then.
    pub contact_cue: (f64, f64),
    /// The cue ball's speed just before, m/s.
    pub contact_speed: f64,
    /// Where it touched: halfway between the centres for a ball, the nearest point of the
    /// segment or jaw for a cushion; NaN otherwise.
    pub contact_point: (f64, f64),
    /// For a ball: the cut angle in degrees, the signed angle from the cue ball's velocity
    /// just before contact to the line of centres (cue ball to object ball): 0 is a full
    /// hit, positive sends the object ball to the left of the cue ball's direction
    /// (counter-clockwise seen from above), ±90 a graze. NaN otherwise.
    pub cut_angle: f64,
    /// The balls pocketed, in order (empty with [`Until::FirstContact`], unless the first
    /// contact was a pocket).
    pub potted: Vec<Pot>,
    /// The cue ball's centre at the end (the pocket's centre if it was potted).
    pub cue_final: (f64, f64),
    /// Events, the strike included (pooltool's count, its two null events left out).
    pub n_events: usize,
    /// The time of the last event, s.
    pub duration: f64,
    /// Why the sample was cut short, if a cap stopped it.
    pub cut: Option<Cut>,
}

impl Sample {
    /// The pocket ball `ball` (an index in the study's balls) went into, if it did.
    pub fn pocket_of(&self, ball: usize) -> Option<usize> {
        self.potted
            .iter()
            .find(|p| p.ball as usize == ball)
            .map(|p| p.pocket as usize)
    }

    /// When ball `ball` was pocketed, if it was.
    pub fn pot_time(&self, ball: usize) -> Option<f64> {
        self.potted
            .iter()
            .find(|p| p.ball as usize == ball)
            .map(|p| p.t)
    }
}

/// How a study runs.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct RunOptions {
    /// How far each sample runs.
    pub until: Until,
    /// The per-sample event and time caps.
    pub limits: Limits,
}

/// Runs the study: `samples` noisy strikes drawn from `seed` ([`noisy_strike`]). See
/// [`run_strikes`].
pub fn run_study(
    config: &StudyConfig,
    sigma: &Noise,
    samples: usize,
    seed: u64,
    options: &RunOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<Sample>, Error> {
    run_samples(config, sigma, seed, 0..samples, options, progress)
}

/// Samples `range` of the study [`run_study`] runs with `seed` (their strikes and physics
/// drawn by their own ids): a part of a study, e.g. a Dask task's. Errors name a sample by
/// its place in `range`.
pub fn run_samples(
    config: &StudyConfig,
    sigma: &Noise,
    seed: u64,
    range: std::ops::Range<usize>,
    options: &RunOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<Sample>, Error> {
    let first = range.start;
    let physics =
        |j: usize| sample_physics(&config.params, &sigma.physics, seed, (first + j) as u64);
    let varies = !sigma.physics.is_empty();
    run_with(
        config,
        range.len(),
        &|j| noisy_strike(config, sigma, seed, (first + j) as u64),
        varies.then_some(&physics as &(dyn Fn(usize) -> SimParams + Sync)),
        options,
        progress,
    )
}

/// Runs the given strikes, in order, without noise. `progress(done, total)` is called
/// after each [`CHUNK`]; the samples come back in input order whatever the thread count.
/// A study whose results would not fit the available memory is refused before it starts
/// ([`Error::TooLarge`]); a strike the simulator refuses (not finite, V0 < 0, a² + b² > 1)
/// is an [`Error::Input`] naming its position.
pub fn run_strikes(
    config: &StudyConfig,
    strikes: &[CueStrike],
    options: &RunOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<Sample>, Error> {
    run_with(
        config,
        strikes.len(),
        &|i| strikes[i],
        None,
        options,
        progress,
    )
}

/// The samples `0..samples`, sample `i` struck `strike(i)` with the physics `physics(i)`
/// (the study's own where `None`).
fn run_with(
    config: &StudyConfig,
    samples: usize,
    strike: &(dyn Fn(usize) -> CueStrike + Sync),
    physics: Option<&(dyn Fn(usize) -> SimParams + Sync)>,
    options: &RunOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<Sample>, Error> {
    let initial = config.initial();
    run_chunks(config, samples, options, progress, |part| {
        (part.start..part.end)
            .into_par_iter()
            .with_min_len(64)
            .map_init(
                || {
                    EventLoop::new(&config.table, config.params, options.limits, initial.len())
                        .expect("checked by run_chunks")
                },
                |lp, i| {
                    if let Some(physics) = physics {
                        lp.set_params(physics(i)).map_err(|e| sample_error(i, e))?;
                    }
                    simulate_sample(lp, config, &initial, strike(i), options.until)
                        .map_err(|e| sample_error(i, e))
                },
            )
            .collect()
    })
}

/// A strike the simulator refuses, as the error of sample `i`.
pub(super) fn sample_error(i: usize, e: SimError) -> Error {
    Error::from(InputError::new(format!("sample {i}: {e}")))
}

/// The samples `0..samples` in chunks of [`CHUNK`], each computed by `chunk(range)`, with
/// `progress` after each (see [`run_chunks_of`]).
pub(super) fn run_chunks(
    config: &StudyConfig,
    samples: usize,
    options: &RunOptions,
    progress: &mut dyn FnMut(usize, usize),
    chunk: impl FnMut(std::ops::Range<usize>) -> Result<Vec<Sample>, Error>,
) -> Result<Vec<Sample>, Error> {
    run_chunks_of(config, samples, CHUNK, options, progress, chunk)
}

/// The samples `0..samples` in chunks of `size`, each computed by `chunk(range)`, with
/// `progress` after each: the study's size checked against the memory first, and the
/// parameters and ball count against the event loop (so that the workers' loops cannot
/// fail).
pub(super) fn run_chunks_of(
    config: &StudyConfig,
    samples: usize,
    size: usize,
    options: &RunOptions,
    progress: &mut dyn FnMut(usize, usize),
    mut chunk: impl FnMut(std::ops::Range<usize>) -> Result<Vec<Sample>, Error>,
) -> Result<Vec<Sample>, Error> {
    crate::limits::check_memory(
        &format!("a study of {samples} samples"),
        (samples as u64).saturating_mul(std::mem::size_of::<Sample>() as u64),
    )?;
    EventLoop::new(
        &config.table,
        config.params,
        options.limits,
        config.initial().len(),
    )?;
    let mut out = Vec::with_capacity(samples);
    let mut first = 0;
    while first < samples {
        let end = samples.min(first + size.max(1));
        out.extend(chunk(first..end)?);
        first = end;
        progress(first, samples);
    }
    Ok(out)
}

/// The cue ball's first contact in `ev`, if `ev` is one (spec of the reference's
/// `first_contact`): ball–ball with the cue ball, a cushion or jaw, a pocket, or the cue
/// ball stopping. The strike and the cue ball's own sliding → rolling are not.
fn first_contact_of(ev: &Event, cue: u32) -> Option<FirstContact> {
    let involves = ev.ball == cue || (ev.kind == EventKind::BallBall && ev.other == cue);
    if !involves {
        return None;
    }
    match ev.kind {
        EventKind::BallBall => Some(FirstContact::Ball(if ev.ball == cue {
            ev.other
        } else {
            ev.ball
        })),
        EventKind::BallLinearCushion => Some(FirstContact::Cushion {
            circular: false,
            index: ev.other,
        }),
        EventKind::BallCircularCushion => Some(FirstContact::Cushion {
            circular: true,
            index: ev.other,
        }),
        EventKind::BallPocket => Some(FirstContact::Pocket(ev.other)),
        EventKind::RollingSpinning
        | EventKind::RollingStationary
        | EventKind::SpinningStationary => Some(FirstContact::Stopped),
        EventKind::StickBall | EventKind::SlidingRolling => None,
    }
}

/// What one sample comes to, built from its events as they go by: the same on the CPU's
/// event loop ([`simulate_sample`]) and on the GPU's (`study::gpu`), which reports each
/// event with the states of its balls right after it.
#[derive(Clone, Debug)]
pub struct SampleWatch {
    cue: usize,
    until: Until,
    /// The sample's ball parameters (the study's, or the sample's own draw).
    ball: BallParams,
    sample: Sample,
    /// Events seen, the strike included.
    seen: usize,
    /// With [`Until::FirstContact`], once the first contact is seen: the events seen then
    /// and the cue ball's centre; later events are ignored.
    stop: Option<(usize, (f64, f64))>,
}

impl SampleWatch {
    /// A watch of `strike` played from `initial` on `config`'s cue ball.
    pub fn new(
        config: &StudyConfig,
        initial: &[crate::model::ball_state::BallState],
        strike: CueStrike,
        until: Until,
    ) -> SampleWatch {
        let cue = config.cue;
        SampleWatch {
            cue,
            until,
            ball: config.params.ball,
            sample: Sample {
                strike,
                first: FirstContact::Nothing,
                first_t: f64::NAN,
                contact_cue: (f64::NAN, f64::NAN),
                contact_speed: f64::NAN,
                contact_point: (f64::NAN, f64::NAN),
                cut_angle: f64::NAN,
                potted: Vec::new(),
                cue_final: (initial[cue].r.x, initial[cue].r.y),
                n_events: 0,
                duration: 0.0,
                cut: None,
            },
            seen: 0,
            stop: None,
        }
    }

    /// The watch of a sample simulated with its own ball parameters (a study whose physics
    /// varies from sample to sample).
    pub fn with_ball_params(mut self, ball: BallParams) -> SampleWatch {
        self.ball = ball;
        self
    }

    /// Whether the watch has all it needs ([`Until::FirstContact`] and the first contact
    /// seen): the caller may stop the loop.
    pub fn is_complete(&self) -> bool {
        self.stop.is_some()
    }

    /// Takes event `ev` in. `cue_before` is the cue ball's state at time `t0` (any time
    /// from its last change to `ev.t`), for its velocity just before the event;
    /// `position(i)` gives ball `i`'s centre right after the event, for the balls `ev`
    /// involves.
    pub fn observe(
        &mut self,
        config: &StudyConfig,
        ev: &Event,
        cue_before: &crate::model::ball_state::BallState,
        t0: f64,
        position: impl Fn(usize) -> crate::model::vec3::Vec3,
    ) {
        if self.stop.is_some() {
            return;
        }
        self.seen += 1;
        let s = &mut self.sample;
        if ev.kind == EventKind::BallPocket {
            s.potted.push(Pot {
                ball: ev.ball,
                pocket: ev.other,
                t: ev.t,
            });
        }
        if s.first != FirstContact::Nothing {
            return;
        }
        let cue = self.cue;
        let Some(first) = first_contact_of(ev, cue as u32) else {
            return;
        };
        let at = position(cue);
        let v = evolve(cue_before, ev.t - t0, &self.ball).v;
        s.first = first;
        s.first_t = ev.t;
        s.contact_cue = (at.x, at.y);
        s.contact_speed = v.x.hypot(v.y);
        s.contact_point = contact_point(config, first, (at.x, at.y));
        if let FirstContact::Ball(k) = first {
            let o = position(k as usize);
            let (nx, ny) = (o.x - at.x, o.y - at.y);
            s.contact_point = (0.5 * (at.x + o.x), 0.5 * (at.y + o.y));
            s.cut_angle = (v.x * ny - v.y * nx)
                .atan2(v.x * nx + v.y * ny)
                .to_degrees();
        }
        if self.until == Until::FirstContact {
            self.stop = Some((self.seen, (at.x, at.y)));
        }
    }

    /// [`SampleWatch::observe`] of the `number`th event (the strike is 1) where the events
    /// before it were not shown: the GPU's watch shows only those that count (the first
    /// contact, the pots).
    pub fn observe_numbered(
        &mut self,
        config: &StudyConfig,
        number: usize,
        ev: &Event,
        cue_before: &crate::model::ball_state::BallState,
        t0: f64,
        position: impl Fn(usize) -> crate::model::vec3::Vec3,
    ) {
        if self.stop.is_none() {
            self.seen = number.saturating_sub(1);
        }
        self.observe(config, ev, cue_before, t0, position);
    }

    /// The sample, given the cue ball's centre at the end and how the loop ended (both
    /// ignored once [`SampleWatch::is_complete`]: the sample ends at the first contact).
    pub fn finish(self, cue_final: (f64, f64), outcome: Outcome) -> Sample {
        let mut s = self.sample;
        match self.stop {
            Some((n_events, at)) => {
                s.cue_final = at;
                s.n_events = n_events;
                s.duration = s.first_t;
                s.cut = None;
            }
            None => {
                s.cue_final = cue_final;
                s.n_events = outcome.n_events;
                s.duration = outcome.t_end;
                s.cut = outcome.cut;
            }
        }
        s
    }
}

/// One sample on `lp`: the balls `initial`, `strike` on the study's cue ball, run
/// [`Until`] the end asked for. Errors only on a strike the loop refuses.
pub fn simulate_sample(
    lp: &mut EventLoop<'_>,
    config: &StudyConfig,
    initial: &[crate::model::ball_state::BallState],
    strike: CueStrike,
    until: Until,
) -> Result<Sample, SimError> {
    let cue = config.cue;
    lp.reset(initial, Some((cue, strike)))?;
    let mut watch =
        SampleWatch::new(config, initial, strike, until).with_ball_params(lp.params().ball);
    loop {
        // the cue ball before the event, for its velocity at the first contact (its state
        // holds at the loop's time, whatever its own time stamp)
        let (before, t0) = (lp.balls()[cue], lp.time());
        let Some(ev) = lp.step() else { break };
        let balls = lp.balls();
        watch.observe(config, &ev, &before, t0, |i| balls[i].r);
        if watch.is_complete() {
            break;
        }
    }
    let end = lp.balls()[cue].r;
    Ok(watch.finish((end.x, end.y), lp.outcome()))
}

/// Where a cue ball centred at `(x, y)` touches the cushion of `first` (the nearest point
/// of the segment, or of the jaw's circle); NaN for anything but a cushion.
fn contact_point(config: &StudyConfig, first: FirstContact, (x, y): (f64, f64)) -> (f64, f64) {
    match first {
        FirstContact::Cushion {
            circular: false,
            index,
        } => {
            let seg = &config.table.linear[index as usize];
            let (dx, dy) = (seg.p2.x - seg.p1.x, seg.p2.y - seg.p1.y);
            let u = ((x - seg.p1.x) * dx + (y - seg.p1.y) * dy) / (dx * dx + dy * dy);
            let u = u.clamp(0.0, 1.0);
            (seg.p1.x + u * dx, seg.p1.y + u * dy)
        }
        FirstContact::Cushion {
            circular: true,
            index,
        } => {
            let arc = &config.table.circular[index as usize];
            let (dx, dy) = (x - arc.center.x, y - arc.center.y);
            let d = dx.hypot(dy);
            (
                arc.center.x + arc.radius * dx / d,
                arc.center.y + arc.radius * dy / d,
            )
        }
        _ => (f64::NAN, f64::NAN),
    }
}
