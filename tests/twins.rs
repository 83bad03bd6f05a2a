//! The WGSL twins stay honest: for each Rust file with a WGSL twin, the functions they
//! share appear in the same order, and every function that only one of them has is on that
//! pair's documented exception list below (with the reason). A function added to one twin
//! and not the other, or moved in one of them, fails this test.
//!
//! Rust methods are matched to WGSL functions by the names in `RENAMED` (WGSL has no
//! methods: `RelPath::at` is `rel_at`). Functions in a Rust file's `#[cfg(test)]` module
//! are not part of the twin.

use std::path::Path;

/// A Rust file, its WGSL twin, and the functions only one of them has (with why).
struct Twin {
    rust: &'static str,
    wgsl: &'static str,
    rust_only: &'static [(&'static str, &'static str)],
    wgsl_only: &'static [(&'static str, &'static str)],
}

/// Rust functions (mostly methods) and the differently named WGSL functions that are their
/// twins.
const RENAMED: &[(&str, &str)] = &[
    ("table_paths", "cache_paths"),
    ("RelPath::between", "rel_between"),
    ("RelPath::at", "rel_at"),
    ("RelPath::velocity_at", "rel_velocity_at"),
    ("Contact::none", "contact_none"),
    ("Contact::hit", "contact_hit"),
    ("Contact::overlap", "contact_overlap"),
    ("dot", "dot2"),
    ("Vec3::dot", "dot3"),
    ("Vec3::cross", "cross3"),
    ("Vec3::norm", "norm3"),
    ("Vec3::unit", "unit3"),
    ("Vec3::xy", "xy3"),
    ("Vec3::rotate_z", "rotate_z"),
    ("Vec3::rotate_z_cs", "rotate_z_cs"),
    ("BallParams::spin_decel", "spin_decel"),
    ("ResolverParams::eta2", "eta2"),
    ("BallState::translating", "ball_translating"),
    ("Clock::new", "clock_new"),
    ("Clock::phase", "clock_phase"),
    ("Path::still", "path_still"),
    (
        "EventLoop<'_>::transition_candidate",
        "transition_candidate",
    ),
    ("EventLoop<'_>::pair_time", "pair_time"),
    ("EventLoop<'_>::ball_ball_candidate", "ball_ball_candidate"),
    ("EventLoop<'_>::item_time", "item_time"),
    ("EventLoop<'_>::n_items", "n_items"),
    ("EventLoop<'_>::item_candidate", "item_candidate"),
    ("EventLoop<'_>::resolve", "resolve"),
    ("EventLoop<'_>::involve", "involve"),
];

const HOST_ONLY: &str = "host side only: the shader gets its inputs already checked";
const TEXT: &str = "names and parsing for files and messages; the shader has codes";
const CPU_PRUNE: &str = "the CPU's prune pass before the solves (the GPU spreads a table's \
     pairs over its workgroup instead)";

