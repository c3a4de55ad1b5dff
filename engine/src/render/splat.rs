//! The compute splat path: many small particles in a 2D view drawn by one
//! compute invocation each instead of one quad each (see
//! `engine/shaders/splat.wgsl` for the method and why). In Hermite mode the
//! splat places the discs by the same `hermite_from_end` as the quads, from
//! a second bind group that adds the velocities (built on first use).

use super::config::Blend;
use super::pipeline::depth_state;
use crate::device::{bind_buffers, entry, wgsl};

/// Largest drawn radius in pixels the splat path handles (as in the shader).
pub(crate) const SPLAT_MAX_RADIUS: f32 = 4.0;

/// Particles per workgroup (as in the shader).
const WORKGROUP: u32 = 64;

/// Pipelines and the per-pixel owner buffer of the splat path.
pub(crate) struct Splat {
    compute_layout: wgpu::BindGroupLayout,
    /// The compute layout plus the velocities at binding 3 (Hermite mode).
    hermite_layout: wgpu::BindGroupLayout,
    /// splat.wgsl, kept for the Hermite pipeline.
    compute_module: wgpu::ShaderModule,
    /// `splat_hermite` or `splat_additive_hermite`, from the first Hermite frame.
    hermite: Option<wgpu::ComputePipeline>,
    additive: bool,
    composite_layout: wgpu::BindGroupLayout,
    compute: wgpu::ComputePipeline,
    resolve: wgpu::ComputePipeline,
    composite: wgpu::RenderPipeline,
    /// Words per pixel in the owner buffer: 1 (owner key) or 3 (additive sums).
    words: u64,
    /// Owner buffer, its size, and the bind groups over it.
    state: Option<SplatState>,
}

struct SplatState {
    size: (u32, u32),
    owners: wgpu::Buffer,
    /// Final pixels, rows padded to 256 bytes, for the copy into the target.
    pixels: wgpu::Buffer,
    /// Bytes per padded row.
    row_bytes: u32,
    compute_group: wgpu::BindGroup,
    /// The compute group plus the velocities, in Hermite mode.
    hermite_group: Option<wgpu::BindGroup>,
    composite_group: wgpu::BindGroup,
}

