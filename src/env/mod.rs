//! Learning environments: many games of pool stepped at once, for reinforcement-learning
//! agents (Python's `kisstime.gym` wraps this as a Gymnasium vector environment).
//!
//! A [`VecEnv`] holds `tables` games ([`crate::game::progress::GameState`]) of one
//! [`Task`] — 8-ball, 9-ball, or a drill (pot the balls of a random position) — and steps
//! them all with one engine call: each table's action ([`ACTION_LOW`] to [`ACTION_HIGH`],
//! [`ACTION_NAMES`]) is played under the cue noise, simulated to rest on the engine's
//! backend, judged by the game's rules (pooltool 0.6.0's) and applied to its game.
//!
//! **Seats.** The learner is player 0 of every table. Against an [`Opponent`] (a built-in
//! agent of [`crate::plan::agents`], or a policy the caller passes in as a function) the
//! opponent's turns are played inside [`VecEnv::step`] (and [`VecEnv::reset`], when it
//! breaks), so the learner sees only its own turns; breaks alternate from episode to
//! episode. With [`Opponent::SelfPlay`] the learner plays both seats, and the observation
//! says whose turn it is. A drill has one player.
//!
//! **Rewards** ([`Rewards`]), to the player who shot: `pot` for each of its own balls
//! pocketed on a legal shot ([`crate::game::progress::ShotResult::own_potted`]), `foul`
//! for a foul (the cue ball off the table included), `win` or `loss` when the game ends
//! (also when the opponent's shot ends it). 8-ball shots are called as they go
//! ([`crate::game::progress::Call::AsPlayed`]).
//!
//! **Episodes** end when the game is over (terminated) or at [`EnvOptions::max_shots`]
//! shots of both players (truncated). The next step of a table whose episode ended resets
//! it (its action is ignored; reward 0; Gymnasium's "next step" autoreset).
//!
//! **Reproducible**: table `k`'s episode `e` draws its drill position and every shot's
//! noise from `(seeds[k], e, shot)` alone ([`VecEnv::reset`]; Python gives table `k` the
//! seed `seed + k`, Gymnasium's convention, so that a table of a vector environment plays
//! as a single environment seeded so), so a run is the same bit for bit for the same
//! seed and actions, whatever the thread count and on the CPU; on the GPU (f64) the
//! positions agree to the simulation's ~1e-12 s (docs/gpu.md) and the verdicts are the
//! same.

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use rayon::prelude::*;

use crate::engine::ShotEngine;
use crate::error::{Error, InputError};
use crate::game::Rules;
use crate::game::progress::{Call, GameState, MAX_IDS, ShotResult};
use crate::model::ball_state::BallState;
use crate::model::sim_params::SimParams;
use crate::model::table::Table;
use crate::plan::agents::{Agent, choose};
use crate::plan::play::{break_choice, place_cue};
use crate::plan::{Budget, position};
use crate::resolve::stick_ball::CueStrike;
use crate::simulate::{BatchError, BatchOptions, Limits};
use crate::study::{Noise, mix, noisy_strike_of};
use crate::workload::{TABLE_LENGTH, TABLE_WIDTH};

