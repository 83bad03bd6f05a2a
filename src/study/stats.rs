//! What a study found: counts per first contact and per outcome (pot, scratch, …), the
//! Wilson intervals that go with them, and summary statistics (times, the cut angle, where
//! the cue ball ends).

use serde_json::{Value, json};

use super::config::StudyConfig;
use super::run::{FirstContact, Sample, Until};
use crate::game::{Foul, Rules};

/// Summary statistics of a set of values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stats {
    /// How many values.
    pub n: usize,
    /// Mean.
    pub mean: f64,
    /// Sample standard deviation (0 for one value).
    pub std: f64,
    /// 5th percentile (linear interpolation between order statistics).
    pub p5: f64,
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
}

impl Stats {
    /// The statistics of `values`, `None` when empty.
    pub fn of(values: &[f64]) -> Option<Stats> {
        if values.is_empty() {
            return None;
        }
        let n = values.len();
        let mean = values.iter().sum::<f64>() / n as f64;
        let var = if n > 1 {
            values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64
        } else {
            0.0
        };
        // each percentile from the two order statistics beside it, found by selection
        // (linear time) rather than by sorting every value: the same values a sort gives
        let mut order = values.to_vec();
        let mut q = |p: f64| {
            let x = p * (n - 1) as f64;
            let lo = x.floor() as usize;
            let hi = (lo + 1).min(n - 1);
            let (_, &mut at_lo, above) = order.select_nth_unstable_by(lo, f64::total_cmp);
            let at_hi = if hi == lo {
                at_lo
            } else {
                above
                    .iter()
                    .copied()
                    .min_by(f64::total_cmp)
                    .expect("a value above")
            };
            at_lo + (x - lo as f64) * (at_hi - at_lo)
        };
        let (p5, p50, p95) = (q(0.05), q(0.5), q(0.95));
        Some(Stats {
            n,
            mean,
            std: var.sqrt(),
            p5,
            p50,
            p95,
        })
    }
}

/// The 95 % Wilson score interval of a proportion `k / n`.
pub fn wilson(k: usize, n: usize) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let z = 1.959_963_984_540_054;
    let (k, n) = (k as f64, n as f64);
    let p = k / n;
    let denom = 1.0 + z * z / n;
    let centre = (p + z * z / (2.0 * n)) / denom;
    let half = z / denom * (p * (1.0 - p) / n + z * z / (4.0 * n * n)).sqrt();
    // exactly 0 and 1 at the ends (the formula leaves rounding there)
    let lo = if k == 0.0 {
        0.0
    } else {
        (centre - half).max(0.0)
    };
    let hi = if k == n {
        1.0
    } else {
        (centre + half).min(1.0)
    };
    (lo, hi)
}

/// A first-contact class of the summary: a ball, any cushion, a pocket, stopped, nothing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Class {
    /// The cue ball touched this ball (its index in the study's balls) first.
    Ball(usize),
    /// The cue ball reached a cushion or a jaw first.
    Cushion,
    /// The cue ball fell into a pocket before touching anything.
    Pocket,
    /// The cue ball stopped without touching anything.
    Stopped,
    /// No event involved the cue ball.
    Nothing,
}

impl Class {
    /// The class of a first contact.
    pub fn of(f: FirstContact) -> Class {
        match f {
            FirstContact::Ball(k) => Class::Ball(k as usize),
            FirstContact::Cushion { .. } => Class::Cushion,
            FirstContact::Pocket(_) => Class::Pocket,
            FirstContact::Stopped => Class::Stopped,
            FirstContact::Nothing => Class::Nothing,
        }
    }
}

/// The outcome of a sample run to rest, as a player counts it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Result4 {
    /// The intended ball went in (in the called pocket, if the study calls one) and the
    /// cue ball stayed up.
    Pot,
    /// The intended ball went in, and so did the cue ball.
    PotScratch,
    /// The cue ball went in, the intended ball did not.
    Scratch,
    /// Neither.
    Miss,
}

