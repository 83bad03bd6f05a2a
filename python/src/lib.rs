//! `kisstime._kisstime`: the Python extension over the kisstime library (PyO3, rust-numpy).
//!
//! Thin: every function takes NumPy columns (1-D, C-contiguous, the dtypes of the command
//! line's `.npy` layouts), runs the library with the GIL released (`Python::detach`), in
//! chunks so that Ctrl-C is noticed between them (`Python::check_signals`), and hands back
//! the command line's own `.npy` bytes (so the arrays are the CLI's, bit for bit) or plain
//! columns. Bad input raises `ValueError` with the command line's message (the input named
//! `balls` or `strikes` instead of a file), GPU failures `RuntimeError`, file errors
//! `OSError`. The Python side (`kisstime/__init__.py`) normalises the arguments.

use std::ops::Range;

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use kisstime::batch::Batch;
use kisstime::engine::ShotEngine;
use kisstime::game::{Context, Foul, Rules, Shot, Verdict};
use kisstime::io::context::{default_context, parse_contexts};
use kisstime::io::npy::{batch_from_columns, batch_from_records};
use kisstime::io::physics::{BatchPhysics, PhysicsColumns, PhysicsValue};
use kisstime::io::sim_output::{EventsWriter, FinalWriter, OutcomesWriter, TableIds};
use kisstime::io::strikes::{match_strikes, sample_strikes_from_columns, strike_rows_from_columns};
use kisstime::io::table_json::{table_by_name, table_from_json_text};
use kisstime::io::{Format, PairsWriter};
use kisstime::simulate::{
    BallState, BatchError, BatchOptions, CueStrike, Limits, Physics, SimError, SimParams, Table,
    TableRun, check_tables,
};
use kisstime::study::{
    Class, FirstContact, Pot, Result4, RunOptions, Sample, StudyConfig, Summary, Until,
};
use kisstime::{Backend, Engine, Error, Params, Precision};

type F64s<'py> = PyReadonlyArray1<'py, f64>;
type I64s<'py> = PyReadonlyArray1<'py, i64>;

/// Tables per chunk between two checks for Ctrl-C (pair and next-collision calls).
const TABLES_PER_CHECK: usize = 8_192;

/// A library error as the Python exception that fits it.
fn py_err(e: Error) -> PyErr {
    match &e {
        Error::Gpu(_) | Error::GpuUnavailable(_) => PyRuntimeError::new_err(e.to_string()),
        Error::Io { .. } => PyOSError::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// Why a sink of [`ShotEngine::simulate_with`] stopped: a Python exception (Ctrl-C), or an
/// error of the engine (a GPU failure) as one.
struct Stop(PyErr);

impl From<Error> for Stop {
    fn from(e: Error) -> Stop {
        Stop(py_err(e))
    }
}

impl From<PyErr> for Stop {
    fn from(e: PyErr) -> Stop {
        Stop(e)
    }
}

/// An I/O error writing to memory (cannot happen short of running out of it).
fn mem_err(e: std::io::Error) -> PyErr {
    PyRuntimeError::new_err(format!("writing the result: {e}"))
}

/// Which outputs [`simulate_npy`] writes besides the final states and the outcomes.
#[derive(Clone, Copy)]
struct Outputs {
    /// The events (the batch must record them).
    events: bool,
    /// The outcomes with each table's verdict.
    judged: bool,
}

/// Simulates `n` tables (`sizes`: their balls in all, and `n`) through the one entry point
/// ([`ShotEngine::simulate_with`]), writing each chunk to the `.npy` writers as it comes
/// (table `k` as `ids(k)`) and noticing Ctrl-C between chunks: the bytes of the events
/// (where `out.events`; else empty), the final states and the outcomes (with each table's
/// verdict `judge(run)` where `out.judged`). A bad table stops it with `bad(k, error)`.
/// `simulate` and the bridge's `simulate_shots` share it; the caller releases the GIL
/// around it.
#[allow(clippy::too_many_arguments)]
fn simulate_npy<'b>(
    engine: &mut ShotEngine,
    tbl: &Table,
    physics: Physics<'_>,
    options: &BatchOptions,
    (n_balls, n): (usize, usize),
    input: impl Fn(usize, &mut Vec<BallState>) -> Result<Option<(usize, CueStrike)>, SimError> + Sync,
    ids: impl Fn(usize) -> TableIds<'b>,
    bad: impl Fn(usize, SimError) -> PyErr,
    out: Outputs,
    judge: &(dyn Fn(&TableRun) -> PyResult<Option<Verdict>> + Sync),
) -> PyResult<(Vec<u8>, Vec<u8>, Vec<u8>)> {
    // the writers start over (empty) when the engine starts the call over on the CPU (a
    // GPU failure under `auto` after chunks came back)
    let restarted = std::cell::Cell::new(false);
    loop {
        let (mut ev_out, mut fin_out, mut oc_out) = (Vec::new(), Vec::new(), Vec::new());
        let mut ev_w = if out.events {
            Some(EventsWriter::new(&mut ev_out, Format::Npy).map_err(mem_err)?)
        } else {
            None
        };
        let mut fin_w =
            FinalWriter::new(&mut fin_out, Format::Npy, n_balls as u64).map_err(mem_err)?;
        let mut oc_w = if out.judged {
            OutcomesWriter::with_verdicts(&mut oc_out, Format::Npy, n as u64)
        } else {
            OutcomesWriter::new(&mut oc_out, Format::Npy, n as u64)
        }
        .map_err(mem_err)?;
        let restart = || {
            restarted.set(true);
            Err(Stop(PyRuntimeError::new_err("restarting on the CPU")))
        };
        let done =
            engine.simulate_restartable(tbl, physics, options, n, &input, restart, |chunk| {
                for run in chunk.iter() {
                    let ids = ids(run.table);
                    if let Some(w) = ev_w.as_mut() {
                        w.write_table(ids, tbl, &run).map_err(mem_err)?;
                    }
                    fin_w.write_table(ids, tbl, &run).map_err(mem_err)?;
                    match judge(&run)? {
                        Some(v) => oc_w.write_judged(ids, &run, &v).map_err(mem_err)?,
                        None => oc_w.write_table(ids, &run).map_err(mem_err)?,
                    }
                }
                Python::attach(|py| py.check_signals()).map_err(Stop)
            });
        match done {
            Ok(_) => {}
            Err(BatchError::Table { table, error }) => return Err(bad(table, error)),
            Err(BatchError::Sink(_)) if restarted.replace(false) => continue,
            Err(BatchError::Sink(Stop(e))) => return Err(e),
        }
        if let Some(w) = ev_w {
            w.finish().map_err(mem_err)?;
        }
        fin_w.finish().map_err(mem_err)?;
        oc_w.finish().map_err(mem_err)?;
        return Ok((ev_out, fin_out, oc_out));
    }
}

/// A contiguous column's values.
fn slice<'a, T: numpy::Element>(a: &'a PyReadonlyArray1<'_, T>, name: &str) -> PyResult<&'a [T]> {
    a.as_slice().map_err(|_| {
        PyValueError::new_err(format!("column {name} must be C-contiguous and aligned"))
    })
}

/// The batch of the ten input columns (`table, ball, state, x, y, vx, vy, wx, wy, wz`).
#[allow(clippy::too_many_arguments)]
fn batch_of(table: &I64s, ball: &I64s, state: &I64s, numbers: [&F64s; 7]) -> PyResult<Batch> {
    let names = ["x", "y", "vx", "vy", "wx", "wy", "wz"];
    let mut cols: [&[f64]; 7] = [&[]; 7];
    for (k, c) in numbers.iter().enumerate() {
        cols[k] = slice(c, names[k])?;
    }
    batch_from_columns(
        "balls",
        slice(table, "table")?,
        slice(ball, "ball")?,
        slice(state, "state")?,
        cols,
    )
    .map_err(py_err)
}

/// The collision-kernel parameters.
fn params_of(p: (f64, f64, f64, f64, f64)) -> PyResult<Params> {
    let params = Params {
        radius: p.0,
        mu_s: p.1,
        mu_r: p.2,
        mu_sp: p.3,
        g: p.4,
    };
    params.validate().map_err(py_err)?;
    Ok(params)
}

/// The backend and precision a backend and precision name (the precision's default is
/// the backend's).
fn backend_of(backend: &str, precision: Option<&str>) -> PyResult<(Backend, Precision)> {
    let backend = match backend {
        "cpu" => Backend::Cpu,
        "gpu" => Backend::Gpu,
        "auto" => Backend::Auto,
        other => {
            return Err(PyValueError::new_err(format!(
                "backend {other:?}: expected \"cpu\", \"gpu\" or \"auto\""
            )));
        }
    };
    let precision = match precision {
        None => kisstime::engine::default_precision(backend),
        Some("f32") => Precision::F32,
        Some("f64") => Precision::F64,
        Some(other) => {
            return Err(PyValueError::new_err(format!(
                "precision {other:?}: expected \"f32\" or \"f64\""
            )));
        }
    };
    Ok((backend, precision))
}

/// The shot engine a backend and precision name (the simulator's precision defaults to
/// f64 on every backend), opened for the caller to keep (a learning environment's).
fn shot_engine_of(backend: &str, precision: Option<&str>) -> PyResult<ShotEngine> {
    let (backend, precision) = backend_of(backend, Some(precision.unwrap_or("f64")))?;
    ShotEngine::new(backend, precision).map_err(py_err)
}

/// An engine's messages for the user, taken ([`warn_notes`]).
trait Notes {
    /// The messages since they were last taken.
    fn notes(&mut self) -> Vec<String>;
}

impl Notes for ShotEngine {
    fn notes(&mut self) -> Vec<String> {
        self.take_notes()
    }
}

impl<E: Reusable> Notes for Pooled<E> {
    /// What the engine said when it was opened (again for each call that reuses it: the
    /// call runs where it said), then since.
    fn notes(&mut self) -> Vec<String> {
        let mut notes = std::mem::take(&mut self.pending);
        notes.extend(std::ops::DerefMut::deref_mut(self).take_notes());
        notes
    }
}

/// An engine the calls of a process share ([`Pool`]).
trait Reusable: Sized + Send + 'static {
    /// Opens one.
    fn open(backend: Backend, precision: Precision) -> Result<Self, Error>;
    /// Its messages since they were last taken.
    fn take_notes(&mut self) -> Vec<String>;
}

