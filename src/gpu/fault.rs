//! Test hooks (the `testing` feature): faults injected into real wgpu calls, and lower
//! chunk limits, so that tests exercise the failure, fallback and chunking paths.

use super::{ChunkLimits, GpuEngine, GpuSimulator};
use crate::error::Error;

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
        self.pending_fault = pending(fault, &self.device);
    }

    /// Applies a pending fault to the dispatch about to run (`row_len` workgroups a row):
    /// a failed dispatch asks for more workgroups than the adapter allows.
    pub(super) fn apply_pending_fault(&mut self, row_len: &mut u32) {
        apply(
            &mut self.pending_fault,
            &self.device,
            self.max_groups_per_dim,
            row_len,
        );
    }
}

impl GpuSimulator {
    /// Injects `fault` into the event loop's next dispatch (see [`Fault`]; "after `n`"
    /// counts the event loop's dispatches, each `events_per_dispatch` events long).
    pub fn inject_fault(&mut self, fault: Fault) {
        self.pending_fault = pending(fault, &self.device);
    }

    /// Applies a pending fault to the dispatch about to run (`row_len` workgroups a row).
    pub(super) fn apply_pending_fault(&mut self, row_len: &mut u32) {
        apply(
            &mut self.pending_fault,
            &self.device,
            self.max_groups_per_dim,
            row_len,
        );
    }
}

/// What `fault` leaves pending (a lost device is destroyed at once, leaving nothing).
fn pending(fault: Fault, device: &wgpu::Device) -> Option<(Fault, u32)> {
    match fault {
        Fault::FailedDispatch => Some((Fault::FailedDispatch, 0)),
        Fault::DeviceLost => {
            device.destroy();
            None
        }
        Fault::FailedDispatchAfter(n) => Some((Fault::FailedDispatch, n)),
        Fault::DeviceLostAfter(n) => Some((Fault::DeviceLost, n)),
    }
}

/// Counts `pending` down; at 0 a lost device is destroyed now, and a failed dispatch gets
/// one workgroup more a row than the adapter allows.
fn apply(
    pending: &mut Option<(Fault, u32)>,
    device: &wgpu::Device,
    max_groups_per_dim: u32,
    row_len: &mut u32,
) {
    match *pending {
        Some((fault, 0)) => {
            *pending = None;
            if fault == Fault::DeviceLost {
                device.destroy();
            } else {
                *row_len = max_groups_per_dim.saturating_add(1);
            }
        }
        Some((fault, n)) => *pending = Some((fault, n - 1)),
        None => {}
    }
}

/// The adapter the engines would open (`WGPU_ADAPTER_NAME`, else wgpu's high-performance
/// choice), for test harnesses that build their own device on it.
pub fn adapter() -> Result<wgpu::Adapter, Error> {
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    super::device::pick_adapter(&instance)
}