/// The action's components, in order.
pub const ACTION_NAMES: [&str; 7] = ["V0", "phi", "theta", "a", "b", "x", "y"];
/// The lower bounds of the action: V0 (m/s), φ (degrees), θ (degrees), a and b (the tip's
/// offsets as fractions of the ball's radius, pooltool's `Cue`), the cue ball's placement
/// x and y (m; used only with the cue ball in hand).
pub const ACTION_LOW: [f64; 7] = [0.0, 0.0, 0.0, -0.5, -0.5, 0.0, 0.0];
/// The upper bounds of the action ([`ACTION_LOW`]'s order). An action outside the bounds
/// is clipped into them; a NaN or infinite one is an error.
pub const ACTION_HIGH: [f64; 7] = [8.0, 360.0, 60.0, 0.5, 0.5, TABLE_WIDTH, TABLE_LENGTH];
/// Numbers per ball in an observation: x, y (m; 0 when off the table), on the table (0 or
/// 1), may be hit first by the player to shoot (0 or 1).
pub const PER_BALL: usize = 4;
/// The numbers after the balls in an observation: the cue ball in hand (0 or 1), the
/// break (0 or 1), the player to shoot (0 or 1), the shots played as a fraction of
/// [`EnvOptions::max_shots`].
pub const GLOBALS: [&str; 4] = ["in_hand", "break", "shooter", "shots"];
/// The most object balls of a drill.
pub const MAX_DRILL_BALLS: usize = 9;
/// The events after which a shot is cut by default: a break has ~200, an ordinary shot
/// ~25; balls frozen together can chatter through hundreds of thousands (seen in
/// self-play), which would stall a whole step.
pub const ENV_MAX_EVENTS: usize = 5_000;
/// The most episodes in a row the opponent may end before the learner's first shot
/// ([`VecEnv::reset`]).
pub const MAX_RESTARTS: usize = 64;
/// The most tables of one environment.
pub const MAX_TABLES: usize = 1 << 24;

/// What the tables play.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Task {
    /// 8-ball from the rack.
    EightBall,
    /// 9-ball from the rack.
    NineBall,
    /// One player pots `balls` object balls (the highest numbers up to the 9, lowest
    /// first, by 9-ball's rules: the 9 alone for one) from a random position, the cue ball
    /// anywhere; potting the 9 legally ends the episode.
    Drill {
        /// Object balls, 1 to [`MAX_DRILL_BALLS`].
        balls: usize,
    },
}

impl Task {
    /// The game whose rules judge the task's shots.
    pub fn rules(self) -> Rules {
        match self {
            Task::EightBall => Rules::EightBall,
            Task::NineBall | Task::Drill { .. } => Rules::NineBall,
        }
    }

    /// The ball ids of the task's observation, in order (the cue ball first).
    pub fn ids(self) -> Vec<i64> {
        match self {
            Task::EightBall => (0..=15).collect(),
            Task::NineBall => (0..=9).collect(),
            Task::Drill { balls } => std::iter::once(0)
                .chain((10 - balls as i64).max(1)..=9)
                .collect(),
        }
    }

    /// Whether two players take turns.
    pub fn two_players(self) -> bool {
        !matches!(self, Task::Drill { .. })
    }
}

/// The rewards, to the player who shot (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rewards {
    /// For each own ball pocketed on a legal shot.
    pub pot: f64,
    /// For a foul.
    pub foul: f64,
    /// For a game won.
    pub win: f64,
    /// For a game lost.
    pub loss: f64,
}

impl Default for Rewards {
    /// +1 an own ball potted, −1 a foul, ±10 the game won or lost.
    fn default() -> Self {
        Rewards {
            pot: 1.0,
            foul: -1.0,
            win: 10.0,
            loss: -10.0,
        }
    }
}

/// Who plays the turns of player 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Opponent {
    /// The learner plays both seats (and a drill's one).
    SelfPlay,
    /// A built-in agent ([`Agent`]: greedy, sampler, planner).
    Agent(Agent),
    /// The caller's policy: [`VecEnv::step`]'s `policy` function.
    Policy,
}

/// How a [`VecEnv`] runs.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvOptions {
    /// What the tables play.
    pub task: Task,
    /// Tables, 1 to [`MAX_TABLES`].
    pub tables: usize,
    /// Shots of both players after which an episode is truncated (at least 1).
    pub max_shots: u32,
    /// The rewards.
    pub rewards: Rewards,
    /// The cue noise every shot is played under (none by default).
    pub noise: Noise,
    /// Who plays player 1 ([`Opponent::SelfPlay`] for a drill).
    pub opponent: Opponent,
    /// A built-in planner opponent's budget per decision.
    pub budget: Budget,
    /// Each shot's limits on events and time ([`ENV_MAX_EVENTS`] events by default).
    pub limits: Limits,
}