impl Reusable for ShotEngine {
    fn open(backend: Backend, precision: Precision) -> Result<Self, Error> {
        ShotEngine::new(backend, precision)
    }
    fn take_notes(&mut self) -> Vec<String> {
        ShotEngine::take_notes(self)
    }
}

impl Reusable for Engine {
    fn open(backend: Backend, precision: Precision) -> Result<Self, Error> {
        Engine::new(backend, precision)
    }
    fn take_notes(&mut self) -> Vec<String> {
        Engine::take_notes(self)
    }
}

/// What an idle engine of a [`Pool`] was opened for: the backend, the precision, and the
/// environment variables that choose and configure a backend (`WGPU_*`, `VK_*`,
/// `KISSTIME_*`) as they were then.
#[derive(Clone, PartialEq)]
struct EngineKey {
    backend: Backend,
    precision: Precision,
    env: Vec<(std::ffi::OsString, std::ffi::OsString)>,
}

impl EngineKey {
    fn now(backend: Backend, precision: Precision) -> EngineKey {
        let mut env: Vec<_> = std::env::vars_os()
            .filter(|(k, _)| {
                let k = k.to_string_lossy();
                ["WGPU_", "VK_", "KISSTIME_"]
                    .iter()
                    .any(|p| k.starts_with(p))
            })
            .collect();
        env.sort();
        EngineKey {
            backend,
            precision,
            env,
        }
    }
}

/// The engines idle between calls. Opening a GPU engine (the adapter, the device, the
/// pipelines) costs far more than a study's chunk of samples, and a study or a Dask task
/// runs chunk after chunk, each its own call: so a call takes an idle engine opened for
/// the same backend, precision and environment, or opens one, and puts it back when it
/// has succeeded ([`Pooled`]); concurrent calls each get their own. An engine whose call
/// failed is dropped (a GPU failure may have lost its device). `release_engines()` drops
/// the idle ones (and the GPU memory they hold).
struct Pool<E> {
    idle: std::sync::Mutex<Vec<(EngineKey, Opened<E>)>>,
}

impl<E> Pool<E> {
    const fn new() -> Pool<E> {
        Pool {
            idle: std::sync::Mutex::new(Vec::new()),
        }
    }

    /// Drops the idle engines; how many there were.
    fn release(&self) -> usize {
        match self.idle.lock() {
            Ok(mut idle) => std::mem::take(&mut *idle).len(),
            Err(_) => 0,
        }
    }
}

/// The whole-shot engines (`simulate`, `shot_study`, `plan`).
static SHOT_ENGINES: Pool<ShotEngine> = Pool::new();
/// The collision kernels' engines (`pair_times`, `next_collisions`).
static PAIR_ENGINES: Pool<Engine> = Pool::new();

/// An engine and what it said when it was opened (a fallback to the CPU).
struct Opened<E> {
    engine: E,
    opening: Vec<String>,
}

/// An engine out of a [`Pool`] for one call: put back when dropped after
/// [`Pooled::succeeded`], else closed.
struct Pooled<E: Reusable> {
    pool: &'static Pool<E>,
    key: EngineKey,
    engine: Option<Opened<E>>,
    /// The notes of this call not yet taken from the engine.
    pending: Vec<String>,
    kept: bool,
}

impl<E: Reusable> Pooled<E> {
    /// An engine of `pool` for one call: an idle one opened for the same backend,
    /// precision and environment where there is one, else a new one.
    fn take(pool: &'static Pool<E>, backend: Backend, precision: Precision) -> PyResult<Self> {
        let key = EngineKey::now(backend, precision);
        let idle = pool.idle.lock().ok().and_then(|mut idle| {
            let at = idle.iter().position(|(k, _)| *k == key)?;
            Some(idle.swap_remove(at).1)
        });
        let opened = match idle {
            Some(opened) => opened,
            None => {
                let mut engine = E::open(backend, precision).map_err(py_err)?;
                let opening = engine.take_notes();
                Opened { engine, opening }
            }
        };
        Ok(Pooled {
            pool,
            key,
            pending: opened.opening.clone(),
            engine: Some(opened),
            kept: false,
        })
    }

    /// The call succeeded: the engine goes back to the idle ones.
    fn succeeded(&mut self) {
        self.kept = true;
    }
}

impl<E: Reusable> std::ops::Deref for Pooled<E> {
    type Target = E;
    fn deref(&self) -> &E {
        &self
            .engine
            .as_ref()
            .expect("an engine until dropped")
            .engine
    }
}

impl<E: Reusable> std::ops::DerefMut for Pooled<E> {
    fn deref_mut(&mut self) -> &mut E {
        &mut self
            .engine
            .as_mut()
            .expect("an engine until dropped")
            .engine
    }
}

impl<E: Reusable> Drop for Pooled<E> {
    fn drop(&mut self) {
        if let (true, Some(engine)) = (self.kept, self.engine.take()) {
            // a poisoned lock (a panic elsewhere) only costs the reuse
            if let Ok(mut idle) = self.pool.idle.lock() {
                idle.push((self.key.clone(), engine));
            }
        }
    }
}

/// A whole-shot engine for one call, as [`shot_engine_of`] opens it, from
/// [`SHOT_ENGINES`].
fn pooled_shot_engine(backend: &str, precision: Option<&str>) -> PyResult<Pooled<ShotEngine>> {
    let (backend, precision) = backend_of(backend, Some(precision.unwrap_or("f64")))?;
    Pooled::take(&SHOT_ENGINES, backend, precision)
}

/// A collision kernels' engine for one call, for the backend and precision named, from
/// [`PAIR_ENGINES`].
fn pooled_engine(backend: &str, precision: Option<&str>) -> PyResult<Pooled<Engine>> {
    let (backend, precision) = backend_of(backend, precision)?;
    Pooled::take(&PAIR_ENGINES, backend, precision)
}

/// Drops the engines kept between calls (`kisstime.release_engines()`): the GPU memory
/// and pipelines they hold are freed; the next call opens an engine again. Returns how
/// many were dropped.
#[pyfunction]
fn release_engines() -> usize {
    SHOT_ENGINES.release() + PAIR_ENGINES.release()
}

/// The engine's notes (fallbacks to the CPU) as Python `RuntimeWarning`s.
fn warn_notes(py: Python<'_>, engine: &mut impl Notes) -> PyResult<()> {
    for note in engine.notes() {
        let text = std::ffi::CString::new(format!("kisstime: {note}"))
            .unwrap_or_else(|_| c"kisstime: a fallback to the CPU".to_owned());
        PyErr::warn(
            py,
            &py.get_type::<pyo3::exceptions::PyRuntimeWarning>(),
            &text,
            1,
        )?;
    }
    Ok(())
}

/// Consecutive table ranges of at most `per` tables.
fn chunks(n: usize, per: usize) -> Vec<Range<usize>> {
    (0..n)
        .step_by(per.max(1))
        .map(|s| s..n.min(s + per))
        .collect()
}

/// A batch of tables built once from NumPy columns and kept on the Rust side, so that
/// repeated calls on the same balls skip the conversion (`kisstime.Batch`).
#[pyclass(name = "Batch", module = "kisstime._kisstime", frozen)]
struct PyBatch {
    batch: Batch,
}

