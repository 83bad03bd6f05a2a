//! Running WGSL twins on the GPU in f64 from a test: the f64 precision prelude, the twin
//! files named (read from `shaders/`), and a test's own entry point that reads `xs` and
//! writes `ys` (both `array<real>`), dispatched in workgroups of 64.
//!
//! Without an adapter with `SHADER_F64`, [`F64Kernels::open`] prints why and returns
//! `None` (the convention of `common::gpu_or_skip`): with `KISSTIME_REQUIRE_GPU=1` (CI, on
//! Mesa's lavapipe) a missing adapter is a failure; an adapter without `SHADER_F64` is a
//! skip either way.

use std::path::Path;

use wgpu::util::DeviceExt;

/// The bindings every test entry point uses.
pub const BINDINGS: &str = "
@group(0) @binding(0) var<storage, read> xs: array<real>;
@group(0) @binding(1) var<storage, read_write> ys: array<real>;
";

/// An f64 device and queue for running test kernels.
pub struct F64Kernels {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    /// Whether pipelines are built as exact SPIR-V (`kisstime::gpu::spirv::exact_pipeline`).
    pub exact: bool,
}

/// The text of `shaders/<file>`.
pub fn shader_file(file: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("shaders")
        .join(file);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The WGSL text: the precision prelude (`"f64"` or `"f32"`), the twin `files` in order,
/// [`BINDINGS`] and `entry`.
pub fn source(precision: &str, files: &[&str], entry: &str) -> String {
    let mut parts = vec![shader_file(&format!("real_{precision}.wgsl"))];
    // the f64 prelude's transcendental functions are the polyfills
    if !files.contains(&"model/fmath.wgsl") {
        parts.push(shader_file("model/fmath.wgsl"));
    }
    parts.extend(files.iter().map(|f| shader_file(f)));
    parts.push(BINDINGS.to_owned());
    parts.push(entry.to_owned());
    parts.join("\n")
}

impl F64Kernels {
    /// A device with `SHADER_F64`, or `None` after printing why.
    pub fn open(test: &str) -> Option<F64Kernels> {
        let skip = |why: String| {
            // straight to the stderr handle: libtest captures eprintln! in passing tests
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "{test}: SKIPPED, {why}");
        };
        let required = std::env::var("KISSTIME_REQUIRE_GPU").is_ok_and(|v| v == "1");
        let adapter = kisstime::gpu::test_adapter().map_err(|e| e.to_string());
        let adapter = match adapter {
            Ok(a) => a,
            Err(why) => {
                assert!(!required, "{test}: KISSTIME_REQUIRE_GPU=1 but {why}");
                skip(why);
                return None;
            }
        };
        let info = adapter.get_info();
        if !adapter.features().contains(wgpu::Features::SHADER_F64) {
            skip(format!("the adapter {} has no SHADER_F64", info.name));
            return None;
        }
        // the kernels as exact SPIR-V (kisstime::gpu::spirv), as the event loop runs, where
        // the device takes SPIR-V (Vulkan)
        let exact = info.backend == wgpu::Backend::Vulkan
            && adapter
                .features()
                .contains(wgpu::Features::PASSTHROUGH_SHADERS);
        let mut features = wgpu::Features::SHADER_F64;
        if exact {
            features |= wgpu::Features::PASSTHROUGH_SHADERS;
        }
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some(test),
            required_features: features,
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .unwrap_or_else(|e| panic!("{test}: cannot open the device {}: {e}", info.name));
        eprintln!(
            "{test}: on {} ({:?}, driver {} {})",
            info.name, info.backend, info.driver, info.driver_info
        );
        Some(F64Kernels {
            device,
            queue,
            exact,
        })
    }

    /// The compute pipeline of `entry` in `source`; panics with the validation error if
    /// the text does not build.
    pub fn pipeline(&self, source: &str, entry: &str, what: &str) -> wgpu::ComputePipeline {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        if self.exact {
            let pipeline = kisstime::gpu::spirv::exact_pipeline(&self.device, source, entry, &[])
                .unwrap_or_else(|e| panic!("the {what} shader does not build: {e}"));
            if let Some(e) = pollster::block_on(scope.pop()) {
                panic!("the {what} shader does not build: {e}");
            }
            return pipeline;
        }
        let module = self
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(what),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
        let pipeline = self
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(what),
                layout: None,
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            });
        if let Some(e) = pollster::block_on(scope.pop()) {
            panic!("the {what} shader does not build: {e}");
        }
        pipeline
    }

    /// Runs the f64 `pipeline` with `invocations` threads on `xs`; returns `n_out` values
    /// of `ys` (zero where the kernel wrote nothing).
    pub fn run(
        &self,
        pipeline: &wgpu::ComputePipeline,
        xs: &[f64],
        n_out: usize,
        invocations: usize,
    ) -> Vec<f64> {
        let device = &self.device;
        let out_bytes = (n_out.max(1) * 8) as u64;
        let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("xs"),
            contents: bytemuck::cast_slice(if xs.is_empty() { &[0.0] } else { xs }),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let output = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("ys"),
            contents: bytemuck::cast_slice(&vec![0.0f64; n_out.max(1)]),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: out_bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("test kernel"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: input.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: output.as_entire_binding(),
                },
            ],
        });
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: None,
                timestamp_writes: None,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(invocations.div_ceil(64).max(1) as u32, 1, 1);
        }
        encoder.copy_buffer_to_buffer(&output, 0, &readback, 0, out_bytes);
        self.queue.submit([encoder.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        readback
            .slice(..)
            .map_async(wgpu::MapMode::Read, move |r| drop(tx.send(r)));
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .expect("the GPU finishes");
        rx.recv()
            .expect("the map callback ran")
            .expect("the results map");
        let ys: Vec<f64> = {
            let view = readback
                .slice(..)
                .get_mapped_range()
                .expect("the mapped results are readable");
            view.chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                .collect()
        };
        readback.unmap();
        ys[..n_out].to_vec()
    }
}

/// `|a − b| ≤ atol + rtol·max(|a|, |b|)`.
pub fn close(a: f64, b: f64, rtol: f64, atol: f64) -> bool {
    (a - b).abs() <= atol + rtol * a.abs().max(b.abs())
}
