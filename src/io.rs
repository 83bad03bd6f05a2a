//! Reading and writing batches and answers: CSV here, NumPy `.npy` in [`crate::npy`],
//! chosen by the file name ([`Format`]).
//!
//! # Input
//! Header `table,ball,state,x,y,vx,vy,wx,wy,wz`, one row a ball: `table` and `ball` are
//! integer ids, `state` one of `stationary`, `spinning`, `sliding`, `rolling`, `pocketed`,
//! then position (m), velocity (m/s) and angular velocity (rad/s). Rows of one table need
//! not be adjacent; fields may be padded with spaces. Tables are answered in ascending id
//! order, balls in ascending id order.
//!
//! # Output
//! [`write_pairs_csv`]: header `table,i,j,t,status,horizon`, one row a pair with `i < j`
//! the ball ids, `t` and `horizon` in seconds printed as the shortest decimal that reads
//! back as the same f64 (`inf` when there is no collision or no horizon), `status` one of
//! `hit`, `none`, `overlap`. [`write_next_csv`]: header `table,t,i,j,status`, one row a
//! table, `inf` and empty ids when the table has no collision.

use std::io::{Read, Write};
use std::path::Path;

use crate::batch::Batch;
use crate::error::{Error, InputError};
use crate::physics::{Ball, MotionState};
use crate::solver::Contact;

/// The input columns, in order.
pub const BALL_COLUMNS: [&str; 10] = [
    "table", "ball", "state", "x", "y", "vx", "vy", "wx", "wy", "wz",
];
/// The numeric ball columns, in the order of [`Ball::numbers`].
pub const BALL_NUMBER_COLUMNS: [&str; 7] = ["x", "y", "vx", "vy", "wx", "wy", "wz"];
/// The per-pair output columns.
pub const PAIR_COLUMNS: &str = "table,i,j,t,status,horizon";

/// Reads a batch from a CSV file (see the module docs). Errors name the file, the line,
/// and the table and ball where known.
pub fn read_batch_csv_path(path: &Path) -> Result<Batch, Error> {
    let name = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|source| Error::Io {
        path: name.clone(),
        source,
    })?;
    read_batch_csv(std::io::BufReader::new(file), &name)
}

/// A file format, chosen by the file name: `.npy` (any case) is [`crate::npy`]'s NumPy
/// layout, anything else CSV.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Comma-separated text with a header line.
    Csv,
    /// NumPy's binary `.npy` (see [`crate::npy`]).
    Npy,
}

impl Format {
    /// The format of the file at `path` (CSV for standard output, `None`).
    pub fn of(path: Option<&Path>) -> Format {
        match path.and_then(|p| p.extension()) {
            Some(ext) if ext.eq_ignore_ascii_case("npy") => Format::Npy,
            _ => Format::Csv,
        }
    }
}

/// Reads a batch from a file in the format its name says ([`Format::of`]).
pub fn read_batch_path(path: &Path) -> Result<Batch, Error> {
    match Format::of(Some(path)) {
        Format::Csv => read_batch_csv_path(path),
        Format::Npy => crate::npy::read_batch_npy_path(path),
    }
}

/// Reads a batch in `format` from `reader`; `file` is the name used in error messages.
pub fn read_batch<R: Read>(reader: R, format: Format, file: &str) -> Result<Batch, Error> {
    match format {
        Format::Csv => read_batch_csv(reader, file),
        Format::Npy => crate::npy::read_batch_npy(reader, file),
    }
}

/// Writes a batch as an input file in `format`.
pub fn write_batch(out: &mut dyn Write, format: Format, batch: &Batch) -> std::io::Result<()> {
    match format {
        Format::Csv => write_batch_csv(out, batch),
        Format::Npy => crate::npy::write_batch_npy(out, batch),
    }
}

/// Writes each table's next collision in `format`.
pub fn write_next(
    out: &mut dyn Write,
    format: Format,
    next: &[crate::NextCollision],
) -> std::io::Result<()> {
    match format {
        Format::Csv => write_next_csv(out, next),
        Format::Npy => crate::npy::write_next_npy(out, next),
    }
}

/// Balls as read, in file order, before they are sorted into a [`Batch`]: one column per
/// field, so that a file of millions of balls is held once, compactly, and handed to the
/// batch without copying when it is already in (table, ball) order.
#[derive(Default)]
pub(crate) struct BallRows {
    tables: Vec<i64>,
    ids: Vec<i64>,
    balls: Vec<Ball>,
    /// Where each ball is in the file: its line (CSV) or row (NPY).
    at: Vec<u64>,
}