#[pymethods]
impl PyBatch {
    #[new]
    #[pyo3(signature = (table, ball, state, x, y, vx, vy, wx, wy, wz))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        table: I64s<'_>,
        ball: I64s<'_>,
        state: I64s<'_>,
        x: F64s<'_>,
        y: F64s<'_>,
        vx: F64s<'_>,
        vy: F64s<'_>,
        wx: F64s<'_>,
        wy: F64s<'_>,
        wz: F64s<'_>,
    ) -> PyResult<Self> {
        let batch = batch_of(&table, &ball, &state, [&x, &y, &vx, &vy, &wx, &wy, &wz])?;
        Ok(PyBatch { batch })
    }

    /// A batch from the raw bytes of a structured array of the input dtype.
    #[staticmethod]
    fn from_records(records: PyReadonlyArray1<'_, u8>) -> PyResult<Self> {
        let batch = batch_from_records("balls", slice(&records, "records")?).map_err(py_err)?;
        Ok(PyBatch { batch })
    }

    /// The number of tables.
    #[getter]
    fn num_tables(&self) -> usize {
        self.batch.num_tables()
    }

    /// The number of balls.
    #[getter]
    fn num_balls(&self) -> usize {
        self.batch.num_balls()
    }

    /// The number of ball pairs.
    #[getter]
    fn num_pairs(&self) -> usize {
        self.batch.num_pairs()
    }
}

/// Each table's next collision, as the raw little-endian records of
/// `kisstime next`'s `.npy` (`table <i8, t <f8, i <i8, j <i8, status <i8`), header-less,
/// for `numpy.frombuffer`.
#[pyfunction]
#[pyo3(signature = (batch, params, backend, precision))]
fn next_collisions<'py>(
    py: Python<'py>,
    batch: &PyBatch,
    params: (f64, f64, f64, f64, f64),
    backend: &str,
    precision: Option<&str>,
) -> PyResult<Bound<'py, PyBytes>> {
    let batch = &batch.batch;
    let params = params_of(params)?;
    let mut engine = pooled_engine(backend, precision)?;
    let mut next = Vec::with_capacity(batch.num_tables());
    for tables in chunks(batch.num_tables(), TABLES_PER_CHECK) {
        let part = py
            .detach(|| engine.next_collisions_of(batch, &params, tables))
            .map_err(py_err)?;
        next.extend(part);
        py.check_signals()?;
    }
    engine.succeeded();
    let mut out: Vec<u8> = Vec::with_capacity(next.len() * 40);
    for n in &next {
        let (i, j) = n.pair.unwrap_or((-1, -1));
        out.extend_from_slice(&n.table.to_le_bytes());
        out.extend_from_slice(&n.t.to_le_bytes());
        out.extend_from_slice(&i.to_le_bytes());
        out.extend_from_slice(&j.to_le_bytes());
        out.extend_from_slice(&(n.status as i64).to_le_bytes());
    }
    Ok(PyBytes::new(py, &out))
}

/// Every pair's first contact, as the `.npy` bytes `kisstime pairs -o x.npy` writes.
#[pyfunction]
#[pyo3(signature = (batch, params, backend, precision))]
fn pair_times<'py>(
    py: Python<'py>,
    batch: &PyBatch,
    params: (f64, f64, f64, f64, f64),
    backend: &str,
    precision: Option<&str>,
) -> PyResult<Bound<'py, PyBytes>> {
    let batch = &batch.batch;
    let params = params_of(params)?;
    let mut engine = pooled_engine(backend, precision)?;
    let mut out: Vec<u8> = Vec::new();
    {
        let mut w = PairsWriter::new(&mut out, Format::Npy, batch).map_err(mem_err)?;
        for tables in batch.table_chunks(1 << 22) {
            let contacts = py
                .detach(|| engine.pair_times_of(batch, &params, tables.clone()))
                .map_err(py_err)?;
            w.write_rows(batch, tables, &contacts).map_err(mem_err)?;
            py.check_signals()?;
        }
        w.finish().map_err(mem_err)?;
    }
    engine.succeeded();
    Ok(PyBytes::new(py, &out))
}

/// The physical parameters Python passes: `None`, or `(kind, text, source)` with `kind`
/// `toml` (a physics file's text, `source` its path), `dict` (a dict of pooltool's names
/// written as TOML by the Python side, `source` the argument's name: messages without
/// lines) or `json` (such a dict as JSON text).
type PhysicsArg = Option<(String, String, String)>;

/// The parameters of a [`PhysicsArg`], read by the library's one parser
/// (`kisstime::io::physics`: the command line's messages); `None` when not given.
fn physics_of(physics: &PhysicsArg) -> PyResult<Option<SimParams>> {
    use kisstime::io::physics::{parse_physics_json, parse_physics_mapping, parse_physics_toml};
    match physics {
        None => Ok(None),
        Some((kind, text, source)) => match kind.as_str() {
            "toml" => parse_physics_toml(text, source).map(Some).map_err(py_err),
            "dict" => parse_physics_mapping(text, source)
                .map(Some)
                .map_err(py_err),
            "json" => parse_physics_json(text, source).map(Some).map_err(py_err),
            other => Err(PyValueError::new_err(format!(
                "unknown physics kind {other:?}"
            ))),
        },
    }
}

/// The entries of a mapping-kind [`PhysicsArg`] (Python's `physics={...}` single values):
/// the base of per-table physics. Empty without one.
fn physics_entries(physics: &PhysicsArg) -> PyResult<Vec<(String, PhysicsValue)>> {
    match physics {
        None => Ok(Vec::new()),
        Some((kind, text, source)) if kind == "dict" || kind == "toml" => {
            // checked whole first, for the one parser's messages
            physics_of(physics)?;
            let table: toml::Table = toml::from_str(text)
                .map_err(|e| PyValueError::new_err(format!("{source}: {e}")))?;
            match PhysicsValue::from_toml_table(&table) {
                PhysicsValue::Table(entries) => Ok(entries),
                _ => Ok(Vec::new()),
            }
        }
        Some((kind, _, _)) => Err(PyValueError::new_err(format!(
            "physics of kind {kind:?} cannot be the base of per-table physics"
        ))),
    }
}

/// Whole shots from the strike to rest: `(events, final, outcomes)` as the `.npy` bytes of
/// `kisstime simulate -o … --final … --outcomes …` (`events` is `None` unless asked).
#[pyfunction]
#[pyo3(signature = (batch, strikes, table_name, max_events, max_time, events, backend, precision, physics=None, physics_columns=None, table_json=None, rules=None, context=None, rule_ids=None, wpa=false))]
#[allow(clippy::type_complexity, clippy::too_many_arguments)]
fn simulate<'py>(
    py: Python<'py>,
    batch: &PyBatch,
    strikes: Option<(I64s<'py>, I64s<'py>, [F64s<'py>; 5])>,
    table_name: &str,
    max_events: u64,
    max_time: f64,
    events: bool,
    backend: &str,
    precision: Option<&str>,
    physics: PhysicsArg,
    physics_columns: Option<(I64s<'py>, Vec<(String, F64s<'py>)>)>,
    table_json: Option<&str>,
    rules: Option<&str>,
    context: Option<&str>,
    rule_ids: Option<(I64s<'py>, I64s<'py>)>,
    wpa: bool,
) -> PyResult<(
    Option<Bound<'py, PyBytes>>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
)> {
    let limits = Limits::new(max_events, max_time).map_err(|e| py_err(e.into()))?;
    let batch = &batch.batch;
    let tbl = table_of(table_name, table_json)?;
    let batch_physics = match &physics_columns {
        // one set per table: the mapping's single values with each table's row in place
        Some((ids, columns)) => {
            let mut cols = PhysicsColumns {
                tables: slice(ids, "physics table")?.to_vec(),
                ..PhysicsColumns::default()
            };
            for (name, values) in columns {
                let v = slice(values, name)?;
                if v.len() != cols.tables.len() {
                    return Err(PyValueError::new_err(format!(
                        "physics: {name} has {} values for {} tables",
                        v.len(),
                        cols.tables.len()
                    )));
                }
                cols.columns.push((name.clone(), v.to_vec()));
            }
            let base = physics_entries(&physics)?;
            let ids: Vec<i64> = (0..batch.num_tables()).map(|k| batch.table_id(k)).collect();
            BatchPhysics::PerTable(cols.for_tables(&base, &ids, "physics").map_err(py_err)?)
        }
        // without physics: the balls of the table's game (snooker, carom), as the CLI
        None => BatchPhysics::Shared(physics_of(&physics)?.unwrap_or_else(|| SimParams {
            ball: kisstime::io::table_json::default_ball_params(table_name),
            ..SimParams::default()
        })),
    };
    let physics = batch_physics.as_physics();
    let strikes = match &strikes {
        Some((t, b, v)) => {
            let cols = [
                slice(&v[0], "V0")?,
                slice(&v[1], "phi")?,
                slice(&v[2], "theta")?,
                slice(&v[3], "a")?,
                slice(&v[4], "b")?,
            ];
            let rows =
                strike_rows_from_columns("strikes", slice(t, "table")?, slice(b, "ball")?, cols)
                    .map_err(py_err)?;
            match_strikes(batch, &rows, "strikes", Format::Npy).map_err(py_err)?
        }
        None => Vec::new(),
    };
    let n = batch.num_tables();
    // the game's rules and each table's context (`kisstime simulate --rules --context`)
    let game = match rules {
        Some(name) => {
            let rules = Rules::from_name(name).map_err(PyValueError::new_err)?;
            let ids: Vec<i64> = (0..n).map(|k| batch.table_id(k)).collect();
            // the balls' ids in the game (the batch's own, or mapped: the bridge's)
            let game_ids: Vec<Vec<i64>> = match &rule_ids {
                None => (0..n).map(|k| batch.ball_ids(k).to_vec()).collect(),
                Some((from, to)) => {
                    let (from, to) = (slice(from, "rule ids")?, slice(to, "rule ids")?);
                    let map = |b: i64| {
                        from.iter()
                            .position(|&f| f == b)
                            .map(|i| to[i])
                            .ok_or_else(|| {
                                PyValueError::new_err(format!("ball {b}: no id in the game"))
                            })
                    };
                    (0..n)
                        .map(|k| batch.ball_ids(k).iter().map(|&b| map(b)).collect())
                        .collect::<PyResult<_>>()?
                }
            };
            let contexts = match context {
                Some(text) => {
                    let balls = |k: usize| game_ids[k].as_slice();
                    parse_contexts(text, "context", rules, &ids, balls, &tbl.pocket_ids)
                        .map_err(py_err)?
                }
                None => vec![default_context(rules); n],
            };
            let contexts: Vec<Context> = contexts
                .into_iter()
                .map(|c| rules.context(Context { wpa, ..c }))
                .collect();
            Some((rules, contexts, game_ids))
        }
        None if context.is_some() => {
            return Err(PyValueError::new_err(
                "context is for rules: give rules too",
            ));
        }
        None => None,
    };
    let options = BatchOptions {
        limits,
        // the rules judge a shot from its events
        record_events: events || game.is_some(),
        ..BatchOptions::default()
    };
    let mut engine = pooled_shot_engine(backend, precision)?;
    warn_notes(py, &mut engine)?;
    // each table's verdict, where judged: its balls at the start, its events
    let judge = |run: &TableRun| -> PyResult<Option<Verdict>> {
        let Some((rules, contexts, game_ids)) = &game else {
            return Ok(None);
        };
        let k = run.table;
        let r = physics.of(k).ball.r;
        let start: Vec<BallState> = batch
            .balls(k)
            .iter()
            .map(|b| BallState::from_ball(b, r))
            .collect();
        let shot = Shot {
            ids: &game_ids[k],
            start: &start,
            events: run.events,
        };
        rules.judge(&shot, &contexts[k]).map(Some).map_err(|e| {
            let e = kisstime::InputError::new(e.to_string())
                .in_file("balls")
                .at_table(batch.table_id(k));
            py_err(Error::from(e))
        })
    };
    let out = Outputs {
        events,
        judged: game.is_some(),
    };
    // the one entry point, with the GIL released
    let input = batch.sim_input_for(&strikes, physics);
    let sizes = (batch.num_balls(), n);
    let ids = |k: usize| TableIds {
        table: batch.table_id(k),
        balls: batch.ball_ids(k),
    };
    let bad = |k: usize, error: SimError| {
        let e = kisstime::InputError::new(error.to_string())
            .in_file("balls")
            .at_table(batch.table_id(k));
        py_err(Error::from(e))
    };
    let result = py.detach(|| {
        simulate_npy(
            &mut engine,
            &tbl,
            physics,
            &options,
            sizes,
            input,
            ids,
            bad,
            out,
            &judge,
        )
    });
    warn_notes(py, &mut engine)?;
    let (ev_out, fin_out, oc_out) = result?;
    engine.succeeded();
    let ev = events.then(|| PyBytes::new(py, &ev_out));
    Ok((ev, PyBytes::new(py, &fin_out), PyBytes::new(py, &oc_out)))
}