impl Default for EnvOptions {
    fn default() -> Self {
        EnvOptions {
            task: Task::NineBall,
            tables: 1,
            max_shots: 100,
            rewards: Rewards::default(),
            noise: Noise::default().scaled(0.0),
            opponent: Opponent::SelfPlay,
            budget: Budget::Samples(20_000),
            limits: Limits {
                max_events: ENV_MAX_EVENTS,
                ..Limits::default()
            },
        }
    }
}

/// What one step did to each table.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepReport {
    /// The reward to the learner (with [`Opponent::SelfPlay`]: to the player who shot).
    pub rewards: Vec<f64>,
    /// Whether the episode ended with the game over.
    pub terminated: Vec<bool>,
    /// Whether the episode was cut at [`EnvOptions::max_shots`].
    pub truncated: Vec<bool>,
    /// Whether this step reset the table (its episode had ended; the action was ignored).
    pub reset: Vec<bool>,
    /// Whether the learner's shot was a foul.
    pub fouled: Vec<bool>,
    /// Own balls the learner's shot pocketed.
    pub potted: Vec<u32>,
    /// Whether the learner has won (the game over and theirs).
    pub won: Vec<bool>,
    /// Shots the opponent played during the step.
    pub opponent_shots: Vec<u32>,
    /// Whether the learner's shot was cut by [`EnvOptions::limits`] (its moving balls
    /// stopped where they were: [`crate::game::progress`]).
    pub cut: Vec<bool>,
}

/// A policy for [`Opponent::Policy`]: given the tables where the opponent is to shoot
/// and their observations (one row of [`VecEnv::obs_len`] a table), their actions (one
/// row of 7 a table, [`ACTION_NAMES`]).
pub type Policy<'a> = dyn FnMut(&[usize], &[f32]) -> Result<Vec<f64>, Error> + 'a;

/// Many games stepped at once (module docs).
pub struct VecEnv {
    options: EnvOptions,
    table: Table,
    params: SimParams,
    ids: Vec<i64>,
    games: Vec<GameState>,
    seeds: Vec<u64>,
    episodes: Vec<u64>,
    ended: Vec<bool>,
}

/// One shot to play: the table, the strike as played (the noise in), the call.
#[derive(Clone, Copy)]
struct Planned {
    table: usize,
    strike: CueStrike,
    call: Call,
}

impl VecEnv {
    /// An environment of `options` (every table still to be [`VecEnv::reset`]). Errors:
    /// no table or more than [`MAX_TABLES`], `max_shots` 0, a drill of no ball or more than
    /// [`MAX_DRILL_BALLS`], a reward that is not finite, a noise σ negative or not finite,
    /// an opponent in a drill.
    pub fn new(options: EnvOptions) -> Result<VecEnv, Error> {
        let bad = |m: String| -> Result<VecEnv, Error> { Err(InputError::new(m).into()) };
        if options.tables == 0 || options.tables > MAX_TABLES {
            return bad(format!(
                "{} tables: an environment has 1 to {MAX_TABLES}",
                options.tables
            ));
        }
        if options.max_shots == 0 {
            return bad("max_shots 0: an episode has at least one shot".into());
        }
        if let Task::Drill { balls } = options.task
            && !(1..=MAX_DRILL_BALLS).contains(&balls)
        {
            return bad(format!(
                "a drill of {balls} balls: 1 to {MAX_DRILL_BALLS} object balls"
            ));
        }
        let r = &options.rewards;
        if ![r.pot, r.foul, r.win, r.loss].iter().all(|x| x.is_finite()) {
            return bad(format!("rewards must be finite numbers: {r:?}"));
        }
        let n = &options.noise;
        if ![n.v0, n.phi, n.theta, n.a, n.b]
            .iter()
            .all(|s| s.is_finite() && *s >= 0.0)
        {
            return bad("the noise's σ must be finite and non-negative".into());
        }
        if !options.task.two_players() && options.opponent != Opponent::SelfPlay {
            return bad("a drill has one player: no opponent".into());
        }
        let params = SimParams::default();
        let tables = options.tables;
        let placeholder = GameState::rack(options.task.rules(), params.ball.r, 0)?;
        Ok(VecEnv {
            ids: options.task.ids(),
            options,
            table: Table::nine_foot(),
            params,
            games: vec![placeholder; tables],
            seeds: (0..tables as u64).collect(),
            // no episode yet: the first is 0
            episodes: vec![u64::MAX; tables],
            ended: vec![true; tables],
        })
    }

