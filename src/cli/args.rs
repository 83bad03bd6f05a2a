//! The command line's arguments (clap): the subcommands and their flags.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};
use kisstime::Params;
use kisstime::engine::{Backend, Precision, default_precision};
use kisstime::model::{
    DEFAULT_G, DEFAULT_MU_R, DEFAULT_MU_S, DEFAULT_MU_SP_PER_RADIUS, DEFAULT_RADIUS,
};
use kisstime::workload::{ShotWorkload, Workload};

#[derive(Parser)]
#[command(
    name = "kisstime",
    version,
    about = "When do two billiard balls collide? Exact first-contact times for every ball pair \
             of many tables at once.",
    long_about = None
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand)]
pub enum Command {
    /// Answer every ball pair of every table: when do they first touch while approaching?
    ///
    /// INPUT is CSV with the header `table,ball,state,x,y,vx,vy,wx,wy,wz` (SI units, pooltool's
    /// frame as every command: x across the table, y along it; state is stationary,
    /// spinning, sliding, rolling or pocketed; rows of one table need not be adjacent). The output is CSV `table,i,j,t,status,horizon`, one row per pair with
    /// i < j the ball ids, in ascending table then ball id order; `t` is the first contact
    /// time in seconds (`inf` for none), `status` is hit, none or overlap, and `horizon` is
    /// the time until the first of the two balls changes its motion state. The output is
    /// streamed: a few million pairs are held at a time, whatever the batch size.
    ///
    /// Files whose name ends in .npy are NumPy arrays instead of CSV, input and output
    /// (layouts in docs/cli.md and `kisstime::io::npy`). Ctrl-C leaves no output file behind.
    Pairs(RunArgs),
    /// Each table's next collision: the earliest pair in contact, as an event loop asks
    /// after every event.
    ///
    /// INPUT as for `pairs`. The output is CSV `table,t,i,j,status`, one row per table in
    /// ascending id order: `t` the time in seconds, (i, j) the ball ids, status hit or
    /// overlap; `inf`, empty ids and `none` when no pair of the table collides. Ties: the
    /// smallest time, then the smallest (i, j). Files ending in .npy are NumPy arrays, as
    /// for `pairs`.
    Next(RunArgs),
    /// Measure each backend on a built-in workload generated in memory: pairs/s per pair
    /// and for the next collision, the GPU's upload / kernel / readback split, and whether
    /// the backends agree (pairs outside the precision's tier against the CPU f64).
    Bench(BenchArgs),
    /// Write a built-in workload as an input file, so that the CLI, other tools and other
    /// simulators can be timed on identical data. The tables are 9-ft tables in pooltool's
    /// frame (x across, 0 to 1.27 m; y along, 0 to 2.54 m): `simulate` takes them too.
    Gen(GenArgs),
    /// Monte Carlo shot study: re-play one intended shot under cue noise many times, every
    /// sample from the strike to rest with the simulator (pooltool 0.6.0's physics and
    /// strike model, f64, on the CPU or the GPU), and count what came of it.
    ///
    /// SCENARIO is a TOML file (table, balls, intended shot, called pocket, target circle,
    /// noise; see examples/study.toml), or a .json scenario in the format of
    /// data/studies; without it the built-in study runs. Prints the first contact (each
    /// object ball, a cushion, nothing), the intended ball potted (and where), the cue ball
    /// potted (scratch), other balls potted, no ball hit, each with count, fraction and 95%
    /// confidence interval; the time to pot; where the cue ball ends (and how often in the
    /// target circle); samples cut by a cap. --strikes replays given strikes without noise.
    /// The same seed gives the same samples whatever the thread count, and the first N
    /// samples of a larger study are the study of N.
    Shots(ShotsArgs),
    /// Whole shots: simulate every table from the cue strike to rest, event by event, with
    /// pooltool 0.6.0's physics (f64; on the CPU, Rayon over tables, or the GPU).
    ///
    /// INPUT holds the balls as for `pairs` (CSV or .npy, any motion state; ball order =
    /// ascending id, which decides exact ties as pooltool's ball order does). --strikes
    /// gives at most one cue strike a table, applied at t = 0 (`table,ball,V0,phi,theta,a,b`,
    /// pooltool's Cue.set_state conventions). Outputs (CSV, or .npy by name, written
    /// atomically and streamed): -o every event, one row per involved ball
    /// (`table,k,t,type,agent_a,agent_b,ball,state,x,y,vx,vy,wx,wy,wz`), --final every
    /// ball's final state
    /// (`table,ball,state,x,y,vx,vy,wx,wy,wz,pocket`), --outcomes one row a table
    /// (`table,events,t_end,cut`). Without -o and --final the final states go to standard
    /// output (unless `--outcomes -` does). A summary line on stderr gives tables/s and
    /// events/s.
    Simulate(SimulateArgs),
    /// Which shot should I play? Plans the next shot of an 8-ball or 9-ball position under
    /// cue noise and the game's rules.
    ///
    /// INPUT holds the position (the format of `simulate`'s input, one table, or pick one
    /// with --table-id): ball ids are the game's, 0 the cue ball; every ball at rest
    /// (pocketed balls are left out). The planner tries each ball the player may hit first
    /// (9-ball: the lowest; 8-ball: --hittable) into each pocket where the ghost-ball aim is
    /// playable (cut under 80°, both paths clear), over speeds and spins; one-rail banks
    /// and two-ball combinations (those that pot without noise); safeties; and, with no
    /// ball on in straight reach, one-rail kicks. It plays every candidate under the same
    /// noise draws (common random numbers) judged by the rules (8-ball: called on that
    /// ball and pocket), halving the field each round; refines the best three in the
    /// continuous strike (the cross-entropy method); then plays the finalists again on
    /// fresh draws and prints them ranked by value: P(keep the table) with its 95 %
    /// interval, P(foul), P(scratch), the position left (the best next shot's ease, 0 to 1)
    /// and the value (won 2, kept 1 + 0.5 × position, a legal miss −0.6 × the opponent's
    /// position, foul −0.7, lost −2). -o writes the chosen strike as `simulate --strikes`
    /// reads it, --plot draws it. --ball-in-hand and --break choose the cue ball's spot
    /// too. docs/plan.md.
    Plan(PlanArgs),
    /// Self-play: whole games of 8-ball or 9-ball between two agents on kisstime's own
    /// simulator (breaks, fouls, ball in hand, game over), every shot under the cue noise
    /// and judged by the rules; reports each agent's win rate with its 95 % interval, balls
    /// potted per visit, fouls per game, break-and-run rate and decision time (mean, p95).
    /// Agents: `planner` (`kisstime plan` with --budget: its own placement in hand and
    /// its own break), `greedy` (the easiest-looking
    /// direct pot, fixed speed, centre ball, no simulation) and `sampler` (every direct pot
    /// × 4 speeds × 5 spins, each played 200 times under the noise in one batch, the best
    /// immediate P(keep the table)). Breaks alternate. Simplified rules: docs/plan.md.
    Play(PlayArgs),
}