impl BallRows {
    /// Makes room for `more` balls, refusing ([`Error::TooLarge`]) when that needs more
    /// memory than is available.
    pub(crate) fn reserve(&mut self, more: usize) -> Result<(), Error> {
        let len = self.balls.len() as u64;
        let want = len.saturating_add(more as u64);
        crate::limits::check_memory(
            &format!("a batch of {want} balls"),
            want.saturating_mul(crate::limits::BYTES_PER_BALL),
        )?;
        self.tables.reserve_exact(more);
        self.ids.reserve_exact(more);
        self.balls.reserve_exact(more);
        self.at.reserve_exact(more);
        Ok(())
    }

    /// Appends one ball read at `at` (a line or a row). The columns grow by doubling, each
    /// growth checked against the available memory first.
    pub(crate) fn push(&mut self, table: i64, id: i64, ball: Ball, at: u64) -> Result<(), Error> {
        if self.balls.len() == self.balls.capacity() {
            self.reserve(self.balls.len().max(4096))?;
        }
        self.tables.push(table);
        self.ids.push(id);
        self.balls.push(ball);
        self.at.push(at);
        Ok(())
    }

    /// Sorts the balls by (table, ball) — stably, so of two balls with the same ids the
    /// later in the file is reported — and builds the batch. `locate` adds a ball's place
    /// (`at`) and the file name to an error; `unit` names what `at` counts (`line`, `row`).
    pub(crate) fn into_batch(
        mut self,
        unit: &str,
        locate: impl Fn(InputError, u64) -> InputError,
    ) -> Result<Batch, Error> {
        let key = |r: usize| (self.tables[r], self.ids[r]);
        let sorted = (1..self.tables.len()).all(|r| key(r - 1) <= key(r));
        if !sorted {
            // the sort order, then each column copied once more
            let n = self.tables.len() as u64;
            crate::limits::check_memory(
                &format!("sorting a batch of {n} balls"),
                n.saturating_mul(2 * crate::limits::BYTES_PER_BALL),
            )?;
            let mut order: Vec<usize> = (0..self.tables.len()).collect();
            order.sort_by_key(|&r| key(r));
            self.tables = order.iter().map(|&r| self.tables[r]).collect();
            self.ids = order.iter().map(|&r| self.ids[r]).collect();
            self.at = order.iter().map(|&r| self.at[r]).collect();
            self.balls = order.iter().map(|&r| self.balls[r]).collect();
        }
        let BallRows {
            tables,
            ids,
            balls,
            at,
        } = self;
        Batch::from_sorted_columns(&tables, ids, balls).map_err(|(row, mut e)| {
            if row > 0 && tables[row - 1] == tables[row] && e.message == "duplicate ball id" {
                e.message = format!("duplicate ball id (first on {unit} {})", at[row - 1]);
            }
            locate(e, at[row]).into()
        })
    }
}

/// Reads a batch from CSV text; `file` is the name used in error messages.
pub fn read_batch_csv<R: Read>(reader: R, file: &str) -> Result<Batch, Error> {
    let err = |line: u64, msg: String| InputError::new(msg).in_file(file).at_line(line);
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(reader);
    let mut rec = csv::StringRecord::new();
    if !rdr.read_record(&mut rec).map_err(|e| csv_error(e, file))? {
        return Err(err(1, "the file is empty; expected the header line".into()).into());
    }
    check_header(&rec).map_err(|m| err(1, m))?;

    let mut rows = BallRows::default();
    while rdr.read_record(&mut rec).map_err(|e| csv_error(e, file))? {
        let line = rec.position().map_or(0, |p| p.line());
        if rec.len() != BALL_COLUMNS.len() {
            return Err(err(
                line,
                format!(
                    "expected {} fields ({}), found {}",
                    BALL_COLUMNS.len(),
                    BALL_COLUMNS.join(","),
                    rec.len()
                ),
            )
            .into());
        }
        let table: i64 = rec[0]
            .parse()
            .map_err(|_| err(line, format!("table id {:?} is not an integer", &rec[0])))?;
        let ball: i64 = rec[1].parse().map_err(|_| {
            err(line, format!("ball id {:?} is not an integer", &rec[1])).at_table(table)
        })?;
        let at = |msg: String| err(line, msg).at_table(table).at_ball(ball);
        let state: MotionState = rec[2]
            .parse()
            .map_err(|e: crate::physics::UnknownState| at(e.to_string()))?;
        let mut v = [0.0f64; 7];
        for (k, name) in BALL_NUMBER_COLUMNS.iter().enumerate() {
            let text = &rec[3 + k];
            let value: f64 = text
                .parse()
                .map_err(|_| at(format!("{name} {text:?} is not a number")))?;
            if !value.is_finite() {
                return Err(at(format!("{name} is {text}, numbers must be finite")).into());
            }
            v[k] = value;
        }
        rows.push(table, ball, Ball::from_numbers(state, v), line)?;
    }
    rows.into_batch("line", |e, line| e.in_file(file).at_line(line))
}

