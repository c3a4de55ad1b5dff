//! The HUD without the `text` feature: no font, no glyphs, nothing drawn
//! (a game cannot ask for text then: `Draw::text` is not there).

use super::overlay::PlacedText;
use crate::device::Gpu;

/// The renderer's text state without text: nothing.
pub(crate) struct Hud;

impl Hud {
    /// No text to set up.
    pub(crate) fn new(gpu: &Gpu, format: wgpu::TextureFormat, multisample: wgpu::MultisampleState, size: f32) -> Self {
        let _ = (gpu, format, multisample, size);
        Self
    }

    /// Nothing to lay out.
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
    ) -> Result<(), std::convert::Infallible> {
        let _ = (gpu, width, height, text, colours, texts, runs, single);
        Ok(())
    }

    /// Nothing to draw.
    pub(crate) fn render_run(&self, pass: &mut wgpu::RenderPass<'_>, k: usize) {
        let _ = (pass, k);
    }

    /// Nothing to draw.
    pub(crate) fn render(&self, pass: &mut wgpu::RenderPass<'_>) {
        let _ = pass;
    }
}
