//! The study's driver: every sample from its strike to rest (or to the cue ball's first
//! contact) through the one whole-shot entry point, [`ShotEngine::simulate_with`] (on the
//! engine's backend, pooltool 0.6.0's physics), with the engine watching the cue ball
//! ([`crate::simulate::watch`]), and what each sample came to ([`Sample`]).
//!
//! The watch keeps what a study needs of a sample's events as they go by — the cue ball's
//! first contact (the first event after the strike that involves it, other than its own
//! sliding → rolling), every `ball_pocket` in order — on the CPU and the GPU alike, and
//! [`sample_of`] turns it, with the cue ball's final state and how the run ended, into the
//! sample: the same samples on every backend. With [`Until::FirstContact`] a sample stops
//! at that first contact: the cheaper study of what the cue ball meets first, on the same
//! code.

use rayon::prelude::*;

use super::config::{Noise, StudyConfig};
use super::noise::{self, noisy_strike, sample_physics};
use super::stats::{Summary, Tally};
use crate::engine::{Backend, Precision, ShotEngine};
use crate::error::{Error, InputError, SimError};
use crate::game::{Context, Played, Verdict};
use crate::model::ball_state::BallState;
use crate::model::sim_params::{BallParams, Physics, SimParams};
use crate::motion::evolve::evolve;
use crate::resolve::stick_ball::CueStrike;
use crate::simulate::events::{Cut, Event, EventKind, Outcome};
use crate::simulate::watch::{TableWatch, WatchOptions};
use crate::simulate::{BatchError, BatchOptions, Limits};

/// Samples simulated on the CPU between two progress reports (memory stays bounded by
/// the results); the GPU's chunks are the engine's
/// ([`crate::engine::GPU_STREAM_TABLES`]).
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
    /// The game's verdict on it, where the study has a game (`[game]`; to rest only).
    pub verdict: Option<Verdict>,
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

/// Which samples a study runs.
#[derive(Clone, Debug)]
pub enum Samples<'a> {
    /// Samples `range` of the study drawn from `sigma` with `seed`: sample `i`'s strike is
    /// [`noisy_strike`]`(…, i)` and its physics [`sample_physics`]`(…, i)`, so any part of a
    /// study (a Dask task's) gives the samples of the whole.
    Drawn {
        /// The noise.
        sigma: &'a Noise,
        /// The study's seed.
        seed: u64,
        /// The samples' ids.
        range: std::ops::Range<usize>,
    },
    /// These strikes, in order, without noise.
    Given(&'a [CueStrike]),
    /// These strikes, in order, without noise, each judged in its own context instead of
    /// the study's game's (`contexts[j]` for `strikes[j]`; a planner's candidates, each
    /// with its call). The study needs a game.
    Judged {
        /// The strikes.
        strikes: &'a [CueStrike],
        /// Each strike's context.
        contexts: &'a [Context],
    },
}

impl Samples<'_> {
    /// How many.
    pub fn len(&self) -> usize {
        match self {
            Samples::Drawn { range, .. } => range.len(),
            Samples::Given(strikes) | Samples::Judged { strikes, .. } => strikes.len(),
        }
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The `j`th sample's strike.
    fn strike(&self, config: &StudyConfig, j: usize) -> CueStrike {
        match self {
            Samples::Drawn { sigma, seed, range } => {
                noisy_strike(config, sigma, *seed, (range.start + j) as u64)
            }
            Samples::Given(strikes) | Samples::Judged { strikes, .. } => strikes[j],
        }
    }

    /// The `j`th sample's context, where it has its own.
    fn context(&self, j: usize) -> Option<&Context> {
        match self {
            Samples::Judged { contexts, .. } => Some(&contexts[j]),
            _ => None,
        }
    }

    /// The `j`th sample's physics, where it varies from sample to sample.
    fn physics(&self, config: &StudyConfig, j: usize) -> Option<SimParams> {
        match self {
            Samples::Drawn { sigma, seed, range } if !sigma.physics.is_empty() => {
                Some(sample_physics(
                    &config.params,
                    &sigma.physics,
                    *seed,
                    (range.start + j) as u64,
                ))
            }
            _ => None,
        }
    }
}