#[derive(Args)]
pub struct SimulateArgs {
    /// The balls: CSV, or a NumPy .npy array when the name ends in .npy (as for `pairs`).
    pub input: PathBuf,
    /// Cue strikes, at most one a table: CSV `table,ball,V0,phi,theta,a,b` or .npy.
    #[arg(long)]
    pub strikes: Option<PathBuf>,
    /// The table: `9ft` (pooltool's 9-ft pocket table), `7ft` (pooltool's default table,
    /// `Table.default()`), `rectangle` (the 9-ft's 1.27 × 2.54 m playing surface with four
    /// rails and no pockets), `snooker` or `carom` (pooltool's snooker and three-cushion
    /// tables; without --physics they play their game's balls, as pooltool's
    /// `BallParams.default(game)`) or a JSON file (the format of data/fullshots/table.json).
    #[arg(long, default_value = "9ft")]
    pub table: String,
    /// Write every event here (atomically; .npy by name).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Write every ball's final state here (atomically; .npy by name).
    #[arg(long = "final")]
    pub final_states: Option<PathBuf>,
    /// Write one row a table here: its events, end time, and whether a limit cut it.
    #[arg(long)]
    pub outcomes: Option<PathBuf>,
    /// Stop a table after this many events (the strike included); it is reported as cut.
    #[arg(long, default_value_t = 200_000)]
    pub max_events: u64,
    /// Stop a table before an event later than this simulated time in s; reported as cut
    /// (`inf`: no time limit).
    #[arg(long, default_value_t = 3600.0, allow_negative_numbers = true)]
    pub max_time: f64,
    /// Worker threads (default: one per core). Results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Draw one table's shot from above (cushions, jaws and pockets to scale, every ball's
    /// path, the collisions, cushion hits and pots, where the balls stopped) as a PNG.
    #[arg(long, value_name = "PNG")]
    pub plot: Option<PathBuf>,
    /// The table `--plot` draws (its id in the input); needed when the input has several.
    #[arg(long, value_name = "K", requires = "plot")]
    pub table_id: Option<i64>,
    /// The balls' and the cue's physical parameters: a TOML file with pooltool 0.6.0's
    /// names (`m`, `R`, `u_s`, `u_r`, `u_sp_proportionality`, `u_b`, `e_b`, `e_c`, `f_c`,
    /// `g`; the cue's `M`, `end_mass` under `[cue]`), as data/physics/physics.toml. Keys
    /// left out keep pooltool's defaults; without the flag, all are pooltool's defaults.
    /// Or, per table, a CSV file (`.csv`): a header `table,KEY,...` (the cue's keys as
    /// `cue.M`, `cue.end_mass`) and one row per table of the input with its values.
    #[arg(long, value_name = "TOML|CSV")]
    pub physics: Option<PathBuf>,
    /// Where to simulate: `cpu` (Rayon, f64, the reference), `gpu` (the WGSL event loop,
    /// one workgroup per table; up to 64 balls a table; an error when no GPU is usable)
    /// or `auto` (the backend measured faster for the work: never a software adapter; whole shots on a
    /// hardware GPU from 512 tables per CPU thread; the pair kernels on the CPU; see docs/gpu.md).
    #[arg(long, value_enum, default_value_t = BackendArg::Cpu)]
    pub backend: BackendArg,
    /// The precision: `f64`, the only one for whole shots (the GPU needs SHADER_F64); `f32`
    /// is refused: it decides contacts to a micrometre, and about half of the reference
    /// shots end elsewhere than pooltool's.
    #[arg(long, value_enum, default_value_t = PrecisionArg::F64)]
    pub precision: PrecisionArg,
    /// Judge every shot by a game's rules, as pooltool 0.6.0's rule sets judge it
    /// (`9-ball`, `8-ball`, `snooker`, `three-cushion`): adds
    /// `legal,foul,turn_over,game_over,won,points,foul_points` to `--outcomes` (`foul`:
    /// cue_pocketed, no_hit, wrong_ball_first, no_rail, break_rails, not_called,
    /// eight_illegal, off_ball_pocketed; `points`: snooker's pots, three-cushion's point;
    /// `foul_points`: snooker's penalty to the opponent). Ball ids are the game's: 0 the
    /// cue ball, object balls their numbers (snooker: reds 1 to 15, yellow 16 … black 21).
    #[arg(long, value_enum, requires = "outcomes")]
    pub rules: Option<RulesArg>,
    /// Each shot's context for `--rules`: CSV `table,break,hittable,ball_call,pocket_call`
    /// and optionally `,score,opponent_score` (hittable ball ids joined by `;`, empty: any
    /// ball but the 8, or snooker's balls on worked out from the table; the pocket's id,
    /// e.g. `lb`; the points before the shot; see docs/games.md). Tables without a row: not
    /// a break, an open table, no call, no points.
    #[arg(long, value_name = "CSV", requires = "rules")]
    pub context: Option<PathBuf>,
    /// With --rules, the WPA's reading where pooltool departs from it and the verdict can
    /// tell: 9-ball's break must hit the 1 first; 8-ball's 8 on the break ends no game
    /// (see docs/games.md). The default is pooltool's.
    #[arg(long, requires = "rules")]
    pub wpa: bool,
    /// Print the table, the batch size, the backend and the cut tables on stderr.
    #[arg(short, long)]
    pub verbose: bool,
    /// Tables read a chunk at a time from an input in table order (the default: 262,144;
    /// the results do not depend on it). For tests.
    #[arg(long, hide = true)]
    pub input_chunk_tables: Option<usize>,
}

