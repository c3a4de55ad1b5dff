//! The wgpu renderer: particles as anti-aliased discs interpolated between
//! fixed steps on the GPU, lines for springs, trails and rigid bodies, a HUD,
//! and off-screen targets read back as images.
//!
//! The renderer only reads the world. Each frame it uploads the previous
//! and current positions if the world changed since the last frame (one
//! pass, no interpolation on the CPU; the current velocities too in
//! [`Interpolation::Hermite`] mode) and the clock's alpha as a uniform.
//!
//! ```no_run
//! use tickwork_engine::render::{Camera, FrameView, Gpu, OffscreenTarget, Renderer, RendererConfig, OFFSCREEN_FORMAT};
//! use tickwork_engine::{Particle, World};
//!
//! let gpu = Gpu::headless()?; // an error naming what to install if there is no adapter
//! let mut world = World::default();
//! world.spawn(Particle::default())?;
//! let mut renderer = Renderer::new(&gpu, OFFSCREEN_FORMAT, RendererConfig::default())?;
//! let target = OffscreenTarget::new(&gpu, 320, 240, 4)?;
//! let image = target.render(&gpu, &mut renderer, &FrameView::new(&world, 0.0, Camera::default()))?;
//! image.save("frame.png")?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

/// A shader's WGSL source: `assets/shaders/common.wgsl` (uniforms, the
/// particle record, colour conversions), then the named file. WGSL has no
/// includes; this keeps the shared definitions in one place.
macro_rules! shader {
    ($file:literal) => {
        concat!(
            include_str!("../../../assets/shaders/common.wgsl"),
            "\n",
            include_str!(concat!("../../../assets/shaders/", $file))
        )
    };
}

mod camera;
mod config;
mod frame_view;
mod golden;
mod gpu;
mod hermite;
mod hud;
mod line_vertices;
mod overlay;
mod pipeline;
mod records;
mod renderer;
mod splat;
mod target;
mod trails;
mod world_lines;

use std::fmt;

pub use crate::interpolation::Interpolation;
pub use camera::{Camera, CameraMatrices};
pub use config::{Blend, RendererConfig};
pub use frame_view::{FrameView, WorldView};
pub use golden::{Comparison, GoldenError, GoldenImages, Tolerance, compare, diff_image};
pub use gpu::{Gpu, quiet_device_select_layer};
pub use image::RgbaImage;
pub use overlay::{Anchor, Line, Text, Triangle};
pub use renderer::Renderer;
pub use target::{DEPTH_FORMAT, FrameBuffers, OFFSCREEN_FORMAT, OffscreenTarget};
pub use trails::Trails;

/// Why a frame could not be drawn.
#[derive(Debug)]
pub enum RenderError {
    /// No adapter on any backend tried.
    NoAdapter {
        /// The backends tried.
        backends: Vec<&'static str>,
        /// wgpu's reason.
        reason: String,
    },
    /// The adapter refused a device, or the device failed.
    Device(String),
    /// A target size that cannot be drawn.
    Size {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// The device's largest texture side.
        max: u32,
    },
    /// A renderer setting or frame input out of range.
    Config(String),
    /// A window surface could not be created or configured.
    Surface(String),
    /// A file could not be written.
    Io {
        /// The file.
        path: std::path::PathBuf,
        /// What went wrong.
        message: String,
    },
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoAdapter { backends, reason } => {
                write!(
                    f,
                    "no graphics adapter found (backends tried: {}; wgpu says: {reason})",
                    if backends.is_empty() {
                        "none: is WGPU_BACKEND set to an empty or unknown value?".to_string()
                    } else {
                        backends.join(", ")
                    }
                )?;
                if cfg!(target_os = "linux") {
                    write!(
                        f,
                        "; for a software adapter install Mesa's Vulkan driver \
                         (Debian/Ubuntu: `apt-get install mesa-vulkan-drivers libvulkan1`) \
                         or its GL driver (`libegl1 libegl-mesa0 libgl1-mesa-dri`)"
                    )?;
                }
                Ok(())
            }
            Self::Device(message) => write!(f, "graphics device error: {message}"),
            Self::Size { width, height, max } => write!(
                f,
                "cannot render a {width}x{height} image: both sides must be between 1 and {max} pixels"
            ),
            Self::Config(message) => write!(f, "renderer: {message}"),
            Self::Surface(message) => write!(f, "window surface: {message}"),
            Self::Io { path, message } => write!(f, "{}: {message}", path.display()),
        }
    }
}

impl std::error::Error for RenderError {}

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
