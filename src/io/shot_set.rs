//! The full-shot reference set's files (`data/fullshots/README.md`): reading its shots
//! (`shots.csv`, `initial.csv`, `table.json`) and writing a replay in the checker's format
//! (`events.csv`: `shot,k,t,type,agents`; `final.csv`: `shot,ball,ball_id,state,x,y,pocket`).

use crate::error::SimError;
use crate::model::MotionState;
use crate::model::ball_state::BallState;
use crate::model::sim_params::SimParams;
use crate::model::table::Table;
use crate::resolve::stick_ball::CueStrike;
use crate::simulate::batch::EventRecord;
use crate::simulate::event_loop::{EventLoop, Limits};
use crate::simulate::events::{Event, EventKind};
use std::io::Write;
use std::path::Path;

/// One shot of a set: its number, the balls in pooltool's order with their ids, the cue
/// ball's index and the strike.
#[derive(Clone, Debug, PartialEq)]
pub struct Shot {
    /// `shot` column.
    pub shot: usize,
    /// pooltool's ball ids, in ball order.
    pub ball_ids: Vec<String>,
    /// The balls at rest before the strike.
    pub balls: Vec<BallState>,
    /// Index of the cue ball in `balls`.
    pub cue: usize,
    /// The strike.
    pub strike: CueStrike,
}

fn file_err(file: &Path, line: usize, reason: impl Into<String>) -> SimError {
    SimError::File {
        file: file.display().to_string(),
        line,
        reason: reason.into(),
    }
}

/// The rows of a CSV file as `(line, header-indexed getter)`.
fn read_csv(path: &Path) -> Result<(csv::StringRecord, Vec<(usize, csv::StringRecord)>), SimError> {
    let mut rd = csv::Reader::from_path(path).map_err(|e| file_err(path, 0, e.to_string()))?;
    let header = rd
        .headers()
        .map_err(|e| file_err(path, 1, e.to_string()))?
        .clone();
    let mut rows = Vec::new();
    for (k, rec) in rd.records().enumerate() {
        rows.push((
            k + 2,
            rec.map_err(|e| file_err(path, k + 2, e.to_string()))?,
        ));
    }
    Ok((header, rows))
}

/// Column `name` of `rec`, parsed.
fn field<T: std::str::FromStr>(
    header: &csv::StringRecord,
    rec: &csv::StringRecord,
    name: &str,
    at: (&Path, usize),
) -> Result<T, SimError> {
    let col = header.iter().position(|h| h == name);
    let col = col.ok_or_else(|| file_err(at.0, 1, format!("no column {name}")))?;
    let text = rec.get(col).unwrap_or("");
    text.parse()
        .map_err(|_| file_err(at.0, at.1, format!("bad {name} {text:?}")))
}

/// Reads `dir/shots.csv` and `dir/initial.csv`: every shot with its balls (at rest on
/// the cloth, centre at z = `radius`). Errors name the file and line.
pub fn read_shots(dir: &Path, radius: f64) -> Result<Vec<Shot>, SimError> {
    let path = dir.join("shots.csv");
    let (h, rows) = read_csv(&path)?;
    let mut shots: Vec<Shot> = Vec::with_capacity(rows.len());
    let mut cue_ids = Vec::with_capacity(rows.len());
    for (line, r) in &rows {
        let at = (path.as_path(), *line);
        let shot: usize = field(&h, r, "shot", at)?;
        if shot != shots.len() {
            return Err(file_err(&path, *line, "shots must be numbered 0, 1, 2, …"));
        }
        let strike = CueStrike {
            v0: field(&h, r, "V0", at)?,
            phi: field(&h, r, "phi", at)?,
            theta: field(&h, r, "theta", at)?,
            a: field(&h, r, "a", at)?,
            b: field(&h, r, "b", at)?,
        };
        cue_ids.push(field::<String>(&h, r, "cue_ball_id", at)?);
        shots.push(Shot {
            shot,
            ball_ids: Vec::new(),
            balls: Vec::new(),
            cue: usize::MAX,
            strike,
        });
    }
    read_initial(dir, radius, &mut shots)?;
    for (s, cue_id) in shots.iter_mut().zip(cue_ids) {
        s.cue = s
            .ball_ids
            .iter()
            .position(|id| *id == cue_id)
            .ok_or_else(|| {
                file_err(
                    &dir.join("initial.csv"),
                    0,
                    format!("shot {}: no ball {cue_id}", s.shot),
                )
            })?;
    }
    Ok(shots)
}

/// Adds the balls of `dir/initial.csv` to their shots, in file order.
fn read_initial(dir: &Path, radius: f64, shots: &mut [Shot]) -> Result<(), SimError> {
    let path = dir.join("initial.csv");
    let (h, rows) = read_csv(&path)?;
    for (line, r) in &rows {
        let at = (path.as_path(), *line);
        let shot: usize = field(&h, r, "shot", at)?;
        let s = shots
            .get_mut(shot)
            .ok_or_else(|| file_err(&path, *line, format!("unknown shot {shot}")))?;
        let (x, y): (f64, f64) = (field(&h, r, "x", at)?, field(&h, r, "y", at)?);
        if !(x.is_finite() && y.is_finite()) {
            return Err(file_err(&path, *line, "non-finite position"));
        }
        s.ball_ids.push(field(&h, r, "ball_id", at)?);
        s.balls.push(BallState::at_rest(x, y, radius));
    }
    Ok(())
}

