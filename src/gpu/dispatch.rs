//! Chunking, and one chunk's upload, dispatch and readback; kernel-only timing.

use std::ops::Range;

use rayon::prelude::*;

use super::device::{PassTimer, Scopes, copy_to_mapped, gpu_error, map_and_wait};
use super::{GpuEngine, Precision};
use crate::batch::Batch;
use crate::error::Error;
use crate::model::Params;

/// Which kernel a call runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    /// `pair_times`: every pair's answer.
    PairTimes,
    /// `next_collisions`: each table's next collision.
    NextCollisions,
}

/// The dispatch grid and result sizes of one chunk.
struct Grid {
    /// Results: one per pair or one per table.
    n_out: usize,
    /// Workgroups per row and rows (one workgroup per table).
    row_len: u32,
    rows: u32,
    /// Bytes of the times and of the codes to read back.
    bytes_t: u64,
    bytes_code: u64,
    /// Bytes of each upload buffer to copy: table_start, ball_state, ball_pv, ball_w.
    uploads: [u64; 4],
}

impl GpuEngine {
    /// Cuts the tables `tables` of the batch into chunks of whole tables within the limits.
    pub(super) fn plan_chunks(
        &self,
        batch: &Batch,
        tables: Range<usize>,
    ) -> Result<Vec<Range<usize>>, Error> {
        let mut chunks = Vec::new();
        let mut first = tables.start;
        while first < tables.end {
            let (mut balls, mut pairs, mut end) = (0, 0, first);
            while end < tables.end && end - first < self.limits.tables {
                let nb = batch.balls(end).len();
                let np = batch.pair_range(end).len();
                if balls + nb > self.limits.balls || pairs + np > self.limits.pairs {
                    break;
                }
                balls += nb;
                pairs += np;
                end += 1;
            }
            if end == first {
                return Err(gpu_error(format!(
                    "table {} has {} balls, more than one GPU dispatch can hold",
                    batch.table_id(first),
                    batch.balls(first).len()
                )));
            }
            chunks.push(first..end);
            first = end;
        }
        Ok(chunks)
    }

    /// Runs `kernel` on one chunk and returns the raw `(t, code)` results: upload, dispatch
    /// and wait, read back (each step timed into [`GpuEngine::timings`]).
    pub(super) fn run_chunk(
        &mut self,
        batch: &Batch,
        tables: Range<usize>,
        kernel: Kernel,
        params: &Params,
    ) -> Result<(Vec<f64>, Vec<u32>), Error> {
        if let Some(e) = self.watch.fault() {
            return Err(e);
        }
        let clock = std::time::Instant::now();
        let grid = self.upload(batch, tables, kernel, params)?;
        self.timings.upload += clock.elapsed().as_secs_f64();

        let clock = std::time::Instant::now();
        if let Some(seconds) = self.dispatch_and_map(kernel, &grid)? {
            *self.timings.kernel_device.get_or_insert(0.0) += seconds;
        }
        self.timings.kernel += clock.elapsed().as_secs_f64();

        let clock = std::time::Instant::now();
        let results = self.read_results(&grid);
        self.timings.readback += clock.elapsed().as_secs_f64();
        results
    }

