//! Shot contexts for the game rules (`kisstime simulate --rules … --context FILE`): one CSV
//! row a table, `table,break,hittable,ball_call,pocket_call` (pooltool's
//! `ShotConstraints`), and optionally `score,opponent_score` after them:
//!
//! - `table`: the table's id in the input;
//! - `break`: `1` (or `true`) for a game's break, `0` (or `false`, empty) otherwise;
//! - `hittable`: the balls the player may hit first, their ids joined by `;` (8-ball: the
//!   group, e.g. `1;2;3;4;5;6;7`; empty: any ball but the 8; 9-ball ignores it: the lowest
//!   ball; snooker: the reds or the colours on, e.g. `16;17;18;19;20;21`, empty: worked
//!   out from the table, see [`crate::game::snooker`]);
//! - `ball_call`, `pocket_call`: the called ball's id and pocket's id (`lb`, `lc`, `lt`,
//!   `rb`, `rc`, `rt` on pooltool's tables), empty where none. Whether a shot must be
//!   called is the game's to say ([`Context::call_shot`]; 8-ball: every shot but the
//!   break, as in pooltool), not the file's;
//! - `score`, `opponent_score`: the points of the player who shoots and of the opponent
//!   before the shot (snooker, three-cushion: who wins when the game ends), 0 when empty
//!   or without the columns.
//!
//! Ball ids are the input's numbers; snooker's balls may also be named as pooltool names
//! them (`white`, `red_01`, …, `yellow`, `black`: [`crate::game::snooker::id_of`]).
//!
//! Tables without a row get [`default_context`]. Errors name the file, the line and the
//! table: a table not in the input, a second row for one, a ball not on the table, a
//! pocket the table lacks, a value that does not parse, a context the game cannot judge
//! ([`Rules::check_context`]).

use std::path::Path;

use crate::error::{Error, InputError};
use crate::game::{Context, Rules};

/// The header of a context file (and, optionally, [`SCORE_COLUMNS`] after it).
pub const CONTEXT_COLUMNS: [&str; 5] = ["table", "break", "hittable", "ball_call", "pocket_call"];

/// The optional columns after [`CONTEXT_COLUMNS`]: the score before the shot.
pub const SCORE_COLUMNS: [&str; 2] = ["score", "opponent_score"];

/// A table's context without a row in `rules`: not a break, no call, no score; the balls
/// that may be hit first: any ball but the 8 (pool: an open table), or, in snooker, none
/// named (worked out from the table).
pub fn default_context(rules: Rules) -> Context {
    Context {
        hittable: match rules {
            Rules::Snooker => 0,
            Rules::NineBall | Rules::EightBall | Rules::ThreeCushion => open_table(),
        },
        ..Context::default()
    }
}

/// The balls 1 to 15 but the 8.
fn open_table() -> u32 {
    Context::balls((1..=15).filter(|&n| n != 8))
}

/// Reads the contexts of a batch's tables in game `rules` from `path`: one per table, in
/// the batch's table order. `tables[k]` is table `k`'s id and `balls(k)` its balls' ids;
/// `pockets` are the table's pocket ids.
pub fn read_contexts<'a>(
    path: &Path,
    rules: Rules,
    tables: &[i64],
    balls: impl Fn(usize) -> &'a [i64],
    pockets: &[String],
) -> Result<Vec<Context>, Error> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: file.clone(),
        source,
    })?;
    parse_contexts(&text, &file, rules, tables, balls, pockets)
}

