//! The GPU backend: the wgpu host code. [`GpuEngine`] owns the device, the two compute
//! pipelines (`pair_times`, `next_collisions` in `shaders/kernels.wgsl`) and the buffers,
//! and reuses them across calls; buffers grow when a batch needs more.
//!
//! # Shaders
//! The shader is the concatenation of a precision prelude (`shaders/real_f32.wgsl` or
//! `shaders/real_f64.wgsl`, which define `real` and the precision constants),
//! `shaders/physics.wgsl`, `shaders/solver.wgsl` and `shaders/kernels.wgsl` — the WGSL
//! twins of `src/physics.rs`, `src/solver.rs` and the per-table loops of `src/batch.rs`.
//! f64 needs the adapter's `SHADER_F64` feature; without it, asking for f64 is an error.
//!
//! # Accuracy care on the host
//! Positions are made table-local in f64 before they are narrowed to the shader's
//! precision: each table's origin is the centre of its balls' bounding box, so an f32
//! coordinate is rounded to at most ~6e-8 m on a 9-ft table wherever the table is
//! (at ±1000 m raw f32 coordinates would be rounded to 6e-5 m). Times need no such care:
//! they count from now. Horizons are computed on the host in f64.
//!
//! # Chunking
//! A batch is cut into chunks of whole tables that fit the buffers and the adapter's
//! limits (binding size, workgroups per dimension: the dispatch is 2-D, one workgroup per
//! table); each chunk is uploaded, dispatched and read back in turn.

use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use crate::batch::{Batch, NextCollision, pair_of_index, table_paths};
use crate::error::Error;
use crate::physics::{Params, pair_horizon};
use crate::solver::{Contact, Status};

/// The floating-point precision a computation runs in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Precision {
    /// IEEE single precision (every GPU).
    F32,
    /// IEEE double precision (the CPU; GPUs whose adapter offers `SHADER_F64`).
    F64,
}

impl Precision {
    /// `f32` or `f64`.
    pub fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }

    fn real_size(self) -> usize {
        match self {
            Precision::F32 => 4,
            Precision::F64 => 8,
        }
    }
}

/// The full WGSL source for `precision`: prelude, physics, solver, kernels.
pub fn shader_source(precision: Precision) -> String {
    let prelude = match precision {
        Precision::F32 => include_str!("../shaders/real_f32.wgsl"),
        Precision::F64 => include_str!("../shaders/real_f64.wgsl"),
    };
    [
        prelude,
        include_str!("../shaders/physics.wgsl"),
        include_str!("../shaders/solver.wgsl"),
        include_str!("../shaders/kernels.wgsl"),
    ]
    .join("\n")
}

/// How large one chunk may be; [`GpuEngine::set_chunk_limits`] lowers them (for tests).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChunkLimits {
    /// Tables per chunk.
    pub tables: usize,
    /// Balls per chunk.
    pub balls: usize,
    /// Pairs per chunk.
    pub pairs: usize,
}

/// Which kernel a call runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    /// `pair_times`: every pair's answer.
    PairTimes,
    /// `next_collisions`: each table's next collision.
    NextCollisions,
}

/// The device buffers, sized for `cap` elements each.
struct Buffers {
    cap_tables: usize,
    cap_balls: usize,
    cap_out: usize,
    uniform: wgpu::Buffer,
    table_start: wgpu::Buffer,
    ball_state: wgpu::Buffer,
    ball_pv: wgpu::Buffer,
    ball_w: wgpu::Buffer,
    out_t: wgpu::Buffer,
    out_code: wgpu::Buffer,
    read_t: wgpu::Buffer,
    read_code: wgpu::Buffer,
    bind: wgpu::BindGroup,
}

/// One chunk's inputs, laid out as the shader reads them (reused across chunks).
#[derive(Default)]
struct HostArrays {
    table_start: Vec<[u32; 2]>,
    ball_state: Vec<u32>,
    ball_pv: Vec<u8>,
    ball_w: Vec<u8>,
}