    /// Its options.
    pub fn options(&self) -> &EnvOptions {
        &self.options
    }

    /// Tables.
    pub fn len(&self) -> usize {
        self.games.len()
    }

    /// Whether it has no table (never: [`VecEnv::new`] refuses none).
    pub fn is_empty(&self) -> bool {
        self.games.is_empty()
    }

    /// Table `k`'s game.
    pub fn game(&self, k: usize) -> &GameState {
        &self.games[k]
    }

    /// Numbers in one table's observation: [`PER_BALL`] for each of the task's balls
    /// ([`Task::ids`]), then [`GLOBALS`].
    pub fn obs_len(&self) -> usize {
        PER_BALL * self.ids.len() + GLOBALS.len()
    }

    /// Every table's observation into `out` (row `k` table `k`'s, [`VecEnv::obs_len`]
    /// numbers), from the point of view of the player to shoot.
    pub fn observe(&self, out: &mut [f32]) {
        let len = self.obs_len();
        out.par_chunks_mut(len)
            .zip(&self.games)
            .for_each(|(row, g)| self.observe_one(g, row));
    }

    /// One table's observation ([`VecEnv::observe`]).
    fn observe_one(&self, g: &GameState, row: &mut [f32]) {
        let hittable = g.hittable();
        for (slot, &id) in self.ids.iter().enumerate() {
            let o = &mut row[slot * PER_BALL..(slot + 1) * PER_BALL];
            let on = g.on_table & (1 << id) != 0;
            let b = g.balls[id as usize].r;
            o[0] = if on { b.x as f32 } else { 0.0 };
            o[1] = if on { b.y as f32 } else { 0.0 };
            o[2] = f32::from(u8::from(on));
            o[3] = f32::from(u8::from(id > 0 && hittable & (1 << id) != 0));
        }
        let tail = &mut row[self.ids.len() * PER_BALL..];
        tail[0] = f32::from(u8::from(g.in_hand));
        tail[1] = f32::from(u8::from(g.break_shot));
        tail[2] = g.shooter as f32;
        tail[3] = g.shots as f32 / self.options.max_shots as f32;
    }

    /// Starts a new episode on every table: with `seeds` (one a table), table `k`'s first
    /// episode from `seeds[k]` (module docs); without, each table's next episode (its
    /// seed going on). The opponent's break is played where it breaks. Returns how many
    /// opponent shots each table saw. Errors: a seed count other than the tables'.
    pub fn reset(
        &mut self,
        engine: &mut ShotEngine,
        seeds: Option<&[u64]>,
        policy: &mut Policy<'_>,
    ) -> Result<Vec<u32>, Error> {
        match seeds {
            Some(seeds) if seeds.len() != self.len() => {
                return Err(InputError::new(format!(
                    "{} seeds for {} tables: one a table",
                    seeds.len(),
                    self.len()
                ))
                .into());
            }
            Some(seeds) => {
                self.seeds.copy_from_slice(seeds);
                self.episodes.iter_mut().for_each(|e| *e = 0);
            }
            None => self
                .episodes
                .iter_mut()
                .for_each(|e| *e = e.wrapping_add(1)),
        }
        let all: Vec<usize> = (0..self.len()).collect();
        for &k in &all {
            self.start_episode(k)?;
        }
        let mut opponent_shots = vec![0; self.len()];
        self.begin(engine, &all, policy, &mut opponent_shots)?;
        Ok(opponent_shots)
    }

