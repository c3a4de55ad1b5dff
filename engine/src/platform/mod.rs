//! Where a native build and the browser differ, and nowhere else.
//!
//! The engine runs the same code on x86_64 and on `wasm32-unknown-unknown`;
//! what the two platforms do differently is a handful of services, each a
//! function here with one implementation per platform (`native.rs`,
//! `web.rs`, chosen below and only here):
//!
//! | service | native | web |
//! |---|---|---|
//! | time ([`Instant`]) | `std::time::Instant` | `performance.now()` (through `web-time`) |
//! | printed lines ([`say`], [`complain`]) | standard output and error | the console (`console.log`, `console.error`) |
//! | the command line ([`args`]) | the process's arguments | the page's URL query (`?hz=120&seed=3`) |
//! | the environment ([`env_var`]) | the process's | none |
//! | threads ([`parallel_threads`]) | rayon's pool, one per core | one: the step runs the one-lane path, bit-identical to the parallel one |
//! | writing a file ([`write_text`]) | the file system | a download offered to the user |
//! | reading an asset ([`read_asset`]) | the file system (`TICKWORK_ASSETS`, or the current folder and those above it) | the bytes fetched before the game's setup (`Game::assets`) |
//! | waiting on a future ([`ready_now`]) | blocks (pollster) | one poll: a browser resolves futures only once the page's script yields |
//! | a task beside the game ([`spawn_background`]) | a thread | the browser's event loop |
//! | a pause in an `async` function ([`pause`]) | the thread sleeps | a timer the page yields to |
//!
//! The browser alone has `platform::web`: fetching files by URL, offering a file as
//! a download, showing a message on the page. Files, windows and GPU
//! start-up differ more than a function can hide; the runners use these
//! services and say where they branch (`app/page.rs` is the page's runner).

use std::ffi::OsString;
use std::future::Future;

#[cfg(not(target_arch = "wasm32"))]
mod native;
#[cfg(not(target_arch = "wasm32"))]
use native as imp;
#[cfg(target_arch = "wasm32")]
pub mod web;
#[cfg(target_arch = "wasm32")]
use web as imp;

/// A point in real time: `std::time::Instant` natively, the page's
/// `performance.now()` in the browser (where `std`'s panics).
pub use web_time::Instant;

/// Whether this is the browser build (`wasm32`): for the few decisions a
/// runner makes differently there (no threads, no files, no blocking).
pub const IS_WEB: bool = cfg!(target_arch = "wasm32");

/// Prints a line for the user: standard output natively, the console in
/// the browser. Every line the engine prints goes through here (or
/// [`say!`](crate::say)), so a page prints what a native run prints.
pub fn say(line: &str) {
    imp::say(line);
}

/// Prints an error line: standard error natively; the console's error
/// level in the browser, and on the page itself.
pub fn complain(line: &str) {
    imp::complain(line);
}

/// The command line: the process's arguments natively; in the browser,
/// the page's name then its URL query as options (`?integrator=rk4&frames=600`
/// is `--integrator rk4 --frames 600`; a flag without a value, `?headless`,
/// is `--headless`), so the same parser reads both.
#[must_use]
pub fn args() -> Vec<OsString> {
    imp::args()
}

/// A page's command line from its name and URL query (with or without
/// its `?`): `?integrator=rk4&headless` is `[name, --integrator, rk4,
/// --headless]`, each name and value through `decode` (the page's
/// percent-decoding). Pure, so it is tested natively too.
#[cfg_attr(not(target_arch = "wasm32"), allow(dead_code))]
fn query_args(name: &str, query: &str, decode: impl Fn(&str) -> String) -> Vec<String> {
    let mut args = vec![name.to_owned()];
    for pair in query.trim_start_matches('?').split('&').filter(|p| !p.is_empty()) {
        let (key, value) = pair.split_once('=').map_or((pair, None), |(k, v)| (k, Some(v)));
        args.push(format!("--{}", decode(key)));
        if let Some(value) = value {
            args.push(decode(value));
        }
    }
    args
}

/// An environment variable: the process's natively, none in the browser.
#[must_use]
pub fn env_var(name: &str) -> Option<OsString> {
    imp::env_var(name)
}

