//! `kisstime shots`: the Monte Carlo shot study and its reports.

use std::path::Path;

use kisstime::engine::{Backend, Precision, ShotEngine};
use kisstime::io::physics::read_physics;
use kisstime::io::strikes::read_sample_strikes;
use kisstime::io::{output_error, write_output};
use kisstime::simulate::{CueStrike, Limits};
use kisstime::study::{self, Noise, RunOptions, StudyConfig, Summary, Until};
use kisstime::{Error, InputError};

use super::args::{ShotsArgs, UntilArg};
use super::commands::check_output;
use super::progress::Progress;
use super::report::{Run, summary_json, summary_text, write_samples_csv};
use super::study_plot::render_png;

/// Samples from which a progress bar is shown (on a terminal).
const SHOW_SAMPLES: usize = 200_000;

/// The noise of a shot study: the file's, scaled by `--noise`, with `--sigma-*` overrides.
fn shots_sigma(args: &ShotsArgs, scenario: &StudyConfig) -> Result<Noise, Error> {
    let check = |name: &'static str, value: f64| {
        if value.is_finite() && value >= 0.0 {
            Ok(value)
        } else {
            Err(Error::Unsupported(format!(
                "invalid {name} {value}: it must be finite and not negative"
            )))
        }
    };
    let factor = check("--noise", args.noise.unwrap_or(scenario.noise_factor))?;
    let mut sigma = scenario.noise.scaled(factor);
    for (name, value, slot) in [
        ("--sigma-v0", args.sigma_v0, &mut sigma.v0),
        ("--sigma-phi", args.sigma_phi, &mut sigma.phi),
        ("--sigma-theta", args.sigma_theta, &mut sigma.theta),
        ("--sigma-a", args.sigma_a, &mut sigma.a),
        ("--sigma-b", args.sigma_b, &mut sigma.b),
    ] {
        if let Some(v) = value {
            *slot = check(name, v)?;
        }
    }
    Ok(sigma)
}

/// The scenario the arguments name: TOML, a reference-format `.json`, or the built-in one;
/// with the parameters of `physics` in place of its own when given.
fn read_scenario(path: Option<&Path>, physics: Option<&Path>) -> Result<StudyConfig, Error> {
    let config = read_scenario_file(path)?;
    match physics {
        Some(p) => config.with_physics(read_physics(p)?, &p.display().to_string()),
        None => Ok(config),
    }
}

/// `--physics-noise KEY=SPREAD …` as the body of a `[noise.physics]` table.
fn physics_noise_toml(items: &[String]) -> Result<String, Error> {
    let mut text = String::new();
    for item in items {
        let Some((key, value)) = item.split_once('=') else {
            return Err(InputError::new(format!(
                "--physics-noise {item}: expected KEY=SPREAD (u_r=0.1, e_c=[0.8,0.9])"
            ))
            .into());
        };
        // the key quoted, so that any text is one key (the parser names unknown ones)
        text.push_str(&format!("{:?} = {}\n", key.trim(), value.trim()));
    }
    Ok(text)
}

/// The scenario file the arguments name, or the built-in one.
fn read_scenario_file(path: Option<&Path>) -> Result<StudyConfig, Error> {
    match path {
        Some(p)
            if p.extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("json")) =>
        {
            StudyConfig::read_reference(p)
        }
        Some(p) => StudyConfig::read(p),
        None => Ok(StudyConfig::builtin()),
    }
}

