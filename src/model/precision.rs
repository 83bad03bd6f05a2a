//! The floating-point precision a computation runs in.
//!
//! Defined here, below both the GPU host and the engine that chooses between backends, so
//! that neither imports the other back; [`crate::engine`] re-exports it beside the backend
//! defaults.

/// The floating-point precision a computation runs in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Precision {
    /// IEEE single precision (every GPU).
    F32,
    /// IEEE double precision (the CPU; GPUs whose adapter offers `SHADER_F64`).
    F64,
}

impl Precision {
    /// `f32` or `f64`.
    pub fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }

    /// The size of one real number in bytes.
    pub fn real_size(self) -> usize {
        match self {
            Precision::F32 => 4,
            Precision::F64 => 8,
        }
    }
}
