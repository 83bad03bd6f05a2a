//! Inputs found by the fuzz targets in `fuzz/` (see FUZZING.md), kept as plain tests with
//! the values inline so they run with every `cargo test`.

use kisstime::motion::PATH_MOVES;
use kisstime::query::RelPath;
use kisstime::{Ball, MotionState, Params, Status, ball_path, pair_contact};

/// `|C(s)| − 2R` along the pair's relative path.
fn gap(rel: &RelPath, r: f64, s: f64) -> f64 {
    let c = rel.at(s);
    c.x.hypot(c.y) - 2.0 * r
}

/// pair_solver, finding 1: a touching pair (`|C| = 2R` exactly) that separates at
/// 6e-20 m/s while ball 1 accelerates into ball 2 (backspin, 0.98 m/s²). The separation
/// never rises above the rounding of `f`, so the critical point's `f` came out `0` and no
/// "entry from outside" was found: the answer was `none` while the balls overlap by 3.8 mm
/// within the horizon. The pair never left contact, so it re-enters where it turns.
#[test]
fn touching_pair_that_turns_back_before_separating_measurably_is_a_hit() {
    let params = Params::default();
    let b1 = Ball {
        state: MotionState::Sliding,
        x: 2.0771976560354234e-5,
        y: 1.990579590177549e-21,
        vx: -5.999999999998508e-20,
        vy: 1.9014222339689e-310,
        wx: 0.0,
        wy: 14.901969315181418,
        wz: -199.99916553497314,
    };
    let b2 = Ball::at_rest(0.057170771976560356, 1.990579590177549e-21);
    let (p1, p2) = (ball_path(&b1, &params), ball_path(&b2, &params));
    assert_eq!(p1.flags, PATH_MOVES);
    let rel = RelPath::between(&p1, &p2);
    let r = params.radius;
    // the balls overlap by millimetres at the end of the horizon
    assert!(gap(&rel, r, p1.tmax) < -1e-3);
    let c = pair_contact(&p1, &p2, r);
    assert_eq!(c.status, Status::Hit, "{c:?}");
    assert!(c.t <= 1e-18, "{c:?}");
    assert!(gap(&rel, r, c.t).abs() <= 1e-12, "{c:?}");
}

/// pair_solver, finding 2: `μr = 1.2e-319`, `g = 4.4e-312` (each finite and positive) make
/// `μr g` underflow to 0, and a rolling ball at rest then got `tmax = 0/0 = NaN`: a NaN
/// horizon in the answer. Such parameters are now refused, naming the product.
#[test]
fn decelerations_that_underflow_or_overflow_are_refused() {
    let bad = Params {
        mu_r: 1.20157e-319,
        g: 4.4004368984e-312,
        ..Params::default()
    };
    let err = bad.validate().unwrap_err().to_string();
    assert!(err.contains("* g"), "{err}");
    let subnormal = Params {
        mu_s: 1e-160,
        g: 1e-160,
        ..Params::default()
    };
    assert!(subnormal.validate().is_err());
    let huge = Params {
        mu_s: 1e200,
        g: 1e200,
        ..Params::default()
    };
    assert!(
        huge.validate()
            .unwrap_err()
            .to_string()
            .contains("mu_s * g")
    );
    // the batch driver refuses them too, instead of answering with a NaN horizon
    let mut batch = kisstime::Batch::new();
    batch
        .push_table(
            0,
            [
                (0, Ball::rolling(0.9, 0.0, 0.0, 0.0, 0.028575)),
                (1, Ball::rolling(0.0, 0.0, 0.0, 0.0, 0.028575)),
            ],
        )
        .unwrap();
    assert!(kisstime::pair_times(&batch, &bad).is_err());
    assert!(Params::default().validate().is_ok());
}

/// scenario: `u_r = 1e-200`, `g = 1e-200` are each finite and positive, but `μr g`
/// underflows to 0 (finding 2 again, through the shot study's reader). Refused, naming it.
#[test]
fn scenario_with_underflowing_deceleration_is_refused() {
    let text = "[physics]\nu_r = 1e-200\ng = 1e-200\n\
                [[balls]]\nid = 0\nx = 0.45\ny = 0.7\n\
                [[balls]]\nid = 3\nx = 0.78\ny = 1.85\n\
                [shot]\ncue_ball = 0\nobject_ball = 3\nv0 = 1.6\nphi = 71.42\n\
                theta = 5.0\na = 0.0\nb = 0.2\n";
    let err = kisstime::study::StudyConfig::parse(text, "s.toml", None)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("`physics.u_r`")
            && err.contains("`physics.g`")
            && err.contains("deceleration"),
        "{err}"
    );
    assert!(err.contains("s.toml"), "{err}");
    // the same file with ordinary values is fine
    let ok = text.replace("u_r = 1e-200\ng = 1e-200\n", "");
    assert!(kisstime::study::StudyConfig::parse(&ok, "s.toml", None).is_ok());
}

