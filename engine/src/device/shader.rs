//! How a shader's WGSL is put together: WGSL has no includes, so a shader
//! is its files under `engine/shaders/` joined in order by [`wgsl!`]
//! (at compile time, into the binary), the renderer's after `common.wgsl`
//! (uniforms, the particle record, colour conversions); the GPU step then
//! appends what it writes for each world (its forces' terms, its
//! constants) to its files' text.

/// The WGSL of `files` (paths under `engine/shaders/`), joined in order
/// with a newline between them: `wgsl!("common.wgsl", "lines.wgsl")`.
macro_rules! wgsl {
    ($($file:literal),+ $(,)?) => {
        concat!($(include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/shaders/", $file)), "\n"),+)
    };
}

pub(crate) use wgsl;
