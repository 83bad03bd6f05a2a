//! The study's driver on the GPU event loop ([`GpuSimulator`], the WGSL twin of the CPU's
//! [`crate::simulate::EventLoop`]): the same samples as [`super::run`], one table per
//! sample, [`CHUNK`](super::CHUNK) samples per batch.
//!
//! Each sample's events stream back from the device after every dispatch and go through
//! the same [`SampleWatch`] as on the CPU; only the cue ball's latest state is kept per
//! sample (for its velocity at the first contact), never the events. With
//! [`Until::FirstContact`](super::Until::FirstContact) the device still runs each sample to
//! rest (the event loop has no per-table stop); the watch ends the sample at its first
//! contact, so the samples are those of the CPU.
//!
//! A strike the simulator refuses is the error of its sample, as on the CPU, found before
//! anything is dispatched; a device failure is an [`Error::Gpu`], which the `auto` backend
//! ([`crate::engine::ShotEngine`]) redoes on the CPU.

use super::config::{Noise, StudyConfig};
use super::noise::noisy_strike;
use super::run::{RunOptions, Sample, SampleWatch, run_chunks, sample_error};
use crate::error::Error;
use crate::gpu::{GPU_MAX_BALLS, GpuShot, GpuSimulator};
use crate::model::ball_state::BallState;
use crate::model::vec3::Vec3;
use crate::resolve::stick_ball::CueStrike;
use crate::simulate::EventLoop;
use crate::simulate::batch::EventRecord;

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
    run_with_gpu(
        gpu,
        config,
        samples,
        &|i| noisy_strike(config, sigma, seed, i as u64),
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
        options,
        progress,
    )
}

/// One sample in flight: its watch and the cue ball's latest state with its time.
struct InFlight {
    watch: SampleWatch,
    cue: BallState,
    cue_t: f64,
}

fn run_with_gpu(
    gpu: &mut GpuSimulator,
    config: &StudyConfig,
    samples: usize,
    strike: &dyn Fn(usize) -> CueStrike,
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
    let mut check = EventLoop::new(&config.table, config.params, options.limits, initial.len())?;
    run_chunks(config, samples, options, progress, |part| {
        let mut shots = Vec::with_capacity(part.len());
        let mut flight = Vec::with_capacity(part.len());
        for i in part {
            let s = strike(i);
            // the CPU's checks of the strike, so that a bad one is the sample's error
            check
                .reset(&initial, Some((cue, s)))
                .map_err(|e| sample_error(i, e))?;
            shots.push(GpuShot {
                balls: initial.clone(),
                strike: Some((cue, s)),
            });
            flight.push(InFlight {
                watch: SampleWatch::new(config, &initial, s, options.until),
                cue: initial[cue],
                cue_t: 0.0,
            });
        }
        let mut on_event = |k: usize, rec: &EventRecord| {
            let f = &mut flight[k];
            let position = |i: usize| {
                rec.balls()
                    .find(|(j, _)| *j == i)
                    .map_or(Vec3::new(f64::NAN, f64::NAN, f64::NAN), |(_, b)| b.r)
            };
            f.watch
                .observe(config, &rec.event, &f.cue, f.cue_t, position);
            if let Some((_, b)) = rec.balls().find(|(j, _)| *j == cue) {
                f.cue = *b;
                f.cue_t = rec.event.t;
            }
        };
        let runs = gpu.simulate_with(
            &config.table,
            config.params,
            options.limits,
            &shots,
            Some(&mut on_event),
        )?;
        Ok(flight
            .into_iter()
            .zip(runs)
            .map(|(f, run)| {
                let end = run.balls[cue].r;
                f.watch.finish((end.x, end.y), run.outcome)
            })
            .collect())
    })
}