    /// Plays the opponent's opening turns on `tables`, just started: an episode begins
    /// with the learner to shoot, so one the opponent's turns end (a break that wins, or
    /// the shot cap) is followed by the next, up to [`MAX_RESTARTS`] times.
    fn begin(
        &mut self,
        engine: &mut ShotEngine,
        tables: &[usize],
        policy: &mut Policy<'_>,
        shots: &mut [u32],
    ) -> Result<(), Error> {
        let max = self.options.max_shots;
        let mut pending = tables.to_vec();
        for _ in 0..MAX_RESTARTS {
            self.opponent_turns(engine, &pending, policy, None, shots)?;
            pending.retain(|&k| self.games[k].over || self.games[k].shots >= max);
            if pending.is_empty() {
                return Ok(());
            }
            for &k in &pending {
                self.next_episode(k)?;
            }
        }
        Err(InputError::new(format!(
            "table {}: the opponent ended {MAX_RESTARTS} episodes in a row before the \
             learner's first shot (max_shots {max})",
            pending[0]
        ))
        .into())
    }

    /// Starts the next episode of every table whose episode ended (what [`VecEnv::step`]
    /// does first; for callers that want the new episode's observation at once: Gymnasium's
    /// "same step" autoreset). Returns which tables, and the opponent's shots on each.
    pub fn reset_ended(
        &mut self,
        engine: &mut ShotEngine,
        policy: &mut Policy<'_>,
    ) -> Result<(Vec<bool>, Vec<u32>), Error> {
        let ended = self.ended.clone();
        let which: Vec<usize> = (0..self.len()).filter(|&k| ended[k]).collect();
        for &k in &which {
            self.next_episode(k)?;
        }
        let mut opponent_shots = vec![0; self.len()];
        self.begin(engine, &which, policy, &mut opponent_shots)?;
        Ok((ended, opponent_shots))
    }

    /// Table `k`'s next episode, its seed going on.
    fn next_episode(&mut self, k: usize) -> Result<(), Error> {
        self.episodes[k] = self.episodes[k].wrapping_add(1);
        self.start_episode(k)
    }

    /// Table `k`'s next episode: the rack (the breaker alternating by episode) or the
    /// drill's random position.
    fn start_episode(&mut self, k: usize) -> Result<(), Error> {
        let r = self.params.ball.r;
        let e = self.episodes[k];
        self.games[k] = match self.options.task {
            Task::EightBall | Task::NineBall => {
                let breaker = if self.options.opponent == Opponent::SelfPlay {
                    0
                } else {
                    (e % 2) as usize
                };
                GameState::rack(self.options.task.rules(), r, breaker)?
            }
            Task::Drill { .. } => self.drill(self.episode_seed(k))?,
        };
        self.ended[k] = false;
        Ok(())
    }

    /// The seed of table `k`'s current episode.
    fn episode_seed(&self, k: usize) -> u64 {
        mix(self.seeds[k], self.episodes[k])
    }

    /// A drill's position: the cue ball and the object balls uniformly on the playing
    /// surface, at least 1 cm clear of each other (the first free draw of each, up to
    /// 1,000 tries).
    fn drill(&self, seed: u64) -> Result<GameState, Error> {
        let r = self.params.ball.r;
        let mut rng = Pcg64Mcg::seed_from_u64(seed);
        let mut balls: Vec<(i64, BallState)> = Vec::with_capacity(self.ids.len());
        for &id in &self.ids {
            let mut placed = None;
            for _ in 0..1000 {
                let x = rng.random_range(r..TABLE_WIDTH - r);
                let y = rng.random_range(r..TABLE_LENGTH - r);
                let game = GameState::from_balls(
                    Rules::NineBall,
                    &[(0, BallState::at_rest(0.0, 0.0, r))]
                        .into_iter()
                        .chain(balls.iter().copied().filter(|(i, _)| *i != 0))
                        .collect::<Vec<_>>(),
                    0,
                )?;
                let clear_of_cue = balls
                    .first()
                    .is_none_or(|(_, c)| (c.r.x - x).hypot(c.r.y - y) > 2.0 * r + 0.01);
                if clear_of_cue && game.is_free(&self.table, x, y, 0.01) {
                    placed = Some(BallState::at_rest(x, y, r));
                    break;
                }
            }
            let b = placed.ok_or_else(|| InputError::new("no room for a drill's ball"))?;
            balls.push((id, b));
        }
        GameState::from_balls(Rules::NineBall, &balls, 0)
    }

