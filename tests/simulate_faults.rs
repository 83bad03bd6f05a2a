//! `kisstime simulate` under faults (issue 31, "Soak and faults"; the by-hand runs are
//! `tools/soak/faults.py`): SIGINT and SIGTERM in the middle of a run (exit 130, a message
//! saying how far it got, the file the user named as it was before, no temporary file
//! left), a full device as an output (a clear error naming it), and the input read in
//! chunks giving the whole read's output bit for bit, with the same errors.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::run_kisstime;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Every file in `dir`, sorted.
fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// `kisstime gen` of `tables` midshot tables (balls already moving: no strikes needed).
fn generated(dir: &Path, name: &str, tables: usize) -> PathBuf {
    let input = dir.join(name);
    let out = run_kisstime(
        &[
            "gen",
            "--scenario",
            "midshot",
            "--tables",
            &tables.to_string(),
            "--balls",
            "6",
            "-o",
            s(&input),
        ],
        &[],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    input
}

#[cfg(unix)]
fn interrupted_with(signal: &str) {
    let dir = tempfile::tempdir().unwrap();
    let input = generated(dir.path(), "in.npy", 200_000);
    let out_dir = dir.path().join("out");
    std::fs::create_dir(&out_dir).unwrap();
    let events = out_dir.join("events.npy");
    let finals = out_dir.join("final.npy");
    std::fs::write(&events, b"the previous run's events").unwrap();
    // small chunks, so that the progress count moves while the outputs are written
    let mut child = Command::new(env!("CARGO_BIN_EXE_kisstime"))
        .args([
            "simulate",
            s(&input),
            "-o",
            s(&events),
            "--final",
            s(&finals),
        ])
        .args(["--input-chunk-tables", "2000"])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // halfway or so: once the final states' temporary file has grown (the events are
    // spooled until the end)
    let start = Instant::now();
    let mut grown = false;
    while start.elapsed() < Duration::from_secs(120) {
        let big = std::fs::read_dir(&out_dir).unwrap().any(|e| {
            let e = e.unwrap();
            e.file_name().to_string_lossy().starts_with(".kisstime-")
                && e.metadata().map_or(0, |m| m.len()) > 4 << 20
        });
        if big {
            grown = true;
            break;
        }
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(grown, "the run ended before it could be interrupted");
    let killed = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let result = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(130), "{signal}: {err}");
    // "interrupted after X of 200000 tables", 0 < X < 200000
    let after = err
        .split("interrupted after ")
        .nth(1)
        .unwrap_or_else(|| panic!("{signal}: no progress in {err:?}"));
    let done: u64 = after.split(' ').next().unwrap().parse().unwrap();
    assert!(after.contains("of 200000 tables"), "{err}");
    assert!(done > 0 && done < 200_000, "{signal}: {done} tables: {err}");
    // the previous file as it was, no new one, no temporary file
    assert_eq!(
        std::fs::read(&events).unwrap(),
        b"the previous run's events",
        "{signal}"
    );
    assert_eq!(files(&out_dir), vec!["events.npy".to_owned()], "{signal}");
}

#[cfg(unix)]
#[test]
fn sigint_mid_simulate_says_how_far_and_keeps_the_previous_file() {
    interrupted_with("INT");
}

#[cfg(unix)]
#[test]
fn sigterm_mid_simulate_says_how_far_and_keeps_the_previous_file() {
    interrupted_with("TERM");
}

#[cfg(target_os = "linux")]
#[test]
fn simulate_to_a_full_device_is_an_error_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let input = generated(dir.path(), "in.npy", 2_000);
    for flag in ["-o", "--final", "--outcomes"] {
        let out = run_kisstime(&["simulate", s(&input), flag, "/dev/full"], &[]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{flag}: {err}");
        assert!(
            err.contains("/dev/full") && err.contains("No space left"),
            "{flag}: {err}"
        );
    }
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_kisstime"))
        .args(["simulate", s(&input)])
        .stdout(full)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("standard output") && err.contains("No space left"),
        "{err}"
    );
    assert_eq!(files(dir.path()), vec!["in.npy".to_owned()]);
}

