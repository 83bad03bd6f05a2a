// pooltool's candidate-time caches (spec §3). WGSL twin of src/simulate/cache.rs: the
// entries live in the event loop's workgroup arrays (simulate/event_loop.wgsl); these are
// the stamps and the pair order they share.
//
// pooltool keeps each category in a dict; min over a dict returns, of equal times, the
// entry inserted first. Each step fills a category's missing entries once, in the
// category's fixed order, so the insertion order within a category is (step, position in
// that order): an entry stores the step that filled it, and its position is its index.

// The most balls of a table on the GPU, and so the most pair entries (Rust: the host's
// SimLayout). The host builds the event loop once per ball-count bucket and writes the
// bucket's count on the next line (GPU_BALL_BUCKETS: 16, 32, 48, 64); every other layout
// constant is derived from it.
const GPU_MAX_BALLS: u32 = 16u;
const GPU_MAX_PAIRS: u32 = GPU_MAX_BALLS * (GPU_MAX_BALLS - 1u) / 2u;

// The step of a cache entry that must be (re)computed (Rust: Slot::MISSING).
const MISSING_STEP: u32 = 0xffffffffu;

// Whether entry (t, step, index) comes before (t2, step2, index2): the earlier time, of
// equal times the earlier insertion (Rust: the comparison of earliest and earliest_row, with the
// insertion stamps of insertion_stamp).
fn entry_before(t: real, step: u32, index: u32, t2: real, step2: u32, index2: u32) -> bool {
    return t < t2 || (t == t2 && (step < step2 || (step == step2 && index < index2)));
}

// The index of pair (i, j), i < j < n, in itertools.combinations order.
fn pair_index(i: u32, j: u32, n: u32) -> u32 {
    return i * n - i * (i + 1u) / 2u + (j - i - 1u);
}

// The pair (i, j) at combinations index k of n balls (n ≤ GPU_MAX_BALLS). The Rust twin's
// walk over the rows, here with a fixed trip count and no branch: on lavapipe the
// data-dependent while loop, run by one thread of the workgroup, sometimes stopped a row
// early.
fn pair_at(k: u32, n: u32) -> vec2<u32> {
    var i = 0u;
    var start = 0u;
    for (var row = 0u; row < GPU_MAX_BALLS; row++) {
        let len = select(0u, n - row - 1u, row + 1u < n);
        let next_row = row == i && len > 0u && start + len <= k;
        start = select(start, start + len, next_row);
        i = select(i, i + 1u, next_row);
    }
    return vec2<u32>(i, i + 1u + (k - start));
}
