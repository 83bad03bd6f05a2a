//! Self-play: whole games of 8-ball or 9-ball between two agents ([`super::agents`]) on
//! kisstime's own simulator, every shot played under the cue noise and judged by the
//! game's rules (pooltool 0.6.0's, [`crate::game`]).
//!
//! A game: the rack on the 9-ft table (9-ball a diamond, the 1 at the foot spot and the 9
//! in the middle; 8-ball a triangle, the 8 in the middle), the breaker (alternating from
//! game to game) breaks from the head string's centre at 8 m/s, under the noise; then each
//! shot is the shooter's agent's choice plus the noise, simulated to rest and judged. The
//! turn passes when the verdict says so; after a foul the next player has the cue ball in
//! hand, placed anywhere where the easiest direct pot is easiest (the same rule for every
//! agent). 8-ball: the table is open until a legal shot pots a ball, whose group (1–7 or
//! 9–15) the shooter then takes; with the group down, the 8. 9-ball: the 9 pocketed
//! without winning is spotted again. A game is over when the verdict says so, or drawn at
//! [`PlayOptions::max_shots`].
//!
//! Simplified against the WPA's rules: the cue ball in hand anywhere (also after a
//! scratch on the break), no push-out, no three-foul rule, no safety called.
//!
//! A ball can end a shot off the playing surface without being pocketed (seen in
//! self-play: a ball at (5.6, −3.4) m after a 9-ball shot; whether pooltool lets the same
//! shot through is not yet checked). Such a ball is off the table, as a jumped ball: an
//! object ball stays off (the 9, or the 8, is spotted again), the cue ball off is a foul
//! (ball in hand); [`PlayReport::off_table`] counts them.

use std::time::Instant;

use super::agents::{Agent, Choice, best_ease, choose};
use super::{Budget, position};
use crate::engine::ShotEngine;
use crate::error::{Error, InputError};
use crate::game::{Context, Foul, Rules, Shot};
use crate::gpu::GpuShot;
use crate::io::context::default_context;
use crate::model::MotionState;
use crate::model::ball_state::BallState;
use crate::model::sim_params::SimParams;
use crate::model::table::Table;
use crate::resolve::stick_ball::CueStrike;
use crate::simulate::Limits;
use crate::simulate::check::check_on_table;
use crate::study::{Noise, StudyConfig, noisy_strike_of};
use crate::workload::{FOOT_SPOT, HEAD_STRING_Y};

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

/// A game's state between shots.
struct Game {
    /// The balls on the table by id (ascending: pooltool's order), the cue ball id 0
    /// (absent while in hand).
    balls: Vec<(i64, BallState)>,
    shooter: usize,
    in_hand: bool,
    break_shot: bool,
    /// 8-ball: each player's group, once taken.
    groups: Option<[u32; 2]>,
}