/// Runs `samples` of `config`'s study on `engine`'s backend: every sample through
/// [`ShotEngine::simulate_with`], watched, in chunks; `progress(done, total)` after each
/// chunk. The samples come back in order, the same on every backend and whatever the
/// thread count.
///
/// Errors: a study whose results would not fit the available memory, refused before it
/// starts ([`Error::TooLarge`]); a strike or a physics draw the simulator refuses (not
/// finite, V0 < 0, a² + b² > 1), an [`Error::Input`] naming the sample by its place in
/// `samples`; a backend failure (a GPU failure on `gpu`; `auto` redoes it on the CPU).
pub fn run(
    engine: &mut ShotEngine,
    config: &StudyConfig,
    samples: Samples<'_>,
    options: &RunOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<Sample>, Error> {
    check(config, &samples, options)?;
    let n = samples.len();
    let each = std::mem::size_of::<Sample>() + std::mem::size_of::<CueStrike>();
    crate::limits::check_memory(
        &format!("a study of {n} samples"),
        (n as u64).saturating_mul(each as u64),
    )?;
    // the strikes, drawn once (Rayon over samples): the input and the samples both read them
    let drawn: Vec<CueStrike> = match &samples {
        Samples::Drawn { .. } => (0..n)
            .into_par_iter()
            .with_min_len(1024)
            .map(|j| samples.strike(config, j))
            .collect(),
        Samples::Given(_) | Samples::Judged { .. } => Vec::new(),
    };
    let strikes: &[CueStrike] = match &samples {
        Samples::Drawn { .. } => &drawn,
        Samples::Given(given) | Samples::Judged { strikes: given, .. } => given,
    };
    let mut out = Vec::with_capacity(n);
    drive(
        engine,
        config,
        &samples,
        options,
        Strikes {
            play: &|j| strikes[j],
            report: Some(&|j| strikes[j]),
        },
        &mut out,
        progress,
    )?;
    Ok(out)
}

/// The [`Summary`] of `samples` of `config`'s study on `engine`'s backend, as
/// [`Summary::of`] gives it on what [`run`] returns, bit for bit — without keeping the
/// samples: each chunk's samples are counted ([`Tally`]) and dropped, and a drawn
/// sample's strike is drawn only where the sample is played (on the CPU; the device
/// draws its own), not up front and not to report it, so memory holds a chunk and the
/// values the statistics need (at most nine numbers a sample). For a study whose
/// per-sample rows nobody asked for. Errors: [`run`]'s.
pub fn summarize(
    engine: &mut ShotEngine,
    config: &StudyConfig,
    samples: Samples<'_>,
    options: &RunOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Summary, Error> {
    check(config, &samples, options)?;
    let n = samples.len();
    crate::limits::check_memory(
        &format!("the summary of a study of {n} samples"),
        (n as u64).saturating_mul(Tally::MOST_BYTES_A_SAMPLE as u64),
    )?;
    let mut counting = Counting {
        config,
        until: options.until,
        tally: Tally::new(config, options.until),
    };
    drive(
        engine,
        config,
        &samples,
        options,
        Strikes {
            play: &|j| samples.strike(config, j),
            report: None,
        },
        &mut counting,
        progress,
    )?;
    Ok(counting.tally.finish())
}

/// Runs `samples` of `config`'s study on `engine`'s backend as [`run`] does, handing each
/// chunk's samples to `collect` as they come, in order, instead of keeping them: for a
/// client that reduces them (a planner's estimates) while the device runs the next chunk.
/// A drawn sample's strike is drawn where it is played and again to report it (on the
/// CPU; the device draws its own). Errors: [`run`]'s.
pub fn run_into(
    engine: &mut ShotEngine,
    config: &StudyConfig,
    samples: Samples<'_>,
    options: &RunOptions,
    collect: &mut dyn Collect,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<(), Error> {
    check(config, &samples, options)?;
    let strike_of = |j: usize| samples.strike(config, j);
    drive(
        engine,
        config,
        &samples,
        options,
        Strikes {
            play: &strike_of,
            report: Some(&strike_of),
        },
        collect,
        progress,
    )
}

/// What takes a study's samples as they come, chunk by chunk in order ([`run_into`]).
pub trait Collect {
    /// Takes the next chunk's samples (the vector left empty).
    fn take(&mut self, chunk: &mut Vec<Sample>);
    /// Forgets every sample taken (the study starts over).
    fn restart(&mut self);
    /// Samples taken.
    fn taken(&self) -> usize;
}

impl Collect for Vec<Sample> {
    fn take(&mut self, chunk: &mut Vec<Sample>) {
        self.append(chunk);
    }

    fn restart(&mut self) {
        self.clear();
    }

    fn taken(&self) -> usize {
        self.len()
    }
}

/// A study's samples counted as they come, none kept.
struct Counting<'c> {
    config: &'c StudyConfig,
    until: Until,
    tally: Tally,
}

impl Collect for Counting<'_> {
    fn take(&mut self, chunk: &mut Vec<Sample>) {
        for s in chunk.drain(..) {
            self.tally.add(&s);
        }
    }

    fn restart(&mut self) {
        self.tally = Tally::new(self.config, self.until);
    }

    fn taken(&self) -> usize {
        self.tally.len()
    }
}

/// Refuses what no sample of `samples` could run as `options` say: a game's study to the
/// first contact, samples judged in their own contexts without a game or without one
/// context each. Before any work ([`run`], [`summarize`], [`run_into`]).
fn check(config: &StudyConfig, samples: &Samples<'_>, options: &RunOptions) -> Result<(), Error> {
    if config.game.is_some() && options.until == Until::FirstContact {
        return Err(Error::Unsupported(
            "a study with a [game] runs to rest: the rules judge the whole shot (leave out \
             --until first-contact)"
                .into(),
        ));
    }
    if let Samples::Judged { strikes, contexts } = samples {
        if config.game.is_none() {
            return Err(InputError::new("samples judged in their own contexts need a game").into());
        }
        if contexts.len() != strikes.len() {
            return Err(InputError::new(format!(
                "{} strikes but {} contexts",
                strikes.len(),
                contexts.len()
            ))
            .into());
        }
    }
    Ok(())
}

/// A study's strikes as [`drive`] takes them: sample `j` is struck by `play(j)` and
/// reported with `report(j)` (where `None`: the intended strike, for samples that only a
/// [`Tally`] sees, which does not count strikes, so that no strike is drawn twice).
struct Strikes<'s> {
    play: &'s (dyn Fn(usize) -> CueStrike + Sync),
    report: Option<&'s (dyn Fn(usize) -> CueStrike + Sync)>,
}

