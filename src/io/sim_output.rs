//! The outputs of `kisstime simulate` ([`crate::simulate::simulate_batch`]'s results), in
//! CSV or NumPy `.npy`, written table by table as the chunks come.
//!
//! # Layouts
//! **Events** ([`EVENT_COLUMNS`]): one row per (event, involved ball) — one row for most
//! events, two for a ball–ball event (ball `agent_a` first, then `agent_b`):
//! `table,k,t,type,agent_a,agent_b,ball,state,x,y,vx,vy,wx,wy,wz`. `k` is the event's
//! number within its table (0 is the strike), `t` its time in s, `type` pooltool's event
//! type (`stick_ball`, `ball_ball`, `ball_linear_cushion`, `ball_circular_cushion`,
//! `ball_pocket`, `sliding_rolling`, `rolling_spinning`, `rolling_stationary`,
//! `spinning_stationary`); `agent_a` is the (first) ball's id (for `stick_ball` the struck
//! ball); `agent_b` the other ball's id (`ball_ball`), the cushion segment's, jaw's or
//! pocket's id in the table (CSV: its name, e.g. `3`, `1t`, `lb`; `.npy`: its index in the
//! table's list of that kind) or empty (`.npy`: −1); then `ball` and its state right after
//! the event, in the input's columns.
//!
//! **Final states** ([`FINAL_COLUMNS`]): one row per ball, tables and balls in ascending id
//! order: `table,ball,state,x,y,vx,vy,wx,wy,wz,pocket`, `pocket` the pocket's name (`.npy`:
//! index) for a pocketed ball, else empty (−1).
//!
//! **Outcomes** ([`OUTCOME_COLUMNS`]): one row per table: `table,events,t_end,cut`, `cut`
//! `none`, `max_events` or `max_time` (`.npy`: 0, 1, 2). With a game's rules
//! ([`JUDGED_OUTCOME_COLUMNS`]) the verdict follows:
//! `legal,foul,turn_over,game_over,won,points,foul_points`, the flags `1`/`0`, `foul` a
//! [`crate::game::Foul`] code or empty (`.npy`: its place in [`crate::game::Foul::ALL`], or
//! −1), the points those of [`crate::game::Verdict`].
//!
//! In `.npy` every field is `<i8` or `<f8` (the ids, `k`, codes and counts `<i8`), `type`
//! and `state` are codes (`type`: the order above from 0; `state`: pooltool's 0 stationary
//! … 4 pocketed). CSV numbers are the shortest decimals that read back as the same f64.

use std::io::{Read, Seek, Write};

use crate::model::ball_state::BallState;
use crate::model::table::Table;
use crate::simulate::batch::{TableRun, pocket_of};
use crate::simulate::events::{Cut, EventKind};

use super::Format;
use super::atomic::Output;

/// The events output's columns.
pub const EVENT_COLUMNS: [&str; 15] = [
    "table", "k", "t", "type", "agent_a", "agent_b", "ball", "state", "x", "y", "vx", "vy", "wx",
    "wy", "wz",
];
/// The final-state output's columns.
pub const FINAL_COLUMNS: [&str; 11] = [
    "table", "ball", "state", "x", "y", "vx", "vy", "wx", "wy", "wz", "pocket",
];
/// The per-table outcome output's columns.
pub const OUTCOME_COLUMNS: [&str; 4] = ["table", "events", "t_end", "cut"];
/// The outcome output's columns with the game's verdict (`simulate --rules`).
pub const JUDGED_OUTCOME_COLUMNS: [&str; 11] = [
    "table",
    "events",
    "t_end",
    "cut",
    "legal",
    "foul",
    "turn_over",
    "game_over",
    "won",
    "points",
    "foul_points",
];

/// Which columns are integers (`<i8` in `.npy`), by name.
fn is_int(name: &str) -> bool {
    matches!(
        name,
        "table"
            | "k"
            | "type"
            | "agent_a"
            | "agent_b"
            | "ball"
            | "state"
            | "pocket"
            | "events"
            | "cut"
            | "legal"
            | "foul"
            | "turn_over"
            | "game_over"
            | "won"
            | "points"
            | "foul_points"
    )
}

/// The `.npy` dtype of a structured array with these columns.
pub fn npy_dtype(columns: &[&str]) -> String {
    let fields: Vec<String> = columns
        .iter()
        .map(|c| format!("('{c}', '{}')", if is_int(c) { "<i8" } else { "<f8" }))
        .collect();
    format!("[{}]", fields.join(", "))
}

