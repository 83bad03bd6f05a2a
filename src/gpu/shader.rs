//! The WGSL source of the kernels, assembled from the twins in `shaders/`.
//!
//! The shader is the concatenation of a precision prelude (`shaders/real_f32.wgsl` or
//! `shaders/real_f64.wgsl`, which define `real` and the precision constants) and the WGSL
//! twins of the Rust modules, vocabulary first, in the order their Rust twins import each
//! other:
//!
//! | WGSL | Rust twin |
//! |---|---|
//! | `shaders/model/fmath.wgsl` | `src/model/fmath.rs` (the preludes' `real_exp`, …) |
//! | `shaders/model/vec2.wgsl` | `src/model/vec2.rs` |
//! | `shaders/model/ball.wgsl` | `src/model/ball.rs` |
//! | `shaders/model/params.wgsl` | `src/model/params.rs` |
//! | `shaders/model/vec3.wgsl` | `src/model/vec3.rs` |
//! | `shaders/model/sim_params.wgsl` | `src/model/sim_params.rs` |
//! | `shaders/model/ball_state.wgsl` | `src/model/ball_state.rs` |
//! | `shaders/model/table.wgsl` | `src/model/table.rs` |
//! | `shaders/motion/path.wgsl` | `src/motion/path.rs` |
//! | `shaders/motion/evolve.wgsl` | `src/motion/evolve.rs` |
//! | `shaders/motion/trajectory.wgsl` | `src/motion/trajectory.rs` |
//! | `shaders/query/roots.wgsl` | `src/query/roots.rs` |
//! | `shaders/query/ball_ball.wgsl` | `src/query/ball_ball.rs` |
//! | `shaders/query/bounds.wgsl` | `src/query/bounds.rs` |
//! | `shaders/query/ball_circle.wgsl` | `src/query/ball_circle.rs` |
//! | `shaders/query/ball_cushion.wgsl` | `src/query/ball_cushion.rs` |
//! | `shaders/query/ball_pocket.wgsl` | `src/query/ball_pocket.rs` |
//! | `shaders/resolve/ball_ball.wgsl` | `src/resolve/ball_ball.rs` |
//! | `shaders/resolve/stronge.wgsl` | `src/resolve/stronge.rs` |
//! | `shaders/resolve/ball_cushion.wgsl` | `src/resolve/ball_cushion.rs` |
//! | `shaders/resolve/ball_pocket.wgsl` | `src/resolve/ball_pocket.rs` |
//! | `shaders/resolve/transition.wgsl` | `src/resolve/transition.rs` |
//! | `shaders/kernels.wgsl` | `src/cpu/kernels.rs` (the per-table loops) |
//!
//! The event loop ([`simulate_source`]) is its own module: the same files without
//! `kernels.wgsl`, then `shaders/resolve/stick_ball.wgsl` (`src/resolve/stick_ball.rs`),
//! `shaders/study/philox.wgsl` and `shaders/study/noise.wgsl` (`src/study/philox.rs`,
//! `src/study/noise.rs`: a study's draws, which the device makes itself),
//! `shaders/simulate/cache.wgsl` (`src/simulate/cache.rs`) and
//! `shaders/simulate/event_loop.wgsl` (`src/simulate/event_loop.rs`).
//!
//! f64 needs the adapter's `SHADER_F64` feature; without it, asking for f64 is an error.

use crate::model::Precision;

