//! The GPU backend: the wgpu host code. [`GpuEngine`] owns the device, the two compute
//! pipelines (`pair_times`, `next_collisions` in `shaders/kernels.wgsl`) and the buffers,
//! and reuses them across calls; buffers grow when a batch needs more.
//!
//! Where things are:
//! - [`shader`]: the WGSL source, assembled from the twins in `shaders/`;
//! - `device`: the adapter and device, and how their failures are noticed;
//! - `pipelines`: the bind-group layout and the two compute pipelines;
//! - `buffers`: the device buffers and the host arrays laid out as the shader reads them;
//! - `dispatch`: chunking, one chunk's upload, dispatch and readback, kernel timing;
//! - `simulate`, `sim_layout`: the event loop's host ([`GpuSimulator`]) and its storage
//!   layout;
//! - [`spirv`]: the event loop as SPIR-V the driver may not contract (the GPU's f64 bit
//!   for bit the CPU's);
//! - here: [`GpuEngine`]'s public calls, which turn the raw results into answers.
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
//! table, or per [`TABLES_PER_GROUP`] tables in the event loop); each chunk is uploaded,
//! dispatched and read back in turn.

use std::ops::Range;

use rayon::prelude::*;

use crate::batch::{Batch, NextCollision, pair_of_index, pairs};
use crate::cpu::kernels::table_paths;
use crate::error::Error;
use crate::model::{Params, Precision};
use crate::motion::path::pair_horizon;
use crate::query::ball_ball::{Contact, Status};

mod buffers;
mod device;
mod dispatch;
#[cfg(feature = "testing")]
mod fault;
mod pipelines;
pub mod shader;
mod sim_layout;
mod simulate;
pub mod spirv;

pub use device::AdapterSummary;
pub use dispatch::Kernel;
#[cfg(feature = "testing")]
pub use fault::{Fault, adapter as test_adapter};
pub use shader::{GPU_MAX_BALLS_LINE, shader_source};
#[doc(hidden)]
pub use sim_layout::{GPU_BALL_BUCKETS, GPU_MAX_BALLS, GpuRun, GpuShot, SimLayout, WatchedRun};
#[doc(hidden)]
pub use simulate::event_loop_constants;
pub use simulate::{
    CheckedTables, EVENT_LOOP_THREADS, EVENTS_PER_DISPATCH, FillTable, GpuOutput, GpuSimulator,
    MAX_TABLES_PER_CHUNK, OnEvent, PIPELINE_CHUNKS, PIPELINE_MIN_TABLES, ROW_THREADS,
    TABLES_PER_GROUP,
};

/// How large one chunk may be (tests can lower them with `set_chunk_limits`, a hook of the
/// `testing` feature).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChunkLimits {
    /// Tables per chunk.
    pub tables: usize,
    /// Balls per chunk.
    pub balls: usize,
    /// Pairs per chunk.
    pub pairs: usize,
}

/// Timings of the last call, for benchmarks: host packing, upload, kernel, readback and
/// host unpacking in seconds (wall clock on the host, summed over chunks). The event loop
/// packs a chunk and unpacks the one before while the device runs a chunk
/// ([`PIPELINE_CHUNKS`]): that time, `overlapped`, is in `pack` and `unpack`
/// too, so the phases add up to more than the call's wall time by about `overlapped`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GpuTimings {
    /// Checking the input and laying it out as the shader reads it, on the host (the
    /// kernels' engine counts this in `upload`).
    pub pack: f64,
    /// Writing the host arrays to the device, waited for.
    pub upload: f64,
    /// The dispatches until the results are ready to copy.
    pub kernel: f64,
    /// Copying the results to mappable memory and mapping them.
    pub readback: f64,
    /// Converting the mapped results into answers, on the host (the kernels' engine
    /// counts this in `readback`).
    pub unpack: f64,
    /// The part of `pack` and `unpack` done on the host while the device ran a chunk.
    pub overlapped: f64,
    /// The event loop's compute passes timed on the device itself (GPU timestamps at each
    /// pass's start and end), where the adapter has timestamps (`None` elsewhere): `kernel`
    /// less this is the host's waiting, the launches and, in the event loop, the "tables
    /// still running" readbacks between dispatches.
    pub kernel_device: Option<f64>,
    /// The part of `kernel` spent in the event loop's dispatches that ran fewer than a
    /// sixteenth of their chunk's tables: the long tail of the few tables with many events,
    /// while most of the device waits (what the next chunk's tables could fill).
    pub kernel_tail: f64,
    /// How many such dispatches ran (of the call's [`GpuSimulator::dispatches`]).
    pub tail_dispatches: u64,
}

impl GpuTimings {
    /// Adds `other`'s phases to these.
    pub fn add(&mut self, other: &GpuTimings) {
        self.pack += other.pack;
        self.upload += other.upload;
        self.kernel += other.kernel;
        self.readback += other.readback;
        self.unpack += other.unpack;
        self.overlapped += other.overlapped;
        self.kernel_tail += other.kernel_tail;
        self.tail_dispatches += other.tail_dispatches;
        if let Some(d) = other.kernel_device {
            *self.kernel_device.get_or_insert(0.0) += d;
        }
    }