/// The bytes of a version-1.0 `.npy` header for `rows` rows of `columns`.
fn npy_header(columns: &[&str], rows: u64) -> Vec<u8> {
    npy_header_of_length(columns, rows, 0)
}

/// [`npy_header`], padded with spaces to at least `length` bytes (a multiple of 64): a
/// header written first for a row count not yet known, `u64::MAX` rows, is as long as any
/// header of the same columns, and the real one, padded to its length, replaces it at the
/// end.
fn npy_header_of_length(columns: &[&str], rows: u64, length: usize) -> Vec<u8> {
    let mut dict = format!(
        "{{'descr': {}, 'fortran_order': False, 'shape': ({rows},), }}",
        npy_dtype(columns)
    );
    // magic (6) + version (2) + length (2) + dict + '\n', a multiple of 64
    while (10 + dict.len() + 1) % 64 != 0 || 10 + dict.len() + 1 < length {
        dict.push(' ');
    }
    dict.push('\n');
    let mut h = b"\x93NUMPY\x01\x00".to_vec();
    h.extend_from_slice(&(dict.len() as u16).to_le_bytes());
    h.extend_from_slice(dict.as_bytes());
    h
}

/// One value of a row.
#[derive(Clone, Copy)]
enum Cell<'a> {
    Int(i64),
    Num(f64),
    /// CSV text, `.npy` integer.
    Named(&'a str, i64),
}

/// Rows of one output in either format. A `.npy` output whose row count is not known in
/// advance gets a placeholder header as long as any (for `u64::MAX` rows), rewritten by
/// `finish` with the count, where the output can go back ([`Output::rewritable`]: a file,
/// memory); a stream (standard output, a FIFO) has its rows spooled to an unnamed
/// temporary file and written after the header by `finish`.
struct Rows<'w> {
    out: &'w mut dyn Output,
    format: Format,
    columns: &'static [&'static str],
    rows: u64,
    /// `.npy`: the promised row count; else the placeholder header's length, or the spool.
    promised: Option<u64>,
    placeholder: Option<usize>,
    spool: Option<std::io::BufWriter<std::fs::File>>,
    buf: ryu::Buffer,
    line: Vec<u8>,
}

impl<'w> Rows<'w> {
    fn new(
        out: &'w mut dyn Output,
        format: Format,
        columns: &'static [&'static str],
        rows: Option<u64>,
    ) -> std::io::Result<Rows<'w>> {
        let (mut spool, mut placeholder) = (None, None);
        match (format, rows) {
            (Format::Csv, _) => writeln!(out, "{}", columns.join(","))?,
            (Format::Npy, Some(n)) => out.write_all(&npy_header(columns, n))?,
            (Format::Npy, None) if out.rewritable() => {
                let header = npy_header(columns, u64::MAX);
                out.write_all(&header)?;
                placeholder = Some(header.len());
            }
            (Format::Npy, None) => {
                spool = Some(std::io::BufWriter::with_capacity(
                    1 << 20,
                    tempfile::tempfile()?,
                ));
            }
        }
        Ok(Rows {
            out,
            format,
            columns,
            rows: 0,
            promised: rows,
            placeholder,
            spool,
            buf: ryu::Buffer::new(),
            line: Vec::with_capacity(256),
        })
    }

    fn row(&mut self, cells: &[Cell]) -> std::io::Result<()> {
        debug_assert_eq!(cells.len(), self.columns.len());
        self.rows += 1;
        self.line.clear();
        match self.format {
            Format::Csv => {
                for (k, c) in cells.iter().enumerate() {
                    if k > 0 {
                        self.line.push(b',');
                    }
                    match *c {
                        Cell::Int(v) => write!(self.line, "{v}")?,
                        Cell::Num(v) => {
                            let text = if v == f64::INFINITY {
                                "inf"
                            } else if v == f64::NEG_INFINITY {
                                "-inf"
                            } else {
                                self.buf.format(v)
                            };
                            self.line.extend_from_slice(text.as_bytes());
                        }
                        Cell::Named(s, _) => self.line.extend_from_slice(s.as_bytes()),
                    }
                }
                self.line.push(b'\n');
            }
            Format::Npy => {
                for c in cells {
                    match *c {
                        Cell::Int(v) | Cell::Named(_, v) => {
                            self.line.extend_from_slice(&v.to_le_bytes())
                        }
                        Cell::Num(v) => self.line.extend_from_slice(&v.to_le_bytes()),
                    }
                }
            }
        }
        match self.spool.as_mut() {
            Some(s) => s.write_all(&self.line),
            None => self.out.write_all(&self.line),
        }
    }

    fn finish(self) -> std::io::Result<()> {
        if let Some(n) = self.promised
            && self.format == Format::Npy
            && n != self.rows
        {
            return Err(std::io::Error::other(format!(
                "{} rows written, {n} promised",
                self.rows
            )));
        }
        if let Some(length) = self.placeholder {
            let header = npy_header_of_length(self.columns, self.rows, length);
            debug_assert_eq!(header.len(), length);
            self.out.rewrite_start(&header)?;
        }
        if let Some(spool) = self.spool {
            let mut file = spool.into_inner().map_err(|e| e.into_error())?;
            self.out.write_all(&npy_header(self.columns, self.rows))?;
            file.rewind()?;
            let mut reader = std::io::BufReader::with_capacity(1 << 20, file);
            std::io::copy(&mut reader.by_ref(), self.out)?;
        }
        Ok(())
    }
}

