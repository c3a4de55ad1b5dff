//! The graphics device and what the renderer and the GPU step share of it:
//! the [`Gpu`] (adapter, device, queue), its errors ([`RenderError`]), the
//! bindings and compute pipelines both build, and how a shader's WGSL is
//! put together ([`wgsl!`](shader)). Both `render` and `gpu_step` import
//! it; neither imports the other for it. Available with the `render`
//! feature; `render` re-exports its public items, where a game finds them.

mod bindings;
mod error;
mod gpu;
mod shader;

pub(crate) use bindings::{bind_buffers, compute_pipeline, compute_storage, entry};
pub use error::RenderError;
pub use gpu::{Gpu, quiet_device_select_layer};
pub(crate) use shader::wgsl;
