//! Batches and answers as NumPy `.npy` files: the binary format for large inputs and
//! outputs, read and written by `numpy.load` / `numpy.save` directly. The CLI picks it when
//! a file name ends in `.npy`.
//!
//! # Layouts
//! Input, one row a ball, either
//! - a 1-D structured array of dtype [`BALL_DTYPE`]:
//!   `[('table','<i8'), ('ball','<i8'), ('state','<i8'), ('x','<f8'), ('y','<f8'),
//!   ('vx','<f8'), ('vy','<f8'), ('wx','<f8'), ('wy','<f8'), ('wz','<f8')]`, or
//! - a plain 2-D `float64` array of shape `(N, 10)` with the same columns in the same order,
//!   ids and state as whole numbers.
//!
//! `state` is pooltool's code: 0 stationary, 1 spinning, 2 sliding, 3 rolling, 4 pocketed.
//! Rows of one table need not be adjacent. Either byte order is read; the arrays must be in
//! C order (`numpy.ascontiguousarray`).
//!
//! Output, structured arrays (little-endian):
//! - per pair ([`PAIR_DTYPE`]): `[('table','<i8'), ('i','<i8'), ('j','<i8'), ('t','<f8'),
//!   ('status','<i8'), ('horizon','<f8')]`, rows in the order of the CSV output;
//! - per table ([`NEXT_DTYPE`]): `[('table','<i8'), ('t','<f8'), ('i','<i8'), ('j','<i8'),
//!   ('status','<i8')]`; when a table has no collision `t` is `inf`, `status` 0 and `i`, `j`
//!   are −1 (the status says which rows these are, whatever the ball ids).
//!
//! `status` is 0 none, 1 hit, 2 overlap ([`crate::Status`]'s codes).
//!
//! Errors name the file and the row (`a[row]`, 0-based), and the table and ball.
//!
//! Headers are checked before the array is read: at most 10,000 bytes long (as
//! `numpy.load` reads by default), brackets nested at most 5 deep, and a shape whose element
//! count fits in 64 bits (NumPy's own headers are a few hundred bytes and nest 3 deep).

use std::io::{Read, Write};

use npyz::WriterBuilder;

use super::columns::{BALL_COLUMNS, BallRows, BallSink};
use crate::batch::{Batch, NextCollision};
use crate::error::{Error, InputError};
use crate::model::{Ball, MotionState};
use crate::query::ball_ball::Contact;

/// The structured input dtype, as NumPy writes it.
pub const BALL_DTYPE: &str = "[('table','<i8'), ('ball','<i8'), ('state','<i8'), \
     ('x','<f8'), ('y','<f8'), ('vx','<f8'), ('vy','<f8'), ('wx','<f8'), ('wy','<f8'), \
     ('wz','<f8')]";
/// The per-pair output dtype.
pub const PAIR_DTYPE: &str = "[('table','<i8'), ('i','<i8'), ('j','<i8'), ('t','<f8'), \
     ('status','<i8'), ('horizon','<f8')]";
/// The per-table output dtype.
pub const NEXT_DTYPE: &str =
    "[('table','<i8'), ('t','<f8'), ('i','<i8'), ('j','<i8'), ('status','<i8')]";

/// One ball, a row of the structured input.
#[derive(npyz::Serialize, npyz::Deserialize, npyz::AutoSerialize)]
struct BallRecord {
    table: i64,
    ball: i64,
    state: i64,
    x: f64,
    y: f64,
    vx: f64,
    vy: f64,
    wx: f64,
    wy: f64,
    wz: f64,
}

/// One pair's answer, a row of the per-pair output.
#[derive(npyz::Serialize, npyz::AutoSerialize)]
struct PairRecord {
    table: i64,
    i: i64,
    j: i64,
    t: f64,
    status: i64,
    horizon: f64,
}

/// One table's next collision, a row of the per-table output.
#[derive(npyz::Serialize, npyz::AutoSerialize)]
struct NextRecord {
    table: i64,
    t: f64,
    i: i64,
    j: i64,
    status: i64,
}

/// Reads a batch from a `.npy` file's bytes (see the module docs); `file` is the name used
/// in error messages.
pub fn read_batch_npy<R: Read>(reader: R, file: &str) -> Result<Batch, Error> {
    let mut rows = BallRows::default();
    read_rows_npy(reader, file, &mut rows)?;
    rows.into_batch("row", |e, row| e.in_file(file).at_row(row))
}

