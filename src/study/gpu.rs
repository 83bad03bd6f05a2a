//! The study's driver on the GPU event loop ([`GpuSimulator`], the WGSL twin of the CPU's
//! [`crate::simulate::EventLoop`]): the same samples as [`super::run`], one table per
//! sample, [`GPU_CHUNK`] samples per batch.
//!
//! No event crosses the bus: the device watches each sample's cue ball
//! ([`GpuSimulator::simulate_strikes_watched`]) and keeps what the study needs of the events (the
//! first contact, with the cue ball's state and the clock before it and both balls'
//! centres after it; every pot), read back once with the final states. On the host these
//! go through the same [`SampleWatch`] as the CPU's events, in event order, so the samples
//! are those of the CPU. With [`Until::FirstContact`] a table stops at its first contact,
//! as the CPU's loop does. Packing and judging run Rayon over samples.
//!
//! A strike the simulator refuses is the error of its sample, as on the CPU, found before
//! anything is dispatched; a device failure is an [`Error::Gpu`], which the `auto` backend
//! ([`crate::engine::ShotEngine`]) redoes on the CPU.

use rayon::prelude::*;

use super::config::{Noise, StudyConfig};
use super::noise::{noisy_strike, sample_physics};
use super::run::{RunOptions, Sample, SampleWatch, Until, run_chunks_of, sample_error};
use crate::error::Error;
use crate::gpu::{GPU_MAX_BALLS, GpuSimulator, WatchedRun};
use crate::model::ball_state::BallState;
use crate::model::sim_params::{BallParams, Physics, SimParams};
use crate::model::vec3::Vec3;
use crate::resolve::stick_ball::CueStrike;
use crate::simulate::EventLoop;

/// Samples per GPU batch: enough tables to fill a large device (each batch is one
/// [`GpuSimulator::simulate_strikes_watched`] call, its buffers reused).
pub const GPU_CHUNK: usize = 1 << 18;

/// [`super::run_study`] on the GPU: `samples` noisy strikes drawn from `seed`.
///
/// Errors: more than [`GPU_MAX_BALLS`] balls ([`Error::Unsupported`]), a refused strike
/// ([`Error::Input`] naming the sample), a study too large for the memory, or a device
/// failure ([`Error::Gpu`]).
pub fn run_study_gpu(
    gpu: &mut GpuSimulator,
    config: &StudyConfig,
    sigma: &Noise,
    samples: usize,
    seed: u64,
    options: &RunOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<Sample>, Error> {
    run_samples_gpu(gpu, config, sigma, seed, 0..samples, options, progress)
}

/// [`super::run_samples`] on the GPU: samples `range` of the study [`run_study_gpu`] runs.
#[allow(clippy::too_many_arguments)]
pub fn run_samples_gpu(
    gpu: &mut GpuSimulator,
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
    run_with_gpu(
        gpu,
        config,
        range.len(),
        &|j| noisy_strike(config, sigma, seed, (first + j) as u64),
        varies.then_some(&physics as &(dyn Fn(usize) -> SimParams + Sync)),
        options,
        progress,
    )
}

/// [`super::run_strikes`] on the GPU: the given strikes, in order, without noise. Errors
/// as [`run_study_gpu`].
pub fn run_strikes_gpu(
    gpu: &mut GpuSimulator,
    config: &StudyConfig,
    strikes: &[CueStrike],
    options: &RunOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<Sample>, Error> {
    run_with_gpu(
        gpu,
        config,
        strikes.len(),
        &|i| strikes[i],
        None,
        options,
        progress,
    )
}

fn run_with_gpu(
    gpu: &mut GpuSimulator,
    config: &StudyConfig,
    samples: usize,
    strike: &(dyn Fn(usize) -> CueStrike + Sync),
    physics: Option<&(dyn Fn(usize) -> SimParams + Sync)>,
    options: &RunOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<Sample>, Error> {
    let initial = config.initial();
    if initial.len() > GPU_MAX_BALLS {
        return Err(Error::Unsupported(format!(
            "the study has {} balls; the GPU event loop takes at most {GPU_MAX_BALLS}",
            initial.len()
        )));
    }
    let cue = config.cue;
    let stop = options.until == Until::FirstContact;
    run_chunks_of(config, samples, GPU_CHUNK, options, progress, |part| {
        // each strike checked as the CPU checks it, so that a bad one is its sample's error
        let strikes: Vec<CueStrike> = part
            .clone()
            .into_par_iter()
            .map(|i| {
                let s = strike(i);
                EventLoop::check_input(&initial, Some((cue, s)))
                    .map(|()| s)
                    .map_err(|e| sample_error(i, e))
            })
            .collect::<Result<_, Error>>()?;
        // each sample's physics where it varies (checked, so that a bad draw is its
        // sample's error)
        let drawn: Vec<SimParams> = match physics {
            Some(f) => part
                .clone()
                .into_par_iter()
                .map(|i| {
                    let p = f(i);
                    p.validate().map(|()| p).map_err(|e| sample_error(i, e))
                })
                .collect::<Result<_, Error>>()?,
            None => Vec::new(),
        };
        let physics: Physics<'_> = if physics.is_some() {
            Physics::PerTable(&drawn)
        } else {
            Physics::Shared(config.params)
        };
        let runs = gpu.simulate_strikes_watched(
            &config.table,
            physics,
            options.limits,
            &initial,
            cue,
            &strikes,
            stop,
        )?;
        Ok(strikes
            .par_iter()
            .zip(runs)
            .enumerate()
            .map(|(k, (s, run))| {
                let ball = physics.of(k).ball;
                judge(config, options, &initial, *s, &run, ball)
            })
            .collect())
    })
}

/// What one sample came to, from the device's watch of it: its first contact and pots go
/// through the CPU's [`SampleWatch`] in event order.
fn judge(
    config: &StudyConfig,
    options: &RunOptions,
    initial: &[BallState],
    strike: CueStrike,
    run: &WatchedRun,
    ball: BallParams,
) -> Sample {
    let watch = &run.watch;
    let cue = config.cue;
    let mut sample =
        SampleWatch::new(config, initial, strike, options.until).with_ball_params(ball);
    let mut first = watch.first.as_ref();
    let mut pots = watch.pots.iter().peekable();
    loop {
        // the next of the first contact and the pots, in event order (a pot that is the
        // first contact is shown once, as the contact)
        let take_first = match (first, pots.peek()) {
            (Some(f), Some((n, _))) => f.number <= *n,
            (Some(_), None) => true,
            (None, Some(_)) => false,
            (None, None) => break,
        };
        if take_first {
            let f = first.take().expect("chosen above");
            if pots.peek().is_some_and(|(n, _)| *n == f.number) {
                pots.next();
            }
            let position = |i: usize| {
                if i == cue {
                    f.cue_after
                } else if i == f.event.ball as usize || i == f.event.other as usize {
                    f.other_after
                } else {
                    Vec3::new(f64::NAN, f64::NAN, f64::NAN)
                }
            };
            sample.observe_numbered(config, f.number, &f.event, &f.cue_before, f.t0, position);
        } else {
            let (n, ev) = pots.next().expect("peeked above");
            let nan = |_: usize| Vec3::new(f64::NAN, f64::NAN, f64::NAN);
            sample.observe_numbered(config, *n, ev, &initial[cue], 0.0, nan);
        }
    }
    let end = run.cue.r;
    sample.finish((end.x, end.y), run.outcome)
}