pub fn run_shots(args: &ShotsArgs) -> Result<(), Error> {
    let (backend, precision) = (args.backend.backend(), args.precision.precision());
    if backend == Backend::Cpu && precision == Precision::F32 {
        return Err(Error::Unsupported(
            "--precision f32 needs --backend gpu or auto: the CPU simulates in f64 only".into(),
        ));
    }
    if let Some(out) = &args.output {
        check_output(out, "-o", &["csv"])?;
    }
    if let Some(plot) = &args.plot {
        check_output(plot, "--plot", &["png"])?;
    }
    let limits = Limits::new(args.max_events, args.max_time)?;
    let mut scenario = read_scenario(args.scenario.as_deref(), args.physics.as_deref())?;
    if !args.physics_noise.is_empty() {
        scenario = scenario
            .with_physics_noise(&physics_noise_toml(&args.physics_noise)?, "--physics-noise")?;
    }
    let sigma = shots_sigma(args, &scenario)?;
    // the given strikes (and their sample ids), or none for a noisy study
    let given: Option<(Vec<i64>, Vec<CueStrike>)> = match &args.strikes {
        Some(path) => {
            let rows = read_sample_strikes(path)?;
            Some(rows.iter().map(|r| (r.sample, r.strike)).unzip())
        }
        None => None,
    };
    let options = RunOptions {
        until: match args.until {
            UntilArg::Rest => Until::Rest,
            UntilArg::FirstContact => Until::FirstContact,
        },
        limits,
    };
    let n = given
        .as_ref()
        .map_or(args.samples as usize, |(ids, _)| ids.len());
    let mut engine = ShotEngine::new(backend, precision)?;
    for note in engine.take_notes() {
        eprintln!("kisstime: {note}");
    }
    if args.verbose {
        eprintln!(
            "kisstime: {n} samples of {} ({} balls, table {}) on {}",
            scenario.source,
            scenario.balls.len(),
            scenario.table_name,
            engine.describe()
        );
    }
    let started = std::time::Instant::now();
    let bar = Progress::new("shots", n as u64, "samples", n >= SHOW_SAMPLES);
    let mut progress = |done: usize, _: usize| bar.set(done as u64);
    let which = match &given {
        Some((_, strikes)) => study::Samples::Given(strikes),
        None => study::Samples::Drawn {
            sigma: &sigma,
            seed: args.seed,
            range: 0..n,
        },
    };
    // the samples themselves only where a file wants them (the CSV, the picture); else
    // each chunk is counted and dropped
    let rows_wanted = args.output.is_some() || args.plot.is_some();
    let result = if rows_wanted {
        study::run(&mut engine, &scenario, which, &options, &mut progress).map(|samples| {
            let summary = Summary::of(&scenario, &samples, options.until);
            (samples, summary)
        })
    } else {
        study::summarize(&mut engine, &scenario, which, &options, &mut progress)
            .map(|summary| (Vec::new(), summary))
    };
    bar.done();
    for note in engine.take_notes() {
        eprintln!("kisstime: {note}");
    }
    if args.verbose
        && let Some(gpu) = engine.gpu()
    {
        eprintln!("kisstime: GPU phases: {}", gpu.total_timings().describe());
    }
    let seconds = started.elapsed().as_secs_f64();
    let (samples, summary) = result?;
    let ids: Vec<i64> = match &given {
        Some((ids, _)) => ids.clone(),
        None => (0..n as i64).collect(),
    };
    let run = Run {
        scenario: &scenario,
        sigma: given.is_none().then_some(sigma),
        seed: args.seed,
        strikes: args.strikes.as_deref(),
        seconds,
        threads: rayon::current_num_threads(),
        backend: engine.describe(),
    };
    let report = if args.json {
        summary_json(&run, &summary) + "\n"
    } else {
        summary_text(&run, &summary)
    };
    // the files first, so that a failure leaves no summary claiming them: the picture is
    // drawn before anything is written, and if the second file fails the first one, when
    // this run created it, is removed again
    let png = match &args.plot {
        Some(_) => Some(render_png(&scenario, &samples, &summary)?),
        None => None,
    };
    let mut written: Option<&Path> = None;
    if let (Some(path), Some(png)) = (&args.plot, &png) {
        let new = !path.exists();
        write_output(Some(path), |w| w.write_all(png).map_err(output_error))?;
        written = new.then_some(path.as_path());
    }
    if let Some(path) = &args.output {
        let result = write_output(Some(path), |w| {
            write_samples_csv(w, &scenario, &ids, &samples, options.until).map_err(output_error)
        });
        if result.is_err()
            && let Some(first) = written
        {
            let _ = std::fs::remove_file(first);
        }
        result?;
    }
    write_output(None, |w| {
        w.write_all(report.as_bytes()).map_err(output_error)
    })?;
    Ok(())
}
