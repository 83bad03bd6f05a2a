//! Shared test helpers: the ground-truth corpus and its tolerance tiers
//! (`tests/data/README.md`).
#![allow(dead_code)]

pub mod kernel;
pub mod rng;

use kisstime::model::{dot, norm};
use kisstime::query::RelPath;
use kisstime::{Ball, MotionState, Params, Status, ball_path};

/// How many doubles apart `a` and `b` are (0 when both are NaN, `u64::MAX` when one is):
/// adjacent doubles differ by 1, and +0 and −0 are the same point.
pub fn ulps(a: f64, b: f64) -> u64 {
    let ordinal = |x: f64| {
        let bits = x.to_bits() as i64;
        if bits < 0 { -(bits & i64::MAX) } else { bits }
    };
    match (a.is_nan(), b.is_nan()) {
        (true, true) => 0,
        (false, false) => (ordinal(a) - ordinal(b)).unsigned_abs(),
        _ => u64::MAX,
    }
}

/// One corpus case.
#[derive(Clone, Debug)]
pub struct Case {
    pub id: String,
    pub category: String,
    pub params: Params,
    pub b1: Ball,
    pub b2: Ball,
    pub expected_t: f64,
    pub horizon: f64,
    pub margin: f64,
    pub label: String,
}

fn num(s: &str) -> f64 {
    s.parse()
        .unwrap_or_else(|_| panic!("bad number {s:?} in the corpus"))
}

/// Reads `tests/data/dev.csv`.
pub fn corpus() -> Vec<Case> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/dev.csv");
    let mut rdr = csv::Reader::from_path(path).expect("tests/data/dev.csv is readable");
    let headers = rdr.headers().unwrap().clone();
    let col = |name: &str| headers.iter().position(|h| h == name).unwrap();
    let ball = |rec: &csv::StringRecord, p: &str| Ball {
        state: rec[col(&format!("{p}_state"))]
            .parse::<MotionState>()
            .unwrap(),
        x: num(&rec[col(&format!("{p}_x"))]),
        y: num(&rec[col(&format!("{p}_y"))]),
        vx: num(&rec[col(&format!("{p}_vx"))]),
        vy: num(&rec[col(&format!("{p}_vy"))]),
        wx: num(&rec[col(&format!("{p}_wx"))]),
        wy: num(&rec[col(&format!("{p}_wy"))]),
        wz: num(&rec[col(&format!("{p}_wz"))]),
    };
    rdr.records()
        .map(|r| {
            let rec = r.unwrap();
            let radius = num(&rec[col("R")]);
            let note = &rec[col("note")];
            Case {
                id: rec[col("case_id")].to_owned(),
                category: rec[col("category")].to_owned(),
                params: Params {
                    radius,
                    g: num(&rec[col("g")]),
                    mu_s: num(&rec[col("mu_s")]),
                    mu_r: num(&rec[col("mu_r")]),
                    mu_sp: 0.444 * radius,
                },
                b1: ball(&rec, "b1"),
                b2: ball(&rec, "b2"),
                expected_t: num(&rec[col("expected_t")]),
                horizon: num(&rec[col("horizon_H")]),
                margin: num(&rec[col("min_distance_margin")]),
                label: note
                    .split(';')
                    .next()
                    .unwrap()
                    .trim_start_matches("label=")
                    .to_owned(),
            }
        })
        .collect()
}

/// Which tolerance tier of the corpus README to apply.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tier {
    F64,
    F32,
}

impl Case {
    /// The case's relative path from its CSV doubles, in f64.
    pub fn rel(&self) -> RelPath {
        RelPath::between(
            &ball_path(&self.b1, &self.params),
            &ball_path(&self.b2, &self.params),
        )
    }

    /// The normal (centre-to-centre) approach speed at the true contact time.
    pub fn normal_speed(&self) -> f64 {
        let rel = self.rel();
        let t = self.expected_t;
        let ct = rel.at(t);
        let vt = rel.velocity_at(t);
        (dot(ct, vt) / norm(ct)).abs()
    }

    /// Length scale of the relative path at the true time: `|C0| + |B| t + |A| t²`.
    pub fn path_scale(&self) -> f64 {
        let rel = self.rel();
        let t = self.expected_t;
        norm(rel.c) + norm(rel.b) * t + norm(rel.a) * t * t
    }

