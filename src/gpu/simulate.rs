//! The host of the GPU event loop (`shaders/simulate/event_loop.wgsl`, the WGSL twin of
//! [`crate::simulate::EventLoop`]): whole shots for many tables at once, one workgroup per
//! table.
//!
//! The host checks each table as [`EventLoop::reset`] does, resolves the strike (the stick
//! event, which has no shader twin) with [`cue_strike`] under the CPU's rule (at t = 0, if
//! every ball is at rest and V0 > 0), lays the tables' states out as the shader reads them,
//! and dispatches up to `events_per_dispatch` events per table at a time until every table
//! is done, reading the recorded events back after each dispatch. The states stay on the
//! device between dispatches.
//!
//! A batch is cut into chunks of whole tables that fit the device's buffers. Limits of
//! this first version: at most [`GPU_MAX_BALLS`] balls per table, and no fall back to the
//! CPU here (the caller chooses: `kisstime simulate --backend auto` does).

use super::GpuTimings;
use super::device::{self, AdapterSummary, Scopes, gpu_error, map_and_wait};
use super::shader::simulate_source;
use crate::error::{Error, InputError, SimError};
use crate::model::ball_state::{BallState, ball_energy};
use crate::model::sim_params::SimParams;
use crate::model::table::Table;
use crate::model::vec3::Vec3;
use crate::model::{MotionState, Precision};
use crate::motion::evolve::{TransitionKind, next_transition};
use crate::resolve::stick_ball::{CueStrike, cue_strike};
use crate::simulate::batch::EventRecord;
use crate::simulate::check::check_layout;
use crate::simulate::events::{Cut, Event, EventKind, NO_AGENT, Outcome};
use crate::simulate::{EventLoop, Limits};

/// Events per table and dispatch, by default. Short dispatches keep a device responsive;
/// on lavapipe (Mesa 22.3) a 16-ball break's first 256-event dispatch stopped part-way
/// (after 172 events, with some threads' states not written back), while dispatches of
/// 32 or 64 events give the CPU's events.
pub const EVENTS_PER_DISPATCH: u32 = 32;

/// The most balls of one table on the GPU (the shader's `GPU_MAX_BALLS`).
pub const GPU_MAX_BALLS: usize = 16;
/// Reals and u32s of one table's state (the shader's `TABLE_REALS`, `TABLE_UINTS`).
const TABLE_REALS: usize = 345;
const TABLE_UINTS: usize = 251;
/// Per recorded event (`EVENT_REALS`, `EVENT_UINTS`).
const EVENT_REALS: usize = 21;
const EVENT_UINTS: usize = 5;
/// Offsets in a table's state (see the shader's `load_table`).
const R_TRANS: usize = 160;
const R_PAIRS: usize = 176;
const R_ROWS: usize = 296;
const R_CLOCK: usize = 344;
const U_TRANS: usize = 16;
const U_PAIRS: usize = 32;
const U_ROWS: usize = 152;
const U_ITEMS: usize = 200;
const U_N: usize = 248;
const MISSING_STEP: u32 = u32::MAX;
/// Pair entries and ball–table rows of one table (`GPU_MAX_PAIRS`, 3 · `GPU_MAX_BALLS`).
const GPU_MAX_PAIRS: usize = GPU_MAX_BALLS * (GPU_MAX_BALLS - 1) / 2;
const GPU_ROWS: usize = 3 * GPU_MAX_BALLS;
/// The shader's "never" as the host writes it in f64 (f32 buffers get `NEVER_F32`).
const NEVER_F64: f64 = 1.0e300;
const NEVER_F32: f32 = 3.0e38;

/// What [`GpuSimulator::simulate_with`] hands each event to: `(table, record)`.
pub type OnEvent<'a> = &'a mut dyn FnMut(usize, &EventRecord);

/// One table's shot: its balls (pooltool's order) and the strike, if any.
#[derive(Clone, Debug)]
pub struct GpuShot {
    /// The balls at t = 0.
    pub balls: Vec<BallState>,
    /// The cue ball's index and the strike.
    pub strike: Option<(usize, CueStrike)>,
}

