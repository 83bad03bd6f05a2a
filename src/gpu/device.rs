//! The adapter and the device, and how their failures are noticed.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use rayon::prelude::*;

use crate::error::Error;
use crate::model::Precision;

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

impl AdapterSummary {
    /// Whether it is a software (CPU-type) adapter, such as Mesa's llvmpipe (lavapipe).
    pub fn is_software(&self) -> bool {
        self.device_type == "Cpu"
    }
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

/// A GPU failure as this crate's error.
pub(super) fn gpu_error(what: impl std::fmt::Display) -> Error {
    Error::Gpu(what.to_string())
}

/// Picks the adapter: the one whose name contains `WGPU_ADAPTER_NAME` (case-insensitive)
/// when that variable is set, else wgpu's choice for high performance. Never panics.
pub(super) fn pick_adapter(instance: &wgpu::Instance) -> Result<wgpu::Adapter, Error> {
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

/// What [`open`] gives: the device and what the engine needs to know about it.
pub(super) struct Opened {
    pub(super) device: wgpu::Device,
    pub(super) queue: wgpu::Queue,
    pub(super) adapter: AdapterSummary,
    pub(super) limits: wgpu::Limits,
    pub(super) watch: DeviceWatch,
    /// Whether the device was opened with `TIMESTAMP_QUERY` (where the adapter offers it).
    pub(super) timestamps: bool,
    /// Whether the device takes SPIR-V as it is (`PASSTHROUGH_SHADERS` on Vulkan): the
    /// event loop's exact build ([`super::spirv`]).
    pub(super) spirv: bool,
}

/// Opens the adapter (see [`pick_adapter`]) and a device on it with the features that
/// `precision` needs and the adapter's own limits.
pub(super) fn open(precision: Precision) -> Result<Opened, Error> {
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
    // the device's own time of the compute passes, where the adapter can tell it
    let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
    if timestamps {
        features |= wgpu::Features::TIMESTAMP_QUERY;
    }
    // the event loop as SPIR-V without contraction (gpu::spirv), where the device is Vulkan
    let spirv = info.backend == wgpu::Backend::Vulkan
        && adapter
            .features()
            .contains(wgpu::Features::PASSTHROUGH_SHADERS);
    if spirv {
        features |= wgpu::Features::PASSTHROUGH_SHADERS;
    }
    let adapter_limits = adapter.limits();
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("kisstime"),
        required_features: features,
        required_limits: adapter_limits.clone(),
        ..Default::default()
    }))
    .map_err(|e| gpu_error(format!("cannot open the GPU device {}: {e}", summary.name)))?;
    let watch = DeviceWatch::install(&device);
    Ok(Opened {
        device,
        queue,
        adapter: summary,
        limits: adapter_limits,
        watch,
        timestamps,
        spirv,
    })
}

/// Bytes of a pass's two timestamps.
const TIMESTAMP_BYTES: u64 = 2 * wgpu::QUERY_SIZE as u64;

/// The device's own time of a compute pass: GPU timestamps written at the pass's start and
/// end (`TIMESTAMP_QUERY`), resolved and read back with the pass's results.
pub(super) struct PassTimer {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    back: wgpu::Buffer,
    /// Nanoseconds a timestamp tick.
    period_ns: f64,
}