impl Splat {
    pub(crate) fn new(device: &wgpu::Device, format: wgpu::TextureFormat, blend: Blend) -> Self {
        let additive = blend == Blend::Additive;
        use wgpu::BufferBindingType::{Storage, Uniform};
        use wgpu::ShaderStages as S;
        // Uniforms, records, owners; Hermite adds the velocities.
        let compute_entries = [
            entry(0, S::COMPUTE, Uniform),
            entry(1, S::COMPUTE, Storage { read_only: true }),
            entry(2, S::COMPUTE, Storage { read_only: false }),
            entry(3, S::COMPUTE, Storage { read_only: true }),
        ];
        let compute_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tickwork splat"),
            entries: &compute_entries[..3],
        });
        let hermite_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tickwork splat (Hermite)"),
            entries: &compute_entries,
        });
        let composite_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tickwork splat composite"),
            entries: &[
                entry(0, S::FRAGMENT | S::COMPUTE, Uniform),
                entry(1, S::FRAGMENT | S::COMPUTE, Storage { read_only: true }),
                entry(2, S::FRAGMENT | S::COMPUTE, Storage { read_only: true }),
                entry(3, S::COMPUTE, Storage { read_only: false }),
            ],
        });
        let compute_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("splat.wgsl"),
            source: wgpu::ShaderSource::Wgsl(wgsl!("common.wgsl", "splat.wgsl").into()),
        });
        let composite_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("splat_composite.wgsl"),
            source: wgpu::ShaderSource::Wgsl(wgsl!("common.wgsl", "splat_composite.wgsl").into()),
        });
        let compute_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &[Some(&compute_layout)],
            immediate_size: 0,
        });
        let composite_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &[Some(&composite_layout)],
            immediate_size: 0,
        });
        let compute_entry = |layout, module, entry: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("tickwork splat"),
                layout: Some(layout),
                module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let compute = compute_entry(
            &compute_pipeline_layout,
            &compute_module,
            if additive { "splat_additive" } else { "splat" },
        );
        let resolve = compute_entry(
            &composite_pipeline_layout,
            &composite_module,
            if additive { "resolve_additive" } else { "resolve" },
        );
        let composite = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("tickwork splat composite"),
            layout: Some(&composite_pipeline_layout),
            vertex: wgpu::VertexState {
                module: &composite_module,
                entry_point: Some("vs_fullscreen"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(depth_state(false)),
            // Splat frames are single-sampled (see Renderer::encode).
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &composite_module,
                entry_point: Some(if additive {
                    "fs_composite_additive"
                } else {
                    "fs_composite"
                }),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: Some(if additive {
                        wgpu::BlendState {
                            color: wgpu::BlendComponent {
                                src_factor: wgpu::BlendFactor::One,
                                dst_factor: wgpu::BlendFactor::One,
                                operation: wgpu::BlendOperation::Add,
                            },
                            alpha: wgpu::BlendComponent::OVER,
                        }
                    } else {
                        wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING
                    }),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        Self {
            compute_layout,
            hermite_layout,
            compute_module,
            hermite: None,
            additive,
            composite_layout,
            compute,
            resolve,
            composite,
            words: if additive { 3 } else { 1 },
            state: None,
        }
    }

    /// Forgets the bind groups (the instance buffer was replaced).
    pub(crate) fn invalidate(&mut self) {
        self.state = None;
    }

    /// Makes the owner buffer match the target size, and with `velocities`
    /// (Hermite mode) the Hermite pipeline and bind group exist.
    pub(crate) fn resize(
        &mut self,
        gpu: &super::Gpu,
        width: u32,
        height: u32,
        globals: &wgpu::Buffer,
        instances: &wgpu::Buffer,
        velocities: Option<&wgpu::Buffer>,
    ) {
        if velocities.is_some() {
            self.prepare_hermite(&gpu.device);
        }
        if self.state.as_ref().is_some_and(|s| s.size == (width, height)) {
            if let (Some(velocities), Some(state)) = (velocities, &mut self.state)
                && state.hermite_group.is_none()
            {
                state.hermite_group = Some(bind_buffers(
                    &gpu.device,
                    &self.hermite_layout,
                    &[globals, instances, &state.owners, velocities],
                ));
            }
            return;
        }
        // Rows of owners and pixels are both padded to 256 bytes.
        let row_bytes = (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let owners = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("tickwork splat owners"),
            size: u64::from(row_bytes) * u64::from(height) * self.words,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let pixels = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("tickwork splat pixels"),
            size: u64::from(row_bytes) * u64::from(height),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        self.state = Some(SplatState {
            size: (width, height),
            compute_group: bind_buffers(&gpu.device, &self.compute_layout, &[globals, instances, &owners]),
            hermite_group: velocities.map(|velocities| {
                bind_buffers(
                    &gpu.device,
                    &self.hermite_layout,
                    &[globals, instances, &owners, velocities],
                )
            }),
            composite_group: bind_buffers(
                &gpu.device,
                &self.composite_layout,
                &[globals, instances, &owners, &pixels],
            ),
            owners,
            pixels,
            row_bytes,
        });
    }

    /// Builds the Hermite pipeline the first time it is needed.
    fn prepare_hermite(&mut self, device: &wgpu::Device) {
        if self.hermite.is_some() {
            return;
        }
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &[Some(&self.hermite_layout)],
            immediate_size: 0,
        });
        self.hermite = Some(device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("tickwork splat (Hermite)"),
            layout: Some(&layout),
            module: &self.compute_module,
            entry_point: Some(if self.additive {
                "splat_additive_hermite"
            } else {
                "splat_hermite"
            }),
            compilation_options: Default::default(),
            cache: None,
        }));
    }

    /// Clears the owners and splats `count` particles, placed by
    /// `hermite_from_end` if `hermite` (after a [`resize`](Self::resize)
    /// given the velocities), else by lerp.
    pub(crate) fn encode_compute(&self, encoder: &mut wgpu::CommandEncoder, count: u32, hermite: bool) {
        let Some(state) = &self.state else {
            return;
        };
        let (pipeline, group) = if hermite {
            match (&self.hermite, &state.hermite_group) {
                (Some(pipeline), Some(group)) => (pipeline, group),
                _ => return,
            }
        } else {
            (&self.compute, &state.compute_group)
        };
        encoder.clear_buffer(&state.owners, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("tickwork splat"),
            timestamp_writes: None,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, group, &[]);
        // Sixteen particles per invocation (as in the shader).
        dispatch(&mut pass, count.div_ceil(16));
    }

    /// Words per padded row of the pixel buffer (for the shader), once sized.
    pub(crate) fn stride(&self) -> u32 {
        self.state.as_ref().map_or(0, |s| s.row_bytes / 4)
    }

    /// Resolves the final pixels (over the background) and copies them into
    /// `texture`, which must accept copies and match the size.
    pub(crate) fn encode_resolve(&self, encoder: &mut wgpu::CommandEncoder, texture: &wgpu::Texture) {
        let Some(state) = &self.state else {
            return;
        };
        let (width, height) = state.size;
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("tickwork splat resolve"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.resolve);
            pass.set_bind_group(0, &state.composite_group, &[]);
            // One invocation per 16 elements of four pixels (as in the shader).
            dispatch(&mut pass, (state.row_bytes / 16 * height).div_ceil(16));
        }
        encoder.copy_buffer_to_texture(
            wgpu::TexelCopyBufferInfo {
                buffer: &state.pixels,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(state.row_bytes),
                    rows_per_image: Some(height),
                },
            },
            texture.as_image_copy(),
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
    }

    /// Composites the owners over what the pass has drawn so far.
    pub(crate) fn encode_composite(&self, pass: &mut wgpu::RenderPass<'_>) {
        let Some(state) = &self.state else {
            return;
        };
        pass.set_pipeline(&self.composite);
        pass.set_bind_group(0, &state.composite_group, &[]);
        pass.draw(0..3, 0..1);
    }
}

/// Dispatches `invocations` in workgroups of 64, at most 65 535 workgroups
/// per dimension (wrapped into y, as the shaders expect).
fn dispatch(pass: &mut wgpu::ComputePass<'_>, invocations: u32) {
    let groups = invocations.div_ceil(WORKGROUP);
    pass.dispatch_workgroups(groups.min(65_535), groups.div_ceil(65_535).max(1), 1);
}