#[derive(Args)]
pub struct RunArgs {
    /// Input file: CSV, or a NumPy .npy array when the name ends in .npy.
    pub input: PathBuf,
    /// Write the output here instead of standard output (atomically: nothing is left under
    /// this name if the run fails or is interrupted); a name ending in .npy writes NumPy.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Where to compute: `cpu` (Rayon, f64), `gpu` (wgpu; an error when no GPU is usable),
    /// `auto` (the backend measured faster for the work: never a software adapter; whole shots on a
    /// hardware GPU from 512 tables per CPU thread; the pair kernels on the CPU; see docs/gpu.md).
    #[arg(long, value_enum, default_value_t = BackendArg::Cpu)]
    pub backend: BackendArg,
    /// Floating-point precision: `f64` (CPU, and GPUs that offer SHADER_F64) or `f32`
    /// (GPU only). Default: f64 on the CPU, f32 on the GPU and auto.
    #[arg(long, value_enum)]
    pub precision: Option<PrecisionArg>,
    /// Print the backend and adapter used on stderr.
    #[arg(short, long)]
    pub verbose: bool,
    /// Worker threads for the CPU backend (default: one per core). Results do not depend
    /// on it.
    #[arg(long)]
    pub threads: Option<usize>,
    #[command(flatten)]
    pub physics: PhysicsArgs,
}