    /// Steps every table with `actions` (row `k`, 7 numbers, table `k`'s: [`ACTION_NAMES`];
    /// clipped into [`ACTION_LOW`]..[`ACTION_HIGH`]); `policy` plays
    /// [`Opponent::Policy`]'s turns. Errors: a row count other than the tables', a NaN or
    /// infinite action (naming its table and component; nothing is played), a
    /// simulation's or the policy's error.
    pub fn step(
        &mut self,
        engine: &mut ShotEngine,
        actions: &[f64],
        policy: &mut Policy<'_>,
    ) -> Result<StepReport, Error> {
        let n = self.len();
        check_actions(actions, n, "")?;
        let mut report = StepReport {
            rewards: vec![0.0; n],
            terminated: vec![false; n],
            truncated: vec![false; n],
            reset: vec![false; n],
            fouled: vec![false; n],
            potted: vec![0; n],
            won: vec![false; n],
            opponent_shots: vec![0; n],
            cut: vec![false; n],
        };
        let mut learners = Vec::with_capacity(n);
        for k in 0..n {
            if self.ended[k] {
                self.next_episode(k)?;
                report.reset[k] = true;
            } else {
                learners.push(k);
            }
        }
        // the learner's shots
        let planned = self.action_shots(&learners, actions, true);
        let results = self.shoot(engine, &planned)?;
        for (p, res) in planned.iter().zip(&results) {
            let k = p.table;
            report.rewards[k] += self.reward_of(res, &self.games[k]);
            report.fouled[k] = res.fouled();
            report.potted[k] = res.own_potted.count_ones();
            report.cut[k] = res.cut;
        }
        // the opponent's turns after the learner's, and on the tables reset
        let mut rewards = std::mem::take(&mut report.rewards);
        let mut opponent_shots = std::mem::take(&mut report.opponent_shots);
        self.opponent_turns(
            engine,
            &learners,
            policy,
            Some(&mut rewards),
            &mut opponent_shots,
        )?;
        let reset: Vec<usize> = (0..n).filter(|&k| report.reset[k]).collect();
        self.begin(engine, &reset, policy, &mut opponent_shots)?;
        report.rewards = rewards;
        report.opponent_shots = opponent_shots;
        for k in 0..n {
            let g = &self.games[k];
            report.terminated[k] = g.over;
            report.truncated[k] = !g.over && g.shots >= self.options.max_shots;
            report.won[k] = g.winner == Some(0);
            self.ended[k] = report.terminated[k] || report.truncated[k];
        }
        Ok(report)
    }

    /// The reward of `res` to the player who shot, `g` the game after it.
    fn reward_of(&self, res: &ShotResult, g: &GameState) -> f64 {
        let w = &self.options.rewards;
        let mut reward = w.pot * f64::from(res.own_potted.count_ones());
        if res.fouled() {
            reward += w.foul;
        }
        if let Some(winner) = g.winner {
            reward += if winner == res.shooter { w.win } else { w.loss };
        }
        reward
    }