const TWINS: &[Twin] = &[
    Twin {
        rust: "src/model/vec2.rs",
        wgsl: "shaders/model/vec2.wgsl",
        rust_only: &[
            ("Vec2::new", "WGSL's vec2 constructor"),
            ("dot", "the WGSL builtin `dot`"),
            ("add", "WGSL's vector operators"),
            ("sub", "WGSL's vector operators"),
            ("neg", "WGSL's vector operators"),
            ("mul", "WGSL's vector operators"),
        ],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/model/ball.rs",
        wgsl: "shaders/model/ball.wgsl",
        rust_only: &[
            ("MotionState::name", TEXT),
            ("MotionState::translates", HOST_ONLY),
            ("fmt", TEXT),
            ("from_str", TEXT),
            ("Ball::at_rest", HOST_ONLY),
            ("Ball::rolling", HOST_ONLY),
            ("Ball::sliding", HOST_ONLY),
            ("Ball::from_numbers", HOST_ONLY),
            ("Ball::check_numbers", HOST_ONLY),
            ("Ball::numbers", HOST_ONLY),
        ],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/model/params.rs",
        wgsl: "shaders/model/params.wgsl",
        rust_only: &[("default", HOST_ONLY), ("Params::validate", HOST_ONLY)],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/model/vec3.rs",
        wgsl: "shaders/model/vec3.wgsl",
        rust_only: &[
            ("Vec3::new", "WGSL's vec3 constructor"),
            ("Vec3::dot", "the WGSL builtin `dot`"),
            ("Vec3::cross", "the WGSL builtin `cross`"),
            ("Vec3::is_finite", HOST_ONLY),
            (
                "angle",
                "the shader rotates by a vector's unit components (rotate_z_cs), not an atan2",
            ),
            ("add", "WGSL's vector operators"),
            ("add_assign", "WGSL's vector operators"),
            ("sub", "WGSL's vector operators"),
            ("sub_assign", "WGSL's vector operators"),
            ("neg", "WGSL's vector operators"),
            ("mul", "WGSL's vector operators"),
        ],
        wgsl_only: &[(
            "rotate_z_cs",
            "a rotation by an angle's cosine and sine (WGSL's f64 has no atan2)",
        )],
    },
    Twin {
        rust: "src/model/sim_params.rs",
        wgsl: "shaders/model/sim_params.wgsl",
        rust_only: &[
            ("default", HOST_ONLY),
            (
                "BallParams::snooker",
                "a preset the host picks; the shader reads whatever block it is given",
            ),
            (
                "BallParams::carom",
                "a preset the host picks; the shader reads whatever block it is given",
            ),
            ("BallParams::validate", HOST_ONLY),
            ("CueParams::validate", "the strike is resolved on the host"),
            ("ResolverParams::validate", HOST_ONLY),
            ("SimParams::validate", HOST_ONLY),
            (
                "Physics<'_>::of",
                "the host writes each table's parameter block; the shader's load_params reads it",
            ),
            ("Physics<'_>::check", HOST_ONLY),
            ("Physics<'_>::part", HOST_ONLY),
            ("Physics<'_>::first", HOST_ONLY),
            ("Physics<'_>::is_shared", HOST_ONLY),
            ("drawn", HOST_ONLY),
            ("fmt", HOST_ONLY),
            ("from", HOST_ONLY),
        ],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/model/ball_state.rs",
        wgsl: "shaders/model/ball_state.wgsl",
        rust_only: &[
            ("BallState::at_rest", HOST_ONLY),
            ("BallState::from_ball", HOST_ONLY),
            ("BallState::to_ball", HOST_ONLY),
        ],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/model/table.rs",
        wgsl: "shaders/model/table.wgsl",
        rust_only: &[
            ("LinearCushion::new", "tables are built on the host"),
            ("default", "tables are built on the host"),
            ("derive", "tables are built on the host"),
            ("pocket_table_lines", "tables are built on the host"),
            ("pocket_table_arcs", "tables are built on the host"),
            ("pocket_table_pockets", "tables are built on the host"),
            ("Table::pocket_table", "tables are built on the host"),
            ("Table::nine_foot", "tables are built on the host"),
            ("Table::seven_foot", "tables are built on the host"),
            (
                "PocketTableSpecs::seven_foot",
                "tables are built on the host",
            ),
            ("Table::empty", "tables are built on the host"),
            ("Table::rectangle", "tables are built on the host"),
        ],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/model/fmath.rs",
        wgsl: "shaders/model/fmath.wgsl",
        rust_only: &[],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/motion/path.rs",
        wgsl: "shaders/motion/path.wgsl",
        rust_only: &[
            (
                "BallPath::at",
                "the shader evaluates relative paths only (rel_at)",
            ),
            (
                "BallPath::velocity_at",
                "the shader evaluates relative paths only (rel_velocity_at)",
            ),
        ],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/motion/evolve.rs",
        wgsl: "shaders/motion/evolve.wgsl",
        rust_only: &[],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/motion/trajectory.rs",
        wgsl: "shaders/motion/trajectory.wgsl",
        rust_only: &[],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/query/roots.rs",
        wgsl: "shaders/query/roots.wgsl",
        rust_only: &[],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/query/ball_ball.rs",
        wgsl: "shaders/query/ball_ball.wgsl",
        rust_only: &[
            (
                "RelPath::quartic",
                "for inspection and tests; the solver never uses it",
            ),
            ("Status::name", TEXT),
            ("Status::is_contact", HOST_ONLY),
            ("fmt", TEXT),
        ],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/query/bounds.rs",
        wgsl: "shaders/query/bounds.wgsl",
        rust_only: &[],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/query/ball_circle.rs",
        wgsl: "shaders/query/ball_circle.wgsl",
        rust_only: &[],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/query/ball_cushion.rs",
        wgsl: "shaders/query/ball_cushion.wgsl",
        rust_only: &[],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/query/ball_pocket.rs",
        wgsl: "shaders/query/ball_pocket.wgsl",
        rust_only: &[],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/resolve/ball_ball.rs",
        wgsl: "shaders/resolve/ball_ball.wgsl",
        rust_only: &[],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/resolve/stronge.rs",
        wgsl: "shaders/resolve/stronge.wgsl",
        rust_only: &[],
        wgsl_only: &[
            (
                "root_fn_at",
                "calls the function bracketed_root is given (WGSL has no closures)",
            ),
            (
                "stick_slip_f",
                "the closure f of stick_slip (WGSL has no closures)",
            ),
            (
                "slip_stick_slip_g",
                "the closure g of slip_stick_slip (WGSL has no closures)",
            ),
        ],
    },
    Twin {
        rust: "src/resolve/ball_cushion.rs",
        wgsl: "shaders/resolve/ball_cushion.wgsl",
        rust_only: &[],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/resolve/ball_pocket.rs",
        wgsl: "shaders/resolve/ball_pocket.wgsl",
        rust_only: &[],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/resolve/transition.rs",
        wgsl: "shaders/resolve/transition.wgsl",
        rust_only: &[],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/resolve/stick_ball.rs",
        wgsl: "shaders/resolve/stick_ball.wgsl",
        rust_only: &[(
            "CueStrike::validate",
            "the host checks a strike before any reaches the device",
        )],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/study/philox.rs",
        wgsl: "shaders/study/philox.wgsl",
        rust_only: &[],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/study/noise.rs",
        wgsl: "shaders/study/noise.wgsl",
        rust_only: &[
            (
                "noisy_strike",
                "a study file's strike: the device is handed the intended strike",
            ),
            (
                "sample_physics",
                "a sample's physics spread is drawn by the host",
            ),
            ("splitmix", "mix's finaliser, the host's"),
            (
                "mix",
                "self-play's and the environments' seeds of games and episodes, the host's",
            ),
            (
                "drawn_strike",
                "the host's draw of a drawn chunk's sample, for reporting it (the device's is \
                 noisy_strike_of in expand_drawn)",
            ),
            (
                "drawn",
                "the host describes a study's draws to the engine (BatchOptions::drawn)",
            ),
            ("max_normal", "the host's bound on the draws"),
            (
                "draws_are_strikes",
                "the host checks once that every draw is a valid strike",
            ),
        ],
        wgsl_only: &[],
    },
    Twin {
        rust: "src/simulate/cache.rs",
        wgsl: "shaders/simulate/cache.wgsl",
        rust_only: &[
            (
                "Slot::is_missing",
                "an entry is missing when its step is MISSING_STEP",
            ),
            ("earliest", "in ball_ball_candidate, with entry_before"),
            ("earliest_row", "in item_candidate, with entry_before"),
            (
                "insertion_stamp",
                "an entry stores its step; its position is its index",
            ),
        ],
        wgsl_only: &[(
            "entry_before",
            "the comparison of earliest and earliest_row",
        )],
    },
    Twin {
        rust: "src/simulate/event_loop.rs",
        wgsl: "shaders/simulate/event_loop.wgsl",
        rust_only: &[
            ("default", "the host sets the limits"),
            ("new", "the host checks the parameters"),
            (
                "reset",
                "the host lays the tables out (src/gpu/simulate.rs)",
            ),
            ("balls", "the host reads the states back"),
            ("time", "the host reads the clock back"),
            ("outcome", "the host reads the status back"),
            ("step", "the entry point's loop body (simulate_tables)"),
            ("stop", "a status code (STATUS_*)"),
            (
                "advance",
                "the entry point's evolve phase, one thread per ball",
            ),
            (
                "path",
                "every ball's path is computed once per step, one thread per ball",
            ),
            ("check_balls", "the host checks the tables"),
            ("check_input", "the host checks the tables"),
            ("Limits::new", "the host checks the limits"),
            (
                "set_params",
                "each table's parameters are its block of `sim` (load_params)",
            ),
            (
                "params",
                "each table's parameters are its block of `sim` (load_params)",
            ),
            ("Limits::check", "the host checks the limits"),
            (
                "choose",
                "the entry point's choice, with comes_before as the comparison",
            ),
            ("EventLoop<'_>::candidates", "the entry point's choice"),
            (
                "EventLoop<'_>::energy",
                "ball_energy where a candidate needs it",
            ),
            (
                "EventLoop<'_>::stamp",
                "an entry stores its step (cache.wgsl)",
            ),
            (
                "EventLoop<'_>::stick_candidate",
                "the strike is resolved on the host",
            ),
            (
                "EventLoop<'_>::fill_pairs",
                "the entry point's fill phase, one thread per pair",
            ),
            (
                "EventLoop<'_>::fill_items",
                "fill_rows and merge_rows, a row's items split over the threads",
            ),
            ("EventLoop<'_>::rows", "the rows are one workgroup array"),
            (
                "EventLoop<'_>::rows_mut",
                "the rows are one workgroup array",
            ),
            (
                "EventLoop<'_>::circular_candidate",
                "item_candidate with ITEMS_CIRCULAR",
            ),
            (
                "EventLoop<'_>::linear_candidate",
                "item_candidate with ITEMS_LINEAR",
            ),
            (
                "EventLoop<'_>::pocket_candidate",
                "item_candidate with ITEMS_POCKET",
            ),
            ("simulate", "one table on the CPU (the host runs batches)"),
        ],
        wgsl_only: &[
            ("no_candidate", "WGSL has no Option"),
            ("load_params", "reads the parameters from storage"),
            ("linear_item", "reads a cushion from storage"),
            ("circular_item", "reads a jaw from storage"),
            ("pocket_item", "reads a pocket from storage"),
            ("io_r", "where a table's block starts in a storage region"),
            ("io_u", "where a table's block starts in a storage region"),
            (
                "cache_r",
                "where a table's block starts in a storage region",
            ),
            (
                "cache_u",
                "where a table's block starts in a storage region",
            ),
            (
                "watch_r",
                "where a table's block starts in a storage region",
            ),
            (
                "watch_u",
                "where a table's block starts in a storage region",
            ),
            ("load_table", "a table's state into workgroup memory"),
            ("store_table", "a table's state back to storage"),
            ("after_clock", "t + τ with NEVER kept (WGSL has no ∞)"),
            ("comes_before", "choose's comparison"),
            ("put_row", "a row filled, as fill_items stores it"),
            (
                "row_part",
                "fill_items's scan of one row, over a part of its items",
            ),
            (
                "earlier_part",
                "fill_items's comparison, for merging a row's parts",
            ),
            ("row_lanes", "how many threads a row's items are split over"),
            (
                "fill_rows",
                "fill_items, a row's items split over the threads",
            ),
            ("merge_rows", "fill_items, the parts of a row merged"),
            (
                "earlier_pair",
                "the candidates' comparison, for the threads' reduction",
            ),
            (
                "earlier_row",
                "the candidates' comparison, for the threads' reduction",
            ),
            (
                "earlier_trans",
                "the candidates' comparison, for the threads' reduction",
            ),
            (
                "reduce_entries",
                "the candidates' scans, by the threads together in a tree",
            ),
            ("record", "writes an event record for the host"),
            (
                "watch_end",
                "a table's end in its watch block, read by the host instead of its I/O block \
                 (gpu::sim_layout's watched_end)",
            ),
            (
                "watch_end_of_io",
                "a table's end in its watch block, read by the host instead of its I/O block \
                 (gpu::sim_layout's watched_end)",
            ),
            (
                "clear_watch",
                "the watch on the device: simulate::watch's Watcher::start (its CPU twin)",
            ),
            (
                "observe_facts",
                "the watch on the device: simulate::watch's ShotFacts::observe (its CPU twin)",
            ),
            (
                "first_contact_of",
                "the watch on the device: simulate::watch's first_contact_of (its CPU twin)",
            ),
            (
                "watch_event",
                "the watch on the device: simulate::watch's Watcher::watch_event (its CPU twin)",
            ),
            ("simulate_tables", "the entry point"),
            (
                "lay_out_position",
                "a table's I/O block copied from the position's (the expansions')",
            ),
            (
                "expand_tables",
                "an entry point: a study's chunk laid out from one position and its strikes \
                 (gpu::sim_layout's start_table and strike_block on the host)",
            ),
            (
                "expand_drawn",
                "an entry point: a study's chunk laid out from one position, each table's \
                 strike drawn and played on the device (gpu::sim_layout's start_table and \
                 drawn_block, study::noise's noisy_strike_of on the host)",
            ),
        ],
    },
    Twin {
        rust: "src/cpu/kernels.rs",
        wgsl: "shaders/kernels.wgsl",
        rust_only: &[
            (
                "pair_times_of",
                "the host cuts batches into chunks (src/gpu)",
            ),
            (
                "group_slices",
                "the host's Rayon tasks (the GPU's workgroups need none)",
            ),
            ("table_next", "inlined in the entry point next_collisions"),
            ("TableMasks::new", CPU_PRUNE),
            ("TableMasks::fill", CPU_PRUNE),
            ("tables_next_masked", CPU_PRUNE),
            ("prune_still", CPU_PRUNE),
            (
                "next",
                "BitIter's Iterator::next: the prune pass's bit masks (CPU only)",
            ),
            (
                "next_collisions_of",
                "the host cuts batches into chunks (src/gpu)",
            ),
        ],
        wgsl_only: &[
            ("load_path", "reads a path from the storage buffers"),
            ("this_table", "the workgroup's table from its id"),
            ("path_of", "a path from workgroup memory or storage"),
            (
                "pair_of_index",
                "Rust twin in src/batch/pairs.rs (the host decodes with it)",
            ),
            (
                "comes_first",
                "the tie rule as a comparison (Rust: NextCollision::consider)",
            ),
        ],
    },
];