/// A `.npy` file of `header` (version 1.0, padded as NumPy pads).
fn npy_v1(header: &str) -> Vec<u8> {
    let mut h = header.as_bytes().to_vec();
    let pad = 64 - (10 + h.len() + 1) % 64;
    h.extend(std::iter::repeat_n(b' ', pad));
    h.push(b'\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend((h.len() as u16).to_le_bytes());
    out.extend(h);
    out
}

/// read_npy, finding 3: a header with many unclosed brackets hung the reader (the header
/// parser inside npyz backtracks exponentially: 18 `[` took 11 s, the fuzzer's input with
/// 86 `{` would take longer than the universe). Refused at once now.
#[test]
fn npy_header_with_deeply_nested_brackets_is_refused_at_once() {
    for open in ["[", "{", "("] {
        let bytes = npy_v1(&format!("{{'descr': {}}}", open.repeat(40)));
        let start = std::time::Instant::now();
        let err = kisstime::io::npy::read_batch_npy(&bytes[..], "deep.npy")
            .unwrap_err()
            .to_string();
        assert!(err.contains("nests brackets"), "{err}");
        assert!(start.elapsed().as_secs() < 5);
    }
    // an ordinary header still reads (here: a valid header, no data)
    let bytes = npy_v1("{'descr': '<f8', 'fortran_order': False, 'shape': (0, 10), }");
    let batch = kisstime::io::npy::read_batch_npy(&bytes[..], "empty.npy").unwrap();
    assert_eq!(batch.num_tables(), 0);
}

/// `read_npy` (fuzzing, session 2): a header whose shape's product overflows 64 bits made
/// npyz multiply with overflow (a panic with overflow checks on, a wrapped length without).
#[test]
fn npy_header_whose_shape_overflows_is_refused() {
    let mut header = b"{'descr': '<f8', 'fortran_order': False, 'shape': \
        (4444444444444444442, 10), }"
        .to_vec();
    while !(10 + header.len() + 1).is_multiple_of(64) {
        header.push(b' ');
    }
    header.push(b'\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(&header);
    bytes.extend_from_slice(&[0u8; 80]);
    let err = kisstime::io::npy::read_batch_npy(&bytes[..], "shape.npy")
        .expect_err("refused")
        .to_string();
    assert!(err.contains("shape.npy") && err.contains("shape"), "{err}");
}

/// read_npy, finding 5 (fuzzing, session 3): the shape check of finding 4 read the header's
/// text and let through what was not plain digits, but npyz's Python-literal parser reads
/// `-02222+000000000014554249058172262684` as one integer (a sum), so the product
/// overflowed again. The header is now read with the same parser before npyz sees it. The
/// fuzzer's bytes as found, then the other ways to write a shape npyz would multiply out:
/// a sum, a list, a repeated key (either value), and a zero beside dimensions whose
/// product overflows (npyz's strides multiply them even though the array is empty).
#[test]
fn npy_header_whose_shape_overflows_when_evaluated_is_refused() {
    let found: &[u8] = b"\x93NUMPY\x01\x00v\x00{'descr': '<f8', 'fortran_order': False, \
        'shape': (2, -02222+000000000014554249058172262684), }                           NMP ";
    let refused = |bytes: &[u8]| {
        let err = kisstime::io::npy::read_batch_npy(bytes, "sum.npy")
            .expect_err("refused")
            .to_string();
        assert!(
            err.contains("sum.npy") && err.contains("more elements than memory"),
            "{err}"
        );
    };
    refused(found);
    for shape in [
        "(3, 6148914691236517205+1)",
        "[4444444444444444442, 10]",
        "(0, 4444444444444444442, 10)",
        "(1, 10), 'shape': (4444444444444444442, 10)",
    ] {
        refused(&npy_v1(&format!(
            "{{'descr': '<f8', 'fortran_order': False, 'shape': {shape}, }}"
        )));
    }
    // a repeated key is refused whichever of its values overflows
    refused(&npy_v1(
        "{'descr': '<f8', 'fortran_order': False, 'shape': (4444444444444444442, 10), \
         'shape': (0, 10), }",
    ));
}

/// npyz allocates a header's declared length before it reads it: a 12-byte file declaring
/// a 4 GB header (format version 2) is refused from the declaration, as is a header cut
/// short of what it declares.
#[test]
fn npy_header_declared_too_long_or_cut_short_is_refused() {
    let mut bytes = b"\x93NUMPY\x02\x00".to_vec();
    bytes.extend(u32::MAX.to_le_bytes());
    bytes.extend(b"{'de");
    let err = kisstime::io::npy::read_batch_npy(&bytes[..], "long.npy")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("long.npy") && err.contains("4294967295 bytes long"),
        "{err}"
    );
    let good = npy_v1("{'descr': '<f8', 'fortran_order': False, 'shape': (0, 10), }");
    let err = kisstime::io::npy::read_batch_npy(&good[..good.len() - 3], "short.npy")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("short.npy") && err.contains("cut short"),
        "{err}"
    );
}

/// Found while fixing finding 5: within the nesting limit, npyz's header parser still takes
/// time that grows faster than the header's length (a 60 KB header 7 deep took 28 s), and
/// its message quotes the whole header. Headers are now at most 10,000 bytes (numpy.load's
/// own limit) nested at most 5 deep, parsed once, and the message quotes one short line.
#[test]
fn npy_header_that_is_slow_to_parse_is_refused_quickly_with_a_short_message() {
    let body = format!("{{'descr': [[[[{}", "1,".repeat(4_900));
    let bytes = npy_v1(&body);
    let start = std::time::Instant::now();
    let err = kisstime::io::npy::read_batch_npy(&bytes[..], "slow.npy")
        .unwrap_err()
        .to_string();
    assert!(start.elapsed().as_secs() < 5);
    assert!(
        err.contains("slow.npy") && err.contains("not a Python literal"),
        "{err}"
    );
    assert!(err.len() < 300, "{} bytes: {err}", err.len());

    let mut bytes = b"\x93NUMPY\x02\x00".to_vec();
    let header = format!("{{'descr': '<f8', 'x': '{}'}}\n", "a".repeat(10_000));
    bytes.extend((header.len() as u32).to_le_bytes());
    bytes.extend(header.as_bytes());
    let err = kisstime::io::npy::read_batch_npy(&bytes[..], "long.npy")
        .unwrap_err()
        .to_string();
    assert!(err.contains("bytes long") && err.len() < 300, "{err}");
}

/// A shot simulated on the 9-ft table through the public engine (CPU), its events recorded
/// and checked against every invariant of `simulate::invariants`.
fn simulate_checked(
    balls: &[kisstime::simulate::BallState],
    strike: (usize, kisstime::simulate::CueStrike),
) -> kisstime::gpu::GpuRun {
    let (run, verdict) = simulate_and_check(balls, strike);
    if let Err(v) = verdict {
        panic!("{v}");
    }
    run
}

/// [`simulate_checked`] that returns the checker's verdict.
fn simulate_and_check(
    balls: &[kisstime::simulate::BallState],
    strike: (usize, kisstime::simulate::CueStrike),
) -> (
    kisstime::gpu::GpuRun,
    Result<kisstime::simulate::invariants::Margins, kisstime::simulate::invariants::Violation>,
) {
    use kisstime::simulate::{Limits, SimParams, Table};
    simulate_and_check_on(
        &Table::nine_foot(),
        SimParams::default(),
        Limits::default(),
        balls,
        Some(strike),
    )
}

/// A shot simulated on `table` under `params` and `limits` through the public engine
/// (CPU), its events recorded, and the checker's verdict on it.
/// The `event_loop` target's limits: 400 events or 20 s.
const FUZZ_LIMITS: kisstime::simulate::Limits = kisstime::simulate::Limits {
    max_events: 400,
    max_time: 20.0,
};