/// What a GPU computation can be asked about itself.
#[derive(Clone, Debug)]
pub struct AdapterSummary {
    /// The adapter's name, e.g. "NVIDIA H100 80GB HBM3" or "llvmpipe (LLVM 15.0.6, 256 bits)".
    pub name: String,
    /// Its backend (Vulkan, Metal, Dx12).
    pub backend: String,
    /// Its device type (discrete, integrated, CPU, …).
    pub device_type: String,
    /// Its driver and driver info.
    pub driver: String,
}

impl std::fmt::Display for AdapterSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} ({}, {}, driver {})",
            self.name, self.backend, self.device_type, self.driver
        )
    }
}

/// Timings of the last call, for benchmarks: upload, kernel and readback in seconds
/// (wall clock on the host, summed over chunks).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GpuTimings {
    /// Building the host arrays and writing them to the device.
    pub upload: f64,
    /// The dispatch until the results are ready to map.
    pub kernel: f64,
    /// Mapping and converting the results.
    pub readback: f64,
}

/// A fault to inject into the next GPU call, so that tests can exercise the failure and
/// fallback paths with real wgpu errors rather than hoping for them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fault {
    /// The next dispatch asks for more workgroups than the adapter allows: wgpu rejects it
    /// with a validation error, as it would any failed dispatch.
    FailedDispatch,
    /// The device is destroyed now: every later call fails as after a device loss.
    DeviceLost,
    /// Mid-batch: after `n` more dispatches succeed, the next one fails as
    /// [`Fault::FailedDispatch`] does (chunks before it have already run).
    FailedDispatchAfter(u32),
    /// Mid-batch: after `n` more dispatches succeed, the device is destroyed.
    DeviceLostAfter(u32),
}

/// The GPU engine: device, pipelines and buffers, reused across calls.
pub struct GpuEngine {
    device: wgpu::Device,
    queue: wgpu::Queue,
    adapter: AdapterSummary,
    precision: Precision,
    layout: wgpu::BindGroupLayout,
    pipe_pairs: wgpu::ComputePipeline,
    pipe_next: wgpu::ComputePipeline,
    bufs: Option<Buffers>,
    host: HostArrays,
    limits: ChunkLimits,
    max_groups_per_dim: u32,
    lost: Arc<AtomicBool>,
    uncaptured: Arc<Mutex<Option<String>>>,
    /// A fault waiting for its dispatch: the fault, and how many dispatches run first.
    pending_fault: Option<(Fault, u32)>,
    timings: GpuTimings,
}

fn gpu_error(what: impl std::fmt::Display) -> Error {
    Error::Gpu(what.to_string())
}

/// Picks the adapter: the one whose name contains `WGPU_ADAPTER_NAME` (case-insensitive)
/// when that variable is set, else wgpu's choice for high performance. Never panics.
fn pick_adapter(instance: &wgpu::Instance) -> Result<wgpu::Adapter, Error> {
    if let Ok(wanted) = std::env::var("WGPU_ADAPTER_NAME") {
        let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
        let names: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
        return adapters
            .into_iter()
            .find(|a| {
                a.get_info()
                    .name
                    .to_lowercase()
                    .contains(&wanted.to_lowercase())
            })
            .ok_or_else(|| {
                Error::GpuUnavailable(format!(
                    "no GPU adapter matches WGPU_ADAPTER_NAME={wanted:?} (adapters found: {})",
                    if names.is_empty() {
                        "none".to_owned()
                    } else {
                        names.join(", ")
                    }
                ))
            });
    }
    let options = wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::from_env()
            .unwrap_or(wgpu::PowerPreference::HighPerformance),
        force_fallback_adapter: false,
        compatible_surface: None,
        ..Default::default()
    };
    pollster::block_on(instance.request_adapter(&options)).map_err(|e| {
        Error::GpuUnavailable(format!(
            "no GPU adapter found ({e}); install a Vulkan driver, e.g. Mesa's lavapipe \
             (Debian: libvulkan1 mesa-vulkan-drivers)"
        ))
    })
}

