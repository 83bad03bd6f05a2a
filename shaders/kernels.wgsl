// Entry points: one workgroup per table. WGSL twin of the per-table loops of
// src/cpu/kernels.rs (`table_paths`, `pair_times`, `next_collisions` with `table_next`)
// and of `pair_of_index` in src/batch/pairs.rs; the buffers are owned and filled by
// src/gpu/ (buffers.rs, dispatch.rs). A batch larger than one dispatch is split there
// into chunks of whole tables; all indices below are relative to the chunk.

// Threads per workgroup.
const WG: u32 = 64u;
// Balls whose paths a workgroup caches in workgroup memory; larger tables read them from
// storage instead (correct, slower).
const MAX_CACHED_BALLS: u32 = 128u;

struct Uniforms {
    params: Params,
    // tables in this chunk
    num_tables: u32,
    // workgroups per row of the 2-D dispatch: table = wg.x + wg.y * row_len
    row_len: u32,
}

@group(0) @binding(0) var<uniform> u: Uniforms;
// per table k: (first ball, first pair), k = 0..=num_tables
@group(0) @binding(1) var<storage, read> table_start: array<vec2<u32>>;
// per ball: motion state (pooltool's codes)
@group(0) @binding(2) var<storage, read> ball_state: array<u32>;
// per ball: (x, y, vx, vy), positions in the table's own frame
@group(0) @binding(3) var<storage, read> ball_pv: array<vec4<real>>;
// per ball: (wx, wy, wz, 0)
@group(0) @binding(4) var<storage, read> ball_w: array<vec4<real>>;
// pair_times: per pair the time; next_collisions: per table the time
@group(0) @binding(5) var<storage, read_write> out_t: array<real>;
// pair_times: per pair the status; next_collisions: per table pair index * 4 + status
@group(0) @binding(6) var<storage, read_write> out_code: array<u32>;

var<workgroup> paths: array<BallPath, MAX_CACHED_BALLS>;
var<workgroup> red_t: array<real, WG>;
var<workgroup> red_code: array<u32, WG>;

// The path of ball `b` (absolute index in the chunk) from storage.
fn load_path(b: u32) -> BallPath {
    let pv = ball_pv[b];
    let w = ball_w[b];
    return ball_path(ball_state[b], pv.xy, pv.zw, w.xyz, u.params);
}

// The table this workgroup answers, and its ball and pair ranges (empty past the end, so
// every thread reaches the barriers).
struct Table {
    k: u32,
    b0: u32,
    n: u32,
    p0: u32,
    np: u32,
}

fn this_table(wg: vec3<u32>) -> Table {
    let k = wg.x + wg.y * u.row_len;
    if k >= u.num_tables {
        return Table(k, 0u, 0u, 0u, 0u);
    }
    let s0 = table_start[k];
    let s1 = table_start[k + 1u];
    return Table(k, s0.x, s1.x - s0.x, s0.y, s1.y - s0.y);
}

// Fills the workgroup's path cache (Rust: table_paths).
fn cache_paths(t: Table, lid: u32) {
    for (var i = lid; i < min(t.n, MAX_CACHED_BALLS); i += WG) {
        paths[i] = load_path(t.b0 + i);
    }
}

fn path_of(t: Table, i: u32) -> BallPath {
    if t.n <= MAX_CACHED_BALLS {
        return paths[i];
    }
    return load_path(t.b0 + i);
}

// The pair (i, j), i < j < n, at local index p in pair order (Rust: batch::pairs::pair_of_index).
// Row i starts at s(i) = i (2n − i − 1) / 2; the f32 estimate of i is corrected exactly.
fn pair_of_index(n: u32, p: u32) -> vec2<u32> {
    let m = f32(2u * n - 1u);
    var i = u32(max(0.0, floor(0.5 * (m - sqrt(max(0.0, m * m - 8.0 * f32(p)))))));
    i = min(i, n - 2u);
    // correct the estimate: s(i) ≤ p < s(i + 1)
    while i > 0u && i * (2u * n - i - 1u) / 2u > p {
        i -= 1u;
    }
    while i + 1u < n - 1u && (i + 1u) * (2u * n - i - 2u) / 2u <= p {
        i += 1u;
    }
    let j = p - i * (2u * n - i - 1u) / 2u + i + 1u;
    return vec2<u32>(i, j);
}

// Every pair of every table (Rust: cpu::kernels::pair_times).
@compute @workgroup_size(64)
fn pair_times(@builtin(workgroup_id) wg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let t = this_table(wg);
    cache_paths(t, lid);
    workgroupBarrier();
    for (var p = lid; p < t.np; p += WG) {
        let ij = pair_of_index(t.n, p);
        let c = pair_contact(path_of(t, ij.x), path_of(t, ij.y), u.params.radius);
        out_t[t.p0 + p] = c.t;
        out_code[t.p0 + p] = c.status;
    }
}

// Whether (t, code) comes before the current best (t_best, code_best) under the tie rule:
// a contact before none, then the smaller time, then the smaller pair index.
fn comes_first(t: real, code: u32, t_best: real, code_best: u32) -> bool {
    if (code & 3u) == STATUS_NONE {
        return false;
    }
    if (code_best & 3u) == STATUS_NONE {
        return true;
    }
    return t < t_best || (t == t_best && (code >> 2u) < (code_best >> 2u));
}

// The next collision of every table (Rust: cpu::kernels::table_next), reduced in the workgroup.
@compute @workgroup_size(64)
fn next_collisions(@builtin(workgroup_id) wg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let t = this_table(wg);
    cache_paths(t, lid);
    workgroupBarrier();
    var best_t: real = NEVER;
    var best_code: u32 = STATUS_NONE;
    for (var p = lid; p < t.np; p += WG) {
        let ij = pair_of_index(t.n, p);
        let c = pair_contact(path_of(t, ij.x), path_of(t, ij.y), u.params.radius);
        let code = p * 4u + c.status;
        if comes_first(c.t, code, best_t, best_code) {
            best_t = c.t;
            best_code = code;
        }
    }
    red_t[lid] = best_t;
    red_code[lid] = best_code;
    workgroupBarrier();
    for (var stride = WG / 2u; stride > 0u; stride /= 2u) {
        if lid < stride && comes_first(red_t[lid + stride], red_code[lid + stride], red_t[lid], red_code[lid]) {
            red_t[lid] = red_t[lid + stride];
            red_code[lid] = red_code[lid + stride];
        }
        workgroupBarrier();
    }
    if lid == 0u && t.k < u.num_tables {
        out_t[t.k] = red_t[0];
        out_code[t.k] = red_code[0];
    }
}