/// A ball sliding at (−3, −3) m/s with (−100, −100, −100) rad/s of spin at (x, y): the
/// `event_loop` target's already-moving ball.
fn fuzzed_moving(x: f64, y: f64, r: f64) -> kisstime::simulate::BallState {
    kisstime::simulate::BallState {
        v: kisstime::simulate::Vec3::new(-3.0, -3.0, 0.0),
        w: kisstime::simulate::Vec3::new(-100.0, -100.0, -100.0),
        s: MotionState::Sliding,
        ..kisstime::simulate::BallState::at_rest(x, y, r)
    }
}

/// pooltool's parameters with the ball's frictions and restitutions the fuzzer chose:
/// `[u_s, u_r, u_sp, e_b, e_c, f_c]`.
fn fuzzed_params(ball: [f64; 6]) -> kisstime::simulate::SimParams {
    let mut params = kisstime::simulate::SimParams::default();
    let [u_s, u_r, u_sp, e_b, e_c, f_c] = ball;
    (params.ball.u_s, params.ball.u_r, params.ball.u_sp) = (u_s, u_r, u_sp);
    (params.ball.e_b, params.ball.e_c, params.ball.f_c) = (e_b, e_c, f_c);
    params
}

fn simulate_and_check_on(
    table: &kisstime::simulate::Table,
    params: kisstime::simulate::SimParams,
    limits: kisstime::simulate::Limits,
    balls: &[kisstime::simulate::BallState],
    strike: Option<(usize, kisstime::simulate::CueStrike)>,
) -> (
    kisstime::gpu::GpuRun,
    Result<kisstime::simulate::invariants::Margins, kisstime::simulate::invariants::Violation>,
) {
    use kisstime::engine::{Backend, Precision, ShotEngine};
    use kisstime::simulate::invariants::{ShotRun, check_shot};
    let shots = [kisstime::gpu::GpuShot {
        balls: balls.to_vec(),
        strike,
    }];
    let mut engine = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let run = engine
        .simulate(table, params, limits, &shots, true)
        .unwrap()
        .remove(0);
    let shot = ShotRun {
        start: balls,
        strike,
        events: &run.events,
        end: &run.balls,
        outcome: run.outcome,
        limits,
    };
    let verdict = check_shot(table, &params, &shot);
    (run, verdict)
}

/// event_loop and tests/invariants.rs, finding 7 (the known "ball off the table"): a ball
/// frozen to a rail (its centre exactly R from the cushion) and struck into it gets no
/// cushion event — pooltool's root τ = 0 fails its `τ > EPS` (Q6) — and rolls through the
/// cushion and off the table, unpocketed (here to (−0.31, 2.48) m; in self-play once to
/// (5.6, −3.4) m). pooltool 0.6.0 does the same, and kisstime reproduces it on purpose
/// (`tests/sim_properties.rs` pins such a shot), so this test of the physical outcome is
/// ignored until that is decided; the proposed fix (a touching ball moving into a
/// straight cushion collides at once) is on branch `fuzz31-q6-contact-rule`. The test
/// below pins what happens now, and that the checker tells it apart.
#[test]
#[ignore = "finding 7: pooltool's Q6, reproduced on purpose (FUZZING.md)"]
fn ball_frozen_to_a_rail_and_struck_into_it_bounces_off_the_rail() {
    use kisstime::simulate::{BallState, CueStrike, EventKind};
    let r = 0.028575;
    let pocketed = |x: f64, y: f64| BallState {
        s: MotionState::Pocketed,
        r: kisstime::simulate::Vec3::new(x, y, -0.08),
        ..BallState::at_rest(x, y, r)
    };
    let balls = [
        BallState::at_rest(1.0674885912422998, 2.511425, r),
        pocketed(1.3385, 1.27),
        BallState::at_rest(r, 2.357635912813119, r),
        BallState::at_rest(0.5746293435328268, 1.2541083190290003, r),
    ];
    let strike = CueStrike {
        v0: 2.492514017913911,
        phi: 159.65987060310096,
        theta: 2.865864972941639,
        a: -0.4226011682650979,
        b: 0.7419187900795443,
    };
    let run = simulate_checked(&balls, (2, strike));
    let second = run.events[1].event;
    assert_eq!(
        (second.kind, second.ball, second.t),
        (EventKind::BallLinearCushion, 2, 0.0),
        "{second:?}"
    );
    // the same straight into each of the four rails, from rest against it
    for (x, y, phi) in [
        (r, 1.0, 180.0),
        (1.27 - r, 1.0, 0.0),
        (0.6, r, 270.0),
        (0.6, 2.54 - r, 90.0),
    ] {
        let balls = [BallState::at_rest(x, y, r)];
        let strike = CueStrike {
            v0: 2.0,
            phi,
            theta: 0.0,
            a: 0.0,
            b: 0.0,
        };
        let run = simulate_checked(&balls, (0, strike));
        assert_eq!(run.events[1].event.kind, EventKind::BallLinearCushion);
    }
}

/// tests/invariants.rs, finding 7 again, by a collision: a ball frozen to the foot rail
/// (y = R) is pushed into it by another ball (0.005 m/s into the rail) and sinks 0.24 mm
/// into the cushion before its slide ends (a later cushion event brings it back). Ignored
/// as the test above. (The layout as found had a 16th ball over the right side pocket,
/// which the layout check now refuses: finding 8; it took no part in the shot.)
#[test]
#[ignore = "finding 7: pooltool's Q6, reproduced on purpose (FUZZING.md)"]
fn ball_frozen_to_a_rail_and_pushed_into_it_stays_out_of_the_cushion() {
    use kisstime::simulate::{BallState, CueStrike, EventKind};
    let r = 0.028575;
    let xy = [
        (1.2200317696656886, 0.6443339495419106),
        (0.03956269120173683, 1.2717556914036274),
        (0.07193820811909898, 1.2246605918248645),
        (1.0969351591226015, 0.24957153064738596),
        (0.8524173329914325, 0.028575),
        (1.0507124014110305, 0.2831824436153104),
        (0.11699954253632878, 0.06959222102917992),
        (1.0968027178468271, 0.8446069607380433),
        (0.523055696143427, 2.487382634004259),
        (0.4320910655712825, 0.6946689659676925),
        (1.2699402052784616, 1.2462003189453048),
        (0.5174897665227344, 0.6529714737465102),
        (0.7649810510299767, 0.2377675770118586),
        (0.1005389640977925, 0.8491979616587345),
    ];
    let balls: Vec<BallState> = xy
        .iter()
        .map(|&(x, y)| BallState::at_rest(x, y, r))
        .collect();
    let strike = CueStrike {
        v0: 4.911536250754389,
        phi: 82.36381216608387,
        theta: 4.279429567903872,
        a: 0.057942100940857486,
        b: 0.6566524034032583,
    };
    let run = simulate_checked(&balls, (13, strike));
    // ball 4 (frozen to the foot rail, segment 18 at index 4) is hit, and meets the rail
    // at the same time
    let hit = run
        .events
        .iter()
        .position(|e| {
            e.event.kind == EventKind::BallBall && (e.event.ball == 4 || e.event.other == 4)
        })
        .expect("ball 4 is hit");
    let next = run.events[hit + 1].event;
    assert_eq!(
        (next.kind, next.ball, next.other, next.t),
        (EventKind::BallLinearCushion, 4, 4, run.events[hit].event.t),
        "{next:?}"
    );
}