/// The twins in the order they are concatenated (after the prelude): each file uses only
/// what the files before it define.
pub const SHADER_FILES: [(&str, &str); 23] = [
    (
        "model/fmath.wgsl",
        include_str!("../../shaders/model/fmath.wgsl"),
    ),
    (
        "model/vec2.wgsl",
        include_str!("../../shaders/model/vec2.wgsl"),
    ),
    (
        "model/ball.wgsl",
        include_str!("../../shaders/model/ball.wgsl"),
    ),
    (
        "model/params.wgsl",
        include_str!("../../shaders/model/params.wgsl"),
    ),
    (
        "model/vec3.wgsl",
        include_str!("../../shaders/model/vec3.wgsl"),
    ),
    (
        "model/sim_params.wgsl",
        include_str!("../../shaders/model/sim_params.wgsl"),
    ),
    (
        "model/ball_state.wgsl",
        include_str!("../../shaders/model/ball_state.wgsl"),
    ),
    (
        "model/table.wgsl",
        include_str!("../../shaders/model/table.wgsl"),
    ),
    (
        "motion/path.wgsl",
        include_str!("../../shaders/motion/path.wgsl"),
    ),
    (
        "motion/evolve.wgsl",
        include_str!("../../shaders/motion/evolve.wgsl"),
    ),
    (
        "motion/trajectory.wgsl",
        include_str!("../../shaders/motion/trajectory.wgsl"),
    ),
    (
        "query/roots.wgsl",
        include_str!("../../shaders/query/roots.wgsl"),
    ),
    (
        "query/ball_ball.wgsl",
        include_str!("../../shaders/query/ball_ball.wgsl"),
    ),
    (
        "query/bounds.wgsl",
        include_str!("../../shaders/query/bounds.wgsl"),
    ),
    (
        "query/ball_circle.wgsl",
        include_str!("../../shaders/query/ball_circle.wgsl"),
    ),
    (
        "query/ball_cushion.wgsl",
        include_str!("../../shaders/query/ball_cushion.wgsl"),
    ),
    (
        "query/ball_pocket.wgsl",
        include_str!("../../shaders/query/ball_pocket.wgsl"),
    ),
    (
        "resolve/ball_ball.wgsl",
        include_str!("../../shaders/resolve/ball_ball.wgsl"),
    ),
    (
        "resolve/stronge.wgsl",
        include_str!("../../shaders/resolve/stronge.wgsl"),
    ),
    (
        "resolve/ball_cushion.wgsl",
        include_str!("../../shaders/resolve/ball_cushion.wgsl"),
    ),
    (
        "resolve/ball_pocket.wgsl",
        include_str!("../../shaders/resolve/ball_pocket.wgsl"),
    ),
    (
        "resolve/transition.wgsl",
        include_str!("../../shaders/resolve/transition.wgsl"),
    ),
    ("kernels.wgsl", include_str!("../../shaders/kernels.wgsl")),
];

/// The precision prelude (`shaders/real_f32.wgsl` or `shaders/real_f64.wgsl`).
fn prelude(precision: Precision) -> &'static str {
    match precision {
        Precision::F32 => include_str!("../../shaders/real_f32.wgsl"),
        Precision::F64 => include_str!("../../shaders/real_f64.wgsl"),
    }
}

/// The event loop's own files, after [`SHADER_FILES`] less `kernels.wgsl` (its shader is
/// a module of its own, with its own bindings): the strike and the study's draws
/// (`expand_drawn` plays each sample's noisy strike on the device), the cache and the loop.
pub const SIMULATE_FILES: [(&str, &str); 5] = [
    (
        "resolve/stick_ball.wgsl",
        include_str!("../../shaders/resolve/stick_ball.wgsl"),
    ),
    (
        "study/philox.wgsl",
        include_str!("../../shaders/study/philox.wgsl"),
    ),
    (
        "study/noise.wgsl",
        include_str!("../../shaders/study/noise.wgsl"),
    ),
    (
        "simulate/cache.wgsl",
        include_str!("../../shaders/simulate/cache.wgsl"),
    ),
    (
        "simulate/event_loop.wgsl",
        include_str!("../../shaders/simulate/event_loop.wgsl"),
    ),
];

/// The line of `simulate/cache.wgsl` that declares the event loop's ball count; the host
/// writes each bucket's there ([`simulate_source`]), and every other layout constant of
/// the shader is derived from it.
pub const GPU_MAX_BALLS_LINE: &str = "const GPU_MAX_BALLS: u32 = 16u;";

