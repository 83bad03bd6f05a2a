// The per-table event loop (spec §3). WGSL twin of src/simulate/event_loop.rs: a table's
// threads in a workgroup (one table a workgroup, or TABLES_PER_GROUP side by side), the
// table's state in workgroup memory while a dispatch lasts and in storage between
// dispatches.
//
// Each step: the threads fill the missing cache entries in parallel (ball pairs, then each
// ball–table category's rows, a row's items split over several threads where few rows are
// missing: see fill_rows), each entry stamped with (step, position in its category's fill
// order) as the Rust twin stamps it (simulate/cache.rs), so that the order they are filled
// in does not matter; the threads reduce each category to its earliest
// entry together (reduce_entries) and the table's thread 0 chooses the winner with the Rust twin's tie
// rules (its choose, with comes_before as the comparison), the threads evolve every ball to
// its time, the table's thread 0 resolves it and invalidates the entries of the balls involved. At
// most `events_per_dispatch` events per dispatch; the host dispatches again until every
// table is done, each dispatch after the first only over the tables still running (listed
// in `live`). Nothing is allocated per event; every loop is bounded.
//
// Only a table's I/O block (its balls, counts and status) crosses the bus: the first
// dispatch starts the caches itself. For a study the watch (watch_event) keeps what the
// host needs of the events and of the table's end (watch_end), so that only the watch
// blocks are read back.
//
// The strike is resolved before the loop: a table arrives here after its stick_ball event,
// at step 1, or at step 0 without one. The host resolves it (start_table), or, for a
// study's chunk (one position struck many ways), sends the position's I/O block and each
// table's strike block, which expand_tables lays out into the tables' I/O blocks, or the
// position and one header, from which expand_drawn draws each table's noisy strike and
// plays it (resolve/stick_ball.wgsl, study/noise.wgsl) as the host would have. That gives the
// Rust twin's events: after the strike the Rust loop keeps, from step 0, only entries
// that are never (every ball was at rest), which no tie with a finite time can involve.
//
// Differences forced by WGSL: NEVER for ∞; a missing entry is marked by its step
// MISSING_STEP instead of a NaN time; a candidate carries a `valid` flag instead of being
// an Option; the winner is passed from the table's thread 0 to the others in workgroup
// memory.

// The threads of a table, and the rounds in which they cover the largest
// per-table loop (GPU_MAX_PAIRS entries). Every per-thread loop runs LOOP_ROUNDS times on
// every thread, with the work under an `if`, so that every thread runs the same loops.
// Pipeline-overridable (the host's EVENT_LOOP_THREADS: 16, 32 or 64, a power of two of at
// least GPU_MAX_BALLS; LOOP_ROUNDS = ⌈GPU_MAX_PAIRS / LOOP_THREADS⌉).
override LOOP_THREADS: u32 = 64u;
override LOOP_ROUNDS: u32 = 2u;
// The most threads one row's items are split over (see fill_rows): 1 fills each row on one
// thread, item by item, as the Rust twin does. Pipeline-overridable (the host's
// ROW_THREADS, for measuring the two on a device; the same answers either way).
override ROW_THREADS: u32 = 64u;
// The most threads a table may have (the reduction's array).
const MAX_LOOP_THREADS: u32 = 64u;
// The tables of a workgroup, each with LOOP_THREADS threads (see `tab`). The host writes
// its build's count on the next line (the host's TABLES_PER_GROUP: 1 by default; more put
// several tables' threads in one workgroup, for measuring occupancy on a device).
const TABLES_PER_GROUP: u32 = 1u;
// The threads of a workgroup: TABLES_PER_GROUP · LOOP_THREADS (the host sets both).
override GROUP_THREADS: u32 = 64u;

// Event kinds (Rust: EventKind, the same codes).
const EVENT_STICK_BALL: u32 = 0u;
const EVENT_BALL_BALL: u32 = 1u;
const EVENT_LINEAR_CUSHION: u32 = 2u;
const EVENT_CIRCULAR_CUSHION: u32 = 3u;
const EVENT_POCKET: u32 = 4u;
const EVENT_SLIDING_ROLLING: u32 = 5u;
// no agent (Rust: NO_AGENT)
const NO_AGENT: u32 = 0xffffffffu;

// A table's status (Rust: EventLoop::done and Outcome::cut).
const STATUS_RUNNING: u32 = 0u;
const STATUS_DONE: u32 = 1u;
const STATUS_CUT_EVENTS: u32 = 2u;
const STATUS_CUT_TIME: u32 = 3u;

// The ball–table categories, in the candidates' order (Rust: Items).
const ITEMS_CIRCULAR: u32 = 0u;
const ITEMS_LINEAR: u32 = 1u;
const ITEMS_POCKET: u32 = 2u;

// Reals of one ball's state in storage: r, v, w, t.
const BALL_REALS: u32 = 10u;
// A batch's state in storage is three regions, one after the other in state_r and in
// state_u, each a block per table: the I/O region (written by the host before the first
// dispatch, read back at the end), the caches (the device's own: filled at the first
// dispatch, never read back) and the watch (a study's record of each table's key events,
// read back at the end where the host asks for it). A region starts at n_tables times the
// blocks before it (Rust: the host's SimLayout, the same names in lower case; a test
// evaluates these declarations for every bucket and compares them).
// I/O reals: every ball's r, v, w, t (10 each), its transition's time, the clock.
const IO_R_TRANS: u32 = 10u * GPU_MAX_BALLS;
const IO_R_CLOCK: u32 = IO_R_TRANS + GPU_MAX_BALLS;
const IO_REALS: u32 = IO_R_CLOCK + 1u;
// I/O u32s: every ball's motion state, its transition's kind, then n_balls, n_events and
// the status.
const IO_U_TRANS: u32 = GPU_MAX_BALLS;
const IO_U_N: u32 = 2u * GPU_MAX_BALLS;
const IO_UINTS: u32 = IO_U_N + 3u;
// The ball–table rows of a table: 3 categories of GPU_MAX_BALLS.
const GPU_ROWS: u32 = 3u * GPU_MAX_BALLS;
// Cache reals: pair times, then row times. Cache u32s: pair steps, row steps, row items.
const CACHE_R_ROWS: u32 = GPU_MAX_PAIRS;
const CACHE_REALS: u32 = GPU_MAX_PAIRS + GPU_ROWS;
const CACHE_U_ROWS: u32 = GPU_MAX_PAIRS;
const CACHE_U_ITEMS: u32 = GPU_MAX_PAIRS + GPU_ROWS;
const CACHE_UINTS: u32 = GPU_MAX_PAIRS + 2u * GPU_ROWS;
// Watch reals: the first contact's time, the clock before it, the cue ball's r, v, w, t
// before it (10), the cue ball's and the other ball's centres after it (3 each), then
// each pot's time (GPU_MAX_BALLS), then the rules' facts (Rust: simulate::watch's
// ShotFacts): the first and second ball contacts' times and the cue ball's last counted
// cushion's, then the table's end (the cue ball's r, v, w, t and the clock: all that a
// study reads back of a table, with no I/O block).
const WATCH_R_BEFORE: u32 = 2u;
const WATCH_R_CUE: u32 = 12u;
const WATCH_R_OTHER: u32 = 15u;
const WATCH_R_POTS: u32 = 18u;
const WATCH_FACT_REALS: u32 = 3u;
const WATCH_R_FACTS: u32 = WATCH_R_POTS + GPU_MAX_BALLS;
const WATCH_R_END: u32 = WATCH_R_FACTS + WATCH_FACT_REALS;
const WATCH_END_REALS: u32 = BALL_REALS + 1u;
const WATCH_REALS: u32 = WATCH_R_END + WATCH_END_REALS;
// Watch u32s: the pots so far, the first contact's event number (0: none yet), kind, ball,
// other and the cue ball's motion state before it, then each pot's event number, ball and
// pocket (GPU_MAX_BALLS each), then the rules' facts: any ball–ball contact, the first ball
// contact's other ball + 1 (0: none), a cushion after it, the balls at a cushion (two
// words), the second contact seen, the cue ball's cushions before it, and how many of
// them came at the last one's time; then the table's end (the cue ball's motion state,
// n_balls, n_events, the status).
const WATCH_U_FIRST: u32 = 1u;
const WATCH_U_POTS: u32 = 6u;
const WATCH_FACT_UINTS: u32 = 8u;
const WATCH_U_FACTS: u32 = WATCH_U_POTS + 3u * GPU_MAX_BALLS;
const WATCH_U_END: u32 = WATCH_U_FACTS + WATCH_FACT_UINTS;
const WATCH_END_UINTS: u32 = 4u;
const WATCH_UINTS: u32 = WATCH_U_END + WATCH_END_UINTS;
// One table's strike block when a chunk is expanded from one position (expand_tables):
// the struck ball's r, v, w, t and its transition's time; its motion state, its
// transition's kind, n_events and the status.
const STRUCK_REALS: u32 = BALL_REALS + 1u;
const STRUCK_UINTS: u32 = 4u;
// A drawn chunk's header after the position's block (expand_drawn): the intended strike
// (V0, phi, theta, a, b), the noise's five σ in the same order, the cue's mass, end mass,
// english and squirt throttles; the seed and the first sample id (low, high words each)
// and whether a strike is played at all.
const DRAWN_REALS: u32 = 14u;
const DRAWN_UINTS: u32 = 5u;
// Reals of one parameter block in `sim` (ball 10, resolver 8, max_time) and where max_time is.
const SIM_REALS: u32 = 19u;
const SIM_R_MAX_TIME: u32 = 18u;
// Reals and u32s of one recorded event (t and the two agents' r, v, w, t; kind, ball,
// other and the two agents' motion states).
const EVENT_REALS: u32 = 21u;
const EVENT_UINTS: u32 = 5u;