/// The balls of a `.npy` batch, each checked, handed to `rows` in file order with their
/// row (after `rows.reserve` of the count the header gives).
pub(crate) fn read_rows_npy<R: Read>(
    reader: R,
    file: &str,
    rows: &mut impl BallSink,
) -> Result<(), Error> {
    let bad = |msg: String| Error::from(InputError::new(msg).in_file(file));
    let npy = open_npy(reader).map_err(bad)?;
    if npy.uses_pickled_array() {
        return Err(bad(
            "object arrays (pickled) are not read; use numeric dtypes".into(),
        ));
    }
    if npy.order() != npyz::Order::C && npy.shape().len() > 1 {
        return Err(bad(
            "the array is in Fortran order; save numpy.ascontiguousarray(a)".into(),
        ));
    }
    let expected = || {
        format!(
            "expected a 1-D structured array of dtype {BALL_DTYPE}, or a 2-D float64 array \
             of shape (N, {}) with columns {}",
            BALL_COLUMNS.len(),
            BALL_COLUMNS.join(",")
        )
    };
    let dtype = npy.dtype();
    let shape = npy.shape().to_vec();
    let read_err = |row: u64, e: std::io::Error| {
        Error::from(
            InputError::new(format!("unreadable data: {e}"))
                .in_file(file)
                .at_row(row),
        )
    };
    // the header says how many balls: refuse a file too large for memory before reading
    let n_balls = shape.first().copied().unwrap_or(0);
    rows.reserve(usize::try_from(n_balls).unwrap_or(usize::MAX))
        .map_err(|e| match e {
            Error::TooLarge(m) => Error::TooLarge(format!("{file}: {m}")),
            other => other,
        })?;
    match &dtype {
        npyz::DType::Record(fields) => {
            if shape.len() != 1 {
                return Err(bad(format!("{}; found shape {shape:?}", expected())));
            }
            check_record_fields(fields).map_err(bad)?;
            let data = npy
                .data::<BallRecord>()
                .map_err(|e| bad(format!("{}; found {}: {e}", expected(), dtype.descr())))?;
            for (row, rec) in (0u64..).zip(data) {
                let r = rec.map_err(|e| read_err(row, e))?;
                let ball = make_ball(r.state as f64, [r.x, r.y, r.vx, r.vy, r.wx, r.wy, r.wz])
                    .map_err(|m| locate(InputError::new(m), file, row, r.table, r.ball))?;
                rows.push(r.table, r.ball, ball, row)?;
            }
        }
        npyz::DType::Plain(ty) => {
            if ty.to_string() != "<f8" {
                return Err(bad(format!(
                    "a plain array must be float64 ('<f8'); this one is {} ('{ty}'): save \
                     a.astype(numpy.float64)",
                    dtype_words(&ty.to_string())
                )));
            }
            if shape.len() != 2 || shape[1] != BALL_COLUMNS.len() as u64 {
                return Err(bad(format!(
                    "{}; found {} of shape {shape:?}",
                    expected(),
                    dtype.descr()
                )));
            }
            let mut data = npy
                .data::<f64>()
                .map_err(|e| bad(format!("{}; found {}: {e}", expected(), dtype.descr())))?;
            let mut v = [0.0f64; 10];
            for row in 0..shape[0] {
                for (k, x) in v.iter_mut().enumerate() {
                    *x = match data.next() {
                        Some(x) => x.map_err(|e| read_err(row, e))?,
                        None => {
                            return Err(read_err(
                                row,
                                std::io::Error::other(format!("file ends in column {k}")),
                            ));
                        }
                    };
                }
                let table = whole(v[0]).ok_or_else(|| {
                    locate_row(file, row, format!("table id {} is not an integer", v[0]))
                })?;
                let id = whole(v[1]).ok_or_else(|| {
                    locate_row(file, row, format!("ball id {} is not an integer", v[1]))
                        .at_table(table)
                })?;
                let mut numbers = [0.0; 7];
                numbers.copy_from_slice(&v[3..]);
                let ball = make_ball(v[2], numbers)
                    .map_err(|m| locate(InputError::new(m), file, row, table, id))?;
                rows.push(table, id, ball, row)?;
            }
        }
        npyz::DType::Array(..) => {
            return Err(bad(format!("{}; found {}", expected(), dtype.descr())));
        }
    }
    Ok(())
}