/// How many threads a step may use: `RAYON_NUM_THREADS` or the machine's
/// cores natively, one in the browser.
#[must_use]
pub fn parallel_threads() -> usize {
    imp::parallel_threads()
}

/// The output of `future` if it can be had now: natively it blocks until
/// the future resolves (always `Some`); in the browser it polls once,
/// since blocking would stop the page from ever resolving it (`None`
/// when it is still pending).
pub fn ready_now<F: Future>(future: F) -> Option<F::Output> {
    imp::ready_now(future)
}

/// The value `receiver` is sent, if it can be had now: natively it blocks
/// until the sender sends (`None` if it was dropped unsent), as a GPU
/// read-back's answer comes from whichever thread's wait runs its
/// callback; in the browser it takes what was sent already (`None` when
/// nothing was: a page cannot block for it).
pub fn received_now<T>(receiver: &std::sync::mpsc::Receiver<T>) -> Option<T> {
    imp::received_now(receiver)
}

/// `attributes` for the runner's window: natively of `size` (physical
/// pixels; `None` leaves it to the system); in a page, a canvas appended
/// to the page's `tickwork` element (or its body), of `size`, or filling
/// the page and following it (`None`), focused so that keys reach it.
///
/// # Errors
/// In a page, the browser's message if the canvas cannot be made.
#[cfg(feature = "window")]
pub fn window_attributes(
    attributes: winit::window::WindowAttributes,
    size: Option<(u32, u32)>,
) -> Result<winit::window::WindowAttributes, String> {
    imp::window_attributes(attributes, size)
}

/// Runs `future` to its end: natively now (blocking), in a page on the
/// browser's event loop once the current script yields.
pub fn spawn_local(future: impl Future<Output = ()> + 'static) {
    imp::spawn_local(future);
}

/// Runs `future` beside the caller, to its end: natively on a thread of
/// its own (so the future must be `Send`), in a page on the browser's
/// event loop. For a connection's loop (a WebRTC socket's) that runs while
/// the game does.
#[cfg(not(target_arch = "wasm32"))]
pub fn spawn_background(future: impl Future<Output = ()> + Send + 'static) {
    imp::spawn_background(future);
}

/// Runs `future` beside the caller, to its end: natively on a thread of
/// its own (so the future must be `Send`), in a page on the browser's
/// event loop. For a connection's loop (a WebRTC socket's) that runs while
/// the game does.
#[cfg(target_arch = "wasm32")]
pub fn spawn_background(future: impl Future<Output = ()> + 'static) {
    imp::spawn_background(future);
}

/// Waits `length` in an `async` function: natively the thread sleeps (the
/// caller blocks on the future anyway); in a page the script yields to the
/// browser until a timer fires, so the page goes on meanwhile.
pub async fn pause(length: std::time::Duration) {
    imp::pause(length).await;
}

/// Writes `text` to the file `path`: natively the file system; in a page
/// (which cannot write files) the user is offered it as a download named
/// after the path's file name.
///
/// # Errors
/// The file system's error, or the browser's.
pub fn write_text(path: &std::path::Path, text: &str) -> std::io::Result<()> {
    imp::write_text(path, text)
}

/// The largest asset file [`read_asset`] reads: 64 MiB. A larger one is an
/// error naming this constant; a game with larger files splits them.
pub const MAX_ASSET_BYTES: u64 = 64 << 20;

/// The bytes of the asset file `path` (a texture, a sound), the same on
/// both platforms:
/// - natively, an absolute path is read as it is; a relative one is read
///   from the folder `TICKWORK_ASSETS` names where it is set, else from
///   the current folder or the nearest folder above it that has it (as
///   git finds `.git`), so `cargo run` and `cargo test` from any crate
///   of a workspace find the workspace's `assets/`;
/// - in a page, which cannot read files, the bytes the page fetched for
///   that path before the game's setup: the game lists them in
///   `Game::assets`, and the page fetches each
///   from its asset root (the `data-assets` attribute of the page's
///   `tickwork` element, else the page's own folder).
///
/// # Errors
/// Natively the file system's error, or `NotFound` naming the folders
/// looked in; in a page, `NotFound` for a path the game did not list.
/// A file larger than [`MAX_ASSET_BYTES`] is an error naming the limit.
pub fn read_asset(path: &std::path::Path) -> std::io::Result<Vec<u8>> {
    imp::read_asset(path)
}