/// The shot to play from one position (`kisstime::plan`): the balls' game ids and
/// centres (at rest), the table, the physics, the game and its hittable balls (8-ball's
/// group; `None`: an open table), the noise (a preset's name, or the five σ in pooltool's
/// units: V0 m/s, φ and θ degrees, a and b fractions of R) times `noise_scale`, the budget
/// (seconds or samples), the seed, the finalists and the backend; the cue ball in hand
/// (`anywhere`, `kitchen`) or the break (the placement the planner's). The plan as JSON text
/// (`kisstime::plan::json`).
#[pyfunction]
#[pyo3(signature = (ids, xs, ys, table_name, table_json, physics, rules, hittable, noise_preset, noise_sigma, noise_scale, budget_seconds, budget_samples, seed, top, backend, ball_in_hand=None, break_shot=false))]
#[allow(clippy::too_many_arguments)]
fn plan(
    py: Python<'_>,
    ids: Vec<i64>,
    xs: Vec<f64>,
    ys: Vec<f64>,
    table_name: &str,
    table_json: Option<&str>,
    physics: PhysicsArg,
    rules: &str,
    hittable: Option<Vec<i64>>,
    noise_preset: Option<&str>,
    noise_sigma: Option<(f64, f64, f64, f64, f64)>,
    noise_scale: f64,
    budget_seconds: Option<f64>,
    budget_samples: Option<usize>,
    seed: u64,
    top: usize,
    backend: &str,
    ball_in_hand: Option<&str>,
    break_shot: bool,
) -> PyResult<String> {
    use kisstime::model::ball_state::BallState;
    use kisstime::plan::breaks::plan_break;
    use kisstime::plan::in_hand::{InHand, cue_in_hand, plan_in_hand};
    use kisstime::plan::{Budget, PlanOptions, position};
    let region = ball_in_hand
        .map(InHand::from_name)
        .transpose()
        .map_err(PyValueError::new_err)?;
    if xs.len() != ids.len() || ys.len() != ids.len() {
        return Err(PyValueError::new_err(
            "balls: ids, x and y of different lengths",
        ));
    }
    let rules = Rules::from_name(rules).map_err(PyValueError::new_err)?;
    let table = table_of(table_name, table_json)?;
    let params = physics_of(&physics)?.unwrap_or_default();
    let mut balls: Vec<BallState> = xs
        .iter()
        .zip(&ys)
        .map(|(&x, &y)| BallState::at_rest(x, y, params.ball.r))
        .collect();
    let mut ids = ids;
    if region.is_some() && break_shot {
        return Err(PyValueError::new_err(
            "ball_in_hand and break_shot: a break places the cue ball itself",
        ));
    }
    if region.is_some() || break_shot {
        (ids, balls) = cue_in_hand(&table, params.ball.r, &ids, &balls).map_err(py_err)?;
    }
    let mut context = default_context(rules);
    context.break_shot = break_shot;
    if let Some(h) = &hittable {
        for id in h {
            if *id <= 0 || !ids.contains(id) {
                return Err(PyValueError::new_err(format!(
                    "hittable: ball {id} is not an object ball on the table"
                )));
            }
        }
        context.hittable = Context::balls(h.iter().copied());
    }
    let config =
        position(&table, table_name, params, (&ids, &balls), rules, context).map_err(py_err)?;
    let noise = noise_of(noise_preset, noise_sigma, config.params.ball.r)?;
    if !(noise_scale.is_finite() && noise_scale >= 0.0) {
        return Err(PyValueError::new_err(format!(
            "noise_scale {noise_scale}: a finite factor of at least 0"
        )));
    }
    let noise = noise.scaled(noise_scale);
    let budget = match (budget_seconds, budget_samples) {
        (Some(s), None) => Budget::Seconds(s),
        (None, Some(k)) => Budget::Samples(k),
        _ => {
            return Err(PyValueError::new_err(
                "give one budget: budget_s (seconds) or budget_samples",
            ));
        }
    };
    if top == 0 {
        return Err(PyValueError::new_err("top: at least one finalist"));
    }
    let options = PlanOptions {
        noise,
        seed,
        budget,
        finalists: top,
        ..PlanOptions::default()
    };
    let mut engine = pooled_shot_engine(backend, None)?;
    let planned = py
        .detach(|| match region {
            Some(region) => plan_in_hand(&mut engine, &config, &options, region),
            None if break_shot => plan_break(&mut engine, &config, &options),
            None => kisstime::plan::plan(&mut engine, &config, &options),
        })
        .map_err(py_err)?;
    engine.succeeded();
    warn_notes(py, &mut engine)?;
    Ok(kisstime::plan::json(&config, &planned).to_string())
}

/// The table a `table` argument gives: JSON text when `json` is given (named `table` in
/// errors `table JSON`), else a built-in name or a path ([`table_by_name`]).
fn table_of(name: &str, json: Option<&str>) -> PyResult<Table> {
    match json {
        Some(text) => table_from_json_text(text, "table JSON").map_err(py_err),
        None => table_by_name(name).map_err(py_err),
    }
}

/// A bad shot's error with the balls named by the position's ids (`names[i]` is ball
/// index `i`'s), e.g. `ball '3': off the table`.
fn shot_message(error: &SimError, names: &[String]) -> String {
    let name = |i: usize| {
        names
            .get(i)
            .map_or_else(|| format!("#{i}"), |n| format!("'{n}'"))
    };
    match error {
        SimError::Ball { index, reason } => format!("ball {}: {reason}", name(*index)),
        SimError::Overlap {
            first,
            second,
            depth,
        } => format!(
            "balls {} and {} overlap by {depth:e} m at rest",
            name(*first),
            name(*second)
        ),
        other => other.to_string(),
    }
}