impl Result4 {
    /// Every outcome, in report order.
    pub const ALL: [Result4; 4] = [
        Result4::Pot,
        Result4::PotScratch,
        Result4::Scratch,
        Result4::Miss,
    ];

    /// Its position in [`Result4::ALL`] (and in [`Summary::results`]).
    pub fn index(self) -> usize {
        self as usize
    }

    /// `pot`, `pot+scratch`, `scratch`, `miss`.
    pub fn name(self) -> &'static str {
        match self {
            Result4::Pot => "pot",
            Result4::PotScratch => "pot+scratch",
            Result4::Scratch => "scratch",
            Result4::Miss => "miss",
        }
    }

    /// The outcome of `s` in `config`.
    pub fn of(config: &StudyConfig, s: &Sample) -> Result4 {
        Result4::of_pockets(
            s.pocket_of(config.intended),
            config.pocket,
            s.pocket_of(config.cue).is_some(),
        )
    }

    /// The outcome of a sample whose intended ball went into pocket `intended` (if it
    /// did), the study calling pocket `called` (if it does), with or without a scratch.
    fn of_pockets(intended: Option<usize>, called: Option<usize>, scratch: bool) -> Result4 {
        match (called_pot(intended, called), scratch) {
            (true, false) => Result4::Pot,
            (true, true) => Result4::PotScratch,
            (false, true) => Result4::Scratch,
            (false, false) => Result4::Miss,
        }
    }
}

/// Whether the intended ball went in: into the called pocket if the study calls one, into
/// any pocket otherwise.
pub fn potted_as_called(config: &StudyConfig, s: &Sample) -> bool {
    called_pot(s.pocket_of(config.intended), config.pocket)
}

/// Whether a ball that went into pocket `pocket` (if it did) was potted as called: in
/// pocket `called` if one is called, in any otherwise.
fn called_pot(pocket: Option<usize>, called: Option<usize>) -> bool {
    match (pocket, called) {
        (Some(p), Some(called)) => p == called,
        (Some(_), None) => true,
        (None, _) => false,
    }
}

/// What a study found.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// Samples.
    pub samples: usize,
    /// How far they ran.
    pub until: Until,
    /// First contacts: every object ball (in the study's order), then cushion, pocket,
    /// stopped and nothing, each with its count.
    pub first: Vec<(Class, usize)>,
    /// Time to the first contact with the intended ball, over the samples that hit it first.
    pub contact_time: Option<Stats>,
    /// Cut angle on the intended ball, degrees, over the same samples.
    pub cut_angle: Option<Stats>,
    /// Samples per outcome, in [`Result4::ALL`]'s order (to rest only).
    pub results: [usize; 4],
    /// Samples where the intended ball went into each pocket (index, count; pockets that
    /// took it, in table order).
    pub intended_pockets: Vec<(usize, usize)>,
    /// Samples where the cue ball went in.
    pub scratches: usize,
    /// Samples where the cue ball went into each pocket (index, count; pockets that took
    /// it, in table order).
    pub scratch_pockets: Vec<(usize, usize)>,
    /// Samples where the cue ball touched no ball at all (a foul).
    pub no_ball_hit: usize,
    /// Every other object ball that was pocketed: (index, samples).
    pub others_potted: Vec<(usize, usize)>,
    /// Time from the strike to the intended ball's pot, over the samples that pot it.
    pub pot_time: Option<Stats>,
    /// The cue ball's final x and y over the samples where it stayed on the table.
    pub cue_final: Option<(Stats, Stats)>,
    /// Of those, how many stopped in the study's target circle.
    pub in_target: Option<usize>,
    /// Samples cut by the event or time cap (still counted everywhere above, with the
    /// state they reached).
    pub cut: usize,
    /// Events per sample.
    pub events: Option<Stats>,
    /// Duration of a sample, s.
    pub duration: Option<Stats>,
    /// The game's verdicts, where the study has a game (to rest).
    pub game: Option<GameCounts>,
}

