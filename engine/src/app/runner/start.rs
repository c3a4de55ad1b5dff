//! [`run`]: where a game's `main` starts, natively or in a page.

use crate::app::api::error::RunError;
use crate::app::api::game::Game;
use crate::app::runner::native::RunSummary;
use crate::app::runner::options::RunOptions;

/// Runs `game` with `options`: in a window when a display is available
/// (and `--headless` is not given), else off-screen into PNG frames and a
/// GIF, saying where; in a browser, on a canvas in the page (its options
/// from the URL; it returns at once and the page plays on). All go
/// through [`GameSession`](crate::app::GameSession)'s per-frame path.
/// Prints where files went and the game's outcome. Call it from `main`
/// before starting threads of your own: it may quiet a Vulkan layer
/// through the environment ([`quiet_device_select_layer`](crate::render::quiet_device_select_layer)).
///
/// # Errors
/// [`RunError`] with what went wrong: a bad option or recording, no GPU
/// adapter, a failed step, a file that exists (without `--force`).
pub fn run<G: Game + Clone + 'static>(game: G, options: RunOptions) -> Result<RunSummary, RunError> {
    // In a browser the page's runner plays it (and returns at once).
    #[cfg(all(target_arch = "wasm32", feature = "window"))]
    let run = crate::app::runner::page::run_in_page;
    #[cfg(all(target_arch = "wasm32", not(feature = "window")))]
    let run = |_: G, _: RunOptions| {
        Err(RunError::Limit(
            "a page draws on its canvas through Tickwork's `window` feature, which this game was built without".into(),
        ))
    };
    #[cfg(not(target_arch = "wasm32"))]
    let run = crate::app::runner::native::run_native;
    run(game, options)
}