/// A batch from the structured input's columns held in memory (what the Python package
/// hands over from NumPy): row `r` is `table[r]`, `ball[r]`, `state[r]` and
/// `numbers[k][r]` for `x, y, vx, vy, wx, wy, wz`. Every row is checked and located
/// exactly as [`read_batch_npy`] checks a file's rows, with `source` in place of the file
/// name, so that the messages are the command line's.
pub fn batch_from_columns(
    source: &str,
    table: &[i64],
    ball: &[i64],
    state: &[i64],
    numbers: [&[f64]; 7],
) -> Result<Batch, Error> {
    let n = table.len();
    if ball.len() != n || state.len() != n || numbers.iter().any(|c| c.len() != n) {
        return Err(InputError::new(format!(
            "columns of different lengths: {n} table ids, {} ball ids, {} states, {} x",
            ball.len(),
            state.len(),
            numbers[0].len()
        ))
        .in_file(source)
        .into());
    }
    let mut rows = BallRows::default();
    rows.reserve(n)?;
    for r in 0..n {
        let row = r as u64;
        let v = [
            numbers[0][r],
            numbers[1][r],
            numbers[2][r],
            numbers[3][r],
            numbers[4][r],
            numbers[5][r],
            numbers[6][r],
        ];
        let b = make_ball(state[r] as f64, v)
            .map_err(|m| locate(InputError::new(m), source, row, table[r], ball[r]))?;
        rows.push(table[r], ball[r], b, row)?;
    }
    rows.into_batch("row", |e, row| e.in_file(source).at_row(row))
}

/// The bytes of one structured input row ([`BALL_DTYPE`]: three `<i8`, seven `<f8`).
pub const BALL_RECORD_BYTES: usize = 80;

/// A batch from the raw bytes of a C-ordered structured array of [`BALL_DTYPE`] held in
/// memory (a NumPy array's buffer, handed over without copying): rows of
/// [`BALL_RECORD_BYTES`] little-endian bytes. Checked and located exactly as
/// [`batch_from_columns`] (and so [`read_batch_npy`]) checks rows.
pub fn batch_from_records(source: &str, data: &[u8]) -> Result<Batch, Error> {
    if !data.len().is_multiple_of(BALL_RECORD_BYTES) {
        return Err(InputError::new(format!(
            "{} bytes are not whole rows of {BALL_RECORD_BYTES} bytes ({BALL_DTYPE})",
            data.len()
        ))
        .in_file(source)
        .into());
    }
    let n = data.len() / BALL_RECORD_BYTES;
    let mut rows = BallRows::default();
    rows.reserve(n)?;
    for (r, rec) in data.chunks_exact(BALL_RECORD_BYTES).enumerate() {
        let word = |k: usize| -> [u8; 8] {
            let mut w = [0u8; 8];
            w.copy_from_slice(&rec[8 * k..8 * k + 8]);
            w
        };
        let (table, ball, state) = (
            i64::from_le_bytes(word(0)),
            i64::from_le_bytes(word(1)),
            i64::from_le_bytes(word(2)),
        );
        let mut v = [0.0f64; 7];
        for (k, x) in v.iter_mut().enumerate() {
            *x = f64::from_le_bytes(word(3 + k));
        }
        let row = r as u64;
        let b = make_ball(state as f64, v)
            .map_err(|m| locate(InputError::new(m), source, row, table, ball))?;
        rows.push(table, ball, b, row)?;
    }
    rows.into_batch("row", |e, row| e.in_file(source).at_row(row))
}

/// The type string each field of the structured input must have: int64 ids and state,
/// float64 numbers.
fn field_type(name: &str) -> &'static str {
    if matches!(name, "table" | "ball" | "state") {
        "<i8"
    } else {
        "<f8"
    }
}

/// Checks a structured array's fields against [`BALL_COLUMNS`] — names in order, then each
/// field's type — and says in plain words what is wrong and how to fix it.
fn check_record_fields(fields: &[npyz::Field]) -> Result<(), String> {
    let names: Vec<&str> = fields.iter().map(|f| f.name.as_str()).collect();
    if names != BALL_COLUMNS {
        return Err(format!(
            "the fields must be {} in this order; this file has {}",
            BALL_COLUMNS.join(", "),
            names.join(", ")
        ));
    }
    for f in fields {
        let want = field_type(&f.name);
        let got = match &f.dtype {
            npyz::DType::Plain(ty) => ty.to_string(),
            other => other.descr(),
        };
        if got != want {
            return Err(format!(
                "field '{}' is {} ('{got}'); kisstime reads int64 ('<i8') for table, ball and \
                 state and float64 ('<f8') for x, y, vx, vy, wx, wy, wz: convert with \
                 a.astype(BALL) (the dtype in docs/cli.md)",
                f.name,
                dtype_words(&got)
            ));
        }
    }
    Ok(())
}

