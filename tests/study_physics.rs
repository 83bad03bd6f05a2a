//! A study whose physics varies from sample to sample (`[noise.physics]`, issue 25): the
//! cloth's and the cushions' parameters drawn per sample alongside the cue noise.
//! - the strikes are the study's without the spread (the physics has a stream of its own);
//! - sample `i` is exactly the strike `i` simulated alone with the parameters drawn for it
//!   (`sample_physics`), through the study with those parameters (`with_physics`);
//! - the draws lie in their ranges and vary;
//! - the GPU's study with the spread has the CPU's first contacts and pots (where a GPU
//!   exists: lavapipe in CI);
//! - bad spreads are errors naming the key.

mod common;

use kisstime::Precision;
use kisstime::engine::{Backend, ShotEngine};
use kisstime::study::noise::sample_physics;
use kisstime::study::{self, RunOptions, Sample, Samples, StudyConfig, run_strikes, run_study};

fn builtin_with(spread: &str) -> StudyConfig {
    let text = format!(
        "{}\n[noise.physics]\n{spread}\n",
        kisstime::study::BUILTIN_TOML
    );
    StudyConfig::parse(&text, "spread.toml", None).unwrap()
}

fn run(config: &StudyConfig, n: usize) -> Vec<Sample> {
    run_study(
        config,
        &config.sigma(),
        n,
        7,
        &RunOptions::default(),
        &mut |_, _| {},
    )
    .unwrap()
}

#[test]
fn each_sample_is_its_strike_alone_with_its_drawn_physics() {
    let config = builtin_with("u_r = 0.1\ne_c = [0.8, 0.9]\nu_s = 0.05");
    let plain = StudyConfig::builtin();
    let n = 400;
    let varied = run(&config, n);
    let fixed = run(&plain, n);
    // the same strikes: the physics draws do not touch the cue noise's stream
    for (a, b) in varied.iter().zip(&fixed) {
        assert_eq!(a.strike, b.strike);
    }
    let sigma = config.sigma();
    let (mut lo_ur, mut hi_ur) = (f64::INFINITY, 0.0f64);
    let mut differ = 0;
    for i in 0..n {
        let p = sample_physics(&config.params, &sigma.physics, 7, i as u64);
        lo_ur = lo_ur.min(p.ball.u_r);
        hi_ur = hi_ur.max(p.ball.u_r);
        assert!((0.009..=0.011).contains(&p.ball.u_r), "{}", p.ball.u_r);
        assert!((0.8..=0.9).contains(&p.ball.e_c), "{}", p.ball.e_c);
        assert!((0.19..=0.21).contains(&p.ball.u_s), "{}", p.ball.u_s);
        assert_eq!(p.ball.e_b, config.params.ball.e_b, "e_b does not vary");
        if i % 40 == 0 {
            // sample i alone, with its drawn parameters as the study's own
            let alone = StudyConfig::builtin().with_physics(p, "the draw").unwrap();
            let one = run_strikes(
                &alone,
                &[varied[i].strike],
                &RunOptions::default(),
                &mut |_, _| {},
            )
            .unwrap();
            assert_eq!(one[0], varied[i], "sample {i}");
        }
        if varied[i] != fixed[i] {
            differ += 1;
        }
    }
    assert!(hi_ur - lo_ur > 0.0015, "u_r drawn in [{lo_ur}, {hi_ur}]");
    assert!(
        differ > n / 2,
        "{differ} of {n} samples differ from the fixed physics'"
    );
    // the noise factor scales the spread too: 0 replays the intended shot exactly
    let quiet = run_study(
        &config,
        &config.noise.scaled(0.0),
        5,
        7,
        &RunOptions::default(),
        &mut |_, _| {},
    )
    .unwrap();
    let plain_quiet = run_study(
        &plain,
        &plain.noise.scaled(0.0),
        5,
        7,
        &RunOptions::default(),
        &mut |_, _| {},
    )
    .unwrap();
    assert_eq!(quiet, plain_quiet);
}

#[test]
fn the_gpu_study_with_a_physics_spread_has_the_cpus_contacts_and_pots() {
    if common::gpu_or_skip(Precision::F64, "study physics on the GPU").is_none() {
        return;
    }
    let config = builtin_with("u_r = 0.1\ne_c = 0.05\nf_c = 0.2");
    let n = 300;
    let cpu = run(&config, n);
    let mut gpu = ShotEngine::new(Backend::Gpu, Precision::F64).unwrap();
    let samples = Samples::Drawn {
        sigma: &config.sigma(),
        seed: 7,
        range: 0..n,
    };
    let on_gpu = study::run(
        &mut gpu,
        &config,
        samples,
        &RunOptions::default(),
        &mut |_, _| {},
    )
    .unwrap();
    for (i, (g, c)) in on_gpu.iter().zip(&cpu).enumerate() {
        assert_eq!(g.strike, c.strike, "sample {i}");
        assert_eq!(g.first, c.first, "sample {i}");
        let pots = |s: &Sample| {
            s.potted
                .iter()
                .map(|p| (p.ball, p.pocket))
                .collect::<Vec<_>>()
        };
        assert_eq!(pots(g), pots(c), "sample {i}");
        let d = (g.cue_final.0 - c.cue_final.0).hypot(g.cue_final.1 - c.cue_final.1);
        assert!(
            d < 1e-6,
            "sample {i}: the cue ball ends {d} m from the CPU's"
        );
    }
}

#[test]
fn bad_spreads_name_the_key() {
    let bad = |spread: &str, words: &[&str]| {
        let text = format!(
            "{}\n[noise.physics]\n{spread}\n",
            kisstime::study::BUILTIN_TOML
        );
        let e = StudyConfig::parse(&text, "spread.toml", None)
            .unwrap_err()
            .to_string();
        for w in words {
            assert!(e.contains(w), "{spread}: {e}");
        }
    };
    bad("R = 0.01", &["noise.physics.R", "ball size", "spread.toml"]);
    bad("e_c = 0.2", &["noise.physics.e_c", "out of range"]);
    bad("u_r = -0.1", &["noise.physics.u_r", "relative spread"]);
    bad("u_r = [0.02, 0.01]", &["noise.physics.u_r", "lo ≤ hi"]);
    bad("mu_r = 0.1", &["noise.physics.mu_r", "u_r"]);
    bad("u_r = \"x\"", &["noise.physics.u_r"]);
}
