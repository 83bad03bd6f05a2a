//! The event loop's buffers ([`LoopBuffers`]): made for a call's largest chunk and its
//! ball-count bucket, and reused across chunks and calls while they fit.

use super::{
    DRAWN_REALS, DRAWN_UINTS, EVENT_REALS, EVENT_UINTS, GpuSimulator, STRUCK_REALS, STRUCK_UINTS,
    SimLayout,
};
use crate::error::Error;
use crate::gpu::device::{Scopes, map_and_wait};

/// The event loop's buffers, made for up to `tables` tables and reused while a call fits.
pub(super) struct LoopBuffers {
    /// The layout (and so the pipeline) the buffers and the bind group were made for.
    pub(super) layout: SimLayout,
    pub(super) tables: usize,
    pub(super) per: usize,
    pub(super) record: bool,
    pub(super) geometry_reals: usize,
    pub(super) sim_reals: usize,
    pub(super) cfg: wgpu::Buffer,
    pub(super) sim: wgpu::Buffer,
    pub(super) geometry: wgpu::Buffer,
    pub(super) state_r: wgpu::Buffer,
    pub(super) state_u: wgpu::Buffer,
    pub(super) events_r: wgpu::Buffer,
    pub(super) events_u: wgpu::Buffer,
    pub(super) running: wgpu::Buffer,
    /// Two lists of tables still running, one half a dispatch (the shader's `live`);
    /// the device alone reads it, through the bind group.
    #[allow(dead_code)]
    pub(super) live: wgpu::Buffer,
    pub(super) bind: wgpu::BindGroup,
    /// The bindings of `expand_tables` (the config, the state, the events buffers).
    pub(super) expand_bind: wgpu::BindGroup,
    /// The bindings of `expand_drawn` (those of `expand_tables` and the parameters).
    pub(super) drawn_bind: wgpu::BindGroup,
    /// Upload buffers for the I/O region (mapped for writing while a chunk is packed).
    pub(super) up_r: wgpu::Buffer,
    pub(super) up_u: wgpu::Buffer,
    /// Readback buffers: the running count, the I/O and watch regions, the events.
    pub(super) back_running: wgpu::Buffer,
    pub(super) back_r: wgpu::Buffer,
    pub(super) back_u: wgpu::Buffer,
    pub(super) back_events_r: Option<wgpu::Buffer>,
    pub(super) back_events_u: Option<wgpu::Buffer>,
}

impl GpuSimulator {
    /// The buffers for chunks of up to `tables` tables: the ones made before where they are
    /// large enough, else new ones.
    pub(super) fn buffers(
        &mut self,
        layout: SimLayout,
        tables: usize,
        record: bool,
        geometry_reals: usize,
        sim_reals: usize,
    ) -> Result<&LoopBuffers, Error> {
        let per = self.events_per_dispatch.max(1) as usize;
        #[cfg(feature = "testing")]
        if self.fresh_buffers {
            self.bufs = None;
        }
        let fits = self.bufs.as_ref().is_some_and(|b| {
            b.layout == layout
                && b.tables >= tables
                && b.per == per
                && b.record == record
                && b.geometry_reals >= geometry_reals
                && b.sim_reals >= sim_reals
        });
        if !fits {
            self.bufs = None;
            // a device lost before fails here, before any buffer is made
            if let Some(e) = self.watch.fault() {
                return Err(e);
            }
            let scopes = Scopes::push(&self.device);
            let made = self.make_buffers(layout, tables, per, record, geometry_reals, sim_reals)?;
            map_and_wait(
                &self.device,
                scopes,
                &self.watch,
                &[],
                &format!("making the event loop's buffers for {tables} tables"),
            )?;
            self.bufs = Some(made);
        }
        Ok(self.bufs.as_ref().expect("made above"))
    }