/// One table's result: its events (if asked for) with the involved balls' states, the
/// final states, and how it ended.
#[derive(Clone, Debug, PartialEq)]
pub struct GpuRun {
    /// The events, the strike included (empty unless events were asked for).
    pub events: Vec<EventRecord>,
    /// The balls at the end.
    pub balls: Vec<BallState>,
    /// Events, end time, and whether a limit cut the run.
    pub outcome: Outcome,
}

/// The GPU event loop: device and pipeline, reused across calls.
pub struct GpuSimulator {
    pub(super) device: wgpu::Device,
    queue: wgpu::Queue,
    adapter: AdapterSummary,
    precision: Precision,
    pipeline: wgpu::ComputePipeline,
    pub(super) max_groups_per_dim: u32,
    /// The largest storage binding the device allows, in bytes.
    max_binding: u64,
    watch: device::DeviceWatch,
    /// A fault waiting for its dispatch: the fault, and how many dispatches run first.
    #[cfg(feature = "testing")]
    pub(super) pending_fault: Option<(super::Fault, u32)>,
    /// The last call's timings (summed over chunks): `upload` the host's checks, layout
    /// and buffers; `kernel` the dispatches until every table is done (with the 4-byte
    /// "running" count after each, and the events where they are read back); `readback`
    /// the final states.
    timings: GpuTimings,
    /// Dispatches of the last call.
    dispatches: u64,
    /// Events per table and dispatch.
    pub events_per_dispatch: u32,
    /// The most tables per chunk: a batch is cut into chunks of whole tables that fit the
    /// device's largest storage binding, and of at most this many tables (by default
    /// [`MAX_TABLES_PER_CHUNK`]), simulated one after the other.
    pub max_tables_per_chunk: usize,
}

/// Tables per chunk, at most, by default.
pub const MAX_TABLES_PER_CHUNK: usize = 1 << 20;