// The batch's sizes (a uniform).
struct LoopConfig {
    n_tables: u32,
    n_linear: u32,
    n_circular: u32,
    n_pockets: u32,
    max_events: u32,
    events_per_dispatch: u32,
    groups_x: u32,
    record_events: u32,
    // 1 at a batch's first dispatch: the caches start empty and the watch blank
    first_dispatch: u32,
    // the cue ball a study watches (NO_AGENT: no watch), and whether a table stops at the
    // cue ball's first contact
    watch_cue: u32,
    watch_stop: u32,
    // the tables of this dispatch: the tables still running (see `live`)
    n_active: u32,
    // 1: the workgroups take their tables from the active list (else workgroup k runs
    // tables k · TABLES_PER_GROUP onwards), and the tables still running are listed for
    // the next dispatch
    compact: u32,
    // where this dispatch's list starts in `live` (0 or n_tables); the next one's is
    // the other half
    live_in: u32,
    // reals between two tables' parameter blocks in `sim`: 0 where the tables share one
    // (one block), SIM_REALS with per-table physics
    sim_stride: u32,
    // expand_tables only: the struck ball of the strike blocks
    struck_ball: u32,
}

@group(0) @binding(0) var<uniform> cfg: LoopConfig;
// Per parameter block (SIM_REALS): ball parameters (10), resolver parameters (8),
// max_time; one block for every table, or one per table (cfg.sim_stride).
@group(0) @binding(1) var<storage, read> sim: array<real>;
// Straight cushions (10 reals each: p1, p2, direction, lx, ly, l0), then jaws (4: centre,
// radius), then pockets (5: centre, radius, depth).
@group(0) @binding(2) var<storage, read> geometry: array<real>;
// The batch's state: the I/O, cache and watch regions (see IO_REALS).
@group(0) @binding(3) var<storage, read_write> state_r: array<real>;
@group(0) @binding(4) var<storage, read_write> state_u: array<u32>;
// The events recorded by this dispatch (only with record_events): EVENT_REALS per event.
// Without events, expand_tables reads its input here: one table's I/O block (IO_REALS),
// then each table's strike block (STRUCK_REALS); expand_drawn's: the I/O block, then the
// header (DRAWN_REALS).
@group(0) @binding(5) var<storage, read_write> events_r: array<real>;
// Per table: the number of events recorded by this dispatch, then EVENT_UINTS per event
// (only with record_events). Without events, expand_tables's input: the I/O block's u32s
// (IO_UINTS), then each table's strike block (STRUCK_UINTS), or expand_drawn's header
// (DRAWN_UINTS).
@group(0) @binding(6) var<storage, read_write> events_u: array<u32>;
// The tables still running after this dispatch (the host zeroes it before each dispatch
// and reads back only this word until it is 0).
@group(0) @binding(7) var<storage, read_write> running: atomic<u32>;
// With cfg.compact, two lists of tables (n_tables each): this dispatch's workgroups run the
// tables of the half at cfg.live_in, and list the tables still running after it in the
// other half, in any order, for the next dispatch (whose n_active is `running`). A table
// done is never dispatched again.
@group(0) @binding(8) var<storage, read_write> live: array<u32>;

// A table's state while the dispatch lasts (one in each slot of `tab`).
struct Resident {
    // Its balls.
    balls: array<BallState, GPU_MAX_BALLS>,
    // Each ball's next transition: absolute time (NEVER if none) and kind.
    trans_t: array<real, GPU_MAX_BALLS>,
    trans_kind: array<u32, GPU_MAX_BALLS>,
    // Pair entries in combinations order: absolute time and the step that filled them.
    pair_t: array<real, GPU_MAX_PAIRS>,
    pair_step: array<u32, GPU_MAX_PAIRS>,
    // Each ball's row of each ball–table category (index category * GPU_MAX_BALLS + ball):
    // the row's earliest time, its step and its item (Rust: RowBest).
    row_t: array<real, GPU_ROWS>,
    row_step: array<u32, GPU_ROWS>,
    row_item: array<u32, GPU_ROWS>,
    // Each ball's path at the current time and its box.
    paths: array<Path, GPU_MAX_BALLS>,
    boxes: array<PathBox, GPU_MAX_BALLS>,
    clock: real,
    n_balls: u32,
    n_events: u32,
    status: u32,
    n_recorded: u32,
    // The winner of this step (the table's thread 0 writes it).
    win_kind: u32,
    win_t: real,
    win_ball: u32,
    win_other: u32,
    // The earliest entries, reduced by the threads together (see reduce_entries): per thread
    // then per tree level, the earliest pair; the earliest row of each category (in the first
    // ball's place of the category); the earliest transition (in ball 0's place).
    red_pair: array<u32, MAX_LOOP_THREADS>,
    red_row: array<u32, GPU_ROWS>,
    red_trans: array<u32, GPU_MAX_BALLS>,
    // The translating balls whose rows are missing this step (in any order), and each thread's
    // part of a row split over several threads: its earliest time and item (see fill_rows).
    row_balls: array<u32, GPU_MAX_BALLS>,
    n_row_balls: atomic<u32>,
    part_t: array<real, MAX_LOOP_THREADS>,
    part_item: array<u32, MAX_LOOP_THREADS>,
    // The cue ball's state and the clock before this step's event, for the watch.
    watch_before: BallState,
    watch_t0: real,
}

