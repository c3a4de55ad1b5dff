//! Helpers shared by the engine's integration tests.

/// A collider that is not pointwise and does nothing: it sends a world down
/// the plain path (rows gathered from the blocks, stepped whole), to compare
/// with the fused path on the same scene.
#[derive(Debug, Clone)]
pub struct ForcePlainPath;

impl tickwork_engine::Collider for ForcePlainPath {
    fn name(&self) -> &'static str {
        "force-plain-path"
    }
    fn is_pointwise(&self) -> bool {
        false
    }
}

/// The state hash `w` would have without its [`ForcePlainPath`] colliders
/// (which change the path a step takes, not its physics), leaving them in
/// place: what a plain-path run is compared with a fused run by.
#[allow(dead_code)] // each test binary compiles this module; not all use it
pub fn hash_without_plain_path(w: &mut tickwork_engine::World) -> u64 {
    let ids: Vec<_> = w
        .colliders()
        .filter(|(_, c)| c.name() == "force-plain-path")
        .map(|(id, _)| id)
        .collect();
    for id in &ids {
        w.remove_collider(*id).expect("in the world");
    }
    let hash = w.state_hash();
    for _ in &ids {
        w.add_collider(ForcePlainPath);
    }
    hash
}

/// The graphics adapter the binary's GPU tests share: one device, made on
/// first use. Without an adapter the tests fail with the error, which names
/// what to install (`scripts/test` installs Mesa's lavapipe); they never
/// skip.
#[cfg(feature = "render")]
pub fn gpu() -> &'static tickwork_engine::render::Gpu {
    static GPU: std::sync::OnceLock<tickwork_engine::render::Gpu> = std::sync::OnceLock::new();
    GPU.get_or_init(|| {
        tickwork_engine::render::Gpu::headless()
            .unwrap_or_else(|error| panic!("the GPU tests need an adapter: {error}"))
    })
}

/// One frame of `view`, drawn off-screen at `size` by a new renderer of
/// `config` on the shared adapter.
#[cfg(feature = "render")]
pub fn draw(
    view: &tickwork_engine::render::FrameView<'_>,
    config: tickwork_engine::render::RendererConfig,
    (width, height): (u32, u32),
) -> tickwork_engine::render::RgbaImage {
    use tickwork_engine::render::{OFFSCREEN_FORMAT, OffscreenTarget, Renderer};
    let mut renderer = Renderer::new(gpu(), OFFSCREEN_FORMAT, config).expect("a renderer");
    let target = OffscreenTarget::new(gpu(), width, height, renderer.config().samples).expect("a target");
    target.render(gpu(), &mut renderer, view).expect("a frame")
}