/// Names and ids of one table, to write its rows.
#[derive(Clone, Copy, Debug)]
pub struct TableIds<'a> {
    /// The table's id.
    pub table: i64,
    /// Its balls' ids, index for index.
    pub balls: &'a [i64],
}

/// The ball columns `state,x,y,vx,vy,wx,wy,wz` of a state.
fn ball_cells(b: &BallState) -> [Cell<'static>; 8] {
    [
        Cell::Named(b.s.name(), b.s as i64),
        Cell::Num(b.r.x),
        Cell::Num(b.r.y),
        Cell::Num(b.v.x),
        Cell::Num(b.v.y),
        Cell::Num(b.w.x),
        Cell::Num(b.w.y),
        Cell::Num(b.w.z),
    ]
}

/// The events output ([`EVENT_COLUMNS`]).
pub struct EventsWriter<'w>(Rows<'w>);

impl<'w> EventsWriter<'w> {
    /// Starts it (the CSV header; a `.npy` output's real header, whose row count is known
    /// only at the end, is written by [`Self::finish`]).
    pub fn new(out: &'w mut dyn Output, format: Format) -> std::io::Result<EventsWriter<'w>> {
        Ok(EventsWriter(Rows::new(out, format, &EVENT_COLUMNS, None)?))
    }

    /// Appends a table's events.
    pub fn write_table(
        &mut self,
        ids: TableIds,
        table: &Table,
        run: &TableRun,
    ) -> std::io::Result<()> {
        for (k, rec) in run.events.iter().enumerate() {
            let ev = rec.event;
            let m = ev.other as usize;
            let none = Cell::Named("", -1);
            let agent_b = match ev.kind {
                EventKind::BallBall => Cell::Int(ids.balls[m]),
                EventKind::BallLinearCushion => Cell::Named(&table.linear_ids[m], m as i64),
                EventKind::BallCircularCushion => Cell::Named(&table.circular_ids[m], m as i64),
                EventKind::BallPocket => Cell::Named(&table.pocket_ids[m], m as i64),
                _ => none,
            };
            for (i, b) in rec.balls() {
                let head = [
                    Cell::Int(ids.table),
                    Cell::Int(k as i64),
                    Cell::Num(ev.t),
                    Cell::Named(ev.kind.name(), ev.kind as i64),
                    Cell::Int(ids.balls[ev.ball as usize]),
                    agent_b,
                    Cell::Int(ids.balls[i]),
                ];
                let mut cells = [none; 15];
                cells[..7].copy_from_slice(&head);
                cells[7..].copy_from_slice(&ball_cells(b));
                self.0.row(&cells)?;
            }
        }
        Ok(())
    }

    /// Ends it.
    pub fn finish(self) -> std::io::Result<()> {
        self.0.finish()
    }
}

/// The final-state output ([`FINAL_COLUMNS`]).
pub struct FinalWriter<'w>(Rows<'w>);

