//! Self-play: whole games of 8-ball or 9-ball between two agents ([`super::agents`]) on
//! kisstime's own simulator, every shot played under the cue noise and judged by the
//! game's rules (pooltool 0.6.0's, [`crate::game`]).
//!
//! A game: the rack on the 9-ft table (9-ball a diamond, the 1 at the foot spot and the 9
//! in the middle; 8-ball a triangle, the 8 in the middle), the breaker (alternating from
//! game to game) breaks from the head string's centre at 8 m/s (the planner chooses its own
//! spot and strike: [`super::breaks`]), under the noise; then each
//! shot is the shooter's agent's choice plus the noise, simulated to rest and judged, and
//! the game goes on as [`crate::game::progress`] says (the turn, ball in hand, 8-ball's
//! groups, the 9 spotted again, balls off the table). After a foul the next player has the
//! cue ball in hand: greedy and the sampler place it where the easiest direct pot is
//! easiest ([`place_cue`]); the planner chooses the placement with the shot
//! ([`super::in_hand`]). A game is over when the verdict says so, or drawn at
//! [`PlayOptions::max_shots`].
//!
//! A ball can end a shot off the playing surface without being pocketed (seen in
//! self-play: a ball at (5.6, −3.4) m after a 9-ball shot; whether pooltool lets the same
//! shot through is not yet checked); [`PlayReport::off_table`] counts them.

use std::time::Instant;

use super::agents::{Agent, Choice, best_ease, choice_of, choose};
use super::breaks::plan_break;
use super::in_hand::{InHand, plan_in_hand};
use super::{Budget, PlanOptions, position};
use crate::engine::ShotEngine;
use crate::error::{Error, InputError};
use crate::game::progress::{Call, FOOT_SPOT, GameState, MAX_IDS};
use crate::game::{Foul, Rules};
use crate::gpu::GpuShot;
use crate::model::sim_params::SimParams;
use crate::model::table::Table;
use crate::resolve::stick_ball::CueStrike;
use crate::simulate::Limits;
use crate::study::{Noise, StudyConfig, mix, noisy_strike_of};

/// How self-play runs.
#[derive(Clone, Debug, PartialEq)]
pub struct PlayOptions {
    /// The game: 8-ball or 9-ball.
    pub rules: Rules,
    /// Games to play.
    pub games: usize,
    /// The two players' agents (player 0 breaks the even games).
    pub agents: [Agent; 2],
    /// The cue noise every shot is played under.
    pub noise: Noise,
    /// The seed of everything random (the noise of every shot, the agents' draws).
    pub seed: u64,
    /// The planner's budget per decision.
    pub budget: Budget,
    /// Shots after which a game is drawn.
    pub max_shots: usize,
}

/// One player's figures over the games.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlayerStats {
    /// Games won.
    pub wins: usize,
    /// Turns at the table (the break's included).
    pub visits: usize,
    /// Object balls pocketed on legal shots.
    pub potted: usize,
    /// Fouls (the rules' and a cue ball off the table).
    pub fouls: usize,
    /// Fouls by kind: the rules' codes in the order of [`crate::game::Foul::ALL`], then
    /// the cue ball off the table.
    pub foul_kinds: [usize; 9],
    /// Games won from the break without the opponent's visit.
    pub break_and_runs: usize,
    /// Games this player broke.
    pub breaks: usize,
    /// Each decision's wall-clock seconds (breaks excluded).
    pub decisions: Vec<f64>,
}

/// Self-play's result.
#[derive(Clone, Debug, PartialEq)]
pub struct PlayReport {
    /// Games played.
    pub games: usize,
    /// Games drawn at the shot cap.
    pub draws: usize,
    /// Balls that ended a shot off the playing surface without being pocketed (module
    /// docs).
    pub off_table: usize,
    /// Each player's figures.
    pub players: [PlayerStats; 2],
}

