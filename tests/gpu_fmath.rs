//! The WGSL polyfills (`shaders/model/fmath.wgsl`) run on the GPU in f64 and compared with
//! their Rust twins (`src/model/fmath.rs`) bit for bit, on 16k arguments per function
//! over the ranges the physics uses and the hard places (near multiples of π/2, near ±1
//! for acos, subnormal results for exp). The shader is the f64 prelude, the polyfill file
//! and a small entry point of this test; the same text is also built with the f32
//! prelude, to check that it compiles there too.
//!
//! # Fused or not
//! The twins use `fma` wherever a product feeds a sum, so that a compiler that contracts
//! `a * b + c` cannot change a bit. That gives the Rust twin's bits where the device's f64
//! `fma` is fused, as on GPUs with a hardware f64 FMA. Vulkan does not promise it (its
//! `fma` may round the product and the sum separately), and Mesa's lavapipe (22.3) does
//! exactly that; its compiler also rewrites sums as if they were exact (naga asks for no
//! float controls), so compensation terms such as TwoSum's errors do not survive there.
//! So a probe asks the device first, and:
//! - with a fused `fma`, the polyfills must give the Rust bits exactly;
//! - with a separately rounded one, they must stay within [`UNFUSED_ULPS`] of them (what
//!   that costs, measured on lavapipe: exp and acos 1 ulp, sin and cos 2).
//!
//! Without a GPU this test prints why it skips, as `common::gpu_or_skip` does: with
//! `KISSTIME_REQUIRE_GPU=1` (CI, on Mesa's lavapipe) a missing adapter is a failure; an
//! adapter without `SHADER_F64` is a skip either way.
//!
//! Bit equality also needs IEEE f64 `+ − ×` (and, for acos, `/` and `sqrt`) with
//! subnormals kept; the test names the first arguments that differ. Non-finite arguments
//! and results (NaN, ±∞) are printed, not asserted: WGSL promises nothing about them.

use std::f64::consts::{FRAC_PI_2, PI};

use kisstime::model::fmath::{TRIG_BOUND, acos_poly, cos_poly, exp_poly, sin_poly};
use wgpu::util::DeviceExt;

const PRELUDE_F64: &str = include_str!("../shaders/real_f64.wgsl");
const PRELUDE_F32: &str = include_str!("../shaders/real_f32.wgsl");
const FMATH: &str = include_str!("../shaders/model/fmath.wgsl");

/// The test's entry points: `fmath_main` reads the arguments of the four functions
/// interleaved in `xs` (exp, sin, cos, acos) and writes their results in the same places;
/// `fma_probe` tells a fused `fma` and a contracted `a * b + c` from rounded ones.
const ENTRY: &str = r#"
@group(0) @binding(0) var<storage, read> xs: array<real>;
@group(0) @binding(1) var<storage, read_write> ys: array<real>;

@compute @workgroup_size(64)
fn fmath_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&xs) / 4u {
        return;
    }
    ys[4u * i] = exp_poly(xs[4u * i]);
    ys[4u * i + 1u] = sin_poly(xs[4u * i + 1u]);
    ys[4u * i + 2u] = cos_poly(xs[4u * i + 2u]);
    ys[4u * i + 3u] = acos_poly(xs[4u * i + 3u]);
}

@compute @workgroup_size(1)
fn fma_probe() {
    ys[0] = fma(xs[0], xs[1], xs[2]);
    ys[1] = xs[0] * xs[1] + xs[2];
}
"#;

/// How far from the Rust twin (in ulps) the polyfills may land where `fma` rounds the
/// product and the sum separately (lavapipe: exp and acos 1, sin and cos 2).
const UNFUSED_ULPS: u64 = 2;

const NAMES: [&str; 4] = ["exp", "sin", "cos", "acos"];

fn rust_twin(which: usize, x: f64) -> f64 {
    match which {
        0 => exp_poly(x),
        1 => sin_poly(x),
        2 => cos_poly(x),
        _ => acos_poly(x),
    }
}

/// A device with `SHADER_F64`, or `None` after printing why (the convention of
/// `common::gpu_or_skip`: no adapter fails under `KISSTIME_REQUIRE_GPU=1`).
fn f64_device_or_skip(test: &str) -> Option<(wgpu::Device, wgpu::Queue)> {
    let skip = |why: String| {
        // straight to the stderr handle: libtest captures eprintln! in passing tests
        use std::io::Write;
        let _ = writeln!(std::io::stderr(), "{test}: SKIPPED, {why}");
    };
    let required = std::env::var("KISSTIME_REQUIRE_GPU").is_ok_and(|v| v == "1");
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = match std::env::var("WGPU_ADAPTER_NAME") {
        Ok(wanted) => pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()))
            .into_iter()
            .find(|a| {
                a.get_info()
                    .name
                    .to_lowercase()
                    .contains(&wanted.to_lowercase())
            })
            .ok_or_else(|| format!("no GPU adapter matches WGPU_ADAPTER_NAME={wanted:?}")),
        Err(_) => pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        }))
        .map_err(|e| format!("no GPU adapter found ({e})")),
    };
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
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("fmath test"),
        required_features: wgpu::Features::SHADER_F64,
        required_limits: adapter.limits(),
        ..Default::default()
    }))
    .unwrap_or_else(|e| panic!("{test}: cannot open the device {}: {e}", info.name));
    eprintln!(
        "{test}: on {} ({:?}, driver {} {})",
        info.name, info.backend, info.driver, info.driver_info
    );
    Some((device, queue))
}

