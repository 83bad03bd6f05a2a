//! Test hooks (the `testing` feature): faults injected into real wgpu calls, and lower
//! chunk limits, so that tests exercise the failure, fallback and chunking paths.

use super::{ChunkLimits, GpuEngine};

/// A fault to inject into the next GPU call, so that tests can exercise the failure and
/// fallback paths with real wgpu errors rather than hoping for them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fault {
    /// The next dispatch asks for more workgroups than the adapter allows: wgpu rejects it
    /// with a validation error, as it would any failed dispatch.
    FailedDispatch,
    /// The device is destroyed now: every later call fails as after a device loss.
    DeviceLost,
    /// Mid-batch: after `n` more dispatches succeed, the next one fails as
    /// [`Fault::FailedDispatch`] does (chunks before it have already run).
    FailedDispatchAfter(u32),
    /// Mid-batch: after `n` more dispatches succeed, the device is destroyed.
    DeviceLostAfter(u32),
}

impl GpuEngine {
    /// Lowers the chunk limits (each is capped at what the adapter allows), e.g. to force
    /// a batch through several chunks in tests.
    pub fn set_chunk_limits(&mut self, limits: ChunkLimits) {
        self.limits = ChunkLimits {
            tables: limits.tables.clamp(1, self.limits.tables),
            balls: limits.balls.clamp(2, self.limits.balls),
            pairs: limits.pairs.clamp(1, self.limits.pairs),
        };
    }

    /// Injects `fault` into the next call (see [`Fault`]).
    pub fn inject_fault(&mut self, fault: Fault) {
        match fault {
            Fault::FailedDispatch => self.pending_fault = Some((Fault::FailedDispatch, 0)),
            Fault::DeviceLost => self.device.destroy(),
            Fault::FailedDispatchAfter(n) => self.pending_fault = Some((Fault::FailedDispatch, n)),
            Fault::DeviceLostAfter(n) => self.pending_fault = Some((Fault::DeviceLost, n)),
        }
    }

    /// Applies a pending fault to the dispatch about to run (`row_len` workgroups a row):
    /// a failed dispatch asks for more workgroups than the adapter allows.
    pub(super) fn apply_pending_fault(&mut self, row_len: &mut u32) {
        match self.pending_fault {
            Some((fault, 0)) => {
                self.pending_fault = None;
                if fault == Fault::DeviceLost {
                    self.device.destroy();
                } else {
                    *row_len = self.max_groups_per_dim.saturating_add(1);
                }
            }
            Some((fault, n)) => self.pending_fault = Some((fault, n - 1)),
            None => {}
        }
    }
}
