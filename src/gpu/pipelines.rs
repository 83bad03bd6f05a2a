//! The bind-group layout and the two compute pipelines (`pair_times`, `next_collisions`).

use super::device::{AdapterSummary, gpu_error};
use super::shader::shader_source;
use crate::error::Error;
use crate::model::Precision;

/// The compiled shader's pipelines and their bind-group layout (bindings as declared at the
/// top of `shaders/kernels.wgsl`).
pub(super) struct Pipelines {
    pub(super) layout: wgpu::BindGroupLayout,
    pub(super) pairs: wgpu::ComputePipeline,
    pub(super) next: wgpu::ComputePipeline,
}

impl Pipelines {
    /// Compiles the shader for `precision` and builds both pipelines; a shader that does
    /// not validate on this adapter is an [`Error::Gpu`] naming it.
    pub(super) fn build(
        device: &wgpu::Device,
        precision: Precision,
        summary: &AdapterSummary,
    ) -> Result<Pipelines, Error> {
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("kisstime kernels"),
            source: wgpu::ShaderSource::Wgsl(shader_source(precision).into()),
        });
        let storage = |binding: u32, read_only: bool| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("kisstime bindings"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                storage(1, true),
                storage(2, true),
                storage(3, true),
                storage(4, true),
                storage(5, false),
                storage(6, false),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("kisstime layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = |entry: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let pipe_pairs = pipeline("pair_times");
        let pipe_next = pipeline("next_collisions");
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(gpu_error(format!(
                "the {} shader does not build on {}: {e}",
                precision.name(),
                summary.name
            )));
        }
        Ok(Pipelines {
            layout,
            pairs: pipe_pairs,
            next: pipe_next,
        })
    }
}