impl GpuSimulator {
    /// Opens the GPU and builds the event loop's pipeline for `precision`.
    ///
    /// Errors: [`Error::GpuUnavailable`] without a usable adapter (or without
    /// `SHADER_F64` for f64); [`Error::Gpu`] when the device or the shader fails to build.
    pub fn new(precision: Precision) -> Result<GpuSimulator, Error> {
        let opened = device::open(precision)?;
        let device = opened.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("kisstime event loop"),
            source: wgpu::ShaderSource::Wgsl(simulate_source(precision).into()),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("simulate_tables"),
            layout: None,
            module: &module,
            entry_point: Some("simulate_tables"),
            compilation_options: Default::default(),
            cache: None,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(gpu_error(format!(
                "the {} event-loop shader does not build on {}: {e}",
                precision.name(),
                opened.adapter.name
            )));
        }
        Ok(GpuSimulator {
            max_groups_per_dim: opened.limits.max_compute_workgroups_per_dimension,
            max_binding: opened
                .limits
                .max_storage_buffer_binding_size
                .min(opened.limits.max_buffer_size),
            device,
            queue: opened.queue,
            adapter: opened.adapter,
            watch: opened.watch,
            #[cfg(feature = "testing")]
            pending_fault: None,
            precision,
            pipeline,
            timings: GpuTimings::default(),
            dispatches: 0,
            events_per_dispatch: EVENTS_PER_DISPATCH,
            max_tables_per_chunk: MAX_TABLES_PER_CHUNK,
        })
    }

    /// The adapter in use.
    pub fn adapter(&self) -> &AdapterSummary {
        &self.adapter
    }

    /// The precision the event loop computes in.
    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// The last call's upload / kernel / readback split (see the field docs of
    /// [`GpuTimings`]: here "kernel" is every dispatch of the event loop, waited for).
    pub fn timings(&self) -> GpuTimings {
        self.timings
    }

    /// The dispatches of the last call (over all chunks).
    pub fn dispatches(&self) -> u64 {
        self.dispatches
    }

    /// Simulates every shot on `table` to rest (or to a limit), in shot order; with
    /// `record_events` each run keeps its events (see [`GpuSimulator::simulate_with`] to
    /// stream them instead).
    ///
    /// Errors: a table with more than [`GPU_MAX_BALLS`] balls ([`Error::Unsupported`]); a
    /// table the CPU refuses too (`check_layout`: non-finite numbers, a ball off the
    /// table; a bad strike), as [`Error::Input`] naming the table and the reason; bad
    /// parameters; or a device failure ([`Error::Gpu`]: validation, out of memory, a lost
    /// device, a failed readback).
    pub fn simulate(
        &mut self,
        table: &Table,
        params: SimParams,
        limits: Limits,
        shots: &[GpuShot],
        record_events: bool,
    ) -> Result<Vec<GpuRun>, Error> {
        if !record_events {
            return self.simulate_with(table, params, limits, shots, None);
        }
        let mut events: Vec<Vec<EventRecord>> = vec![Vec::new(); shots.len()];
        let mut keep = |k: usize, e: &EventRecord| events[k].push(*e);
        let mut runs = self.simulate_with(table, params, limits, shots, Some(&mut keep))?;
        for (run, ev) in runs.iter_mut().zip(events) {
            run.events = ev;
        }
        Ok(runs)
    }

    /// [`GpuSimulator::simulate`] that hands each event, in order within each table, to
    /// `on_event(table, record)` as it is read back (after every dispatch) instead of
    /// keeping it: a study watches a million shots' events without holding them. Without
    /// `on_event` no event is read back. The runs' `events` stay empty.
    pub fn simulate_with(
        &mut self,
        table: &Table,
        params: SimParams,
        limits: Limits,
        shots: &[GpuShot],
        on_event: Option<OnEvent<'_>>,
    ) -> Result<Vec<GpuRun>, Error> {
        let record_events = on_event.is_some();
        let mut ignore = |_: usize, _: &EventRecord| {};
        let on_event: &mut dyn FnMut(usize, &EventRecord) = match on_event {
            Some(f) => f,
            None => &mut ignore,
        };
        let per = self.events_per_dispatch.max(1) as usize;
        let real = self.precision.real_size();
        // the largest per-table buffer decides how many tables fit one binding
        let per_table = (TABLE_REALS * real)
            .max(per * EVENT_REALS * real)
            .max(4 * (1 + per * EVENT_UINTS));
        let fit = (self.max_binding / per_table as u64).max(1) as usize;
        let chunk = self.max_tables_per_chunk.max(1).min(fit);
        self.timings = GpuTimings::default();
        self.dispatches = 0;
        let mut runs = Vec::with_capacity(shots.len());
        for (c, part) in shots.chunks(chunk).enumerate() {
            runs.extend(self.simulate_chunk(
                table,
                params,
                limits,
                part,
                c * chunk,
                record_events,
                &mut *on_event,
            )?);
        }
        Ok(runs)
    }

    /// [`GpuSimulator::simulate_with`] for one chunk of tables that fits the device's
    /// buffers; `first` is the chunk's first table in the batch (for messages and for
    /// `on_event`, which is called only with `record_events`).
    #[allow(clippy::too_many_arguments)]
    fn simulate_chunk(
        &mut self,
        table: &Table,
        params: SimParams,
        limits: Limits,
        shots: &[GpuShot],
        first: usize,
        record_events: bool,
        on_event: &mut dyn FnMut(usize, &EventRecord),
    ) -> Result<Vec<GpuRun>, Error> {
        let n_tables = shots.len();
        let clock = std::time::Instant::now();
        // the parameters and every table checked as the CPU loop checks them
        let mut check = EventLoop::new(table, params, limits, GPU_MAX_BALLS)
            .map_err(|e| gpu_error(format!("the simulation parameters: {e}")))?;
        let mut runs = Vec::with_capacity(n_tables);
        let mut state_r = vec![0.0f64; n_tables * TABLE_REALS];
        let mut state_u = vec![0u32; n_tables * TABLE_UINTS];
        for (k, shot) in shots.iter().enumerate() {
            let at = first + k;
            let bad = |e: SimError| Error::from(InputError::new(format!("table {at}: {e}")));
            if shot.balls.len() > GPU_MAX_BALLS {
                return Err(Error::Unsupported(format!(
                    "table {at}: {} balls, the GPU event loop takes at most {GPU_MAX_BALLS}",
                    shot.balls.len()
                )));
            }
            check_layout(table, params.ball.r, &shot.balls).map_err(bad)?;
            check.reset(&shot.balls, shot.strike).map_err(bad)?;
            let (run, strike) = start_table(
                shot,
                &params,
                limits,
                &mut state_r[k * TABLE_REALS..(k + 1) * TABLE_REALS],
                &mut state_u[k * TABLE_UINTS..(k + 1) * TABLE_UINTS],
            );
            if let (true, Some(record)) = (record_events, strike) {
                on_event(at, &record);
            }
            runs.push(run);
        }
        if n_tables == 0 {
            return Ok(runs);
        }
        let mut sim = Vec::with_capacity(19);
        let b = &params.ball;
        sim.extend([
            b.m, b.r, b.u_s, b.u_r, b.u_sp, b.u_b, b.e_b, b.e_c, b.f_c, b.g,
        ]);
        let r = &params.resolver;
        sim.extend([
            r.alciatore_a,
            r.alciatore_b,
            r.alciatore_c,
            r.omega_ratio,
            r.beta_t,
            r.beta_n,
            r.k_n,
            r.spacer,
            limits.max_time,
        ]);
        let mut geometry = Vec::new();
        for s in &table.linear {
            geometry.extend([s.p1.x, s.p1.y, s.p1.z, s.p2.x, s.p2.y, s.p2.z]);
            geometry.extend([s.direction as f64, s.lx, s.ly, s.l0]);
        }
        for c in &table.circular {
            geometry.extend([c.center.x, c.center.y, c.center.z, c.radius]);
        }
        for p in &table.pockets {
            geometry.extend([p.center.x, p.center.y, p.center.z, p.radius, p.depth]);
        }
        geometry.push(0.0);
        let per = self.events_per_dispatch as usize;
        let groups_x = (n_tables as u32).min(self.max_groups_per_dim);
        let groups_y = (n_tables as u32).div_ceil(groups_x);
        let cfg: [u32; 8] = [
            n_tables as u32,
            table.linear.len() as u32,
            table.circular.len() as u32,
            table.pockets.len() as u32,
            u32::try_from(limits.max_events).unwrap_or(u32::MAX),
            self.events_per_dispatch,
            groups_x,
            u32::from(record_events),
        ];
        // a device lost before this chunk fails here, before any buffer is made
        if let Some(e) = self.watch.fault() {
            return Err(e);
        }
        let dev = &self.device;
        // buffers filled through the queue (wgpu's `create_buffer_init` panics on a lost
        // device; this way its failure is reported at the first dispatch)
        let filled = |label: &str, bytes: &[u8], usage: wgpu::BufferUsages| {
            let buffer = dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: (bytes.len() as u64).max(4).next_multiple_of(4),
                usage: usage | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            self.queue.write_buffer(&buffer, 0, bytes);
            buffer
        };
        let reals = |label: &str, v: &[f64], usage: wgpu::BufferUsages| {
            filled(label, &self.real_bytes(v), usage)
        };
        let uints = |label: &str, v: &[u32], usage: wgpu::BufferUsages| {
            filled(label, bytemuck::cast_slice(v), usage)
        };
        let storage = wgpu::BufferUsages::STORAGE;
        let rw = storage | wgpu::BufferUsages::COPY_SRC;
        let cfg_buf = uints("config", &cfg, wgpu::BufferUsages::UNIFORM);
        let sim_buf = reals("sim", &sim, storage);
        let geo_buf = reals("geometry", &geometry, storage);
        let sr_buf = reals("state_r", &state_r, rw);
        let su_buf = uints("state_u", &state_u, rw);
        // the events buffers are one word where no event is read back
        let (n_er, n_eu) = if record_events {
            (
                n_tables * per * EVENT_REALS,
                n_tables * (1 + per * EVENT_UINTS),
            )
        } else {
            (1, n_tables * (1 + per * EVENT_UINTS))
        };
        let er_buf = reals("events_r", &vec![0.0; n_er], rw);
        let eu_buf = uints("events_u", &vec![0; n_eu], rw);
        let running_buf = uints("running", &[0], rw | wgpu::BufferUsages::COPY_DST);
        let layout = self.pipeline.get_bind_group_layout(0);
        let entries: Vec<wgpu::BindGroupEntry> = [
            &cfg_buf,
            &sim_buf,
            &geo_buf,
            &sr_buf,
            &su_buf,
            &er_buf,
            &eu_buf,
            &running_buf,
        ]
        .iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: b.as_entire_binding(),
        })
        .collect();
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("event loop"),
            layout: &layout,
            entries: &entries,
        });
        // what each dispatch reads back, with its readback buffers, made once
        let mut read = vec![&running_buf];
        if record_events {
            read.extend([&eu_buf, &er_buf]);
        }
        let per_dispatch = self.readbacks(&read);
        self.timings.upload += clock.elapsed().as_secs_f64();
        let clock = std::time::Instant::now();
        loop {
            #[cfg_attr(not(feature = "testing"), allow(unused_mut))]
            let mut row = groups_x;
            #[cfg(feature = "testing")]
            self.apply_pending_fault(&mut row);
            self.queue
                .write_buffer(&running_buf, 0, bytemuck::bytes_of(&0u32));
            let back = self.dispatch_and_read([row, groups_y], &bind, &per_dispatch)?;
            self.dispatches += 1;
            if record_events {
                let eu: Vec<u32> = bytemuck::pod_collect_to_vec(&back[1]);
                let er = self.reals_of(&back[2]);
                for k in 0..n_tables {
                    let base = k * (1 + per * EVENT_UINTS);
                    for e in 0..eu[base] as usize {
                        let u = &eu[base + 1 + e * EVENT_UINTS..base + 1 + (e + 1) * EVENT_UINTS];
                        let r0 = (k * per + e) * EVENT_REALS;
                        on_event(first + k, &event_record(u, &er[r0..r0 + EVENT_REALS])?);
                    }
                }
            }
            let running: u32 = bytemuck::pod_read_unaligned(&back[0][..4]);
            if running == 0 {
                self.timings.kernel += clock.elapsed().as_secs_f64();
                let clock = std::time::Instant::now();
                let last = self.readbacks(&[&sr_buf, &su_buf]);
                let back = self.dispatch_and_read([0, 0], &bind, &last)?;
                let sr = self.reals_of(&back[0]);
                let su: Vec<u32> = bytemuck::pod_collect_to_vec(&back[1]);
                for (k, run) in runs.iter_mut().enumerate() {
                    finish_table(
                        run,
                        &sr[k * TABLE_REALS..(k + 1) * TABLE_REALS],
                        &su[k * TABLE_UINTS..(k + 1) * TABLE_UINTS],
                    )?;
                }
                self.timings.readback += clock.elapsed().as_secs_f64();
                return Ok(runs);
            }
        }
    }

    /// A readback buffer for each of `buffers`: `(source, readback)` pairs for
    /// [`GpuSimulator::dispatch_and_read`].
    fn readbacks<'b>(&self, buffers: &[&'b wgpu::Buffer]) -> Vec<(&'b wgpu::Buffer, wgpu::Buffer)> {
        buffers
            .iter()
            .map(|b| {
                let back = self.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("readback"),
                    size: b.size(),
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                (*b, back)
            })
            .collect()
    }

    /// One dispatch of `groups` workgroups (none where a count is 0), then each source of
    /// `read` copied to its readback buffer and returned, in order. Any failure
    /// (validation, out of memory, a lost device, a failed map) is an error, and no buffer
    /// is left mapped then.
    fn dispatch_and_read(
        &self,
        groups: [u32; 2],
        bind: &wgpu::BindGroup,
        read: &[(&wgpu::Buffer, wgpu::Buffer)],
    ) -> Result<Vec<Vec<u8>>, Error> {
        let dev = &self.device;
        let scopes = Scopes::push(dev);
        let mut encoder = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("kisstime event loop"),
        });
        if groups[0] > 0 && groups[1] > 0 {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("kisstime event loop"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, bind, &[]);
            pass.dispatch_workgroups(groups[0], groups[1], 1);
        }
        for (src, back) in read {
            encoder.copy_buffer_to_buffer(src, 0, back, 0, src.size());
        }
        self.queue.submit([encoder.finish()]);
        let views: Vec<(&wgpu::Buffer, u64)> = read.iter().map(|(s, b)| (b, s.size())).collect();
        map_and_wait(dev, scopes, &self.watch, &views, "the GPU event loop")?;
        let mut out = Vec::with_capacity(read.len());
        for (_, back) in read {
            let bytes = back
                .slice(..)
                .get_mapped_range()
                .map(|v| v.to_vec())
                .map_err(|e| gpu_error(format!("the results are not readable: {e}")));
            back.unmap();
            out.push(bytes?);
        }
        Ok(out)
    }

    /// `v` in the shader's precision, as bytes.
    fn real_bytes(&self, v: &[f64]) -> Vec<u8> {
        match self.precision {
            Precision::F64 => bytemuck::cast_slice(v).to_vec(),
            Precision::F32 => {
                let narrow: Vec<f32> = v
                    .iter()
                    .map(|&x| if x >= NEVER_F64 { NEVER_F32 } else { x as f32 })
                    .collect();
                bytemuck::cast_slice(&narrow).to_vec()
            }
        }
    }

    /// Reals read back in the shader's precision, as f64.
    fn reals_of(&self, bytes: &[u8]) -> Vec<f64> {
        match self.precision {
            Precision::F64 => bytemuck::pod_collect_to_vec(bytes),
            Precision::F32 => bytemuck::pod_collect_to_vec::<u8, f32>(bytes)
                .into_iter()
                .map(f64::from)
                .collect(),
        }
    }
}