    /// One line: each phase in seconds.
    pub fn describe(&self) -> String {
        let device = match self.kernel_device {
            Some(d) => format!(" ({d:.3} s on the device's clock)"),
            None => String::new(),
        };
        let tail = match self.tail_dispatches {
            0 => String::new(),
            n => format!(
                " ({:.3} s of it in {n} dispatch{} of under a sixteenth of the tables)",
                self.kernel_tail,
                if n == 1 { "" } else { "es" }
            ),
        };
        format!(
            "pack {:.3} s, upload {:.3} s, kernel {:.3} s{device}{tail}, readback {:.3} s, \
             unpack {:.3} s ({:.3} s of packing and unpacking while the kernel ran)",
            self.pack, self.upload, self.kernel, self.readback, self.unpack, self.overlapped
        )
    }
}

/// The GPU engine: device, pipelines and buffers, reused across calls.
pub struct GpuEngine {
    device: wgpu::Device,
    queue: wgpu::Queue,
    adapter: AdapterSummary,
    precision: Precision,
    pipelines: pipelines::Pipelines,
    bufs: Option<buffers::Buffers>,
    host: buffers::HostArrays,
    limits: ChunkLimits,
    max_groups_per_dim: u32,
    watch: device::DeviceWatch,
    /// A fault waiting for its dispatch: the fault, and how many dispatches run first.
    #[cfg(feature = "testing")]
    pending_fault: Option<(Fault, u32)>,
    timings: GpuTimings,
    /// The kernels' passes timed on the device, where the adapter has timestamps.
    timer: Option<device::PassTimer>,
}

impl GpuEngine {
    /// Opens the GPU: adapter, device, pipelines for `precision`.
    ///
    /// Errors: [`Error::GpuUnavailable`] when there is no usable adapter, or when f64 is
    /// asked for and the adapter lacks `SHADER_F64`; [`Error::Gpu`] when the device or the
    /// shader fails to build.
    pub fn new(precision: Precision) -> Result<GpuEngine, Error> {
        let opened = device::open(precision)?;
        let pipelines = pipelines::Pipelines::build(&opened.device, precision, &opened.adapter)?;
        let adapter_limits = &opened.limits;
        let binding = (adapter_limits.max_storage_buffer_binding_size as usize)
            .min(adapter_limits.max_buffer_size as usize);
        let real = precision.real_size();
        let limits = ChunkLimits {
            tables: (1 << 20).min(binding / 8 - 1),
            balls: (1 << 22).min(binding / (4 * real)),
            pairs: (1 << 24).min(binding / real),
        };
        Ok(GpuEngine {
            max_groups_per_dim: adapter_limits.max_compute_workgroups_per_dimension,
            adapter: opened.adapter,
            precision,
            pipelines,
            bufs: None,
            host: buffers::HostArrays::default(),
            limits,
            timer: opened
                .timestamps
                .then(|| device::PassTimer::new(&opened.device, &opened.queue)),
            device: opened.device,
            queue: opened.queue,
            watch: opened.watch,
            #[cfg(feature = "testing")]
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

    /// Upload, kernel and readback times of the last call.
    pub fn timings(&self) -> GpuTimings {
        self.timings
    }

    /// The answer for every pair of every table, in pair order, as
    /// [`crate::pair_times`] gives it (times in the shader's precision; horizons in f64).
    pub fn pair_times(&mut self, batch: &Batch, params: &Params) -> Result<Vec<Contact>, Error> {
        self.pair_times_of(batch, params, 0..batch.num_tables())
    }

    /// The answers for the pairs of the tables `tables` only, as
    /// [`crate::pair_times_of`] gives them.
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
        for chunk in self.plan_chunks(batch, tables)? {
            let (t, code) = self.run_chunk(batch, chunk.clone(), Kernel::PairTimes, params)?;
            // the answers with their horizons (in f64 on the host), Rayon over blocks
            let first_pair = batch.pair_range(chunk.start).start;
            let blocks: Vec<Range<usize>> = (chunk.start..chunk.end)
                .step_by(DECODE_BLOCK)
                .map(|k| k..chunk.end.min(k + DECODE_BLOCK))
                .collect();
            let decoded: Vec<Vec<Contact>> = blocks
                .into_par_iter()
                .map(|block| {
                    let mut paths = Vec::new();
                    let mut part = Vec::new();
                    for k in block {
                        table_paths(batch.balls(k), params, &mut paths);
                        let from = batch.pair_range(k).start - first_pair;
                        for (at, (i, j)) in (from..).zip(pairs(paths.len())) {
                            let horizon = pair_horizon(&paths[i], &paths[j]);
                            part.push(decode_contact(t[at], code[at], horizon));
                        }
                    }
                    part
                })
                .collect();
            for part in decoded {
                out.extend(part);
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
    /// [`crate::next_collisions_of`] gives it.
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
            let first = chunk.start;
            let decoded: Vec<NextCollision> = chunk
                .into_par_iter()
                .with_min_len(DECODE_BLOCK)
                .map_init(Vec::new, |paths, k| {
                    let local = k - first;
                    let status = decode_status(code[local] & 3);
                    let ids = batch.ball_ids(k);
                    let mut next = NextCollision::none(batch.table_id(k));
                    // the horizon on the host, in f64, as for per-pair answers
                    table_paths(batch.balls(k), params, paths);
                    next.horizon = paths.iter().map(|p| p.tmax).fold(f64::INFINITY, f64::min);
                    if status != Status::None {
                        let (i, j) = pair_of_index(ids.len(), (code[local] >> 2) as usize);
                        next.t = t[local];
                        next.pair = Some((ids[i], ids[j]));
                        next.status = status;
                    }
                    next
                })
                .collect();
            out.extend(decoded);
        }
        Ok(out)
    }
}

/// Tables decoded by one Rayon task.
const DECODE_BLOCK: usize = 512;

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
