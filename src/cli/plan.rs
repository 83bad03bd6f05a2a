//! `kisstime plan`: the shot to play from one position (the library's `plan`), printed as
//! a ranked table or JSON, the chosen strike written as `simulate --strikes` reads it.

use kisstime::engine::{Precision, ShotEngine};
use kisstime::error::{Error, InputError};
use kisstime::game::{Context, Rules};
use kisstime::io::atomic::write_output;
use kisstime::io::context::default_context;
use kisstime::io::physics::read_physics_or_default;
use kisstime::io::table_json::table_by_name;
use kisstime::model::ball_state::BallState;
use kisstime::plan::agents::Agent;
use kisstime::plan::breaks::plan_break;
use kisstime::plan::in_hand::{InHand, cue_in_hand, plan_in_hand};
use kisstime::plan::play::{PlayOptions, PlayReport, PlayerStats, play};
use kisstime::plan::{Budget, Kind, Plan, PlanOptions, Ranked, plan, position};
use kisstime::study::wilson;
use kisstime::study::{NOISE_PRESETS, Noise, StudyConfig};

use super::args::{PlanArgs, PlayArgs};
use super::commands::{check_output, read_input};

/// The budget `text` names: seconds (`1s`, `250ms`) or a number of samples.
pub fn parse_budget(text: &str) -> Result<Budget, Error> {
    let t = text.trim();
    let bad = || {
        InputError::new(format!(
            "--budget {text}: expected seconds (1s, 250ms) or a number of samples (200000)"
        ))
    };
    let budget = if let Some(ms) = t.strip_suffix("ms") {
        Budget::Seconds(ms.trim().parse::<f64>().map_err(|_| bad())? / 1000.0)
    } else if let Some(s) = t.strip_suffix('s') {
        Budget::Seconds(s.trim().parse::<f64>().map_err(|_| bad())?)
    } else {
        Budget::Samples(t.parse::<usize>().map_err(|_| bad())?)
    };
    Ok(budget)
}

/// The noise preset `name` times `scale`.
fn noise_of(name: &str, scale: f64) -> Result<Noise, Error> {
    let Some(noise) = Noise::preset(name) else {
        let names: Vec<&str> = NOISE_PRESETS.iter().map(|(n, _, _)| *n).collect();
        return Err(InputError::new(format!(
            "--noise {name}: not a preset (one of {})",
            names.join(", ")
        ))
        .into());
    };
    if !(scale.is_finite() && scale >= 0.0) {
        return Err(InputError::new(format!(
            "--noise-scale {scale}: a finite factor of at least 0"
        ))
        .into());
    }
    Ok(noise.scaled(scale))
}

/// The position of `args`' input: its table (the only one, or --table-id's) as the
/// planner's study configuration.
fn read_position(args: &PlanArgs, rules: Rules) -> Result<(i64, StudyConfig), Error> {
    let file = args.input.display().to_string();
    let batch = read_input(&args.input)?;
    let table = table_by_name(&args.table)?;
    let params = read_physics_or_default(args.physics.as_deref())?;
    let k = match args.table_id {
        Some(id) => (0..batch.num_tables())
            .find(|&k| batch.table_id(k) == id)
            .ok_or_else(|| InputError::new(format!("{file}: no table {id}")))?,
        None if batch.num_tables() == 1 => 0,
        None => {
            return Err(InputError::new(format!(
                "{file} holds {} tables: name one with --table-id",
                batch.num_tables()
            ))
            .into());
        }
    };
    let at = format!("{file}, table {}", batch.table_id(k));
    let mut ids = batch.ball_ids(k).to_vec();
    let mut balls: Vec<BallState> = batch
        .balls(k)
        .iter()
        .map(|b| BallState::from_ball(b, params.ball.r))
        .collect();
    // in hand: the cue ball, wherever it is (or is not), waits at a free spot; the
    // placement is the planner's
    if args.ball_in_hand.is_some() || args.break_shot {
        (ids, balls) = cue_in_hand(&table, params.ball.r, &ids, &balls)
            .map_err(|e| InputError::new(format!("{at}: {e}")))?;
    }
    let ids = &ids[..];
    let mut context = default_context(rules);
    context.break_shot = args.break_shot;
    if let Some(list) = &args.hittable {
        let mut set = Vec::new();
        for item in list
            .split([';', ','])
            .map(str::trim)
            .filter(|s| !s.is_empty())
        {
            let id: i64 = item
                .parse()
                .map_err(|_| InputError::new(format!("--hittable: {item} is not a ball id")))?;
            let on_table = ids
                .iter()
                .zip(&balls)
                .any(|(&i, b)| i == id && b.s != kisstime::model::MotionState::Pocketed);
            if !on_table || id <= 0 {
                return Err(InputError::new(format!(
                    "--hittable: ball {id} is not an object ball on the table ({at})"
                ))
                .into());
            }
            set.push(id);
        }
        context.hittable = Context::balls(set);
    }
    let config = position(&table, &args.table, params, (ids, &balls), rules, context).map_err(
        |e| match e {
            Error::Input(e) => Error::from(InputError::new(format!("{at}: {e}"))),
            other => other,
        },
    )?;
    Ok((batch.table_id(k), config))
}