/// The shader's "never" as the CPU's ∞.
fn from_never(t: f64) -> f64 {
    if t >= f64::from(NEVER_F32) {
        f64::INFINITY
    } else {
        t
    }
}

/// Lays out one table's state at its start (after the strike, which is resolved here)
/// and returns its run so far, with the strike's event record if there was one.
fn start_table(
    shot: &GpuShot,
    params: &SimParams,
    limits: Limits,
    sr: &mut [f64],
    su: &mut [u32],
) -> (GpuRun, Option<EventRecord>) {
    let mut balls: Vec<BallState> = shot
        .balls
        .iter()
        .map(|b| BallState { t: 0.0, ..*b })
        .collect();
    let mut strike = None;
    let mut n_events = 0u32;
    // the stick candidate of the CPU loop: at t = 0, every ball at rest, V0 > 0
    if let Some((cue, s)) = shot.strike {
        let at_rest = balls.iter().all(|b| ball_energy(b, &params.ball) == 0.0);
        if at_rest && s.v0 > 0.0 && limits.max_events > 0 {
            let struck = cue_strike(&balls[cue], &s, &params.ball, &params.cue);
            balls[cue] = BallState { t: 0.0, ..struck };
            n_events = 1;
            let event = Event {
                kind: EventKind::StickBall,
                t: 0.0,
                ball: cue as u32,
                other: NO_AGENT,
            };
            strike = Some(EventRecord::new(event, &balls));
        }
    }
    for (i, b) in balls.iter().enumerate() {
        let at = 10 * i;
        sr[at..at + 10].copy_from_slice(&[
            b.r.x, b.r.y, b.r.z, b.v.x, b.v.y, b.v.z, b.w.x, b.w.y, b.w.z, b.t,
        ]);
        su[i] = b.s as u32;
        let (t, kind) = next_transition(b, &params.ball).map_or((f64::INFINITY, 0), |(tau, k)| {
            (b.t + tau, transition_code(k))
        });
        sr[R_TRANS + i] = if t.is_finite() { t } else { NEVER_F64 };
        su[U_TRANS + i] = kind;
    }
    for k in 0..GPU_MAX_PAIRS {
        sr[R_PAIRS + k] = NEVER_F64;
        su[U_PAIRS + k] = MISSING_STEP;
    }
    for k in 0..GPU_ROWS {
        sr[R_ROWS + k] = NEVER_F64;
        su[U_ROWS + k] = MISSING_STEP;
        su[U_ITEMS + k] = 0;
    }
    sr[R_CLOCK] = 0.0;
    su[U_N] = balls.len() as u32;
    su[U_N + 1] = n_events;
    // a table without balls, or one cut before its first event, is done already
    su[U_N + 2] = if limits.max_events == 0 {
        2
    } else if balls.is_empty() {
        1
    } else {
        0
    };
    let run = GpuRun {
        events: Vec::new(),
        balls,
        outcome: Outcome {
            n_events: n_events as usize,
            t_end: 0.0,
            cut: None,
        },
    };
    (run, strike)
}