/// The bridge's batch form: shots, each one of a few positions with its own strike, from
/// the strike to rest on one table, through [`ShotEngine::simulate_with`].
///
/// `positions` holds the positions as tables with ids `0..P` (`names[p]` their balls'
/// names, for messages); shot `k` is position `shots.0[k]` with a strike on ball index
/// `shots.1[k]` (none where negative) with `V0, phi, theta, a, b = shots.2[..][k]`.
/// `physics` is one set for all, or one a position. Returns `(events, final, outcomes,
/// bad)`: the `.npy` bytes of `simulate` with shot `k` as table id `k`, of the simulated
/// shots only, and `bad` the `(shot, message)` of each shot not simulated. With `report`
/// every shot is checked first ([`check_tables`]) and the bad ones are left out; without,
/// the first bad shot raises `ValueError` (`shot k: …`).
#[pyfunction]
#[pyo3(signature = (positions, names, shots, table_name, table_json, physics, max_events, max_time, events, backend, precision, report))]
#[allow(clippy::type_complexity, clippy::too_many_arguments)]
fn simulate_shots<'py>(
    py: Python<'py>,
    positions: &PyBatch,
    names: Vec<Vec<String>>,
    shots: (I64s<'py>, I64s<'py>, [F64s<'py>; 5]),
    table_name: &str,
    table_json: Option<&str>,
    physics: Vec<PhysicsArg>,
    max_events: u64,
    max_time: f64,
    events: bool,
    backend: &str,
    precision: Option<&str>,
    report: bool,
) -> PyResult<(
    Option<Bound<'py, PyBytes>>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Vec<(usize, String)>,
)> {
    let limits = Limits::new(max_events, max_time).map_err(|e| py_err(e.into()))?;
    let batch = &positions.batch;
    let n_pos = batch.num_tables();
    if (0..n_pos).any(|p| batch.table_id(p) != p as i64) {
        return Err(PyValueError::new_err(
            "positions: the table ids must be 0, 1, ..., P - 1",
        ));
    }
    let tbl = table_of(table_name, table_json)?;
    // one parameter set for all, or one a position
    let mut sets = Vec::with_capacity(physics.len());
    for arg in &physics {
        sets.push(physics_of(arg)?.unwrap_or_default());
    }
    if sets.is_empty() {
        sets.push(SimParams::default());
    }
    if sets.len() != 1 && sets.len() != n_pos {
        return Err(PyValueError::new_err(format!(
            "physics: {} parameter sets for {n_pos} positions (one, or one a position)",
            sets.len()
        )));
    }
    let set_of = |p: usize| sets[if sets.len() == 1 { 0 } else { p }];
    let (pos, cue, v) = &shots;
    let (pos, cue) = (slice(pos, "position")?, slice(cue, "cue")?);
    let cols = [
        slice(&v[0], "V0")?,
        slice(&v[1], "phi")?,
        slice(&v[2], "theta")?,
        slice(&v[3], "a")?,
        slice(&v[4], "b")?,
    ];
    let n = pos.len();
    if cue.len() != n || cols.iter().any(|c| c.len() != n) {
        return Err(PyValueError::new_err(
            "strikes: columns of different lengths",
        ));
    }
    let mut at = Vec::with_capacity(n);
    for (k, &p) in pos.iter().enumerate() {
        match usize::try_from(p) {
            Ok(p) if p < n_pos => at.push(p),
            _ => {
                return Err(PyValueError::new_err(format!(
                    "shot {k}: position {p}: there are {n_pos}"
                )));
            }
        }
    }
    let input = |k: usize, balls: &mut Vec<BallState>| {
        let p = at[k];
        let r = set_of(p).ball.r;
        balls.clear();
        balls.extend(batch.balls(p).iter().map(|b| BallState::from_ball(b, r)));
        let strike = CueStrike {
            v0: cols[0][k],
            phi: cols[1][k],
            theta: cols[2][k],
            a: cols[3][k],
            b: cols[4][k],
        };
        Ok(usize::try_from(cue[k]).ok().map(|i| (i, strike)))
    };
    let shared = sets.len() == 1 || sets.iter().all(|s| *s == sets[0]);
    let per_shot = |shots: &[usize]| -> Vec<SimParams> {
        if shared {
            Vec::new()
        } else {
            shots.iter().map(|&k| set_of(at[k])).collect()
        }
    };
    fn physics_for(shared: Option<SimParams>, per: &[SimParams]) -> Physics<'_> {
        match shared {
            Some(p) => Physics::Shared(p),
            None => Physics::PerTable(per),
        }
    }
    let one = shared.then_some(sets[0]);
    let mut options = BatchOptions {
        limits,
        record_events: events,
        ..BatchOptions::default()
    };
    let message = |k: usize, e: &SimError| format!("shot {k}: {}", shot_message(e, &names[at[k]]));
    // with `report`, every shot checked first (as simulate_with would), the bad ones named
    let mut bad = Vec::new();
    let good: Vec<usize> = if report {
        let all: Vec<usize> = (0..n).collect();
        let per = per_shot(&all);
        let verdicts = py
            .detach(|| check_tables(&tbl, physics_for(one, &per), &options, n, input))
            .map_err(|e| py_err(e.into()))?;
        let mut good = Vec::with_capacity(n);
        for (k, v) in verdicts.iter().enumerate() {
            match v {
                Ok(()) => good.push(k),
                Err(e) => bad.push((k, message(k, e))),
            }
        }
        // checked now: not again
        options.check_layout = false;
        good
    } else {
        (0..n).collect()
    };
    let per = per_shot(&good);
    let n_balls: usize = good.iter().map(|&k| batch.balls(at[k]).len()).sum();
    let mut engine = pooled_shot_engine(backend, precision)?;
    warn_notes(py, &mut engine)?;
    let sub = |j: usize, balls: &mut Vec<BallState>| input(good[j], balls);
    let ids = |j: usize| TableIds {
        table: good[j] as i64,
        balls: batch.ball_ids(at[good[j]]),
    };
    let failed = |j: usize, error: SimError| PyValueError::new_err(message(good[j], &error));
    let physics = physics_for(one, &per);
    let sizes = (n_balls, good.len());
    let out = Outputs {
        events,
        judged: false,
    };
    let judge = |_: &TableRun| Ok(None);
    let result = py.detach(|| {
        simulate_npy(
            &mut engine,
            &tbl,
            physics,
            &options,
            sizes,
            sub,
            ids,
            failed,
            out,
            &judge,
        )
    });
    warn_notes(py, &mut engine)?;
    let (ev_out, fin_out, oc_out) = result?;
    engine.succeeded();
    let ev = events.then(|| PyBytes::new(py, &ev_out));
    Ok((
        ev,
        PyBytes::new(py, &fin_out),
        PyBytes::new(py, &oc_out),
        bad,
    ))
}

/// A study's configuration from its kind and text: `builtin`, `toml` (with the folder
/// its table file is relative to), `json` (the reference format of `data/studies`),
/// `dict` (the TOML schema as JSON text); with `physics` in place of its own parameters
/// when given ([`StudyConfig::with_physics`]).
fn config_of(
    kind: &str,
    text: &str,
    source: &str,
    dir: Option<&str>,
    physics: &PhysicsArg,
    physics_noise: Option<&str>,
) -> PyResult<StudyConfig> {
    let config = scenario_of(kind, text, source, dir)?;
    let config = match (physics_of(physics)?, physics) {
        (Some(params), Some((_, _, from))) => config.with_physics(params, from).map_err(py_err)?,
        _ => config,
    };
    match physics_noise {
        // the body of a [noise.physics] table, replacing the scenario's
        Some(text) => config
            .with_physics_noise(text, "physics_noise")
            .map_err(py_err),
        None => Ok(config),
    }
}

/// A study's scenario from its kind and text (see [`config_of`]).
fn scenario_of(kind: &str, text: &str, source: &str, dir: Option<&str>) -> PyResult<StudyConfig> {
    let dir = dir.map(std::path::Path::new);
    match kind {
        "builtin" => Ok(StudyConfig::builtin()),
        "toml" => StudyConfig::parse(text, source, dir).map_err(py_err),
        "json" => StudyConfig::parse_reference(text, source).map_err(py_err),
        "dict" => {
            let value: toml::Value = serde_json::from_str(text)
                .map_err(|e| PyValueError::new_err(format!("{source}: not a scenario: {e}")))?;
            let toml_text = toml::to_string(&value)
                .map_err(|e| PyValueError::new_err(format!("{source}: not a scenario: {e}")))?;
            // the TOML is ours, not the user's: its line numbers mean nothing to them
            StudyConfig::parse(&toml_text, source, dir).map_err(|e| {
                let message = e.to_string();
                let lined = format!("{source}, line ");
                match message.strip_prefix(&lined).and_then(|r| r.split_once(':')) {
                    Some((_, rest)) => PyValueError::new_err(format!("{source}:{rest}")),
                    None => py_err(e),
                }
            })
        }
        other => Err(PyValueError::new_err(format!(
            "unknown scenario kind {other:?}"
        ))),
    }
}