impl PassTimer {
    /// The query set and buffers, on a device opened with `TIMESTAMP_QUERY`.
    pub(super) fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> PassTimer {
        let buffer = |label, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: TIMESTAMP_BYTES,
                usage,
                mapped_at_creation: false,
            })
        };
        PassTimer {
            set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("kisstime pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            }),
            resolve: buffer(
                "kisstime timestamps resolved",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            back: buffer(
                "kisstime timestamps readback",
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            ),
            period_ns: f64::from(queue.get_timestamp_period()),
        }
    }

    /// The pass's timestamp writes: its start in query 0, its end in query 1.
    pub(super) fn writes(&self) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: &self.set,
            beginning_of_pass_write_index: Some(0),
            end_of_pass_write_index: Some(1),
        }
    }

    /// After the pass: the timestamps resolved and copied to the readback buffer, which is
    /// returned with its length, to be mapped with the submission's other readbacks.
    pub(super) fn resolve(&self, encoder: &mut wgpu::CommandEncoder) -> (&wgpu::Buffer, u64) {
        encoder.resolve_query_set(&self.set, 0..2, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.back, 0, TIMESTAMP_BYTES);
        self.back()
    }

    /// The pass's seconds on the device, from the readback mapped after the submission
    /// that resolved them (its timestamps, in ticks; 0 if the end reads before the
    /// start); the readback is unmapped then.
    pub(super) fn seconds(&self) -> Result<f64, Error> {
        let (back, len) = self.back();
        let ticks = match back.slice(..len).get_mapped_range() {
            Ok(view) => {
                let start: u64 = bytemuck::pod_read_unaligned(&view[..8]);
                let end: u64 = bytemuck::pod_read_unaligned(&view[8..16]);
                Ok(end.saturating_sub(start))
            }
            Err(e) => Err(gpu_error(format!(
                "the GPU's timestamps are not readable: {e}"
            ))),
        };
        back.unmap();
        Ok(ticks? as f64 * self.period_ns * 1e-9)
    }

    /// The readback buffer and its length (mapped after a submission that resolved).
    pub(super) fn back(&self) -> (&wgpu::Buffer, u64) {
        (&self.back, TIMESTAMP_BYTES)
    }
}

/// Notices a lost device, and errors that the device raises outside any error scope
/// (wgpu's default handler would panic).
pub(super) struct DeviceWatch {
    lost: Arc<AtomicBool>,
    uncaptured: Arc<Mutex<Option<String>>>,
}

impl DeviceWatch {
    /// Installs the callbacks on `device`.
    fn install(device: &wgpu::Device) -> DeviceWatch {
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
        DeviceWatch { lost, uncaptured }
    }

    /// A lost device, or an error the device recorded outside any error scope since the
    /// last call (reported once).
    pub(super) fn fault(&self) -> Option<Error> {
        if self.lost.load(Ordering::SeqCst) {
            return Some(gpu_error("the GPU device was lost"));
        }
        let mut slot = self.uncaptured.lock().ok()?;
        slot.take()
            .map(|e| gpu_error(format!("the GPU device failed: {e}")))
    }
}

/// The error scopes one submission runs in: validation and out of memory (pushed by
/// [`Scopes::push`] before encoding, popped by [`map_and_wait`]).
pub(super) struct Scopes {
    invalid: wgpu::ErrorScopeGuard,
    oom: wgpu::ErrorScopeGuard,
}

impl Scopes {
    /// Pushes the scopes on `device`.
    pub(super) fn push(device: &wgpu::Device) -> Scopes {
        let invalid = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        Scopes { invalid, oom }
    }
}

/// Maps the first `len` bytes of each buffer of `buffers` for reading, waits for the
/// device, and pops `scopes`: any failure (validation or out of memory in the submission,
/// the wait, a map, a lost device or an error `watch` saw) is an error naming `what`, and
/// no buffer is left mapped then. On success every buffer is mapped; the caller reads and
/// unmaps them.
pub(super) fn map_and_wait(
    device: &wgpu::Device,
    scopes: Scopes,
    watch: &DeviceWatch,
    buffers: &[(&wgpu::Buffer, u64)],
    what: &str,
) -> Result<(), Error> {
    let (tx, rx) = std::sync::mpsc::channel();
    for (which, (buf, len)) in buffers.iter().enumerate() {
        let tx = tx.clone();
        buf.slice(..*len)
            .map_async(wgpu::MapMode::Read, move |r| drop(tx.send((which, r))));
    }
    drop(tx);
    let polled = device.poll(wgpu::PollType::wait_indefinitely());
    let oom = pollster::block_on(scopes.oom.pop());
    let invalid = pollster::block_on(scopes.invalid.pop());
    // every map callback has run once the poll returned
    let mut mapped = vec![false; buffers.len()];
    let mut map_error = None;
    for (which, r) in rx.try_iter() {
        match r {
            Ok(()) => mapped[which] = true,
            Err(e) => map_error = Some(e),
        }
    }
    let failure = if let Some(e) = oom.or(invalid) {
        Some(gpu_error(format!("{what} failed: {e}")))
    } else if let Err(e) = polled {
        Some(gpu_error(format!("waiting for the GPU failed: {e}")))
    } else if let Some(e) = map_error {
        Some(gpu_error(format!(
            "reading results back from the GPU failed: {e}"
        )))
    } else if mapped.iter().any(|m| !m) {
        Some(gpu_error("the GPU results never became readable"))
    } else {
        watch.fault()
    };
    match failure {
        Some(e) => {
            for ((buf, _), was_mapped) in buffers.iter().zip(mapped) {
                if was_mapped {
                    buf.unmap();
                }
            }
            Err(e)
        }
        None => Ok(()),
    }
}

