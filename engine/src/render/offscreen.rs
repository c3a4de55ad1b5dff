//! An off-screen frame: [`OffscreenTarget::render`] and
//! [`OffscreenTarget::draw`], which prepare the renderer, encode its passes
//! into the target's buffers, copy and read the image back. They sit apart
//! from `target.rs` because they use the [`Renderer`], which itself uses
//! the target's buffers: this way the imports run one way.

use image::RgbaImage;

use super::{FrameView, Gpu, OffscreenTarget, RenderError, Renderer};

impl OffscreenTarget {
    /// Draws `view` and reads the frame back: prepare, encode, copy,
    /// submit, wait.
    ///
    /// # Errors
    /// As [`Renderer::prepare`] and [`OffscreenTarget::read_image`].
    pub fn render(&self, gpu: &Gpu, renderer: &mut Renderer, view: &FrameView<'_>) -> Result<RgbaImage, RenderError> {
        self.draw(gpu, renderer, view, true)?;
        self.read_image(gpu)
    }

    /// Draws `view` without reading it back (for benchmarks of the render
    /// alone); with `copy`, also records the copy into the read-back buffer.
    ///
    /// # Errors
    /// As [`Renderer::prepare`].
    pub fn draw(
        &self,
        gpu: &Gpu,
        renderer: &mut Renderer,
        view: &FrameView<'_>,
        copy: bool,
    ) -> Result<(), RenderError> {
        renderer.prepare(gpu, self.buffers(), view)?;
        let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("tickwork frame"),
        });
        renderer.encode(&mut encoder, self.buffers(), self.view());
        if copy {
            self.encode_copy(&mut encoder);
        }
        gpu.queue.submit(Some(encoder.finish()));
        Ok(())
    }
}
