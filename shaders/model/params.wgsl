// The physical parameters of a batch. WGSL twin of src/model/params.rs; `real` is f32 or
// f64 (see real_f32.wgsl / real_f64.wgsl).

// The physical parameters of one batch (Rust: Params; mu_sp is not needed here).
struct Params {
    radius: real,
    mu_s: real,
    mu_r: real,
    g: real,
}