/// The line of `simulate/event_loop.wgsl` that declares how many tables a workgroup
/// holds; the host writes each build's there ([`simulate_source`]).
pub const TABLES_PER_GROUP_LINE: &str = "const TABLES_PER_GROUP: u32 = 1u;";

/// The WGSL source of the event loop for `precision`, tables of up to `max_balls` balls
/// and `tables_per_group` tables a workgroup: the prelude, [`SHADER_FILES`] without the
/// kernels' entry points, then [`SIMULATE_FILES`] with [`GPU_MAX_BALLS_LINE`] set to
/// `max_balls` and [`TABLES_PER_GROUP_LINE`] to `tables_per_group`.
pub fn simulate_source(precision: Precision, max_balls: usize, tables_per_group: usize) -> String {
    let balls = format!("const GPU_MAX_BALLS: u32 = {max_balls}u;");
    let group = format!("const TABLES_PER_GROUP: u32 = {tables_per_group}u;");
    std::iter::once(prelude(precision).to_owned())
        .chain(
            SHADER_FILES
                .iter()
                .filter(|(name, _)| *name != "kernels.wgsl")
                .map(|(_, text)| (*text).to_owned()),
        )
        .chain(SIMULATE_FILES.iter().map(|(_, text)| {
            text.replace(GPU_MAX_BALLS_LINE, &balls)
                .replace(TABLES_PER_GROUP_LINE, &group)
        }))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The full WGSL source for `precision`: the prelude, then [`SHADER_FILES`].
pub fn shader_source(precision: Precision) -> String {
    std::iter::once(prelude(precision))
        .chain(SHADER_FILES.iter().map(|(_, text)| *text))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The workgroup memory of `entry` in `source` (WGSL), in bytes: the sizes of the
/// workgroup variables it uses, as naga lays them out. For choosing a build the device
/// holds before asking the device to build it.
///
/// Errors: the source does not parse or validate (naga's message), or has no `entry`.
pub fn workgroup_bytes(source: &str, entry: &str) -> Result<u64, String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| format!("{e:?}"))?;
    let at = module
        .entry_points
        .iter()
        .position(|e| e.name == entry)
        .ok_or_else(|| format!("no entry point {entry}"))?;
    let mut layouter = naga::proc::Layouter::default();
    layouter
        .update(module.to_ctx())
        .map_err(|e| format!("{e:?}"))?;
    let used = info.get_entry_point(at);
    Ok(module
        .global_variables
        .iter()
        .filter(|(h, v)| v.space == naga::AddressSpace::WorkGroup && !used[*h].is_empty())
        .map(|(_, v)| u64::from(layouter[v.ty].size))
        .sum())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn workgroup_bytes_counts_what_the_entry_uses() {
        let source = "var<workgroup> a: array<f32, 10>;\n\
                      var<workgroup> b: u32;\n\
                      var<workgroup> unused: array<f32, 100>;\n\
                      @compute @workgroup_size(1) fn main() { a[b] = 1.0; }";
        assert_eq!(workgroup_bytes(source, "main"), Ok(44));
        assert!(
            workgroup_bytes(source, "other")
                .unwrap_err()
                .contains("other")
        );
        assert!(workgroup_bytes("fn (", "main").is_err());
    }

    #[test]
    fn each_table_of_a_workgroup_has_its_own_state() {
        let bytes = |tables| {
            workgroup_bytes(
                &simulate_source(Precision::F64, 16, tables),
                "simulate_tables",
            )
            .unwrap()
        };
        let (one, four) = (bytes(1), bytes(4));
        // a 16-ball table's state in f64 is several kilobytes; the group's flag is shared
        assert!((4_000..10_000).contains(&one), "{one}");
        assert!(four > 3 * one && four < 4 * one, "{one} {four}");
    }
}
