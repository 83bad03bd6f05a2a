//! `kisstime shots`: the Monte Carlo shot study and its reports.

use kisstime::Error;
use kisstime::io::{output_error, write_output};
use kisstime::study::{Noise, StudyConfig, Summary, run_study};

use super::args::ShotsArgs;
use super::commands::{check_output, open_engine, print_notes};
use super::plot::write_study_png;
use super::progress::Progress;
use super::report::{summary_text, write_samples_csv};

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

pub fn run_shots(args: &ShotsArgs) -> Result<(), Error> {
    if let Some(out) = &args.output {
        check_output(out, "-o", &["csv"])?;
    }
    if let Some(plot) = &args.plot {
        check_output(plot, "--plot", &["png"])?;
    }
    let scenario = match &args.scenario {
        Some(path) => StudyConfig::read(path)?,
        None => StudyConfig::builtin(),
    };
    let sigma = shots_sigma(args, &scenario)?;
    let mut engine = open_engine(args.backend, args.precision, args.verbose)?;
    let n = args.samples as usize;
    let started = std::time::Instant::now();
    let bar = Progress::new("shots", n as u64, "samples", n >= 100_000);
    let samples = run_study(
        &scenario,
        &sigma,
        n,
        args.seed,
        &mut engine,
        &mut |done, _| bar.set(done as u64),
    );
    bar.done();
    let seconds = started.elapsed().as_secs_f64();
    print_notes(&mut engine);
    let samples = samples?;
    let summary = Summary::of(&scenario, &samples);
    let text = format!(
        "kisstime shots: {}\n{n} samples, seed {}; noise σ: v0 {} m/s, phi {}°, theta {}°, \
         a {} mm, b {} mm\n\n{}\n{n} samples in {seconds:.3} s: {:.0} samples/s on {}\n",
        scenario.source,
        args.seed,
        sigma.v0,
        sigma.phi,
        sigma.theta,
        1e3 * sigma.a,
        1e3 * sigma.b,
        summary_text(&summary),
        n as f64 / seconds,
        engine.describe()
    );
    write_output(None, |w| w.write_all(text.as_bytes()).map_err(output_error))?;
    if let Some(path) = &args.output {
        write_output(Some(path), |w| {
            write_samples_csv(w, &scenario, &sigma, args.seed, &samples).map_err(output_error)
        })?;
    }
    if let Some(path) = &args.plot {
        write_study_png(path, &scenario, &samples, &summary)?;
    }
    Ok(())
}
