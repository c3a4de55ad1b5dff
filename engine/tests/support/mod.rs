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