/// Plays `options.games` games on `engine` (module docs); `progress(games done)` after
/// each. Errors: a game other than 8-ball and 9-ball, no game, a simulation failure.
pub fn play(
    engine: &mut ShotEngine,
    options: &PlayOptions,
    progress: &mut dyn FnMut(usize),
) -> Result<PlayReport, Error> {
    if !matches!(options.rules, Rules::EightBall | Rules::NineBall) {
        return Err(InputError::new(format!(
            "self-play plays 8-ball and 9-ball, not {}",
            options.rules.name()
        ))
        .into());
    }
    if options.games == 0 {
        return Err(InputError::new("0 games: play at least one").into());
    }
    let mut report = PlayReport {
        games: 0,
        draws: 0,
        off_table: 0,
        players: [PlayerStats::default(), PlayerStats::default()],
    };
    for g in 0..options.games {
        play_game(engine, options, g, &mut report)?;
        report.games += 1;
        progress(g + 1);
    }
    Ok(report)
}

fn play_game(
    engine: &mut ShotEngine,
    options: &PlayOptions,
    g: usize,
    report: &mut PlayReport,
) -> Result<(), Error> {
    let table = Table::nine_foot();
    let params = SimParams::default();
    let r = params.ball.r;
    let rules = options.rules;
    let breaker = g % 2;
    let mut game = GameState::rack(rules, r, breaker)?;
    report.players[breaker].breaks += 1;
    report.players[breaker].visits += 1;
    let mut other_visited = false;
    let game_seed = mix(options.seed, g as u64);
    let mut ids = [0i64; MAX_IDS];
    let mut states = [game.balls[0]; MAX_IDS];
    for shot in 0..options.max_shots {
        let s = game.shooter;
        // in hand: placed where the easiest pot is easiest; the planner places it itself
        let in_hand = game.in_hand;
        if in_hand {
            place_cue(&mut game, &table, params)?;
        }
        // the position of the game's balls as the planner sees it
        let position_of = |game: &GameState, ids: &mut [i64; MAX_IDS], states: &mut _| {
            let n = game.layout(ids, states);
            let config = position(
                &table,
                "9ft",
                params,
                (&ids[..n], &states[..n]),
                rules,
                game.context(),
            );
            config.map(|c| (n, c))
        };
        let (mut n, mut config) = position_of(&game, &mut ids, &mut states)?;
        let choice = if game.break_shot && options.agents[s] == Agent::Planner {
            // the planner's own break: the spot and the strike
            let plan_options = PlanOptions {
                noise: options.noise,
                seed: mix(game_seed, 0),
                budget: options.budget,
                finalists: 3,
                ..PlanOptions::default()
            };
            let planned = plan_break(engine, &config, &plan_options)?;
            if let Some((x, y)) = planned.placement {
                game.place_cue(x, y);
                (n, config) = position_of(&game, &mut ids, &mut states)?;
            }
            choice_of(&planned.ranked[0].candidate)
        } else if game.break_shot {
            break_choice(&config)
        } else {
            let started = Instant::now();
            let agent_seed = mix(game_seed, 1 + shot as u64);
            let c = if in_hand && options.agents[s] == Agent::Planner {
                let plan_options = PlanOptions {
                    noise: options.noise,
                    seed: agent_seed,
                    budget: options.budget,
                    finalists: 3,
                    ..PlanOptions::default()
                };
                let planned = plan_in_hand(engine, &config, &plan_options, InHand::Anywhere)?;
                if let Some((x, y)) = planned.placement {
                    game.place_cue(x, y);
                    (n, config) = position_of(&game, &mut ids, &mut states)?;
                }
                choice_of(&planned.ranked[0].candidate)
            } else {
                choose(
                    options.agents[s],
                    engine,
                    &config,
                    &options.noise,
                    options.budget,
                    agent_seed,
                )?
            };
            report.players[s]
                .decisions
                .push(started.elapsed().as_secs_f64());
            c
        };
        // the shot as played: the choice plus the noise
        let played = noisy_strike_of(choice.strike, r, &options.noise, game_seed, shot as u64);
        // the game's balls are all on the table: the position's are they, in their order
        let shots = [GpuShot {
            balls: states[..n].to_vec(),
            strike: Some((config.cue, played)),
        }];
        let run = engine
            .simulate(&table, params, Limits::default(), &shots, true)
            .map_err(|e| match e {
                crate::simulate::BatchError::Table { error, .. } => Error::from(error),
                crate::simulate::BatchError::Sink(e) => e,
            })?
            .remove(0);
        let call = match choice.call {
            Some((ball, pocket)) if rules == Rules::EightBall => Call::Given {
                ball: ids[ball],
                pocket,
            },
            _ => Call::None,
        };
        let done = game.apply(&table, &run.events, &run.balls, call)?;
        report.off_table += done.off.count_ones() as usize;
        let verdict = done.verdict;
        let stats = &mut report.players[s];
        if let Some(f) = verdict.foul {
            let k = Foul::ALL
                .iter()
                .position(|x| *x == f)
                .expect("a foul of ALL");
            stats.foul_kinds[k] += 1;
        }
        if done.cue_off {
            stats.foul_kinds[8] += 1;
        }
        stats.fouls += usize::from(done.fouled());
        if verdict.legal {
            stats.potted += done.potted.count_ones() as usize;
        }
        if let Some(winner) = game.winner {
            report.players[winner].wins += 1;
            if winner == breaker && !other_visited {
                report.players[winner].break_and_runs += 1;
            }
            return Ok(());
        }
        if game.shooter != s {
            report.players[game.shooter].visits += 1;
            if game.shooter != breaker {
                other_visited = true;
            }
        }
    }
    report.draws += 1;
    Ok(())
}