/// The WGSL text: `prelude`, the polyfills, the entry points.
fn shader(prelude: &str) -> String {
    [prelude, FMATH, ENTRY].join("\n")
}

/// The compute pipeline of `entry` in `source`; panics with the validation error if the
/// text does not build.
fn pipeline(device: &wgpu::Device, source: &str, entry: &str, what: &str) -> wgpu::ComputePipeline {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(what),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
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

/// Runs the f64 pipeline on `xs` (interleaved as the entry point reads them).
fn run_f64(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    pipeline: &wgpu::ComputePipeline,
    xs: &[f64],
) -> Vec<f64> {
    let bytes = std::mem::size_of_val(xs) as u64;
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("xs"),
        contents: bytemuck::cast_slice(xs),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("ys"),
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: bytes,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("fmath"),
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
        pass.dispatch_workgroups((xs.len() / 4).div_ceil(64) as u32, 1, 1);
    }
    encoder.copy_buffer_to_buffer(&output, 0, &readback, 0, bytes);
    queue.submit([encoder.finish()]);
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
    let ys = {
        let view = readback
            .slice(..)
            .get_mapped_range()
            .expect("the mapped results are readable");
        view.chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
            .collect()
    };
    readback.unmap();
    ys
}

/// splitmix64, for a fixed set of arguments.
struct Rng(u64);

