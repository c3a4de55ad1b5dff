//! The renderer: pipelines and buffers that turn a world's previous and
//! current columns into a frame.
//!
//! Per frame it uploads, only when the world changed since the last upload,
//! one 32-byte record per particle (previous position, radius, current
//! position, colour: `../records.rs`); the vertex shader interpolates with the frame's
//! alpha, so a frame without a fixed step uploads nothing but a uniform.
//! In [`Interpolation::Hermite`] mode a 12-byte velocity per particle goes
//! into a second buffer too (see `../hermite.rs`).
//! Lines (springs, trails, rigid-body boxes, a game's own) are few and built
//! on the CPU (`line_vertices.rs`). The pipelines are built by
//! `pipeline.rs`.

mod geometry;
mod plan;

use bytemuck::{Pod, Zeroable};
use std::ops::Range;

use super::camera::{CameraMatrices, FrameRect};
use super::config::RendererConfig;
use super::frame_view::FrameView;
use super::hermite::HermiteParticles;
use super::hud::Hud;
use super::line_vertices::{LineVertex, vertex_buffer};
use super::overlay::PlacedText;
use super::pipeline::{particle_layout_entries, particle_pipeline, pipeline};
use super::records::{Instance, instance_buffer_layout, record_buffer};
use super::splat::{SPLAT_MAX_RADIUS, Splat};
use super::sprites::Sprites;
use super::target::FrameBuffers;
use super::{Gpu, RenderError};
use crate::device::{bind_buffers, wgsl};
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
            source: wgpu::ShaderSource::Wgsl(wgsl!("common.wgsl", "particles.wgsl").into()),
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
            source: wgpu::ShaderSource::Wgsl(wgsl!("common.wgsl", "lines.wgsl").into()),
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

use plan::{ShapeCall, WorldDraw};