/// A NumPy type string in words (`<f4` → `float32`), for messages.
fn dtype_words(ty: &str) -> String {
    let code = ty.trim_start_matches(['<', '>', '|', '=']);
    let (kind, bytes) = code.split_at(code.len().min(1));
    let bits = bytes.parse::<u32>().map(|b| 8 * b).unwrap_or(0);
    let order = if ty.starts_with('>') {
        ", big-endian"
    } else {
        ""
    };
    match kind {
        "f" => format!("float{bits}{order}"),
        "i" => format!("int{bits}{order}"),
        "u" => format!("uint{bits}{order}"),
        "b" => "bool".to_owned(),
        _ => format!("type {ty}"),
    }
}

/// The deepest bracket nesting a header may have. NumPy's headers for the arrays read here
/// nest three deep (`{'descr': [('x', '<f8'), …], …}`, four with a sub-array field). The
/// header parser npyz uses, `py_literal` (a pest grammar), backtracks exponentially in the
/// depth of unclosed brackets (20 `{` in 100 bytes took seconds, found by fuzzing) and
/// about quadratically in the length (10,000 bytes 6 deep took 0.4 s, 7 deep 0.9 s).
const MAX_HEADER_NESTING: usize = 5;

/// The longest header read: `numpy.load`'s own default limit (`max_header_size`). NumPy
/// writes headers of a few hundred bytes; npyz allocates the declared length (up to 4 GiB)
/// before reading it, and parses it in a time that grows faster than the length.
const MAX_HEADER_LEN: u64 = 10_000;

/// The longest part of a header parser's message quoted in an error (pest quotes the whole
/// offending line, which can be the whole header).
const MAX_QUOTED: usize = 160;

/// A `.npy` file opened by [`open_npy`]: its checked header read again, then the rest.
pub(crate) type CheckedNpy<R> = npyz::NpyFile<std::io::Chain<std::io::Cursor<Vec<u8>>, R>>;

/// Opens `.npy` bytes with npyz after the checks of [`check_header`] (every `.npy` reader
/// of the crate comes through here: npyz alone hangs or panics on some headers); the error
/// is the message, `not a readable .npy file: …`, for the caller to locate.
pub(crate) fn open_npy<R: Read>(mut reader: R) -> Result<CheckedNpy<R>, String> {
    let prefix =
        read_header_prefix(&mut reader).map_err(|e| format!("not a readable .npy file: {e}"))?;
    check_header(&prefix).map_err(|e| format!("not a readable .npy file: {e}"))?;
    let reader = std::io::Cursor::new(prefix).chain(reader);
    npyz::NpyFile::new(reader)
        .map_err(|e| format!("not a readable .npy file: {}", first_line(&e.to_string())))
}

/// The magic string, version, header length and header of a `.npy` file, as far as the
/// reader has them (at most [`MAX_HEADER_LEN`] bytes of header; a short file gives fewer
/// bytes, and [`check_header`] says what is missing).
fn read_header_prefix<R: Read>(reader: &mut R) -> std::io::Result<Vec<u8>> {
    let mut prefix = Vec::new();
    reader.by_ref().take(8).read_to_end(&mut prefix)?;
    if prefix.len() < 8 {
        return Ok(prefix);
    }
    reader
        .by_ref()
        .take(header_len_bytes(&prefix) as u64)
        .read_to_end(&mut prefix)?;
    if let Some(len) = declared_header_len(&prefix) {
        reader
            .by_ref()
            .take(len.min(MAX_HEADER_LEN))
            .read_to_end(&mut prefix)?;
    }
    Ok(prefix)
}

/// How many bytes give the header's length: 2 in format version 1, 4 from version 2 on.
fn header_len_bytes(prefix: &[u8]) -> usize {
    if prefix[6] == 1 { 2 } else { 4 }
}

/// The header length that the bytes after the magic string and version declare, if they
/// are all there.
fn declared_header_len(prefix: &[u8]) -> Option<u64> {
    let n = header_len_bytes(prefix);
    let bytes = prefix.get(8..8 + n)?;
    Some(
        bytes
            .iter()
            .enumerate()
            .fold(0u64, |len, (k, &b)| len | (b as u64) << (8 * k)),
    )
}