/// The error for an asset of `bytes` bytes, over [`MAX_ASSET_BYTES`]
/// (natively; a page's fetch says so in its own words).
#[cfg_attr(target_arch = "wasm32", allow(dead_code))]
fn asset_too_large(bytes: u64) -> std::io::Error {
    std::io::Error::other(format!(
        "{bytes} bytes is larger than the limit of {MAX_ASSET_BYTES} bytes for an asset \
         (tickwork::platform::MAX_ASSET_BYTES): split the file"
    ))
}

/// A status line for the user beside the picture: in a page, the
/// `tickwork-status` element (the adapter, the backend); natively nothing
/// (a terminal has the printed lines).
pub fn show_status(line: &str) {
    imp::show_status(line);
}

/// Ends the program with `code` after an error it has already printed:
/// natively the process exits; a page's script stops (a JavaScript
/// exception that no Rust code catches), leaving the message shown.
pub fn exit(code: i32) -> ! {
    imp::exit(code)
}

/// Prints a line through [`say`], formatted as `println!` formats.
#[macro_export]
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::platform::say(&format!($($arg)*))
    };
}

/// Prints a line through [`complain`], formatted as `eprintln!` formats.
#[macro_export]
macro_rules! complain {
    ($($arg:tt)*) => {
        $crate::platform::complain(&format!($($arg)*))
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_url_query_is_a_command_line() {
        let upper = |s: &str| s.to_uppercase();
        assert_eq!(
            query_args("lander", "?hz=120&headless&&replay=../r.ron", upper),
            ["lander", "--HZ", "120", "--HEADLESS", "--REPLAY", "../R.RON"]
        );
        assert_eq!(query_args("orbits", "", upper), ["orbits"]);
        // A value may hold '=' (only the first splits).
        assert_eq!(query_args("p", "a=b=c", str::to_owned), ["p", "--a", "b=c"]);
    }

    #[test]
    fn an_asset_is_found_from_any_folder_of_the_workspace_and_a_missing_one_says_where_it_was_looked_for() {
        use std::path::Path;
        // The tests run in engine/: the workspace's assets are one folder up
        // (TICKWORK_ASSETS unset, whatever this process's environment says).
        let here = std::env::current_dir().expect("a current folder");
        let workspace = here.join("..");
        let read = |path: &str, root: Option<&Path>| native::read_asset_in(Path::new(path), root, &here);
        let ball = read("assets/sprites/ball.png", None).expect("found above");
        assert_eq!(
            ball,
            std::fs::read(workspace.join("assets/sprites/ball.png")).expect("the file")
        );
        let error = read("assets/no/such.png", None).expect_err("missing");
        assert_eq!(error.kind(), std::io::ErrorKind::NotFound);
        assert!(
            error
                .to_string()
                .contains(&format!("not found in {} or any folder above it", here.display())),
            "{error}"
        );
        // TICKWORK_ASSETS: only its folder is looked in.
        let assets = workspace.join("assets");
        assert_eq!(read("sprites/ball.png", Some(&assets)).expect("in the root"), ball);
        let error = read("assets/sprites/ball.png", Some(&assets)).expect_err("not above it");
        assert!(error.to_string().contains("which TICKWORK_ASSETS names"), "{error}");
        // Past the limit: an error naming it (a sparse file, no disk used).
        let big = std::env::temp_dir().join(format!("tickwork-big-asset-{}", std::process::id()));
        std::fs::File::create(&big)
            .and_then(|f| f.set_len(MAX_ASSET_BYTES + 1))
            .expect("a sparse file");
        let error = read_asset(&big).expect_err("too large");
        let _ = std::fs::remove_file(&big);
        assert!(error.to_string().contains("MAX_ASSET_BYTES"), "{error}");
    }

    #[test]
    fn native_services() {
        const { assert!(!IS_WEB) };
        assert_eq!(args(), std::env::args_os().collect::<Vec<_>>());
        assert_eq!(env_var("PATH"), std::env::var_os("PATH"));
        assert!(parallel_threads() >= 1);
        assert_eq!(ready_now(async { 7 }), Some(7));
        let start = Instant::now();
        assert!(start.elapsed().as_secs_f64() >= 0.0);
    }
}
