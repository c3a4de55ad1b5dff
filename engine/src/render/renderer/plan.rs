//! Encoding a frame's passes, and planning its draws: each world's layer and ranges, the shapes in
//! the order drawn with their scissors, text runs merged where they can be.

use std::ops::Range;

use super::Renderer;
use crate::render::RenderError;
use crate::render::frame_view::FrameView;
use crate::render::overlay::Shapes;
use crate::render::target::FrameBuffers;

impl Renderer {
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
    pub(super) fn draw_worlds(&self, pass: &mut wgpu::RenderPass<'_>, layer: i32, resolved: bool, single: bool) {
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
    pub(super) fn plan_worlds(&mut self, view: &FrameView<'_>, gpu_count: u64) {
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
    pub(super) fn draw_shapes(&self, pass: &mut wgpu::RenderPass<'_>, call: &ShapeCall, single: bool) {
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
    pub(super) fn scissor(&self, view: &FrameView<'_>, (min, max): (glam::Vec2, glam::Vec2)) -> [u32; 4] {
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

    pub(super) fn draw_unclipped(&self, pass: &mut wgpu::RenderPass<'_>, call: &ShapeCall, single: bool) {
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
    pub(super) fn order_shapes(&mut self, view: &FrameView<'_>) -> Result<(), RenderError> {
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
        if self.text_runs.len() > crate::render::overlay::MAX_TEXT_RUNS {
            return Err(RenderError::Config(format!(
                "the frame has {} runs of text between other shapes, more than the limit of {} \
                 (render::MAX_TEXT_RUNS): draw its texts together",
                self.text_runs.len(),
                crate::render::overlay::MAX_TEXT_RUNS
            )));
        }
        Ok(())
    }

    /// Runs of text side by side in the sorted calls (on one layer and
    /// clip, of consecutive texts: labels on a layer of their own, each
    /// added after a shape on another) become one run, drawn at once.
    pub(super) fn merge_text_runs(&mut self) {
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
}

/// One world of a frame: the layer it is drawn on, its particles' range
/// of the instance buffer and its lines' range of the line vertices.
#[derive(Clone, Debug)]
pub(super) struct WorldDraw {
    pub(super) layer: i32,
    pub(super) instances: Range<u32>,
    pub(super) lines: Range<u32>,
}

/// One draw of a run of the frame's shapes: which kind, on which layer,
/// which vertices of its buffer (sprites: which sprites), and the pixel
/// rectangle `[x, y, width, height]` it is clipped to, if any.
#[derive(Clone, Debug)]
pub(super) struct ShapeCall {
    pub(super) shapes: Shapes,
    pub(super) layer: i32,
    pub(super) vertices: Range<u32>,
    pub(super) scissor: Option<[u32; 4]>,
}