/// `rest` or `first-contact`.
fn until_of(until: &str) -> PyResult<Until> {
    match until {
        "rest" => Ok(Until::Rest),
        "first-contact" | "first_contact" => Ok(Until::FirstContact),
        other => Err(PyValueError::new_err(format!(
            "until {other:?}: expected \"rest\" or \"first-contact\""
        ))),
    }
}

// ------------------------------------------------------------- the blob of a study chunk
//
// Samples as little-endian bytes, one after the other: the sample id, then the fields of
// `Sample` in order (the potted list as a count and its entries). Only this module writes
// and reads it; it travels between Dask workers and the client.

fn put_f(out: &mut Vec<u8>, v: f64) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn put_u(out: &mut Vec<u8>, v: u64) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn encode(out: &mut Vec<u8>, id: i64, s: &Sample) {
    put_u(out, id as u64);
    for v in [
        s.strike.v0,
        s.strike.phi,
        s.strike.theta,
        s.strike.a,
        s.strike.b,
    ] {
        put_f(out, v);
    }
    let (kind, a, b) = match s.first {
        FirstContact::Ball(k) => (0u64, u64::from(k), 0),
        FirstContact::Cushion { circular, index } => (1, u64::from(index), u64::from(circular)),
        FirstContact::Pocket(p) => (2, u64::from(p), 0),
        FirstContact::Stopped => (3, 0, 0),
        FirstContact::Nothing => (4, 0, 0),
    };
    for v in [kind, a, b] {
        put_u(out, v);
    }
    for v in [
        s.first_t,
        s.contact_cue.0,
        s.contact_cue.1,
        s.contact_speed,
        s.contact_point.0,
        s.contact_point.1,
        s.cut_angle,
    ] {
        put_f(out, v);
    }
    put_u(out, s.potted.len() as u64);
    for p in &s.potted {
        put_u(out, u64::from(p.ball));
        put_u(out, u64::from(p.pocket));
        put_f(out, p.t);
    }
    put_f(out, s.cue_final.0);
    put_f(out, s.cue_final.1);
    put_u(out, s.n_events as u64);
    put_f(out, s.duration);
    put_u(
        out,
        match s.cut {
            None => 0,
            Some(kisstime::simulate::Cut::MaxEvents) => 1,
            Some(kisstime::simulate::Cut::MaxTime) => 2,
        },
    );
    put_u(out, verdict_code(s.verdict));
}

/// A sample's verdict as one number: 0 none; else bit 0 set, then legal, turn over, game
/// over and won in bits 1 to 4, the foul's index in `Foul::ALL` plus one in bits 8 to 15,
/// the points in bits 16 to 31 and the foul points from bit 32.
fn verdict_code(v: Option<Verdict>) -> u64 {
    let Some(v) = v else { return 0 };
    let foul = v
        .foul
        .and_then(|f| Foul::ALL.iter().position(|&g| g == f))
        .map_or(0, |i| i as u64 + 1);
    1 | u64::from(v.legal) << 1
        | u64::from(v.turn_over) << 2
        | u64::from(v.game_over) << 3
        | u64::from(v.won) << 4
        | foul << 8
        | u64::from(v.points.min(0xFFFF)) << 16
        | u64::from(v.foul_points) << 32
}

/// [`verdict_code`] read back; `None` inside when it is not one.
fn verdict_of(code: u64) -> Option<Option<Verdict>> {
    if code == 0 {
        return Some(None);
    }
    let foul = match (code >> 8) & 0xFF {
        0 => None,
        k => Some(*Foul::ALL.get(k as usize - 1)?),
    };
    Some(Some(Verdict {
        legal: code & 2 != 0,
        foul,
        turn_over: code & 4 != 0,
        game_over: code & 8 != 0,
        won: code & 16 != 0,
        points: ((code >> 16) & 0xFFFF) as u32,
        foul_points: u32::try_from(code >> 32).ok()?,
    }))
}

/// Reads the blob back; `None` if it is not one.
struct Reader<'a>(&'a [u8]);

impl Reader<'_> {
    fn u(&mut self) -> Option<u64> {
        let (head, rest) = self.0.split_first_chunk::<8>()?;
        self.0 = rest;
        Some(u64::from_le_bytes(*head))
    }
    fn f(&mut self) -> Option<f64> {
        self.u().map(f64::from_bits)
    }
    fn u32(&mut self) -> Option<u32> {
        self.u().and_then(|v| u32::try_from(v).ok())
    }
}

fn decode(blob: &[u8], ids: &mut Vec<i64>, out: &mut Vec<Sample>) -> Option<()> {
    let mut r = Reader(blob);
    while !r.0.is_empty() {
        ids.push(r.u()? as i64);
        let strike = kisstime::simulate::CueStrike {
            v0: r.f()?,
            phi: r.f()?,
            theta: r.f()?,
            a: r.f()?,
            b: r.f()?,
        };
        let (kind, a, b) = (r.u()?, r.u32()?, r.u()?);
        let first = match kind {
            0 => FirstContact::Ball(a),
            1 => FirstContact::Cushion {
                circular: b == 1,
                index: a,
            },
            2 => FirstContact::Pocket(a),
            3 => FirstContact::Stopped,
            4 => FirstContact::Nothing,
            _ => return None,
        };
        let first_t = r.f()?;
        let contact_cue = (r.f()?, r.f()?);
        let contact_speed = r.f()?;
        let contact_point = (r.f()?, r.f()?);
        let cut_angle = r.f()?;
        let n = r.u()?;
        let mut potted = Vec::with_capacity(n.min(64) as usize);
        for _ in 0..n {
            potted.push(Pot {
                ball: r.u32()?,
                pocket: r.u32()?,
                t: r.f()?,
            });
        }
        let cue_final = (r.f()?, r.f()?);
        let n_events = r.u()? as usize;
        let duration = r.f()?;
        let cut = match r.u()? {
            0 => None,
            1 => Some(kisstime::simulate::Cut::MaxEvents),
            2 => Some(kisstime::simulate::Cut::MaxTime),
            _ => return None,
        };
        let verdict = verdict_of(r.u()?)?;
        out.push(Sample {
            strike,
            first,
            first_t,
            contact_cue,
            contact_speed,
            contact_point,
            cut_angle,
            potted,
            cue_final,
            n_events,
            duration,
            cut,
            verdict,
        });
    }
    Some(())
}

/// One chunk of a study: samples `first .. first + n` (noisy, from `seed`; or rows
/// `first .. first + n` of the given strikes), as an opaque blob for [`study_merge`].
#[pyfunction]
#[pyo3(signature = (kind, text, source, dir, physics, physics_noise, first, n, seed, strikes, until, noise, max_events, max_time, backend, precision))]
#[allow(clippy::too_many_arguments)]
fn study_chunk<'py>(
    py: Python<'py>,
    kind: &str,
    text: &str,
    source: &str,
    dir: Option<&str>,
    physics: PhysicsArg,
    physics_noise: Option<&str>,
    first: usize,
    n: usize,
    seed: u64,
    strikes: Option<(I64s<'py>, [F64s<'py>; 5])>,
    until: &str,
    noise: Option<f64>,
    max_events: u64,
    max_time: f64,
    backend: &str,
    precision: Option<&str>,
) -> PyResult<Bound<'py, PyBytes>> {
    let config = config_of(kind, text, source, dir, &physics, physics_noise)?;
    // checked now; the device is opened only for a chunk that has samples (the Python
    // side checks its arguments with an empty chunk first)
    let (_, precision_kind) = backend_of(backend, Some(precision.unwrap_or("f64")))?;
    if precision_kind == Precision::F32 {
        // refused on every backend (whole shots are f64 only)
        shot_engine_of(backend, precision)?;
    }
    let until = until_of(until)?;
    let limits = Limits::new(max_events, max_time).map_err(|e| py_err(e.into()))?;
    // the given strikes, or the noise of the study's samples first .. first + n
    let mut noisy = None;
    let (ids, strikes): (Vec<i64>, Vec<_>) = match &strikes {
        Some((sample, v)) => {
            let cols = [
                slice(&v[0], "V0")?,
                slice(&v[1], "phi")?,
                slice(&v[2], "theta")?,
                slice(&v[3], "a")?,
                slice(&v[4], "b")?,
            ];
            let all = sample_strikes_from_columns("strikes", slice(sample, "sample")?, cols)
                .map_err(py_err)?;
            let end = all.len().min(first.saturating_add(n));
            all[first.min(end)..end]
                .iter()
                .map(|s| (s.sample, s.strike))
                .unzip()
        }
        None => {
            let factor = noise.unwrap_or(config.noise_factor);
            if !(factor.is_finite() && factor >= 0.0) {
                return Err(PyValueError::new_err(format!(
                    "noise {factor}: it must be finite and not negative"
                )));
            }
            noisy = Some(config.noise.scaled(factor));
            let end = first.saturating_add(n);
            ((first..end).map(|i| i as i64).collect(), Vec::new())
        }
    };
    let options = RunOptions { until, limits };
    let samples = if ids.is_empty() {
        kisstime::study::run_strikes(&config, &[], &options, &mut |_, _| {}).map_err(py_err)?
    } else {
        let mut engine = pooled_shot_engine(backend, precision)?;
        warn_notes(py, &mut engine)?;
        let which = match &noisy {
            // the study's own samples: their strikes and physics drawn by their ids
            Some(sigma) => kisstime::study::Samples::Drawn {
                sigma,
                seed,
                range: first..first + ids.len(),
            },
            None => kisstime::study::Samples::Given(&strikes),
        };
        let samples = py
            .detach(|| kisstime::study::run(&mut engine, &config, which, &options, &mut |_, _| {}));
        warn_notes(py, &mut engine)?;
        let samples = samples.map_err(py_err)?;
        engine.succeeded();
        samples
    };
    let mut out = Vec::with_capacity(samples.len() * 256);
    for (id, s) in ids.iter().zip(&samples) {
        encode(&mut out, *id, s);
    }
    Ok(PyBytes::new(py, &out))
}

