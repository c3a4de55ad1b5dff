//! The tests that play pages in a headless Chromium (through the
//! DevTools-protocol client in `browser/`), and the game made outside the
//! checkout: one test binary.

mod browser;
mod browser_smoke;
mod netplay;
mod own_game;
mod web;
