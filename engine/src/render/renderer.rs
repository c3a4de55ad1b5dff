//! The renderer: pipelines and buffers that turn a world's previous and
//! current columns into a frame.
//!
//! Per frame it uploads, only when the world changed since the last upload,
//! one 32-byte record per particle (previous position, radius, current
//! position, colour: `records.rs`); the vertex shader interpolates with the frame's
//! alpha, so a frame without a fixed step uploads nothing but a uniform.
//! In [`Interpolation::Hermite`] mode a 12-byte velocity per particle goes
//! into a second buffer too (see `hermite.rs`).
//! Lines (springs, trails, rigid-body boxes, a game's own) are few and built
//! on the CPU (`line_vertices.rs`). The pipelines are built by
//! `pipeline.rs`.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use std::ops::Range;

use super::camera::{CameraMatrices, FrameRect};
use super::config::RendererConfig;
use super::frame_view::FrameView;
use super::hermite::HermiteParticles;
use super::hud::Hud;
use super::line_vertices::{LineVertex, upload_vertices, vertex_buffer};
use super::overlay::{PlacedText, Shapes, TextUnit};
use super::pipeline::{bind_buffers, particle_layout_entries, particle_pipeline, pipeline};
use super::records::{Instance, hide_instances, instance_block, instance_buffer_layout, record_buffer, write_records};
use super::splat::{SPLAT_MAX_RADIUS, Splat};
use super::sprites::Sprites;
use super::target::FrameBuffers;
use super::{Gpu, RenderError};
use crate::interpolation::Interpolation;

/// Uniforms shared by every pipeline (128 bytes, as in the WGSL `Globals`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Globals {
    view_proj: [[f32; 4]; 4],
    viewport: [f32; 2],
    pixels_per_unit: f32,
    t: f32,
    min_radius_px: f32,
    /// Particles drawn (read by the splat pass).
    count: u32,
    /// Words per row of the splat's pixel buffer.
    stride: u32,
    /// 1 for BGRA targets (the splat packs pixels itself).
    swap_rb: u32,
    /// Clear colour, linear RGBA.
    background: [f32; 4],
    /// Clear colour packed as the target stores it (sRGB bytes, RGBA or BGRA).
    background_word: u32,
    /// The fixed step in seconds, in Hermite mode (0 otherwise).
    dt: f32,
    _pad: [u32; 2],
}

/// Pipelines, GPU buffers and CPU scratch for drawing frames. One renderer
/// draws into targets of one colour format and sample count.
pub struct Renderer {
    config: RendererConfig,
    format: wgpu::TextureFormat,
    globals: wgpu::Buffer,
    particle_pipeline: wgpu::RenderPipeline,
    particle_layout: wgpu::BindGroupLayout,
    /// The particle shader, kept for the Hermite pipeline, built on demand.
    particle_shader: wgpu::ShaderModule,
    /// Hermite mode's velocities and pipeline, from the first Hermite frame.
    hermite: Option<HermiteParticles>,
    /// This frame is drawn in Hermite mode.
    hermite_active: bool,
    instances: wgpu::Buffer,
    particle_bind_group: wgpu::BindGroup,
    instance_count: u32,
    line_pipeline: wgpu::RenderPipeline,
    /// Lines in single-sampled frames (the splat path).
    line_pipeline_single: wgpu::RenderPipeline,
    line_bind_group: wgpu::BindGroup,
    line_buffer: wgpu::Buffer,
    line_count: u32,
    line_scratch: Vec<LineVertex>,
    triangle_pipeline: wgpu::RenderPipeline,
    /// Triangles in single-sampled frames (the splat path).
    triangle_pipeline_single: wgpu::RenderPipeline,
    triangle_buffer: wgpu::Buffer,
    triangle_count: u32,
    triangle_scratch: Vec<LineVertex>,
    /// The worlds' lines (outlines, trails, springs): the first vertices of
    /// `line_buffer`, drawn with the particles.
    world_line_vertices: u32,
    /// The game's shapes in drawing order (by layer, then as drawn).
    shape_calls: Vec<ShapeCall>,
    /// The worlds are drawn after the shapes of this layer, but those with
    /// their own.
    particle_layer: i32,
    /// Each world of the frame: its layer, its instances and its lines.
    world_draws: Vec<WorldDraw>,
    /// The layers the worlds are drawn on, lowest first, each once.
    world_layers: Vec<i32>,
    /// The CPU worlds' records in `instances` (the GPU worlds' follow).
    cpu_instances: u32,
    /// The largest radius among the CPU worlds' particles.
    cpu_max_radius: f32,
    /// GPU worlds' particles into `instances`, made at the first frame
    /// that has one.
    gather: Option<super::gather::Gather>,
    /// Where a letterboxed camera draws (`None`: the whole frame).
    letterbox: Option<FrameRect>,
    /// The game's sprites.
    sprites: Sprites,
    /// Where this frame draws, as a scissor `[x, y, width, height]` (the
    /// letterbox's rectangle, or the whole frame).
    frame_scissor: [u32; 4],
    /// This frame's size in pixels.
    frame_size: (u32, u32),
    /// The frame's texts in pixels, for the HUD.
    placed_texts: Vec<PlacedText>,
    /// How many of the frame's texts before each (and all of them, last)
    /// were placed: what maps a run of texts to its placed ones.
    placed_before: Vec<usize>,
    /// The frame's runs of texts, in the texts' indices until they are
    /// placed, then in the placed texts': one text draw call each.
    text_runs: Vec<Range<usize>>,
    /// The runs as merged (see `merge_text_runs`), reused.
    merged_runs: Vec<Range<usize>>,
    instance_scratch: Vec<Instance>,
    /// The world states last uploaded: (world id, revision) of each world.
    uploaded: Vec<(u64, u64)>,
    /// This frame's (world id, revision) pairs, compared with `uploaded`.
    upload_key: Vec<(u64, u64)>,
    /// Largest particle radius in the last upload (world units).
    max_radius: f32,
    /// `None` where the device has no compute (WebGL2).
    splat: Option<Splat>,
    /// `config.splat_threshold`, or the adapter's default.
    splat_threshold: usize,
    splat_active: bool,
    hud: Hud,
}

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Renderer")
            .field("config", &self.config)
            .field("format", &self.format)
            .field("instances", &self.instance_count)
            .finish_non_exhaustive()
    }
}

