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

pub(super) fn received_now<T>(receiver: &std::sync::mpsc::Receiver<T>) -> Option<T> {
    receiver.recv().ok()
}

#[cfg(feature = "window")]
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

pub(super) fn spawn_background(future: impl Future<Output = ()> + Send + 'static) {
    // A thread of its own: the future's I/O is driven by its own reactor
    // (async-io's), so any executor runs it.
    std::thread::spawn(move || pollster::block_on(future));
}

pub(super) async fn pause(length: std::time::Duration) {
    std::thread::sleep(length);
}

pub(super) fn show_status(_line: &str) {}

pub(super) fn write_text(path: &std::path::Path, text: &str) -> std::io::Result<()> {
    std::fs::write(path, text)
}

pub(super) fn read_asset(path: &std::path::Path) -> std::io::Result<Vec<u8>> {
    let root = std::env::var_os("TICKWORK_ASSETS").map(std::path::PathBuf::from);
    read_asset_in(path, root.as_deref(), &std::env::current_dir()?)
}

/// [`read_asset`] with the folder `TICKWORK_ASSETS` names (`root`) and the
/// current folder (`here`) given: a relative `path` is read from `root`,
/// else from `here` or the nearest folder above it that has it.
pub(super) fn read_asset_in(
    path: &std::path::Path,
    root: Option<&std::path::Path>,
    here: &std::path::Path,
) -> std::io::Result<Vec<u8>> {
    use std::io::{Error, ErrorKind};
    let read = |file: &std::path::Path| {
        let bytes = std::fs::metadata(file)?.len();
        if bytes > super::MAX_ASSET_BYTES {
            return Err(super::asset_too_large(bytes));
        }
        std::fs::read(file)
    };
    if path.is_absolute() {
        return read(path);
    }
    if let Some(root) = root {
        return read(&root.join(path)).map_err(|e| {
            Error::new(
                e.kind(),
                format!("{e} (in {}, which TICKWORK_ASSETS names)", root.display()),
            )
        });
    }
    match here.ancestors().map(|dir| dir.join(path)).find(|file| file.is_file()) {
        Some(file) => read(&file),
        None => Err(Error::new(
            ErrorKind::NotFound,
            format!(
                "not found in {} or any folder above it (TICKWORK_ASSETS names the folder to read assets from)",
                here.display()
            ),
        )),
    }
}

pub(super) fn exit(code: i32) -> ! {
    std::process::exit(code)
}