fn read(path: &str) -> String {
    let full = Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{}: {e}", full.display()))
}

/// The name after `fn ` on a line, if the line declares a function.
fn fn_name(line: &str) -> Option<&str> {
    let t = line.trim_start();
    let rest = [
        "pub fn ",
        "pub(crate) fn ",
        "pub(super) fn ",
        "fn ",
        "const fn ",
        "pub const fn ",
    ]
    .iter()
    .find_map(|p| t.strip_prefix(p))?;
    let end = rest.find(|c: char| !(c.is_alphanumeric() || c == '_'))?;
    Some(&rest[..end])
}

/// The Rust file's functions in order, methods as `Type::name` for inherent impls (trait
/// methods by their bare name), without its test module.
fn rust_functions(text: &str) -> Vec<String> {
    let text = text.split("#[cfg(test)]\nmod tests").next().unwrap_or(text);
    let mut out = Vec::new();
    let mut inherent: Option<String> = None;
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("impl ") {
            // `impl Type {` is inherent; `impl Trait for Type {` is not
            inherent = (!rest.contains(" for ") && !rest.starts_with('<'))
                .then(|| rest.trim_end_matches(" {").trim().to_owned());
            continue;
        }
        if line.starts_with('}') {
            inherent = None;
            continue;
        }
        if let Some(name) = fn_name(line) {
            let in_impl = line.starts_with("    ");
            out.push(match (&inherent, in_impl) {
                (Some(ty), true) => format!("{ty}::{name}"),
                _ => name.to_owned(),
            });
        }
    }
    out
}