impl Rng {
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

/// How many doubles apart `a` and `b` are (0 when both are NaN).
fn ulps(a: f64, b: f64) -> u64 {
    let ordinal = |x: f64| {
        let bits = x.to_bits() as i64;
        if bits < 0 { -(bits & i64::MAX) } else { bits }
    };
    match (a.is_nan(), b.is_nan()) {
        (true, true) => 0,
        (false, false) => (ordinal(a) - ordinal(b)).unsigned_abs(),
        _ => u64::MAX,
    }
}

/// `n` ulps above `x` (for x > 0).
fn up(x: f64, n: u64) -> f64 {
    f64::from_bits(x.to_bits() + n)
}

/// The arguments of each function: the physics' ranges and the hard places, `per` each.
fn arguments(per: usize) -> [Vec<f64>; 4] {
    let mut rng = Rng(0x6F3A);
    let mut exp = vec![
        0.0, -0.0, 1.0, -1.0, 1e-300, -1e-20, -745.0, -708.4, -746.5, -800.0,
    ];
    while exp.len() < per {
        let x = match exp.len() % 8 {
            0..=3 => rng.range(-745.0, 0.0),
            4 => rng.range(-1.0, 1.0),
            5 => rng.range(0.0, 709.7),
            6 => rng.range(-745.13, -708.0),
            _ => (rng.range(-1075.0, 1024.0).floor() + 0.5) * std::f64::consts::LN_2,
        };
        exp.push(x);
    }
    let mut trig = vec![0.0, -0.0, 1e-10, FRAC_PI_2, PI, -PI, 2.0 * PI, TRIG_BOUND];
    while trig.len() < per {
        let x = match trig.len() % 6 {
            0 | 1 => rng.range(-2.0 * PI, 2.0 * PI),
            2 => rng.range(-1e4, 1e4),
            3 => up(
                (rng.range(1.0, 2e4).floor()) * FRAC_PI_2,
                trig.len() as u64 % 5,
            ),
            4 => -up(
                (rng.range(1.0, 5e5).floor()) * FRAC_PI_2,
                trig.len() as u64 % 3,
            ),
            _ => rng.range(-TRIG_BOUND, TRIG_BOUND),
        };
        trig.push(x);
    }
    let mut acos = vec![1.0, -1.0, 0.0, -0.0, 0.5, -0.5, up(0.5, 1), -up(0.5, 1)];
    while acos.len() < per {
        let x = match acos.len() % 4 {
            0 | 1 => rng.range(-1.0, 1.0),
            2 => 1.0 - 10f64.powf(rng.range(-16.0, -0.3)),
            _ => -1.0 + 10f64.powf(rng.range(-16.0, -0.3)),
        };
        acos.push(x);
    }
    let mut cos = trig.clone();
    cos.reverse();
    [exp, trig, cos, acos]
}

/// Runs `pipeline` on the interleaved `args` and compares with the Rust twins: the
/// largest distance in ulps per function (and from the standard library), and the first
/// differing arguments in `problems`.
fn compare(
    gpu: (&wgpu::Device, &wgpu::Queue, &wgpu::ComputePipeline),
    args: &[Vec<f64>; 4],
    problems: &mut Vec<String>,
) -> [u64; 4] {
    let per = args[0].len();
    let mut xs = vec![0.0; 4 * per];
    for (which, a) in args.iter().enumerate() {
        assert_eq!(a.len(), per);
        for (i, &x) in a.iter().enumerate() {
            xs[4 * i + which] = x;
        }
    }
    let ys = run_f64(gpu.0, gpu.1, gpu.2, &xs);
    assert_eq!(ys.len(), xs.len());
    let std_fn: [fn(f64) -> f64; 4] = [f64::exp, f64::sin, f64::cos, f64::acos];
    let mut worst = [0; 4];
    for (which, fname) in NAMES.iter().enumerate() {
        let (mut differ, mut max_std) = (0, 0);
        for i in 0..per {
            let x = xs[4 * i + which];
            let (g, cpu) = (ys[4 * i + which], rust_twin(which, x));
            assert!(cpu.is_finite(), "{fname}({x:e}) is finite on the CPU");
            worst[which] = worst[which].max(ulps(g, cpu));
            max_std = max_std.max(ulps(g, std_fn[which](x)));
            if g.to_bits() != cpu.to_bits() {
                differ += 1;
                if problems.len() < 20 {
                    problems.push(format!(
                        "{fname}({x:e} = {:#018x}): GPU {g:e} ({:#018x}), Rust {cpu:e} ({:#018x})",
                        x.to_bits(),
                        g.to_bits(),
                        cpu.to_bits()
                    ));
                }
            }
        }
        println!(
            "gpu_fmath: {fname}: {per} arguments, {differ} differ from the Rust twin \
             (at most {} ulp), at most {max_std} ulp from std",
            worst[which]
        );
    }
    worst
}

#[test]
fn wgsl_polyfills_match_their_rust_twins() {
    let name = "gpu_fmath";
    let Some((device, queue)) = f64_device_or_skip(name) else {
        return;
    };
    // the same text builds in the f32 shader (it is not run there)
    pipeline(&device, &shader(PRELUDE_F32), "fmath_main", "f32 polyfill");
    let source = shader(PRELUDE_F64);
    let main = pipeline(&device, &source, "fmath_main", "f64 polyfill");

    // does the device fuse fma, and does it contract a * b + c? (a² − (1 + 2⁻²⁹) is
    // 2⁻⁶⁰ exactly, and 0 when a² is rounded first)
    let probe = pipeline(&device, &source, "fma_probe", "fma probe");
    let a = 1.0 + 2f64.powi(-30);
    let p = run_f64(
        &device,
        &queue,
        &probe,
        &[a, a, -(1.0 + 2f64.powi(-29)), 0.0],
    );
    let fused = p[0] != 0.0;
    println!(
        "{name}: fma is {}; a * b + c is {}",
        if fused { "fused" } else { "rounded twice" },
        if p[1] != 0.0 {
            "contracted"
        } else {
            "not contracted"
        }
    );

    let mut problems = Vec::new();
    let worst = compare((&device, &queue, &main), &arguments(16384), &mut problems);
    if !fused {
        // separately rounded: within the bound, not bit for bit
        problems.clear();
        for (which, w) in worst.iter().enumerate() {
            if *w > UNFUSED_ULPS {
                problems.push(format!(
                    "{}: {w} ulp from the Rust twin with an fma rounded twice (> {UNFUSED_ULPS})",
                    NAMES[which]
                ));
            }
        }
    }

    // non-finite arguments and results: reported, not asserted
    let specials = [
        (0, f64::NAN),
        (0, f64::INFINITY),
        (0, f64::NEG_INFINITY),
        (0, 710.0),
        (1, f64::NAN),
        (1, f64::INFINITY),
        (1, 1e6),
        (2, f64::NEG_INFINITY),
        (3, f64::NAN),
        (3, up(1.0, 1)),
        (3, -2.0),
    ];
    let mut sx = vec![0.0; 4 * specials.len()];
    for (i, &(which, x)) in specials.iter().enumerate() {
        sx[4 * i + which] = x;
    }
    let sy = run_f64(&device, &queue, &main, &sx);
    for (i, &(which, x)) in specials.iter().enumerate() {
        let (gpu, cpu) = (sy[4 * i + which], rust_twin(which, x));
        let same = gpu.to_bits() == cpu.to_bits() || (gpu.is_nan() && cpu.is_nan());
        println!(
            "{name}: {}({x:e}): GPU {gpu:e}, Rust {cpu:e}{}",
            NAMES[which],
            if same { "" } else { "  (differs)" }
        );
    }

    assert!(
        problems.is_empty(),
        "the GPU differs from the Rust twins (first {}):\n{}",
        problems.len(),
        problems.join("\n")
    );
}