/// read_strikes (found by reading the code while writing the target): the strike files'
/// `.npy` reader opened files with npyz directly, without the header checks of findings
/// 3–5 that the batch reader makes, so a header of unclosed brackets hung it and a shape
/// whose product overflows panicked in npyz. It now opens them through the same checks.
#[test]
fn strike_npy_headers_are_checked_as_batch_headers_are() {
    use kisstime::io::Format;
    use kisstime::io::strikes::{parse_sample_strikes, parse_strikes};
    let deep = npy_v1(&format!("{{'descr': {}}}", "[".repeat(40)));
    let overflow =
        npy_v1("{'descr': '<f8', 'fortran_order': False, 'shape': (4444444444444444442, 10), }");
    for bytes in [&deep, &overflow] {
        let start = std::time::Instant::now();
        let a = parse_strikes(&bytes[..], "s.npy", Format::Npy).unwrap_err();
        let b = parse_sample_strikes(&bytes[..], "s.npy", Format::Npy).unwrap_err();
        for e in [a.to_string(), b.to_string()] {
            assert!(
                e.contains("s.npy") && e.contains("not a readable .npy"),
                "{e}"
            );
        }
        assert!(start.elapsed().as_secs() < 5);
    }
    // a valid file still reads
    let mut ok = npy_v1("{'descr': '<f8', 'fortran_order': False, 'shape': (1, 7), }");
    for v in [3.0f64, 0.0, 2.0, 90.0, 0.0, 0.1, 0.2] {
        ok.extend_from_slice(&v.to_le_bytes());
    }
    let rows = parse_strikes(&ok[..], "s.npy", Format::Npy).unwrap();
    assert_eq!((rows[0].table, rows[0].strike.v0), (3, 2.0));
}

/// rules_judge, finding 9: events whose balls are not in the shot (here a first contact
/// with ball 3,222,086,847 of a 1-ball shot) made snooker's judge index the ids out of
/// bounds (a panic). Every judge now refuses facts that name a ball the shot does not
/// have, and ids and states of different lengths.
#[test]
fn judges_refuse_events_of_balls_not_in_the_shot() {
    use kisstime::game::{Context, Rules, Shot};
    use kisstime::simulate::{BallState, Event, EventKind, EventRecord, NO_AGENT};
    let r = 0.028575;
    let record = |kind, ball, other| {
        let s = BallState::at_rest(0.5, 0.5, r);
        EventRecord {
            event: Event {
                kind,
                t: 0.0,
                ball,
                other,
            },
            states: [s, s],
        }
    };
    let ids = [0i64];
    let start = [BallState::at_rest(0.5, 0.5, r)];
    let cases = [
        vec![
            record(EventKind::StickBall, 0, NO_AGENT),
            record(EventKind::BallBall, 0, 3_222_086_847),
        ],
        vec![
            record(EventKind::StickBall, 0, NO_AGENT),
            record(EventKind::BallPocket, 40, 0),
        ],
        vec![
            record(EventKind::StickBall, 0, NO_AGENT),
            record(EventKind::BallLinearCushion, 7, 2),
        ],
    ];
    for events in &cases {
        let shot = Shot {
            ids: &ids,
            start: &start,
            events,
        };
        for (rules, _) in Rules::ALL {
            let context = rules.context(Context::default());
            let err = rules.judge(&shot, &context).expect_err("refused");
            assert!(!err.to_string().is_empty());
        }
    }
    // ids and states of different lengths
    let shot = Shot {
        ids: &[0, 1],
        start: &start,
        events: &cases[0][..1],
    };
    for (rules, _) in Rules::ALL {
        assert!(rules.judge(&shot, &Context::default()).is_err());
    }
}

/// Finding 7 as kisstime (and pooltool) simulate it today: the ball frozen to the left rail
/// and struck into it leaves the table with no cushion event, and the invariant checker
/// reports it as `RailTunnel` (the known Q6 behaviour), not as a plain `OffTable`.
#[test]
fn ball_frozen_to_a_rail_and_struck_into_it_goes_through_as_in_pooltool() {
    use kisstime::simulate::invariants::Invariant;
    use kisstime::simulate::{BallState, CueStrike, EventKind};
    let r = 0.028575;
    let balls = [
        BallState::at_rest(r, 2.357635912813119, r),
        BallState::at_rest(0.5746293435328268, 1.2541083190290003, r),
    ];
    let strike = CueStrike {
        v0: 2.492514017913911,
        phi: 159.65987060310096,
        theta: 2.865864972941639,
        a: -0.4226011682650979,
        b: 0.7419187900795443,
    };
    let (run, verdict) = simulate_and_check(&balls, (0, strike));
    assert!(
        run.events
            .iter()
            .all(|e| e.event.kind != EventKind::BallLinearCushion || e.event.ball != 0)
    );
    assert!(run.balls[0].r.x < -0.2, "{:?}", run.balls[0].r);
    let v = verdict.unwrap_err();
    assert_eq!(
        (v.invariant, v.ball),
        (Invariant::RailTunnel, Some(0)),
        "{v}"
    );
    assert!(v.detail.contains("segment 6"), "{v}");
}

