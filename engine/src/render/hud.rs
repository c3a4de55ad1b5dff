//! Text with glyphon, from the font shipped in `engine/fonts/` (never the
//! machine's fonts, so golden images are the same everywhere): the HUD
//! line, drawn over the frame, and the game's texts, in runs drawn where
//! the frame's order puts them (one glyphon renderer per run, sharing one
//! glyph atlas).

use glyphon::{
    Attrs, Buffer, Cache, Color, Family, FontSystem, Metrics, PrepareError, Resolution, Shaping, SwashCache, TextArea,
    TextAtlas, TextBounds, TextRenderer, Viewport,
};

use super::Gpu;
use super::overlay::{Anchor, PlacedText};
use super::target::DEPTH_FORMAT;
use super::text_layout::{LINE_HEIGHT, font_system, lay_out};

/// A laid-out text of the game's, kept from frame to frame: laid out again
/// only when its text or size changes.
struct LaidOut {
    buffer: Buffer,
    text: String,
    size: f32,
    /// Its anchor, which aligns its lines.
    anchor: Anchor,
    /// Width and height of the laid-out text, in pixels.
    extent: (f32, f32),
}

/// glyphon's state for one renderer: fonts, glyph atlas, laid-out text.
pub(crate) struct Hud {
    fonts: FontSystem,
    swash: SwashCache,
    viewport: Viewport,
    atlas: TextAtlas,
    renderer: TextRenderer,
    /// For single-sampled frames (the splat path).
    renderer_single: TextRenderer,
    /// Which of the two the last `prepare` filled.
    single: bool,
    /// One renderer per run of the game's texts (as many as a frame has
    /// had runs, kept), for multisampled and single-sampled frames.
    runs: Vec<TextRenderer>,
    runs_single: Vec<TextRenderer>,
    multisample: wgpu::MultisampleState,
    depth: wgpu::DepthStencilState,
    buffer: Buffer,
    text: String,
    /// Colour changes of the laid-out text: (byte offset, sRGB RGBA).
    colours: Vec<(usize, [u8; 4])>,
    laid_out: (u32, u32),
    size: f32,
    /// The game's placed texts, one buffer each, reused.
    placed: Vec<LaidOut>,
}

