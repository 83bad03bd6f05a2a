//! The learning environments (`kisstime::env`): games stepped at once, rewards as the
//! rules say, episodes and autoreset, reproducibility, bad actions, and the CPU and the
//! GPU (f64) agreeing.

mod common;

use kisstime::engine::{Backend, Precision, ShotEngine};
use kisstime::env::{
    ACTION_HIGH, EnvOptions, Opponent, PER_BALL, Policy, Rewards, StepReport, Task, VecEnv,
};
use kisstime::model::table::Table;
use kisstime::plan::agents::Agent;
use kisstime::plan::aim::ghost_ball;
use kisstime::study::Noise;

fn cpu() -> ShotEngine {
    ShotEngine::new(Backend::Cpu, Precision::F64).unwrap()
}

fn no_policy() -> Box<Policy<'static>> {
    Box::new(|_: &[usize], _: &[f32]| panic!("no policy in this test"))
}

/// Gymnasium's seeds of a vector environment: `seed + k` for table `k`.
fn seeds(seed: u64, n: usize) -> Vec<u64> {
    (0..n as u64).map(|k| seed + k).collect()
}

fn observe(env: &VecEnv) -> Vec<f32> {
    let mut obs = vec![0f32; env.len() * env.obs_len()];
    env.observe(&mut obs);
    obs
}

/// Each table's straightest ghost-ball pot of the lowest ball on (from the observation),
/// centre ball at `v0`; the cue ball in hand placed where it stands.
fn aimed(env: &VecEnv, v0: f64) -> Vec<f64> {
    let table = Table::nine_foot();
    let r = 0.028575;
    let mut actions = Vec::new();
    for k in 0..env.len() {
        let g = env.game(k);
        let cue = (g.balls[0].r.x, g.balls[0].r.y);
        // a game over has no ball on: any aim
        let on = (g.hittable().trailing_zeros() as usize).min(15);
        let object = (g.balls[on].r.x, g.balls[on].r.y);
        let best = table
            .pockets
            .iter()
            .filter_map(|p| ghost_ball(cue, object, (p.center.x, p.center.y), r))
            .min_by(|a, b| a.cut.total_cmp(&b.cut));
        let phi = best.map_or(0.0, |a| a.phi);
        actions.extend([v0, phi, 0.0, 0.0, 0.0, cue.0, cue.1]);
    }
    actions
}

fn drill(tables: usize) -> EnvOptions {
    EnvOptions {
        task: Task::Drill { balls: 1 },
        tables,
        max_shots: 3,
        ..EnvOptions::default()
    }
}

#[test]
fn a_drill_rewards_the_pots_and_ends_the_episode() {
    let mut engine = cpu();
    let mut env = VecEnv::new(drill(48)).unwrap();
    env.reset(&mut engine, Some(&seeds(7, env.len())), &mut *no_policy())
        .unwrap();
    let obs = observe(&env);
    // two balls (the cue ball and the 9), each on the table; the 9 the ball on
    assert_eq!(env.obs_len(), 2 * PER_BALL + 4);
    for row in obs.chunks(env.obs_len()) {
        assert_eq!(row[2], 1.0);
        assert_eq!(row[PER_BALL + 2], 1.0);
        assert_eq!(row[PER_BALL + 3], 1.0);
    }
    let actions = aimed(&env, 2.0);
    let step = env.step(&mut engine, &actions, &mut *no_policy()).unwrap();
    let potted = step.potted.iter().filter(|&&p| p == 1).count();
    // straight-in ghost-ball aims pot most drills without noise
    assert!(potted > 24, "{potted} of 48 potted");
    for k in 0..48 {
        let rewards = Rewards::default();
        let expected = rewards.pot * f64::from(step.potted[k])
            + if step.fouled[k] { rewards.foul } else { 0.0 }
            + if step.won[k] { rewards.win } else { 0.0 };
        assert_eq!(step.rewards[k], expected, "table {k}");
        // the 9 potted legally ends the drill: the game won
        assert_eq!(step.terminated[k], step.potted[k] == 1, "table {k}");
        assert_eq!(step.won[k], step.terminated[k]);
        assert!(!step.truncated[k] && !step.reset[k]);
    }
    // the next step resets the finished tables, whatever the action
    let step2 = env
        .step(&mut engine, &vec![0.0; 48 * 7], &mut *no_policy())
        .unwrap();
    for k in 0..48 {
        assert_eq!(step2.reset[k], step.terminated[k], "table {k}");
        if step2.reset[k] {
            assert_eq!(step2.rewards[k], 0.0);
            assert!(!step2.terminated[k]);
        } else {
            // V0 = 0: no ball hit, a foul
            assert!(step2.fouled[k]);
            assert_eq!(step2.rewards[k], -1.0);
        }
    }
}