impl<'w> FinalWriter<'w> {
    /// Starts it for `balls` balls in all (the `.npy` header promises them).
    pub fn new(
        out: &'w mut dyn Output,
        format: Format,
        balls: u64,
    ) -> std::io::Result<FinalWriter<'w>> {
        Ok(FinalWriter(Rows::new(
            out,
            format,
            &FINAL_COLUMNS,
            Some(balls),
        )?))
    }

    /// Appends a table's final states.
    pub fn write_table(
        &mut self,
        ids: TableIds,
        table: &Table,
        run: &TableRun,
    ) -> std::io::Result<()> {
        for (b, id) in run.balls.iter().zip(ids.balls) {
            let pocket = match pocket_of(table, b) {
                Some(k) => Cell::Named(&table.pocket_ids[k], k as i64),
                None => Cell::Named("", -1),
            };
            let mut cells = [pocket; 11];
            cells[0] = Cell::Int(ids.table);
            cells[1] = Cell::Int(*id);
            cells[2..10].copy_from_slice(&ball_cells(b));
            self.0.row(&cells)?;
        }
        Ok(())
    }

    /// Ends it (an error if balls are missing).
    pub fn finish(self) -> std::io::Result<()> {
        self.0.finish()
    }
}

/// A table's outcome cells.
fn outcome_cells<'a>(ids: TableIds, run: &TableRun) -> [Cell<'a>; 4] {
    let o = run.outcome;
    let cut = match o.cut {
        None => Cell::Named("none", 0),
        Some(Cut::MaxEvents) => Cell::Named("max_events", 1),
        Some(Cut::MaxTime) => Cell::Named("max_time", 2),
    };
    [
        Cell::Int(ids.table),
        Cell::Int(o.n_events as i64),
        Cell::Num(o.t_end),
        cut,
    ]
}

/// The per-table outcome output ([`OUTCOME_COLUMNS`]).
pub struct OutcomesWriter<'w>(Rows<'w>);

impl<'w> OutcomesWriter<'w> {
    /// Starts it for `tables` tables.
    pub fn new(
        out: &'w mut dyn Output,
        format: Format,
        tables: u64,
    ) -> std::io::Result<OutcomesWriter<'w>> {
        Ok(OutcomesWriter(Rows::new(
            out,
            format,
            &OUTCOME_COLUMNS,
            Some(tables),
        )?))
    }

    /// Starts it for `tables` tables with the game's verdict
    /// ([`JUDGED_OUTCOME_COLUMNS`]; rows by [`OutcomesWriter::write_judged`]).
    pub fn with_verdicts(
        out: &'w mut dyn Output,
        format: Format,
        tables: u64,
    ) -> std::io::Result<OutcomesWriter<'w>> {
        Ok(OutcomesWriter(Rows::new(
            out,
            format,
            &JUDGED_OUTCOME_COLUMNS,
            Some(tables),
        )?))
    }

    /// Appends a table's outcome.
    pub fn write_table(&mut self, ids: TableIds, run: &TableRun) -> std::io::Result<()> {
        self.0.row(&outcome_cells(ids, run))
    }

    /// Appends a table's outcome and its verdict (a writer made by
    /// [`OutcomesWriter::with_verdicts`]).
    pub fn write_judged(
        &mut self,
        ids: TableIds,
        run: &TableRun,
        v: &crate::game::Verdict,
    ) -> std::io::Result<()> {
        let [a, b, c, d] = outcome_cells(ids, run);
        let flag = |f: bool| Cell::Int(i64::from(f));
        let foul = match v.foul {
            Some(f) => {
                let at = crate::game::Foul::ALL.iter().position(|&g| g == f);
                Cell::Named(f.code(), at.map_or(-1, |k| k as i64))
            }
            None => Cell::Named("", -1),
        };
        self.0.row(&[
            a,
            b,
            c,
            d,
            flag(v.legal),
            foul,
            flag(v.turn_over),
            flag(v.game_over),
            flag(v.won),
            Cell::Int(i64::from(v.points)),
            Cell::Int(i64::from(v.foul_points)),
        ])
    }

    /// Ends it.
    pub fn finish(self) -> std::io::Result<()> {
        self.0.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn npy_headers_are_aligned_and_name_every_column() {
        for rows in [0, 7, 123_456_789] {
            let h = npy_header(&EVENT_COLUMNS, rows);
            assert_eq!(h.len() % 64, 0);
            assert_eq!(*h.last().unwrap(), b'\n');
            let text = String::from_utf8_lossy(&h[10..]);
            assert!(text.contains(&format!("({rows},)")), "{text}");
            assert!(text.contains("('t', '<f8')") && text.contains("('agent_b', '<i8')"));
        }
    }
}