    #[allow(clippy::too_many_arguments)]
    fn make_buffers(
        &mut self,
        layout: SimLayout,
        tables: usize,
        per: usize,
        record: bool,
        geometry_reals: usize,
        sim_reals: usize,
    ) -> Result<LoopBuffers, Error> {
        let l = &layout;
        let pipelines = self.pipeline(l)?;
        let bind_layout = pipelines.simulate.get_bind_group_layout(0);
        let expand_layout = pipelines.expand.get_bind_group_layout(0);
        let drawn_layout = pipelines.drawn.get_bind_group_layout(0);
        let real = self.precision.real_size() as u64;
        let n = tables as u64;
        let dev = &self.device;
        let make = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(4).next_multiple_of(8),
                usage,
                mapped_at_creation: false,
            })
        };
        let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
        let rw = storage | wgpu::BufferUsages::COPY_SRC;
        let back = wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST;
        let up = wgpu::BufferUsages::MAP_WRITE | wgpu::BufferUsages::COPY_SRC;
        let state_reals = n * (l.io_reals + l.cache_reals + l.watch_reals) as u64;
        let state_uints = n * (l.io_uints + l.cache_uints + l.watch_uints) as u64;
        // what comes back at the end: the I/O region, or a study's watch region
        let back_reals = n * l.io_reals.max(l.watch_reals) as u64;
        let back_uints = n * l.io_uints.max(l.watch_uints) as u64;
        // the input of expand_tables (one I/O block and a strike block a table) or of
        // expand_drawn (one I/O block and a header)
        let expand_reals = (l.io_reals + (tables * STRUCK_REALS).max(DRAWN_REALS)) as u64;
        let expand_uints = (l.io_uints + (tables * STRUCK_UINTS).max(DRAWN_UINTS)) as u64;
        let (events_reals, events_uints) = if record {
            (
                n * (per * EVENT_REALS) as u64,
                n * (1 + per * EVENT_UINTS) as u64,
            )
        } else {
            // without events, the expansions' input
            (expand_reals, expand_uints)
        };
        let cfg = make(
            "config",
            64,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let sim = make("sim", sim_reals as u64 * real, storage);
        let geometry = make("geometry", geometry_reals as u64 * real, storage);
        let state_r = make("state_r", state_reals * real, rw);
        let state_u = make("state_u", state_uints * 4, rw);
        let events_r = make("events_r", events_reals * real, rw);
        let events_u = make("events_u", events_uints * 4, rw);
        let running = make("running", 4, rw);
        let live = make("live", 2 * n * 4, rw);
        let entries: Vec<wgpu::BindGroupEntry> = [
            &cfg, &sim, &geometry, &state_r, &state_u, &events_r, &events_u, &running, &live,
        ]
        .iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: b.as_entire_binding(),
        })
        .collect();
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("event loop"),
            layout: &bind_layout,
            entries: &entries,
        });
        // expand_tables uses the config (0), the state (3, 4) and the events buffers (5, 6)
        let expand_entries: Vec<wgpu::BindGroupEntry> = entries
            .iter()
            .filter(|e| matches!(e.binding, 0 | 3..=6))
            .cloned()
            .collect();
        let expand_bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("expand tables"),
            layout: &expand_layout,
            entries: &expand_entries,
        });
        // expand_drawn's: expand_tables's and the parameters (1)
        let drawn_entries: Vec<wgpu::BindGroupEntry> = entries
            .iter()
            .filter(|e| matches!(e.binding, 0 | 1 | 3..=6))
            .cloned()
            .collect();
        let drawn_bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("expand drawn"),
            layout: &drawn_layout,
            entries: &drawn_entries,
        });
        Ok(LoopBuffers {
            layout,
            tables,
            per,
            record,
            geometry_reals,
            sim_reals,
            // the I/O blocks, or one block and the strike blocks (pack_expanded) or the
            // header (pack_drawn)
            up_r: make(
                "upload reals",
                (n * l.io_reals as u64).max(expand_reals) * real,
                up,
            ),
            up_u: make(
                "upload u32s",
                (n * l.io_uints as u64).max(expand_uints) * 4,
                up,
            ),
            back_running: make("readback running", 4, back),
            back_r: make("readback reals", back_reals * real, back),
            back_u: make("readback u32s", back_uints * 4, back),
            back_events_r: record.then(|| make("readback events_r", events_r.size(), back)),
            back_events_u: record.then(|| make("readback events_u", events_u.size(), back)),
            cfg,
            sim,
            geometry,
            state_r,
            state_u,
            events_r,
            events_u,
            running,
            live,
            bind,
            expand_bind,
            drawn_bind,
        })
    }
}
