//! NumPy `.npy` batches and answers: both input layouts read back the batch that was
//! written, bad arrays are refused naming the file, row, table and ball, and the CLI's
//! `.npy` outputs carry exactly the answers of its CSV outputs.

use std::path::Path;

use kisstime::Params;
use kisstime::io::npy::{read_batch_npy, write_batch_npy};
use kisstime::io::{read_batch_csv, write_batch_csv};
use kisstime::workload::{Workload, generate};

mod common;
use common::{plain_array_npy, run_kisstime};

/// A batch as CSV text: two batches are the same when these are.
fn csv_of(batch: &kisstime::Batch) -> String {
    let mut out = Vec::new();
    write_batch_csv(&mut out, batch).unwrap();
    String::from_utf8(out).unwrap()
}

fn sample_batch() -> kisstime::Batch {
    generate(Workload::Spread, 50, 7, 3, &Params::default())
}

#[test]
fn structured_layout_round_trips() {
    let batch = sample_batch();
    let mut bytes = Vec::new();
    write_batch_npy(&mut bytes, &batch).unwrap();
    let back = read_batch_npy(&bytes[..], "t.npy").unwrap();
    assert_eq!(csv_of(&back), csv_of(&batch));
}

/// The plain layout: a float64 array of shape (N, 10), rows in any order.
fn plain_npy(rows: &[[f64; 10]]) -> Vec<u8> {
    plain_array_npy(&[rows.len() as u64, 10], rows.as_flattened())
}

/// The batch's rows as (table, ball, state code, numbers…), last table first and each
/// table's balls reversed, to check that order does not matter.
fn plain_rows(batch: &kisstime::Batch) -> Vec<[f64; 10]> {
    let mut rows = Vec::new();
    for k in (0..batch.num_tables()).rev() {
        for (id, b) in batch.ball_ids(k).iter().zip(batch.balls(k)).rev() {
            let mut row = [0.0; 10];
            row[0] = batch.table_id(k) as f64;
            row[1] = *id as f64;
            row[2] = b.state as u8 as f64;
            row[3..].copy_from_slice(&b.numbers());
            rows.push(row);
        }
    }
    rows
}

#[test]
fn plain_layout_in_any_row_order_reads_as_the_same_batch() {
    let batch = sample_batch();
    let bytes = plain_npy(&plain_rows(&batch));
    let back = read_batch_npy(&bytes[..], "plain.npy").unwrap();
    assert_eq!(csv_of(&back), csv_of(&batch));
}

fn npy_error(bytes: &[u8]) -> String {
    match read_batch_npy(bytes, "bad.npy") {
        Ok(_) => panic!("the array was accepted"),
        Err(e) => {
            assert!(e.is_bad_input(), "{e}");
            e.to_string()
        }
    }
}

#[test]
fn bad_arrays_are_refused_naming_row_table_and_ball() {
    let batch = sample_batch();
    let good = plain_rows(&batch);

    let mut rows = good.clone();
    rows[5][2] = 7.0;
    let msg = npy_error(&plain_npy(&rows));
    assert!(msg.starts_with("bad.npy, row 5, table "), "{msg}");
    assert!(msg.contains("state 7 is not a state code"), "{msg}");

    let mut rows = good.clone();
    rows[3][6] = f64::NAN;
    let msg = npy_error(&plain_npy(&rows));
    assert!(msg.contains("row 3") && msg.contains("vy is NaN"), "{msg}");

    let mut rows = good.clone();
    rows[2][1] = 0.5;
    let msg = npy_error(&plain_npy(&rows));
    assert!(
        msg.contains("row 2") && msg.contains("ball id 0.5 is not an integer"),
        "{msg}"
    );

    // the same ball twice: the later row is named, with the first
    let mut rows = good.clone();
    rows[4] = rows[3];
    let msg = npy_error(&plain_npy(&rows));
    assert!(
        msg.contains("row 4") && msg.contains("duplicate ball id (first on row 3)"),
        "{msg}"
    );

    // a table of one ball
    let mut rows = good.clone();
    rows[0][0] = 1e6;
    let msg = npy_error(&plain_npy(&rows));
    assert!(
        msg.contains("row 0, table 1000000") && msg.contains("has 1"),
        "{msg}"
    );
}

