//! The platform services of a native build (see the module above).

use std::ffi::OsString;
use std::future::Future;

pub(super) fn say(line: &str) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    // Flushed: tests and tools wait on these lines as signals.
    let _ = writeln!(out, "{line}");
    let _ = out.flush();
}

pub(super) fn complain(line: &str) {
    eprintln!("{line}");
}

pub(super) fn args() -> Vec<OsString> {
    std::env::args_os().collect()
}

pub(super) fn env_var(name: &str) -> Option<OsString> {
    std::env::var_os(name)
}

pub(super) fn parallel_threads() -> usize {
    std::env::var("RAYON_NUM_THREADS")
        .ok()
        .and_then(|n| n.parse::<usize>().ok())
        .filter(|&n| n > 0)
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, std::num::NonZero::get))
}

pub(super) fn ready_now<F: Future>(future: F) -> Option<F::Output> {
    Some(pollster::block_on(future))
}

#[cfg(feature = "render")]
pub(super) fn window_attributes(
    attributes: winit::window::WindowAttributes,
    size: Option<(u32, u32)>,
) -> Result<winit::window::WindowAttributes, String> {
    Ok(match size {
        Some((width, height)) => attributes.with_inner_size(winit::dpi::PhysicalSize::new(width, height)),
        None => attributes,
    })
}

pub(super) fn spawn_local(future: impl Future<Output = ()> + 'static) {
    pollster::block_on(future);
}

pub(super) fn show_status(_line: &str) {}

pub(super) fn write_text(path: &std::path::Path, text: &str) -> std::io::Result<()> {
    std::fs::write(path, text)
}

pub(super) fn exit(code: i32) -> ! {
    std::process::exit(code)
}