/// The blobs of a study's chunks, merged in order: `(summary JSON, columns, potted)` —
/// `columns` a dict of 1-D arrays, one row per sample, `potted` the `ball@pocket;…`
/// strings.
#[pyfunction]
#[pyo3(signature = (kind, text, source, dir, physics, physics_noise, blobs, until))]
#[allow(clippy::type_complexity, clippy::too_many_arguments)]
fn study_merge<'py>(
    py: Python<'py>,
    kind: &str,
    text: &str,
    source: &str,
    dir: Option<&str>,
    physics: PhysicsArg,
    physics_noise: Option<&str>,
    blobs: Vec<Bound<'py, PyBytes>>,
    until: &str,
) -> PyResult<(String, Bound<'py, PyDict>, Vec<String>)> {
    let config = config_of(kind, text, source, dir, &physics, physics_noise)?;
    let until = until_of(until)?;
    let mut ids = Vec::new();
    let mut samples = Vec::new();
    for b in &blobs {
        decode(b.as_bytes(), &mut ids, &mut samples)
            .ok_or_else(|| PyValueError::new_err("not a study chunk (corrupt blob)"))?;
    }
    let summary = Summary::of(&config, &samples, until);
    let json = summary.to_json(&config).to_string();
    let cols = PyDict::new(py);
    let col_i = |f: &dyn Fn(&Sample) -> i64| -> Vec<i64> { samples.iter().map(f).collect() };
    let col_f = |f: &dyn Fn(&Sample) -> f64| -> Vec<f64> { samples.iter().map(f).collect() };
    let rest = until == Until::Rest;
    cols.set_item("sample", PyArray1::from_vec(py, ids.clone()))?;
    cols.set_item("V0", PyArray1::from_vec(py, col_f(&|s| s.strike.v0)))?;
    cols.set_item("phi", PyArray1::from_vec(py, col_f(&|s| s.strike.phi)))?;
    cols.set_item("theta", PyArray1::from_vec(py, col_f(&|s| s.strike.theta)))?;
    cols.set_item("a", PyArray1::from_vec(py, col_f(&|s| s.strike.a)))?;
    cols.set_item("b", PyArray1::from_vec(py, col_f(&|s| s.strike.b)))?;
    let first_kind = |s: &Sample| match Class::of(s.first) {
        Class::Ball(_) => 0,
        Class::Cushion => 1,
        Class::Pocket => 2,
        Class::Stopped => 3,
        Class::Nothing => 4,
    };
    cols.set_item("first_contact", PyArray1::from_vec(py, col_i(&first_kind)))?;
    let first_item = |s: &Sample| match s.first {
        FirstContact::Ball(k) | FirstContact::Pocket(k) => i64::from(k),
        FirstContact::Cushion { index, .. } => i64::from(index),
        _ => -1,
    };
    cols.set_item("first_index", PyArray1::from_vec(py, col_i(&first_item)))?;
    cols.set_item("first_t", PyArray1::from_vec(py, col_f(&|s| s.first_t)))?;
    cols.set_item("speed", PyArray1::from_vec(py, col_f(&|s| s.contact_speed)))?;
    cols.set_item("cut_angle", PyArray1::from_vec(py, col_f(&|s| s.cut_angle)))?;
    let result = |s: &Sample| {
        if !rest {
            return -1;
        }
        Result4::of(&config, s).index() as i64
    };
    cols.set_item("result", PyArray1::from_vec(py, col_i(&result)))?;
    let pocket = |k: usize| move |s: &Sample| s.pocket_of(k).map_or(-1, |p| p as i64);
    cols.set_item(
        "intended_pocket",
        PyArray1::from_vec(py, col_i(&pocket(config.intended))),
    )?;
    cols.set_item(
        "cue_pocket",
        PyArray1::from_vec(py, col_i(&pocket(config.cue))),
    )?;
    cols.set_item("cue_x", PyArray1::from_vec(py, col_f(&|s| s.cue_final.0)))?;
    cols.set_item("cue_y", PyArray1::from_vec(py, col_f(&|s| s.cue_final.1)))?;
    cols.set_item(
        "n_events",
        PyArray1::from_vec(py, col_i(&|s| s.n_events as i64)),
    )?;
    cols.set_item("duration", PyArray1::from_vec(py, col_f(&|s| s.duration)))?;
    let cut = |s: &Sample| match s.cut {
        None => 0,
        Some(kisstime::simulate::Cut::MaxEvents) => 1,
        Some(kisstime::simulate::Cut::MaxTime) => 2,
    };
    cols.set_item("cut", PyArray1::from_vec(py, col_i(&cut)))?;
    // the game's verdict (-1 everywhere without a game)
    let flag =
        |f: fn(&Verdict) -> bool| move |s: &Sample| s.verdict.map_or(-1, |v| i64::from(f(&v)));
    cols.set_item("legal", PyArray1::from_vec(py, col_i(&flag(|v| v.legal))))?;
    let foul = |s: &Sample| {
        s.verdict
            .and_then(|v| v.foul)
            .and_then(|f| Foul::ALL.iter().position(|&g| g == f))
            .map_or(-1, |i| i as i64)
    };
    cols.set_item("foul", PyArray1::from_vec(py, col_i(&foul)))?;
    cols.set_item(
        "turn_over",
        PyArray1::from_vec(py, col_i(&flag(|v| v.turn_over))),
    )?;
    cols.set_item(
        "game_over",
        PyArray1::from_vec(py, col_i(&flag(|v| v.game_over))),
    )?;
    cols.set_item("won", PyArray1::from_vec(py, col_i(&flag(|v| v.won))))?;
    let points =
        |f: fn(&Verdict) -> u32| move |s: &Sample| s.verdict.map_or(-1, |v| i64::from(f(&v)));
    cols.set_item(
        "points",
        PyArray1::from_vec(py, col_i(&points(|v| v.points))),
    )?;
    cols.set_item(
        "foul_points",
        PyArray1::from_vec(py, col_i(&points(|v| v.foul_points))),
    )?;
    let potted = samples
        .iter()
        .map(|s| kisstime::study::reference::potted_field(&config, s))
        .collect();
    Ok((json, cols, potted))
}

/// The ids of a study's balls and of its table's pockets, cushions and jaws:
/// `(balls, pockets, linear, circular, cue index, intended index)`.
#[pyfunction]
#[pyo3(signature = (kind, text, source, dir, physics, physics_noise))]
#[allow(clippy::type_complexity)]
fn study_ids(
    kind: &str,
    text: &str,
    source: &str,
    dir: Option<&str>,
    physics: PhysicsArg,
    physics_noise: Option<&str>,
) -> PyResult<(
    Vec<String>,
    Vec<String>,
    Vec<String>,
    Vec<String>,
    usize,
    usize,
)> {
    let c = config_of(kind, text, source, dir, &physics, physics_noise)?;
    Ok((
        c.balls.iter().map(|b| b.id.clone()).collect(),
        c.table.pocket_ids.clone(),
        c.table.linear_ids.clone(),
        c.table.circular_ids.clone(),
        c.cue,
        c.intended,
    ))
}

/// A table's item ids `(linear, circular, pockets)` in index order (of the JSON text
/// `json` when given, else of the table `name` names).
#[pyfunction]
#[pyo3(signature = (name, json=None))]
fn table_ids(name: &str, json: Option<&str>) -> PyResult<(Vec<String>, Vec<String>, Vec<String>)> {
    let t = table_of(name, json)?;
    Ok((t.linear_ids, t.circular_ids, t.pocket_ids))
}

/// Many games stepped at once for learning agents (`kisstime.gym`'s engine: the library's
/// `env::VecEnv` with its shot engine). Actions and observations cross as flat NumPy
/// arrays; a Python opponent is called with the GIL held, between the engine's calls.
#[pyclass(name = "VecEnv", module = "kisstime._kisstime")]
struct PyVecEnv {
    env: kisstime::env::VecEnv,
    engine: ShotEngine,
}