/// rules_judge, finding 10: snooker's winner on the final black was decided from
/// `score + points > opponent_score + foul_points` in u32, and a score of `u32::MAX` (which
/// a context file may give: its scores are read as u32) overflowed (a panic with overflow
/// checks on, a wrapped sum and the wrong winner without). The sums are now in u64.
#[test]
fn snooker_scores_at_the_top_of_u32_do_not_overflow() {
    use kisstime::game::{Context, Rules, Shot};
    use kisstime::simulate::{BallState, Event, EventKind, EventRecord, NO_AGENT};
    let r = 0.028575;
    // the white and the black alone; the white pots the black (ids 0 and 21)
    let ids = [0i64, 21];
    let start = [
        BallState::at_rest(0.5, 0.5, r),
        BallState::at_rest(0.5, 1.5, r),
    ];
    let record = |kind, ball, other, t| {
        let s = BallState::at_rest(0.5, 0.5, r);
        EventRecord {
            event: Event {
                kind,
                t,
                ball,
                other,
            },
            states: [s, s],
        }
    };
    let events = [
        record(EventKind::StickBall, 0, NO_AGENT, 0.0),
        record(EventKind::BallBall, 0, 1, 0.5),
        record(EventKind::BallPocket, 1, 5, 1.0),
    ];
    let shot = Shot {
        ids: &ids,
        start: &start,
        events: &events,
    };
    for (score, won) in [([u32::MAX, u32::MAX], true), ([0, u32::MAX], false)] {
        let context = Rules::Snooker.context(Context {
            hittable: 1 << 21,
            ball_call: Some(21),
            score,
            ..Context::default()
        });
        let v = Rules::Snooker.judge(&shot, &context).unwrap();
        assert!(v.legal && v.game_over, "{v:?}");
        assert_eq!(v.won, won, "{score:?}: {v:?}");
    }
}

/// event_loop, finding 11: a gravity of 1e-320 (positive and finite, so accepted) makes
/// every deceleration μ g a subnormal, every motion time v / (μ g) infinite, and a ball
/// moving at 3 m/s never stopped: the loop found no event, ended, and did not report a
/// cut. The simulation's parameters now refuse decelerations that are not normal f64, as
/// the pair solver's do (finding 2).
#[test]
fn simulation_parameters_with_subnormal_decelerations_are_refused() {
    use kisstime::simulate::{BallState, Limits, SimParams, Table, Vec3, simulate};
    let mut params = SimParams::default();
    params.ball.g = 1e-320;
    let err = params.validate().unwrap_err().to_string();
    assert!(err.contains("u_s * g"), "{err}");
    let mut b = BallState::at_rest(0.3, 0.3, params.ball.r);
    b.v = Vec3::new(-3.0, -3.0, 0.0);
    b.s = MotionState::Sliding;
    let table = Table::nine_foot();
    assert!(simulate(&table, params, Limits::default(), &[b], None, |_, _| ()).is_err());
    // a small but normal deceleration still simulates (and the run is cut by the time cap)
    params.ball.g = 1e-300;
    let limits = Limits {
        max_events: 100,
        max_time: 10.0,
    };
    let out = simulate(&table, params, limits, &[b], None, |_, _| ()).unwrap();
    assert!(out.cut.is_some() || out.n_events > 0, "{out:?}");
}

/// event_loop, finding 12: a ball radius of 1e-320 (positive and finite, so accepted)
/// made the spins `v / R` of a rolling ball infinite and its state NaN. The parameters now
/// refuse a radius whose moment of inertia `2/5 m R²`, inverse `1/R` or spin deceleration
/// `5 μ_sp g / (2R)` is not a normal f64.
#[test]
fn simulation_parameters_with_a_subnormal_radius_are_refused() {
    use kisstime::simulate::SimParams;
    for r in [1e-320, 1e-160, 1e200] {
        let mut params = SimParams::default();
        params.ball.r = r;
        assert!(params.validate().is_err(), "R = {r}");
    }
    let mut params = SimParams::default();
    params.ball.m = 1e-320;
    assert!(params.validate().is_err());
    // small but ordinary balls still pass
    params = SimParams::default();
    params.ball.r = 0.001;
    params.validate().unwrap();
}

/// event_loop, finding 13: moving balls that overlapped deeply were accepted, and the
/// kiss (Q1) that resolves the overlap at once (Q3) pushed a ball 2 cm into a cushion: the
/// fuzzer put 20 balls sliding on one spot in a corner. Moving balls that overlap by more
/// than `MOVING_OVERLAP_TOLERANCE` (0.1 mm; pooltool's own mid-shot states overlap by
/// ~20 µm at most) are refused now, naming the pair; a lesser overlap is simulated.
#[test]
fn deeply_overlapping_moving_balls_are_refused() {
    use kisstime::engine::{Backend, Precision, ShotEngine};
    use kisstime::simulate::{BallState, SimParams, Table, Vec3};
    let r = 0.028575;
    let moving = |x: f64, y: f64| fuzzed_moving(x, y, r);
    let mut balls = vec![
        BallState::at_rest(0.032034765625, r, r),
        moving(0.0424140625, r),
    ];
    balls.extend((0..20).map(|_| moving(r, r)));
    let (table, params) = (Table::nine_foot(), SimParams::default());
    let limits = FUZZ_LIMITS;
    let mut engine = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
    let shots = [kisstime::gpu::GpuShot {
        balls: balls.clone(),
        strike: None,
    }];
    let err = engine
        .simulate(&table, params, limits, &shots, true)
        .unwrap_err()
        .to_string();
    assert!(err.contains("balls 0 and 1 overlap"), "{err}");
    // 50 µm is simulated, and its kiss keeps the balls on the table
    let balls = [
        BallState::at_rest(0.6, 1.0, r),
        BallState {
            v: Vec3::new(0.0, -1.0, 0.0),
            s: MotionState::Sliding,
            ..BallState::at_rest(0.6, 1.0 + 2.0 * r - 5e-5, r)
        },
    ];
    let (_, verdict) = simulate_and_check_on(&table, params, limits, &balls, None);
    if let Err(v) = verdict {
        panic!("{v}");
    }
}

/// event_loop, finding 14: a strike of V0 = 1e-300 m/s gives the cue ball a speed whose
/// energy rounds to 0, so after the strike the table still looked at rest at t = 0 and the
/// strike was offered again: 400 strikes at t = 0, to the event cap. The strike now happens
/// once.
#[test]
fn a_strike_too_soft_to_move_the_ball_happens_once() {
    use kisstime::simulate::{BallState, CueStrike, EventKind};
    let r = 0.028575;
    let balls = [BallState::at_rest(
        1.2561225524902344,
        2.4912409606933594,
        r,
    )];
    let strike = CueStrike {
        v0: 1e-300,
        phi: 115.257568359375,
        theta: -10.0,
        a: 1.0,
        b: 0.0,
    };
    let (run, verdict) = simulate_and_check(&balls, (0, strike));
    let strikes = run
        .events
        .iter()
        .filter(|e| e.event.kind == EventKind::StickBall)
        .count();
    assert_eq!(strikes, 1, "{:?}", run.outcome);
    assert!(run.outcome.cut.is_none(), "{:?}", run.outcome);
    verdict.unwrap();
}