/// [`read_contexts`] of text already read (`file` names it in errors).
pub fn parse_contexts<'a>(
    text: &str,
    file: &str,
    rules: Rules,
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
    let with_score = [&CONTEXT_COLUMNS[..], &SCORE_COLUMNS[..]].concat();
    if header != CONTEXT_COLUMNS && header != with_score {
        return Err(at(1)
            .with_message(format!(
                "the header must be {} (and optionally ,{}); it is {}",
                CONTEXT_COLUMNS.join(","),
                SCORE_COLUMNS.join(","),
                header.join(",")
            ))
            .into());
    }
    let mut out = vec![default_context(rules); tables.len()];
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
                .ok()
                .or_else(|| rules.ball_named(text))
                .ok_or_else(|| bad(format!("{what} {text:?}: not a ball id")))?;
            if !on_table.contains(&n) {
                return Err(bad(format!("{what} {text}: no such ball on the table")));
            }
            Ok(n)
        };
        let break_shot = match cell(1) {
            "1" | "true" => true,
            "0" | "false" | "" => false,
            other => return Err(bad(format!("break {other:?}: expected 1 or 0")).into()),
        };
        let hittable = match cell(2) {
            "" => default_context(rules).hittable,
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
        let mut score = [0u32; 2];
        for (s, (i, what)) in score.iter_mut().zip([(5, "score"), (6, "opponent_score")]) {
            *s = match cell(i) {
                "" => 0,
                text => text
                    .parse()
                    .map_err(|_| bad(format!("{what} {text:?}: not a whole number of points")))?,
            };
        }
        let context = Context {
            break_shot,
            hittable,
            call_shot: false,
            ball_call,
            pocket_call,
            wpa: false,
            score,
        };
        rules.check_context(&context).map_err(bad)?;
        out[k] = context;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_as(rules: Rules, text: &str) -> Result<Vec<Context>, String> {
        let pockets: Vec<String> = ["lb", "rt"].map(str::to_owned).to_vec();
        let balls = [vec![0i64, 1, 2, 8], vec![0, 3, 9, 16, 19, 21]];
        parse_contexts(text, "ctx.csv", rules, &[10, 20], |k| &balls[k], &pockets)
            .map_err(|e| e.to_string())
    }

    fn parse(text: &str) -> Result<Vec<Context>, String> {
        parse_as(Rules::EightBall, text)
    }

    #[test]
    fn rows_give_their_tables_contexts_and_the_others_the_default() {
        let head = "table,break,hittable,ball_call,pocket_call\n";
        let c = parse(&format!("{head}20,0,3;9,9,rt\n")).unwrap();
        assert_eq!(c[0], default_context(Rules::EightBall));
        assert_eq!(
            c[1],
            Context {
                break_shot: false,
                hittable: Context::balls([3, 9]),
                call_shot: false,
                ball_call: Some(9),
                pocket_call: Some(1),
                wpa: false,
                score: [0, 0],
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

    #[test]
    fn snooker_contexts_take_pooltools_names_and_the_score() {
        let head = "table,break,hittable,ball_call,pocket_call,score,opponent_score\n";
        let c = parse_as(
            Rules::Snooker,
            &format!("{head}20,0,yellow;blue;black,black,,31,24\n"),
        )
        .unwrap();
        assert_eq!(c[0], default_context(Rules::Snooker));
        assert_eq!(
            c[0].hittable, 0,
            "snooker's balls on are worked out by default"
        );
        assert_eq!(c[1].hittable, Context::balls([16, 19, 21]));
        assert_eq!((c[1].ball_call, c[1].score), (Some(21), [31, 24]));
        // numbers are still numbers; empty scores are 0
        let c = parse_as(Rules::Snooker, &format!("{head}20,0,3,,,,\n")).unwrap();
        assert_eq!((c[1].hittable, c[1].score), (Context::balls([3]), [0, 0]));
        for (row, words) in [
            ("20,0,3;16,,,,", &["line 2", "table 20", "not both"][..]),
            ("20,0,16;19,,,,", &["table 20", "call one"]),
            ("20,0,pink,,,,", &["hittable ball pink", "no such ball"]),
            ("20,0,,,,-3,", &["score \"-3\"", "whole number"]),
        ] {
            let e = parse_as(Rules::Snooker, &format!("{head}{row}\n")).unwrap_err();
            for w in words {
                assert!(e.contains(w), "{row}: {w} not in {e}");
            }
        }
        // pool games do not know snooker's names
        let e = parse(&format!("{head}20,0,black,,,,\n")).unwrap_err();
        assert!(e.contains("not a ball id"), "{e}");
    }
}