/// A study's game verdicts counted over its samples.
#[derive(Clone, Debug, PartialEq)]
pub struct GameCounts {
    /// The rules that judged them.
    pub rules: Rules,
    /// Legal shots.
    pub legal: usize,
    /// Each foul's count, in [`Foul::ALL`]'s order.
    pub fouls: [usize; Foul::ALL.len()],
    /// Shots after which the player stays at the table (three-cushion: a point).
    pub turn_kept: usize,
    /// Shots that ended the game, won by the player who shot.
    pub won: usize,
    /// Shots that ended the game and not won by the player who shot (lost, or in snooker
    /// tied).
    pub lost: usize,
    /// The points the player who shot scored, per shot (games that score: snooker,
    /// three-cushion; [`Verdict::points`](crate::game::Verdict::points)).
    pub points: Option<Stats>,
    /// The points the shot's foul gave the opponent, per shot (snooker).
    pub foul_points: Option<Stats>,
}

impl GameCounts {
    /// No verdict yet, under `rules`.
    fn new(rules: Rules) -> GameCounts {
        GameCounts {
            rules,
            legal: 0,
            fouls: [0; Foul::ALL.len()],
            turn_kept: 0,
            won: 0,
            lost: 0,
            points: None,
            foul_points: None,
        }
    }

    /// Counts verdict `v`.
    fn add(&mut self, v: &crate::game::Verdict) {
        self.legal += usize::from(v.legal);
        if let Some(k) = v.foul.and_then(|f| Foul::ALL.iter().position(|&x| x == f)) {
            self.fouls[k] += 1;
        }
        self.turn_kept += usize::from(!v.turn_over);
        self.won += usize::from(v.game_over && v.won);
        self.lost += usize::from(v.game_over && !v.won);
    }
}

/// A [`Summary`] under construction: the counts of the samples added so far and the values
/// its statistics need, one sample at a time in the study's order ([`Tally::add`]), so a
/// study that wants only its summary keeps no sample ([`crate::study::summarize`]).
/// [`Tally::finish`] gives what [`Summary::of`] gives on the same samples, bit for bit.
#[derive(Clone, Debug)]
pub struct Tally {
    until: Until,
    cue: usize,
    intended: usize,
    called: Option<usize>,
    target: Option<super::config::Target>,
    samples: usize,
    first: Vec<(Class, usize)>,
    contact_times: Vec<f64>,
    cuts: Vec<f64>,
    results: [usize; 4],
    intended_pockets: Vec<usize>,
    scratch_pockets: Vec<usize>,
    potted: Vec<usize>,
    scratches: usize,
    no_ball_hit: usize,
    cut: usize,
    in_target: usize,
    pot_times: Vec<f64>,
    xs: Vec<f64>,
    ys: Vec<f64>,
    events: Vec<f64>,
    durations: Vec<f64>,
    game: Option<GameCounts>,
    points: Vec<f64>,
    foul_points: Vec<f64>,
}

impl Tally {
    /// An empty tally of `config`'s study, run as `until` says.
    pub fn new(config: &StudyConfig, until: Until) -> Tally {
        let first = (0..config.balls.len())
            .filter(|&k| k != config.cue)
            .map(Class::Ball)
            .chain([
                Class::Cushion,
                Class::Pocket,
                Class::Stopped,
                Class::Nothing,
            ])
            .map(|c| (c, 0))
            .collect();
        let pockets = config.table.pockets.len();
        Tally {
            until,
            cue: config.cue,
            intended: config.intended,
            called: config.pocket,
            target: config.target,
            samples: 0,
            first,
            contact_times: Vec::new(),
            cuts: Vec::new(),
            results: [0; 4],
            intended_pockets: vec![0; pockets],
            scratch_pockets: vec![0; pockets],
            potted: vec![0; config.balls.len()],
            scratches: 0,
            no_ball_hit: 0,
            cut: 0,
            in_target: 0,
            pot_times: Vec::new(),
            xs: Vec::new(),
            ys: Vec::new(),
            events: Vec::new(),
            durations: Vec::new(),
            game: match (&config.game, until) {
                (Some(g), Until::Rest) => Some(GameCounts::new(g.rules)),
                _ => None,
            },
            points: Vec::new(),
            foul_points: Vec::new(),
        }
    }