#[derive(Args)]
pub struct GenArgs {
    /// The workload: `rack` (the break: a 15-ball rack and the cue ball), `midshot` (one
    /// sliding and two rolling balls, the rest still), `spread` (every ball moving at
    /// random), `worst` (every ball moving towards every other: every pair fully solved).
    #[arg(long, value_enum, default_value_t = WorkloadArg::Midshot)]
    pub scenario: WorkloadArg,
    /// Number of tables.
    #[arg(long, default_value_t = 10_000)]
    pub tables: usize,
    /// Balls per table, 2 to 64 (the rack always has 16).
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u16).range(2..=64))]
    pub balls: u16,
    /// Random seed: the same seed gives the same file on every machine.
    #[arg(long, default_value_t = 42)]
    pub seed: u64,
    /// The file to write: CSV, or a NumPy .npy array when the name ends in .npy.
    #[arg(short, long)]
    pub output: PathBuf,
}

/// The cue noise of `plan` and `play`.
#[derive(Args)]
pub struct NoiseArgs {
    /// The cue noise: `fastfiz` (the computational-pool tournaments': σ V0 0.075 m/s, φ
    /// 0.125°, θ 0.1°, a and b 0.5 mm), `club` (twice that), `casual` (four times) or
    /// `none`.
    #[arg(long, default_value = "fastfiz")]
    pub noise: String,
    /// Every σ of --noise times this.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub noise_scale: f64,
}

#[derive(Args)]
pub struct PlayArgs {
    /// The game: `8-ball` or `9-ball`.
    #[arg(long, value_enum)]
    pub game: RulesArg,
    /// Games to play.
    #[arg(long, default_value_t = 20)]
    pub games: usize,
    /// The two agents, joined by `,` (the first breaks the even games).
    #[arg(long, default_value = "planner,greedy")]
    pub agents: String,
    #[command(flatten)]
    pub noise: NoiseArgs,
    /// The planner's budget per decision (as `plan --budget`).
    #[arg(long, default_value = "20000")]
    pub budget: String,
    /// The seed of every shot's noise and the agents' draws.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Shots after which a game is drawn.
    #[arg(long, default_value_t = 150)]
    pub max_shots: usize,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
    /// Where to simulate (as `simulate --backend`).
    #[arg(long, value_enum, default_value_t = BackendArg::Cpu)]
    pub backend: BackendArg,
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
}