/// Runs `samples` (sample `j` struck by `strikes.play(j)`), every chunk's samples made from
/// their watches (Rayon over the chunk) and handed to `collect` in order, each with its
/// reported strike.
fn drive(
    engine: &mut ShotEngine,
    config: &StudyConfig,
    samples: &Samples<'_>,
    options: &RunOptions,
    strikes: Strikes<'_>,
    collect: &mut dyn Collect,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<(), Error> {
    let n = samples.len();
    let initial = config.initial();
    let cue = config.cue;
    let batch = BatchOptions {
        limits: options.limits,
        record_events: false,
        chunk_tables: CHUNK,
        // the position was checked when the study was read
        check_layout: false,
        watch: Some(WatchOptions {
            cue,
            stop_at_first_contact: options.until == Until::FirstContact,
            facts: config.game.is_some(),
        }),
        one_position: true,
        // the device draws and plays the strikes itself where it can
        drawn: match samples {
            Samples::Drawn { sigma, seed, range } => {
                noise::drawn(config, sigma, *seed, range.start as u64)
            }
            _ => None,
        },
    };
    let draw = |j: usize| samples.physics(config, j).unwrap_or(config.params);
    let physics = if samples.physics(config, 0).is_some() {
        Physics::drawn(&draw)
    } else {
        Physics::Shared(config.params)
    };
    let input = |j: usize, balls: &mut Vec<BallState>| {
        balls.clear();
        balls.extend_from_slice(&initial);
        Ok(Some((cue, (strikes.play)(j))))
    };
    let collect = std::cell::RefCell::new(collect);
    let made = std::cell::RefCell::new(Vec::new());
    let sink = |chunk: &crate::simulate::Chunk| {
        let mut made = made.borrow_mut();
        // each sample judged from its watch, Rayon over the chunk
        made.par_extend((0..chunk.len()).into_par_iter().with_min_len(64).map(|i| {
            let run = chunk.get(i).expect("a table of the chunk");
            let j = run.table;
            let watch = run.watch.expect("a watched batch");
            let ball = physics.of(j).ball;
            let end = run.balls[0].r;
            sample_of(
                config,
                options.until,
                strikes.report.map_or(config.shot, |r| r(j)),
                ball,
                watch,
                (end.x, end.y),
                run.outcome,
                (&initial, samples.context(j)),
            )
        }));
        let mut collect = collect.borrow_mut();
        collect.take(&mut made);
        progress(collect.taken(), n);
        Ok::<(), Error>(())
    };
    // a GPU failure under `auto` after samples came back: the study starts over on the CPU
    let restart = || {
        collect.borrow_mut().restart();
        Ok::<(), Error>(())
    };
    engine
        .simulate_restartable(&config.table, physics, &batch, n, input, restart, sink)
        .map_err(|e| match e {
            BatchError::Table { table, error } => sample_error(table, error),
            BatchError::Sink(e) => e,
        })?;
    Ok(())
}

/// Runs the study on the CPU: `samples` noisy strikes drawn from `seed` ([`noisy_strike`]).
/// See [`run`].
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

/// Samples `range` of the study [`run_study`] runs with `seed`, on the CPU (their strikes
/// and physics drawn by their own ids): a part of a study. See [`run`].
pub fn run_samples(
    config: &StudyConfig,
    sigma: &Noise,
    seed: u64,
    range: std::ops::Range<usize>,
    options: &RunOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<Sample>, Error> {
    let samples = Samples::Drawn { sigma, seed, range };
    run(&mut cpu()?, config, samples, options, progress)
}

/// Runs the given strikes, in order, without noise, on the CPU. See [`run`].
pub fn run_strikes(
    config: &StudyConfig,
    strikes: &[CueStrike],
    options: &RunOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<Sample>, Error> {
    run(
        &mut cpu()?,
        config,
        Samples::Given(strikes),
        options,
        progress,
    )
}

/// The CPU backend.
fn cpu() -> Result<ShotEngine, Error> {
    ShotEngine::new(Backend::Cpu, Precision::F64)
}

/// A strike the simulator refuses, as the error of sample `i`.
fn sample_error(i: usize, e: SimError) -> Error {
    Error::from(InputError::new(format!("sample {i}: {e}")))
}

/// What the cue ball's first contact `ev` was (`ev` is one: [`crate::simulate::watch`]'s
/// `first_contact_of`): a ball, a cushion or jaw, a pocket, or the cue ball stopping.
fn first_contact_kind(ev: &Event, cue: u32) -> FirstContact {
    match ev.kind {
        EventKind::BallBall => FirstContact::Ball(if ev.ball == cue { ev.other } else { ev.ball }),
        EventKind::BallLinearCushion => FirstContact::Cushion {
            circular: false,
            index: ev.other,
        },
        EventKind::BallCircularCushion => FirstContact::Cushion {
            circular: true,
            index: ev.other,
        },
        EventKind::BallPocket => FirstContact::Pocket(ev.other),
        // the strike and the cue ball's sliding → rolling are no first contact (the watch
        // passes them by); the rest are the cue ball stopping
        EventKind::RollingSpinning
        | EventKind::RollingStationary
        | EventKind::SpinningStationary
        | EventKind::StickBall
        | EventKind::SlidingRolling => FirstContact::Stopped,
    }
}

/// What one sample came to, from its watch ([`TableWatch`], either backend's): `strike`
/// played with the ball parameters `ball`, run [`Until`] the end asked for; `cue_final` is
/// the cue ball's centre at the end and `outcome` how the run ended (both ignored where
/// the sample ends at its first contact); `start` holds the balls at the start, for the
/// game's verdict (where the study has a game and the watch kept the rules' facts), and
/// the context that judges it where not the game's own.
// every argument is one part of what a sample came to; a struct of them would only rename them
#[allow(clippy::too_many_arguments)]
pub fn sample_of(
    config: &StudyConfig,
    until: Until,
    strike: CueStrike,
    ball: BallParams,
    watch: TableWatch<'_>,
    cue_final: (f64, f64),
    outcome: Outcome,
    (start, context): (&[BallState], Option<&Context>),
) -> Sample {
    let cue = config.cue;
    let potted = watch
        .pots
        .iter()
        .map(|(_, ev)| Pot {
            ball: ev.ball,
            pocket: ev.other,
            t: ev.t,
        })
        .collect();
    let mut s = Sample {
        strike,
        first: FirstContact::Nothing,
        first_t: f64::NAN,
        contact_cue: (f64::NAN, f64::NAN),
        contact_speed: f64::NAN,
        contact_point: (f64::NAN, f64::NAN),
        cut_angle: f64::NAN,
        potted,
        cue_final,
        n_events: outcome.n_events,
        duration: outcome.t_end,
        cut: outcome.cut,
        verdict: None,
    };
    // the game's verdict, from the facts the watch kept (the CPU's), on the balls at the start
    if let (Some(game), Some(facts)) = (&config.game, watch.facts) {
        let played = Played {
            ids: &game.ids,
            start,
            cue,
            facts,
        };
        let context = context.unwrap_or(&game.context);
        s.verdict = game.rules.judge_played(&played, context).ok();
    }
    let Some(f) = watch.first else {
        return s;
    };
    let ev = f.event;
    let first = first_contact_kind(&ev, cue as u32);
    let at = (f.cue_after.x, f.cue_after.y);
    let v = evolve(&f.cue_before, ev.t - f.t0, &ball).v;
    s.first = first;
    s.first_t = ev.t;
    s.contact_cue = at;
    s.contact_speed = v.x.hypot(v.y);
    s.contact_point = contact_point(config, first, at);
    if let FirstContact::Ball(_) = first {
        let o = f.other_after;
        let (nx, ny) = (o.x - at.0, o.y - at.1);
        s.contact_point = (0.5 * (at.0 + o.x), 0.5 * (at.1 + o.y));
        s.cut_angle = (v.x * ny - v.y * nx)
            .atan2(v.x * nx + v.y * ny)
            .to_degrees();
    }
    if until == Until::FirstContact {
        // the sample ends at its first contact (the loop stopped there: no pot comes after)
        let own = watch
            .pots
            .iter()
            .take_while(|(n, _)| *n <= f.number)
            .count();
        s.potted.truncate(own);
        s.cue_final = at;
        s.n_events = f.number;
        s.duration = ev.t;
        s.cut = None;
    }
    s
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