#[test]
fn wrong_shapes_dtypes_and_truncated_files_are_errors() {
    // a 1-D float array
    let bytes = plain_array_npy(&[3], &[1.0f64, 2.0, 3.0]);
    let msg = npy_error(&bytes);
    assert!(msg.contains("expected a 1-D structured array"), "{msg}");

    // 2-D of the wrong width
    let bytes = plain_array_npy(&[1, 3], &[1.0f64, 2.0, 3.0]);
    assert!(npy_error(&bytes).contains("shape [1, 3]"));

    // integers instead of floats
    let bytes = plain_array_npy(&[1, 10], &[0i32; 10]);
    assert!(npy_error(&bytes).contains("'<i4'"));

    // not an npy file at all, and every truncation of a good one
    assert!(npy_error(b"table,ball\n").contains("not a readable .npy file"));
    let good = plain_npy(&plain_rows(&sample_batch()));
    for cut in [0, 5, 60, good.len() / 2, good.len() - 1] {
        npy_error(&good[..cut]);
    }
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[derive(npyz::Deserialize)]
struct PairRow {
    table: i64,
    i: i64,
    j: i64,
    t: f64,
    status: i64,
    horizon: f64,
}

#[derive(npyz::Deserialize)]
struct NextRow {
    table: i64,
    t: f64,
    i: i64,
    j: i64,
    status: i64,
}

fn status_code(name: &str) -> i64 {
    match name {
        "none" => 0,
        "hit" => 1,
        "overlap" => 2,
        other => panic!("status {other}"),
    }
}

fn time(text: &str) -> f64 {
    if text == "inf" {
        f64::INFINITY
    } else {
        text.parse().unwrap()
    }
}

#[test]
fn cli_npy_outputs_carry_the_csv_answers() {
    let dir = tempfile::tempdir().unwrap();
    let input_npy = dir.path().join("in.npy");
    let input_csv = dir.path().join("in.csv");
    for input in [&input_npy, &input_csv] {
        let out = run_kisstime(
            &[
                "gen",
                "--scenario",
                "rack",
                "--tables",
                "40",
                "-o",
                s(input),
            ],
            &[],
        );
        assert!(out.status.success());
    }
    let pairs_npy = dir.path().join("pairs.npy");
    let next_npy = dir.path().join("next.NPY");
    for (cmd, out) in [("pairs", &pairs_npy), ("next", &next_npy)] {
        let o = run_kisstime(&[cmd, s(&input_npy), "-o", s(out)], &[]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let pairs_csv = run_kisstime(&["pairs", s(&input_csv)], &[]);
    let next_csv = run_kisstime(&["next", s(&input_csv)], &[]);

    let bytes = std::fs::read(&pairs_npy).unwrap();
    let rows: Vec<PairRow> = npyz::NpyFile::new(&bytes[..]).unwrap().into_vec().unwrap();
    let text = String::from_utf8(pairs_csv.stdout).unwrap();
    let lines: Vec<&str> = text.lines().skip(1).collect();
    assert_eq!(rows.len(), lines.len());
    assert_eq!(rows.len(), 40 * 120);
    for (r, line) in rows.iter().zip(&lines) {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(
            (r.table, r.i, r.j),
            (
                f[0].parse().unwrap(),
                f[1].parse().unwrap(),
                f[2].parse().unwrap()
            )
        );
        assert_eq!(r.t.to_bits(), time(f[3]).to_bits(), "{line}");
        assert_eq!(r.status, status_code(f[4]), "{line}");
        assert_eq!(r.horizon.to_bits(), time(f[5]).to_bits(), "{line}");
    }

    let bytes = std::fs::read(&next_npy).unwrap();
    let rows: Vec<NextRow> = npyz::NpyFile::new(&bytes[..]).unwrap().into_vec().unwrap();
    let text = String::from_utf8(next_csv.stdout).unwrap();
    let lines: Vec<&str> = text.lines().skip(1).collect();
    assert_eq!(rows.len(), 40);
    for (r, line) in rows.iter().zip(&lines) {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(r.table, f[0].parse::<i64>().unwrap());
        assert_eq!(r.t.to_bits(), time(f[1]).to_bits(), "{line}");
        assert_eq!(r.status, status_code(f[4]), "{line}");
        if f[2].is_empty() {
            assert_eq!((r.i, r.j), (-1, -1));
        } else {
            assert_eq!((r.i, r.j), (f[2].parse().unwrap(), f[3].parse().unwrap()));
        }
    }
}

#[test]
fn cli_names_the_npy_file_and_row_of_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("bad.npy");
    let mut rows = plain_rows(&sample_batch());
    rows[9][4] = f64::INFINITY;
    std::fs::write(&input, plain_npy(&rows)).unwrap();
    let out_file = dir.path().join("out.npy");
    let out = run_kisstime(&["next", s(&input), "-o", s(&out_file)], &[]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.npy, row 9, table ") && err.contains("y is inf"),
        "{err}"
    );
    assert!(!out_file.exists());
}

#[test]
fn csv_input_still_reads_in_any_order() {
    let text = "table,ball,state,x,y,vx,vy,wx,wy,wz\n\
                2,5,stationary,1,0,0,0,0,0,0\n\
                1,1,stationary,0,0,0,0,0,0,0\n\
                2,1,rolling,0,0,1,0,0,0,0\n\
                1,0,stationary,0.5,0,0,0,0,0,0\n";
    let batch = read_batch_csv(text.as_bytes(), "x.csv").unwrap();
    assert_eq!(batch.num_tables(), 2);
    assert_eq!(batch.table_id(0), 1);
    assert_eq!(batch.ball_ids(0), &[0, 1]);
    assert_eq!(batch.ball_ids(1), &[1, 5]);
}

/// Files written by NumPy itself (`np.save`, docs/cli.md's example: a rolling cue ball 1 m
/// from a still ball), in both layouts.
#[test]
fn files_saved_by_numpy_read() {
    for name in ["numpy_structured.npy", "numpy_plain.npy"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data")
            .join(name);
        let batch = kisstime::io::npy::read_batch_npy_path(&path).unwrap();
        assert_eq!(batch.num_tables(), 1);
        assert_eq!(batch.ball_ids(0), &[0, 1]);
        assert_eq!(batch.balls(0)[0].state, kisstime::MotionState::Rolling);
        let next = kisstime::next_collisions(&batch, &Params::default()).unwrap();
        assert_eq!(next[0].pair, Some((0, 1)));
        assert!((next[0].t - 0.477).abs() < 1e-3, "{}", next[0].t);
    }
}

/// An `.npy` file with the header `descr` (a NumPy dtype description) and `rows` rows of
/// `row_bytes` zero bytes, as `numpy.save` lays it out (version 1.0, header padded to 64).
fn npy_with_descr(descr: &str, rows: usize, row_bytes: usize) -> Vec<u8> {
    let mut header = format!("{{'descr': {descr}, 'fortran_order': False, 'shape': ({rows},), }}");
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    bytes.resize(bytes.len() + rows * row_bytes, 0);
    bytes
}

#[test]
fn structured_arrays_with_other_names_or_widths_are_refused_in_plain_words() {
    // a misnamed field: what is needed first, then what the file has
    let misnamed = "[('tbl', '<i8'), ('ball', '<i8'), ('state', '<i8'), ('x', '<f8'), \
                    ('y', '<f8'), ('vx', '<f8'), ('vy', '<f8'), ('wx', '<f8'), ('wy', '<f8'), \
                    ('wz', '<f8')]";
    let msg = npy_error(&npy_with_descr(misnamed, 2, 80));
    assert!(
        msg.contains("must be table, ball, state, x, y, vx, vy, wx, wy, wz in this order")
            && msg.contains("this file has tbl, ball"),
        "{msg}"
    );
    assert!(!msg.contains("), ]"), "{msg}");
    // int32 ids and float32 numbers: named in words, with the fix
    let narrow = "[('table', '<i4'), ('ball', '<i4'), ('state', '<i4'), ('x', '<f4'), \
                  ('y', '<f4'), ('vx', '<f4'), ('vy', '<f4'), ('wx', '<f4'), ('wy', '<f4'), \
                  ('wz', '<f4')]";
    let msg = npy_error(&npy_with_descr(narrow, 2, 40));
    assert!(
        msg.contains("field 'table' is int32 ('<i4')") && msg.contains("int64 ('<i8')"),
        "{msg}"
    );
    // a float32 plain array
    let bytes = plain_array_npy(&[1, 10], &[0f32; 10]);
    let msg = npy_error(&bytes);
    assert!(
        msg.contains("float32 ('<f4')") && msg.contains("float64"),
        "{msg}"
    );
}