// The tables of the workgroup: TABLES_PER_GROUP of them, each with LOOP_THREADS threads;
// thread lid works for table g = lid / LOOP_THREADS, as that table's thread
// `lane` = lid % LOOP_THREADS ("the table's thread 0" is its lane 0). Every function below
// works on its thread's table, tab[g].
var<workgroup> tab: array<Resident, TABLES_PER_GROUP>;
// This thread's table in the workgroup (set once, at the entry point).
var<private> g: u32;
// Whether any table of the workgroup is still running (thread 0 writes it; the threads
// read it with workgroupUniformLoad, so that every thread takes the same barriers).
var<workgroup> group_running: u32;

// One category's earliest candidate (Rust: Candidate); `valid` false for none.
struct Candidate {
    valid: bool,
    t: real,
    tier: u32,
    energy: real,
    kind: u32,
    ball: u32,
    other: u32,
}

// A row's earliest entry so far: its time and item (NO_AGENT: none yet).
struct RowPart {
    t: real,
    item: u32,
}

fn no_candidate() -> Candidate {
    return Candidate(false, NEVER, 0u, 0.0, 0u, NO_AGENT, NO_AGENT);
}

// Table `table`'s parameters: its block of `sim` (the shared one where cfg.sim_stride is 0).
fn load_params(table: u32) -> SimParams {
    let at = table * cfg.sim_stride;
    let ball = BallParams(
        sim[at], sim[at + 1u], sim[at + 2u], sim[at + 3u], sim[at + 4u],
        sim[at + 5u], sim[at + 6u], sim[at + 7u], sim[at + 8u], sim[at + 9u],
    );
    let resolver = ResolverParams(
        sim[at + 10u], sim[at + 11u], sim[at + 12u], sim[at + 13u],
        sim[at + 14u], sim[at + 15u], sim[at + 16u], sim[at + 17u],
    );
    return SimParams(ball, resolver);
}

fn linear_item(m: u32) -> LinearCushion {
    let at = 10u * m;
    return LinearCushion(
        real3(geometry[at], geometry[at + 1u], geometry[at + 2u]),
        real3(geometry[at + 3u], geometry[at + 4u], geometry[at + 5u]),
        u32(geometry[at + 6u]),
        geometry[at + 7u],
        geometry[at + 8u],
        geometry[at + 9u],
    );
}

fn circular_item(m: u32) -> CircularCushion {
    let at = 10u * cfg.n_linear + 4u * m;
    return CircularCushion(real3(geometry[at], geometry[at + 1u], geometry[at + 2u]), geometry[at + 3u]);
}

fn pocket_item(m: u32) -> Pocket {
    let at = 10u * cfg.n_linear + 4u * cfg.n_circular + 5u * m;
    return Pocket(real3(geometry[at], geometry[at + 1u], geometry[at + 2u]), geometry[at + 3u], geometry[at + 4u]);
}

// Where table `table`'s blocks start in each region (see IO_REALS).
fn io_r(table: u32) -> u32 {
    return table * IO_REALS;
}
fn io_u(table: u32) -> u32 {
    return table * IO_UINTS;
}
fn cache_r(table: u32) -> u32 {
    return cfg.n_tables * IO_REALS + table * CACHE_REALS;
}
fn cache_u(table: u32) -> u32 {
    return cfg.n_tables * IO_UINTS + table * CACHE_UINTS;
}
fn watch_r(table: u32) -> u32 {
    return cfg.n_tables * (IO_REALS + CACHE_REALS) + table * WATCH_REALS;
}
fn watch_u(table: u32) -> u32 {
    return cfg.n_tables * (IO_UINTS + CACHE_UINTS) + table * WATCH_UINTS;
}

// A table's state into workgroup memory: its I/O block, and its caches (empty at the
// batch's first dispatch: every entry missing, as after the host's reset).
fn load_table(table: u32, lane: u32) {
    let r0 = io_r(table);
    let u0 = io_u(table);
    let c_r = cache_r(table);
    let c_u = cache_u(table);
    let fresh = cfg.first_dispatch != 0u;
    for (var round = 0u; round < LOOP_ROUNDS; round++) {
        let i = lane + round * LOOP_THREADS;
        if i < GPU_MAX_BALLS {
            let at = r0 + 10u * i;
            tab[g].balls[i] = BallState(
                real3(state_r[at], state_r[at + 1u], state_r[at + 2u]),
                real3(state_r[at + 3u], state_r[at + 4u], state_r[at + 5u]),
                real3(state_r[at + 6u], state_r[at + 7u], state_r[at + 8u]),
                state_u[u0 + i],
                state_r[at + 9u],
            );
            tab[g].trans_t[i] = state_r[r0 + IO_R_TRANS + i];
            tab[g].trans_kind[i] = state_u[u0 + IO_U_TRANS + i];
        }
    }
    for (var round = 0u; round < LOOP_ROUNDS; round++) {
        let k = lane + round * LOOP_THREADS;
        if k < GPU_MAX_PAIRS {
            if fresh {
                tab[g].pair_t[k] = NEVER;
                tab[g].pair_step[k] = MISSING_STEP;
            } else {
                tab[g].pair_t[k] = state_r[c_r + k];
                tab[g].pair_step[k] = state_u[c_u + k];
            }
        }
    }
    for (var round = 0u; round < LOOP_ROUNDS; round++) {
        let k = lane + round * LOOP_THREADS;
        if k < GPU_ROWS {
            if fresh {
                tab[g].row_t[k] = NEVER;
                tab[g].row_step[k] = MISSING_STEP;
                tab[g].row_item[k] = 0u;
            } else {
                tab[g].row_t[k] = state_r[c_r + CACHE_R_ROWS + k];
                tab[g].row_step[k] = state_u[c_u + CACHE_U_ROWS + k];
                tab[g].row_item[k] = state_u[c_u + CACHE_U_ITEMS + k];
            }
        }
    }
    if lane == 0u {
        tab[g].clock = state_r[r0 + IO_R_CLOCK];
        tab[g].n_balls = state_u[u0 + IO_U_N];
        tab[g].n_events = state_u[u0 + IO_U_N + 1u];
        // (its status was read at the entry point, which loads only a running table)
        tab[g].n_recorded = 0u;
        atomicStore(&tab[g].n_row_balls, 0u);
        if fresh && cfg.watch_cue != NO_AGENT {
            clear_watch(table);
        }
    }
}

// A table's state back to storage.
fn store_table(table: u32, lane: u32) {
    let r0 = io_r(table);
    let u0 = io_u(table);
    let c_r = cache_r(table);
    let c_u = cache_u(table);
    for (var round = 0u; round < LOOP_ROUNDS; round++) {
        let i = lane + round * LOOP_THREADS;
        if i < GPU_MAX_BALLS {
            let at = r0 + 10u * i;
            let b = tab[g].balls[i];
            state_r[at] = b.r.x;
            state_r[at + 1u] = b.r.y;
            state_r[at + 2u] = b.r.z;
            state_r[at + 3u] = b.v.x;
            state_r[at + 4u] = b.v.y;
            state_r[at + 5u] = b.v.z;
            state_r[at + 6u] = b.w.x;
            state_r[at + 7u] = b.w.y;
            state_r[at + 8u] = b.w.z;
            state_r[at + 9u] = b.t;
            state_u[u0 + i] = b.s;
            state_r[r0 + IO_R_TRANS + i] = tab[g].trans_t[i];
            state_u[u0 + IO_U_TRANS + i] = tab[g].trans_kind[i];
        }
    }
    for (var round = 0u; round < LOOP_ROUNDS; round++) {
        let k = lane + round * LOOP_THREADS;
        if k < GPU_MAX_PAIRS {
            state_r[c_r + k] = tab[g].pair_t[k];
            state_u[c_u + k] = tab[g].pair_step[k];
        }
    }
    for (var round = 0u; round < LOOP_ROUNDS; round++) {
        let k = lane + round * LOOP_THREADS;
        if k < GPU_ROWS {
            state_r[c_r + CACHE_R_ROWS + k] = tab[g].row_t[k];
            state_u[c_u + CACHE_U_ROWS + k] = tab[g].row_step[k];
            state_u[c_u + CACHE_U_ITEMS + k] = tab[g].row_item[k];
        }
    }
    if lane == 0u {
        state_r[r0 + IO_R_CLOCK] = tab[g].clock;
        state_u[u0 + IO_U_N + 1u] = tab[g].n_events;
        state_u[u0 + IO_U_N + 2u] = tab[g].status;
        if cfg.watch_cue != NO_AGENT {
            watch_end(table);
        }
        if cfg.record_events != 0u {
            events_u[table * (1u + EVENT_UINTS * cfg.events_per_dispatch)] = tab[g].n_recorded;
        }
        if tab[g].status == STATUS_RUNNING {
            let k = atomicAdd(&running, 1u);
            if cfg.compact != 0u {
                live[cfg.n_tables - cfg.live_in + k] = table;
            }
        }
    }
}