/// The WGSL file's functions in order.
fn wgsl_functions(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .filter_map(fn_name)
        .map(str::to_owned)
        .collect()
}

/// The WGSL name of a Rust function.
fn as_wgsl(name: &str) -> String {
    RENAMED
        .iter()
        .find(|(r, _)| *r == name)
        .map_or_else(|| name.to_owned(), |(_, w)| (*w).to_owned())
}

#[test]
fn twins_share_their_functions_in_the_same_order() {
    let mut problems = Vec::new();
    for twin in TWINS {
        let rust: Vec<String> = rust_functions(&read(twin.rust));
        let wgsl: Vec<String> = wgsl_functions(&read(twin.wgsl));
        let rust_as_wgsl: Vec<String> = rust.iter().map(|n| as_wgsl(n)).collect();
        for (r, w) in rust.iter().zip(&rust_as_wgsl) {
            if !wgsl.contains(w) && !twin.rust_only.iter().any(|(n, _)| n == r) {
                problems.push(format!(
                    "{} has `{r}` but {} has no `{w}` (add it, or list it in rust_only with why)",
                    twin.rust, twin.wgsl
                ));
            }
        }
        for w in &wgsl {
            if !rust_as_wgsl.contains(w) && !twin.wgsl_only.iter().any(|(n, _)| n == w) {
                problems.push(format!(
                    "{} has `{w}` but {} has no twin of it (add it, or list it in wgsl_only)",
                    twin.wgsl, twin.rust
                ));
            }
        }
        // the exception lists must not go stale
        for (n, _) in twin.rust_only {
            if !rust.iter().any(|r| r == n) {
                problems.push(format!(
                    "{}: rust_only lists `{n}`, which is gone",
                    twin.rust
                ));
            }
        }
        for (n, _) in twin.wgsl_only {
            if !wgsl.iter().any(|w| w == n) {
                problems.push(format!(
                    "{}: wgsl_only lists `{n}`, which is gone",
                    twin.wgsl
                ));
            }
        }
        let shared_rust: Vec<&String> = rust_as_wgsl.iter().filter(|n| wgsl.contains(n)).collect();
        let shared_wgsl: Vec<&String> = wgsl.iter().filter(|n| rust_as_wgsl.contains(n)).collect();
        if shared_rust != shared_wgsl {
            problems.push(format!(
                "{} and {} list their shared functions in different orders:\n  rust: {shared_rust:?}\n  wgsl: {shared_wgsl:?}",
                twin.rust, twin.wgsl
            ));
        }
        assert!(
            !shared_wgsl.is_empty() || wgsl.is_empty(),
            "{}: nothing shared",
            twin.wgsl
        );
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn every_shader_file_has_a_twin_entry() {
    let shader = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut found = Vec::new();
    let mut dirs = vec![shader.clone()];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "wgsl") {
                let rel = path.strip_prefix(shader.parent().unwrap()).unwrap();
                found.push(rel.to_string_lossy().replace('\\', "/"));
            }
        }
    }
    for file in found {
        let prelude = file.starts_with("shaders/real_");
        assert!(
            prelude || TWINS.iter().any(|t| t.wgsl == file),
            "{file} has no entry in tests/twins.rs"
        );
    }
}

#[test]
fn the_parser_sees_methods_and_skips_tests() {
    let text = "pub fn a() {}\nimpl X {\n    pub fn b(&self) {}\n}\nimpl Y for X {\n    fn c() {}\n}\n#[cfg(test)]\nmod tests {\n    fn d() {}\n}\n";
    assert_eq!(rust_functions(text), ["a", "X::b", "c"]);
    let wgsl = "// fn not_this()\nfn e(x: u32) -> u32 {\n    return x;\n}\n@compute @workgroup_size(64)\nfn f() {}\n";
    assert_eq!(wgsl_functions(wgsl), ["e", "f"]);
}
