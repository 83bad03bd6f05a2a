//! Output integrity and limits: an interrupted run leaves no file behind (neither under the
//! requested name nor a temporary beside it), a full disk is an error, and an input that
//! asks for more than the machine or the crate allows is refused before allocating.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::run_kisstime;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Every file in `dir`.
fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[cfg(unix)]
#[test]
fn ctrl_c_leaves_no_output_and_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.npy");
    let out = run_kisstime(
        &[
            "gen",
            "--scenario",
            "spread",
            "--tables",
            "100000",
            "-o",
            s(&input),
        ],
        &[],
    );
    assert!(out.status.success());
    let out_dir = dir.path().join("out");
    std::fs::create_dir(&out_dir).unwrap();
    let output = out_dir.join("pairs.csv");
    // 12 M pairs of CSV: seconds of writing, long enough to be interrupted mid-file
    let mut child = Command::new(env!("CARGO_BIN_EXE_kisstime"))
        .args(["pairs", s(&input), "-o", s(&output)])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let mut temporary = false;
    while start.elapsed() < Duration::from_secs(60) {
        if files(&out_dir).iter().any(|f| f.starts_with(".kisstime-")) {
            temporary = true;
            break;
        }
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    assert!(temporary, "the run ended before it could be interrupted");
    std::thread::sleep(Duration::from_millis(50));
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let result = child.wait_with_output().unwrap();
    assert_eq!(result.status.code(), Some(130), "exit code after Ctrl-C");
    let err = String::from_utf8_lossy(&result.stderr);
    assert!(err.contains("interrupted"), "{err}");
    assert_eq!(files(&out_dir), Vec::<String>::new(), "left behind");
}

#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.csv");
    let out = run_kisstime(&["gen", "--tables", "2000", "-o", s(&input)], &[]);
    assert!(out.status.success());
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let result = Command::new(env!("CARGO_BIN_EXE_kisstime"))
        .args(["pairs", s(&input)])
        .stdout(full)
        .output()
        .unwrap();
    assert_eq!(result.status.code(), Some(1));
    let err = String::from_utf8_lossy(&result.stderr);
    assert!(
        err.contains("standard output") && err.contains("No space left"),
        "{err}"
    );
}

#[test]
fn a_table_of_a_million_balls_is_refused_before_allocating() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("huge.csv");
    let mut text = String::from("table,ball,state,x,y,vx,vy,wx,wy,wz\n");
    for ball in 0..1_000_000 {
        text.push_str(&format!("7,{ball},stationary,{ball},0,0,0,0,0,0\n"));
    }
    std::fs::write(&input, text).unwrap();
    let out = run_kisstime(&["pairs", s(&input)], &[]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("table 7") && err.contains("1000000 balls") && err.contains("at most"),
        "{err}"
    );
}

/// An `.npy` header that promises more balls than memory holds is refused from the header,
/// before anything is allocated or read.
#[test]
fn an_npy_header_promising_too_much_is_refused() {
    if kisstime::limits::available_memory().is_none() {
        eprintln!("skipped: the available memory is not known on this system");
        return;
    }
    let bytes = common::plain_array_npy(&[1, 10], &[0.0f64; 10]);
    // rewrite the shape in the header text: (1, 10) becomes (10**15, 10)
    let key = b"'shape': (";
    let at = bytes
        .windows(key.len())
        .position(|w| w == key)
        .expect("the shape in the header")
        + key.len();
    let end = at + bytes[at..].iter().position(|&b| b == b')').unwrap();
    let mut forged = bytes[..at].to_vec();
    forged.extend_from_slice(b"1000000000000000, 10");
    forged.extend_from_slice(&bytes[end..]);
    // keep the header length field consistent: pad or trim spaces before the newline
    let header_end = forged.iter().position(|&b| b == b'\n').unwrap();
    let extra = forged.len() - bytes.len();
    forged.drain(header_end - extra..header_end);
    let err = kisstime::io::npy::read_batch_npy(&forged[..], "forged.npy").expect_err("refused");
    let msg = err.to_string();
    assert!(matches!(err, kisstime::Error::TooLarge(_)), "{msg}");
    assert!(
        msg.starts_with("forged.npy: ") && msg.contains("available"),
        "{msg}"
    );
}