#[derive(Args)]
pub struct PlanArgs {
    /// The position: CSV `table,ball,state,x,y,vx,vy,wx,wy,wz` or .npy (as `simulate`).
    pub input: PathBuf,
    /// The game: `8-ball` or `9-ball`.
    #[arg(long, value_enum)]
    pub rules: RulesArg,
    /// 8-ball: the balls the player may hit first (their group), ids joined by `;` or `,`
    /// (default: an open table, any ball but the 8; the 8 alone once the group is down).
    #[arg(long, value_name = "IDS")]
    pub hittable: Option<String>,
    /// The cue ball is in hand: choose its placement too, `anywhere` or `kitchen`
    /// (behind the head string). INPUT's cue ball, if any, is ignored.
    #[arg(long, value_name = "WHERE")]
    pub ball_in_hand: Option<String>,
    /// Plan the break of INPUT's rack: the cue ball's spot behind the head string and the
    /// strike (INPUT's cue ball, if any, is ignored).
    #[arg(long = "break", conflicts_with = "ball_in_hand")]
    pub break_shot: bool,
    /// Draw the chosen shot (PNG): its paths without noise, and where the cue ball stops
    /// in 2,000 plays of it under the noise.
    #[arg(long, value_name = "PNG")]
    pub plot: Option<PathBuf>,
    /// The table of INPUT to plan for (its id); needed when INPUT has several.
    #[arg(long, value_name = "K")]
    pub table_id: Option<i64>,
    /// The table (as `simulate --table`).
    #[arg(long, default_value = "9ft")]
    pub table: String,
    /// The balls' and the cue's physical parameters: a TOML file (as `simulate --physics`).
    #[arg(long, value_name = "TOML")]
    pub physics: Option<PathBuf>,
    #[command(flatten)]
    pub noise: NoiseArgs,
    /// What the plan may spend: seconds (`1s`, `250ms`) or samples (`200000`).
    #[arg(long, default_value = "1s")]
    pub budget: String,
    /// The noise draws' seed (with a sample budget, the same seed gives the same plan).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// The finalists estimated again and printed.
    #[arg(long, default_value_t = 5)]
    pub top: usize,
    /// Write the chosen strike here: CSV `table,ball,V0,phi,theta,a,b` (`simulate
    /// --strikes`), atomically.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Print the plan as JSON on standard output instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Where to simulate (as `simulate --backend`).
    #[arg(long, value_enum, default_value_t = BackendArg::Cpu)]
    pub backend: BackendArg,
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
}

