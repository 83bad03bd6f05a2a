//! `-o` writes what the user named and touches nothing else: a symbolic link is followed
//! (the link stays a link), a device or a FIFO is written through (never replaced), `-` is
//! standard output, and a path in a missing folder is an error that leaves nothing behind.

#![cfg(unix)]

use std::os::unix::fs::FileTypeExt;
use std::path::Path;

mod common;
use common::run_kisstime;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `kisstime gen` of a tiny batch to `out`.
fn gen_to(out: &str) -> std::process::Output {
    run_kisstime(&["gen", "--tables", "2", "--balls", "2", "-o", out], &[])
}

#[test]
fn a_symlink_is_followed_and_stays_a_link() {
    let dir = tempfile::tempdir().unwrap();
    let real = dir.path().join("real.csv");
    std::fs::write(&real, "old").unwrap();
    let link = dir.path().join("link.csv");
    std::os::unix::fs::symlink("real.csv", &link).unwrap();
    let out = gen_to(s(&link));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    let text = std::fs::read_to_string(&real).unwrap();
    assert!(text.starts_with("table,ball,state"), "{text}");
    // a link to a file that does not exist yet creates that file
    let dangling = dir.path().join("dangling.csv");
    std::os::unix::fs::symlink(dir.path().join("sub-new.csv"), &dangling).unwrap();
    assert!(gen_to(s(&dangling)).status.success());
    assert!(
        std::fs::symlink_metadata(&dangling)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert!(dir.path().join("sub-new.csv").is_file());
}

#[test]
fn a_device_is_written_through_not_replaced() {
    let out = gen_to("/dev/null");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let meta = std::fs::metadata("/dev/null").unwrap();
    assert!(
        meta.file_type().is_char_device(),
        "/dev/null is still a device"
    );
    // /dev/stdout reaches the pipe the output is captured by
    let out = gen_to("/dev/stdout");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with("table,ball,state"), "{text}");
}

#[test]
fn a_fifo_is_written_through() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.csv");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        eprintln!("a_fifo_is_written_through: mkfifo is not available, skipped");
        return;
    }
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let out = gen_to(s(&fifo));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = reader.join().unwrap();
    assert!(text.starts_with("table,ball,state"), "{text}");
    let meta = std::fs::symlink_metadata(&fifo).unwrap();
    assert!(meta.file_type().is_fifo(), "the FIFO is still a FIFO");
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(left.len(), 1, "no temporary file beside the FIFO");
}

#[test]
fn a_dash_is_standard_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_kisstime"))
        .args(["gen", "--tables", "2", "--balls", "2", "-o", "-"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("table,ball,state"));
    assert!(!dir.path().join("-").exists(), "no file named '-'");
}

#[test]
fn a_missing_folder_is_an_error_that_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out_path = dir.path().join("missing").join("out.csv");
    let out = gen_to(s(&out_path));
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("out.csv"), "{err}");
    assert!(!dir.path().join("missing").exists());
}

#[test]
fn outputs_are_checked_before_anything_is_computed() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing").join("x.png");
    let wrong = dir.path().join("x.npz");
    // (a missing folder cannot be written: exit 1; a wrong extension is bad usage: exit 2)
    for (args, code, expect) in [
        (
            vec!["shots", "--samples", "10", "--plot", s(&missing)],
            1,
            "does not exist",
        ),
        (
            vec!["shots", "--samples", "10", "--plot", "out.jpg"],
            2,
            "written as .png",
        ),
        (
            vec!["shots", "--samples", "10", "-o", s(&wrong)],
            2,
            "written as .csv",
        ),
        (
            vec!["shots", "--samples", "10", "-o", "x.npy"],
            2,
            "written as .csv",
        ),
        (
            vec!["gen", "--tables", "2", "-o", s(&wrong)],
            2,
            "written as .csv or .npy",
        ),
    ] {
        let out = run_kisstime(&args, &[]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{args:?}: {err}");
        assert!(err.contains(expect), "{args:?}: {err}");
        // refused at once: no study summary was computed and printed
        assert!(out.stdout.is_empty(), "{args:?}");
    }
    assert!(!wrong.exists());
    // a name without an extension is CSV, and devices pass
    assert!(gen_to(s(&dir.path().join("plain"))).status.success());
    assert!(gen_to("/dev/null").status.success());
}

#[test]
fn thread_counts_outside_1_to_1024_are_refused_before_starting() {
    for n in ["0", "1025", "100000"] {
        let out = run_kisstime(&["gen", "--tables", "2", "-o", "/dev/null"], &[]);
        assert!(out.status.success());
        let out = run_kisstime(&["shots", "--samples", "10", "--threads", n], &[]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "--threads {n}: {err}");
        assert!(err.contains("give 1 to 1024"), "{err}");
        assert!(out.stdout.is_empty());
    }
    let out = run_kisstime(&["shots", "--samples", "10", "--threads", "1"], &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn no_runtime_directory_noise_on_stderr() {
    // without XDG_RUNTIME_DIR, Mesa's drivers used to print an error twice per GPU run
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("t.csv");
    let made = run_kisstime(
        &["gen", "--tables", "20", "-o", input.to_str().unwrap()],
        &[],
    );
    assert!(made.status.success());
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_kisstime"))
        .args(["next", input.to_str().unwrap(), "--backend", "auto"])
        .env("KISSTIME_AUTO_GPU", "always")
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(!err.contains("XDG_RUNTIME_DIR"), "{err}");
}