pub fn run(args: &PlanArgs) -> Result<(), Error> {
    let rules = args.rules.rules();
    let budget = parse_budget(&args.budget)?;
    let noise = noise_of(&args.noise.noise, args.noise.noise_scale)?;
    if let Some(path) = &args.output {
        check_output(path, "-o", &["csv"])?;
    }
    if let Some(path) = &args.plot {
        check_output(path, "--plot", &["png"])?;
    }
    if args.top == 0 {
        return Err(InputError::new("--top 0: at least one finalist").into());
    }
    let (table_id, config) = read_position(args, rules)?;
    let mut engine = ShotEngine::new(args.backend.backend(), Precision::F64)?;
    let options = PlanOptions {
        noise,
        seed: args.seed,
        budget,
        finalists: args.top,
        ..PlanOptions::default()
    };
    let planned = match &args.ball_in_hand {
        None if args.break_shot => plan_break(&mut engine, &config, &options)?,
        Some(region) => {
            let region = InHand::from_name(region).map_err(InputError::new)?;
            plan_in_hand(&mut engine, &config, &options, region)?
        }
        None => plan(&mut engine, &config, &options)?,
    };
    for note in engine.take_notes() {
        eprintln!("kisstime: {note}");
    }
    eprintln!(
        "kisstime: {} candidates ({} of them refined strikes), {} samples in {:.2} s ({} rounds, \
         {:.0} samples/s) on {}",
        planned.candidates,
        planned.refined,
        planned.samples,
        planned.seconds,
        planned.rounds,
        planned.samples as f64 / planned.seconds.max(1e-9),
        engine.describe()
    );
    if args.json {
        println!("{}", kisstime::plan::json(&config, &planned));
    } else {
        match planned.placement {
            Some((x, y)) if args.break_shot => {
                println!("break from x = {x:.3} m, y = {y:.3} m")
            }
            Some((x, y)) => println!("cue ball in hand: place it at x = {x:.3} m, y = {y:.3} m"),
            None => {}
        }
        print!("{}", plan_table(&config, &planned));
    }
    if let Some(path) = &args.plot {
        let png = plot_plan(&mut engine, &config, &planned, &options)?;
        write_output(Some(path), |w| {
            w.write_all(&png)
                .map_err(kisstime::io::atomic::output_error)
        })?;
    }
    if let Some(path) = &args.output {
        let best = &planned.ranked[0];
        let s = best.candidate.strike;
        write_output(Some(path), |w| {
            let table = table_id;
            let cue = &config.balls[config.cue].id;
            writeln!(w, "table,ball,V0,phi,theta,a,b")
                .and_then(|()| {
                    writeln!(
                        w,
                        "{table},{cue},{},{},{},{},{}",
                        s.v0, s.phi, s.theta, s.a, s.b
                    )
                })
                .map_err(kisstime::io::atomic::output_error)
        })?;
    }
    Ok(())
}

/// The plays of the chosen strike under the noise that `--plot` draws the cue ball's ends
/// of.
pub const PLOT_SAMPLES: usize = 2_000;

/// The picture of the chosen shot (`--plot`): its strike played without noise, every
/// ball's path, and where the cue ball stopped in [`PLOT_SAMPLES`] plays of it under the
/// noise (draws of their own: other sample numbers than the plan's).
fn plot_plan(
    engine: &mut ShotEngine,
    config: &StudyConfig,
    planned: &Plan,
    options: &PlanOptions,
) -> Result<Vec<u8>, Error> {
    use kisstime::plan::context_of;
    use kisstime::plan::in_hand::at;
    use kisstime::study::{RunOptions, Samples, noisy_strike_of, run};
    let best = &planned.ranked[0];
    let placed = planned
        .placement
        .map_or_else(|| config.clone(), |p| at(config, p));
    let r = placed.params.ball.r;
    let first = 3 << 40;
    let strikes: Vec<_> = (first..first + PLOT_SAMPLES as u64)
        .map(|i| noisy_strike_of(best.candidate.strike, r, &options.noise, options.seed, i))
        .collect();
    let contexts = vec![context_of(&placed, &best.candidate); PLOT_SAMPLES];
    let samples = Samples::Judged {
        strikes: &strikes,
        contexts: &contexts,
    };
    let done = run(
        engine,
        &placed,
        samples,
        &RunOptions::default(),
        &mut |_, _| {},
    )?;
    let cloud: Vec<(f64, f64)> = done
        .iter()
        .filter(|s| s.pocket_of(placed.cue).is_none())
        .map(|s| s.cue_final)
        .collect();
    let balls: Vec<BallState> = placed
        .balls
        .iter()
        .map(|b| BallState::at_rest(b.x, b.y, r))
        .collect();
    let ids: Vec<i64> = placed
        .game
        .as_ref()
        .map_or_else(Vec::new, |g| g.ids.clone());
    let e = &best.estimate;
    let label = format!(
        "{}: P(keep) {:.3}, P(foul) {:.3}, value {:.3}",
        shot_name(config, best),
        e.p_keep().0,
        e.p_foul().0,
        e.value()
    );
    super::shot_plot::render_shot_png(
        &placed.table,
        placed.params,
        kisstime::simulate::Limits::default(),
        &balls,
        &ids,
        Some((placed.cue, best.candidate.strike)),
        &label,
        &cloud,
    )
}