// The absolute time of an entry τ after the clock (NEVER stays NEVER).
fn after_clock(tau: real) -> real {
    return select(tab[g].clock + tau, NEVER, tau >= NEVER);
}

// The winner among the categories' candidates (spec §3): the earliest time; of exact
// ties the smallest (tier, −energy), then the earlier category.
fn comes_before(c: Candidate, b: Candidate) -> bool {
    if !b.valid {
        return true;
    }
    return c.t < b.t || (c.t == b.t && (c.tier < b.tier || (c.tier == b.tier && c.energy > b.energy)));
}

// The earliest transition (ties: ball order).
fn transition_candidate(p: BallParams) -> Candidate {
    // the earliest of balls 0..n (of equal times the first), reduced by reduce_entries
    let best = tab[g].red_trans[0];
    let kind = EVENT_SLIDING_ROLLING + tab[g].trans_kind[best];
    return Candidate(true, tab[g].trans_t[best], 2u, ball_energy(tab[g].balls[best], p), kind, best, NO_AGENT);
}

// τ until balls i < j collide, with pairs whose boxes stay apart skipped (the box test
// comes before the overlap rule, Q3: boxes farther apart than 2R hold centres farther
// apart than 2R at τ = 0 too).
fn pair_time(i: u32, j: u32, p: BallParams) -> real {
    let r = p.r;
    let bi = tab[g].balls[i];
    let bj = tab[g].balls[j];
    let pocketed = bi.s == STATE_POCKETED || bj.s == STATE_POCKETED;
    if pocketed || !(ball_translating(bi) || ball_translating(bj)) {
        return NEVER;
    }
    if boxes_apart(tab[g].boxes[i], tab[g].boxes[j], 2.0 * r) {
        return NEVER;
    }
    let rule = ball_ball_rules(bi, bj, r);
    if rule >= 0.0 {
        return rule;
    }
    return ball_ball_time_on(tab[g].paths[i], tab[g].paths[j], r);
}

// The earliest ball–ball collision (tier 3, energy |v1 − v2|²).
fn ball_ball_candidate() -> Candidate {
    let n = tab[g].n_balls;
    let n_pairs = n * (n - 1u) / 2u;
    if n_pairs == 0u {
        return no_candidate();
    }
    // the earliest entry (entry_before over the pairs), reduced by reduce_entries
    let best = tab[g].red_pair[0];
    let ij = pair_at(best, n);
    let dv = tab[g].balls[ij.x].v - tab[g].balls[ij.y].v;
    return Candidate(true, tab[g].pair_t[best], 3u, dot3(dv, dv), EVENT_BALL_BALL, ij.x, ij.y);
}

// τ until a translating ball on `path` (box `bx`) meets item m of a category, or NEVER;
// items its box keeps clear of are skipped.
fn item_time(which: u32, m: u32, path: Path, bx: PathBox, r: real) -> real {
    if which == ITEMS_LINEAR {
        let seg = linear_item(m);
        if box_outside_extent(bx, seg) {
            return NEVER;
        }
        return linear_cushion_time_on(path, seg, r);
    }
    var center: real2;
    var rho: real;
    if which == ITEMS_CIRCULAR {
        let jaw = circular_item(m);
        center = real2(jaw.center.x, jaw.center.y);
        rho = jaw.radius + r;
    } else {
        let pocket = pocket_item(m);
        center = real2(pocket.center.x, pocket.center.y);
        rho = pocket.radius;
    }
    if box_outside_circle(bx, center, rho) || circle_out_of_reach(path, center, rho) {
        return NEVER;
    }
    return circle_crossing(path, center, rho);
}

fn n_items(which: u32) -> u32 {
    switch which {
        case ITEMS_CIRCULAR: {
            return cfg.n_circular;
        }
        case ITEMS_LINEAR: {
            return cfg.n_linear;
        }
        default: {
            return cfg.n_pockets;
        }
    }
}

// Ball i's row of one ball–table category, filled: its earliest time and item, stamped
// with this step (no item: NEVER and item 0).
fn put_row(which: u32, i: u32, t: real, item: u32) {
    let at = which * GPU_MAX_BALLS + i;
    tab[g].row_t[at] = t;
    tab[g].row_step[at] = tab[g].n_events;
    tab[g].row_item[at] = select(item, 0u, item == NO_AGENT);
}

// The earliest of items lane, lane + lanes, lane + 2·lanes, … of one ball–table category
// for translating ball i (of equal times the first), or item NO_AGENT where there is none.
// With lane 0 and lanes 1, the whole row in table order, as the Rust twin's fill_items.
fn row_part(which: u32, i: u32, lane: u32, lanes: u32, r: real) -> RowPart {
    var best = RowPart(NEVER, NO_AGENT);
    for (var m = lane; m < n_items(which); m += lanes) {
        let t = after_clock(item_time(which, m, tab[g].paths[i], tab[g].boxes[i], r));
        if best.item == NO_AGENT || t < best.t {
            best = RowPart(t, m);
        }
    }
    return best;
}

// Of two parts of one row (item NO_AGENT: none), the earlier (of equal times the lower
// item): what the Rust twin's scan in table order keeps.
fn earlier_part(a: RowPart, b: RowPart) -> RowPart {
    if b.item == NO_AGENT {
        return a;
    }
    if a.item == NO_AGENT || b.t < a.t || (b.t == a.t && b.item < a.item) {
        return b;
    }
    return a;
}

// How many threads each missing row's items are split over this step: as many as the
// workgroup has for each (at most ROW_THREADS), or one where rows outnumber threads.
fn row_lanes(rows: u32) -> u32 {
    return clamp(LOOP_THREADS / max(rows, 1u), 1u, ROW_THREADS);
}

// Fills the missing rows of the balls in row_balls (the Rust twin's fill_items: every
// item of the ball in table order gets its time; the row keeps the earliest, of equal
// times the first). A row's items are split over `lanes` threads, each keeping the
// earliest of its part; with one lane a thread fills whole rows, else the parts are put
// in part_t/part_item and merged by merge_rows after a barrier. Called by every thread.
fn fill_rows(lane: u32, r: real) {
    let rows = 3u * atomicLoad(&tab[g].n_row_balls);
    let lanes = row_lanes(rows);
    for (var s = lane; s < rows * lanes; s += LOOP_THREADS) {
        let row = s / lanes;
        let which = row % 3u;
        let i = tab[g].row_balls[row / 3u];
        if tab[g].row_step[which * GPU_MAX_BALLS + i] == MISSING_STEP {
            let part = row_part(which, i, s % lanes, lanes, r);
            if lanes == 1u {
                put_row(which, i, part.t, part.item);
            } else {
                tab[g].part_t[s] = part.t;
                tab[g].part_item[s] = part.item;
            }
        }
    }
}

