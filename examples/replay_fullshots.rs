//! Replays a full-shot reference set through `kisstime::sim` and writes the checker's
//! files.
//!
//! ```text
//! cargo run --release --example replay_fullshots -- SET_DIR OUT_DIR
//! python3 SET_DIR/check_fullshots.py OUT_DIR
//! ```
//!
//! Reads SET_DIR's `shots.csv`, `initial.csv` and `table.json`, simulates every shot with
//! the set's `physics.toml` where it has one (pooltool's names; `data/physics`,
//! `data/snooker`, `data/carom`), else pooltool's default parameters, writes `OUT_DIR/events.csv` and `OUT_DIR/final.csv`, and
//! prints as its last line `N shots, E events in S s: X shots/s, Y events/s` (simulation
//! time only). With `--event-balls` it also writes `OUT_DIR/event_balls.csv` (the
//! agents' states after each event, as in the reference set).

use kisstime::io::shot_set::{ReplayOut, read_shots, read_table, replay};
use kisstime::simulate::{Limits, SimParams};
use std::io::{BufWriter, Write};
use std::path::PathBuf;

fn main() {
    if let Err(e) = run() {
        eprintln!("replay_fullshots: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (set, out, with_balls) = match args.as_slice() {
        [set, out] => (set, out, false),
        [set, out, flag] if flag == "--event-balls" => (set, out, true),
        _ => return Err("usage: replay_fullshots SET_DIR OUT_DIR [--event-balls]".into()),
    };
    let (set, out) = (PathBuf::from(set), PathBuf::from(out));
    let physics = set.join("physics.toml");
    let params = match physics.exists() {
        true => kisstime::io::physics::read_physics(&physics)?,
        false => SimParams::default(),
    };
    let table = read_table(&set)?;
    let shots = read_shots(&set, params.ball.r)?;
    std::fs::create_dir_all(&out)?;
    let mut events = BufWriter::new(std::fs::File::create(out.join("events.csv"))?);
    let mut fin = BufWriter::new(std::fs::File::create(out.join("final.csv"))?);
    let mut balls = match with_balls {
        true => Some(BufWriter::new(std::fs::File::create(
            out.join("event_balls.csv"),
        )?)),
        false => None,
    };
    let mut files = ReplayOut {
        events: &mut events,
        final_balls: &mut fin,
        event_balls: balls.as_mut().map(|w| w as &mut dyn Write),
    };
    let stats = replay(&shots, &table, params, Limits::default(), &mut files)?;
    events.flush()?;
    fin.flush()?;
    if let Some(w) = balls.as_mut() {
        w.flush()?;
    }
    if stats.cut > 0 {
        println!("{} shots were cut by a limit", stats.cut);
    }
    let s = stats.sim_seconds;
    println!(
        "{} shots, {} events in {:.3} s: {:.1} shots/s, {:.0} events/s",
        stats.shots,
        stats.events,
        s,
        stats.shots as f64 / s,
        stats.events as f64 / s
    );
    Ok(())
}
