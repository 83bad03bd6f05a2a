//! Shot contexts for the game rules (`kisstime simulate --rules … --context FILE`): one CSV
//! row a table, `table,break,hittable,ball_call,pocket_call` (pooltool's
//! `ShotConstraints`):
//!
//! - `table`: the table's id in the input;
//! - `break`: `1` (or `true`) for a game's break, `0` (or `false`, empty) otherwise;
//! - `hittable`: the balls the player may hit first, their ids joined by `;` (8-ball: the
//!   group, e.g. `1;2;3;4;5;6;7`; empty: any ball but the 8; 9-ball ignores it: the lowest
//!   ball);
//! - `ball_call`, `pocket_call`: the called ball's id and pocket's id (`lb`, `lc`, `lt`,
//!   `rb`, `rc`, `rt` on pooltool's tables), empty where none. Whether a shot must be
//!   called is the game's to say ([`Context::call_shot`]; 8-ball: every shot but the
//!   break, as in pooltool), not the file's.
//!
//! Tables without a row get [`default_context`]. Errors name the file, the line and the
//! table: a table not in the input, a second row for one, a ball not on the table, a
//! pocket the table lacks, a value that does not parse.

use std::path::Path;

use crate::error::{Error, InputError};
use crate::game::Context;

/// The header of a context file.
pub const CONTEXT_COLUMNS: [&str; 5] = ["table", "break", "hittable", "ball_call", "pocket_call"];

/// A table's context without a row: not a break, any ball but the 8 may be hit first (an
/// open table), no call.
pub fn default_context() -> Context {
    Context {
        hittable: open_table(),
        ..Context::default()
    }
}

/// The balls 1 to 15 but the 8.
fn open_table() -> u16 {
    Context::balls((1..=15).filter(|&n| n != 8))
}

/// Reads the contexts of a batch's tables from `path`: one per table, in the batch's table
/// order. `tables[k]` is table `k`'s id and `balls(k)` its balls' ids; `pockets` are the
/// table's pocket ids.
pub fn read_contexts<'a>(
    path: &Path,
    tables: &[i64],
    balls: impl Fn(usize) -> &'a [i64],
    pockets: &[String],
) -> Result<Vec<Context>, Error> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: file.clone(),
        source,
    })?;
    parse_contexts(&text, &file, tables, balls, pockets)
}

/// [`read_contexts`] of text already read (`file` names it in errors).
pub fn parse_contexts<'a>(
    text: &str,
    file: &str,
    tables: &[i64],
    balls: impl Fn(usize) -> &'a [i64],
    pockets: &[String],
) -> Result<Vec<Context>, Error> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let at = |line: u64| InputError::new("").in_file(file).at_line(line);
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| at(1).with_message(format!("cannot read the header: {e}")))?
        .iter()
        .map(str::to_owned)
        .collect();
    if header != CONTEXT_COLUMNS {
        return Err(at(1)
            .with_message(format!(
                "the header must be {}; it is {}",
                CONTEXT_COLUMNS.join(","),
                header.join(",")
            ))
            .into());
    }
    let mut out = vec![default_context(); tables.len()];
    let mut seen = vec![false; tables.len()];
    for record in reader.records() {
        let record = record.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line());
            at(line).with_message(format!("not a CSV row: {e}"))
        })?;
        let line = record.position().map_or(0, |p| p.line());
        let cell = |i: usize| record.get(i).unwrap_or("");
        let bad = |msg: String| at(line).with_message(msg);
        let id: i64 = cell(0)
            .parse()
            .map_err(|_| bad(format!("table {:?}: not an integer id", cell(0))))?;
        let bad = |msg: String| at(line).at_table(id).with_message(msg);
        let k = tables
            .iter()
            .position(|&t| t == id)
            .ok_or_else(|| bad("the table is not in the input".to_owned()))?;
        if std::mem::replace(&mut seen[k], true) {
            return Err(bad("a second row for this table".to_owned()).into());
        }
        let on_table = balls(k);
        let ball = |text: &str, what: &str| -> Result<i64, InputError> {
            let n: i64 = text
                .parse()
                .map_err(|_| bad(format!("{what} {text:?}: not a ball id")))?;
            if !on_table.contains(&n) {
                return Err(bad(format!("{what} {n}: no such ball on the table")));
            }
            Ok(n)
        };
        let break_shot = match cell(1) {
            "1" | "true" => true,
            "0" | "false" | "" => false,
            other => return Err(bad(format!("break {other:?}: expected 1 or 0")).into()),
        };
        let hittable = match cell(2) {
            "" => open_table(),
            list => {
                let mut ids = Vec::new();
                for item in list.split(';') {
                    ids.push(ball(item.trim(), "hittable ball")?);
                }
                Context::balls(ids)
            }
        };
        let ball_call = match cell(3) {
            "" => None,
            text => Some(ball(text, "ball_call")?),
        };
        let pocket_call = match cell(4) {
            "" => None,
            p => Some(pockets.iter().position(|q| q == p).ok_or_else(|| {
                bad(format!(
                    "pocket_call {p:?}: the table has no such pocket (its pockets: {})",
                    if pockets.is_empty() {
                        "none".to_owned()
                    } else {
                        pockets.join(", ")
                    }
                ))
            })?),
        };
        out[k] = Context {
            break_shot,
            hittable,
            call_shot: false,
            ball_call,
            pocket_call,
            wpa: false,
        };
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Vec<Context>, String> {
        let pockets: Vec<String> = ["lb", "rt"].map(str::to_owned).to_vec();
        let balls = [vec![0i64, 1, 2, 8], vec![0, 3, 9]];
        parse_contexts(text, "ctx.csv", &[10, 20], |k| &balls[k], &pockets)
            .map_err(|e| e.to_string())
    }

    #[test]
    fn rows_give_their_tables_contexts_and_the_others_the_default() {
        let head = "table,break,hittable,ball_call,pocket_call\n";
        let c = parse(&format!("{head}20,0,3;9,9,rt\n")).unwrap();
        assert_eq!(c[0], default_context());
        assert_eq!(
            c[1],
            Context {
                break_shot: false,
                hittable: Context::balls([3, 9]),
                call_shot: false,
                ball_call: Some(9),
                pocket_call: Some(1),
                wpa: false,
            }
        );
        let c = parse(&format!("{head}10,1,,,\n")).unwrap();
        assert!(c[0].break_shot && c[0].ball_call.is_none());
        for (row, words) in [
            (
                "30,0,,,",
                &["ctx.csv", "line 2", "table 30", "not in the input"][..],
            ),
            (
                "10,0,5,,",
                &["line 2", "table 10", "hittable ball 5", "no such ball"],
            ),
            ("10,0,,,lc", &["pocket_call \"lc\"", "lb, rt"]),
            ("10,2,,,", &["break \"2\""]),
            ("10,0,,x,", &["ball_call \"x\""]),
        ] {
            let e = parse(&format!("{head}{row}\n")).unwrap_err();
            for w in words {
                assert!(e.contains(w), "{row}: {w} not in {e}");
            }
        }
        let e = parse(&format!("{head}10,0,,,\n10,1,,,\n")).unwrap_err();
        assert!(e.contains("line 3") && e.contains("second row"), "{e}");
        let e = parse("table,break\n10,0\n").unwrap_err();
        assert!(e.contains("line 1") && e.contains("header"), "{e}");
    }
}
