//! The window's control panel: its egui state, the events it takes, and
//! the pass that draws it over a finished frame (the panel returns
//! controls; it changes nothing). Without the `panel` feature a window has
//! none: [`Panel`] takes no event and draws nothing.

use winit::event::WindowEvent;
use winit::window::Window;

use crate::app::api::control::Control;
use crate::app::session::source::FrameSource;
use crate::render::Gpu;

/// The egui side of the window: context, winit input state, wgpu renderer.
#[cfg(feature = "panel")]
pub(super) struct Panel {
    context: egui::Context,
    input: egui_winit::State,
    renderer: egui_wgpu::Renderer,
}

/// What the panel is drawn onto: the window, its GPU and its size in
/// pixels (the window's state without its renderer, which the panel does
/// not use).
#[cfg_attr(not(feature = "panel"), allow(dead_code))]
pub(super) struct PanelTarget<'a> {
    /// The window, for egui's input and cursor.
    pub(super) window: &'a Window,
    /// The window's GPU.
    pub(super) gpu: &'a Gpu,
    /// The surface's width in pixels.
    pub(super) width: u32,
    /// The surface's height in pixels.
    pub(super) height: u32,
}

/// No panel: the `panel` feature is off.
#[cfg(not(feature = "panel"))]
pub(super) struct Panel;

impl Panel {
    /// The panel of `window`, drawn by `gpu` in `format`.
    #[cfg(feature = "panel")]
    pub(super) fn new(window: &Window, gpu: &Gpu, format: wgpu::TextureFormat) -> Self {
        let context = egui::Context::default();
        Self {
            input: egui_winit::State::new(
                context.clone(),
                egui::ViewportId::ROOT,
                window,
                Some(window.scale_factor() as f32),
                None,
                Some(gpu.device.limits().max_texture_dimension_2d as usize),
            ),
            context,
            renderer: egui_wgpu::Renderer::new(&gpu.device, format, egui_wgpu::RendererOptions::default()),
        }
    }

    /// No panel.
    #[cfg(not(feature = "panel"))]
    pub(super) fn new(window: &Window, gpu: &Gpu, format: wgpu::TextureFormat) -> Self {
        let _ = (window, gpu, format);
        Self
    }

    /// Whether the panel takes `event` (a click on it, a key while it has
    /// the focus), so the game does not see it.
    #[cfg(feature = "panel")]
    pub(super) fn takes(&mut self, window: &Window, event: &WindowEvent) -> bool {
        self.input.on_window_event(window, event).consumed
    }

    /// No panel takes nothing.
    #[cfg(not(feature = "panel"))]
    pub(super) fn takes(&mut self, window: &Window, event: &WindowEvent) -> bool {
        let _ = (window, event);
        false
    }
}

/// No panel draws nothing.
#[cfg(not(feature = "panel"))]
pub(super) fn draw_panel(
    panel: &mut Panel,
    source: &dyn FrameSource,
    chosen: &mut Vec<Control>,
    target: &PanelTarget<'_>,
    encoder: &mut wgpu::CommandEncoder,
    output: &wgpu::TextureView,
) -> Vec<wgpu::CommandBuffer> {
    let _ = (panel, source, chosen, target, encoder, output);
    Vec::new()
}

/// Lays out the panel, uploads its meshes and records its pass over
/// `output` (loaded, not cleared); returns the upload command buffers.
#[cfg(feature = "panel")]
pub(super) fn draw_panel(
    panel: &mut Panel,
    source: &dyn FrameSource,
    chosen: &mut Vec<Control>,
    target: &PanelTarget<'_>,
    encoder: &mut wgpu::CommandEncoder,
    output: &wgpu::TextureView,
) -> Vec<wgpu::CommandBuffer> {
    let raw = panel.input.take_egui_input(target.window);
    let mut full = panel.context.run_pass(raw, |ctx| source.panel(ctx, chosen));
    panel
        .input
        .handle_platform_output(target.window, std::mem::take(&mut full.platform_output));
    let pixels_per_point = full.pixels_per_point;
    let jobs = panel
        .context
        .tessellate(std::mem::take(&mut full.shapes), pixels_per_point);
    let (device, queue) = (&target.gpu.device, &target.gpu.queue);
    for (id, deltas) in &full.textures_delta.set {
        for delta in deltas {
            panel.renderer.update_texture(device, queue, *id, delta);
        }
    }
    let screen = egui_wgpu::ScreenDescriptor {
        size_in_pixels: [target.width, target.height],
        pixels_per_point,
    };
    let commands = panel.renderer.update_buffers(device, queue, encoder, &jobs, &screen);
    {
        let mut pass = encoder
            .begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("tickwork panel"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: output,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            })
            .forget_lifetime();
        panel.renderer.render(&mut pass, &jobs, &screen);
    }
    for id in &full.textures_delta.free {
        panel.renderer.free_texture(id);
    }
    // Applied: egui checks that every delta was handled.
    full.textures_delta.clear();
    commands
}