// Merges the parts of each row that fill_rows split (rows · lanes ≤ LOOP_THREADS then),
// in lane order. Called by every thread after a barrier that follows fill_rows.
fn merge_rows(lane: u32) {
    let rows = 3u * atomicLoad(&tab[g].n_row_balls);
    let lanes = row_lanes(rows);
    if lanes == 1u || lane >= rows {
        return;
    }
    let which = lane % 3u;
    let i = tab[g].row_balls[lane / 3u];
    if tab[g].row_step[which * GPU_MAX_BALLS + i] != MISSING_STEP {
        return;
    }
    var best = RowPart(NEVER, NO_AGENT);
    for (var k = 0u; k < lanes; k++) {
        let s = lane * lanes + k;
        best = earlier_part(best, RowPart(tab[g].part_t[s], tab[g].part_item[s]));
    }
    put_row(which, i, best.t, best.item);
}

// The earliest event of one ball–table category.
fn item_candidate(which: u32, kind: u32, tier: u32, p: BallParams) -> Candidate {
    if n_items(which) == 0u {
        return no_candidate();
    }
    let base = which * GPU_MAX_BALLS;
    // the earliest row (entry_before over the balls), reduced by reduce_entries
    let at = tab[g].red_row[base];
    let best = at - base;
    return Candidate(true, tab[g].row_t[at], tier, ball_energy(tab[g].balls[best], p), kind, best, tab[g].row_item[at]);
}

// Of two pair entries (NO_AGENT: none), the one entry_before puts first.
fn earlier_pair(a: u32, b: u32) -> u32 {
    if a == NO_AGENT {
        return b;
    }
    if b == NO_AGENT {
        return a;
    }
    return select(a, b, entry_before(tab[g].pair_t[b], tab[g].pair_step[b], b, tab[g].pair_t[a], tab[g].pair_step[a], a));
}

// Of two rows of one category (their places in the row arrays; NO_AGENT: none), the one
// entry_before puts first (the ball's index breaks ties).
fn earlier_row(a: u32, b: u32) -> u32 {
    if a == NO_AGENT {
        return b;
    }
    if b == NO_AGENT {
        return a;
    }
    let ia = a % GPU_MAX_BALLS;
    let ib = b % GPU_MAX_BALLS;
    return select(a, b, entry_before(tab[g].row_t[b], tab[g].row_step[b], ib, tab[g].row_t[a], tab[g].row_step[a], ia));
}

// Of two balls' transitions (NO_AGENT: none), the earlier (of equal times the first ball).
fn earlier_trans(a: u32, b: u32) -> u32 {
    if a == NO_AGENT {
        return b;
    }
    if b == NO_AGENT {
        return a;
    }
    return select(a, b, tab[g].trans_t[b] < tab[g].trans_t[a] || (tab[g].trans_t[b] == tab[g].trans_t[a] && b < a));
}

// The threads reduce each category to its earliest entry together, in a tree of
// LOOP_THREADS: the candidates' scans of the Rust twin, whose comparisons are total
// orders (time, then stamp, then index), so any order of reduction gives their answer.
// Called by every thread after the entries are filled; ends with a barrier.
fn reduce_entries(lane: u32, n: u32) {
    let n_pairs = n * (n - 1u) / 2u;
    var mine = NO_AGENT;
    for (var round = 0u; round < LOOP_ROUNDS; round++) {
        let k = lane + round * LOOP_THREADS;
        if k < n_pairs {
            mine = earlier_pair(mine, k);
        }
    }
    tab[g].red_pair[lane] = mine;
    for (var round = 0u; round < LOOP_ROUNDS; round++) {
        let q = lane + round * LOOP_THREADS;
        if q < GPU_ROWS {
            tab[g].red_row[q] = select(NO_AGENT, q, q % GPU_MAX_BALLS < n);
        }
    }
    if lane < GPU_MAX_BALLS {
        tab[g].red_trans[lane] = select(NO_AGENT, lane, lane < n);
    }
    workgroupBarrier();
    for (var stride = LOOP_THREADS / 2u; stride > 0u; stride = stride / 2u) {
        if lane < stride {
            tab[g].red_pair[lane] = earlier_pair(tab[g].red_pair[lane], tab[g].red_pair[lane + stride]);
        }
        if stride < GPU_MAX_BALLS {
            for (var round = 0u; round < LOOP_ROUNDS; round++) {
                let q = lane + round * LOOP_THREADS;
                if q < GPU_ROWS && q % GPU_MAX_BALLS < stride {
                    tab[g].red_row[q] = earlier_row(tab[g].red_row[q], tab[g].red_row[q + stride]);
                }
            }
            if lane < stride {
                tab[g].red_trans[lane] = earlier_trans(tab[g].red_trans[lane], tab[g].red_trans[lane + stride]);
            }
        }
        workgroupBarrier();
    }
}

// Whether a translating path provably stays farther than rho from center within its
// horizon: the pair solver's hull test on the path relative to the circle's centre, with
// the reach 2 · (rho/2). Conservative, as for ball pairs.
fn circle_out_of_reach(path: Path, center: real2, rho: real) -> bool {
    let rel = RelPath(path.a, path.b, path.c - center);
    return cannot_meet(rel, 0.5 * rho, path.horizon);
}

// Applies the winner (the balls already evolved to its time), then re-stamps, re-caches
// the transitions of, and invalidates the entries of the balls involved.
fn resolve(sp: SimParams) {
    let p = sp.ball;
    let rp = sp.resolver;
    let i = tab[g].win_ball;
    let m = tab[g].win_other;
    let b = tab[g].balls[i];
    // Q17: a transition's agent is stamped t + (T − t), a collision's T
    var stamp = tab[g].win_t;
    if tab[g].win_kind >= EVENT_SLIDING_ROLLING {
        stamp = tab[g].clock + (tab[g].win_t - tab[g].clock);
    }
    var new_b: BallState;
    switch tab[g].win_kind {
        case EVENT_BALL_BALL: {
            let pair = resolve_ball_ball(b, tab[g].balls[m], p, rp);
            tab[g].balls[m] = BallState(pair.b2.r, pair.b2.v, pair.b2.w, pair.b2.s, stamp);
            new_b = pair.b1;
        }
        case EVENT_LINEAR_CUSHION: {
            new_b = resolve_linear_cushion(b, linear_item(m), p, rp);
        }
        case EVENT_CIRCULAR_CUSHION: {
            new_b = resolve_circular_cushion(b, circular_item(m), p, rp);
        }
        case EVENT_POCKET: {
            new_b = resolve_pocket(b, pocket_item(m));
        }
        default: {
            new_b = resolve_transition(b, tab[g].trans_kind[i]);
        }
    }
    tab[g].balls[i] = BallState(new_b.r, new_b.v, new_b.w, new_b.s, stamp);
    tab[g].clock = tab[g].win_t;
    involve(i, p);
    if tab[g].win_kind == EVENT_BALL_BALL {
        involve(m, p);
    }
}

// Ball i took part in the last event: its next transition is recomputed from its new
// state and every cached entry that names it is deleted.
fn involve(i: u32, p: BallParams) {
    let b = tab[g].balls[i];
    let next = next_transition(b, p);
    tab[g].trans_t[i] = select(b.t + next.x, NEVER, next.x >= NEVER);
    tab[g].trans_kind[i] = u32(next.y);
    let n = tab[g].n_balls;
    for (var j = 0u; j < n; j++) {
        if j != i {
            tab[g].pair_step[pair_index(min(i, j), max(i, j), n)] = MISSING_STEP;
        }
    }
    for (var c = 0u; c < 3u; c++) {
        tab[g].row_step[c * GPU_MAX_BALLS + i] = MISSING_STEP;
    }
}

