//! The runners: [`run`](fn@crate::app::run) and what it hands a game to,
//! natively off-screen ([`OffscreenRun`](crate::app::OffscreenRun)) or in a
//! window (the `window` feature; winit lives only here and in
//! `platform/`), in a page; the shared options ([`RunOptions`](crate::app::RunOptions),
//! clap with the `cli` feature).

pub(crate) mod native;
pub(crate) mod offscreen;
pub(crate) mod options;
// The page's runner: only the browser build has one (its canvas is a
// window's).
#[cfg(all(target_arch = "wasm32", feature = "window"))]
pub(crate) mod page;
// A match in a page, over WebRTC.
#[cfg(all(target_arch = "wasm32", feature = "window", feature = "webrtc"))]
pub(crate) mod page_match;
pub(crate) mod start;
#[cfg(feature = "window")]
pub(crate) mod window;