impl GpuEngine {
    /// Opens the GPU: adapter, device, pipelines for `precision`.
    ///
    /// Errors: [`Error::GpuUnavailable`] when there is no usable adapter, or when f64 is
    /// asked for and the adapter lacks `SHADER_F64`; [`Error::Gpu`] when the device or the
    /// shader fails to build.
    pub fn new(precision: Precision) -> Result<GpuEngine, Error> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = pick_adapter(&instance)?;
        let info = adapter.get_info();
        let summary = AdapterSummary {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend),
            device_type: format!("{:?}", info.device_type),
            driver: format!("{} {}", info.driver, info.driver_info)
                .trim()
                .to_owned(),
        };
        let mut features = wgpu::Features::empty();
        if precision == Precision::F64 {
            if !adapter.features().contains(wgpu::Features::SHADER_F64) {
                return Err(Error::GpuUnavailable(format!(
                    "the GPU adapter {} does not offer SHADER_F64, so it cannot compute in f64 \
                     (use --precision f32, or the CPU backend)",
                    summary.name
                )));
            }
            features |= wgpu::Features::SHADER_F64;
        }
        let adapter_limits = adapter.limits();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("kisstime"),
            required_features: features,
            required_limits: adapter_limits.clone(),
            ..Default::default()
        }))
        .map_err(|e| gpu_error(format!("cannot open the GPU device {}: {e}", summary.name)))?;
        let lost = Arc::new(AtomicBool::new(false));
        {
            let lost = lost.clone();
            device.set_device_lost_callback(move |_, _| lost.store(true, Ordering::SeqCst));
        }
        // wgpu's default handler panics; keep the first error instead and report it
        let uncaptured = Arc::new(Mutex::new(None));
        {
            let uncaptured = uncaptured.clone();
            device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
                if let Ok(mut slot) = uncaptured.lock() {
                    slot.get_or_insert_with(|| e.to_string());
                }
            }));
        }

        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("kisstime kernels"),
            source: wgpu::ShaderSource::Wgsl(shader_source(precision).into()),
        });
        let storage = |binding: u32, read_only: bool| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("kisstime bindings"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                storage(1, true),
                storage(2, true),
                storage(3, true),
                storage(4, true),
                storage(5, false),
                storage(6, false),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("kisstime layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = |entry: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let pipe_pairs = pipeline("pair_times");
        let pipe_next = pipeline("next_collisions");
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(gpu_error(format!(
                "the {} shader does not build on {}: {e}",
                precision.name(),
                summary.name
            )));
        }

        let binding = (adapter_limits.max_storage_buffer_binding_size as usize)
            .min(adapter_limits.max_buffer_size as usize);
        let real = precision.real_size();
        let limits = ChunkLimits {
            tables: (1 << 20).min(binding / 8 - 1),
            balls: (1 << 22).min(binding / (4 * real)),
            pairs: (1 << 24).min(binding / real),
        };
        Ok(GpuEngine {
            device,
            queue,
            adapter: summary,
            precision,
            layout,
            pipe_pairs,
            pipe_next,
            bufs: None,
            host: HostArrays::default(),
            limits,
            max_groups_per_dim: adapter_limits.max_compute_workgroups_per_dimension,
            lost,
            uncaptured,
            pending_fault: None,
            timings: GpuTimings::default(),
        })
    }

    /// The adapter in use.
    pub fn adapter(&self) -> &AdapterSummary {
        &self.adapter
    }

    /// The precision the shaders compute in.
    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// The chunk limits in force.
    pub fn chunk_limits(&self) -> ChunkLimits {
        self.limits
    }

    /// Lowers the chunk limits (each is capped at what the adapter allows), e.g. to force
    /// a batch through several chunks in tests.
    pub fn set_chunk_limits(&mut self, limits: ChunkLimits) {
        self.limits = ChunkLimits {
            tables: limits.tables.clamp(1, self.limits.tables),
            balls: limits.balls.clamp(2, self.limits.balls),
            pairs: limits.pairs.clamp(1, self.limits.pairs),
        };
    }

    /// Injects `fault` into the next call (see [`Fault`]).
    pub fn inject_fault(&mut self, fault: Fault) {
        match fault {
            Fault::FailedDispatch => self.pending_fault = Some((Fault::FailedDispatch, 0)),
            Fault::DeviceLost => self.device.destroy(),
            Fault::FailedDispatchAfter(n) => self.pending_fault = Some((Fault::FailedDispatch, n)),
            Fault::DeviceLostAfter(n) => self.pending_fault = Some((Fault::DeviceLost, n)),
        }
    }

    /// A lost device, or an error the device recorded outside any error scope since the
    /// last call (reported once).
    fn device_fault(&self) -> Option<Error> {
        if self.lost.load(Ordering::SeqCst) {
            return Some(gpu_error("the GPU device was lost"));
        }
        let mut slot = self.uncaptured.lock().ok()?;
        slot.take()
            .map(|e| gpu_error(format!("the GPU device failed: {e}")))
    }

    /// Upload, kernel and readback times of the last call.
    pub fn timings(&self) -> GpuTimings {
        self.timings
    }

    /// Cuts the tables `tables` of the batch into chunks of whole tables within the limits.
    fn plan_chunks(&self, batch: &Batch, tables: Range<usize>) -> Result<Vec<Range<usize>>, Error> {
        let mut chunks = Vec::new();
        let mut first = tables.start;
        while first < tables.end {
            let (mut balls, mut pairs, mut end) = (0, 0, first);
            while end < tables.end && end - first < self.limits.tables {
                let nb = batch.balls(end).len();
                let np = batch.pair_range(end).len();
                if balls + nb > self.limits.balls || pairs + np > self.limits.pairs {
                    break;
                }
                balls += nb;
                pairs += np;
                end += 1;
            }
            if end == first {
                return Err(gpu_error(format!(
                    "table {} has {} balls, more than one GPU dispatch can hold",
                    batch.table_id(first),
                    batch.balls(first).len()
                )));
            }
            chunks.push(first..end);
            first = end;
        }
        Ok(chunks)
    }

    /// Makes sure the buffers hold `tables`, `balls` and `out` elements.
    fn ensure_buffers(&mut self, tables: usize, balls: usize, out: usize) {
        if let Some(b) = &self.bufs
            && b.cap_tables >= tables
            && b.cap_balls >= balls
            && b.cap_out >= out
        {
            return;
        }
        let grow = |need: usize, old: usize| need.max(old + old / 2).max(64);
        let (old_t, old_b, old_o) = self
            .bufs
            .as_ref()
            .map_or((0, 0, 0), |b| (b.cap_tables, b.cap_balls, b.cap_out));
        let cap_tables = grow(tables, old_t).min(self.limits.tables.max(tables));
        let cap_balls = grow(balls, old_b).min(self.limits.balls.max(balls));
        let cap_out = grow(out, old_o).min(self.limits.pairs.max(self.limits.tables).max(out));
        let real = self.precision.real_size() as u64;
        let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
        let buffer = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(16),
                usage,
                mapped_at_creation: false,
            })
        };
        let uniform = buffer(
            "uniforms",
            64,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let table_start = buffer("table_start", 8 * (cap_tables as u64 + 1), storage);
        let ball_state = buffer("ball_state", 4 * cap_balls as u64, storage);
        let ball_pv = buffer("ball_pv", 4 * real * cap_balls as u64, storage);
        let ball_w = buffer("ball_w", 4 * real * cap_balls as u64, storage);
        let out_usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
        let out_t = buffer("out_t", real * cap_out as u64, out_usage);
        let out_code = buffer("out_code", 4 * cap_out as u64, out_usage);
        let read = wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST;
        let read_t = buffer("read_t", real * cap_out as u64, read);
        let read_code = buffer("read_code", 4 * cap_out as u64, read);
        let bind = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("kisstime bind group"),
            layout: &self.layout,
            entries: &[
                (0, &uniform),
                (1, &table_start),
                (2, &ball_state),
                (3, &ball_pv),
                (4, &ball_w),
                (5, &out_t),
                (6, &out_code),
            ]
            .map(|(binding, buf)| wgpu::BindGroupEntry {
                binding,
                resource: buf.as_entire_binding(),
            }),
        });
        self.bufs = Some(Buffers {
            cap_tables,
            cap_balls,
            cap_out,
            uniform,
            table_start,
            ball_state,
            ball_pv,
            ball_w,
            out_t,
            out_code,
            read_t,
            read_code,
            bind,
        });
    }

    /// Lays out the chunk's tables in `self.host`: table-local positions (the origin is
    /// the centre of each table's bounding box, in f64), narrowed to the shader precision.
    fn fill_host(&mut self, batch: &Batch, tables: Range<usize>) {
        let prec = self.precision;
        let h = &mut self.host;
        h.table_start.clear();
        h.ball_state.clear();
        h.ball_pv.clear();
        h.ball_w.clear();
        let push = |out: &mut Vec<u8>, v: f64| match prec {
            Precision::F32 => out.extend_from_slice(&(v as f32).to_le_bytes()),
            Precision::F64 => out.extend_from_slice(&v.to_le_bytes()),
        };
        let (mut b, mut p) = (0u32, 0u32);
        for k in tables {
            h.table_start.push([b, p]);
            let balls = batch.balls(k);
            let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
            for ball in balls {
                x0 = x0.min(ball.x);
                x1 = x1.max(ball.x);
                y0 = y0.min(ball.y);
                y1 = y1.max(ball.y);
            }
            let (ox, oy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
            for ball in balls {
                h.ball_state.push(ball.state as u32);
                for v in [ball.x - ox, ball.y - oy, ball.vx, ball.vy] {
                    push(&mut h.ball_pv, v);
                }
                for v in [ball.wx, ball.wy, ball.wz, 0.0] {
                    push(&mut h.ball_w, v);
                }
            }
            b += balls.len() as u32;
            p += batch.pair_range(k).len() as u32;
        }
        h.table_start.push([b, p]);
    }

    /// Runs `kernel` on one chunk and returns the raw `(t, code)` results.
    fn run_chunk(
        &mut self,
        batch: &Batch,
        tables: Range<usize>,
        kernel: Kernel,
        params: &Params,
    ) -> Result<(Vec<f64>, Vec<u32>), Error> {
        if let Some(e) = self.device_fault() {
            return Err(e);
        }
        let clock = std::time::Instant::now();
        let n_tables = tables.len();
        self.fill_host(batch, tables);
        let n_balls = self.host.ball_state.len();
        let n_pairs = self.host.table_start[n_tables][1] as usize;
        let n_out = match kernel {
            Kernel::PairTimes => n_pairs,
            Kernel::NextCollisions => n_tables,
        };
        self.ensure_buffers(n_tables, n_balls, n_out);
        let mut row_len = (n_tables as u32).min(self.max_groups_per_dim).max(1);
        match self.pending_fault {
            Some((fault, 0)) => {
                self.pending_fault = None;
                if fault == Fault::DeviceLost {
                    self.device.destroy();
                } else {
                    row_len = self.max_groups_per_dim.saturating_add(1);
                }
            }
            Some((fault, n)) => self.pending_fault = Some((fault, n - 1)),
            None => {}
        }
        let rows = (n_tables as u32)
            .div_ceil(row_len.min(self.max_groups_per_dim))
            .max(1);
        let mut uniform = Vec::with_capacity(64);
        for v in [params.radius, params.mu_s, params.mu_r, params.g] {
            match self.precision {
                Precision::F32 => uniform.extend_from_slice(&(v as f32).to_le_bytes()),
                Precision::F64 => uniform.extend_from_slice(&v.to_le_bytes()),
            }
        }
        uniform.extend_from_slice(&(n_tables as u32).to_le_bytes());
        uniform.extend_from_slice(&row_len.to_le_bytes());
        uniform.resize(64, 0);
        let bufs = self.bufs.as_ref().expect("buffers were just ensured");
        let q = &self.queue;
        q.write_buffer(&bufs.uniform, 0, &uniform);
        q.write_buffer(
            &bufs.table_start,
            0,
            bytemuck::cast_slice(&self.host.table_start),
        );
        q.write_buffer(
            &bufs.ball_state,
            0,
            bytemuck::cast_slice(&self.host.ball_state),
        );
        q.write_buffer(&bufs.ball_pv, 0, &self.host.ball_pv);
        q.write_buffer(&bufs.ball_w, 0, &self.host.ball_w);
        self.timings.upload += clock.elapsed().as_secs_f64();

        let clock = std::time::Instant::now();
        let real = self.precision.real_size() as u64;
        let bytes_t = (real * n_out as u64).max(4);
        let bytes_code = (4 * n_out as u64).max(4);
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("kisstime"),
            });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("kisstime"),
                timestamp_writes: None,
            });
            pass.set_pipeline(match kernel {
                Kernel::PairTimes => &self.pipe_pairs,
                Kernel::NextCollisions => &self.pipe_next,
            });
            pass.set_bind_group(0, &bufs.bind, &[]);
            pass.dispatch_workgroups(row_len, rows, 1);
        }
        encoder.copy_buffer_to_buffer(&bufs.out_t, 0, &bufs.read_t, 0, bytes_t);
        encoder.copy_buffer_to_buffer(&bufs.out_code, 0, &bufs.read_code, 0, bytes_code);
        self.queue.submit([encoder.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        for (which, buf, bytes) in [(0, &bufs.read_t, bytes_t), (1, &bufs.read_code, bytes_code)] {
            let tx = tx.clone();
            buf.slice(..bytes)
                .map_async(wgpu::MapMode::Read, move |r| drop(tx.send((which, r))));
        }
        drop(tx);
        let polled = self.device.poll(wgpu::PollType::wait_indefinitely());
        let oom = pollster::block_on(oom.pop());
        let invalid = pollster::block_on(scope.pop());
        // every map callback has run once the poll returned; leave no buffer mapped
        let mut mapped = [false, false];
        let mut map_error = None;
        for (which, r) in rx.try_iter() {
            match r {
                Ok(()) => mapped[which] = true,
                Err(e) => map_error = Some(e),
            }
        }
        let failure = if let Some(e) = oom.or(invalid) {
            Some(gpu_error(format!("the GPU dispatch failed: {e}")))
        } else if let Err(e) = polled {
            Some(gpu_error(format!("waiting for the GPU failed: {e}")))
        } else if let Some(e) = map_error {
            Some(gpu_error(format!(
                "reading results back from the GPU failed: {e}"
            )))
        } else if !(mapped[0] && mapped[1]) {
            Some(gpu_error("the GPU results never became readable"))
        } else {
            self.device_fault()
        };
        if let Some(e) = failure {
            for (buf, was_mapped) in [(&bufs.read_t, mapped[0]), (&bufs.read_code, mapped[1])] {
                if was_mapped {
                    buf.unmap();
                }
            }
            return Err(e);
        }
        self.timings.kernel += clock.elapsed().as_secs_f64();

        let clock = std::time::Instant::now();
        let t: Vec<f64> = {
            let view = bufs
                .read_t
                .slice(..bytes_t)
                .get_mapped_range()
                .map_err(|e| gpu_error(format!("reading results back from the GPU failed: {e}")))?;
            match self.precision {
                Precision::F32 => view
                    .chunks_exact(4)
                    .take(n_out)
                    .map(|c| f32::from_le_bytes(c.try_into().unwrap()) as f64)
                    .collect(),
                Precision::F64 => view
                    .chunks_exact(8)
                    .take(n_out)
                    .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                    .collect(),
            }
        };
        let code: Vec<u32> = {
            let view = bufs
                .read_code
                .slice(..bytes_code)
                .get_mapped_range()
                .map_err(|e| gpu_error(format!("reading results back from the GPU failed: {e}")))?;
            view.chunks_exact(4)
                .take(n_out)
                .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
                .collect()
        };
        bufs.read_t.unmap();
        bufs.read_code.unmap();
        self.timings.readback += clock.elapsed().as_secs_f64();
        Ok((t, code))
    }

    /// Kernel-only timing for benchmarks: uploads `batch` (which must fit one chunk), runs
    /// `kernel` once to warm up, then submits it `iters` times back to back with the data
    /// resident and returns the wall time from the first submit until the last finished.
    pub fn time_kernel(
        &mut self,
        batch: &Batch,
        params: &Params,
        kernel: Kernel,
        iters: u64,
    ) -> Result<std::time::Duration, Error> {
        let chunks = self.plan_chunks(batch, 0..batch.num_tables())?;
        if chunks.len() != 1 {
            return Err(gpu_error(format!(
                "time_kernel needs a batch that fits one chunk, this one needs {}",
                chunks.len()
            )));
        }
        let n_tables = batch.num_tables() as u32;
        self.run_chunk(batch, chunks[0].clone(), kernel, params)?;
        let row_len = n_tables.min(self.max_groups_per_dim).max(1);
        let rows = n_tables.div_ceil(row_len).max(1);
        let bufs = self.bufs.as_ref().expect("run_chunk made the buffers");
        let pipeline = match kernel {
            Kernel::PairTimes => &self.pipe_pairs,
            Kernel::NextCollisions => &self.pipe_next,
        };
        let start = std::time::Instant::now();
        for _ in 0..iters {
            let mut encoder = self
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: None,
                    timestamp_writes: None,
                });
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &bufs.bind, &[]);
                pass.dispatch_workgroups(row_len, rows, 1);
            }
            self.queue.submit([encoder.finish()]);
        }
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| gpu_error(format!("waiting for the GPU failed: {e}")))?;
        if let Some(e) = self.device_fault() {
            return Err(e);
        }
        Ok(start.elapsed())
    }

    /// The answer for every pair of every table, in pair order, as
    /// [`crate::pair_times`] gives it (times in the shader's precision; horizons in f64).
    pub fn pair_times(&mut self, batch: &Batch, params: &Params) -> Result<Vec<Contact>, Error> {
        self.pair_times_of(batch, params, 0..batch.num_tables())
    }

    /// The answers for the pairs of the tables `tables` only, as
    /// [`crate::batch::pair_times_of`] gives them.
    pub fn pair_times_of(
        &mut self,
        batch: &Batch,
        params: &Params,
        tables: Range<usize>,
    ) -> Result<Vec<Contact>, Error> {
        params.validate()?;
        self.timings = GpuTimings::default();
        let n_pairs = batch.pairs_of_tables(tables.clone()).len();
        crate::limits::check_memory(
            &format!("answering {n_pairs} pairs at once"),
            (n_pairs as u64).saturating_mul(crate::limits::BYTES_PER_PAIR),
        )?;
        let mut out = Vec::with_capacity(n_pairs);
        let mut paths = Vec::new();
        for chunk in self.plan_chunks(batch, tables)? {
            let (t, code) = self.run_chunk(batch, chunk.clone(), Kernel::PairTimes, params)?;
            let mut at = 0;
            for k in chunk {
                table_paths(batch.balls(k), params, &mut paths);
                for i in 0..paths.len() {
                    for j in i + 1..paths.len() {
                        let horizon = pair_horizon(&paths[i], &paths[j]);
                        out.push(decode_contact(t[at], code[at], horizon));
                        at += 1;
                    }
                }
            }
        }
        Ok(out)
    }

    /// The next collision of every table, in table order, as [`crate::next_collisions`]
    /// gives it (same tie rule; times in the shader's precision).
    pub fn next_collisions(
        &mut self,
        batch: &Batch,
        params: &Params,
    ) -> Result<Vec<NextCollision>, Error> {
        self.next_collisions_of(batch, params, 0..batch.num_tables())
    }

    /// The next collision of the tables `tables` only, as
    /// [`crate::batch::next_collisions_of`] gives it.
    pub fn next_collisions_of(
        &mut self,
        batch: &Batch,
        params: &Params,
        tables: Range<usize>,
    ) -> Result<Vec<NextCollision>, Error> {
        params.validate()?;
        self.timings = GpuTimings::default();
        let mut out = Vec::with_capacity(tables.len());
        for chunk in self.plan_chunks(batch, tables)? {
            let (t, code) = self.run_chunk(batch, chunk.clone(), Kernel::NextCollisions, params)?;
            for (local, k) in chunk.enumerate() {
                let status = decode_status(code[local] & 3);
                let ids = batch.ball_ids(k);
                let mut next = NextCollision::none(batch.table_id(k));
                if status != Status::None {
                    let (i, j) = pair_of_index(ids.len(), (code[local] >> 2) as usize);
                    next.t = t[local];
                    next.pair = Some((ids[i], ids[j]));
                    next.status = status;
                }
                out.push(next);
            }
        }
        Ok(out)
    }
}

fn decode_status(code: u32) -> Status {
    match code {
        1 => Status::Hit,
        2 => Status::Overlap,
        _ => Status::None,
    }
}

fn decode_contact(t: f64, code: u32, horizon: f64) -> Contact {
    match decode_status(code) {
        Status::None => Contact::none(horizon),
        Status::Hit => Contact::hit(t, horizon),
        Status::Overlap => Contact::overlap(horizon),
    }
}
