//! The platform services of the browser build (see the module above), and
//! what only a page has: fetching a file by URL, offering one as a
//! download, and a message on the page.

use std::ffi::OsString;
use std::future::Future;
use std::pin::pin;
use std::task::{Context, Poll, Waker};

use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_futures::JsFuture;

pub(super) fn say(line: &str) {
    web_sys::console::log_1(&JsValue::from_str(line));
}

pub(super) fn complain(line: &str) {
    web_sys::console::error_1(&JsValue::from_str(line));
    show_message(line);
}

/// The page's URL query as command-line arguments after the page's name:
/// `?integrator=rk4&headless` is `[page, --integrator, rk4, --headless]`.
/// Names and values are percent-decoded (`+` is a space).
pub(super) fn args() -> Vec<OsString> {
    let location = web_sys::window().map(|w| w.location());
    let name = location.as_ref().and_then(|l| l.pathname().ok()).map_or_else(
        || "page".to_owned(),
        |p| p.trim_end_matches('/').rsplit('/').next().unwrap_or("page").to_owned(),
    );
    let query = location.and_then(|l| l.search().ok()).unwrap_or_default();
    super::query_args(&name, &query, decode)
        .into_iter()
        .map(OsString::from)
        .collect()
}

/// Percent-decoding of a URL query component (`+` is a space); a broken
/// escape is kept as written, so the parser quotes it back.
fn decode(text: &str) -> String {
    js_sys::decode_uri_component(&text.replace('+', " "))
        .ok()
        .and_then(|s| s.as_string())
        .unwrap_or_else(|| text.to_owned())
}

pub(super) fn env_var(_name: &str) -> Option<OsString> {
    None
}

pub(super) fn parallel_threads() -> usize {
    1
}

pub(super) fn ready_now<F: Future>(future: F) -> Option<F::Output> {
    let mut future = pin!(future);
    match future.as_mut().poll(&mut Context::from_waker(Waker::noop())) {
        Poll::Ready(output) => Some(output),
        Poll::Pending => None,
    }
}

pub(super) fn received_now<T>(receiver: &std::sync::mpsc::Receiver<T>) -> Option<T> {
    receiver.try_recv().ok()
}

#[cfg(feature = "window")]
pub(super) fn window_attributes(
    attributes: winit::window::WindowAttributes,
    size: Option<(u32, u32)>,
) -> Result<winit::window::WindowAttributes, String> {
    use winit::platform::web::WindowAttributesExtWebSys;
    let document = web_sys::window()
        .and_then(|w| w.document())
        .ok_or("no document (not a page)")?;
    let canvas: web_sys::HtmlCanvasElement = document
        .create_element("canvas")
        .map_err(|e| js_text(&e))?
        .dyn_into()
        .map_err(|_| "cannot make a canvas")?;
    canvas.set_id("tickwork-canvas");
    let container: web_sys::Node = match document.get_element_by_id("tickwork") {
        Some(element) => element.into(),
        None => document.body().ok_or("the page has no body")?.into(),
    };
    container.append_child(&canvas).map_err(|e| js_text(&e))?;
    // Touches are the game's (the mouse, see app/window/touch.rs), not the
    // page's: no scrolling or zooming on a drag or a double tap.
    canvas
        .style()
        .set_property("touch-action", "none")
        .map_err(|e| js_text(&e))?;
    let attributes = attributes
        .with_canvas(Some(canvas.clone()))
        .with_focusable(true)
        .with_prevent_default(true);
    Ok(match size {
        Some((width, height)) => attributes.with_inner_size(winit::dpi::PhysicalSize::new(width, height)),
        None => {
            let style = canvas.style();
            for (name, value) in [("width", "100%"), ("height", "100%"), ("display", "block")] {
                style.set_property(name, value).map_err(|e| js_text(&e))?;
            }
            attributes
        }
    })
}

pub(super) fn spawn_local(future: impl Future<Output = ()> + 'static) {
    wasm_bindgen_futures::spawn_local(future);
}

pub(super) fn spawn_background(future: impl Future<Output = ()> + 'static) {
    wasm_bindgen_futures::spawn_local(future);
}

