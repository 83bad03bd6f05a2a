//! The `kisstime` command line: a thin layer over the library (its code is in `src/cli/`).
//!
//! Exit codes: 0 success, 2 bad input or usage (the message names the file, line, table and
//! ball), 1 a file that cannot be read or written, 130 interrupted.

use std::process::ExitCode;

use clap::Parser;
use kisstime::Error;

mod cli;

use cli::args::{Cli, Command};

fn main() -> ExitCode {
    let cli = Cli::parse();
    // Mesa's Vulkan drivers complain on stderr when XDG_RUNTIME_DIR is unset (twice a GPU
    // run); compute needs no runtime directory, so give them a private empty one
    let _runtime_dir = quiet_mesa();
    // Ctrl-C (or SIGTERM): leave no output file, finished or half-written, behind, and say
    // how far the run had got
    let _ = ctrlc::set_handler(|| {
        let kept = if kisstime::io::remove_unfinished_outputs() {
            "the outputs finished before it are complete and in place"
        } else {
            "no output file was written"
        };
        eprintln!("kisstime: {}; {kept}", cli::progress::interrupted_message());
        std::process::exit(130);
    });
    let threads = match &cli.command {
        Command::Pairs(a) | Command::Next(a) => a.threads,
        Command::Bench(a) => a.threads,
        Command::Gen(_) => None,
        Command::Shots(a) => a.threads,
        Command::Simulate(a) => a.threads,
        Command::Plan(a) => a.threads,
        Command::Play(a) => a.threads,
    };
    if let Err(e) = cli::commands::set_threads(threads) {
        eprintln!("kisstime: error: {e}");
        return ExitCode::from(2);
    }
    let result = match &cli.command {
        Command::Pairs(args) => cli::commands::run_pairs(args),
        Command::Next(args) => cli::commands::run_next(args),
        Command::Bench(args) => cli::bench::run(args),
        Command::Gen(args) => cli::commands::run_gen(args),
        Command::Shots(args) => cli::shots::run_shots(args),
        Command::Plan(args) => cli::plan::run(args),
        Command::Play(args) => cli::plan::run_play(args),
        Command::Simulate(args) => cli::simulate::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // a closed pipe (`kisstime pairs … | head`) is not an error of ours
        Err(Error::Io { source, .. }) if source.kind() == std::io::ErrorKind::BrokenPipe => {
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("kisstime: error: {e}");
            ExitCode::from(if e.is_bad_input() { 2 } else { 1 })
        }
    }
}

/// Sets `XDG_RUNTIME_DIR` to a private temporary directory when it is unset (removed when
/// the returned guard drops, at the end of `main`).
fn quiet_mesa() -> Option<tempfile::TempDir> {
    if std::env::var_os("XDG_RUNTIME_DIR").is_some() {
        return None;
    }
    let dir = tempfile::Builder::new()
        .prefix("kisstime-runtime-")
        .tempdir()
        .ok()?;
    // SAFETY: at the start of main, before any other thread exists, nothing reads the
    // environment concurrently
    unsafe { std::env::set_var("XDG_RUNTIME_DIR", dir.path()) };
    Some(dir)
}
