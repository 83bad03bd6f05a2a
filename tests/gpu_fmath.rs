//! The WGSL polyfills (`shaders/model/fmath.wgsl`) run on the GPU in f64 and compared with
//! their Rust twins (`src/model/fmath.rs`) bit for bit, on 16k arguments per function
//! over the ranges the physics uses and the hard places (near multiples of π/2, near ±1
//! for acos, subnormal results for exp). The shader is the f64 prelude, the polyfill file
//! and a small entry point of this test; the same text is also built with the f32
//! prelude, to check that it compiles there too.
//!
//! # Exact SPIR-V
//! The twins compute `a·b + c` as a product and a sum (`mad`), never fused. On Vulkan the
//! kernels are built as the event loop is, SPIR-V with every float operation marked
//! `NoContraction` (`kisstime::gpu::spirv`), so the driver may neither fuse nor
//! re-associate: there the polyfills must give the Rust bits exactly, and a probe checks
//! that `a * b + c` is not contracted. Elsewhere (WGSL as wgpu compiles it, which a driver
//! may contract) they must stay within [`CONTRACTED_ULPS`] of them.

//! Without a GPU this test prints why it skips (`common::kernel`): with
//! `KISSTIME_REQUIRE_GPU=1` (CI, on Mesa's lavapipe) a missing adapter is a failure; an
//! adapter without `SHADER_F64` is a skip either way.
//!
//! Bit equality also needs IEEE f64 `+ − ×` (and, for acos, `/` and `sqrt`) with
//! subnormals kept; the test names the first arguments that differ. Non-finite arguments
//! and results (NaN, ±∞) are printed, not asserted: WGSL promises nothing about them.

use std::f64::consts::{FRAC_PI_2, PI};

use kisstime::model::fmath::{TRIG_BOUND, acos_poly, cos_poly, exp_poly, sin_poly};
mod common;

use common::kernel::F64Kernels;
use common::rng::TestRng;
use common::ulps;

const PRELUDE_F64: &str = include_str!("../shaders/real_f64.wgsl");
const PRELUDE_F32: &str = include_str!("../shaders/real_f32.wgsl");
const FMATH: &str = include_str!("../shaders/model/fmath.wgsl");

/// The test's entry points: `fmath_main` reads the arguments of the four functions
/// interleaved in `xs` (exp, sin, cos, acos) and writes their results in the same places;
/// `fma_probe` tells a fused `fma` builtin and a contracted `a * b + c` from rounded ones.
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

/// How far from the Rust twin (in ulps) the polyfills may land where the driver may
/// contract and re-associate (not on Vulkan: there they must be exact).
const CONTRACTED_ULPS: u64 = 2;

const NAMES: [&str; 4] = ["exp", "sin", "cos", "acos"];

fn rust_twin(which: usize, x: f64) -> f64 {
    match which {
        0 => exp_poly(x),
        1 => sin_poly(x),
        2 => cos_poly(x),
        _ => acos_poly(x),
    }
}

/// The WGSL text: `prelude`, the polyfills, the entry points.
fn shader(prelude: &str) -> String {
    [prelude, FMATH, ENTRY].join("\n")
}

/// Runs the f64 pipeline on `xs` (interleaved as the entry point reads them, four
/// arguments per invocation).
fn run_f64(k: &F64Kernels, pipeline: &wgpu::ComputePipeline, xs: &[f64]) -> Vec<f64> {
    k.run(pipeline, xs, xs.len(), xs.len().div_ceil(4))
}

/// `n` ulps above `x` (for x > 0).
fn up(x: f64, n: u64) -> f64 {
    f64::from_bits(x.to_bits() + n)
}

/// The arguments of each function: the physics' ranges and the hard places, `per` each.
fn arguments(per: usize) -> [Vec<f64>; 4] {
    let mut rng = TestRng::new(0x6F3A);
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
    gpu: (&F64Kernels, &wgpu::ComputePipeline),
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
    let ys = run_f64(gpu.0, gpu.1, &xs);
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
    let Some(k) = F64Kernels::open(name) else {
        return;
    };
    // the same text builds in the f32 shader (it is not run there)
    k.pipeline(&shader(PRELUDE_F32), "fmath_main", "f32 polyfill");
    let source = shader(PRELUDE_F64);
    let main = k.pipeline(&source, "fmath_main", "f64 polyfill");

    // does the device fuse the fma builtin, and does it contract a * b + c? (a² − (1 + 2⁻²⁹)
    // is 2⁻⁶⁰ exactly, and 0 when a² is rounded first)
    let probe = k.pipeline(&source, "fma_probe", "fma probe");
    let a = 1.0 + 2f64.powi(-30);
    let p = run_f64(&k, &probe, &[a, a, -(1.0 + 2f64.powi(-29)), 0.0]);
    let contracted = p[1] != 0.0;
    println!(
        "{name}: the fma builtin is {}; a * b + c is {} ({})",
        if p[0] != 0.0 {
            "fused"
        } else {
            "rounded twice"
        },
        if contracted {
            "contracted"
        } else {
            "not contracted"
        },
        if k.exact {
            "exact SPIR-V"
        } else {
            "WGSL as wgpu compiles it"
        }
    );
    if k.exact {
        assert!(
            !contracted,
            "{name}: NoContraction did not hold on the device"
        );
    }

    let mut problems = Vec::new();
    let worst = compare((&k, &main), &arguments(16384), &mut problems);
    if !k.exact {
        // a driver free to contract: within the bound, not bit for bit
        problems.clear();
        for (which, w) in worst.iter().enumerate() {
            if *w > CONTRACTED_ULPS {
                problems.push(format!(
                    "{}: {w} ulp from the Rust twin (> {CONTRACTED_ULPS})",
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
    let sy = run_f64(&k, &main, &sx);
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