#[test]
fn a_run_is_the_same_for_the_same_seed_and_thread_count_does_not_matter() {
    let run = |threads: usize, seed: u64| -> (Vec<f32>, Vec<StepReport>) {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut engine = cpu();
            let options = EnvOptions {
                task: Task::NineBall,
                tables: 24,
                max_shots: 6,
                noise: Noise::preset("club").unwrap(),
                opponent: Opponent::Agent(Agent::Greedy),
                ..EnvOptions::default()
            };
            let mut env = VecEnv::new(options).unwrap();
            env.reset(
                &mut engine,
                Some(&seeds(seed, env.len())),
                &mut *no_policy(),
            )
            .unwrap();
            let mut reports = Vec::new();
            let mut obs = Vec::new();
            for i in 0..5 {
                let actions: Vec<f64> = (0..24 * 7)
                    .map(|j| ACTION_HIGH[j % 7] * (((i * 31 + j * 17) % 97) as f64 / 97.0))
                    .collect();
                reports.push(env.step(&mut engine, &actions, &mut *no_policy()).unwrap());
                obs.extend(observe(&env));
            }
            (obs, reports)
        })
    };
    let (a_obs, a) = run(2, 11);
    let (b_obs, b) = run(1, 11);
    assert_eq!(a, b);
    assert_eq!(
        a_obs.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        b_obs.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
    );
    let (c_obs, _) = run(2, 12);
    assert_ne!(a_obs, c_obs, "another seed, other noise");
    // the greedy opponent played: some table saw its shots
    assert!(a.iter().any(|r| r.opponent_shots.iter().any(|&s| s > 0)));
}

#[test]
fn the_opponents_turns_are_played_and_the_learner_sees_only_its_own() {
    let mut engine = cpu();
    let options = EnvOptions {
        task: Task::EightBall,
        tables: 8,
        max_shots: 40,
        opponent: Opponent::Policy,
        ..EnvOptions::default()
    };
    let mut env = VecEnv::new(options).unwrap();
    let mut calls = 0;
    // the opponent plays a soft shot straight up the table
    let mut policy = |tables: &[usize], obs: &[f32]| -> Result<Vec<f64>, kisstime::Error> {
        calls += 1;
        assert_eq!(obs.len(), tables.len() * (16 * PER_BALL + 4));
        // the observation is the opponent's: player 1 to shoot
        for row in obs.chunks(16 * PER_BALL + 4) {
            assert_eq!(row[16 * PER_BALL + 2], 1.0);
        }
        Ok(tables
            .iter()
            .flat_map(|_| [1.0, 90.0, 0.0, 0.0, 0.0, 0.6, 0.5])
            .collect())
    };
    let opening = env
        .reset(&mut engine, Some(&seeds(3, env.len())), &mut policy)
        .unwrap();
    // breaks alternate: episode 0, the learner breaks everywhere
    assert!(opening.iter().all(|&s| s == 0));
    for _ in 0..6 {
        let actions = aimed(&env, 3.0);
        let step = env.step(&mut engine, &actions, &mut policy).unwrap();
        for k in 0..8 {
            let g = env.game(k);
            // after a step, the learner is to shoot, or the episode ended
            assert!(g.shooter == 0 || step.terminated[k] || step.truncated[k] || step.reset[k]);
        }
    }
    assert!(calls > 0, "the opponent never shot");
}

