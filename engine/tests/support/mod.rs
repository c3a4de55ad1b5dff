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