    /// The most bytes a sample's values take in a tally (seven numbers: the contact time
    /// and cut angle, the pot time, the cue ball's final x and y, events, duration; with a
    /// game two more).
    pub const MOST_BYTES_A_SAMPLE: usize = 9 * std::mem::size_of::<f64>();

    /// Samples added so far.
    pub fn len(&self) -> usize {
        self.samples
    }

    /// Whether no sample was added.
    pub fn is_empty(&self) -> bool {
        self.samples == 0
    }

    /// Adds sample `s`, the next of the study's (its ball and pocket indices `config`'s).
    pub fn add(&mut self, s: &Sample) {
        self.samples += 1;
        let class = Class::of(s.first);
        if let Some(c) = self.first.iter_mut().find(|(k, _)| *k == class) {
            c.1 += 1;
        }
        if !matches!(class, Class::Ball(_)) {
            self.no_ball_hit += 1;
        }
        if class == Class::Ball(self.intended) {
            self.contact_times.push(s.first_t);
            self.cuts.push(s.cut_angle);
        }
        self.cut += usize::from(s.cut.is_some());
        self.events.push(s.n_events as f64);
        self.durations.push(s.duration);
        if self.until == Until::FirstContact {
            return;
        }
        let intended = s.pocket_of(self.intended);
        let scratch = s.pocket_of(self.cue);
        let r = Result4::of_pockets(intended, self.called, scratch.is_some());
        self.results[r.index()] += 1;
        for pot in &s.potted {
            self.potted[pot.ball as usize] += 1;
        }
        if let Some(p) = intended {
            self.intended_pockets[p] += 1;
        }
        if let Some(t) = s.pot_time(self.intended) {
            self.pot_times.push(t);
        }
        if let Some(p) = scratch {
            self.scratches += 1;
            self.scratch_pockets[p] += 1;
        } else {
            self.xs.push(s.cue_final.0);
            self.ys.push(s.cue_final.1);
            if self
                .target
                .is_some_and(|t| t.contains(s.cue_final.0, s.cue_final.1))
            {
                self.in_target += 1;
            }
        }
        if let (Some(g), Some(v)) = (&mut self.game, &s.verdict) {
            g.add(v);
            self.points.push(f64::from(v.points));
            self.foul_points.push(f64::from(v.foul_points));
        }
    }

    /// The summary of the samples added.
    pub fn finish(self) -> Summary {
        let t = self;
        let (cue, intended) = (t.cue, t.intended);
        let listed = |counts: Vec<usize>| -> Vec<(usize, usize)> {
            counts
                .into_iter()
                .enumerate()
                .filter(|&(_, n)| n > 0)
                .collect()
        };
        let game = t.game.map(|mut g| {
            if g.rules.scores() {
                g.points = Stats::of(&t.points);
                g.foul_points = if g.rules == Rules::Snooker {
                    Stats::of(&t.foul_points)
                } else {
                    None
                };
            }
            g
        });
        Summary {
            samples: t.samples,
            until: t.until,
            first: t.first,
            contact_time: Stats::of(&t.contact_times),
            cut_angle: Stats::of(&t.cuts),
            results: t.results,
            intended_pockets: listed(t.intended_pockets),
            scratches: t.scratches,
            scratch_pockets: listed(t.scratch_pockets),
            no_ball_hit: t.no_ball_hit,
            others_potted: listed(t.potted)
                .into_iter()
                .filter(|&(k, _)| k != cue && k != intended)
                .collect(),
            pot_time: Stats::of(&t.pot_times),
            cue_final: Stats::of(&t.xs).zip(Stats::of(&t.ys)),
            in_target: t.target.map(|_| t.in_target),
            cut: t.cut,
            events: Stats::of(&t.events),
            duration: Stats::of(&t.durations),
            game,
        }
    }
}