pub(super) async fn pause(length: std::time::Duration) {
    let milliseconds = i32::try_from(length.as_millis()).unwrap_or(i32::MAX);
    let timer = js_sys::Promise::new(&mut |resolve, _| {
        if let Some(window) = web_sys::window() {
            let _ = window.set_timeout_with_callback_and_timeout_and_arguments_0(&resolve, milliseconds);
        }
    });
    // A page without a window never resolves the timer: nothing runs there.
    let _ = JsFuture::from(timer).await;
}

/// Fetches `url` (relative to the page): the response, checked to be a
/// success whose announced length (if any) is at most `limit` bytes, so
/// that a body past it is refused before it is read.
async fn fetch(url: &str, limit: u64, limit_name: &str) -> Result<web_sys::Response, String> {
    let window = web_sys::window().ok_or("no window (not a page)")?;
    let response = JsFuture::from(window.fetch_with_str(url))
        .await
        .map_err(|e| format!("cannot fetch {url}: {}", js_text(&e)))?;
    let response: web_sys::Response = response
        .dyn_into()
        .map_err(|_| format!("cannot fetch {url}: not an HTTP response"))?;
    if !response.ok() {
        return Err(format!(
            "cannot fetch {url}: HTTP {} {}",
            response.status(),
            response.status_text()
        ));
    }
    let announced = response
        .headers()
        .get("content-length")
        .ok()
        .flatten()
        .and_then(|length| length.trim().parse::<u64>().ok());
    if let Some(bytes) = announced.filter(|&bytes| bytes > limit) {
        return Err(too_large(url, bytes, limit, limit_name));
    }
    Ok(response)
}

/// The error for a body of `bytes` bytes from `url`, over `limit`.
fn too_large(url: &str, bytes: u64, limit: u64, limit_name: &str) -> String {
    format!("{url} is larger than the limit of {limit} bytes ({limit_name}): {bytes} bytes")
}

/// Fetches `url` (relative to the page) as text of at most `limit` bytes.
///
/// # Errors
/// What went wrong, naming the URL: the request failed, the server
/// answered with an error status, the body is larger than `limit`
/// (`limit_name` names the constant) or is not text.
pub async fn fetch_text(url: &str, limit: u64, limit_name: &str) -> Result<String, String> {
    let response = fetch(url, limit, limit_name).await?;
    let text = JsFuture::from(
        response
            .text()
            .map_err(|e| format!("cannot read {url}: {}", js_text(&e)))?,
    )
    .await
    .map_err(|e| format!("cannot read {url}: {}", js_text(&e)))?;
    let text = text.as_string().ok_or_else(|| format!("{url} is not text"))?;
    if text.len() as u64 > limit {
        return Err(too_large(url, text.len() as u64, limit, limit_name));
    }
    Ok(text)
}

/// Fetches `url` (relative to the page) as bytes, at most `limit` of them.
///
/// # Errors
/// As [`fetch_text`], but for bytes.
pub async fn fetch_bytes(url: &str, limit: u64, limit_name: &str) -> Result<Vec<u8>, String> {
    let response = fetch(url, limit, limit_name).await?;
    let buffer = JsFuture::from(
        response
            .array_buffer()
            .map_err(|e| format!("cannot read {url}: {}", js_text(&e)))?,
    )
    .await
    .map_err(|e| format!("cannot read {url}: {}", js_text(&e)))?;
    let bytes = js_sys::Uint8Array::new(&buffer);
    if u64::from(bytes.length()) > limit {
        return Err(too_large(url, u64::from(bytes.length()), limit, limit_name));
    }
    Ok(bytes.to_vec())
}

thread_local! {
    /// The assets a page fetched before its game's setup, by the path the
    /// game named them with (a page has one thread).
    static ASSETS: std::cell::RefCell<std::collections::HashMap<std::path::PathBuf, std::rc::Rc<[u8]>>> =
        std::cell::RefCell::default();
}

/// The page's asset root: the `data-assets` attribute of its `tickwork`
/// element (scripts/web's pages say `../`, the site's root, where the
/// `assets/` folder is), else the page's folder.
fn asset_root() -> String {
    web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.get_element_by_id("tickwork"))
        .and_then(|e| e.get_attribute("data-assets"))
        .unwrap_or_default()
}

