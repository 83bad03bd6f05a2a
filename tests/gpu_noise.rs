//! The study's strike on the GPU: the WGSL twins of the cue noise
//! (`shaders/study/philox.wgsl`, `shaders/study/noise.wgsl`), of the strike
//! (`shaders/resolve/stick_ball.wgsl`) and of the functions they use from
//! `shaders/model/fmath.wgsl` (`ln`, the normal quantile, `atan`, `atan2`) run on the GPU
//! in f64 and compared with their Rust twins (`src/study/philox.rs`,
//! `src/study/noise.rs`, `src/resolve/stick_ball.rs`, `src/model/fmath.rs`) bit for bit:
//! Philox on Random123's known answers and on random counters and keys; `ln`, Φ⁻¹,
//! `atan` and `atan2` over their ranges; the noisy strikes of whole studies (the rim case
//! included) and the cue ball each one strikes. The same text also builds with the f32
//! prelude.
//!
//! On Vulkan the kernels are exact SPIR-V (every float operation `NoContraction`) and must
//! give the Rust bits; elsewhere (WGSL as wgpu compiles it, which a driver may contract)
//! the integers must still be exact and the floats within [`CONTRACTED_ULPS`].
//!
//! Without a GPU this test prints why it skips (`common::kernel`): with
//! `KISSTIME_REQUIRE_GPU=1` (CI, on Mesa's lavapipe) a missing adapter is a failure; an
//! adapter without `SHADER_F64` is a skip either way.

mod common;

use common::kernel::{F64Kernels, source};
use common::rng::TestRng;
use common::ulps;
use kisstime::model::fmath::{atan_poly, atan2_poly, log_poly, normal_quantile};
use kisstime::model::{BallParams, BallState, CueParams};
use kisstime::resolve::stick_ball::{CueStrike, cue_strike};
use kisstime::study::philox::{open_unit, philox4x32};
use kisstime::study::{Noise, noisy_strike_of};

/// The twins in dependency order: the model the strike needs, the strike, the noise.
const FILES: [&str; 8] = [
    "model/fmath.wgsl",
    "model/ball.wgsl",
    "model/vec3.wgsl",
    "model/sim_params.wgsl",
    "model/ball_state.wgsl",
    "resolve/stick_ball.wgsl",
    "study/philox.wgsl",
    "study/noise.wgsl",
];

/// The test's entry points. `philox_main`: six numbers an invocation (counter, key, as
/// exact f64s) in, the four words and the open unit of the first two out. `real_main`:
/// `ln x`, `Φ⁻¹(p)`, `atan y` and `atan2(y, x')` of `(x, p, y, x')`. `strike_main`: a header (the intended strike,
/// R, the five σ, the seed's two words, the ball's ten parameters, the cue's four) then
/// two words of a sample index an invocation; out the five numbers of the noisy strike
/// and the struck ball's v and ω (a ball at rest at (0.5, 1, R), struck by it).
const ENTRY: &str = r#"
@compute @workgroup_size(64)
fn philox_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&xs) / 6u {
        return;
    }
    let c = vec4<u32>(u32(xs[6u * i]), u32(xs[6u * i + 1u]), u32(xs[6u * i + 2u]), u32(xs[6u * i + 3u]));
    let k = vec2<u32>(u32(xs[6u * i + 4u]), u32(xs[6u * i + 5u]));
    let w = philox4x32(c, k);
    ys[5u * i] = real(w.x);
    ys[5u * i + 1u] = real(w.y);
    ys[5u * i + 2u] = real(w.z);
    ys[5u * i + 3u] = real(w.w);
    ys[5u * i + 4u] = open_unit(w.x, w.y);
}

@compute @workgroup_size(64)
fn real_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&xs) / 4u {
        return;
    }
    ys[4u * i] = log_poly(xs[4u * i]);
    ys[4u * i + 1u] = normal_quantile(xs[4u * i + 1u]);
    ys[4u * i + 2u] = atan_poly(xs[4u * i + 2u]);
    ys[4u * i + 3u] = atan2_poly(xs[4u * i + 2u], xs[4u * i + 3u]);
}

const HEADER: u32 = 27u;
const OUT: u32 = 11u;

