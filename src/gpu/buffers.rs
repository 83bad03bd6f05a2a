//! The device buffers, and the host arrays laid out as the shader reads them.

use std::ops::Range;

use rayon::prelude::*;

use super::GpuEngine;
use crate::batch::Batch;
use crate::model::Precision;

/// The device buffers, sized for `cap` elements each.
pub(super) struct Buffers {
    pub(super) cap_tables: usize,
    pub(super) cap_balls: usize,
    pub(super) cap_out: usize,
    pub(super) uniform: wgpu::Buffer,
    pub(super) table_start: wgpu::Buffer,
    pub(super) ball_state: wgpu::Buffer,
    pub(super) ball_pv: wgpu::Buffer,
    pub(super) ball_w: wgpu::Buffer,
    pub(super) out_t: wgpu::Buffer,
    pub(super) out_code: wgpu::Buffer,
    pub(super) read_t: wgpu::Buffer,
    pub(super) read_code: wgpu::Buffer,
    /// Upload buffers (mapped for writing while a chunk is copied in), one per input.
    pub(super) up_table_start: wgpu::Buffer,
    pub(super) up_ball_state: wgpu::Buffer,
    pub(super) up_ball_pv: wgpu::Buffer,
    pub(super) up_ball_w: wgpu::Buffer,
    pub(super) bind: wgpu::BindGroup,
}

/// One chunk's inputs, laid out as the shader reads them (reused across chunks).
#[derive(Default)]
pub(super) struct HostArrays {
    pub(super) table_start: Vec<[u32; 2]>,
    pub(super) ball_state: Vec<u32>,
    pub(super) ball_pv: Vec<u8>,
    pub(super) ball_w: Vec<u8>,
}