    /// Lays out the chunk's tables, makes sure the buffers hold them, and writes them and
    /// the uniforms to the device.
    fn upload(
        &mut self,
        batch: &Batch,
        tables: Range<usize>,
        kernel: Kernel,
        params: &Params,
    ) -> Result<Grid, Error> {
        let n_tables = tables.len();
        self.fill_host(batch, tables);
        let n_balls = self.host.ball_state.len();
        let n_pairs = self.host.table_start[n_tables][1] as usize;
        let n_out = match kernel {
            Kernel::PairTimes => n_pairs,
            Kernel::NextCollisions => n_tables,
        };
        self.ensure_buffers(n_tables, n_balls, n_out);
        // one workgroup per table, in rows of at most the adapter's limit
        #[cfg_attr(not(feature = "testing"), allow(unused_mut))]
        let mut row_len = (n_tables as u32).min(self.max_groups_per_dim).max(1);
        #[cfg(feature = "testing")]
        self.apply_pending_fault(&mut row_len);
        let rows = (n_tables as u32)
            .div_ceil(row_len.min(self.max_groups_per_dim))
            .max(1);
        // the uniforms, as `Uniforms` in shaders/kernels.wgsl
        let mut uniform = Vec::with_capacity(64);
        for v in [params.radius, params.mu_s, params.mu_r, params.g] {
            match self.precision {
                Precision::F32 => uniform.extend_from_slice(&(v as f32).to_le_bytes()),
                Precision::F64 => uniform.extend_from_slice(&v.to_le_bytes()),
            }
        }
        uniform.extend_from_slice(&(n_tables as u32).to_le_bytes());
        uniform.extend_from_slice(&row_len.to_le_bytes());
        uniform.resize(64, 0);
        let bufs = self.bufs.as_ref().expect("buffers were just ensured");
        self.queue.write_buffer(&bufs.uniform, 0, &uniform);
        // the arrays into the mapped upload buffers (copied to the storage buffers at the
        // start of the dispatch's submission)
        let h = &self.host;
        let arrays: [(&wgpu::Buffer, &[u8]); 4] = [
            (&bufs.up_table_start, bytemuck::cast_slice(&h.table_start)),
            (&bufs.up_ball_state, bytemuck::cast_slice(&h.ball_state)),
            (&bufs.up_ball_pv, &h.ball_pv),
            (&bufs.up_ball_w, &h.ball_w),
        ];
        let nonempty: Vec<(&wgpu::Buffer, &[u8])> =
            arrays.into_iter().filter(|(_, a)| !a.is_empty()).collect();
        copy_to_mapped(&self.device, &nonempty)?;
        let real = self.precision.real_size() as u64;
        Ok(Grid {
            n_out,
            row_len,
            rows,
            bytes_t: (real * n_out as u64).max(4),
            bytes_code: (4 * n_out as u64).max(4),
            uploads: [
                h.table_start.len() as u64 * 8,
                h.ball_state.len() as u64 * 4,
                h.ball_pv.len() as u64,
                h.ball_w.len() as u64,
            ],
        })
    }