const SOLIDS: [i64; 7] = [1, 2, 3, 4, 5, 6, 7];
const STRIPES: [i64; 7] = [9, 10, 11, 12, 13, 14, 15];

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
    let mut game = Game {
        balls: rack(rules, r),
        shooter: breaker,
        in_hand: false,
        break_shot: true,
        groups: None,
    };
    report.players[breaker].breaks += 1;
    report.players[breaker].visits += 1;
    let mut other_visited = false;
    let game_seed = mix(options.seed, g as u64);
    for shot in 0..options.max_shots {
        let s = game.shooter;
        if game.in_hand || !game.balls.iter().any(|(id, _)| *id == 0) {
            place_cue(&mut game, &table, params, rules)?;
        }
        let context = context_of(&game, rules);
        let (ids, states): (Vec<i64>, Vec<BallState>) = game.balls.iter().copied().unzip();
        let config = position(&table, "9ft", params, (&ids, &states), rules, context)?;
        let choice = if game.break_shot {
            break_choice(&config)
        } else {
            let started = Instant::now();
            let agent_seed = mix(game_seed, 1 + shot as u64);
            let c = choose(
                options.agents[s],
                engine,
                &config,
                &options.noise,
                options.budget,
                agent_seed,
            )?;
            report.players[s]
                .decisions
                .push(started.elapsed().as_secs_f64());
            c
        };
        // the shot as played: the choice plus the noise
        let played = noisy_strike_of(choice.strike, r, &options.noise, game_seed, shot as u64);
        let cue = config.cue;
        // the game's balls are all on the table: the position's are they, in their order
        let shots = [GpuShot {
            balls: states.clone(),
            strike: Some((cue, played)),
        }];
        let run = engine
            .simulate(&table, params, Limits::default(), &shots, true)
            .map_err(|e| match e {
                crate::simulate::BatchError::Table { error, .. } => Error::from(error),
                crate::simulate::BatchError::Sink(e) => e,
            })?
            .remove(0);
        let game_ids = &ids;
        let mut judged_context = config.game.as_ref().expect("a game").context;
        if rules == Rules::EightBall && !game.break_shot {
            judged_context.ball_call = choice.call.map(|(b, _)| game_ids[b]);
            judged_context.pocket_call = choice.call.map(|(_, p)| p);
        }
        let verdict = rules.judge(
            &Shot {
                ids: game_ids,
                start: &states,
                events: &run.events,
            },
            &judged_context,
        )?;
        // the balls after it; a ball that left the playing surface unpocketed is off the
        // table (the cue ball: a foul)
        let potted: Vec<i64> = game_ids
            .iter()
            .zip(&run.balls)
            .filter(|(_, b)| b.s == MotionState::Pocketed)
            .map(|(id, _)| *id)
            .collect();
        let on_surface = |b: &BallState| check_on_table(&table, r, b.r).is_ok();
        let off: Vec<i64> = game_ids
            .iter()
            .zip(&run.balls)
            .filter(|(_, b)| b.s != MotionState::Pocketed && !on_surface(b))
            .map(|(id, _)| *id)
            .collect();
        report.off_table += off.len();
        game.balls = game_ids
            .iter()
            .copied()
            .zip(run.balls.iter().copied())
            .filter(|(_, b)| b.s != MotionState::Pocketed && on_surface(b))
            .map(|(id, b)| (id, BallState { t: 0.0, ..b }))
            .collect();
        let mut verdict = verdict;
        let cue_off = off.contains(&0) && verdict.foul.is_none();
        if cue_off {
            verdict.legal = false;
            verdict.turn_over = true;
        }
        let stats = &mut report.players[s];
        if let Some(f) = verdict.foul {
            let k = Foul::ALL
                .iter()
                .position(|x| *x == f)
                .expect("a foul of ALL");
            stats.foul_kinds[k] += 1;
        }
        if cue_off {
            stats.foul_kinds[8] += 1;
        }
        stats.fouls += usize::from(verdict.foul.is_some() || cue_off);
        if verdict.legal {
            stats.potted += potted.iter().filter(|&&id| id > 0).count();
        }
        if verdict.game_over {
            let winner = if verdict.won { s } else { 1 - s };
            report.players[winner].wins += 1;
            if winner == breaker && !other_visited {
                report.players[winner].break_and_runs += 1;
            }
            return Ok(());
        }
        // 8-ball: the first legal pot after the break takes its group
        if rules == Rules::EightBall
            && game.groups.is_none()
            && !game.break_shot
            && verdict.legal
            && !verdict.turn_over
            && let Some(&first) = potted.iter().find(|&&id| id > 0 && id != 8)
        {
            let (mine, theirs) = if first < 8 {
                (SOLIDS, STRIPES)
            } else {
                (STRIPES, SOLIDS)
            };
            let mut groups = [0; 2];
            groups[s] = Context::balls(mine);
            groups[1 - s] = Context::balls(theirs);
            game.groups = Some(groups);
        }
        // a 9 (or 8) pocketed or off the table without ending the game comes back
        let spotted = if rules == Rules::NineBall { 9 } else { 8 };
        if potted.contains(&spotted) || off.contains(&spotted) {
            respot(&mut game, spotted, r);
        }
        game.break_shot = false;
        game.in_hand = verdict.foul.is_some() || cue_off;
        if verdict.turn_over {
            game.shooter = 1 - s;
            report.players[game.shooter].visits += 1;
            if game.shooter != breaker {
                other_visited = true;
            }
        }
    }
    report.draws += 1;
    Ok(())
}

/// The shooter's context: the break; 9-ball's (worked out from the table); 8-ball's
/// group, the open table before one is taken, the 8 with the group down.
fn context_of(game: &Game, rules: Rules) -> Context {
    let mut c = default_context(rules);
    c.break_shot = game.break_shot;
    if rules == Rules::EightBall
        && let Some(groups) = game.groups
    {
        c.hittable = groups[game.shooter];
    }
    c
}