/// Checks the header row against [`BALL_COLUMNS`], naming a missing or extra column.
fn check_header(header: &csv::StringRecord) -> Result<(), String> {
    let got: Vec<&str> = header.iter().collect();
    if got == BALL_COLUMNS {
        return Ok(());
    }
    let expected = BALL_COLUMNS.join(",");
    if let Some(missing) = BALL_COLUMNS.iter().find(|c| !got.contains(c)) {
        return Err(format!(
            "missing column {missing:?}; the header must be {expected}"
        ));
    }
    if let Some(extra) = got.iter().find(|c| !BALL_COLUMNS.contains(c)) {
        return Err(format!(
            "unexpected column {extra:?}; the header must be {expected}"
        ));
    }
    Err(format!(
        "columns out of order or repeated ({}); the header must be {expected}",
        got.join(",")
    ))
}

/// A CSV syntax or encoding error as an input error with its line.
fn csv_error(e: csv::Error, file: &str) -> Error {
    let line = e.position().map(|p| p.line());
    let mut ie = InputError::new(format!("unreadable CSV: {e}")).in_file(file);
    ie.line = line;
    if let csv::ErrorKind::Io(_) = e.kind() {
        return Error::Io {
            path: file.to_owned(),
            source: std::io::Error::other(e.to_string()),
        };
    }
    ie.into()
}

/// Formats a time as the shortest decimal that reads back as the same f64; `inf` for ∞.
pub fn format_time(t: f64, buf: &mut ryu::Buffer) -> &str {
    if t == f64::INFINITY {
        "inf"
    } else {
        buf.format(t)
    }
}

/// Writes per-pair answers (as [`crate::pair_times`] returns them) as CSV (module docs).
pub fn write_pairs_csv<W: Write + ?Sized>(
    out: &mut W,
    batch: &Batch,
    contacts: &[Contact],
) -> std::io::Result<()> {
    writeln!(out, "{PAIR_COLUMNS}")?;
    write_pairs_rows(out, batch, 0..batch.num_tables(), contacts)
}

/// Writes the per-pair rows (no header) of the tables `tables`, whose answers are
/// `contacts` (as [`crate::batch::pair_times_of`] returns them).
pub fn write_pairs_rows<W: Write + ?Sized>(
    out: &mut W,
    batch: &Batch,
    tables: std::ops::Range<usize>,
    contacts: &[Contact],
) -> std::io::Result<()> {
    let mut tb = ryu::Buffer::new();
    let mut hb = ryu::Buffer::new();
    for ((table, i, j), c) in batch.pair_ids(tables).zip(contacts) {
        writeln!(
            out,
            "{table},{i},{j},{},{},{}",
            format_time(c.t, &mut tb),
            c.status,
            format_time(c.horizon, &mut hb)
        )?;
    }
    Ok(())
}

/// Per-pair output in either format, written chunk by chunk as the answers come.
pub struct PairsWriter<'w> {
    sink: PairsSink<'w>,
}

enum PairsSink<'w> {
    Csv(&'w mut dyn Write),
    Npy(crate::npy::PairsNpy<&'w mut dyn Write>),
}

impl<'w> PairsWriter<'w> {
    /// Starts the output of all pairs of `batch` (the CSV header, or the `.npy` header
    /// promising every pair).
    pub fn new(
        out: &'w mut dyn Write,
        format: Format,
        batch: &Batch,
    ) -> std::io::Result<PairsWriter<'w>> {
        let sink = match format {
            Format::Csv => {
                writeln!(out, "{PAIR_COLUMNS}")?;
                PairsSink::Csv(out)
            }
            Format::Npy => PairsSink::Npy(crate::npy::PairsNpy::new(out, batch)?),
        };
        Ok(PairsWriter { sink })
    }

    /// Appends the answers `contacts` of the tables `tables` (positions in the batch), as
    /// [`crate::batch::pair_times_of`] returns them.
    pub fn write_rows(
        &mut self,
        batch: &Batch,
        tables: std::ops::Range<usize>,
        contacts: &[Contact],
    ) -> std::io::Result<()> {
        match &mut self.sink {
            PairsSink::Csv(out) => write_pairs_rows(*out, batch, tables, contacts),
            PairsSink::Npy(npy) => npy.write_rows(batch, tables, contacts),
        }
    }

    /// Ends the output (for `.npy`, an error if pairs are missing).
    pub fn finish(self) -> std::io::Result<()> {
        match self.sink {
            PairsSink::Csv(_) => Ok(()),
            PairsSink::Npy(npy) => npy.finish(),
        }
    }
}