/// A Python opponent as [`kisstime::env::Policy`]: `policy(obs)` with the opponent's rows
/// of observations (2-D float32), returning their actions (n × 7 float64); a Python
/// exception is kept in `raised` and stops the step.
fn py_policy<'a>(
    policy: Option<&'a Py<PyAny>>,
    raised: &'a mut Option<PyErr>,
    obs_len: usize,
) -> impl FnMut(&[usize], &[f32]) -> Result<Vec<f64>, Error> + 'a {
    move |tables: &[usize], obs: &[f32]| {
        let Some(policy) = policy else {
            return Err(kisstime::error::InputError::new(
                "the opponent is a policy, and none was given",
            )
            .into());
        };
        Python::attach(|py| {
            let call = || -> PyResult<Vec<f64>> {
                let rows = numpy::PyArrayMethods::reshape(
                    &PyArray1::from_slice(py, obs),
                    [tables.len(), obs_len],
                )?;
                let out = policy.call1(py, (rows,))?;
                let np = py.import("numpy")?;
                let flat = np
                    .call_method1("ascontiguousarray", (out, "float64"))?
                    .call_method1("reshape", (-1,))?;
                flat.extract::<Vec<f64>>()
            };
            call().map_err(|e| {
                *raised = Some(e);
                kisstime::error::InputError::new("the opponent's policy raised").into()
            })
        })
    }
}

#[pymethods]
impl PyVecEnv {
    #[new]
    #[pyo3(signature = (task, drill_balls, tables, max_shots, rewards, noise_preset, noise_sigma, noise_scale, opponent, budget_samples, max_events, backend))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        task: &str,
        drill_balls: usize,
        tables: usize,
        max_shots: u32,
        rewards: (f64, f64, f64, f64),
        noise_preset: Option<&str>,
        noise_sigma: Option<(f64, f64, f64, f64, f64)>,
        noise_scale: f64,
        opponent: &str,
        budget_samples: usize,
        max_events: u64,
        backend: &str,
    ) -> PyResult<Self> {
        use kisstime::env::{EnvOptions, Opponent, Rewards, Task};
        let task = match task {
            "8-ball" => Task::EightBall,
            "9-ball" => Task::NineBall,
            "drill" => Task::Drill { balls: drill_balls },
            other => {
                return Err(PyValueError::new_err(format!(
                    "game {other:?}: \"8-ball\", \"9-ball\" or \"drill\""
                )));
            }
        };
        let opponent = match opponent {
            "self" => Opponent::SelfPlay,
            "policy" => Opponent::Policy,
            name => Opponent::Agent(
                kisstime::plan::agents::Agent::from_name(name).map_err(PyValueError::new_err)?,
            ),
        };
        if !(noise_scale.is_finite() && noise_scale >= 0.0) {
            return Err(PyValueError::new_err(format!(
                "noise_scale {noise_scale}: a finite factor of at least 0"
            )));
        }
        let noise =
            noise_of(noise_preset, noise_sigma, SimParams::default().ball.r)?.scaled(noise_scale);
        let limits = Limits::new(max_events, f64::INFINITY).map_err(|e| py_err(e.into()))?;
        let options = EnvOptions {
            task,
            tables,
            max_shots,
            rewards: Rewards {
                pot: rewards.0,
                foul: rewards.1,
                win: rewards.2,
                loss: rewards.3,
            },
            noise,
            opponent,
            budget: kisstime::plan::Budget::Samples(budget_samples),
            limits,
        };
        let env = kisstime::env::VecEnv::new(options).map_err(py_err)?;
        let engine = shot_engine_of(backend, Some("f64"))?;
        Ok(PyVecEnv { env, engine })
    }

    /// Numbers in one table's observation.
    #[getter]
    fn obs_len(&self) -> usize {
        self.env.obs_len()
    }

    /// Tables.
    #[getter]
    fn num_tables(&self) -> usize {
        self.env.len()
    }

    /// What ran (`cpu f64 (2 threads)`, the adapter…).
    fn describe(&self) -> String {
        self.engine.describe()
    }

    /// Every table's observation, flat (tables × obs_len float32).
    fn observe<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        let mut out = vec![0f32; self.env.len() * self.env.obs_len()];
        self.env.observe(&mut out);
        PyArray1::from_vec(py, out)
    }

    /// New episodes (seeds: one a table, or None to go on); returns the opponent's shots
    /// per table.
    #[pyo3(signature = (seeds, policy=None))]
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        seeds: Option<Vec<u64>>,
        policy: Option<Py<PyAny>>,
    ) -> PyResult<Vec<u32>> {
        let obs_len = self.env.obs_len();
        let mut raised = None;
        let (env, engine) = (&mut self.env, &mut self.engine);
        let done = {
            let mut policy = py_policy(policy.as_ref(), &mut raised, obs_len);
            py.detach(|| env.reset(engine, seeds.as_deref(), &mut policy))
        };
        warn_notes(py, &mut self.engine)?;
        if let Some(e) = raised {
            return Err(e);
        }
        done.map_err(py_err)
    }

    /// The next episode of every table whose episode ended: `(which, opponent shots)`.
    #[pyo3(signature = (policy=None))]
    fn reset_ended(
        &mut self,
        py: Python<'_>,
        policy: Option<Py<PyAny>>,
    ) -> PyResult<(Vec<bool>, Vec<u32>)> {
        let obs_len = self.env.obs_len();
        let mut raised = None;
        let (env, engine) = (&mut self.env, &mut self.engine);
        let done = {
            let mut policy = py_policy(policy.as_ref(), &mut raised, obs_len);
            py.detach(|| env.reset_ended(engine, &mut policy))
        };
        warn_notes(py, &mut self.engine)?;
        if let Some(e) = raised {
            return Err(e);
        }
        done.map_err(py_err)
    }

    /// One step of every table (actions: tables × 7 float64, flat): `(rewards,
    /// terminated, truncated, info)`, `info` a dict of per-table lists.
    #[pyo3(signature = (actions, policy=None))]
    #[allow(clippy::type_complexity)]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: F64s<'py>,
        policy: Option<Py<PyAny>>,
    ) -> PyResult<(Vec<f64>, Vec<bool>, Vec<bool>, Bound<'py, PyDict>)> {
        let actions = slice(&actions, "actions")?;
        let obs_len = self.env.obs_len();
        let mut raised = None;
        let (env, engine) = (&mut self.env, &mut self.engine);
        let done = {
            let mut policy = py_policy(policy.as_ref(), &mut raised, obs_len);
            py.detach(|| env.step(engine, actions, &mut policy))
        };
        warn_notes(py, &mut self.engine)?;
        if let Some(e) = raised {
            return Err(e);
        }
        let r = done.map_err(py_err)?;
        let info = PyDict::new(py);
        info.set_item("reset", r.reset)?;
        info.set_item("fouled", r.fouled)?;
        info.set_item("potted", r.potted)?;
        info.set_item("won", r.won)?;
        info.set_item("opponent_shots", r.opponent_shots)?;
        info.set_item("cut", r.cut)?;
        Ok((r.rewards, r.terminated, r.truncated, info))
    }
}

/// The cue noise a preset's name or five sigmas in pooltool's units (V0 m/s; φ, θ
/// degrees; a, b fractions of the radius `r`) name, one of the two.
fn noise_of(
    noise_preset: Option<&str>,
    noise_sigma: Option<(f64, f64, f64, f64, f64)>,
    r: f64,
) -> PyResult<kisstime::study::Noise> {
    Ok(match (noise_preset, noise_sigma) {
        (Some(name), None) => kisstime::study::Noise::preset(name).ok_or_else(|| {
            let names: Vec<&str> = kisstime::study::NOISE_PRESETS
                .iter()
                .map(|(n, _, _)| *n)
                .collect();
            PyValueError::new_err(format!(
                "noise {name:?}: not a preset (one of {}), nor a dict of sigmas",
                names.join(", ")
            ))
        })?,
        (None, Some((v0, phi, theta, a, b))) => {
            if ![v0, phi, theta, a, b]
                .iter()
                .all(|x| x.is_finite() && *x >= 0.0)
            {
                return Err(PyValueError::new_err(
                    "noise: every sigma must be finite and at least 0",
                ));
            }
            kisstime::study::Noise {
                v0,
                phi,
                theta,
                a: a * r,
                b: b * r,
                physics: Default::default(),
            }
        }
        _ => return Err(PyValueError::new_err("give one noise: a preset or sigmas")),
    })
}

/// The extension module.
#[pymodule]
fn _kisstime(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(pair_times, m)?)?;
    m.add_function(wrap_pyfunction!(release_engines, m)?)?;
    m.add_function(wrap_pyfunction!(next_collisions, m)?)?;
    m.add_class::<PyBatch>()?;
    m.add_class::<PyVecEnv>()?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_shots, m)?)?;
    m.add_function(wrap_pyfunction!(plan, m)?)?;
    m.add_function(wrap_pyfunction!(study_chunk, m)?)?;
    m.add_function(wrap_pyfunction!(study_merge, m)?)?;
    m.add_function(wrap_pyfunction!(study_ids, m)?)?;
    m.add_function(wrap_pyfunction!(table_ids, m)?)?;
    Ok(())
}