/// The shader's code of a transition kind (`TRANSITION_*` of `motion/evolve.wgsl`).
fn transition_code(k: TransitionKind) -> u32 {
    match k {
        TransitionKind::SlidingRolling => 0,
        TransitionKind::RollingSpinning => 1,
        TransitionKind::RollingStationary => 2,
        TransitionKind::SpinningStationary => 3,
    }
}

fn event_kind(code: u32) -> Result<EventKind, Error> {
    Ok(match code {
        0 => EventKind::StickBall,
        1 => EventKind::BallBall,
        2 => EventKind::BallLinearCushion,
        3 => EventKind::BallCircularCushion,
        4 => EventKind::BallPocket,
        5 => EventKind::SlidingRolling,
        6 => EventKind::RollingSpinning,
        7 => EventKind::RollingStationary,
        8 => EventKind::SpinningStationary,
        _ => return Err(gpu_error(format!("the GPU reported event kind {code}"))),
    })
}

fn motion_state(code: u32) -> Result<MotionState, Error> {
    Ok(match code {
        0 => MotionState::Stationary,
        1 => MotionState::Spinning,
        2 => MotionState::Sliding,
        3 => MotionState::Rolling,
        4 => MotionState::Pocketed,
        _ => return Err(gpu_error(format!("the GPU reported motion state {code}"))),
    })
}