/// The per-table output columns of `kisstime next`.
pub const NEXT_COLUMNS: &str = "table,t,i,j,status";

/// Writes each table's next collision as CSV `table,t,i,j,status`: `t` the shortest decimal
/// that reads back as the same f64, `inf` and empty ids when the table has none.
pub fn write_next_csv<W: Write + ?Sized>(
    out: &mut W,
    next: &[crate::NextCollision],
) -> std::io::Result<()> {
    writeln!(out, "{NEXT_COLUMNS}")?;
    let mut tb = ryu::Buffer::new();
    for n in next {
        let t = format_time(n.t, &mut tb);
        match n.pair {
            Some((i, j)) => writeln!(out, "{},{t},{i},{j},{}", n.table, n.status)?,
            None => writeln!(out, "{},{t},,,{}", n.table, n.status)?,
        }
    }
    Ok(())
}

/// An I/O error while writing the output of [`write_output`], which names the output.
pub fn output_error(source: std::io::Error) -> Error {
    Error::Io {
        path: String::new(),
        source,
    }
}

/// Writes the output of a command: to `path` atomically when given, else to standard
/// output. `body` writes through the writer it is handed and reports write failures with
/// [`output_error`]; they come back naming the output.
///
/// To a file, the content goes to a temporary file in the same folder, renamed over `path`
/// only when `body` succeeded and the data reached the disk. On any error nothing is left
/// under `path` (an earlier file there is kept as it was) and the temporary file is removed.
pub fn write_output(
    path: Option<&Path>,
    body: impl FnOnce(&mut dyn Write) -> Result<(), Error>,
) -> Result<(), Error> {
    let name = path.map_or_else(|| "standard output".to_owned(), |p| p.display().to_string());
    let named = |e: Error| match e {
        Error::Io { path, source } if path.is_empty() => Error::Io {
            path: name.clone(),
            source,
        },
        other => other,
    };
    let io = |source| Error::Io {
        path: name.clone(),
        source,
    };
    let Some(path) = path else {
        let stdout = std::io::stdout();
        let mut w = std::io::BufWriter::new(stdout.lock());
        body(&mut w).map_err(named)?;
        return w.flush().map_err(io);
    };
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".kisstime-");
    // an ordinary new file's permissions (0666 less the umask), not a temporary file's 0600
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let tmp = builder.tempfile_in(dir).map_err(io)?;
    let pending = Pending::register(tmp.path());
    let mut w = std::io::BufWriter::new(tmp);
    body(&mut w).map_err(named)?;
    let tmp = w.into_inner().map_err(|e| io(e.into_error()))?;
    tmp.as_file().sync_all().map_err(io)?;
    tmp.persist(path).map_err(|e| io(e.error))?;
    drop(pending);
    Ok(())
}

/// Temporary files of [`write_output`] not yet renamed into place.
static PENDING: std::sync::Mutex<Vec<std::path::PathBuf>> = std::sync::Mutex::new(Vec::new());

/// One entry of [`PENDING`], removed from the list when dropped (the file itself is removed
/// by `tempfile` on failure, or renamed on success).
struct Pending(std::path::PathBuf);

impl Pending {
    fn register(path: &Path) -> Pending {
        if let Ok(mut list) = PENDING.lock() {
            list.push(path.to_owned());
        }
        Pending(path.to_owned())
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        if let Ok(mut list) = PENDING.lock() {
            list.retain(|p| p != &self.0);
        }
    }
}

/// Removes the temporary files of every [`write_output`] still in progress: for a signal
/// handler (Ctrl-C), which then ends the process, so that an interrupted run leaves
/// nothing behind, neither under the requested names nor beside them.
pub fn remove_unfinished_outputs() {
    // try_lock, a few times: a handler must not wait for ever on a lock that another
    // thread holds for an instant
    for _ in 0..100 {
        if let Ok(list) = PENDING.try_lock() {
            for path in list.iter() {
                let _ = std::fs::remove_file(path);
            }
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
}

/// Writes a batch as input CSV (module docs), numbers as the shortest decimals that read
/// back as the same f64: `read_batch_csv` of the result gives the same batch.
pub fn write_batch_csv<W: Write + ?Sized>(out: &mut W, batch: &Batch) -> std::io::Result<()> {
    writeln!(out, "{}", BALL_COLUMNS.join(","))?;
    let mut buf = ryu::Buffer::new();
    for k in 0..batch.num_tables() {
        let table = batch.table_id(k);
        for (id, ball) in batch.ball_ids(k).iter().zip(batch.balls(k)) {
            write!(out, "{table},{id},{}", ball.state)?;
            for v in ball.numbers() {
                write!(out, ",{}", buf.format(v))?;
            }
            writeln!(out)?;
        }
    }
    Ok(())
}