/// The shot a candidate tries, in words: `3 -> rt (cut 12.3°)`, `bank 3 -> rc off 3`,
/// `combo 1-9 -> lb`, `kick off 15 at 4`, `safety: hit 2 full` (cushions by their ids).
fn shot_name(config: &StudyConfig, r: &Ranked) -> String {
    let ball = &config.balls[r.candidate.kind.ball()].id;
    match r.candidate.kind {
        Kind::Pot { pocket, .. } => format!(
            "{ball} -> {} (cut {:.1}°)",
            config.table.pocket_ids[pocket], r.candidate.aim.cut
        ),
        Kind::Bank { pocket, rail, .. } => format!(
            "bank {ball} -> {} off {}",
            config.table.pocket_ids[pocket], config.table.linear_ids[rail]
        ),
        Kind::Combo { first, pocket, .. } => format!(
            "combo {}-{ball} -> {}",
            config.balls[first].id, config.table.pocket_ids[pocket]
        ),
        Kind::Kick { rail, .. } => format!("kick off {} at {ball}", config.table.linear_ids[rail]),
        Kind::Break { .. } => format!("break at {ball} (cut {:.1}°)", r.candidate.aim.cut),
        Kind::Safety { .. } if r.candidate.aim.cut == 0.0 => format!("safety: hit {ball} full"),
        Kind::Safety { .. } => format!("safety: hit {ball} thin"),
    }
}

/// The ranked finalists as a text table.
fn plan_table(config: &StudyConfig, planned: &Plan) -> String {
    let mut out = format!(
        "{:<4} {:<22} {:>5} {:>8} {:>5} {:>5} {:>5}  {:<22} {:>7} {:>9} {:>8} {:>6}\n",
        "rank",
        "shot",
        "V0",
        "phi",
        "theta",
        "a",
        "b",
        "P(keep) [95%]",
        "P(foul)",
        "P(scratch)",
        "position",
        "value"
    );
    for (k, r) in planned.ranked.iter().enumerate() {
        let s = r.candidate.strike;
        let e = &r.estimate;
        let (keep, lo, hi) = e.p_keep();
        out.push_str(&format!(
            "{:<4} {:<22} {:>5.2} {:>8.3} {:>5.1} {:>5.2} {:>5.2}  {:<22} {:>7.3} {:>9.3} {:>8.2} {:>6.3}\n",
            k + 1,
            shot_name(config, r),
            s.v0,
            s.phi,
            s.theta,
            s.a,
            s.b,
            format!("{keep:.3} [{lo:.3}, {hi:.3}]"),
            e.p_foul().0,
            e.p_scratch().0,
            e.position(),
            e.value()
        ));
    }
    let n = planned.ranked.first().map_or(0, |r| r.estimate.samples);
    out.push_str(&format!(
        "each finalist on {n} fresh samples; play rank 1\n"
    ));
    out
}