/// A ball state from its 10 reals (r, v, w, t) and its motion state.
fn ball_state(r: &[f64], s: u32) -> Result<BallState, Error> {
    Ok(BallState {
        r: Vec3::new(r[0], r[1], r[2]),
        v: Vec3::new(r[3], r[4], r[5]),
        w: Vec3::new(r[6], r[7], r[8]),
        s: motion_state(s)?,
        t: r[9],
    })
}

/// One recorded event from its u32s (kind, ball, other, two states) and reals.
fn event_record(u: &[u32], r: &[f64]) -> Result<EventRecord, Error> {
    let event = Event {
        kind: event_kind(u[0])?,
        t: r[0],
        ball: u[1],
        other: u[2],
    };
    Ok(EventRecord {
        event,
        states: [ball_state(&r[1..11], u[3])?, ball_state(&r[11..21], u[4])?],
    })
}

/// Reads a finished table's final states and outcome into its run.
fn finish_table(run: &mut GpuRun, sr: &[f64], su: &[u32]) -> Result<(), Error> {
    let n = su[U_N] as usize;
    for i in 0..n {
        run.balls[i] = ball_state(&sr[10 * i..10 * i + 10], su[i])?;
    }
    run.outcome = Outcome {
        n_events: su[U_N + 1] as usize,
        t_end: from_never(sr[R_CLOCK]),
        cut: match su[U_N + 2] {
            2 => Some(Cut::MaxEvents),
            3 => Some(Cut::MaxTime),
            _ => None,
        },
    };
    Ok(())
}