/// Finding 22: a run's outputs are renamed into place together, only when all are
/// complete. The events go to `/dev/full`, which fails only when its buffer is flushed at
/// the end (a few tables' events fit in it), after the final states and the outcomes were
/// complete: neither file may then appear (they used to be renamed into place one by one,
/// the innermost first, before the events' failure).
#[cfg(target_os = "linux")]
#[test]
fn outputs_are_renamed_together_or_not_at_all() {
    let dir = tempfile::tempdir().unwrap();
    let input = generated(dir.path(), "in.npy", 3);
    let (finals, outcomes) = (dir.path().join("final.csv"), dir.path().join("out.csv"));
    let out = run_kisstime(
        &[
            "simulate",
            s(&input),
            "-o",
            "/dev/full",
            "--final",
            s(&finals),
            "--outcomes",
            s(&outcomes),
        ],
        &[],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("/dev/full") && err.contains("No space left"),
        "{err}"
    );
    assert_eq!(files(dir.path()), vec!["in.npy".to_owned()]);
    // and with every output a file, all three are written
    let events = dir.path().join("events.csv");
    let out = run_kisstime(
        &[
            "simulate",
            s(&input),
            "-o",
            s(&events),
            "--final",
            s(&finals),
            "--outcomes",
            s(&outcomes),
        ],
        &[],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        files(dir.path()),
        ["events.csv", "final.csv", "in.npy", "out.csv"].map(String::from)
    );
}

/// Finding 29: the events' `.npy` (whose row count is known only at the end) is written
/// straight into its file, a header for any count first and the real one over it at the
/// end, not spooled through `$TMPDIR`: with `$TMPDIR` a folder that does not exist the
/// run succeeds and gives the same array as CSV does. To standard output (which cannot go
/// back) the rows are still spooled: there the missing `$TMPDIR` is an error.
#[cfg(unix)]
#[test]
fn the_events_npy_is_written_in_place_without_a_spool() {
    let dir = tempfile::tempdir().unwrap();
    let input = generated(dir.path(), "in.npy", 50);
    let (npy, csv) = (dir.path().join("ev.npy"), dir.path().join("ev.csv"));
    let no_tmp = [("TMPDIR", "/nonexistent-kisstime-tmp")];
    let out = run_kisstime(&["simulate", s(&input), "-o", s(&npy)], &no_tmp);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = run_kisstime(&["simulate", s(&input), "-o", s(&csv)], &[]);
    assert!(out.status.success());
    let rows = std::fs::read_to_string(&csv).unwrap().lines().count() - 1;
    assert!(rows > 50, "{rows} event rows");
    let bytes = std::fs::read(&npy).unwrap();
    let array = npyz::NpyFile::new(&bytes[..]).unwrap();
    assert_eq!(array.shape(), &[rows as u64]);
    let header_len = bytes.len() - rows * 15 * 8;
    assert_eq!(header_len % 64, 0, "{header_len}");
    assert_eq!(
        files(dir.path()),
        ["ev.csv", "ev.npy", "in.npy"].map(String::from)
    );
    // a device (here through a link named .npy) is written through and cannot go back:
    // spooled, so the missing $TMPDIR is an error naming the output
    let null = dir.path().join("null.npy");
    std::os::unix::fs::symlink("/dev/null", &null).unwrap();
    let out = run_kisstime(&["simulate", s(&input), "-o", s(&null)], &no_tmp);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("null.npy"), "{err}");
}

/// Runs `simulate` on `input` (strikes `strikes`) with `extra`, returning the bytes of its
/// three outputs, or its exit code and error message.
fn outputs(
    dir: &Path,
    input: &Path,
    strikes: &Path,
    extra: &[&str],
) -> Result<Vec<Vec<u8>>, (Option<i32>, String)> {
    let names = ["ev.npy", "final.csv", "outcomes.npy"].map(|n| dir.join(n));
    let mut args = vec!["simulate", s(input), "--strikes", s(strikes)];
    args.extend(["-o", s(&names[0]), "--final", s(&names[1])]);
    args.extend(["--outcomes", s(&names[2]), "--rules", "9-ball"]);
    args.extend(extra);
    let out = run_kisstime(&args, &[]);
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        return Err((out.status.code(), err));
    }
    Ok(names.iter().map(|p| std::fs::read(p).unwrap()).collect())
}

