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

mod camera;
mod config;
mod follow;
mod frame_view;
mod gather;
mod golden;
mod hermite;
// Text through glyphon with the `text` feature; without it, nothing draws
// text (`Draw::text` is not there).
#[cfg(feature = "text")]
mod hud;
#[cfg(not(feature = "text"))]
#[path = "no_text.rs"]
mod hud;
mod line_vertices;
mod offscreen;
mod overlay;
mod pipeline;
mod records;
mod renderer;
mod splat;
mod sprite;
mod sprites;
mod stroke;
mod target;
pub(crate) mod tessellate;
#[cfg(feature = "text")]
mod text_layout;
mod texture;
mod trails;
mod world_lines;

pub use crate::device::RenderError;
pub use crate::device::{Gpu, quiet_device_select_layer};
pub use crate::interpolation::Interpolation;
pub use camera::{Camera, CameraMatrices, Fit, FrameRect};
pub use config::{Blend, RendererConfig};
pub use follow::Follow;
pub use frame_view::{FrameView, GpuParticles, WorldView};
pub use golden::{Comparison, GoldenError, GoldenImages, Tolerance, compare, diff_image};
pub use image::{Rgba, RgbaImage};
pub(crate) use overlay::extend_batches;
pub use overlay::{Anchor, Batch, Line, MAX_TEXT_RUNS, Shapes, Text, TextUnit, Triangle};
pub use renderer::Renderer;
pub use sprite::{Animation, Sprite};
pub use stroke::{Cap, Join, Stroke, Width};
pub use target::{DEPTH_FORMAT, FrameBuffers, OFFSCREEN_FORMAT, OffscreenTarget};
#[cfg(feature = "text")]
pub use text_layout::measure_text;
pub use texture::{MAX_TEXTURE_SIDE, Texture, TextureError};
pub use trails::Trails;