/// Checks what npyz would trip over in a header that [`read_header_prefix`] read, and
/// parses it once, so that npyz parses only a header known to parse: a header longer than
/// [`MAX_HEADER_LEN`] or cut short, brackets nested deeper than [`MAX_HEADER_NESTING`], a
/// header that is not UTF-8 or not a Python literal, and a shape whose element count
/// overflows 64 bits (npyz multiplies the dimensions unchecked: fuzzed headers overflowed
/// it, once with plain digits and once with an integer written as a sum, which its
/// Python-literal parser evaluates). The header is read with the parser npyz uses,
/// `py_literal`, so both see the same numbers. A file that is not `.npy` at all (no magic
/// string, an unknown version) and a header without the keys npyz needs are left for npyz
/// to report.
fn check_header(prefix: &[u8]) -> Result<(), String> {
    if prefix.len() < 8 || !prefix.starts_with(b"\x93NUMPY") || !(1..=3).contains(&prefix[6]) {
        return Ok(());
    }
    let Some(len) = declared_header_len(prefix) else {
        return Ok(());
    };
    if len > MAX_HEADER_LEN {
        return Err(format!(
            "its header is {len} bytes long (at most {MAX_HEADER_LEN} are read, as by \
             numpy.load)"
        ));
    }
    let text = &prefix[8 + header_len_bytes(prefix)..];
    if (text.len() as u64) < len {
        return Err(format!(
            "its header is cut short ({} of {len} bytes)",
            text.len()
        ));
    }
    let depth = nesting_depth(text);
    if depth > MAX_HEADER_NESTING {
        return Err(format!(
            "its header nests brackets {depth} deep (a NumPy header needs at most \
             {MAX_HEADER_NESTING})"
        ));
    }
    let text = text.strip_suffix(b"\n").unwrap_or(text);
    let text = std::str::from_utf8(text).map_err(|_| "its header is not UTF-8 text".to_string())?;
    let header = text.parse::<py_literal::Value>().map_err(|e| {
        format!(
            "its header is not a Python literal: {}",
            first_line(&e.to_string())
        )
    })?;
    let py_literal::Value::Dict(entries) = header else {
        return Ok(());
    };
    // every 'shape' entry: npyz keeps the last of a repeated key
    let shapes = entries
        .iter()
        .filter_map(|(key, value)| match (key, value) {
            (
                py_literal::Value::String(key),
                py_literal::Value::Tuple(dims) | py_literal::Value::List(dims),
            ) if key == "shape" => Some(dims),
            _ => None,
        });
    for dims in shapes {
        if !shape_fits(dims) {
            return Err("its header's shape has more elements than memory can address".into());
        }
    }
    Ok(())
}

/// Whether a shape's non-negative integer dimensions, at 8 bytes a number, multiply out
/// within 64 bits. Zeros are skipped: a zero does not make the others fit, as npyz's
/// strides multiply them even for an empty array. What is not a non-negative integer is
/// left for npyz to refuse.
fn shape_fits(dims: &[py_literal::Value]) -> bool {
    dims.iter()
        .filter_map(|dim| match dim {
            py_literal::Value::Integer(dim) => u64::try_from(dim).ok(),
            _ => None,
        })
        .filter(|&dim| dim != 0)
        .try_fold(8u64, |total, dim| total.checked_mul(dim))
        .is_some()
}

/// The first line of a parser's message, at most [`MAX_QUOTED`] characters of it.
fn first_line(msg: &str) -> String {
    let line = msg.lines().next().unwrap_or("").trim_end();
    match line.char_indices().nth(MAX_QUOTED) {
        Some((at, _)) => format!("{}…", &line[..at]),
        None => line.to_string(),
    }
}