    /// Dispatches `kernel` over `grid`, copies the results to the readback buffers, maps
    /// them and waits; returns the pass's seconds on the device's clock where the adapter
    /// has timestamps. Any failure (validation, out of memory, a lost device, a failed map)
    /// is an error, and no buffer is left mapped then.
    fn dispatch_and_map(&self, kernel: Kernel, grid: &Grid) -> Result<Option<f64>, Error> {
        let bufs = self.bufs.as_ref().expect("upload made the buffers");
        let scopes = Scopes::push(&self.device);
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("kisstime"),
            });
        let ups = [
            (&bufs.up_table_start, &bufs.table_start),
            (&bufs.up_ball_state, &bufs.ball_state),
            (&bufs.up_ball_pv, &bufs.ball_pv),
            (&bufs.up_ball_w, &bufs.ball_w),
        ];
        for ((up, storage), len) in ups.into_iter().zip(grid.uploads) {
            if len > 0 {
                encoder.copy_buffer_to_buffer(up, 0, storage, 0, len);
            }
        }
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("kisstime"),
                timestamp_writes: self.timer.as_ref().map(PassTimer::writes),
            });
            pass.set_pipeline(self.pipeline(kernel));
            pass.set_bind_group(0, &bufs.bind, &[]);
            pass.dispatch_workgroups(grid.row_len, grid.rows, 1);
        }
        let (bytes_t, bytes_code) = (grid.bytes_t, grid.bytes_code);
        encoder.copy_buffer_to_buffer(&bufs.out_t, 0, &bufs.read_t, 0, bytes_t);
        encoder.copy_buffer_to_buffer(&bufs.out_code, 0, &bufs.read_code, 0, bytes_code);
        let mut mapped = vec![(&bufs.read_t, bytes_t), (&bufs.read_code, bytes_code)];
        if let Some(timer) = &self.timer {
            mapped.push(timer.resolve(&mut encoder));
        }
        self.queue.submit([encoder.finish()]);
        map_and_wait(
            &self.device,
            scopes,
            &self.watch,
            &mapped,
            "the GPU dispatch",
        )?;
        // the pass on the device's clock, where it has one
        let Some(timer) = &self.timer else {
            return Ok(None);
        };
        let seconds = timer.seconds();
        if seconds.is_err() {
            bufs.read_t.unmap();
            bufs.read_code.unmap();
        }
        seconds.map(Some)
    }

    /// Converts the grid's mapped results to f64 times and codes, and unmaps the buffers.
    fn read_results(&self, grid: &Grid) -> Result<(Vec<f64>, Vec<u32>), Error> {
        let n_out = grid.n_out;
        let bufs = self.bufs.as_ref().expect("upload made the buffers");
        let read_error = |e| gpu_error(format!("reading results back from the GPU failed: {e}"));
        let t: Vec<f64> = {
            let view = bufs
                .read_t
                .slice(..grid.bytes_t)
                .get_mapped_range()
                .map_err(read_error)?;
            match self.precision {
                Precision::F32 => view[..4 * n_out]
                    .par_chunks_exact(4)
                    .map(|c| f32::from_le_bytes(c.try_into().unwrap()) as f64)
                    .collect(),
                Precision::F64 => view[..8 * n_out]
                    .par_chunks_exact(8)
                    .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                    .collect(),
            }
        };
        let code: Vec<u32> = {
            let view = bufs
                .read_code
                .slice(..grid.bytes_code)
                .get_mapped_range()
                .map_err(read_error)?;
            view[..4 * n_out]
                .par_chunks_exact(4)
                .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
                .collect()
        };
        bufs.read_t.unmap();
        bufs.read_code.unmap();
        Ok((t, code))
    }

    /// The pipeline of `kernel`.
    fn pipeline(&self, kernel: Kernel) -> &wgpu::ComputePipeline {
        match kernel {
            Kernel::PairTimes => &self.pipelines.pairs,
            Kernel::NextCollisions => &self.pipelines.next,
        }
    }

    /// Kernel-only timing for benchmarks: uploads `batch` (which must fit one chunk), runs
    /// `kernel` once to warm up, then submits it `iters` times back to back with the data
    /// resident and returns the wall time from the first submit until the last finished.
    pub fn time_kernel(
        &mut self,
        batch: &Batch,
        params: &Params,
        kernel: Kernel,
        iters: u64,
    ) -> Result<std::time::Duration, Error> {
        let chunks = self.plan_chunks(batch, 0..batch.num_tables())?;
        if chunks.len() != 1 {
            return Err(gpu_error(format!(
                "time_kernel needs a batch that fits one chunk, this one needs {}",
                chunks.len()
            )));
        }
        let n_tables = batch.num_tables() as u32;
        self.run_chunk(batch, chunks[0].clone(), kernel, params)?;
        let row_len = n_tables.min(self.max_groups_per_dim).max(1);
        let rows = n_tables.div_ceil(row_len).max(1);
        let bufs = self.bufs.as_ref().expect("run_chunk made the buffers");
        let pipeline = self.pipeline(kernel);
        let start = std::time::Instant::now();
        for _ in 0..iters {
            let mut encoder = self
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: None,
                    timestamp_writes: None,
                });
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &bufs.bind, &[]);
                pass.dispatch_workgroups(row_len, rows, 1);
            }
            self.queue.submit([encoder.finish()]);
        }
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| gpu_error(format!("waiting for the GPU failed: {e}")))?;
        if let Some(e) = self.watch.fault() {
            return Err(e);
        }
        Ok(start.elapsed())
    }
}