impl Summary {
    /// Counts and statistics of `samples`, run as `until` says.
    pub fn of(config: &StudyConfig, samples: &[Sample], until: Until) -> Summary {
        let mut tally = Tally::new(config, until);
        for s in samples {
            tally.add(s);
        }
        tally.finish()
    }

    /// The count of a first-contact class.
    pub fn count(&self, class: Class) -> usize {
        self.first
            .iter()
            .find(|(c, _)| *c == class)
            .map_or(0, |c| c.1)
    }

    /// The count of an outcome.
    pub fn result(&self, r: Result4) -> usize {
        self.results[r.index()]
    }

    /// Samples where the intended ball went in (any pocket).
    pub fn intended_potted(&self) -> usize {
        self.intended_pockets.iter().map(|p| p.1).sum()
    }
}

/// Statistics as JSON (`null` when there are none).
fn stats_json(st: Option<&Stats>) -> Value {
    match st {
        Some(s) => json!({
            "n": s.n, "mean": s.mean, "std": s.std, "p5": s.p5, "p50": s.p50, "p95": s.p95
        }),
        None => Value::Null,
    }
}

/// A count as JSON: count, fraction and the Wilson 95 % interval.
fn count_json(k: usize, n: usize) -> Value {
    let (lo, hi) = wilson(k, n);
    let frac = if n > 0 { k as f64 / n as f64 } else { 0.0 };
    json!({"count": k, "fraction": frac, "ci95": [lo, hi]})
}