/// event_loop, finding 15: a tip on the rim of the ball (a = 0.9569…, b = −0.2902…, which
/// `CueStrike::validate` accepts: a² + b² ≤ 1) made `1 − a² − b²` round to −1e-17, its
/// square root NaN, the strike NaN, and the shot's event times NaN. The difference is
/// clamped at 0 now.
#[test]
fn a_strike_on_the_rim_of_the_ball_is_finite() {
    use kisstime::simulate::{BallState, CueStrike};
    let r = 0.028575;
    let balls = [BallState::at_rest(
        0.032198023509979246,
        0.7839516206642613,
        r,
    )];
    let strike = CueStrike {
        v0: 9.999847412109375,
        phi: 359.9945068359375,
        theta: 0.0,
        a: 0.9569403357322088,
        b: -0.2902846772544625,
    };
    strike.validate().unwrap();
    assert!(1.0 - strike.a * strike.a - strike.b * strike.b < 0.0);
    let (run, verdict) = simulate_and_check(&balls, (0, strike));
    assert!(run.outcome.t_end.is_finite(), "{:?}", run.outcome);
    if let Err(v) = verdict {
        // the ball may go through the rail it is struck into (finding 7); nothing else
        assert_eq!(
            v.invariant,
            kisstime::simulate::invariants::Invariant::RailTunnel,
            "{v}"
        );
    }
}

/// event_loop, finding 16, pooltool's own: at a straight cushion the ball leaves with more
/// kinetic energy than it brought: 2.17 J after the event against 1.63 J just before.
/// Parameters far from pooltool's (cushion friction f_c = 0.79, 4 times its default;
/// restitution e_c = 0.26; sliding friction 0.055) and a ball spinning at 150 rad/s (side
/// and top spin), sliding at 3.4 m/s into the foot rail. pooltool 0.6.0's cushion model
/// does the same, event for event over the shot's 840 events
/// (python/tests/test_pooltool.py, `test_a_cushion_adds_energy_as_in_pooltool`, runs
/// pooltool on it), so it is reproduced, not changed; this test pins where the checker
/// sees it.
#[test]
fn a_cushion_adds_energy_as_in_pooltool() {
    use kisstime::simulate::invariants::Invariant;
    use kisstime::simulate::{BallState, Limits, Table};
    let params = fuzzed_params([
        0.055084161926952604,
        0.002500317317734928,
        0.019301464723413223,
        0.5,
        0.26104106999514737,
        0.7913824105551804,
    ]);
    let r = params.ball.r;
    let balls = [
        fuzzed_moving(0.09667239379882812, 2.4915564453125003, r),
        BallState::at_rest(1.0, 0.3, r),
    ];
    let limits = Limits {
        max_events: 1000,
        max_time: 20.0,
    };
    let (run, verdict) = simulate_and_check_on(&Table::nine_foot(), params, limits, &balls, None);
    assert_eq!(run.events.len(), 840);
    let v = verdict.unwrap_err();
    assert_eq!((v.invariant, v.ball), (Invariant::Energy, Some(0)), "{v}");
    assert!(v.detail.starts_with("ball_linear_cushion:"), "{v}");
}

/// event_loop, finding 7 again, by a massé: the cue ball frozen to the left rail and to a
/// second ball is struck almost vertically (theta 87.5°, a = 1). The collision at t = 0
/// and its kiss (Q1) leave it 1.1 µm inside the rail's checked line, moving out at 0.7 mm/s
/// while its spin curves it back in: it never crosses the line from outside, gets no
/// cushion event, and ends 1 m off the table. The checker reports it as `RailTunnel` (the
/// ball was on the line with its path heading in), as pooltool's Q6.
#[test]
fn a_masse_off_a_frozen_ball_goes_through_the_rail_as_in_pooltool() {
    use kisstime::simulate::invariants::Invariant;
    use kisstime::simulate::{BallState, CueStrike};
    let r = 0.028575;
    let balls = [
        BallState::at_rest(r, 0.48687539405822755, r),
        BallState::at_rest(0.08572485156246025, 0.4868754614567604, r),
    ];
    let strike = CueStrike {
        v0: 1.49017333984375,
        phi: 37.55126953125,
        theta: 87.5390625,
        a: 1.0,
        b: 0.0,
    };
    let (run, verdict) = simulate_and_check(&balls, (0, strike));
    assert!(run.balls[0].r.x < -0.5, "{:?}", run.balls[0].r);
    let v = verdict.unwrap_err();
    assert_eq!(
        (v.invariant, v.ball),
        (Invariant::RailTunnel, Some(0)),
        "{v}"
    );
}

/// event_loop, finding 17: a cushion restitution of 1e-320 (in (0, 1], so accepted) made
/// the cushion's resolution NaN, and with it the shot's end time and the ball's position.
/// Restitutions must be normal f64 now.
#[test]
fn subnormal_restitutions_are_refused() {
    use kisstime::simulate::SimParams;
    for (e_b, e_c) in [(0.95, 1e-320), (1e-320, 0.85), (0.95, 0.0)] {
        let mut params = SimParams::default();
        params.ball.e_b = e_b;
        params.ball.e_c = e_c;
        assert!(params.validate().is_err(), "e_b {e_b}, e_c {e_c}");
    }
    let mut params = SimParams::default();
    params.ball.e_c = 1e-300;
    params.validate().unwrap();
}