/// The break: from where the cue ball is, at the rack's apex, 8 m/s, centre ball.
pub fn break_choice(config: &StudyConfig) -> Choice {
    let cue = (config.balls[config.cue].x, config.balls[config.cue].y);
    Choice {
        strike: CueStrike {
            v0: 8.0,
            phi: (FOOT_SPOT.1 - cue.1)
                .atan2(FOOT_SPOT.0 - cue.0)
                .to_degrees()
                .rem_euclid(360.0),
            theta: 0.0,
            a: 0.0,
            b: 0.0,
        },
        call: None,
    }
}

/// The cue ball in hand: placed on a grid over the table (10 cm apart, clear of every
/// ball by 1 mm) where the easiest direct pot is easiest.
pub fn place_cue(game: &mut GameState, table: &Table, params: SimParams) -> Result<(), Error> {
    let context = game.context();
    let mut ids = [0i64; MAX_IDS];
    let mut states = [game.balls[0]; MAX_IDS];
    let mut best: Option<((f64, f64), f64)> = None;
    for i in 0..12 {
        for j in 0..24 {
            let p = (0.08 + 0.1 * i as f64, 0.08 + 0.1 * j as f64);
            if p.0 > crate::workload::TABLE_WIDTH - 0.05
                || p.1 > crate::workload::TABLE_LENGTH - 0.05
                || !game.is_free(table, p.0, p.1, 1e-3)
            {
                continue;
            }
            let mut placed = *game;
            placed.place_cue(p.0, p.1);
            let n = placed.layout(&mut ids, &mut states);
            let Ok(config) = position(
                table,
                "9ft",
                params,
                (&ids[..n], &states[..n]),
                game.rules,
                context,
            ) else {
                continue;
            };
            let ease = best_ease(&config);
            if best.is_none_or(|(_, e)| ease > e) {
                best = Some((p, ease));
            }
        }
    }
    let (p, _) = best.ok_or_else(|| InputError::new("no free spot for the cue ball in hand"))?;
    game.place_cue(p.0, p.1);
    Ok(())
}