#[test]
fn the_input_read_in_chunks_gives_the_whole_reads_output_and_errors() {
    let dir = tempfile::tempdir().unwrap();
    let input = generated(dir.path(), "in.csv", 300);
    let text = std::fs::read_to_string(&input).unwrap();
    let (header, rows) = text.split_once('\n').unwrap();
    let rows: Vec<&str> = rows.lines().collect();
    // the same rows in another order (read whole and sorted), and strikes every 3rd table
    let mut shuffled = rows.clone();
    shuffled.reverse();
    shuffled.swap(10, 700);
    let unordered = dir.path().join("unordered.csv");
    std::fs::write(&unordered, format!("{header}\n{}\n", shuffled.join("\n"))).unwrap();
    let mut strike_text = String::from("table,ball,V0,phi,theta,a,b\n");
    for t in (0..300).step_by(3) {
        strike_text.push_str(&format!(
            "{t},0,{},{},{},0.1,-0.2\n",
            1.0 + t as f64 / 300.0,
            t,
            t % 10
        ));
    }
    let strikes = dir.path().join("strikes.csv");
    std::fs::write(&strikes, &strike_text).unwrap();
    let whole = outputs(dir.path(), &unordered, &strikes, &[]).unwrap();
    for chunk in ["1", "7", "1000"] {
        let streamed = outputs(
            dir.path(),
            &input,
            &strikes,
            &["--input-chunk-tables", chunk],
        );
        assert!(streamed.unwrap() == whole, "chunks of {chunk}: other bytes");
    }
    // the strikes in another order: read whole, the same again
    let mut lines: Vec<&str> = strike_text.lines().collect();
    lines[1..].reverse();
    let unordered_strikes = dir.path().join("unordered_strikes.csv");
    std::fs::write(&unordered_strikes, lines.join("\n") + "\n").unwrap();
    let other = outputs(
        dir.path(),
        &input,
        &unordered_strikes,
        &["--input-chunk-tables", "7"],
    );
    assert!(other.unwrap() == whole, "strikes out of order: other bytes");

    // errors: the same message and exit code read in chunks as read whole
    let bad_number = dir.path().join("bad_number.csv");
    let mut b = rows.clone();
    let mut fields: Vec<&str> = b[500].split(',').collect();
    fields[3] = "x0.5";
    let broken = fields.join(",");
    b[500] = &broken;
    std::fs::write(&bad_number, format!("{header}\n{}\n", b.join("\n"))).unwrap();
    let off_table = dir.path().join("off_table.csv");
    let mut o = rows.clone();
    let mut fields: Vec<&str> = o[601].split(',').collect();
    fields[3] = "-3.0";
    let moved = fields.join(",");
    o[601] = &moved;
    std::fs::write(&off_table, format!("{header}\n{}\n", o.join("\n"))).unwrap();
    let strike_cases = [
        ("missing.csv", format!("{strike_text}999,0,1,0,0,0,0\n")),
        (
            "negative.csv",
            strike_text.replace("\n120,0,1.4,", "\n120,0,-1.4,"),
        ),
        ("no_ball.csv", strike_text.replace("\n12,0,", "\n12,9,")),
    ];
    let mut cases: Vec<(PathBuf, PathBuf)> =
        vec![(bad_number, strikes.clone()), (off_table, strikes.clone())];
    for (name, body) in strike_cases {
        let p = dir.path().join(name);
        std::fs::write(&p, body).unwrap();
        cases.push((input.clone(), p));
    }
    for (balls, strikes) in &cases {
        let chunked = outputs(dir.path(), balls, strikes, &["--input-chunk-tables", "7"]);
        let (code, err) = chunked.expect_err("refused");
        assert_eq!(code, Some(2), "{err}");
        // read whole: the same strikes sorted otherwise, or the balls reordered
        let plot = dir.path().join("p.png");
        let whole = outputs(
            dir.path(),
            balls,
            strikes,
            &["--plot", s(&plot), "--table-id", "0"],
        );
        let (_, whole_err) = whole.expect_err("refused");
        let first = |e: &str| e.lines().next().unwrap_or("").to_owned();
        assert_eq!(first(&err), first(&whole_err));
        assert!(err.contains("line "), "{err}");
        assert!(err.contains("table "), "{err}");
    }
    assert!(
        !files(dir.path())
            .iter()
            .any(|f| f.starts_with(".kisstime-")),
        "a temporary file was left"
    );
}

/// A write that fails midway into a regular file (here a file-size limit, `ulimit -f`, which
/// any user may set, standing in for a disk that fills up; `tools/soak/faults.py` fills a
/// real tmpfs): a clear error naming the output (finding 23: it named the removed
/// temporary file), a non-zero exit, the previous file as it was, no temporary file left.
#[cfg(target_os = "linux")]
#[test]
fn a_write_failing_midway_is_an_error_naming_the_output() {
    let dir = tempfile::tempdir().unwrap();
    let input = generated(dir.path(), "in.npy", 2_000);
    let out_dir = dir.path().join("out");
    std::fs::create_dir(&out_dir).unwrap();
    let finals = out_dir.join("final.csv");
    std::fs::write(&finals, b"previous").unwrap();
    // 64 blocks of 512 bytes; SIGXFSZ ignored so that the write fails with EFBIG
    let script = format!(
        "trap '' XFSZ; ulimit -f 64; exec '{}' simulate '{}' --final '{}'",
        env!("CARGO_BIN_EXE_kisstime"),
        s(&input),
        s(&finals)
    );
    let out = Command::new("sh").args(["-c", &script]).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains(&format!("error: {}: File too large", s(&finals))),
        "{err}"
    );
    assert!(
        !err.contains(".kisstime-"),
        "names the temporary file: {err}"
    );
    assert_eq!(std::fs::read(&finals).unwrap(), b"previous");
    assert_eq!(files(&out_dir), vec!["final.csv".to_owned()]);
}