    /// Checks an answer against the truth under `tier`; `Err` says why it fails.
    pub fn check(&self, t: f64, status: Status, tier: Tier) -> Result<(), String> {
        let expect_hit = self.expected_t.is_finite();
        let got_hit = status != Status::None;
        let excused = match tier {
            Tier::F64 => self.margin.abs() < 1e-7,
            Tier::F32 => self.margin.abs() < 1e-5,
        };
        if expect_hit != got_hit {
            if excused {
                return Ok(());
            }
            return Err(format!(
                "classification: expected t={} got {status} t={t}",
                self.expected_t
            ));
        }
        if self.label == "overlap" && status != Status::Overlap && !excused {
            return Err(format!("expected overlap, got {status}"));
        }
        if !expect_hit {
            return Ok(());
        }
        if status == Status::Overlap && self.label != "overlap" && !excused {
            return Err(format!(
                "unexpected overlap (expected t={})",
                self.expected_t
            ));
        }
        let te = self.expected_t;
        let dt = (t - te).abs();
        let vn = self.normal_speed();
        let ok = match tier {
            Tier::F64 => {
                let strict = self.margin.abs() >= 1e-4;
                let time_ok = if strict {
                    dt <= 1e-12 + 1e-9 * te
                } else {
                    dt <= 1e-9 + 1e-6 * te
                };
                time_ok || dt * vn <= 1e-9
            }
            Tier::F32 => {
                excused || dt <= 1e-6 + 1e-6 * te || dt * vn <= 1e-5 + 5e-7 * self.path_scale()
            }
        };
        if ok {
            Ok(())
        } else {
            Err(format!(
                "time: expected {te} got {t} (|dt| = {dt:e}, dt·vn = {:e}, margin {:e})",
                dt * vn,
                self.margin
            ))
        }
    }

    /// The same case with both balls moved by `(dx, dy)`.
    pub fn translated(&self, dx: f64, dy: f64) -> Case {
        let mut c = self.clone();
        c.b1.x += dx;
        c.b1.y += dy;
        c.b2.x += dx;
        c.b2.y += dy;
        c
    }
}

/// A GPU engine for `precision`, or `None` (after printing why) when this machine has no
/// usable adapter. With `KISSTIME_REQUIRE_GPU=1` (CI sets it) a missing adapter fails the
/// test instead. f64 without `SHADER_F64` on the adapter is a skip too, with its reason.
pub fn gpu_or_skip(precision: kisstime::Precision, test: &str) -> Option<kisstime::GpuEngine> {
    match kisstime::GpuEngine::new(precision) {
        Ok(engine) => {
            eprintln!("{test}: on {}", engine.adapter());
            Some(engine)
        }
        Err(kisstime::Error::GpuUnavailable(why)) => {
            let required = std::env::var("KISSTIME_REQUIRE_GPU").is_ok_and(|v| v == "1");
            let no_f64 = why.contains("SHADER_F64");
            if required && !no_f64 {
                panic!("{test}: KISSTIME_REQUIRE_GPU=1 but no usable GPU: {why}");
            }
            // straight to the stderr handle: libtest captures eprintln! in passing tests
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "{test}: SKIPPED, no usable GPU: {why}");
            None
        }
        // a GPU that is there but fails (e.g. the shader does not build) is a failure
        Err(e) => panic!("{test}: {e}"),
    }
}

/// Every corpus case as a 2-ball table `k` (balls 1 and 2), all with the corpus's one
/// parameter set.
pub fn corpus_batch(cases: &[Case]) -> (kisstime::Batch, Params) {
    let params = cases[0].params;
    let mut batch = kisstime::Batch::new();
    for (k, case) in cases.iter().enumerate() {
        assert_eq!(case.params, params);
        batch
            .push_table(k as i64, [(1, case.b1), (2, case.b2)])
            .unwrap();
    }
    (batch, params)
}

/// Proptest configuration: a fixed case count, no regression files, and the fixed `seed`
/// unless `PROPTEST_RNG_SEED` asks for another.
pub fn proptest_config(seed: u64, cases: u32) -> proptest::test_runner::Config {
    use proptest::test_runner::{Config, RngSeed};
    let mut c = Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    };
    if matches!(c.rng_seed, RngSeed::Random) {
        c.rng_seed = RngSeed::Fixed(seed);
    }
    c
}

/// Runs the `kisstime` binary with `args` and extra environment variables `env`.
pub fn run_kisstime(args: &[&str], env: &[(&str, &str)]) -> std::process::Output {
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_kisstime"));
    cmd.args(args);
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().expect("the kisstime binary runs")
}

