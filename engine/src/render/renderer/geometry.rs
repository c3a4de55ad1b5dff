//! A frame's geometry: the particle records uploaded when the worlds
//! changed, the lines, triangles and placed texts built on the CPU.

use glam::Vec3;

use super::Renderer;
use crate::render::frame_view::FrameView;
use crate::render::line_vertices::{LineVertex, upload_vertices};
use crate::render::overlay::{PlacedText, TextUnit};
use crate::render::records::{Instance, hide_instances, instance_block, record_buffer, write_records};
use crate::render::{Gpu, RenderError};

impl Renderer {
    /// The particles of the frame's GPU worlds, checked against their
    /// buffers.
    pub(super) fn gather_count(&self, view: &FrameView<'_>) -> Result<u64, RenderError> {
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

    pub(super) fn upload_particles(&mut self, gpu: &Gpu, view: &FrameView<'_>) {
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

    pub(super) fn build_lines(&mut self, view: &FrameView<'_>, t: f32) {
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
            crate::render::world_lines::world_lines(&self.config, &shown, t, &mut |a, b, c| push(scratch, a, b, c));
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
    pub(super) fn build_triangles(&mut self, view: &FrameView<'_>) -> Result<(), RenderError> {
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

    pub(super) fn upload_triangles(&mut self, gpu: &Gpu) {
        self.triangle_count = upload_vertices(gpu, &self.triangle_scratch, &mut self.triangle_buffer);
    }

    /// The frame's texts in pixels: each anchor point projected through the
    /// camera (texts behind a 3D camera are left out).
    pub(super) fn place_texts(&mut self, view: &FrameView<'_>, width: u32, height: u32) -> Result<(), RenderError> {
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

    pub(super) fn upload_lines(&mut self, gpu: &Gpu) {
        self.line_count = upload_vertices(gpu, &self.line_scratch, &mut self.line_buffer);
    }
}
