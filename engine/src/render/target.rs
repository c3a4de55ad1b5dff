//! Render targets: the multisampled colour and depth buffers every frame
//! draws into, and an off-screen target that resolves them into a texture
//! and reads it back as an image.

use image::RgbaImage;

use super::{Gpu, RenderError};

/// Depth buffer format of every pass.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Colour format of off-screen targets: 8-bit sRGB, so blending happens in
/// linear light and the PNG holds sRGB values.
pub const OFFSCREEN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// wgpu's alignment of texture rows copied into a buffer.
const ROW_ALIGNMENT: u32 = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;

/// The buffers a frame is drawn into before it is resolved: a multisampled
/// colour buffer (absent without MSAA) and a depth buffer of the same size.
#[derive(Debug)]
pub struct FrameBuffers {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Colour format (of the resolve target too).
    pub format: wgpu::TextureFormat,
    /// Samples per pixel (1 or 4).
    pub samples: u32,
    msaa: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
    /// Single-sampled depth for frames drawn without MSAA (the splat path);
    /// the same as `depth` when `samples` is 1.
    single_depth: wgpu::TextureView,
}

impl FrameBuffers {
    /// Buffers of `width` x `height` pixels.
    ///
    /// # Errors
    /// [`RenderError::Size`] for a zero or too large size.
    pub fn new(
        gpu: &Gpu,
        width: u32,
        height: u32,
        format: wgpu::TextureFormat,
        samples: u32,
    ) -> Result<Self, RenderError> {
        check_size(gpu, width, height)?;
        gpu.allocate(
            &|| format!("{width}x{height} frame buffers with {samples} samples per pixel"),
            || Ok(Self::create(gpu, width, height, format, samples)),
        )
    }

    fn create(gpu: &Gpu, width: u32, height: u32, format: wgpu::TextureFormat, samples: u32) -> Self {
        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let texture = |label, format, sample_count| {
            gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                view_formats: &[],
            })
        };
        let msaa =
            (samples > 1).then(|| texture("tickwork msaa colour", format, samples).create_view(&Default::default()));
        let depth = texture("tickwork depth", DEPTH_FORMAT, samples).create_view(&Default::default());
        let single_depth = if samples > 1 {
            texture("tickwork single-sample depth", DEPTH_FORMAT, 1).create_view(&Default::default())
        } else {
            depth.clone()
        };
        Self {
            width,
            height,
            format,
            samples,
            msaa,
            depth,
            single_depth,
        }
    }

    /// The colour attachment that draws into `output` (through the
    /// multisampled buffer, resolved into `output`, when MSAA is on).
    #[must_use]
    pub fn colour_attachment<'a>(
        &'a self,
        output: &'a wgpu::TextureView,
        clear: wgpu::Color,
    ) -> wgpu::RenderPassColorAttachment<'a> {
        let (view, resolve_target) = match &self.msaa {
            Some(msaa) => (msaa, Some(output)),
            None => (output, None),
        };
        wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(clear),
                // The multisampled samples are not needed after the resolve.
                store: if resolve_target.is_some() {
                    wgpu::StoreOp::Discard
                } else {
                    wgpu::StoreOp::Store
                },
            },
        }
    }

    /// The colour attachment that draws straight into `output`, one sample
    /// per pixel (frames whose particles are anti-aliased analytically),
    /// cleared to `clear` or, with `None`, keeping what `output` holds.
    #[must_use]
    pub fn single_sample_attachment<'a>(
        &'a self,
        output: &'a wgpu::TextureView,
        clear: Option<wgpu::Color>,
    ) -> wgpu::RenderPassColorAttachment<'a> {
        wgpu::RenderPassColorAttachment {
            view: output,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: clear.map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear),
                store: wgpu::StoreOp::Store,
            },
        }
    }

    /// The depth attachment, cleared to the far plane; `single` selects the
    /// single-sampled one.
    #[must_use]
    pub fn depth_attachment(&self, single: bool) -> wgpu::RenderPassDepthStencilAttachment<'_> {
        wgpu::RenderPassDepthStencilAttachment {
            view: if single { &self.single_depth } else { &self.depth },
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Discard,
            }),
            stencil_ops: None,
        }
    }
}