    /// Plays player 1's turns on `tables` until each is the learner's turn, the game is
    /// over, or the shot cap: the built-in agent's or `policy`'s. The learner's reward
    /// (`rewards`) takes the games' ends.
    fn opponent_turns(
        &mut self,
        engine: &mut ShotEngine,
        tables: &[usize],
        policy: &mut Policy<'_>,
        mut rewards: Option<&mut Vec<f64>>,
        shots: &mut [u32],
    ) -> Result<(), Error> {
        if self.options.opponent == Opponent::SelfPlay {
            return Ok(());
        }
        let max = self.options.max_shots;
        let to_move = |g: &GameState| !g.over && g.shooter == 1 && g.shots < max;
        let mut waiting: Vec<usize> = tables
            .iter()
            .copied()
            .filter(|&k| to_move(&self.games[k]))
            .collect();
        while !waiting.is_empty() {
            let planned = match self.options.opponent {
                Opponent::Agent(agent) => {
                    let mut planned = Vec::with_capacity(waiting.len());
                    for &k in &waiting {
                        planned.push(self.agent_shot(engine, agent, k)?);
                    }
                    planned
                }
                _ => {
                    let len = self.obs_len();
                    let mut obs = vec![0f32; waiting.len() * len];
                    for (row, &k) in obs.chunks_mut(len).zip(&waiting) {
                        self.observe_one(&self.games[k], row);
                    }
                    let actions = policy(&waiting, &obs)?;
                    check_actions(&actions, waiting.len(), "the opponent's policy: ")?;
                    self.action_shots(&waiting, &actions, false)
                }
            };
            self.shoot(engine, &planned)?;
            for p in &planned {
                let k = p.table;
                shots[k] += 1;
                if let (Some(rw), Some(winner)) = (rewards.as_deref_mut(), self.games[k].winner) {
                    let w = &self.options.rewards;
                    rw[k] += if winner == 0 { w.win } else { w.loss };
                }
            }
            waiting.retain(|&k| to_move(&self.games[k]));
        }
        Ok(())
    }

    /// A built-in agent's shot on table `k` (its cue ball placed first where in hand).
    fn agent_shot(
        &mut self,
        engine: &mut ShotEngine,
        agent: Agent,
        k: usize,
    ) -> Result<Planned, Error> {
        let rules = self.options.task.rules();
        if self.games[k].in_hand {
            place_cue(&mut self.games[k], &self.table, self.params)?;
        }
        let g = &self.games[k];
        let mut ids = [0i64; MAX_IDS];
        let mut states = [g.balls[0]; MAX_IDS];
        let n = g.layout(&mut ids, &mut states);
        let config = position(
            &self.table,
            "9ft",
            self.params,
            (&ids[..n], &states[..n]),
            rules,
            g.context(),
        )?;
        let seed = mix(self.episode_seed(k), 1 + u64::from(g.shots));
        let choice = if g.break_shot {
            break_choice(&config)
        } else {
            choose(
                agent,
                engine,
                &config,
                &self.options.noise,
                self.options.budget,
                seed,
            )?
        };
        let call = match choice.call {
            Some((ball, pocket)) if rules == Rules::EightBall => Call::Given {
                ball: ids[ball],
                pocket,
            },
            _ => Call::None,
        };
        Ok(Planned {
            table: k,
            strike: self.noisy(k, choice.strike),
            call,
        })
    }

    /// The shots of `tables` from checked action rows (row `i` of `actions` for
    /// `tables[i]`, or row `k` for table `k` where `by_table`): the cue ball placed where
    /// in hand (the free spot nearest the action's x, y), the strike clipped and played
    /// under the noise. Rayon over the tables.
    fn action_shots(&mut self, tables: &[usize], actions: &[f64], by_table: bool) -> Vec<Planned> {
        let clip = |a: &[f64], i: usize| a[i].clamp(ACTION_LOW[i], ACTION_HIGH[i]);
        let row_of = |i: usize, k: usize| {
            let r = if by_table { k } else { i };
            &actions[r * 7..(r + 1) * 7]
        };
        let mut row = vec![usize::MAX; self.len()];
        for (i, &k) in tables.iter().enumerate() {
            row[k] = i;
        }
        let table = &self.table;
        self.games
            .par_iter_mut()
            .enumerate()
            .filter(|(k, g)| row[*k] != usize::MAX && g.in_hand)
            .for_each(|(k, g)| {
                let a = row_of(row[k], k);
                let spot = g
                    .free_spot(table, clip(a, 5), clip(a, 6))
                    .unwrap_or((TABLE_WIDTH / 2.0, TABLE_LENGTH / 4.0));
                g.place_cue(spot.0, spot.1);
            });
        let this = &*self;
        tables
            .par_iter()
            .enumerate()
            .map(|(i, &k)| {
                let a = row_of(i, k);
                let strike = CueStrike {
                    v0: clip(a, 0),
                    phi: clip(a, 1),
                    theta: clip(a, 2),
                    a: clip(a, 3),
                    b: clip(a, 4),
                };
                Planned {
                    table: k,
                    strike: this.noisy(k, strike),
                    call: Call::AsPlayed,
                }
            })
            .collect()
    }