/// Reads `dir/table.json` ([`Table::from_json`]).
pub fn read_table(dir: &Path) -> Result<Table, SimError> {
    let path = dir.join("table.json");
    let text = std::fs::read_to_string(&path).map_err(|e| file_err(&path, 0, e.to_string()))?;
    Table::from_json(&text)
}

/// An event's agents as the reference set writes them (`cue_stick;cue`, `i;j`,
/// `ball;segment`, `ball;pocket`, `ball`).
pub fn agents(ev: &Event, ball_ids: &[String], table: &Table) -> String {
    let ball = &ball_ids[ev.ball as usize];
    let m = ev.other as usize;
    match ev.kind {
        EventKind::StickBall => format!("cue_stick;{ball}"),
        EventKind::BallBall => format!("{ball};{}", ball_ids[m]),
        EventKind::BallLinearCushion => format!("{ball};{}", table.linear_ids[m]),
        EventKind::BallCircularCushion => format!("{ball};{}", table.circular_ids[m]),
        EventKind::BallPocket => format!("{ball};{}", table.pocket_ids[m]),
        _ => ball.clone(),
    }
}

/// Totals of a replay.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReplayStats {
    /// Shots simulated.
    pub shots: usize,
    /// Events in all.
    pub events: usize,
    /// Shots cut by a limit.
    pub cut: usize,
    /// Seconds spent in the event loop (simulation only, no file output).
    pub sim_seconds: f64,
}

/// Where a replay writes: the checker's `events.csv` and `final.csv`, and optionally the
/// reference set's `event_balls.csv` (each ball agent's state right after each event).
pub struct ReplayOut<'w> {
    /// `shot,k,t,type,agents`.
    pub events: &'w mut dyn Write,
    /// `shot,ball,ball_id,state,x,y,pocket`.
    pub final_balls: &'w mut dyn Write,
    /// `shot,k,ball_id,state,x,y,vx,vy,wx,wy,wz`, if wanted.
    pub event_balls: Option<&'w mut dyn Write>,
}

/// Simulates every shot on `table` and writes the files of `out` (headers included).
/// Returns the totals; the time counted is the event loop's alone.
pub fn replay(
    shots: &[Shot],
    table: &Table,
    params: SimParams,
    limits: Limits,
    out: &mut ReplayOut,
) -> Result<ReplayStats, SimError> {
    let io = |e: std::io::Error| file_err(Path::new("<output>"), 0, e.to_string());
    write_headers(out).map_err(io)?;
    let mut stats = ReplayStats::default();
    let n_max = shots.iter().map(|s| s.balls.len()).max().unwrap_or(0);
    let mut lp = EventLoop::new(table, params, limits, n_max)?;
    let mut records = Vec::new();
    for s in shots {
        let start = std::time::Instant::now();
        lp.reset(&s.balls, Some((s.cue, s.strike)))?;
        records.clear();
        while let Some(ev) = lp.step() {
            records.push(EventRecord::new(ev, lp.balls()));
        }
        let outcome = lp.outcome();
        stats.sim_seconds += start.elapsed().as_secs_f64();
        stats.shots += 1;
        stats.events += records.len();
        stats.cut += usize::from(outcome.cut.is_some());
        write_shot(s, &records, lp.balls(), table, out).map_err(io)?;
    }
    Ok(stats)
}

/// Writes the header rows of the files of `out`.
pub fn write_headers(out: &mut ReplayOut) -> std::io::Result<()> {
    writeln!(out.events, "shot,k,t,type,agents")?;
    writeln!(out.final_balls, "shot,ball,ball_id,state,x,y,pocket")?;
    if let Some(w) = out.event_balls.as_mut() {
        writeln!(w, "shot,k,ball_id,state,x,y,vx,vy,wx,wy,wz")?;
    }
    Ok(())
}

/// Writes one shot's rows: its events (with their agents' states, for
/// `event_balls.csv`) and its balls' final states, from any simulator (the CPU's
/// [`replay`], or the GPU's event loop).
pub fn write_shot(
    s: &Shot,
    records: &[EventRecord],
    final_balls: &[BallState],
    table: &Table,
    out: &mut ReplayOut,
) -> std::io::Result<()> {
    for (k, ev) in records.iter().map(|r| &r.event).enumerate() {
        let ag = agents(ev, &s.ball_ids, table);
        writeln!(
            out.events,
            "{},{k},{:?},{},{ag}",
            s.shot,
            ev.t,
            ev.kind.name()
        )?;
    }
    if let Some(w) = out.event_balls.as_mut() {
        write_event_balls(s, records, w)?;
    }
    for (i, b) in final_balls.iter().enumerate() {
        let pocket = pocket_of(b, table);
        writeln!(
            out.final_balls,
            "{},{i},{},{},{:?},{:?},{pocket}",
            s.shot,
            s.ball_ids[i],
            b.s.name(),
            b.r.x,
            b.r.y
        )?;
    }
    Ok(())
}