impl Summary {
    /// The summary as a JSON object (what `kisstime shots --json` prints, less the run's
    /// description, and what the Python package returns): every count as `{count,
    /// fraction, ci95}`, every statistic as `{n, mean, std, p5, p50, p95}` (`null` when no
    /// sample has it), balls and pockets by their ids. The outcome keys (`outcome`,
    /// `intended_potted`, `scratch`, …) are there only for a study run to rest.
    pub fn to_json(&self, c: &StudyConfig) -> Value {
        let s = self;
        let n = s.samples;
        let first: serde_json::Map<String, Value> = s
            .first
            .iter()
            .map(|&(class, k)| {
                let key = match class {
                    Class::Ball(b) => c.balls[b].id.clone(),
                    Class::Cushion => "cushion".to_owned(),
                    Class::Pocket => "pocket".to_owned(),
                    Class::Stopped => "stopped".to_owned(),
                    Class::Nothing => "nothing".to_owned(),
                };
                (key, count_json(k, n))
            })
            .collect();
        let mut v = json!({
            "scenario": c.source,
            "table": c.table_name,
            "cue_ball": c.cue_id(),
            "intended": c.intended_id(),
            "called_pocket": c.pocket_id(),
            "until": match s.until { Until::Rest => "rest", Until::FirstContact => "first-contact" },
            "samples": n,
            "first_contact": first,
            "contact_time_s": stats_json(s.contact_time.as_ref()),
            "cut_angle_deg": stats_json(s.cut_angle.as_ref()),
            "cut_by_cap": s.cut,
            "events": stats_json(s.events.as_ref()),
            "duration_s": stats_json(s.duration.as_ref()),
        });
        if s.until == Until::Rest {
            let ids =
                |list: &[(usize, usize)], names: &[String]| -> serde_json::Map<String, Value> {
                    list.iter()
                        .map(|&(i, k)| (names[i].clone(), count_json(k, n)))
                        .collect()
                };
            let ball_ids: Vec<String> = c.balls.iter().map(|b| b.id.clone()).collect();
            let results: serde_json::Map<String, Value> = Result4::ALL
                .iter()
                .map(|&r| (r.name().to_owned(), count_json(s.result(r), n)))
                .collect();
            let extra = json!({
                "outcome": results,
                "intended_potted": count_json(s.intended_potted(), n),
                "intended_pockets": ids(&s.intended_pockets, &c.table.pocket_ids),
                "scratch": count_json(s.scratches, n),
                "scratch_pockets": ids(&s.scratch_pockets, &c.table.pocket_ids),
                "others_potted": ids(&s.others_potted, &ball_ids),
                "no_ball_hit": count_json(s.no_ball_hit, n),
                "pot_time_s": stats_json(s.pot_time.as_ref()),
                "cue_final_x": stats_json(s.cue_final.as_ref().map(|p| &p.0)),
                "cue_final_y": stats_json(s.cue_final.as_ref().map(|p| &p.1)),
                "target": c.target.map(|t| json!({"x": t.x, "y": t.y, "radius": t.radius})),
                "in_target": s.in_target.map(|k| count_json(k, n)),
                "game": s.game.as_ref().map(|g| json!({
                    "rules": g.rules.name(),
                    "legal": count_json(g.legal, n),
                    "fouls": Foul::ALL
                        .iter()
                        .zip(g.fouls)
                        .map(|(f, k)| (f.code().to_owned(), count_json(k, n)))
                        .collect::<serde_json::Map<String, Value>>(),
                    "turn_kept": count_json(g.turn_kept, n),
                    "won": count_json(g.won, n),
                    "lost": count_json(g.lost, n),
                    "points": stats_json(g.points.as_ref()),
                    "foul_points": stats_json(g.foul_points.as_ref()),
                })),
            });
            if let (Value::Object(m), Value::Object(e)) = (&mut v, extra) {
                m.extend(e);
            }
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wilson_interval_brackets_the_proportion() {
        let (lo, hi) = wilson(50, 100);
        assert!(lo < 0.5 && hi > 0.5 && (0.5 - lo - (hi - 0.5)).abs() < 1e-12);
        assert_eq!(wilson(0, 100).0, 0.0);
        assert!(wilson(0, 100).1 > 0.0);
        assert_eq!(wilson(100, 100).1, 1.0);
    }

    #[test]
    fn stats_percentiles_interpolate() {
        let v: Vec<f64> = (0..=100).map(f64::from).collect();
        let s = Stats::of(&v).unwrap();
        assert_eq!((s.p5, s.p50, s.p95), (5.0, 50.0, 95.0));
        assert_eq!(s.mean, 50.0);
    }

    /// The percentiles found by selection are the ones a full sort gives, bit for bit:
    /// random values with ties, every length up to 60 and a long one, ±0 and infinities.
    #[test]
    fn stats_percentiles_are_the_sorted_values() {
        let by_sorting = |values: &[f64]| {
            let mut sorted = values.to_vec();
            sorted.sort_by(f64::total_cmp);
            let n = sorted.len();
            let q = |p: f64| {
                let x = p * (n - 1) as f64;
                let lo = x.floor() as usize;
                let hi = (lo + 1).min(n - 1);
                sorted[lo] + (x - lo as f64) * (sorted[hi] - sorted[lo])
            };
            [q(0.05), q(0.5), q(0.95)].map(f64::to_bits)
        };
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let mut lengths: Vec<usize> = (1..=60).collect();
        lengths.push(10_007);
        for n in lengths {
            for ties in [3u64, 1000, u64::MAX] {
                let values: Vec<f64> = (0..n)
                    .map(|_| match next() % ties {
                        0 => -0.0,
                        1 if ties < u64::MAX => f64::INFINITY,
                        k => (k % 97) as f64 * 0.37 - 12.0,
                    })
                    .collect();
                let s = Stats::of(&values).unwrap();
                assert_eq!(
                    [s.p5, s.p50, s.p95].map(f64::to_bits),
                    by_sorting(&values),
                    "{n} values, ties {ties}"
                );
            }
        }
    }
}