/// event_loop, finding 19: on a pocketless 3 m × 3 m table (`Table::rectangle`) with no
/// cushion friction (f_c = 0), a ball sliding at 4.2 m/s with 150 rad/s of spin bounced
/// off the bottom and left cushions and got its top-cushion event at y = 3.0285 m, R
/// *beyond* the rail, and rolled on off the table. After the frictionless cushion its
/// sliding acceleration along y was ~2.5e-14 m/s², just above pooltool's `EPS`, and
/// pooltool's quadratic formula (copied for identity, Q6) then loses the root to
/// cancellation (τ₂ = −τ₁ − B/A with τ₁ ~ 1e14 s): 18 ms late. pooltool itself refuses
/// f_c = 0 (its `BallParams` requires positive frictions, and its cushion model divides
/// by f_c), and so does kisstime now; with f_c = 1e-9 the ball meets the top rail at
/// y = l − R, and on pooltool's billiard table of the same size the shot is pooltool's,
/// event for event (python/tests/test_pooltool.py,
/// `test_a_nearly_frictionless_cushion_shot_on_a_billiard_table_is_pooltools`).
#[test]
fn a_frictionless_cushion_is_refused_and_a_nearly_frictionless_one_stays_on_the_table() {
    use kisstime::engine::{Backend, Precision, ShotEngine};
    use kisstime::simulate::{BallState, EventKind, SimParams, Table};
    let side = 2.9999618530273438;
    let table = Table::rectangle(side, side, 0.036576).unwrap();
    let mut params = SimParams::default();
    let r = params.ball.r;
    let balls = [
        fuzzed_moving(2.8219471886157987, 0.07527489512860774, r),
        BallState::at_rest(1.5, 2.5, r),
    ];
    let limits = FUZZ_LIMITS;
    for f_c in [0.0, -0.1, 1e-320] {
        params.ball.f_c = f_c;
        let shots = [kisstime::gpu::GpuShot {
            balls: balls.to_vec(),
            strike: None,
        }];
        let mut engine = ShotEngine::new(Backend::Cpu, Precision::F64).unwrap();
        let err = engine
            .simulate(&table, params, limits, &shots, true)
            .unwrap_err()
            .to_string();
        assert!(err.contains("f_c"), "{f_c}: {err}");
    }
    params.ball.f_c = 1e-9;
    let (run, verdict) = simulate_and_check_on(&table, params, limits, &balls, None);
    if let Err(v) = verdict {
        panic!("{v}");
    }
    let top = run
        .events
        .iter()
        .find(|e| e.event.kind == EventKind::BallLinearCushion && e.event.other == 3)
        .expect("a top-rail event");
    assert!(
        (top.states[0].r.y - (side - r)).abs() < 2e-6,
        "{:?}",
        top.states[0].r
    );
}

/// event_loop, finding 30 (FUZZING.md): on the 7-ft table, four balls at rest near the
/// left rail's lower stretch (one pocketed) and the cue ball struck hard with draw (V0
/// 6.27 m/s, θ 16.5°, b = 0.70) under scaled frictions and restitutions. The cue ball ends
/// chattering between ball 1 and the jaw 11t; each ball–ball kiss (Q1) presses it a little
/// further into the jaw, where the detection finds no root τ > EPS (Q6), and after its
/// 74th event its centre is 0.0495 m from the jaw's centre, inside r_jaw + R. pooltool
/// 0.6.0 does the same, event for event (python/tests/test_pooltool.py,
/// `test_a_ball_pressed_into_a_jaw_goes_in_as_in_pooltool`), so the checker reports it as
/// `RailTunnel` at the jaw — finding 7's case for a jaw — not as `OffTable`. Found by the
/// fuzzer after 666,989 executions.
#[test]
fn a_ball_pressed_into_a_jaw_goes_in_as_in_pooltool() {
    use kisstime::simulate::invariants::Invariant;
    use kisstime::simulate::{BallState, CueStrike, Table, Vec3};
    let params = fuzzed_params([
        0.10703053615979914,
        0.005351526807989957,
        0.006796439046147245,
        0.6372528076171875,
        0.4548797786791463,
        0.10706676685817214,
    ]);
    let r = params.ball.r;
    let balls = [
        BallState::at_rest(0.26190203704833986, 0.5338272994995117, r),
        BallState::at_rest(0.2680727123695044, 0.5906429130597868, r),
        BallState::at_rest(0.32274157165991874, 0.5739864331195599, r),
        BallState::at_rest(0.25930369188503394, 0.647115874765602, r),
        BallState {
            r: Vec3::new(1.020086352775479, -0.029486352775479032, -0.1),
            s: MotionState::Pocketed,
            ..BallState::at_rest(0.0, 0.0, r)
        },
    ];
    let strike = (
        0,
        CueStrike {
            v0: 6.2689208984375,
            phi: 112.5,
            theta: 16.5234375,
            a: -0.10865749163367232,
            b: 0.7001047596694929,
        },
    );
    let limits = FUZZ_LIMITS;
    let (run, verdict) =
        simulate_and_check_on(&Table::seven_foot(), params, limits, &balls, Some(strike));
    assert_eq!(run.outcome.cut, None);
    let v = verdict.unwrap_err();
    assert_eq!(
        (v.invariant, v.ball),
        (Invariant::RailTunnel, Some(0)),
        "{v}"
    );
    assert!(v.detail.contains("inside the jaw 11t"), "{v}");
    assert!(
        v.detail.contains("touched the jaw 11t moving into it"),
        "{v}"
    );
}

/// event_loop, finding 31: three balls at rest in a row, each pair exactly 2R apart as
/// pooltool computes it (its quartic's constant coefficient `Δx² + Δy² − 4R²` is 0), and
/// the end ball struck away from its neighbour at 1e-9 m/s with massé. pooltool's root
/// filter keeps the root τ = 0 (spec §4.2), so it collides the pair at once although it
/// moves apart, and then the next pair, and the first again, all at t = 0
/// (python/tests/test_pooltool.py, `test_exactly_touching_balls_collide_at_once_as_in_pooltool`,
/// runs pooltool on it). kisstime waited for the pair to come back (its rule for touching
/// balls moving apart), met it 2.85 ns later, and the kiss of the other pair (Q1) then left
/// balls 1 and 2 overlapping by 3.9 µm at the end. Found after 385,426 executions.
#[test]
fn exactly_touching_balls_collide_at_once_as_in_pooltool() {
    use kisstime::simulate::{BallState, CueStrike, EventKind, Limits, SimParams, Table};
    let params = SimParams::default();
    let r = params.ball.r;
    let balls = [
        BallState::at_rest(0.3205843640387058, 0.191408986531198, r),
        BallState::at_rest(0.28262233721207614, 0.23412908741139543, r),
        BallState::at_rest(0.2363870159835479, 0.2005371602428806, r),
    ];
    let strike = CueStrike {
        v0: 1e-9,
        phi: 215.9967041015625,
        theta: 53.988189697265625,
        a: -0.629118477661764,
        b: -0.45188581056623933,
    };
    let (run, verdict) = simulate_and_check_on(
        &Table::nine_foot(),
        params,
        Limits::default(),
        &balls,
        Some((2, strike)),
    );
    if let Err(v) = verdict {
        panic!("{v}");
    }
    let kisses: Vec<(u32, u32, f64)> = run
        .events
        .iter()
        .filter(|e| e.event.kind == EventKind::BallBall)
        .map(|e| (e.event.ball, e.event.other, e.event.t))
        .collect();
    assert_eq!(kisses, [(1, 2, 0.0), (0, 1, 0.0), (1, 2, 0.0)]);
    assert_eq!(run.events.len(), 10);
}