// Appends the winner and its agents' states to this dispatch's records.
fn record(table: u32) {
    if cfg.record_events == 0u || tab[g].n_recorded >= cfg.events_per_dispatch {
        return;
    }
    let k = tab[g].n_recorded;
    let ru = table * (1u + EVENT_UINTS * cfg.events_per_dispatch) + 1u + EVENT_UINTS * k;
    let rr = (table * cfg.events_per_dispatch + k) * EVENT_REALS;
    let second = select(tab[g].win_ball, tab[g].win_other, tab[g].win_kind == EVENT_BALL_BALL);
    events_u[ru] = tab[g].win_kind;
    events_u[ru + 1u] = tab[g].win_ball;
    events_u[ru + 2u] = tab[g].win_other;
    events_u[ru + 3u] = tab[g].balls[tab[g].win_ball].s;
    events_u[ru + 4u] = tab[g].balls[second].s;
    events_r[rr] = tab[g].win_t;
    for (var a = 0u; a < 2u; a++) {
        let b = tab[g].balls[select(tab[g].win_ball, second, a == 1u)];
        let at = rr + 1u + 10u * a;
        events_r[at] = b.r.x;
        events_r[at + 1u] = b.r.y;
        events_r[at + 2u] = b.r.z;
        events_r[at + 3u] = b.v.x;
        events_r[at + 4u] = b.v.y;
        events_r[at + 5u] = b.v.z;
        events_r[at + 6u] = b.w.x;
        events_r[at + 7u] = b.w.y;
        events_r[at + 8u] = b.w.z;
        events_r[at + 9u] = b.t;
    }
    tab[g].n_recorded = k + 1u;
}

// A table's watch blank: no pot, no first contact, no fact (Rust: Watcher::start).
// The table's end in its watch block, from the workgroup's state (at each dispatch's
// end, so that the last one's stays): the cue ball, the clock and the counts.
fn watch_end(table: u32) {
    let e_r = watch_r(table) + WATCH_R_END;
    let e_u = watch_u(table) + WATCH_U_END;
    let b = tab[g].balls[min(cfg.watch_cue, GPU_MAX_BALLS - 1u)];
    state_r[e_r] = b.r.x;
    state_r[e_r + 1u] = b.r.y;
    state_r[e_r + 2u] = b.r.z;
    state_r[e_r + 3u] = b.v.x;
    state_r[e_r + 4u] = b.v.y;
    state_r[e_r + 5u] = b.v.z;
    state_r[e_r + 6u] = b.w.x;
    state_r[e_r + 7u] = b.w.y;
    state_r[e_r + 8u] = b.w.z;
    state_r[e_r + 9u] = b.t;
    state_r[e_r + BALL_REALS] = tab[g].clock;
    state_u[e_u] = b.s;
    state_u[e_u + 1u] = tab[g].n_balls;
    state_u[e_u + 2u] = tab[g].n_events;
    state_u[e_u + 3u] = tab[g].status;
}

// watch_end for a table done before its first dispatch: from its I/O block.
fn watch_end_of_io(table: u32) {
    let r0 = io_r(table);
    let u0 = io_u(table);
    let e_r = watch_r(table) + WATCH_R_END;
    let e_u = watch_u(table) + WATCH_U_END;
    let cue = min(cfg.watch_cue, GPU_MAX_BALLS - 1u);
    for (var k = 0u; k < BALL_REALS; k = k + 1u) {
        state_r[e_r + k] = state_r[r0 + BALL_REALS * cue + k];
    }
    state_r[e_r + BALL_REALS] = state_r[r0 + IO_R_CLOCK];
    state_u[e_u] = state_u[u0 + cue];
    state_u[e_u + 1u] = state_u[u0 + IO_U_N];
    state_u[e_u + 2u] = state_u[u0 + IO_U_N + 1u];
    state_u[e_u + 3u] = state_u[u0 + IO_U_N + 2u];
}

fn clear_watch(table: u32) {
    let w_u = watch_u(table);
    state_u[w_u] = 0u;
    state_u[w_u + WATCH_U_FIRST] = 0u;
    for (var k = 0u; k < WATCH_FACT_UINTS; k = k + 1u) {
        state_u[w_u + WATCH_U_FACTS + k] = 0u;
    }
}

// The rules' facts of the event just resolved (Rust: simulate::watch's
// ShotFacts::observe): any ball–ball contact; the cue ball's first ball contact and its
// time, and the first with another ball (its time); a cushion or jaw strictly after the
// first contact; the balls at a cushion; the cue ball's straight-cushion contacts strictly
// before the second contact (those at its very time taken back). The pockets come from
// the pots. Kept on every watched table; the host reads them where they were asked for
// (WatchOptions::facts), as the CPU keeps them only then.
fn observe_facts(w_r: u32, w_u: u32, cue: u32) {
    let f = w_u + WATCH_U_FACTS;
    let fr = w_r + WATCH_R_FACTS;
    if tab[g].win_kind == EVENT_BALL_BALL {
        state_u[f] = 1u;
        if tab[g].win_ball != cue && tab[g].win_other != cue {
            return;
        }
        let other = select(tab[g].win_ball, tab[g].win_other, tab[g].win_ball == cue);
        if state_u[f + 1u] == 0u {
            state_u[f + 1u] = other + 1u;
            state_r[fr] = tab[g].win_t;
        } else if state_u[f + 1u] != other + 1u && state_u[f + 5u] == 0u {
            state_u[f + 5u] = 1u;
            state_r[fr + 1u] = tab[g].win_t;
            if state_u[f + 7u] != 0u && state_r[fr + 2u] == tab[g].win_t {
                state_u[f + 6u] = state_u[f + 6u] - state_u[f + 7u];
            }
        }
        return;
    }
    if tab[g].win_kind == EVENT_LINEAR_CUSHION || tab[g].win_kind == EVENT_CIRCULAR_CUSHION {
        // two words of 32 balls each
        let word = tab[g].win_ball / 32u;
        let mask = 1u << (tab[g].win_ball % 32u);
        if word < 2u {
            state_u[f + 3u + word] = state_u[f + 3u + word] | mask;
        }
        if state_u[f + 1u] != 0u && tab[g].win_t > state_r[fr] {
            state_u[f + 2u] = 1u;
        }
        if tab[g].win_kind == EVENT_LINEAR_CUSHION && tab[g].win_ball == cue && state_u[f + 5u] == 0u {
            state_u[f + 6u] = state_u[f + 6u] + 1u;
            if state_u[f + 7u] != 0u && state_r[fr + 2u] == tab[g].win_t {
                state_u[f + 7u] = state_u[f + 7u] + 1u;
            } else {
                state_r[fr + 2u] = tab[g].win_t;
                state_u[f + 7u] = 1u;
            }
        }
    }
}

// Whether event (kind, ball, other) is the cue ball's first contact, if none came before
// (Rust: simulate::watch::first_contact_of): ball–ball with the cue ball, a
// cushion or jaw, a pocket, or the cue ball stopping; not the strike, nor the cue ball's
// own sliding → rolling.
fn first_contact_of(kind: u32, ball: u32, other: u32, cue: u32) -> bool {
    let involves = ball == cue || (kind == EVENT_BALL_BALL && other == cue);
    return involves && kind != EVENT_STICK_BALL && kind != EVENT_SLIDING_ROLLING;
}