#[derive(Args)]
pub struct ShotsArgs {
    /// The study: TOML (see examples/study.toml) or a .json scenario in the format of
    /// data/studies. Default: the built-in study.
    pub scenario: Option<PathBuf>,
    /// Number of noisy samples (ignored with --strikes).
    #[arg(long, default_value_t = 100_000, value_parser = at_least_one_u64)]
    pub samples: u64,
    /// Random seed: sample i's noise depends on (seed, i) only.
    #[arg(long, default_value_t = 42)]
    pub seed: u64,
    /// Evaluate exactly these strikes, without noise, instead of drawing samples: CSV
    /// `sample,V0,phi,theta,a,b` (pooltool's Cue.set_state fields: V0 in m/s, phi and
    /// theta in degrees, a and b fractions of R) or .npy by name.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["samples", "seed", "noise", "sigma_v0", "sigma_phi", "sigma_theta", "sigma_a", "sigma_b"])]
    pub strikes: Option<PathBuf>,
    /// How far each sample runs: to rest (the full outcome), or only to the cue ball's
    /// first contact (cheaper; first-contact table only).
    #[arg(long, value_enum, default_value_t = UntilArg::Rest)]
    pub until: UntilArg,
    /// Print the summary as JSON on standard output instead of text.
    #[arg(long)]
    pub json: bool,
    /// Multiply every noise standard deviation by this factor (replaces the file's
    /// `noise.factor`; 0 replays the intended shot exactly).
    #[arg(long, allow_negative_numbers = true)]
    pub noise: Option<f64>,
    /// Standard deviation of the cue speed in m/s (replaces the scaled value).
    #[arg(long, allow_negative_numbers = true)]
    pub sigma_v0: Option<f64>,
    /// Standard deviation of the aim azimuth in degrees (replaces the scaled value).
    #[arg(long, allow_negative_numbers = true)]
    pub sigma_phi: Option<f64>,
    /// Standard deviation of the cue elevation in degrees (replaces the scaled value).
    #[arg(long, allow_negative_numbers = true)]
    pub sigma_theta: Option<f64>,
    /// Standard deviation of the sideways tip offset in metres (replaces the scaled value).
    #[arg(long, allow_negative_numbers = true)]
    pub sigma_a: Option<f64>,
    /// Standard deviation of the vertical tip offset in metres (replaces the scaled value).
    #[arg(long, allow_negative_numbers = true)]
    pub sigma_b: Option<f64>,
    /// Write one CSV row per sample here (atomically): the strike, the first contact, the
    /// outcome, the balls potted with their pockets, the cue ball's final position, the
    /// event count.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Draw the study as a PNG here: the table with its pockets and cushions, the balls and
    /// the intended path, a heat map of where the cue ball stops coloured by outcome, and
    /// the cut angles on the intended ball.
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Stop a sample after this many events (the strike included); it is counted as cut.
    #[arg(long, default_value_t = 10_000)]
    pub max_events: u64,
    /// Stop a sample before an event later than this simulated time in s; counted as cut
    /// (`inf`: no time limit).
    #[arg(long, default_value_t = 600.0, allow_negative_numbers = true)]
    pub max_time: f64,
    /// Where to simulate: `cpu` (Rayon, f64, the reference), `gpu` (the WGSL event loop,
    /// one workgroup per sample; up to 64 balls; an error when no GPU is usable) or
    /// `auto` (the backend measured faster for the work: never a software adapter; whole shots on a
    /// hardware GPU from 512 tables per CPU thread; the pair kernels on the CPU; see docs/gpu.md).
    #[arg(long, value_enum, default_value_t = BackendArg::Cpu)]
    pub backend: BackendArg,
    /// The precision: `f64`, the only one for whole shots (the GPU needs SHADER_F64); `f32`
    /// is refused: it decides contacts to a micrometre, and about half of the reference
    /// shots end elsewhere than pooltool's.
    #[arg(long, value_enum, default_value_t = PrecisionArg::F64)]
    pub precision: PrecisionArg,
    /// Print the table, the run's size and the backend on stderr.
    #[arg(short, long)]
    pub verbose: bool,
    /// Worker threads (default: one per core). Results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// The balls' and the cue's physical parameters, replacing the scenario's `[physics]`
    /// (or a .json scenario's `ball_params`) as a whole: a TOML file in the format of
    /// `simulate --physics` (pooltool 0.6.0's names; keys left out keep pooltool's
    /// defaults).
    #[arg(long, value_name = "TOML")]
    pub physics: Option<PathBuf>,
    /// Vary a physical parameter from sample to sample, uniformly (repeatable; replaces
    /// the scenario's `[noise.physics]`): `u_r=0.1` draws u_r in ±10 % of its value,
    /// `e_c=[0.8,0.9]` in that range; pooltool's ball parameter names (not R). Scaled by
    /// --noise like the cue noise.
    #[arg(long, value_name = "KEY=SPREAD")]
    pub physics_noise: Vec<String>,
}