/// event_loop, finding 32: a ball sliding with 170 rad/s of spin chatters along the left
/// rail of the 7-ft table into the corner pocket lb (a hundred cushion events ~1 ms apart),
/// and one cushion's kiss (Q1) leaves its centre a rounding error inside the pocket's
/// circle. kisstime pocketed a ball only where its centre *entered* the circle, so this one
/// rolled on, out of the circle and off the table; pooltool's quartic takes the first
/// crossing either way and pockets it where it leaves the circle, 0.31 s later
/// (python/tests/test_pooltool.py, `test_a_ball_inside_a_pocket_circle_falls_in_as_in_pooltool`,
/// runs pooltool on it). `circle_crossing` now does the same. Found after 375,654
/// executions.
#[test]
fn a_ball_a_kiss_leaves_inside_a_pocket_circle_falls_in_as_in_pooltool() {
    use kisstime::simulate::{BallState, EventKind, Table};
    let params = fuzzed_params([
        0.1879169515578241,
        0.013252366431597414,
        0.004261549747994339,
        0.5,
        0.21333772610400897,
        0.050544464302585024,
    ]);
    let r = params.ball.r;
    let balls = [
        fuzzed_moving(0.6960367782592773, 0.974774609375, r),
        BallState::at_rest(0.8, 1.8, r),
    ];
    let limits = FUZZ_LIMITS;
    let table = Table::seven_foot();
    let (run, verdict) = simulate_and_check_on(&table, params, limits, &balls, None);
    if let Err(v) = verdict {
        panic!("{v}");
    }
    let last = run.events.last().unwrap().event;
    assert_eq!(run.events.len(), 185);
    assert_eq!((last.kind, last.ball), (EventKind::BallPocket, 0));
    assert_eq!(table.pocket_ids[last.other as usize], "lb");
    assert!((last.t - 1.128845880053901).abs() < 1e-9, "{}", last.t);
}

/// event_loop, finding 33: on a 0.735 m square table (`Table::rectangle`), a massé
/// (θ = 89.999°, a = 0.998) sends the cue ball into two balls by the left rail, one 2 mm
/// from it; they chatter, and at event 282 a ball–ball kiss (Q1, which moves the pair
/// apart without looking at the cushions) pushes ball 1 10 µm into the left rail. pooltool
/// would do the same, but its own run stops earlier: at its 196th event its cushion
/// resolver asserts that the ball approaches (Q16) and raises, where kisstime gives no
/// impulse; up to there the events are pooltool's (python/tests/test_pooltool.py,
/// `test_a_chattering_masse_is_pooltools_until_pooltool_raises`). The checker reports the
/// push as `RailTunnel` (the kiss), as it reports pooltool's Q6 (finding 13 is the same
/// push from balls given overlapping). Found after 77,165 executions (sixth round).
#[test]
fn a_kiss_that_pushes_a_ball_into_a_rail_is_told_apart() {
    use kisstime::simulate::invariants::Invariant;
    use kisstime::simulate::{BallState, CueStrike, Table};
    let table = Table::rectangle(0.73529052734375, 0.7353286743164063, 0.036576).unwrap();
    let params = fuzzed_params([
        0.050010577705338156,
        0.0025,
        0.003175,
        0.5688400268554688,
        0.2125,
        0.05007409094683693,
    ]);
    let r = params.ball.r;
    let balls = [
        BallState::at_rest(0.07692935004085302, 0.32022825556844475, r),
        BallState::at_rest(0.0306652158588171, 0.4391806460296735, r),
        BallState::at_rest(0.08881520060002804, 0.43918064602967344, r),
    ];
    let strike = CueStrike {
        v0: 1.68304443359375,
        phi: 8.4320068359375,
        theta: 89.99862670898438,
        a: 0.998044963916957,
        b: 0.0,
    };
    let limits = FUZZ_LIMITS;
    let (_, verdict) = simulate_and_check_on(&table, params, limits, &balls, Some((0, strike)));
    let v = verdict.unwrap_err();
    assert_eq!(
        (v.invariant, v.ball, v.event),
        (Invariant::RailTunnel, Some(1), Some(282)),
        "{v}"
    );
    assert!(v.detail.contains("the kiss of this ball–ball event"), "{v}");
}

/// event_loop, finding 34: on the 7-ft table a ball sliding with 170 rad/s of spin
/// chatters along the throat of the corner pocket lb (a hundred cushion events against
/// segment 2) and, rolling into the pocket, passes the segment's deep end with its centre
/// 0.43 mm closer than R to the end point. pooltool's straight cushion is met only where
/// the ball's centre projects inside the segment (§4.4), so neither pooltool nor kisstime
/// has an event there, and the ball is pocketed 0.15 s later; the 141 events are
/// pooltool's (python/tests/test_pooltool.py,
/// `test_a_ball_clipping_a_throat_segment_end_is_pooltools`). The checker measured the
/// distance to the segment's end point; it now measures as the model does, within the
/// segment's extent. Found after 2,656,925 executions (sixth round).
#[test]
fn a_ball_clipping_the_end_of_a_throat_segment_is_in_play() {
    use kisstime::simulate::{BallState, EventKind, Table};
    let params = fuzzed_params([
        0.20322407042678328,
        0.004767399444076855,
        0.0031786287836843797,
        0.5,
        0.2125,
        0.050544464302585024,
    ]);
    let r = params.ball.r;
    let balls = [
        BallState::at_rest(0.6509302291870117, 0.6450686683654785, r),
        fuzzed_moving(0.322786402130127, 0.6505086463928222, r),
    ];
    let limits = FUZZ_LIMITS;
    let table = Table::seven_foot();
    let (run, verdict) = simulate_and_check_on(&table, params, limits, &balls, None);
    if let Err(v) = verdict {
        panic!("{v}");
    }
    assert_eq!(run.events.len(), 141);
    let last = run.events.last().unwrap().event;
    assert_eq!((last.kind, last.ball), (EventKind::BallPocket, 1));
}
