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