#[test]
fn bad_actions_and_options_are_refused_and_nothing_is_played() {
    let mut engine = cpu();
    let mut env = VecEnv::new(drill(3)).unwrap();
    env.reset(&mut engine, Some(&seeds(1, env.len())), &mut *no_policy())
        .unwrap();
    let before = observe(&env);
    let mut actions = aimed(&env, 2.0);
    actions[7 + 1] = f64::NAN;
    let err = env
        .step(&mut engine, &actions, &mut *no_policy())
        .unwrap_err()
        .to_string();
    assert!(err.contains("table 1") && err.contains("phi"), "{err}");
    assert_eq!(observe(&env), before);
    let err = env
        .step(&mut engine, &actions[..14], &mut *no_policy())
        .unwrap_err()
        .to_string();
    assert!(err.contains("14 action numbers for 3 tables"), "{err}");
    // out of bounds: clipped, played
    let mut wild = aimed(&env, 2.0);
    wild[0] = 1e9;
    wild[3] = -7.0;
    env.step(&mut engine, &wild, &mut *no_policy()).unwrap();
    for (options, what) in [
        (
            EnvOptions {
                tables: 0,
                ..drill(1)
            },
            "0 tables",
        ),
        (
            EnvOptions {
                max_shots: 0,
                ..drill(1)
            },
            "max_shots 0",
        ),
        (
            EnvOptions {
                task: Task::Drill { balls: 10 },
                ..drill(1)
            },
            "a drill of 10 balls",
        ),
        (
            EnvOptions {
                opponent: Opponent::Agent(Agent::Greedy),
                ..drill(1)
            },
            "no opponent",
        ),
        (
            EnvOptions {
                rewards: Rewards {
                    win: f64::NAN,
                    ..Rewards::default()
                },
                ..drill(1)
            },
            "finite",
        ),
    ] {
        let err = VecEnv::new(options).err().expect(what).to_string();
        assert!(err.contains(what), "{err}");
    }
}

/// The drill (no cluster of touching balls): the GPU's verdicts and rewards are the CPU's,
/// positions to 1e-6 m, step after step. (From a rack the shots are chaotic: docs/rl.md.)
#[test]
fn gpu_and_cpu_observe_and_reward_the_same() {
    let Some(_) = common::gpu_or_skip(Precision::F64, "gpu_and_cpu_observe_and_reward_the_same")
    else {
        return;
    };
    let run = |backend: Backend| {
        let mut engine = ShotEngine::new(backend, Precision::F64).unwrap();
        let options = EnvOptions {
            task: Task::Drill { balls: 3 },
            tables: 16,
            max_shots: 4,
            noise: Noise::preset("fastfiz").unwrap(),
            ..EnvOptions::default()
        };
        let mut env = VecEnv::new(options).unwrap();
        env.reset(&mut engine, Some(&seeds(5, env.len())), &mut *no_policy())
            .unwrap();
        let mut out = Vec::new();
        for _ in 0..5 {
            let actions = aimed(&env, 1.5);
            let step = env.step(&mut engine, &actions, &mut *no_policy()).unwrap();
            out.push((step, observe(&env)));
        }
        out
    };
    let cpu = run(Backend::Cpu);
    let gpu = run(Backend::Gpu);
    for ((cs, co), (gs, go)) in cpu.iter().zip(&gpu) {
        assert_eq!(cs, gs);
        for (a, b) in co.iter().zip(go) {
            assert!((a - b).abs() <= 1e-6, "{a} {b}");
        }
    }
}