    /// `strike` as played on table `k`'s next shot: plus the noise of `(seed, k, episode,
    /// shot)`.
    fn noisy(&self, k: usize, strike: CueStrike) -> CueStrike {
        let shot = u64::from(self.games[k].shots);
        noisy_strike_of(
            strike,
            self.params.ball.r,
            &self.options.noise,
            self.episode_seed(k),
            shot,
        )
    }

    /// Plays `planned` in one engine call and applies each shot to its game.
    fn shoot(
        &mut self,
        engine: &mut ShotEngine,
        planned: &[Planned],
    ) -> Result<Vec<ShotResult>, Error> {
        if planned.is_empty() {
            return Ok(Vec::new());
        }
        let options = BatchOptions {
            limits: self.options.limits,
            record_events: true,
            ..BatchOptions::default()
        };
        let games = &self.games;
        let table = &self.table;
        let input = |i: usize, balls: &mut Vec<BallState>| {
            let g = &games[planned[i].table];
            balls.clear();
            balls.extend(
                (0..MAX_IDS)
                    .filter(|&id| g.on_table & (1 << id) != 0)
                    .map(|id| g.balls[id]),
            );
            // the cue ball (id 0) is on the table and first
            Ok(Some((0, planned[i].strike)))
        };
        // the shots applied so far; a GPU failure under `auto` after some came back starts
        // the call over on the CPU, and them with it
        let after: std::cell::RefCell<Vec<(GameState, ShotResult)>> =
            std::cell::RefCell::new(Vec::with_capacity(planned.len()));
        engine
            .simulate_restartable(
                table,
                self.params,
                &options,
                planned.len(),
                input,
                || {
                    after.borrow_mut().clear();
                    Ok::<(), Error>(())
                },
                |chunk| {
                    let mut after = after.borrow_mut();
                    let first = after.len();
                    let applied: Vec<Result<(GameState, ShotResult), Error>> = chunk
                        .iter()
                        .collect::<Vec<_>>()
                        .into_par_iter()
                        .enumerate()
                        .map(|(j, run)| {
                            let p = planned[first + j];
                            let mut g = games[p.table];
                            let res = g.apply(table, run.events, run.balls, p.call)?;
                            Ok((g, res))
                        })
                        .collect();
                    for a in applied {
                        after.push(a?);
                    }
                    Ok::<(), Error>(())
                },
            )
            .map_err(|e| match e {
                BatchError::Table { table, error } => Error::from(InputError::new(format!(
                    "table {}: {error}",
                    planned[table].table
                ))),
                BatchError::Sink(e) => e,
            })?;
        let mut results = Vec::with_capacity(planned.len());
        for (p, (g, res)) in planned.iter().zip(after.into_inner()) {
            let mut g = g;
            if !self.options.task.two_players() {
                g.shooter = 0;
            }
            self.games[p.table] = g;
            results.push(res);
        }
        Ok(results)
    }
}

/// Checks `n` action rows of 7: the length, every number finite.
fn check_actions(actions: &[f64], n: usize, whose: &str) -> Result<(), Error> {
    if actions.len() != n * 7 {
        return Err(InputError::new(format!(
            "{whose}{} action numbers for {n} tables: each table takes 7 ({})",
            actions.len(),
            ACTION_NAMES.join(", ")
        ))
        .into());
    }
    if let Some(i) = actions.iter().position(|x| !x.is_finite()) {
        return Err(InputError::new(format!(
            "{whose}table {}: action {} is {} (a finite number is needed)",
            i / 7,
            ACTION_NAMES[i % 7],
            actions[i]
        ))
        .into());
    }
    Ok(())
}