// The watch's record of the event just resolved (Rust: simulate::watch's
// Watcher::watch_event): the cue ball's first contact with its state and the clock before
// it and both balls' centres after it, and every pot. With watch_stop the table ends at
// the first contact, as the CPU's watched loop stops there.
fn watch_event(table: u32) {
    let cue = cfg.watch_cue;
    let w_r = watch_r(table);
    let w_u = watch_u(table);
    if tab[g].win_kind == EVENT_POCKET {
        let k = state_u[w_u];
        if k < GPU_MAX_BALLS {
            state_u[w_u + WATCH_U_POTS + k] = tab[g].n_events;
            state_u[w_u + WATCH_U_POTS + GPU_MAX_BALLS + k] = tab[g].win_ball;
            state_u[w_u + WATCH_U_POTS + 2u * GPU_MAX_BALLS + k] = tab[g].win_other;
            state_r[w_r + WATCH_R_POTS + k] = tab[g].win_t;
            state_u[w_u] = k + 1u;
        }
    }
    observe_facts(w_r, w_u, cue);
    if state_u[w_u + WATCH_U_FIRST] != 0u || !first_contact_of(tab[g].win_kind, tab[g].win_ball, tab[g].win_other, cue) {
        return;
    }
    let b = tab[g].watch_before;
    state_u[w_u + WATCH_U_FIRST] = tab[g].n_events;
    state_u[w_u + WATCH_U_FIRST + 1u] = tab[g].win_kind;
    state_u[w_u + WATCH_U_FIRST + 2u] = tab[g].win_ball;
    state_u[w_u + WATCH_U_FIRST + 3u] = tab[g].win_other;
    state_u[w_u + WATCH_U_FIRST + 4u] = b.s;
    state_r[w_r] = tab[g].win_t;
    state_r[w_r + 1u] = tab[g].watch_t0;
    let at = w_r + WATCH_R_BEFORE;
    state_r[at] = b.r.x;
    state_r[at + 1u] = b.r.y;
    state_r[at + 2u] = b.r.z;
    state_r[at + 3u] = b.v.x;
    state_r[at + 4u] = b.v.y;
    state_r[at + 5u] = b.v.z;
    state_r[at + 6u] = b.w.x;
    state_r[at + 7u] = b.w.y;
    state_r[at + 8u] = b.w.z;
    state_r[at + 9u] = b.t;
    let c = tab[g].balls[cue].r;
    state_r[w_r + WATCH_R_CUE] = c.x;
    state_r[w_r + WATCH_R_CUE + 1u] = c.y;
    state_r[w_r + WATCH_R_CUE + 2u] = c.z;
    let other = select(tab[g].win_ball, tab[g].win_other, tab[g].win_ball == cue);
    let o = tab[g].balls[min(other, tab[g].n_balls - 1u)].r;
    state_r[w_r + WATCH_R_OTHER] = o.x;
    state_r[w_r + WATCH_R_OTHER + 1u] = o.y;
    state_r[w_r + WATCH_R_OTHER + 2u] = o.z;
    if cfg.watch_stop != 0u {
        tab[g].status = STATUS_DONE;
    }
}

// TABLES_PER_GROUP tables a workgroup, LOOP_THREADS threads each: up to
// events_per_dispatch steps of each table's loop (Rust: EventLoop::step, with candidates,
// choose, advance and resolve). The tables of a workgroup step together: a table done
// (or a slot without a table) waits through the others' steps with its work skipped, and
// the loop ends when none of them is running.
@compute @workgroup_size(GROUP_THREADS)
fn simulate_tables(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    g = min(lid / LOOP_THREADS, TABLES_PER_GROUP - 1u);
    let lane = lid % LOOP_THREADS;
    let slot = (wid.y * cfg.groups_x + wid.x) * TABLES_PER_GROUP + g;
    let occupied = slot < cfg.n_active;
    var table = min(slot, cfg.n_tables - 1u);
    if occupied && cfg.compact != 0u && cfg.first_dispatch == 0u {
        table = live[cfg.live_in + slot];
    }
    // a table done in an earlier dispatch is left as it is (not loaded, not stored)
    if lane == 0u {
        tab[g].status = select(STATUS_DONE, state_u[io_u(table) + IO_U_N + 2u], occupied);
        tab[g].n_balls = 0u;
    }
    workgroupBarrier();
    let loaded = tab[g].status == STATUS_RUNNING;
    if occupied && !loaded && lane == 0u {
        if cfg.record_events != 0u {
            events_u[table * (1u + EVENT_UINTS * cfg.events_per_dispatch)] = 0u;
        }
        if cfg.first_dispatch != 0u && cfg.watch_cue != NO_AGENT {
            clear_watch(table);
            watch_end_of_io(table);
        }
    }
    let sp = load_params(table);
    let p = sp.ball;
    let max_time = sim[table * cfg.sim_stride + SIM_R_MAX_TIME];
    if loaded {
        load_table(table, lane);
    }
    workgroupBarrier();
    for (var step = 0u; step < cfg.events_per_dispatch; step++) {
        if lid == 0u {
            var any = 0u;
            for (var k = 0u; k < TABLES_PER_GROUP; k++) {
                any = any | u32(tab[k].status == STATUS_RUNNING);
            }
            group_running = any;
        }
        if workgroupUniformLoad(&group_running) == 0u {
            break;
        }
        let stepping = tab[g].status == STATUS_RUNNING;
        let n = select(0u, tab[g].n_balls, stepping);
        // the paths and boxes of every ball at the current time; the translating balls
        // whose rows are missing listed for fill_rows, the others' missing rows filled now
        // (a ball that does not translate meets nothing)
        for (var round = 0u; round < LOOP_ROUNDS; round++) {
            let i = lane + round * LOOP_THREADS;
            if i < n {
                let path = trajectory(tab[g].balls[i], p);
                tab[g].paths[i] = path;
                tab[g].boxes[i] = path_box(path);
                var missing = false;
                for (var which = 0u; which < 3u; which++) {
                    missing = missing || tab[g].row_step[which * GPU_MAX_BALLS + i] == MISSING_STEP;
                }
                if missing && ball_translating(tab[g].balls[i]) {
                    tab[g].row_balls[atomicAdd(&tab[g].n_row_balls, 1u)] = i;
                } else if missing {
                    for (var which = 0u; which < 3u; which++) {
                        if tab[g].row_step[which * GPU_MAX_BALLS + i] == MISSING_STEP {
                            put_row(which, i, NEVER, 0u);
                        }
                    }
                }
            }
        }
        workgroupBarrier();
        // the missing pair entries, then the missing rows, in parallel
        let n_pairs = n * (n - 1u) / 2u;
        for (var round = 0u; round < LOOP_ROUNDS; round++) {
            let k = lane + round * LOOP_THREADS;
            if k < n_pairs {
                if tab[g].pair_step[k] == MISSING_STEP {
                    let ij = pair_at(k, n);
                    tab[g].pair_t[k] = after_clock(pair_time(ij.x, ij.y, p));
                    tab[g].pair_step[k] = tab[g].n_events;
                }
            }
        }
        if stepping {
            fill_rows(lane, p.r);
        }
        workgroupBarrier();
        if stepping {
            merge_rows(lane);
        }
        workgroupBarrier();
        // each category's earliest entry, by the threads together
        reduce_entries(lane, n);
        if stepping && lane == 0u {
            // the list is read (fill_rows, merge_rows): empty for the next step
            atomicStore(&tab[g].n_row_balls, 0u);
            if tab[g].n_events >= cfg.max_events {
                tab[g].status = STATUS_CUT_EVENTS;
            } else {
                // the candidates in category order: transition, ball–ball, circular
                // cushion, linear cushion, pocket (the stick was resolved on the host)
                var best = transition_candidate(p);
                let pairs = ball_ball_candidate();
                if pairs.valid && comes_before(pairs, best) {
                    best = pairs;
                }
                let circular = item_candidate(ITEMS_CIRCULAR, EVENT_CIRCULAR_CUSHION, 3u, p);
                if circular.valid && comes_before(circular, best) {
                    best = circular;
                }
                let linear = item_candidate(ITEMS_LINEAR, EVENT_LINEAR_CUSHION, 3u, p);
                if linear.valid && comes_before(linear, best) {
                    best = linear;
                }
                let pocket = item_candidate(ITEMS_POCKET, EVENT_POCKET, 2u, p);
                if pocket.valid && comes_before(pocket, best) {
                    best = pocket;
                }
                if !best.valid || best.t >= NEVER {
                    tab[g].status = STATUS_DONE;
                } else if best.t > max_time {
                    tab[g].status = STATUS_CUT_TIME;
                } else {
                    tab[g].win_kind = best.kind;
                    tab[g].win_t = best.t;
                    tab[g].win_ball = best.ball;
                    tab[g].win_other = best.other;
                    if cfg.watch_cue != NO_AGENT {
                        tab[g].watch_before = tab[g].balls[cfg.watch_cue];
                        tab[g].watch_t0 = tab[g].clock;
                    }
                }
            }
        }
        workgroupBarrier();
        // a table whose loop ended at this step has no event to apply
        let applies = stepping && tab[g].status == STATUS_RUNNING;
        // every ball evolved to the winner's time (closed forms, labels kept)
        let dt = tab[g].win_t - tab[g].clock;
        for (var round = 0u; round < LOOP_ROUNDS; round++) {
            let i = lane + round * LOOP_THREADS;
            if applies && i < n {
                tab[g].balls[i] = evolve(tab[g].balls[i], dt, p);
            }
        }
        workgroupBarrier();
        if applies && lane == 0u {
            resolve(sp);
            tab[g].n_events += 1u;
            record(table);
            if cfg.watch_cue != NO_AGENT {
                watch_event(table);
            }
        }
        workgroupBarrier();
    }
    workgroupBarrier();
    if loaded {
        store_table(table, lane);
    }
}

