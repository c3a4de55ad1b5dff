//! The demos' and the command line's tests, one module a subject, in one
//! test binary; the browser's are in `tests/web/`.

mod breakout;
mod cli;
mod demos;
mod hostile_input;
mod lab;
mod platformer;
mod rally;
mod render;
mod support;