/// How far a study's samples run.
#[derive(Clone, Copy, ValueEnum, PartialEq, Eq)]
pub enum UntilArg {
    /// Every ball at rest.
    Rest,
    /// The cue ball's first contact.
    FirstContact,
}

#[derive(Args)]
pub struct BenchArgs {
    /// Whole-shot mode: simulate built-in shots from the strike to rest with the simulator
    /// (`kisstime simulate`'s, events not kept) instead of timing the collision kernels,
    /// on the backends `--backend` names (the GPU's event loop in `--precision`, with its
    /// upload / kernel / readback split and its agreement with the CPU); reports shots/s,
    /// events/s and events per shot. `breaks`: a racked break; `ordinary`: 6 to 16 balls,
    /// the cue ball struck towards one of them.
    #[arg(long, value_enum, conflicts_with_all = ["scenario", "balls"])]
    pub sim: Option<SimWorkloadArg>,
    /// Number of tables (at least 1; default 10,000, with --sim 2,000 breaks or 10,000
    /// ordinary shots).
    #[arg(long, value_parser = at_least_one)]
    pub tables: Option<usize>,
    /// Balls per table, 2 to 64 (the rack always has 16).
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u16).range(2..=64))]
    pub balls: u16,
    /// The workload (see `kisstime gen --help`).
    #[arg(long, value_enum, default_value_t = WorkloadArg::Midshot)]
    pub scenario: WorkloadArg,
    /// Which backends to measure; `all` is the CPU and, when one is usable, the GPU.
    #[arg(long, value_enum, default_value_t = BenchBackend::All)]
    pub backend: BenchBackend,
    /// The GPU's precision (the CPU computes in f64).
    #[arg(long, value_enum, default_value_t = PrecisionArg::F32)]
    pub precision: PrecisionArg,
    /// Random seed of the workload.
    #[arg(long, default_value_t = 42)]
    pub seed: u64,
    /// Measured runs per operation, after one warm-up, at least 1; the median is reported.
    #[arg(long, default_value_t = 3, value_parser = at_least_one)]
    pub reps: usize,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
    /// Worker threads for the CPU backend and the simulator (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
}

/// A count of at least 1, as a u64 (clap's own range check words it as "0 is not in
/// 1..18446744073709551615").
fn at_least_one_u64(s: &str) -> Result<u64, String> {
    match s.parse::<u64>() {
        Ok(0) => Err("must be at least 1".to_owned()),
        Ok(n) => Ok(n),
        Err(e) => Err(e.to_string()),
    }
}

/// A count of at least 1.
fn at_least_one(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(0) => Err("must be at least 1".to_owned()),
        Ok(n) => Ok(n),
        Err(e) => Err(e.to_string()),
    }
}

/// A game's rules for `kisstime simulate --rules`.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum RulesArg {
    /// 9-ball (pooltool's `nine_ball`): the lowest ball first, the 9 wins.
    #[value(name = "9-ball")]
    NineBall,
    /// 8-ball (pooltool's `eight_ball`): the group first, called shots, the 8 last.
    #[value(name = "8-ball")]
    EightBall,
    /// Snooker (pooltool's `snooker`): the balls on, fouls worth 4 to 7 to the opponent,
    /// the final black.
    #[value(name = "snooker")]
    Snooker,
    /// Three-cushion billiards (pooltool's `three_cushion`): a point (the turn kept) when
    /// the struck ball meets both others, three cushions or more before the second.
    #[value(name = "three-cushion")]
    ThreeCushion,
}

/// A built-in whole-shot workload for `kisstime bench --sim`.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SimWorkloadArg {
    /// A 15-ball rack on the foot spot, broken from behind the head string at 6-9 m/s.
    Breaks,
    /// 6 to 16 balls anywhere, the cue ball struck towards one of them at 0.5-4 m/s.
    Ordinary,
}

impl SimWorkloadArg {
    pub fn workload(self) -> ShotWorkload {
        match self {
            SimWorkloadArg::Breaks => ShotWorkload::Breaks,
            SimWorkloadArg::Ordinary => ShotWorkload::Ordinary,
        }
    }
}