@compute @workgroup_size(64)
fn strike_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= (arrayLength(&xs) - HEADER) / 2u {
        return;
    }
    let s = CueStrike(xs[0], xs[1], xs[2], xs[3], xs[4]);
    let sigma = Noise(xs[6], xs[7], xs[8], xs[9], xs[10]);
    let seed = vec2<u32>(u32(xs[11]), u32(xs[12]));
    let n = vec2<u32>(u32(xs[HEADER + 2u * i]), u32(xs[HEADER + 2u * i + 1u]));
    let t = noisy_strike_of(s, xs[5], sigma, seed, n);
    let p = BallParams(xs[13], xs[14], xs[15], xs[16], xs[17], xs[18], xs[19], xs[20], xs[21], xs[22]);
    let cue = CueParams(xs[23], xs[24], xs[25], xs[26]);
    let rest = BallState(real3(0.5, 1.0, p.r), real3(0.0, 0.0, 0.0), real3(0.0, 0.0, 0.0), STATE_STATIONARY, 0.0);
    let b = cue_strike(rest, t, p, cue);
    let o = OUT * i;
    ys[o] = t.v0;
    ys[o + 1u] = t.phi;
    ys[o + 2u] = t.theta;
    ys[o + 3u] = t.a;
    ys[o + 4u] = t.b;
    ys[o + 5u] = b.v.x;
    ys[o + 6u] = b.v.y;
    ys[o + 7u] = b.v.z;
    ys[o + 8u] = b.w.x;
    ys[o + 9u] = b.w.y;
    ys[o + 10u] = b.w.z;
}
"#;

/// Numbers out per sample of `strike_main`.
const OUT: usize = 11;

/// How far from the Rust twin (in ulps) the floats may land where the driver may contract
/// and re-associate (not on Vulkan: there they must be exact).
const CONTRACTED_ULPS: u64 = 8;

/// Compares the GPU's floats with the Rust twin's: bit for bit where the pipelines are
/// exact, else within [`CONTRACTED_ULPS`]; the first differences go to `problems`.
fn compare(
    exact: bool,
    what: &str,
    got: f64,
    want: f64,
    problems: &mut Vec<String>,
    differ: &mut usize,
) {
    let u = ulps(got, want);
    if u > 0 {
        *differ += 1;
    }
    let bad = if exact { u > 0 } else { u > CONTRACTED_ULPS };
    if bad && problems.len() < 20 {
        problems.push(format!(
            "{what}: GPU {got:e} ({:#018x}), Rust {want:e} ({:#018x})",
            got.to_bits(),
            want.to_bits()
        ));
    }
}