/// Writes one shot's `event_balls.csv` rows (ball–ball events in the pair's order).
fn write_event_balls(s: &Shot, records: &[EventRecord], w: &mut dyn Write) -> std::io::Result<()> {
    for (k, (ev, states)) in records.iter().map(|r| (&r.event, &r.states)).enumerate() {
        let two = ev.kind == EventKind::BallBall;
        let ids = [ev.ball, if two { ev.other } else { ev.ball }];
        for (b, id) in states.iter().zip(ids).take(if two { 2 } else { 1 }) {
            let (r, v, o) = (b.r, b.v, b.w);
            writeln!(
                w,
                "{},{k},{},{},{:?},{:?},{:?},{:?},{:?},{:?},{:?}",
                s.shot,
                s.ball_ids[id as usize],
                b.s.name(),
                r.x,
                r.y,
                v.x,
                v.y,
                o.x,
                o.y,
                o.z
            )?;
        }
    }
    Ok(())
}

/// The id of the pocket a pocketed ball sits in (its centre is the pocket's), else "".
fn pocket_of<'t>(b: &BallState, table: &'t Table) -> &'t str {
    if b.s != MotionState::Pocketed {
        return "";
    }
    let k = table
        .pockets
        .iter()
        .position(|p| p.center.x == b.r.x && p.center.y == b.r.y);
    k.map_or("", |k| table.pocket_ids[k].as_str())
}

#[cfg(test)]
mod tests {
    use super::*;

    const SHOTS: &str = "shot,seed,kind,game,table_l,table_w,cue_ball_id,V0,phi,theta,a,b,n_balls,target,n_events,duration\n\
        0,1,ordinary,none,2.54,1.27,cue,1.5,90.0,0.0,0.0,0.2,2,1,0,0\n";
    const INITIAL: &str = "shot,ball,ball_id,x,y\n0,0,1,0.635,1.2\n0,1,cue,0.635,0.6\n";

    fn write_set(shots: &str, initial: &str) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("shots.csv"), shots).unwrap();
        std::fs::write(dir.path().join("initial.csv"), initial).unwrap();
        dir
    }

    #[test]
    fn reads_and_replays_a_tiny_set() {
        let dir = write_set(SHOTS, INITIAL);
        let r = SimParams::default().ball.r;
        let shots = read_shots(dir.path(), r).unwrap();
        assert_eq!(shots.len(), 1);
        assert_eq!((shots[0].cue, shots[0].ball_ids.len()), (1, 2));
        let (mut ev, mut fin, mut balls) = (Vec::new(), Vec::new(), Vec::new());
        let mut out = ReplayOut {
            events: &mut ev,
            final_balls: &mut fin,
            event_balls: Some(&mut balls),
        };
        let table = Table::nine_foot();
        let stats = replay(
            &shots,
            &table,
            SimParams::default(),
            Limits::default(),
            &mut out,
        )
        .unwrap();
        let ev = String::from_utf8(ev).unwrap();
        let mut lines = ev.lines();
        assert_eq!(lines.next(), Some("shot,k,t,type,agents"));
        assert_eq!(lines.next(), Some("0,0,0.0,stick_ball,cue_stick;cue"));
        assert!(ev.contains(",ball_ball,1;cue"));
        assert_eq!(ev.lines().count(), stats.events + 1);
        let fin = String::from_utf8(fin).unwrap();
        assert_eq!(fin.lines().count(), 3);
        assert!(fin.lines().nth(2).unwrap().starts_with("0,1,cue,"));
        assert!(String::from_utf8(balls).unwrap().lines().count() > stats.events);
    }

    #[test]
    fn bad_files_name_the_file_and_line() {
        let r = SimParams::default().ball.r;
        let missing = tempfile::tempdir().unwrap();
        assert!(read_shots(missing.path(), r).is_err());
        let bad_x = INITIAL.replace("0.635,1.2", "abc,1.2");
        let dir = write_set(SHOTS, &bad_x);
        let err = read_shots(dir.path(), r).unwrap_err().to_string();
        assert!(
            err.contains("initial.csv:2") && err.contains("bad x"),
            "{err}"
        );
        let no_cue = INITIAL.replace(",cue,", ",7,");
        let dir = write_set(SHOTS, &no_cue);
        assert!(
            read_shots(dir.path(), r)
                .unwrap_err()
                .to_string()
                .contains("no ball cue")
        );
        let bad_shot = INITIAL.replace("0,1,cue", "5,1,cue");
        let dir = write_set(SHOTS, &bad_shot);
        assert!(read_shots(dir.path(), r).is_err());
    }
}