/// A plain `.npy` file (NumPy's default little-endian dtype for `T`) holding `values` in
/// C order under the shape `shape`, as `numpy.save` writes it.
pub fn plain_array_npy<T: npyz::AutoSerialize + Copy>(shape: &[u64], values: &[T]) -> Vec<u8> {
    use npyz::WriterBuilder;
    let mut bytes = Vec::new();
    let mut w = npyz::WriteOptions::new()
        .default_dtype()
        .shape(shape)
        .writer(&mut bytes)
        .begin_nd()
        .expect("an in-memory npy header is written");
    w.extend(values.iter().copied())
        .expect("in-memory npy rows are written");
    w.finish().expect("an in-memory npy file is finished");
    bytes
}

/// The full-shot reference set's folder (`data/fullshots`).
pub fn fullshots_dir() -> std::path::PathBuf {
    std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/fullshots")).to_path_buf()
}

/// The physics set: 120 shots under non-default ball parameters (`data/physics`, the
/// format of `data/fullshots`; its parameters in `physics.toml`).
pub fn physics_dir() -> std::path::PathBuf {
    std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/physics")).to_path_buf()
}

/// Has `write` write a replay's `events.csv` and `final.csv` (through a
/// `kisstime::io::shot_set::ReplayOut`) into a temporary folder, then runs the judge of
/// the reference set in `reference` on them ([`check_against`]): `write`'s result and the
/// verdict, `None` where python3 is missing.
pub fn write_and_judge<T>(
    reference: &std::path::Path,
    write: impl FnOnce(&mut kisstime::io::shot_set::ReplayOut<'_>) -> T,
) -> (T, Option<(usize, usize, String)>) {
    use std::io::{BufWriter, Write};
    let out = tempfile::tempdir().unwrap();
    let (ev_path, fin_path) = (out.path().join("events.csv"), out.path().join("final.csv"));
    let mut events = BufWriter::new(std::fs::File::create(&ev_path).unwrap());
    let mut fin = BufWriter::new(std::fs::File::create(&fin_path).unwrap());
    let mut files = kisstime::io::shot_set::ReplayOut {
        events: &mut events,
        final_balls: &mut fin,
        event_balls: None,
    };
    let written = write(&mut files);
    events.flush().unwrap();
    fin.flush().unwrap();
    (written, check_against(out.path(), reference))
}

/// Replays the reference set in `dir` (the format of `data/fullshots`) with `params`
/// through the library's replay (`kisstime::io::shot_set::replay`) and runs the set's judge
/// on it ([`write_and_judge`]): `(shots, events, the judge's verdict)`, the verdict `None`
/// where python3 is missing. No shot may be cut by the default limits.
pub fn replay_and_judge(
    dir: &std::path::Path,
    params: kisstime::simulate::SimParams,
) -> (usize, usize, Option<(usize, usize, String)>) {
    use kisstime::io::shot_set::{read_shots, read_table, replay};
    let table = read_table(dir).unwrap();
    let shots = read_shots(dir, params.ball.r).unwrap();
    let limits = kisstime::simulate::Limits::default();
    let (stats, verdict) = write_and_judge(dir, |files| {
        replay(&shots, &table, params, limits, files).unwrap()
    });
    assert_eq!(stats.cut, 0, "no shot may be cut by the default limits");
    (stats.shots, stats.events, verdict)
}

/// Runs the set's judge, `check_fullshots.py`, on a replay in `out` (its `events.csv` and
/// `final.csv`): `Some((passed, failed, output))`, or `None` where python3 is missing
/// (after saying so; in CI, which has it, that is a failure).
pub fn check_fullshots(out: &std::path::Path) -> Option<(usize, usize, String)> {
    check_against(out, &fullshots_dir())
}

/// [`check_fullshots`] against the reference set in `reference` (`--ref`): the judge of
/// `data/fullshots` judges any set in its format, `data/physics` too.
pub fn check_against(
    out: &std::path::Path,
    reference: &std::path::Path,
) -> Option<(usize, usize, String)> {
    let run = std::process::Command::new("python3")
        .arg(fullshots_dir().join("check_fullshots.py"))
        .arg(out)
        .arg("--ref")
        .arg(reference)
        .output();
    let Ok(run) = run else {
        assert!(
            std::env::var_os("CI").is_none(),
            "python3 is needed to run check_fullshots.py"
        );
        eprintln!("python3 not found: the checker was not run");
        return None;
    };
    let text = String::from_utf8_lossy(&run.stdout).into_owned();
    let last = text
        .lines()
        .rev()
        .find(|l| l.contains(" passed, "))
        .unwrap_or_else(|| panic!("check_fullshots.py printed no summary:\n{text}"));
    let mut words = last.split_whitespace();
    let passed = words.next().and_then(|w| w.parse().ok()).unwrap();
    let failed = words.nth(1).and_then(|w| w.parse().ok()).unwrap();
    Some((passed, failed, text))
}