/// Refuses sizes a texture cannot have, naming the size.
pub(crate) fn check_size(gpu: &Gpu, width: u32, height: u32) -> Result<(), RenderError> {
    let max = gpu.device.limits().max_texture_dimension_2d;
    if width == 0 || height == 0 || width > max || height > max {
        return Err(RenderError::Size { width, height, max });
    }
    Ok(())
}

/// An image-sized render target with no window: frames are drawn, resolved
/// into a texture, copied into a buffer and read back as an [`RgbaImage`].
#[derive(Debug)]
pub struct OffscreenTarget {
    buffers: FrameBuffers,
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    readback: wgpu::Buffer,
    padded_row: u32,
}

impl OffscreenTarget {
    /// A target of `width` x `height` pixels with `samples` samples per
    /// pixel (4 for MSAA, 1 without).
    ///
    /// # Errors
    /// [`RenderError::Size`] for a zero or too large size.
    pub fn new(gpu: &Gpu, width: u32, height: u32, samples: u32) -> Result<Self, RenderError> {
        let buffers = FrameBuffers::new(gpu, width, height, OFFSCREEN_FORMAT, samples)?;
        gpu.allocate(
            &|| format!("a {width}x{height} off-screen target and its readback buffer"),
            || Ok(Self::create(gpu, buffers, width, height)),
        )
    }

    fn create(gpu: &Gpu, buffers: FrameBuffers, width: u32, height: u32) -> Self {
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("tickwork offscreen"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: OFFSCREEN_FORMAT,
            // COPY_DST: the splat path copies its resolved pixels in.
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        // Rows in the buffer are padded up to 256 bytes.
        let padded_row = (width * 4).div_ceil(ROW_ALIGNMENT) * ROW_ALIGNMENT;
        let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("tickwork readback"),
            size: u64::from(padded_row) * u64::from(height),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        Self {
            buffers,
            texture,
            view,
            readback,
            padded_row,
        }
    }

    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.buffers.width
    }

    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.buffers.height
    }

    /// The buffers frames are drawn into.
    #[must_use]
    pub fn buffers(&self) -> &FrameBuffers {
        &self.buffers
    }

    /// The resolved texture's view (the pass's output).
    #[must_use]
    pub fn view(&self) -> &wgpu::TextureView {
        &self.view
    }

    /// Records the copy of the resolved texture into the read-back buffer.
    pub fn encode_copy(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.copy_texture_to_buffer(
            self.texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &self.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.padded_row),
                    rows_per_image: Some(self.buffers.height),
                },
            },
            wgpu::Extent3d {
                width: self.buffers.width,
                height: self.buffers.height,
                depth_or_array_layers: 1,
            },
        );
    }

    /// Waits for the copy recorded by [`OffscreenTarget::encode_copy`] and
    /// returns the image, dropping each row's padding.
    ///
    /// # Errors
    /// [`RenderError::Device`] if the buffer cannot be mapped.
    pub fn read_image(&self, gpu: &Gpu) -> Result<RgbaImage, RenderError> {
        let slice = self.readback.slice(..);
        let (sender, receiver) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |result| {
            let _ = sender.send(result);
        });
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|error| RenderError::Device(format!("waiting for the read-back: {error}")))?;
        receiver
            .recv()
            .map_err(|_| RenderError::Device("the read-back was dropped".into()))?
            .map_err(|error| RenderError::Device(format!("mapping the read-back buffer: {error}")))?;
        let (width, height) = (self.buffers.width, self.buffers.height);
        let row = (width * 4) as usize;
        let mut pixels = Vec::with_capacity(row * height as usize);
        {
            let mapped = slice
                .get_mapped_range()
                .map_err(|error| RenderError::Device(format!("reading the read-back buffer: {error}")))?;
            for padded in mapped.chunks_exact(self.padded_row as usize) {
                pixels.extend_from_slice(&padded[..row]);
            }
        }
        self.readback.unmap();
        RgbaImage::from_raw(width, height, pixels)
            .ok_or_else(|| RenderError::Device("read-back size does not match the target".into()))
    }
}