/// Backends to benchmark.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum BenchBackend {
    /// The CPU only.
    Cpu,
    /// The GPU only (the CPU still computes the reference answers, untimed).
    Gpu,
    /// Both.
    All,
}

/// A built-in workload.
#[derive(Clone, Copy, ValueEnum)]
pub enum WorkloadArg {
    /// The break.
    Rack,
    /// A few balls moving, the rest still.
    Midshot,
    /// Every ball moving at random.
    Spread,
    /// Every ball moving towards every other.
    Worst,
}

impl WorkloadArg {
    pub fn workload(self) -> Workload {
        match self {
            WorkloadArg::Rack => Workload::Rack,
            WorkloadArg::Midshot => Workload::Midshot,
            WorkloadArg::Spread => Workload::Spread,
            WorkloadArg::Worst => Workload::Worst,
        }
    }
}

/// The compute backend.
#[derive(Clone, Copy, ValueEnum)]
pub enum BackendArg {
    /// Rayon on all cores, f64: the reference.
    Cpu,
    /// The GPU through wgpu.
    Gpu,
    /// The GPU when one works, else the CPU.
    Auto,
}

/// The floating-point precision.
#[derive(Clone, Copy, ValueEnum)]
pub enum PrecisionArg {
    /// IEEE single precision.
    F32,
    /// IEEE double precision.
    F64,
}

#[derive(Args)]
pub struct PhysicsArgs {
    /// Ball radius R in metres.
    #[arg(long, default_value_t = DEFAULT_RADIUS, allow_negative_numbers = true)]
    pub radius: f64,
    /// Sliding friction coefficient.
    #[arg(long, default_value_t = DEFAULT_MU_S, allow_negative_numbers = true)]
    pub mu_s: f64,
    /// Rolling friction coefficient.
    #[arg(long, default_value_t = DEFAULT_MU_R, allow_negative_numbers = true)]
    pub mu_r: f64,
    /// Spinning friction coefficient in metres [default: 0.444 × radius]. Spin about the
    /// vertical axis never moves a ball, so it does not change collision times.
    #[arg(long, allow_negative_numbers = true)]
    pub mu_sp: Option<f64>,
    /// Gravitational acceleration in m/s².
    #[arg(long, default_value_t = DEFAULT_G, allow_negative_numbers = true)]
    pub g: f64,
}

impl PhysicsArgs {
    pub fn params(&self) -> Params {
        Params {
            radius: self.radius,
            mu_s: self.mu_s,
            mu_r: self.mu_r,
            mu_sp: self.mu_sp.unwrap_or(DEFAULT_MU_SP_PER_RADIUS * self.radius),
            g: self.g,
        }
    }
}

impl RulesArg {
    /// The library's game.
    pub fn rules(self) -> kisstime::game::Rules {
        use kisstime::game::Rules;
        match self {
            RulesArg::NineBall => Rules::NineBall,
            RulesArg::EightBall => Rules::EightBall,
            RulesArg::Snooker => Rules::Snooker,
            RulesArg::ThreeCushion => Rules::ThreeCushion,
        }
    }
}

impl BackendArg {
    /// The library's backend.
    pub fn backend(self) -> Backend {
        match self {
            BackendArg::Cpu => Backend::Cpu,
            BackendArg::Gpu => Backend::Gpu,
            BackendArg::Auto => Backend::Auto,
        }
    }
}

impl PrecisionArg {
    /// The library's precision.
    pub fn precision(self) -> Precision {
        match self {
            PrecisionArg::F32 => Precision::F32,
            PrecisionArg::F64 => Precision::F64,
        }
    }
}

/// The precision for `backend` when `--precision` is `arg` (the engine's default when it
/// is not given).
pub fn precision_for(arg: Option<PrecisionArg>, backend: Backend) -> Precision {
    arg.map_or_else(|| default_precision(backend), PrecisionArg::precision)
}
