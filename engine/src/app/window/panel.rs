//! The pass that draws the control panel over a finished frame (the panel
//! returns controls; it changes nothing).

use super::super::control::Control;
use super::super::source::FrameSource;
use super::surface::{Panel, WindowState};

/// Lays out the panel, uploads its meshes and records its pass over
/// `output` (loaded, not cleared); returns the upload command buffers.
pub(super) fn draw_panel(
    panel: &mut Panel,
    source: &dyn FrameSource,
    chosen: &mut Vec<Control>,
    state: &WindowState,
    encoder: &mut wgpu::CommandEncoder,
    output: &wgpu::TextureView,
) -> Vec<wgpu::CommandBuffer> {
    let raw = panel.input.take_egui_input(&state.window);
    let mut full = panel.context.run_pass(raw, |ctx| source.panel(ctx, chosen));
    panel
        .input
        .handle_platform_output(&state.window, std::mem::take(&mut full.platform_output));
    let pixels_per_point = full.pixels_per_point;
    let jobs = panel
        .context
        .tessellate(std::mem::take(&mut full.shapes), pixels_per_point);
    let (device, queue) = (&state.gpu.device, &state.gpu.queue);
    for (id, deltas) in &full.textures_delta.set {
        for delta in deltas {
            panel.renderer.update_texture(device, queue, *id, delta);
        }
    }
    let screen = egui_wgpu::ScreenDescriptor {
        size_in_pixels: [state.config.width, state.config.height],
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
