//! [`guarded`]: a call into GGRS, as an error where GGRS panics.

use crate::app::RunError;

/// Runs a call into GGRS that reads what the other peer sent, as the error
/// that ends the match where GGRS panics: GGRS 0.13 asserts on some
/// messages a damaged datagram or a hostile peer can send (an input for a
/// frame its rollback cannot load), which would otherwise take this
/// process down. A `NetSession` refuses every later call after such an
/// error (`NetSession::guard`).
pub(super) fn guarded<T>(what: &str, call: impl FnOnce() -> T) -> Result<T, RunError> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(call)).map_err(|cause| {
        let why = cause
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| cause.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        RunError::Network(format!(
            "GGRS panicked while {what} ({why}), most likely on a message from the other player that it could \
             not take; the match ends"
        ))
    })
}
