//! Drawing a frame's sprites: their vertices (two triangles a sprite,
//! built on the CPU), one texture and bind group per image, uploaded the
//! first frame it is drawn and dropped the first frame it is not, and the
//! pipeline that samples them.

use std::ops::Range;

use bytemuck::{Pod, Zeroable};

use super::line_vertices::vertex_buffer_of;
use super::pipeline::depth_state;
use super::sprite::Sprite;
use super::{Gpu, RenderError};
use crate::device::wgsl;

/// One sprite vertex as the shader reads it (24 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct SpriteVertex {
    position: [f32; 3],
    uv: [f32; 2],
    tint: [u8; 4],
}

/// An uploaded texture: its identity, its GPU texture, a bind group per
/// sampler (nearest, linear), and whether this frame drew it.
struct Uploaded {
    id: u64,
    _texture: wgpu::Texture,
    bind_groups: [wgpu::BindGroup; 2],
    used: bool,
}

/// The sprites' pipelines, samplers, uploaded textures and vertices.
pub(crate) struct Sprites {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    pipeline_single: wgpu::RenderPipeline,
    samplers: [wgpu::Sampler; 2],
    uploaded: Vec<Uploaded>,
    vertices: Vec<SpriteVertex>,
    buffer: wgpu::Buffer,
    /// Per sprite of the frame, the index of its bind group in `uploaded`
    /// and which sampler.
    bindings: Vec<(usize, usize)>,
}

impl Sprites {
    /// Pipelines drawing into `format` with `samples` (and single-sampled),
    /// the globals bound at group 0 through `globals_layout`.
    pub(crate) fn new(
        device: &wgpu::Device,
        globals_layout: &wgpu::BindGroupLayout,
        format: wgpu::TextureFormat,
        samples: u32,
    ) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tickwork sprite texture"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("sprites.wgsl"),
            source: wgpu::ShaderSource::Wgsl(wgsl!("common.wgsl", "sprites.wgsl").into()),
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("tickwork sprites"),
            bind_group_layouts: &[Some(globals_layout), Some(&layout)],
            immediate_size: 0,
        });
        let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x2, 2 => Unorm8x4];
        let pipeline_for = |count: u32| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("tickwork sprites"),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: std::mem::size_of::<SpriteVertex>() as u64,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &attributes,
                    })],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: Some(depth_state(false)),
                multisample: wgpu::MultisampleState {
                    count,
                    mask: !0,
                    alpha_to_coverage_enabled: false,
                },
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let sampler = |filter: wgpu::FilterMode| {
            device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("tickwork sprites"),
                mag_filter: filter,
                min_filter: filter,
                ..Default::default()
            })
        };
        Self {
            pipeline: pipeline_for(samples),
            pipeline_single: pipeline_for(1),
            layout,
            samplers: [sampler(wgpu::FilterMode::Nearest), sampler(wgpu::FilterMode::Linear)],
            uploaded: Vec::new(),
            vertices: Vec::new(),
            buffer: vertex_buffer_of::<SpriteVertex>(device, 64),
            bindings: Vec::new(),
        }
    }

    /// The frame's sprites as vertices, their textures uploaded (those no
    /// sprite drew are dropped).
    ///
    /// # Errors
    /// [`RenderError::Config`] naming a sprite that is not finite, or whose
    /// region is not part of its texture.
    pub(crate) fn prepare(&mut self, gpu: &Gpu, sprites: &[Sprite]) -> Result<(), RenderError> {
        self.vertices.clear();
        self.bindings.clear();
        for uploaded in &mut self.uploaded {
            uploaded.used = false;
        }
        for (k, sprite) in sprites.iter().enumerate() {
            let corners = sprite
                .corners()
                .map_err(|problem| RenderError::Config(format!("sprite {k} of the frame: {problem}")))?;
            let tint = sprite.tint;
            let vertex = |(at, uv): (glam::Vec2, glam::Vec2)| SpriteVertex {
                position: [at.x, at.y, 0.0],
                uv: uv.to_array(),
                tint,
            };
            for corner in [0, 1, 2, 0, 2, 3] {
                self.vertices.push(vertex(corners[corner]));
            }
            let index = self.upload(gpu, &sprite.texture);
            self.bindings.push((index, usize::from(sprite.smooth)));
        }
        self.uploaded.retain(|u| u.used);
        // Indices may have moved with the retain: found again by identity.
        for (binding, sprite) in self.bindings.iter_mut().zip(sprites) {
            binding.0 = self
                .uploaded
                .iter()
                .position(|u| u.id == sprite.texture.id())
                .unwrap_or_else(|| unreachable!("drawn this frame, so kept"));
        }
        if !self.vertices.is_empty() {
            let bytes: &[u8] = bytemuck::cast_slice(&self.vertices);
            if bytes.len() as u64 > self.buffer.size() {
                self.buffer = vertex_buffer_of::<SpriteVertex>(&gpu.device, self.vertices.len().next_power_of_two());
            }
            gpu.queue.write_buffer(&self.buffer, 0, bytes);
        }
        Ok(())
    }

    /// The index of `texture`'s upload, uploading it if new; marks it used.
    fn upload(&mut self, gpu: &Gpu, texture: &super::texture::Texture) -> usize {
        if let Some(k) = self.uploaded.iter().position(|u| u.id == texture.id()) {
            self.uploaded[k].used = true;
            return k;
        }
        let size = wgpu::Extent3d {
            width: texture.width(),
            height: texture.height(),
            depth_or_array_layers: 1,
        };
        let gpu_texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("tickwork sprite"),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        gpu.queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &gpu_texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            texture.pixels(),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(texture.width() * 4),
                rows_per_image: Some(texture.height()),
            },
            size,
        );
        let view = gpu_texture.create_view(&wgpu::TextureViewDescriptor::default());
        let bind_groups = self.samplers.each_ref().map(|sampler| {
            gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("tickwork sprite"),
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::Sampler(sampler),
                    },
                ],
            })
        });
        self.uploaded.push(Uploaded {
            id: texture.id(),
            _texture: gpu_texture,
            bind_groups,
            used: true,
        });
        self.uploaded.len() - 1
    }

    /// Draws sprites `range` of the frame, a run of the same texture and
    /// sampler per draw call (globals bound at group 0 already).
    pub(crate) fn draw(&self, pass: &mut wgpu::RenderPass<'_>, range: Range<usize>, single: bool) {
        let range = range.start.min(self.bindings.len())..range.end.min(self.bindings.len());
        if range.is_empty() {
            return;
        }
        pass.set_pipeline(if single { &self.pipeline_single } else { &self.pipeline });
        pass.set_vertex_buffer(0, self.buffer.slice(..));
        let mut start = range.start;
        while start < range.end {
            let binding = self.bindings[start];
            let end = (start..range.end)
                .find(|&k| self.bindings[k] != binding)
                .unwrap_or(range.end);
            pass.set_bind_group(1, &self.uploaded[binding.0].bind_groups[binding.1], &[]);
            let vertices = |k: usize| u32::try_from(k * 6).unwrap_or(u32::MAX);
            pass.draw(vertices(start)..vertices(end), 0..1);
            start = end;
        }
    }
}