impl Hud {
    pub(crate) fn new(gpu: &Gpu, format: wgpu::TextureFormat, multisample: wgpu::MultisampleState, size: f32) -> Self {
        let mut fonts = font_system();
        let cache = Cache::new(&gpu.device);
        let viewport = Viewport::new(&gpu.device, &cache);
        let mut atlas = TextAtlas::new(&gpu.device, &gpu.queue, &cache, format);
        // Text is drawn in the frame's pass, which has a depth buffer:
        // test always, write never (the order of the calls decides).
        let depth = wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(false),
            depth_compare: Some(wgpu::CompareFunction::Always),
            stencil: Default::default(),
            bias: Default::default(),
        };
        let renderer = TextRenderer::new(&mut atlas, &gpu.device, multisample, Some(depth.clone()));
        let renderer_single = TextRenderer::new(
            &mut atlas,
            &gpu.device,
            wgpu::MultisampleState::default(),
            Some(depth.clone()),
        );
        let buffer = Buffer::new(&mut fonts, Metrics::new(size, size * 1.3));
        Self {
            fonts,
            swash: SwashCache::new(),
            viewport,
            atlas,
            renderer,
            renderer_single,
            single: false,
            runs: Vec::new(),
            runs_single: Vec::new(),
            multisample,
            depth,
            buffer,
            text: String::new(),
            colours: Vec::new(),
            laid_out: (0, 0),
            size,
            placed: Vec::new(),
        }
    }

    /// Lays out `text` (only if it changed) and the game's placed `texts`,
    /// and uploads their glyphs: the HUD's, and each of `runs` (ranges of
    /// `texts`) for its own draw call.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn prepare(
        &mut self,
        gpu: &Gpu,
        width: u32,
        height: u32,
        text: &str,
        colours: &[(usize, [u8; 4])],
        texts: &[PlacedText],
        runs: &[std::ops::Range<usize>],
        single: bool,
    ) -> Result<(), PrepareError> {
        // Glyphs no text of the last frame used may go, so the atlas holds
        // what is shown rather than every glyph ever drawn.
        self.atlas.trim();
        self.lay_out_placed(texts);
        self.single = single;
        self.viewport.update(&gpu.queue, Resolution { width, height });
        if text != self.text || colours != self.colours || (width, height) != self.laid_out {
            self.laid_out = (width, height);
            self.text.clear();
            self.text.push_str(text);
            self.colours.clear();
            self.colours.extend_from_slice(colours);
            self.buffer.set_size(Some(width as f32), Some(height as f32));
            let base = Attrs::new().family(Family::SansSerif);
            if colours.is_empty() {
                self.buffer.set_text(text, &base, Shaping::Basic, None);
            } else {
                // Span k runs from its offset to the next one's, in its colour.
                let mut cuts: Vec<(usize, Option<[u8; 4]>)> = vec![(0, None)];
                cuts.extend(
                    colours
                        .iter()
                        .filter(|(at, _)| *at <= text.len() && text.is_char_boundary(*at))
                        .map(|&(at, c)| (at, Some(c))),
                );
                let spans = cuts.iter().enumerate().map(|(k, &(start, colour))| {
                    let end = cuts.get(k + 1).map_or(text.len(), |c| c.0).max(start);
                    let attrs = match colour {
                        Some([r, g, b, a]) => base.clone().color(Color::rgba(r, g, b, a)),
                        None => base.clone(),
                    };
                    (&text[start..end], attrs)
                });
                self.buffer.set_rich_text(spans, &base, Shaping::Basic, None);
            }
            self.buffer.shape_until_scroll(&mut self.fonts, false);
        }
        let margin = (self.size * 0.5) as i32;
        let area = TextArea {
            buffer: &self.buffer,
            left: margin as f32,
            top: margin as f32,
            scale: 1.0,
            bounds: TextBounds {
                left: 0,
                top: 0,
                right: width as i32,
                bottom: height as i32,
            },
            default_color: Color::rgb(235, 235, 235),
            custom_glyphs: &[],
        };
        let bounds = area.bounds;
        let placed = |run: std::ops::Range<usize>| {
            texts[run.clone()]
                .iter()
                .zip(&self.placed[run])
                .map(move |(text, laid)| {
                    let (w, h) = laid.extent;
                    let (fx, fy) = text.anchor.fractions();
                    let (left, top) = (text.x - fx * w, text.y - fy * h);
                    let [r, g, b, a] = text.colour;
                    TextArea {
                        buffer: &laid.buffer,
                        left: left.round(),
                        top: top.round(),
                        scale: 1.0,
                        bounds,
                        default_color: Color::rgba(r, g, b, a),
                        custom_glyphs: &[],
                    }
                })
        };
        let (renderer, pool) = if single {
            (&mut self.renderer_single, &mut self.runs_single)
        } else {
            (&mut self.renderer, &mut self.runs)
        };
        renderer.prepare(
            &gpu.device,
            &gpu.queue,
            &mut self.fonts,
            &mut self.atlas,
            &self.viewport,
            std::iter::once(area),
            &mut self.swash,
        )?;
        let multisample = if single {
            wgpu::MultisampleState::default()
        } else {
            self.multisample
        };
        for (k, run) in runs.iter().enumerate() {
            if k == pool.len() {
                pool.push(TextRenderer::new(
                    &mut self.atlas,
                    &gpu.device,
                    multisample,
                    Some(self.depth.clone()),
                ));
            }
            pool[k].prepare(
                &gpu.device,
                &gpu.queue,
                &mut self.fonts,
                &mut self.atlas,
                &self.viewport,
                placed(run.clone()),
                &mut self.swash,
            )?;
        }
        Ok(())
    }

    /// Lays out the texts that changed since the last frame (a buffer per
    /// text, kept), measuring each.
    fn lay_out_placed(&mut self, texts: &[PlacedText]) {
        for (k, text) in texts.iter().enumerate() {
            if k == self.placed.len() {
                self.placed.push(LaidOut {
                    buffer: Buffer::new(&mut self.fonts, Metrics::new(text.size, text.size * LINE_HEIGHT)),
                    text: String::new(),
                    size: 0.0,
                    anchor: text.anchor,
                    extent: (0.0, 0.0),
                });
            }
            let laid = &mut self.placed[k];
            if laid.text == text.text && laid.size == text.size && laid.anchor == text.anchor {
                continue;
            }
            laid.text.clone_from(&text.text);
            laid.size = text.size;
            laid.anchor = text.anchor;
            let extent = lay_out(
                &mut self.fonts,
                &mut laid.buffer,
                &text.text,
                text.size,
                text.anchor.align(),
            );
            laid.extent = (extent.x, extent.y);
        }
    }

    /// Draws the prepared run `k` of the game's texts.
    pub(crate) fn render_run(&self, pass: &mut wgpu::RenderPass<'_>, k: usize) {
        let pool = if self.single { &self.runs_single } else { &self.runs };
        if let Some(renderer) = pool.get(k) {
            // As in `render`.
            let _ = renderer.render(&self.atlas, &self.viewport, pass);
        }
    }

    /// Draws the prepared HUD line (nothing if it is empty).
    pub(crate) fn render(&self, pass: &mut wgpu::RenderPass<'_>) {
        // Fails only if glyphs were evicted between prepare and render,
        // which cannot happen within one frame.
        let renderer = if self.single {
            &self.renderer_single
        } else {
            &self.renderer
        };
        let _ = renderer.render(&self.atlas, &self.viewport, pass);
    }
}