// Table `table`'s I/O block as the position's, which an expansion's input starts with
// (events_r/events_u from 0).
fn lay_out_position(table: u32) {
    let r0 = io_r(table);
    let u0 = io_u(table);
    for (var k = 0u; k < IO_REALS; k = k + 1u) {
        state_r[r0 + k] = events_r[k];
    }
    for (var k = 0u; k < IO_UINTS; k = k + 1u) {
        state_u[u0 + k] = events_u[k];
    }
}

// One position struck many ways (a study's chunk): every table's I/O block is the
// position's (events_r/events_u from 0) with the struck ball's state, its transition, the
// event count and the status from the table's strike block, which the host made as it
// would have made the whole block (Rust: gpu::sim_layout's start_table and strike_block).
// One thread a table; the host dispatches ⌈n_tables / 64⌉ workgroups in rows of
// cfg.groups_x before the event loop's first dispatch.
@compute @workgroup_size(64)
fn expand_tables(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let table = (wid.y * cfg.groups_x + wid.x) * 64u + lid;
    if table >= cfg.n_tables {
        return;
    }
    lay_out_position(table);
    let r0 = io_r(table);
    let u0 = io_u(table);
    let cue = min(cfg.struck_ball, GPU_MAX_BALLS - 1u);
    let s_r = IO_REALS + table * STRUCK_REALS;
    let s_u = IO_UINTS + table * STRUCK_UINTS;
    for (var k = 0u; k < BALL_REALS; k = k + 1u) {
        state_r[r0 + BALL_REALS * cue + k] = events_r[s_r + k];
    }
    state_r[r0 + IO_R_TRANS + cue] = events_r[s_r + BALL_REALS];
    state_u[u0 + cue] = events_u[s_u];
    state_u[u0 + IO_U_TRANS + cue] = events_u[s_u + 1u];
    state_u[u0 + IO_U_N + 1u] = events_u[s_u + 2u];
    state_u[u0 + IO_U_N + 2u] = events_u[s_u + 3u];
}

// A study's chunk drawn on the device: every table's I/O block is the position's with
// the struck ball struck by its sample's noisy strike, sample first + table (the study's
// noisy_strike_of: Philox keyed by the seed, study/noise.wgsl), under the CPU loop's rule
// (Rust: gpu::sim_layout's start_table and drawn_block, study::noise's noisy_strike_of).
// The header after the position's block: DRAWN_REALS (the intended strike, the five σ,
// the cue's parameters), DRAWN_UINTS (the seed and the first sample id as low and high
// words, and whether a strike is played at all); the ball parameters are sim's shared
// block. One thread a table, dispatched as expand_tables is. The host reads no strike back:
// it draws the same ones itself where it reports them.
@compute @workgroup_size(64)
fn expand_drawn(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let table = (wid.y * cfg.groups_x + wid.x) * 64u + lid;
    if table >= cfg.n_tables {
        return;
    }
    lay_out_position(table);
    let h_r = IO_REALS;
    let h_u = IO_UINTS;
    let shot = CueStrike(
        events_r[h_r], events_r[h_r + 1u], events_r[h_r + 2u], events_r[h_r + 3u],
        events_r[h_r + 4u],
    );
    let sigma = Noise(
        events_r[h_r + 5u], events_r[h_r + 6u], events_r[h_r + 7u], events_r[h_r + 8u],
        events_r[h_r + 9u],
    );
    let cue_params = CueParams(
        events_r[h_r + 10u], events_r[h_r + 11u], events_r[h_r + 12u], events_r[h_r + 13u],
    );
    let p = load_params(0u).ball;
    let seed = vec2<u32>(events_u[h_u], events_u[h_u + 1u]);
    // the sample id, first + table, its carry into the high word
    let lo = events_u[h_u + 2u] + table;
    let hi = events_u[h_u + 3u] + select(0u, 1u, lo < table);
    let s = noisy_strike_of(shot, p.r, sigma, seed, vec2<u32>(lo, hi));
    // the CPU loop's stick candidate: every ball at rest, an event allowed (the header's
    // flag), V0 > 0; else the ball stays as the position has it
    if events_u[h_u + 4u] == 0u || !(s.v0 > 0.0) {
        return;
    }
    let cue = min(cfg.struck_ball, GPU_MAX_BALLS - 1u);
    let at = BALL_REALS * cue;
    let ball = BallState(
        real3(events_r[at], events_r[at + 1u], events_r[at + 2u]),
        real3(events_r[at + 3u], events_r[at + 4u], events_r[at + 5u]),
        real3(events_r[at + 6u], events_r[at + 7u], events_r[at + 8u]),
        events_u[cue],
        events_r[at + 9u],
    );
    let b = cue_strike(ball, s, p, cue_params);
    let r0 = io_r(table) + at;
    state_r[r0] = b.r.x;
    state_r[r0 + 1u] = b.r.y;
    state_r[r0 + 2u] = b.r.z;
    state_r[r0 + 3u] = b.v.x;
    state_r[r0 + 4u] = b.v.y;
    state_r[r0 + 5u] = b.v.z;
    state_r[r0 + 6u] = b.w.x;
    state_r[r0 + 7u] = b.w.y;
    state_r[r0 + 8u] = b.w.z;
    state_r[r0 + 9u] = b.t;
    let u0 = io_u(table);
    state_u[u0 + cue] = b.s;
    // its next transition, as involve() writes one
    let next = next_transition(b, p);
    state_r[io_r(table) + IO_R_TRANS + cue] = select(b.t + next.x, NEVER, next.x >= NEVER);
    state_u[u0 + IO_U_TRANS + cue] = u32(next.y);
    state_u[u0 + IO_U_N + 1u] = 1u;
}