/// A piece of a mapped upload buffer, written by one Rayon task.
struct Block<'a>(wgpu::WriteOnly<'a, [u8]>);

// SAFETY: a `WriteOnly<[u8]>` is an exclusive, write-only view of bytes, as `&mut [u8]`
// is (wgpu marks `WriteOnly<T>` Send for sized `T` only); each block is a disjoint piece
// of the mapping, written by one task while the mapping lives.
unsafe impl Send for Block<'_> {}

/// `view` cut into blocks of `size` bytes (the last one shorter).
fn split_blocks(mut view: wgpu::WriteOnly<'_, [u8]>, size: usize) -> Vec<Block<'_>> {
    let mut out = Vec::with_capacity(view.len().div_ceil(size));
    while view.len() > size {
        let (head, tail) = view.split_at(size);
        out.push(Block(head));
        view = tail;
    }
    out.push(Block(view));
    out
}

/// Copies each host array to the start of its upload buffer: maps them for writing, copies
/// in large blocks Rayon over blocks, unmaps them.
pub(super) fn copy_to_mapped(
    device: &wgpu::Device,
    pairs: &[(&wgpu::Buffer, &[u8])],
) -> Result<(), Error> {
    let sizes: Vec<(&wgpu::Buffer, u64)> =
        pairs.iter().map(|(b, h)| (*b, h.len() as u64)).collect();
    map_for_writing(device, &sizes)?;
    let mut result = Ok(());
    for (buf, host) in pairs {
        match buf.slice(..host.len() as u64).get_mapped_range_mut() {
            Ok(mut view) => {
                let blocks = split_blocks(view.slice(..), COPY_BLOCK);
                blocks
                    .into_par_iter()
                    .zip(host.par_chunks(COPY_BLOCK))
                    .for_each(|(mut dst, src)| dst.0.copy_from_slice(src));
            }
            Err(e) => {
                result = Err(gpu_error(format!(
                    "the GPU's upload buffers are not writable: {e}"
                )));
            }
        }
    }
    for (buf, _) in pairs {
        buf.unmap();
    }
    result
}

/// Bytes one Rayon task copies into mapped memory.
const COPY_BLOCK: usize = 1 << 22;

/// Maps the first `len` bytes of each buffer for writing and waits.
fn map_for_writing(device: &wgpu::Device, buffers: &[(&wgpu::Buffer, u64)]) -> Result<(), Error> {
    let (tx, rx) = std::sync::mpsc::channel();
    for (buf, len) in buffers {
        let tx = tx.clone();
        buf.slice(..*len)
            .map_async(wgpu::MapMode::Write, move |r| drop(tx.send(r)));
    }
    drop(tx);
    let polled = device.poll(wgpu::PollType::wait_indefinitely());
    let results: Vec<_> = rx.try_iter().collect();
    let failed = results
        .iter()
        .find_map(|r| r.as_ref().err().map(|e| e.to_string()));
    if polled.is_err() || failed.is_some() || results.len() != buffers.len() {
        for ((buf, _), r) in buffers.iter().zip(&results) {
            if r.is_ok() {
                buf.unmap();
            }
        }
        return Err(gpu_error(format!(
            "the GPU's upload buffers cannot be written: {}",
            failed.unwrap_or_else(|| "the device did not answer".into())
        )));
    }
    Ok(())
}