impl Renderer {
    /// A renderer for targets of `format` (e.g. [`super::OFFSCREEN_FORMAT`],
    /// or a window surface's format).
    ///
    /// # Errors
    /// [`RenderError::Config`] for a sample count other than 1 or 4 or a
    /// non-finite minimum radius.
    pub fn new(gpu: &Gpu, format: wgpu::TextureFormat, config: RendererConfig) -> Result<Self, RenderError> {
        if config.samples != 1 && config.samples != 4 {
            return Err(RenderError::Config(format!(
                "samples must be 1 or 4, got {}",
                config.samples
            )));
        }
        if !(config.min_radius_px.is_finite() && config.min_radius_px >= 0.0) {
            return Err(RenderError::Config(format!(
                "min_radius_px must be finite and at least 0, got {}",
                config.min_radius_px
            )));
        }
        if !(config.hud_size.is_finite() && config.hud_size > 0.0) {
            return Err(RenderError::Config(format!(
                "hud_size must be finite and positive, got {}",
                config.hud_size
            )));
        }
        check_interpolation(config.interpolation)?;
        let device = &gpu.device;
        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("tickwork globals"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let [globals_entry] = particle_layout_entries();
        let particle_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tickwork particles"),
            entries: &[globals_entry],
        });
        let line_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tickwork lines"),
            entries: &[globals_entry],
        });
        let multisample = wgpu::MultisampleState {
            count: config.samples,
            mask: !0,
            alpha_to_coverage_enabled: false,
        };
        let particle_shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("particles.wgsl"),
            source: wgpu::ShaderSource::Wgsl(shader!("particles.wgsl").into()),
        });
        let particle_pipeline = particle_pipeline(
            device,
            &particle_layout,
            &particle_shader,
            "vs_main",
            &[Some(instance_buffer_layout())],
            format,
            &config,
        );
        let line_shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("lines.wgsl"),
            source: wgpu::ShaderSource::Wgsl(shader!("lines.wgsl").into()),
        });
        let line_attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Unorm8x4];
        let line_pipeline_for = |multisample, topology| {
            pipeline(
                device,
                &line_layout,
                &line_shader,
                "vs_main",
                &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<LineVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &line_attributes,
                })],
                topology,
                format,
                wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING,
                false,
                multisample,
            )
        };
        let (lines, triangles) = (wgpu::PrimitiveTopology::LineList, wgpu::PrimitiveTopology::TriangleList);
        let line_pipeline = line_pipeline_for(multisample, lines);
        let line_pipeline_single = line_pipeline_for(wgpu::MultisampleState::default(), lines);
        let triangle_pipeline = line_pipeline_for(multisample, triangles);
        let triangle_pipeline_single = line_pipeline_for(wgpu::MultisampleState::default(), triangles);
        let instances = record_buffer::<Instance>(device, "tickwork particles", 1024);
        let particle_bind_group = bind_buffers(device, &particle_layout, &[&globals]);
        let line_bind_group = bind_buffers(device, &line_layout, &[&globals]);
        let line_buffer = vertex_buffer(device, 1024);
        let triangle_buffer = vertex_buffer(device, 1024);
        let hud = Hud::new(gpu, format, multisample, config.hud_size);
        let sprites = Sprites::new(device, &line_layout, format, config.samples);
        // WebGL2 has no compute: no splat there, every particle a quad.
        let splat = gpu
            .adapter
            .get_downlevel_capabilities()
            .flags
            .contains(wgpu::DownlevelFlags::COMPUTE_SHADERS)
            .then(|| Splat::new(device, format, config.blend));
        let splat_threshold =
            config
                .splat_threshold
                .unwrap_or(if gpu.adapter.get_info().device_type == wgpu::DeviceType::Cpu {
                    2_000
                } else {
                    250_000
                });
        Ok(Self {
            config,
            format,
            globals,
            particle_pipeline,
            particle_layout,
            particle_shader,
            hermite: None,
            hermite_active: false,
            instances,
            particle_bind_group,
            instance_count: 0,
            line_pipeline,
            line_pipeline_single,
            line_bind_group,
            line_buffer,
            line_count: 0,
            line_scratch: Vec::new(),
            triangle_pipeline,
            triangle_pipeline_single,
            triangle_buffer,
            triangle_count: 0,
            triangle_scratch: Vec::new(),
            world_line_vertices: 0,
            shape_calls: Vec::new(),
            particle_layer: 0,
            world_draws: Vec::new(),
            world_layers: Vec::new(),
            cpu_instances: 0,
            cpu_max_radius: 0.0,
            gather: None,
            letterbox: None,
            sprites,
            frame_scissor: [0, 0, 1, 1],
            frame_size: (1, 1),
            placed_texts: Vec::new(),
            placed_before: Vec::new(),
            text_runs: Vec::new(),
            merged_runs: Vec::new(),
            instance_scratch: Vec::new(),
            uploaded: Vec::new(),
            upload_key: Vec::new(),
            max_radius: 0.0,
            splat,
            splat_threshold,
            splat_active: false,
            hud,
        })
    }

    /// The settings in use.
    #[must_use]
    pub fn config(&self) -> &RendererConfig {
        &self.config
    }

    /// The colour format this renderer draws.
    #[must_use]
    pub fn format(&self) -> wgpu::TextureFormat {
        self.format
    }

    /// Changes the interpolation mode (takes effect at the next frame; the
    /// first Hermite frame builds its pipeline and velocity buffer). A
    /// Hermite `dt` that is not finite and positive is refused by the next
    /// [`prepare`](Self::prepare).
    pub fn set_interpolation(&mut self, interpolation: Interpolation) {
        self.config.interpolation = interpolation;
    }

    /// Uploads what `view` shows for a target of `buffers`' size: the
    /// particles if the world changed since the last upload, the lines, the
    /// uniforms and the HUD text.
    ///
    /// # Errors
    /// [`RenderError::Config`] for a non-finite alpha or a Hermite `dt` that
    /// is not finite and positive; [`RenderError::Device`] if the HUD cannot
    /// be laid out.
    pub fn prepare(&mut self, gpu: &Gpu, buffers: &FrameBuffers, view: &FrameView<'_>) -> Result<(), RenderError> {
        if !view.alpha.is_finite() {
            return Err(RenderError::Config(format!("alpha must be finite, got {}", view.alpha)));
        }
        check_interpolation(self.config.interpolation)?;
        let CameraMatrices {
            view_proj,
            pixels_per_unit,
        } = view.camera.matrices(buffers.width, buffers.height);
        let rect = view.camera.frame_rect(buffers.width, buffers.height);
        self.letterbox = (rect != FrameRect::whole(buffers.width, buffers.height)).then_some(rect);
        self.frame_size = (buffers.width.max(1), buffers.height.max(1));
        self.frame_scissor = match self.letterbox {
            Some(r) => [r.x as u32, r.y as u32, r.width as u32, r.height as u32],
            None => [0, 0, self.frame_size.0, self.frame_size.1],
        };
        let t = self.config.interpolation.parameter(view.alpha);
        let gpu_count = self.gather_count(view)?;
        self.upload_particles(gpu, view);
        let total = u64::from(self.cpu_instances) + gpu_count;
        if gpu_count > 0 && total * std::mem::size_of::<Instance>() as u64 > self.instances.size() {
            // Room for the GPU worlds' records too: the CPU's go again.
            let rows = usize::try_from(total).unwrap_or(usize::MAX).next_power_of_two();
            self.instances = record_buffer::<Instance>(&gpu.device, "tickwork particles", rows);
            if let Some(splat) = &mut self.splat {
                splat.invalidate();
            }
            self.uploaded.clear();
            self.upload_particles(gpu, view);
        }
        self.instance_count = u32::try_from(total).unwrap_or(u32::MAX);
        self.max_radius = view
            .gpu_particles
            .iter()
            .fold(self.cpu_max_radius, |m, g| m.max(g.max_radius));
        self.plan_worlds(view, gpu_count);
        let dt = match self.config.interpolation {
            Interpolation::Hermite { dt } => Some(dt),
            _ => None,
        };
        self.hermite_active = dt.is_some();
        if self.hermite_active {
            let (config, shader, format) = (&self.config, &self.particle_shader, self.format);
            let layout = &self.particle_layout;
            let hermite = self.hermite.get_or_insert_with(|| {
                HermiteParticles::new(&gpu.device, |entry, buffers| {
                    particle_pipeline(&gpu.device, layout, shader, entry, buffers, format, config)
                })
            });
            if hermite.upload(gpu, view, usize::try_from(gpu_count).unwrap_or(usize::MAX))
                && let Some(splat) = &mut self.splat
            {
                splat.invalidate();
            }
        }
        // The GPU worlds' records (and velocities) after the CPU's, on the GPU.
        if gpu_count > 0 {
            let hermite = self
                .hermite
                .as_ref()
                .filter(|_| self.hermite_active)
                .map(HermiteParticles::velocities);
            let gather = self
                .gather
                .get_or_insert_with(|| super::gather::Gather::new(&gpu.device));
            gather.gather(gpu, &self.instances, hermite, self.cpu_instances, view.gpu_particles);
        }
        self.splat_active = self.splat.is_some()
            && self.instance_count as usize >= self.splat_threshold
            && self.instance_count < 1 << 24
            && view.camera.is_2d()
            // The splat covers the whole frame, and composites every
            // world's particles at once: on one layer, none of them drawn
            // from a GPU world's buffers (which the multisampled pipeline
            // draws).
            && self.letterbox.is_none()
            && self.world_layers.len() <= 1
            && self.max_radius * pixels_per_unit <= SPLAT_MAX_RADIUS;
        if self.splat_active
            && let Some(splat) = &mut self.splat
        {
            let velocities = self
                .hermite
                .as_ref()
                .filter(|_| self.hermite_active)
                .map(HermiteParticles::velocities);
            splat.resize(
                gpu,
                buffers.width,
                buffers.height,
                &self.globals,
                &self.instances,
                velocities,
            );
        }
        let globals = Globals {
            view_proj: view_proj.to_cols_array_2d(),
            viewport: [rect.width, rect.height],
            pixels_per_unit,
            t,
            min_radius_px: self.config.min_radius_px,
            count: self.instance_count,
            stride: self.splat.as_ref().map_or(0, Splat::stride),
            swap_rb: u32::from(self.bgra()),
            background: self.background_linear(),
            background_word: {
                let [r, g, b, a] = self.config.background;
                u32::from_le_bytes(if self.bgra() { [b, g, r, a] } else { [r, g, b, a] })
            },
            dt: dt.unwrap_or(0.0),
            _pad: [0; 2],
        };
        gpu.queue.write_buffer(&self.globals, 0, bytemuck::bytes_of(&globals));
        self.build_lines(view, t);
        self.upload_lines(gpu);
        self.build_triangles(view)?;
        self.upload_triangles(gpu);
        self.sprites.prepare(gpu, view.sprites)?;
        self.order_shapes(view)?;
        self.place_texts(view, buffers.width, buffers.height)?;
        for run in &mut self.text_runs {
            *run = self.placed_before[run.start]..self.placed_before[run.end];
        }
        self.hud
            .prepare(
                gpu,
                buffers.width,
                buffers.height,
                view.hud,
                view.hud_colours,
                &self.placed_texts,
                &self.text_runs,
                self.splat_active,
            )
            .map_err(|error| RenderError::Device(format!("laying out the HUD: {error}")))?;
        Ok(())
    }

    /// Records the frame's render pass into `encoder`, drawing into
    /// `output` through `buffers`.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, buffers: &FrameBuffers, output: &wgpu::TextureView) {
        // The splat resolves straight into targets that accept copies (an
        // 8-bit sRGB format and COPY_DST), which the pass then only loads.
        let resolved = self.splat_active && {
            let texture = output.texture();
            texture.usage().contains(wgpu::TextureUsages::COPY_DST)
                && matches!(
                    texture.format(),
                    wgpu::TextureFormat::Rgba8UnormSrgb | wgpu::TextureFormat::Bgra8UnormSrgb
                )
                && (texture.width(), texture.height()) == (buffers.width, buffers.height)
                // Nothing to draw under the particles.
                && !self.shape_calls.iter().any(|c| self.world_layers.iter().any(|&w| c.layer <= w))
        };
        if self.splat_active
            && let Some(splat) = &self.splat
        {
            splat.encode_compute(encoder, self.instance_count, self.hermite_active);
            if resolved {
                splat.encode_resolve(encoder, output.texture());
            }
        }
        let [r, g, b, a] = self.background_linear().map(f64::from);
        let clear = wgpu::Color { r, g, b, a };
        // A splat frame is single-sampled: its particles are anti-aliased
        // analytically, the HUD's glyphs carry their own coverage, and MSAA
        // costs software rasterisers more than the splat itself.
        let single = self.splat_active;
        let colour = if single {
            buffers.single_sample_attachment(output, (!resolved).then_some(clear))
        } else {
            buffers.colour_attachment(output, clear)
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("tickwork frame"),
            color_attachments: &[Some(colour)],
            depth_stencil_attachment: Some(buffers.depth_attachment(single)),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if let Some(r) = self.letterbox {
            // Only the field: the bars keep the clear colour.
            pass.set_viewport(r.x, r.y, r.width, r.height, 0.0, 1.0);
            pass.set_scissor_rect(r.x as u32, r.y as u32, r.width as u32, r.height as u32);
        }
        // Each layer a world is on: the shapes up to it, then its worlds.
        let mut below: Option<i32> = None;
        let above = |below: Option<i32>, layer: i32| below.is_none_or(|b| layer > b);
        for &layer in &self.world_layers {
            for call in self
                .shape_calls
                .iter()
                .filter(|c| above(below, c.layer) && c.layer <= layer)
            {
                self.draw_shapes(&mut pass, call, single);
            }
            self.draw_worlds(&mut pass, layer, resolved, single);
            below = Some(layer);
        }
        for call in self.shape_calls.iter().filter(|c| above(below, c.layer)) {
            self.draw_shapes(&mut pass, call, single);
        }
        if self.letterbox.is_some() {
            // The HUD over the whole frame, bars included.
            let (w, h) = (buffers.width.max(1), buffers.height.max(1));
            pass.set_viewport(0.0, 0.0, w as f32, h as f32, 0.0, 1.0);
            pass.set_scissor_rect(0, 0, w, h);
        }
        self.hud.render(&mut pass);
    }

    /// The worlds on `layer`: their lines (trails, outlines), then their
    /// particles (the splat's composite, when it drew them all: `resolved`
    /// when it already resolved them into the target).
    fn draw_worlds(&self, pass: &mut wgpu::RenderPass<'_>, layer: i32, resolved: bool, single: bool) {
        let on_layer = || self.world_draws.iter().filter(move |w| w.layer == layer);
        for world in on_layer().filter(|w| !w.lines.is_empty()) {
            let lines = ShapeCall {
                shapes: Shapes::Lines,
                layer,
                vertices: world.lines.clone(),
                scissor: None,
            };
            self.draw_shapes(pass, &lines, single);
        }
        if self.splat_active {
            if !resolved && let Some(splat) = &self.splat {
                splat.encode_composite(pass);
            }
            return;
        }
        for world in on_layer().filter(|w| !w.instances.is_empty()) {
            match &self.hermite {
                Some(hermite) if self.hermite_active => {
                    hermite.draw(
                        pass,
                        &self.particle_bind_group,
                        &self.instances,
                        world.instances.clone(),
                    );
                }
                _ => {
                    pass.set_pipeline(&self.particle_pipeline);
                    pass.set_bind_group(0, &self.particle_bind_group, &[]);
                    pass.set_vertex_buffer(0, self.instances.slice(..));
                    pass.draw(0..4, world.instances.clone());
                }
            }
        }
    }

    /// Each world's layer and instances this frame, and the layers they
    /// are on (lowest first). Their lines are set as they are built.
    fn plan_worlds(&mut self, view: &FrameView<'_>, gpu_count: u64) {
        self.world_draws.clear();
        self.world_layers.clear();
        // The CPU worlds' records, then the GPU worlds' (gathered after
        // them), in order, each on its layer.
        let cpu = view
            .worlds()
            .map(|shown| (shown.layer, u32::try_from(shown.world.len()).unwrap_or(u32::MAX)));
        let gpu = view.gpu_particles.iter().map(|g| (g.layer, g.count));
        let mut first = 0u32;
        for (layer, count) in cpu.chain(gpu.filter(|_| gpu_count > 0)) {
            let layer = layer.unwrap_or(view.particle_layer);
            self.world_draws.push(WorldDraw {
                layer,
                instances: first..first.saturating_add(count),
                lines: 0..0,
            });
            first = first.saturating_add(count);
            if !self.world_layers.contains(&layer) {
                self.world_layers.push(layer);
            }
        }
        self.world_layers.sort_unstable();
    }

    /// One run of the frame's fills, lines or sprites, clipped as it asks.
    fn draw_shapes(&self, pass: &mut wgpu::RenderPass<'_>, call: &ShapeCall, single: bool) {
        let Some([x, y, w, h]) = call.scissor else {
            self.draw_unclipped(pass, call, single);
            return;
        };
        if w == 0 || h == 0 {
            return;
        }
        pass.set_scissor_rect(x, y, w, h);
        self.draw_unclipped(pass, call, single);
        let [x, y, w, h] = self.frame_scissor;
        pass.set_scissor_rect(x, y, w, h);
    }

    /// The pixel rectangle of the world rectangle `clip` in this frame,
    /// within where the camera draws.
    fn scissor(&self, view: &FrameView<'_>, (min, max): (glam::Vec2, glam::Vec2)) -> [u32; 4] {
        let [fx, fy, fw, fh] = self.frame_scissor;
        let (width, height) = (self.frame_size.0, self.frame_size.1);
        let corner = |p: glam::Vec2| view.camera.pixel_of(p.extend(0.0), width, height);
        let (Some(a), Some(b)) = (corner(min), corner(max)) else {
            return [fx, fy, 0, 0];
        };
        let (lo, hi) = (a.min(b), a.max(b));
        let clamp = |v: f32, from: u32, to: u32| (v.round().max(from as f32).min(to as f32)) as u32;
        let (x0, x1) = (clamp(lo.x, fx, fx + fw), clamp(hi.x, fx, fx + fw));
        let (y0, y1) = (clamp(lo.y, fy, fy + fh), clamp(hi.y, fy, fy + fh));
        [x0, y0, x1 - x0, y1 - y0]
    }

    fn draw_unclipped(&self, pass: &mut wgpu::RenderPass<'_>, call: &ShapeCall, single: bool) {
        if call.shapes == Shapes::Texts {
            // Text calls name their run, placed in the whole frame's
            // pixels (the letterbox's scissor still clips them).
            let run = call.vertices.start as usize;
            match self.letterbox {
                Some(r) => {
                    let (w, h) = self.frame_size;
                    pass.set_viewport(0.0, 0.0, w as f32, h as f32, 0.0, 1.0);
                    self.hud.render_run(pass, run);
                    pass.set_viewport(r.x, r.y, r.width, r.height, 0.0, 1.0);
                }
                None => self.hud.render_run(pass, run),
            }
            return;
        }
        if call.shapes == Shapes::Sprites {
            pass.set_bind_group(0, &self.line_bind_group, &[]);
            self.sprites
                .draw(pass, call.vertices.start as usize..call.vertices.end as usize, single);
            return;
        }
        let (pipeline, buffer) = match (call.shapes, single) {
            (Shapes::Fills, true) => (&self.triangle_pipeline_single, &self.triangle_buffer),
            (Shapes::Fills, false) => (&self.triangle_pipeline, &self.triangle_buffer),
            // Sprites and texts returned above.
            (Shapes::Lines | Shapes::Sprites | Shapes::Texts, true) => (&self.line_pipeline_single, &self.line_buffer),
            (Shapes::Lines | Shapes::Sprites | Shapes::Texts, false) => (&self.line_pipeline, &self.line_buffer),
        };
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &self.line_bind_group, &[]);
        pass.set_vertex_buffer(0, buffer.slice(..));
        pass.draw(call.vertices.clone(), 0..1);
    }

    /// The frame's shapes and texts as draw calls, by layer and then in
    /// the order drawn (the batches'); shapes no batch covers come after
    /// them on layer 0, fills first, and texts no batch covers over
    /// everything (a view built without text batches).
    fn order_shapes(&mut self, view: &FrameView<'_>) -> Result<(), RenderError> {
        self.shape_calls.clear();
        self.text_runs.clear();
        self.particle_layer = view.particle_layer;
        let (fills, lines, sprites) = (view.triangles.len(), view.lines.len(), view.sprites.len());
        let texts = view.texts.len();
        let (mut fills_drawn, mut lines_drawn, mut sprites_drawn, mut texts_drawn) = (0, 0, 0, 0);
        let world = self.world_line_vertices as usize;
        let vertices = |range: Range<usize>| {
            u32::try_from(range.start).unwrap_or(u32::MAX)..u32::try_from(range.end).unwrap_or(u32::MAX)
        };
        for (k, batch) in view.batches.iter().enumerate() {
            let (len, kind) = match batch.shapes {
                Shapes::Fills => (fills, "triangles"),
                Shapes::Lines => (lines, "lines"),
                Shapes::Sprites => (sprites, "sprites"),
                Shapes::Texts => (texts, "texts"),
            };
            if batch.start > batch.end || batch.end > len {
                return Err(RenderError::Config(format!(
                    "batch {k} of the frame covers {kind} {}..{}, but the frame has {len} {kind}",
                    batch.start, batch.end
                )));
            }
            let range = match batch.shapes {
                Shapes::Fills => {
                    fills_drawn = fills_drawn.max(batch.end);
                    batch.start * 3..batch.end * 3
                }
                Shapes::Lines => {
                    lines_drawn = lines_drawn.max(batch.end);
                    world + batch.start * 2..world + batch.end * 2
                }
                // Sprite calls count sprites, not vertices.
                Shapes::Sprites => {
                    sprites_drawn = sprites_drawn.max(batch.end);
                    batch.start..batch.end
                }
                // A text call names its run.
                Shapes::Texts => {
                    texts_drawn = texts_drawn.max(batch.end);
                    self.text_runs.push(batch.start..batch.end);
                    self.text_runs.len() - 1..self.text_runs.len()
                }
            };
            self.shape_calls.push(ShapeCall {
                shapes: batch.shapes,
                layer: batch.layer,
                vertices: vertices(range),
                scissor: batch.clip.map(|clip| self.scissor(view, clip)),
            });
        }
        if fills_drawn < fills {
            self.shape_calls.push(ShapeCall {
                shapes: Shapes::Fills,
                layer: 0,
                vertices: vertices(fills_drawn * 3..fills * 3),
                scissor: None,
            });
        }
        if lines_drawn < lines {
            self.shape_calls.push(ShapeCall {
                shapes: Shapes::Lines,
                layer: 0,
                vertices: vertices(world + lines_drawn * 2..world + lines * 2),
                scissor: None,
            });
        }
        if sprites_drawn < sprites {
            self.shape_calls.push(ShapeCall {
                shapes: Shapes::Sprites,
                layer: 0,
                vertices: vertices(sprites_drawn..sprites),
                scissor: None,
            });
        }
        if texts_drawn < texts {
            self.text_runs.push(texts_drawn..texts);
            self.shape_calls.push(ShapeCall {
                shapes: Shapes::Texts,
                layer: i32::MAX,
                vertices: vertices(self.text_runs.len() - 1..self.text_runs.len()),
                scissor: None,
            });
        }
        // A stable sort: the order drawn is kept within a layer.
        self.shape_calls.sort_by_key(|c| c.layer);
        self.merge_text_runs();
        if self.text_runs.len() > super::overlay::MAX_TEXT_RUNS {
            return Err(RenderError::Config(format!(
                "the frame has {} runs of text between other shapes, more than the limit of {} \
                 (render::MAX_TEXT_RUNS): draw its texts together",
                self.text_runs.len(),
                super::overlay::MAX_TEXT_RUNS
            )));
        }
        Ok(())
    }

    /// Runs of text side by side in the sorted calls (on one layer and
    /// clip, of consecutive texts: labels on a layer of their own, each
    /// added after a shape on another) become one run, drawn at once.
    fn merge_text_runs(&mut self) {
        let mut merged = std::mem::take(&mut self.merged_runs);
        merged.clear();
        let mut kept = 0usize;
        for k in 0..self.shape_calls.len() {
            let mut call = self.shape_calls[k].clone();
            if call.shapes == Shapes::Texts {
                let run = self.text_runs[call.vertices.start as usize].clone();
                let previous = kept.checked_sub(1).map(|p| &self.shape_calls[p]);
                let joins = previous
                    .is_some_and(|p| p.shapes == Shapes::Texts && p.layer == call.layer && p.scissor == call.scissor);
                if let Some(last) = merged.last_mut().filter(|last| joins && last.end == run.start) {
                    last.end = run.end;
                    continue;
                }
                merged.push(run);
                let index = u32::try_from(merged.len() - 1).unwrap_or(u32::MAX);
                call.vertices = index..index + 1;
            }
            self.shape_calls[kept] = call;
            kept += 1;
        }
        self.shape_calls.truncate(kept);
        std::mem::swap(&mut self.text_runs, &mut merged);
        self.merged_runs = merged;
    }

    /// Whether the target stores blue first.
    fn bgra(&self) -> bool {
        matches!(
            self.format,
            wgpu::TextureFormat::Bgra8UnormSrgb | wgpu::TextureFormat::Bgra8Unorm
        )
    }

    /// The clear colour in linear light (it is given in sRGB).
    fn background_linear(&self) -> [f32; 4] {
        let [r, g, b, a] = self.config.background.map(|c| f64::from(c) / 255.0);
        [
            srgb_to_linear(r) as f32,
            srgb_to_linear(g) as f32,
            srgb_to_linear(b) as f32,
            a as f32,
        ]
    }

    /// Forgets what was uploaded, so the next frame uploads the world again
    /// (needed only if the world was edited through a path that does not
    /// count as a change, which none of [`World`](crate::World)'s methods is).
    pub fn invalidate(&mut self) {
        self.uploaded.clear();
        if let Some(hermite) = &mut self.hermite {
            hermite.forget_upload();
        }
    }

    /// The particles of the frame's GPU worlds, checked against their
    /// buffers.
    fn gather_count(&self, view: &FrameView<'_>) -> Result<u64, RenderError> {
        let mut total = 0u64;
        for (k, g) in view.gpu_particles.iter().enumerate() {
            let count = u64::from(g.count);
            let held = (g.previous.size().min(g.current.size()) / 16).min(g.colours.size() / 4);
            if count > held {
                return Err(RenderError::Config(format!(
                    "gpu_particles[{k}] counts {count} particles, but its buffers hold {held}"
                )));
            }
            total += count;
        }
        Ok(total)
    }

    fn upload_particles(&mut self, gpu: &Gpu, view: &FrameView<'_>) {
        self.upload_key.clear();
        self.upload_key
            .extend(view.worlds().map(|w| (w.world.id(), w.world.revision())));
        if self.uploaded == self.upload_key {
            return;
        }
        std::mem::swap(&mut self.uploaded, &mut self.upload_key);
        let n: usize = view.worlds().map(|w| w.world.len()).sum();
        self.cpu_instances = u32::try_from(n).unwrap_or(u32::MAX);
        self.cpu_max_radius = view
            .worlds()
            .flat_map(|w| w.world.particles().radius.iter())
            .fold(0.0, |m: f32, &r| m.max(r));
        if n == 0 {
            return;
        }
        let bytes = n * std::mem::size_of::<Instance>();
        if bytes as u64 > self.instances.size() {
            self.instances = record_buffer::<Instance>(&gpu.device, "tickwork particles", n.next_power_of_two());
            if let Some(splat) = &mut self.splat {
                splat.invalidate();
            }
        }
        write_records(
            gpu,
            view,
            n,
            &mut self.instance_scratch,
            &self.instances,
            instance_block,
            hide_instances,
        );
    }

    fn build_lines(&mut self, view: &FrameView<'_>, t: f32) {
        fn push(scratch: &mut Vec<LineVertex>, a: Vec3, b: Vec3, colour: [u8; 4]) {
            for p in [a, b] {
                scratch.push(LineVertex {
                    position: p.to_array(),
                    colour,
                });
            }
        }
        self.line_scratch.clear();
        let vertex = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
        for (k, shown) in view.worlds().enumerate() {
            let start = vertex(self.line_scratch.len());
            let scratch = &mut self.line_scratch;
            super::world_lines::world_lines(&self.config, &shown, t, &mut |a, b, c| push(scratch, a, b, c));
            if let Some(world) = self.world_draws.get_mut(k) {
                world.lines = start..vertex(self.line_scratch.len());
            }
        }
        self.world_line_vertices = vertex(self.line_scratch.len());
        for line in view.lines {
            push(&mut self.line_scratch, line.a, line.b, line.colour);
        }
    }

    /// The frame's triangles as vertices.
    fn build_triangles(&mut self, view: &FrameView<'_>) -> Result<(), RenderError> {
        self.triangle_scratch.clear();
        for (k, triangle) in view.triangles.iter().enumerate() {
            if let Some(corner) = triangle.corners.iter().find(|c| !c.is_finite()) {
                return Err(RenderError::Config(format!(
                    "triangle {k} of the frame has a non-finite corner {corner}"
                )));
            }
            self.triangle_scratch
                .extend(triangle.corners.iter().map(|corner| LineVertex {
                    position: corner.to_array(),
                    colour: triangle.colour,
                }));
        }
        Ok(())
    }

    fn upload_triangles(&mut self, gpu: &Gpu) {
        self.triangle_count = upload_vertices(gpu, &self.triangle_scratch, &mut self.triangle_buffer);
    }

    /// The frame's texts in pixels: each anchor point projected through the
    /// camera (texts behind a 3D camera are left out).
    fn place_texts(&mut self, view: &FrameView<'_>, width: u32, height: u32) -> Result<(), RenderError> {
        self.placed_texts.clear();
        self.placed_before.clear();
        let matrices = view.camera.matrices(width, height);
        let rect = view.camera.frame_rect(width, height);
        for (k, text) in view.texts.iter().enumerate() {
            self.placed_before.push(self.placed_texts.len());
            let most = if text.unit == TextUnit::Pixels {
                1000.0
            } else {
                f32::MAX
            };
            if !(text.at.is_finite() && text.size.is_finite() && text.size > 0.0 && text.size <= most) {
                return Err(RenderError::Config(format!(
                    "text {k} of the frame ({:?}) has position {} and size {} ({:?}): the position must be finite \
                     and the size above 0 (at most 1000 pixels)",
                    text.text, text.at, text.size, text.unit
                )));
            }
            let clip = matrices.view_proj * text.at.extend(1.0);
            let Some(at) = view.camera.pixel_of(text.at, width, height) else {
                continue;
            };
            let pixels = match text.unit {
                TextUnit::Pixels => text.size,
                // Perspective: smaller with distance, as the world is.
                TextUnit::Metres => text.size * matrices.pixels_per_unit / clip.w,
                TextUnit::FrameHeight => text.size * rect.height,
            };
            // Less than a pixel high (or a NaN from a degenerate camera):
            // nothing to see.
            if pixels.is_nan() || pixels < 1.0 {
                continue;
            }
            self.placed_texts.push(PlacedText {
                text: text.text.clone(),
                x: at.x,
                y: at.y,
                size: pixels.min(1000.0),
                colour: text.colour,
                anchor: text.anchor,
            });
        }
        self.placed_before.push(self.placed_texts.len());
        Ok(())
    }

    fn upload_lines(&mut self, gpu: &Gpu) {
        self.line_count = upload_vertices(gpu, &self.line_scratch, &mut self.line_buffer);
    }
}

/// sRGB transfer function, for the clear colour.
fn srgb_to_linear(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        crate::math::powf((c + 0.055) / 1.055, 2.4)
    }
}

/// Refuses a Hermite step that cannot scale velocities into a step.
fn check_interpolation(interpolation: Interpolation) -> Result<(), RenderError> {
    match interpolation {
        Interpolation::Hermite { dt } if !(dt.is_finite() && dt > 0.0) => Err(RenderError::Config(format!(
            "Hermite interpolation needs the fixed step dt in seconds, finite and positive, got {dt}"
        ))),
        _ => Ok(()),
    }
}

/// One world of a frame: the layer it is drawn on, its particles' range
/// of the instance buffer and its lines' range of the line vertices.
#[derive(Clone, Debug)]
struct WorldDraw {
    layer: i32,
    instances: Range<u32>,
    lines: Range<u32>,
}

/// One draw of a run of the frame's shapes: which kind, on which layer,
/// which vertices of its buffer (sprites: which sprites), and the pixel
/// rectangle `[x, y, width, height]` it is clipped to, if any.
#[derive(Clone, Debug)]
struct ShapeCall {
    shapes: Shapes,
    layer: i32,
    vertices: Range<u32>,
    scissor: Option<[u32; 4]>,
}