/// `kisstime play`: self-play between two agents, reported per agent.
pub fn run_play(args: &PlayArgs) -> Result<(), Error> {
    let rules = args.game.rules();
    let names: Vec<&str> = args.agents.split(',').map(str::trim).collect();
    if names.len() != 2 {
        return Err(InputError::new(format!(
            "--agents {}: two agents joined by ',' (greedy, sampler, planner)",
            args.agents
        ))
        .into());
    }
    let agent = |n: &str| Agent::from_name(n).map_err(|e| Error::from(InputError::new(e)));
    let agents = [agent(names[0])?, agent(names[1])?];
    let options = PlayOptions {
        rules,
        games: args.games,
        agents,
        noise: noise_of(&args.noise.noise, args.noise.noise_scale)?,
        seed: args.seed,
        budget: parse_budget(&args.budget)?,
        max_shots: args.max_shots,
    };
    let mut engine = ShotEngine::new(args.backend.backend(), Precision::F64)?;
    let started = std::time::Instant::now();
    let bar = super::progress::Progress::new("playing", args.games as u64, "games", true);
    let report = play(&mut engine, &options, &mut |done| bar.set(done as u64))?;
    bar.done();
    eprintln!(
        "kisstime: {} games of {} in {:.1} s on {}",
        report.games,
        rules.name(),
        started.elapsed().as_secs_f64(),
        engine.describe()
    );
    let labels = [
        format!("{} (player 1)", agents[0].name()),
        format!("{} (player 2)", agents[1].name()),
    ];
    if args.json {
        let players: Vec<serde_json::Value> = report
            .players
            .iter()
            .zip(&labels)
            .map(|(p, label)| player_json(label, p, &report))
            .collect();
        println!(
            "{}",
            serde_json::json!({
                "game": rules.name(),
                "games": report.games,
                "draws": report.draws,
                "off_table": report.off_table,
                "players": players,
            })
        );
    } else {
        print!("{}", play_table(&report, &labels));
    }
    Ok(())
}

/// A player's figures: wins (with the 95 % interval), per visit, per game, decisions.
struct Figures {
    win: (f64, f64, f64),
    per_visit: f64,
    fouls_per_game: f64,
    break_and_run: f64,
    decision_mean: f64,
    decision_p95: f64,
}

fn figures(p: &PlayerStats, report: &PlayReport) -> Figures {
    let (lo, hi) = wilson(p.wins, report.games);
    let mut d = p.decisions.clone();
    d.sort_by(f64::total_cmp);
    let p95 = d
        .get(((d.len() as f64 * 0.95).ceil() as usize).saturating_sub(1))
        .copied()
        .unwrap_or(f64::NAN);
    Figures {
        win: (p.wins as f64 / report.games.max(1) as f64, lo, hi),
        per_visit: p.potted as f64 / p.visits.max(1) as f64,
        fouls_per_game: p.fouls as f64 / report.games.max(1) as f64,
        break_and_run: p.break_and_runs as f64 / p.breaks.max(1) as f64,
        decision_mean: d.iter().sum::<f64>() / d.len().max(1) as f64,
        decision_p95: p95,
    }
}

fn player_json(label: &str, p: &PlayerStats, report: &PlayReport) -> serde_json::Value {
    let f = figures(p, report);
    serde_json::json!({
        "agent": label,
        "wins": p.wins,
        "win_rate": [f.win.0, f.win.1, f.win.2],
        "visits": p.visits,
        "potted": p.potted,
        "potted_per_visit": f.per_visit,
        "fouls": p.fouls,
        "fouls_per_game": f.fouls_per_game,
        "foul_kinds": foul_kinds(p),
        "breaks": p.breaks,
        "break_and_runs": p.break_and_runs,
        "break_and_run_rate": f.break_and_run,
        "decisions": p.decisions.len(),
        "decision_mean_s": f.decision_mean,
        "decision_p95_s": f.decision_p95,
    })
}

fn play_table(report: &PlayReport, labels: &[String; 2]) -> String {
    let mut out = format!(
        "{:<22} {:>5} {:<24} {:>12} {:>14} {:>14} {:>15} {:>12}\n",
        "agent",
        "wins",
        "win rate [95%]",
        "pots/visit",
        "fouls/game",
        "break & run",
        "decision mean",
        "p95"
    );
    for (p, label) in report.players.iter().zip(labels) {
        let f = figures(p, report);
        out.push_str(&format!(
            "{:<22} {:>5} {:<24} {:>12.2} {:>14.2} {:>14} {:>13.3} s {:>10.3} s\n",
            label,
            p.wins,
            format!("{:.3} [{:.3}, {:.3}]", f.win.0, f.win.1, f.win.2),
            f.per_visit,
            f.fouls_per_game,
            format!("{}/{}", p.break_and_runs, p.breaks),
            f.decision_mean,
            f.decision_p95
        ));
    }
    for (p, label) in report.players.iter().zip(labels) {
        let kinds: Vec<String> = foul_kinds(p)
            .iter()
            .filter(|(_, n)| *n > 0)
            .map(|(code, n)| format!("{code} {n}"))
            .collect();
        if !kinds.is_empty() {
            out.push_str(&format!("{label} fouls: {}\n", kinds.join(", ")));
        }
    }
    out.push_str(&format!(
        "{} games, {} drawn at the shot cap; {} balls ended a shot off the table\n",
        report.games, report.draws, report.off_table
    ));
    out
}

/// A player's fouls by code (the rules' codes, then `cue_off_table`).
fn foul_kinds(p: &PlayerStats) -> Vec<(&'static str, usize)> {
    kisstime::game::Foul::ALL
        .iter()
        .map(|f| f.code())
        .chain(["cue_off_table"])
        .zip(p.foul_kinds)
        .collect()
}