/// The break: from where the cue ball is, at the rack's apex, 8 m/s, centre ball.
fn break_choice(config: &StudyConfig) -> Choice {
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

/// The rack (module docs), the cue ball on the head string's centre, a little behind it;
/// neighbours 2R + 1 µm apart.
fn rack(rules: Rules, r: f64) -> Vec<(i64, BallState)> {
    let d = 2.0 * r + 1e-6;
    let row_y = |row: usize| FOOT_SPOT.1 + row as f64 * d * 3f64.sqrt() / 2.0;
    let spot = |row: usize, i: usize, n: usize| {
        (
            FOOT_SPOT.0 + (i as f64 - (n - 1) as f64 / 2.0) * d,
            row_y(row),
        )
    };
    let mut balls = vec![(0, BallState::at_rest(0.635, HEAD_STRING_Y - 0.1, r))];
    let place = |order: &[&[i64]]| -> Vec<(i64, BallState)> {
        let mut out = Vec::new();
        for (row, ids) in order.iter().enumerate() {
            for (i, &id) in ids.iter().enumerate() {
                let (x, y) = spot(row, i, ids.len());
                out.push((id, BallState::at_rest(x, y, r)));
            }
        }
        out
    };
    balls.extend(match rules {
        Rules::NineBall => place(&[&[1], &[2, 3], &[4, 9, 5], &[6, 7], &[8]]),
        _ => place(&[
            &[1],
            &[9, 2],
            &[10, 8, 3],
            &[11, 4, 12, 5],
            &[6, 13, 7, 14, 15],
        ]),
    });
    balls.sort_by_key(|(id, _)| *id);
    balls
}

/// The cue ball in hand: placed on a grid over the table (10 cm apart, clear of every
/// ball by 1 mm) where the easiest direct pot is easiest.
fn place_cue(game: &mut Game, table: &Table, params: SimParams, rules: Rules) -> Result<(), Error> {
    let r = params.ball.r;
    game.balls.retain(|(id, _)| *id != 0);
    let context = context_of(game, rules);
    let mut best: Option<((f64, f64), f64)> = None;
    for i in 0..12 {
        for j in 0..24 {
            let p = (0.08 + 0.1 * i as f64, 0.08 + 0.1 * j as f64);
            if p.0 > crate::workload::TABLE_WIDTH - 0.05
                || p.1 > crate::workload::TABLE_LENGTH - 0.05
            {
                continue;
            }
            let clear = game
                .balls
                .iter()
                .all(|(_, b)| (b.r.x - p.0).hypot(b.r.y - p.1) > 2.0 * r + 1e-3);
            if !clear {
                continue;
            }
            let mut balls = game.balls.clone();
            balls.insert(0, (0, BallState::at_rest(p.0, p.1, r)));
            let (ids, states): (Vec<i64>, Vec<BallState>) = balls.into_iter().unzip();
            let Ok(config) = position(table, "9ft", params, (&ids, &states), rules, context) else {
                continue;
            };
            let ease = best_ease(&config);
            if best.is_none_or(|(_, e)| ease > e) {
                best = Some((p, ease));
            }
        }
    }
    let (p, _) = best.ok_or_else(|| InputError::new("no free spot for the cue ball in hand"))?;
    game.balls.insert(0, (0, BallState::at_rest(p.0, p.1, r)));
    game.in_hand = false;
    Ok(())
}

/// Ball `id` back on the table: on the foot spot, or the first free point behind it.
fn respot(game: &mut Game, id: i64, r: f64) {
    let mut y = FOOT_SPOT.1;
    while game
        .balls
        .iter()
        .any(|(_, b)| (b.r.x - FOOT_SPOT.0).hypot(b.r.y - y) <= 2.0 * r + 1e-3)
    {
        y += 0.01;
    }
    game.balls.push((id, BallState::at_rest(FOOT_SPOT.0, y, r)));
    game.balls.sort_by_key(|(i, _)| *i);
}

/// SplitMix64 of a seed and a counter.
fn mix(seed: u64, k: u64) -> u64 {
    let mut z = seed
        .wrapping_add(0x9e37_79b9_7f4a_7c15)
        .wrapping_add(k.wrapping_mul(0xbf58_476d_1ce4_e5b9));
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}