/// Fetches each of `paths` from the page's asset root, for
/// [`read_asset`](super::read_asset) to give the game's setup; paths
/// fetched before are kept.
///
/// # Errors
/// The first asset that cannot be fetched, naming its URL.
pub async fn fetch_assets(paths: &[&str]) -> Result<(), String> {
    let root = asset_root();
    for path in paths {
        if ASSETS.with(|assets| assets.borrow().contains_key(std::path::Path::new(path))) {
            continue;
        }
        let url = format!("{root}{path}");
        let bytes = fetch_bytes(&url, super::MAX_ASSET_BYTES, "tickwork::platform::MAX_ASSET_BYTES").await?;
        ASSETS.with(|assets| assets.borrow_mut().insert(path.into(), bytes.into()));
    }
    Ok(())
}

pub(super) fn read_asset(path: &std::path::Path) -> std::io::Result<Vec<u8>> {
    ASSETS
        .with(|assets| assets.borrow().get(path).map(|bytes| bytes.to_vec()))
        .ok_or_else(|| {
            std::io::Error::new(
                std::io::ErrorKind::NotFound,
                format!(
                    "a page cannot read files, and the game did not list {} in Game::assets (what the page \
                     fetches before setup)",
                    path.display()
                ),
            )
        })
}

pub(super) fn write_text(path: &std::path::Path, text: &str) -> std::io::Result<()> {
    let name = path
        .file_name()
        .map_or_else(|| "tickwork.txt".into(), |n| n.to_string_lossy());
    download(&name, text).map_err(std::io::Error::other)
}

/// Offers `text` to the user as a download named `name` (what `--record`
/// does in a page: a browser cannot write files).
///
/// # Errors
/// The browser's message if the download cannot be made.
pub fn download(name: &str, text: &str) -> Result<(), String> {
    let document = web_sys::window()
        .and_then(|w| w.document())
        .ok_or("no document (not a page)")?;
    let parts = js_sys::Array::of1(&JsValue::from_str(text));
    let options = web_sys::BlobPropertyBag::new();
    options.set_type("text/plain");
    let blob = web_sys::Blob::new_with_str_sequence_and_options(&parts, &options).map_err(|e| js_text(&e))?;
    let url = web_sys::Url::create_object_url_with_blob(&blob).map_err(|e| js_text(&e))?;
    let link: web_sys::HtmlAnchorElement = document
        .create_element("a")
        .map_err(|e| js_text(&e))?
        .dyn_into()
        .map_err(|_| "cannot make a link")?;
    link.set_href(&url);
    link.set_download(name);
    link.click();
    let _ = web_sys::Url::revoke_object_url(&url);
    Ok(())
}

/// Shows `text` on the page, in the element with id `tickwork-message`
/// (the page template has one over the canvas), or a new one.
pub fn show_message(text: &str) {
    let Some(document) = web_sys::window().and_then(|w| w.document()) else {
        return;
    };
    let element = document.get_element_by_id("tickwork-message").or_else(|| {
        let element = document.create_element("pre").ok()?;
        element.set_id("tickwork-message");
        document.body()?.append_child(&element).ok()?;
        Some(element)
    });
    if let Some(element) = element {
        let shown = element.text_content().unwrap_or_default();
        element.set_text_content(Some(&if shown.is_empty() {
            text.to_owned()
        } else {
            format!("{shown}\n{text}")
        }));
        if let Ok(element) = element.dyn_into::<web_sys::HtmlElement>() {
            let _ = element.style().set_property("display", "block");
        }
    }
}

pub(super) fn show_status(line: &str) {
    if let Some(element) = web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.get_element_by_id("tickwork-status"))
    {
        element.set_text_content(Some(line));
    }
}

pub(super) fn exit(code: i32) -> ! {
    wasm_bindgen::throw_str(&format!(
        "tickwork: stopped (exit code {code}) after the error shown above"
    ))
}

/// A JavaScript error or value as text.
pub(crate) fn js_text(value: &JsValue) -> String {
    value
        .dyn_ref::<js_sys::Error>()
        .map(|e| String::from(e.message()))
        .or_else(|| value.as_string())
        .unwrap_or_else(|| format!("{value:?}"))
}

/// Sends panics to the console (with their message and place) instead of
/// a bare "unreachable" trap.
pub fn install_panic_hook() {
    console_error_panic_hook::set_once();
}
