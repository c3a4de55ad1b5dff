//! How the renderer's passes are built: the render pipeline every pass
//! uses (and the particle pipeline, blended as configured), bind group
//! layout entries and bind groups of whole buffers, and the depth test.
//! The splat's compute pass shares the bindings and depth state.

use super::config::{Blend, RendererConfig};
use super::target::DEPTH_FORMAT;
use crate::device::entry;

/// The particle passes' binding: the uniforms (the records come as
/// instance vertex buffers, which WebGL2 has too).
pub(crate) fn particle_layout_entries() -> [wgpu::BindGroupLayoutEntry; 1] {
    [entry(
        0,
        wgpu::ShaderStages::VERTEX_FRAGMENT,
        wgpu::BufferBindingType::Uniform,
    )]
}

/// The particle pipeline drawing through `vertex_entry` (`vs_main`: lerp,
/// `vs_hermite`: Hermite) with `config`'s blend and samples.
pub(crate) fn particle_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    shader: &wgpu::ShaderModule,
    vertex_entry: &str,
    buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
    format: wgpu::TextureFormat,
    config: &RendererConfig,
) -> wgpu::RenderPipeline {
    let multisample = wgpu::MultisampleState {
        count: config.samples,
        mask: !0,
        alpha_to_coverage_enabled: false,
    };
    let blend = match config.blend {
        Blend::Alpha => wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING,
        Blend::Additive => wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            },
            alpha: wgpu::BlendComponent::OVER,
        },
    };
    pipeline(
        device,
        layout,
        shader,
        vertex_entry,
        buffers,
        wgpu::PrimitiveTopology::TriangleStrip,
        format,
        blend,
        config.blend == Blend::Alpha,
        multisample,
    )
}

/// Depth test (less or equal) with or without writes.
pub(crate) fn depth_state(write: bool) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(write),
        depth_compare: Some(wgpu::CompareFunction::LessEqual),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// A render pipeline of `shader`'s `vertex_entry` and `fs_main` over one
/// bind group `layout`, drawing `topology` into `format` with `blend`, the
/// depth test (writing with `depth_write`) and `multisample`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    shader: &wgpu::ShaderModule,
    vertex_entry: &str,
    buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
    topology: wgpu::PrimitiveTopology,
    format: wgpu::TextureFormat,
    blend: wgpu::BlendState,
    depth_write: bool,
    multisample: wgpu::MultisampleState,
) -> wgpu::RenderPipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: None,
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: None,
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module: shader,
            entry_point: Some(vertex_entry),
            compilation_options: Default::default(),
            buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology,
            ..Default::default()
        },
        depth_stencil: Some(depth_state(depth_write)),
        multisample,
        fragment: Some(wgpu::FragmentState {
            module: shader,
            entry_point: Some("fs_main"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format,
                blend: Some(blend),
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}