#[test]
fn the_cue_noise_on_the_gpu_is_the_cpus_bit_for_bit() {
    let name = "gpu_noise";
    let Some(k) = F64Kernels::open(name) else {
        return;
    };
    // the same text builds in the f32 shader (it is not run there)
    for entry in ["philox_main", "real_main", "strike_main"] {
        k.pipeline(&source("f32", &FILES, ENTRY), entry, "f32 noise");
    }
    let text = source("f64", &FILES, ENTRY);
    let mut problems = Vec::new();
    let mut rng = TestRng::new(0x9411);
    let word = |rng: &mut TestRng| (rng.unit() * 4_294_967_296.0).floor();

    // Philox: Random123's known answers, then random counters and keys (integers exact
    // on every device)
    let philox = k.pipeline(&text, "philox_main", "philox");
    let mut cases: Vec<([u32; 4], [u32; 2])> = vec![
        ([0; 4], [0; 2]),
        ([u32::MAX; 4], [u32::MAX; 2]),
        (
            [0x243f_6a88, 0x85a3_08d3, 0x1319_8a2e, 0x0370_7344],
            [0xa409_3822, 0x299f_31d0],
        ),
    ];
    while cases.len() < 4096 {
        let mut w = [0u32; 6];
        for v in &mut w {
            *v = word(&mut rng) as u32;
        }
        cases.push(([w[0], w[1], w[2], w[3]], [w[4], w[5]]));
    }
    let xs: Vec<f64> = cases
        .iter()
        .flat_map(|(c, key)| c.iter().chain(key.iter()).map(|&v| f64::from(v)))
        .collect();
    let ys = k.run(&philox, &xs, 5 * cases.len(), cases.len());
    let mut word_differ = 0;
    let mut unit_differ = 0;
    for (i, (c, key)) in cases.iter().enumerate() {
        let want = philox4x32(*c, *key);
        let got: Vec<u32> = ys[5 * i..5 * i + 4].iter().map(|&v| v as u32).collect();
        if got != want {
            word_differ += 1;
            if problems.len() < 20 {
                problems.push(format!(
                    "philox({c:x?}, {key:x?}): GPU {got:x?}, Rust {want:x?}"
                ));
            }
        }
        compare(
            k.exact,
            &format!("open_unit of philox({c:x?}, {key:x?})"),
            ys[5 * i + 4],
            open_unit(want[0], want[1]),
            &mut problems,
            &mut unit_differ,
        );
    }
    println!(
        "{name}: philox4x32-10: {} counters, {word_differ} differ; open_unit: {unit_differ} differ",
        cases.len()
    );
    assert_eq!(
        word_differ, 0,
        "Philox's words are integers: exact everywhere"
    );

    // ln and Φ⁻¹: the quantile's three regions and their boundaries, ln over its range
    let real = k.pipeline(&text, "real_main", "ln and the normal quantile");
    let mut pairs: Vec<(f64, f64)> = vec![
        (1.0, 0.5),
        (2f64.powi(-53), 2f64.powi(-53)),
        (0.5, 1.0 - 2f64.powi(-53)),
        (f64::MIN_POSITIVE, 0.075),
        (f64::MAX, 0.925),
        (std::f64::consts::SQRT_2, (-25f64).exp()),
    ];
    while pairs.len() < 16384 {
        let x = match pairs.len() % 3 {
            0 => 2f64.powf(rng.range(-53.0, 0.0)),
            1 => rng.range(0.5, 2.0),
            _ => 2f64.powf(rng.range(-1020.0, 1020.0)),
        };
        let p = match pairs.len() % 4 {
            0 | 1 => open_unit(word(&mut rng) as u32, word(&mut rng) as u32),
            2 => 2f64.powf(rng.range(-53.0, -3.0)),
            _ => 1.0 - 2f64.powf(rng.range(-53.0, -3.0)),
        };
        pairs.push((x, p));
    }
    // atan2's arguments: every quadrant, the axes, magnitudes apart
    let angles: Vec<(f64, f64)> = (0..pairs.len())
        .map(|i| match i % 5 {
            0 => (rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)),
            1 => (rng.log_signed(-8.0, 8.0), rng.log_signed(-8.0, 8.0)),
            2 => (rng.range(-1.0, 1.0), 0.0),
            3 => (0.0, rng.range(-1.0, 1.0)),
            _ => (rng.range(-2.0, 2.0), rng.range(1.0, 3.0)),
        })
        .collect();
    let xs: Vec<f64> = pairs
        .iter()
        .zip(&angles)
        .flat_map(|(&(x, p), &(y, xx))| [x, p, y, xx])
        .collect();
    let ys = k.run(&real, &xs, xs.len(), pairs.len());
    let (mut log_differ, mut q_differ, mut atan_differ) = (0, 0, 0);
    for (i, (&(x, p), &(y, xx))) in pairs.iter().zip(&angles).enumerate() {
        compare(
            k.exact,
            &format!("atan({y:e})"),
            ys[4 * i + 2],
            atan_poly(y),
            &mut problems,
            &mut atan_differ,
        );
        compare(
            k.exact,
            &format!("atan2({y:e}, {xx:e})"),
            ys[4 * i + 3],
            atan2_poly(y, xx),
            &mut problems,
            &mut atan_differ,
        );
        compare(
            k.exact,
            &format!("ln({x:e})"),
            ys[4 * i],
            log_poly(x),
            &mut problems,
            &mut log_differ,
        );
        compare(
            k.exact,
            &format!("Φ⁻¹({p:e})"),
            ys[4 * i + 1],
            normal_quantile(p),
            &mut problems,
            &mut q_differ,
        );
    }
    println!(
        "{name}: ln: {} arguments, {log_differ} differ; Φ⁻¹: {q_differ} differ; atan and \
         atan2: {atan_differ} differ",
        pairs.len()
    );

    // noisy strikes and the cue ball they strike: the built-in noise on an ordinary
    // strike, a strike near the rim under wide noise (the rescaling back onto the ball,
    // throttles and masses not pooltool's defaults), a masse under wide noise; seeds with
    // both words set
    let strike_kernel = k.pipeline(&text, "strike_main", "noisy strikes");
    let p = BallParams::default();
    let r = p.r;
    let cues = [
        CueParams::default(),
        CueParams {
            mass: 0.5,
            end_mass: 0.01,
            english_throttle: 0.8,
            squirt_throttle: 1.7,
        },
        CueParams::default(),
    ];
    let studies = [
        (
            CueStrike {
                v0: 2.5,
                phi: 93.7,
                theta: 5.0,
                a: 0.1,
                b: -0.2,
            },
            Noise::default(),
            5u64,
        ),
        (
            CueStrike {
                v0: 0.05,
                phi: -170.0,
                theta: 88.0,
                a: 0.98,
                b: 0.1,
            },
            Noise {
                v0: 0.5,
                phi: 3.0,
                theta: 5.0,
                a: 0.02,
                b: 0.02,
                ..Noise::default()
            },
            0xdead_beef_0000_0007,
        ),
        (
            CueStrike {
                v0: 1.0,
                phi: 400.0,
                theta: 60.0,
                a: -0.4,
                b: 0.3,
            },
            Noise {
                v0: 0.2,
                phi: 20.0,
                theta: 20.0,
                a: 0.01,
                b: 0.01,
                ..Noise::default()
            },
            u64::MAX,
        ),
    ];
    let mut strike_differ = 0;
    for ((s, sigma, seed), cue) in studies.iter().zip(&cues) {
        let indices: Vec<u64> = (0..4000u64).chain([1 << 32, (7 << 32) | 5]).collect();
        let mut xs = vec![
            s.v0,
            s.phi,
            s.theta,
            s.a,
            s.b,
            r,
            sigma.v0,
            sigma.phi,
            sigma.theta,
            sigma.a,
            sigma.b,
            f64::from(*seed as u32),
            f64::from((*seed >> 32) as u32),
            p.m,
            p.r,
            p.u_s,
            p.u_r,
            p.u_sp,
            p.u_b,
            p.e_b,
            p.e_c,
            p.f_c,
            p.g,
            cue.mass,
            cue.end_mass,
            cue.english_throttle,
            cue.squirt_throttle,
        ];
        for &i in &indices {
            xs.push(f64::from(i as u32));
            xs.push(f64::from((i >> 32) as u32));
        }
        let ys = k.run(&strike_kernel, &xs, OUT * indices.len(), indices.len());
        let rest = BallState::at_rest(0.5, 1.0, r);
        for (j, &i) in indices.iter().enumerate() {
            let want = noisy_strike_of(*s, r, sigma, *seed, i);
            let b = cue_strike(&rest, &want, &p, cue);
            let got = &ys[OUT * j..OUT * (j + 1)];
            let wanted = [
                want.v0, want.phi, want.theta, want.a, want.b, b.v.x, b.v.y, b.v.z, b.w.x, b.w.y,
                b.w.z,
            ];
            for (f, w) in got.iter().zip(wanted) {
                compare(
                    k.exact,
                    &format!("sample {i} of seed {seed:#x}"),
                    *f,
                    w,
                    &mut problems,
                    &mut strike_differ,
                );
            }
            assert!(
                got[3] * got[3] + got[4] * got[4] <= 1.0,
                "sample {i}: the tip is on the ball on the GPU"
            );
        }
    }
    println!(
        "{name}: noisy strikes and the balls they strike: {} samples, {strike_differ} numbers \
         differ ({})",
        studies.len() * 4002,
        if k.exact {
            "exact SPIR-V"
        } else {
            "WGSL as wgpu compiles it"
        }
    );
    assert!(
        problems.is_empty(),
        "the GPU differs from the Rust twins (first {}):\n{}",
        problems.len(),
        problems.join("\n")
    );
}