impl GpuEngine {
    /// Makes sure the buffers hold `tables`, `balls` and `out` elements.
    pub(super) fn ensure_buffers(&mut self, tables: usize, balls: usize, out: usize) {
        if let Some(b) = &self.bufs
            && b.cap_tables >= tables
            && b.cap_balls >= balls
            && b.cap_out >= out
        {
            return;
        }
        let grow = |need: usize, old: usize| need.max(old + old / 2).max(64);
        let (old_t, old_b, old_o) = self
            .bufs
            .as_ref()
            .map_or((0, 0, 0), |b| (b.cap_tables, b.cap_balls, b.cap_out));
        let cap_tables = grow(tables, old_t).min(self.limits.tables.max(tables));
        let cap_balls = grow(balls, old_b).min(self.limits.balls.max(balls));
        let cap_out = grow(out, old_o).min(self.limits.pairs.max(self.limits.tables).max(out));
        let real = self.precision.real_size() as u64;
        let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
        let buffer = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(16),
                usage,
                mapped_at_creation: false,
            })
        };
        let uniform = buffer(
            "uniforms",
            64,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let table_start = buffer("table_start", 8 * (cap_tables as u64 + 1), storage);
        let ball_state = buffer("ball_state", 4 * cap_balls as u64, storage);
        let ball_pv = buffer("ball_pv", 4 * real * cap_balls as u64, storage);
        let ball_w = buffer("ball_w", 4 * real * cap_balls as u64, storage);
        let out_usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
        let out_t = buffer("out_t", real * cap_out as u64, out_usage);
        let out_code = buffer("out_code", 4 * cap_out as u64, out_usage);
        let read = wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST;
        let read_t = buffer("read_t", real * cap_out as u64, read);
        let read_code = buffer("read_code", 4 * cap_out as u64, read);
        let up = wgpu::BufferUsages::MAP_WRITE | wgpu::BufferUsages::COPY_SRC;
        let up_table_start = buffer("upload table_start", table_start.size(), up);
        let up_ball_state = buffer("upload ball_state", ball_state.size(), up);
        let up_ball_pv = buffer("upload ball_pv", ball_pv.size(), up);
        let up_ball_w = buffer("upload ball_w", ball_w.size(), up);
        let bind = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("kisstime bind group"),
            layout: &self.pipelines.layout,
            entries: &[
                (0, &uniform),
                (1, &table_start),
                (2, &ball_state),
                (3, &ball_pv),
                (4, &ball_w),
                (5, &out_t),
                (6, &out_code),
            ]
            .map(|(binding, buf)| wgpu::BindGroupEntry {
                binding,
                resource: buf.as_entire_binding(),
            }),
        });
        self.bufs = Some(Buffers {
            cap_tables,
            cap_balls,
            cap_out,
            uniform,
            table_start,
            ball_state,
            ball_pv,
            ball_w,
            out_t,
            out_code,
            read_t,
            read_code,
            up_table_start,
            up_ball_state,
            up_ball_pv,
            up_ball_w,
            bind,
        });
    }

    /// Lays out the chunk's tables in `self.host`: table-local positions (the origin is
    /// the centre of each table's bounding box, in f64), narrowed to the shader precision.
    /// The offsets first, then the balls Rayon over blocks of tables.
    pub(super) fn fill_host(&mut self, batch: &Batch, tables: Range<usize>) {
        let prec = self.precision;
        let real = prec.real_size();
        let h = &mut self.host;
        h.table_start.clear();
        let (mut b, mut p) = (0u32, 0u32);
        for k in tables.clone() {
            h.table_start.push([b, p]);
            b += batch.balls(k).len() as u32;
            p += batch.pair_range(k).len() as u32;
        }
        h.table_start.push([b, p]);
        let n_balls = b as usize;
        h.ball_state.resize(n_balls, 0);
        h.ball_pv.resize(4 * real * n_balls, 0);
        h.ball_w.resize(4 * real * n_balls, 0);
        // each block of tables gets its own piece of each array
        let starts = &h.table_start;
        let mut pieces = Vec::new();
        let (mut state, mut pv, mut w) =
            (&mut h.ball_state[..], &mut h.ball_pv[..], &mut h.ball_w[..]);
        for first in (0..tables.len()).step_by(FILL_BLOCK) {
            let end = tables.len().min(first + FILL_BLOCK);
            let n = (starts[end][0] - starts[first][0]) as usize;
            let (s_head, s_tail) = std::mem::take(&mut state).split_at_mut(n);
            let (pv_head, pv_tail) = std::mem::take(&mut pv).split_at_mut(4 * real * n);
            let (w_head, w_tail) = std::mem::take(&mut w).split_at_mut(4 * real * n);
            pieces.push((
                tables.start + first..tables.start + end,
                s_head,
                pv_head,
                w_head,
            ));
            (state, pv, w) = (s_tail, pv_tail, w_tail);
        }
        let put = |out: &mut [u8], v: f64| match prec {
            Precision::F32 => out.copy_from_slice(&(v as f32).to_le_bytes()),
            Precision::F64 => out.copy_from_slice(&v.to_le_bytes()),
        };
        pieces.into_par_iter().for_each(|(block, state, pv, w)| {
            let mut at = 0;
            for k in block {
                let balls = batch.balls(k);
                let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
                for ball in balls {
                    x0 = x0.min(ball.x);
                    x1 = x1.max(ball.x);
                    y0 = y0.min(ball.y);
                    y1 = y1.max(ball.y);
                }
                let (ox, oy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
                for ball in balls {
                    state[at] = ball.state as u32;
                    let pvs = [ball.x - ox, ball.y - oy, ball.vx, ball.vy];
                    let ws = [ball.wx, ball.wy, ball.wz, 0.0];
                    for (c, (v, u)) in pvs.into_iter().zip(ws).enumerate() {
                        let q = (4 * at + c) * real;
                        put(&mut pv[q..q + real], v);
                        put(&mut w[q..q + real], u);
                    }
                    at += 1;
                }
            }
        });
    }
}

/// Tables laid out by one Rayon task.
const FILL_BLOCK: usize = 1024;