/// The deepest nesting of `(`, `[` and `{` in `bytes` (closing brackets of any kind close).
fn nesting_depth(bytes: &[u8]) -> usize {
    let (mut depth, mut deepest) = (0usize, 0usize);
    for &b in bytes {
        match b {
            b'(' | b'[' | b'{' => {
                depth += 1;
                deepest = deepest.max(depth);
            }
            b')' | b']' | b'}' => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    deepest
}

/// Reads a batch from a `.npy` file.
pub fn read_batch_npy_path(path: &std::path::Path) -> Result<Batch, Error> {
    let name = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|source| Error::Io {
        path: name.clone(),
        source,
    })?;
    read_batch_npy(std::io::BufReader::new(file), &name)
}

/// The id in a float column, when it is a whole number that an `i64` holds exactly.
fn whole(v: f64) -> Option<i64> {
    const LIMIT: f64 = 9_007_199_254_740_992.0; // 2^53: beyond it floats skip integers
    (v.fract() == 0.0 && v.abs() <= LIMIT).then_some(v as i64)
}

/// A ball from a state code and its numbers, or what is wrong with them.
fn make_ball(state: f64, numbers: [f64; 7]) -> Result<Ball, String> {
    let code = whole(state)
        .and_then(|c| u8::try_from(c).ok())
        .and_then(|c| MotionState::ALL.get(usize::from(c)).copied())
        .ok_or_else(|| {
            format!(
                "state {state} is not a state code (0 stationary, 1 spinning, 2 sliding, \
                 3 rolling, 4 pocketed)"
            )
        })?;
    if let Some(k) = numbers.iter().position(|v| !v.is_finite()) {
        return Err(format!(
            "{} is {}, numbers must be finite",
            Ball::NUMBER_NAMES[k],
            numbers[k]
        ));
    }
    Ok(Ball::from_numbers(code, numbers))
}

fn locate(e: InputError, file: &str, row: u64, table: i64, ball: i64) -> Error {
    e.in_file(file)
        .at_row(row)
        .at_table(table)
        .at_ball(ball)
        .into()
}

fn locate_row(file: &str, row: u64, msg: String) -> InputError {
    InputError::new(msg).in_file(file).at_row(row)
}

/// Writes a batch as a structured `.npy` input array ([`BALL_DTYPE`]): reading it back
/// gives the same batch.
pub fn write_batch_npy<W: Write>(out: W, batch: &Batch) -> std::io::Result<()> {
    let mut w = npyz::WriteOptions::new()
        .default_dtype()
        .shape(&[batch.num_balls() as u64])
        .writer(out)
        .begin_nd()?;
    for k in 0..batch.num_tables() {
        let table = batch.table_id(k);
        for (&ball, b) in batch.ball_ids(k).iter().zip(batch.balls(k)) {
            w.push(&BallRecord {
                table,
                ball,
                state: b.state as i64,
                x: b.x,
                y: b.y,
                vx: b.vx,
                vy: b.vy,
                wx: b.wx,
                wy: b.wy,
                wz: b.wz,
            })?;
        }
    }
    w.finish()
}

/// Writes each table's next collision as a `.npy` array of dtype [`NEXT_DTYPE`].
pub fn write_next_npy<W: Write>(out: W, next: &[NextCollision]) -> std::io::Result<()> {
    let mut w = npyz::WriteOptions::new()
        .default_dtype()
        .shape(&[next.len() as u64])
        .writer(out)
        .begin_nd()?;
    for n in next {
        let (i, j) = n.pair.unwrap_or((-1, -1));
        w.push(&NextRecord {
            table: n.table,
            t: n.t,
            i,
            j,
            status: n.status as i64,
        })?;
    }
    w.finish()
}

/// A `.npy` per-pair output written chunk by chunk (the CSV's streaming twin): the header,
/// which holds the number of rows, is written first, so the whole batch's pairs are
/// promised up front and [`PairsNpy::finish`] checks that they all came.
pub struct PairsNpy<W: Write> {
    writer: npyz::NpyWriter<PairRecord, W>,
}

impl<W: Write> PairsNpy<W> {
    /// Starts the output for all pairs of `batch`.
    pub fn new(out: W, batch: &Batch) -> std::io::Result<PairsNpy<W>> {
        let writer = npyz::WriteOptions::new()
            .default_dtype()
            .shape(&[batch.num_pairs() as u64])
            .writer(out)
            .begin_nd()?;
        Ok(PairsNpy { writer })
    }

    /// Appends the answers `contacts` of the tables `tables` (positions in the batch), as
    /// [`crate::pair_times_of`] returns them.
    pub fn write_rows(
        &mut self,
        batch: &Batch,
        tables: std::ops::Range<usize>,
        contacts: &[Contact],
    ) -> std::io::Result<()> {
        for ((table, i, j), c) in batch.pair_ids(tables).zip(contacts) {
            self.writer.push(&PairRecord {
                table,
                i,
                j,
                t: c.t,
                status: c.status as i64,
                horizon: c.horizon,
            })?;
        }
        Ok(())
    }

    /// Ends the output; an error if fewer rows were written than the header promised.
    pub fn finish(self) -> std::io::Result<()> {
        self.writer.finish()
    }
}
