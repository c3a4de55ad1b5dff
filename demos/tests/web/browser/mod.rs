//! What the browser tests share: a static file server for the web build, and
//! headless Chromium driven over the Chrome DevTools Protocol (CDP).
//!
//! ```ignore
//! mod browser;
//! use browser::{Browser, Server};
//!
//! let server = Server::start(&site_dir).expect("the file server starts");
//! let browser = Browser::launch().unwrap_or_else(|e| panic!("{e}"));
//! let mut page = browser
//!     .open(&server.url("index.html?backend=webgl2"))
//!     .unwrap_or_else(|e| panic!("{e}"));
//! let line = page
//!     .wait_console(|line| line.starts_with("ready"), Duration::from_secs(120))
//!     .unwrap_or_else(|e| panic!("{e}"));
//! let shot = page.screenshot("canvas").unwrap_or_else(|e| panic!("{e}"));
//! assert_eq!(shot.pixel(0, 0), [51, 102, 153, 255]);
//! ```
//!
//! # The browser
//! Debian's `chromium` package (`/usr/bin/chromium`, or the program named by
//! the `CHROMIUM` environment variable), headless, on the CPU: SwiftShader
//! gives it both a WebGPU adapter and a WebGL2 context (see
//! `shared/notes/web.md`). The flags are the same for both backends; a page
//! chooses its backend itself (through its URL), so there is no backend
//! argument here. A missing browser is an error that says to install the
//! package: the browser tests fail loudly without it, they never skip.
//!
//! # Why a client of our own
//! The protocol is JSON over a websocket: a command is `{id, method, params}`,
//! its answer carries the same `id`, and everything else is an event. The few
//! commands used here (`Target.createTarget`, `Page.navigate`,
//! `Runtime.evaluate`, `Page.captureScreenshot`) and the console events fit in
//! this one file on top of `tungstenite` 0.30 (a synchronous websocket: 11
//! small crates, about 10 s of build at `-j 1`) and `serde_json`, which demos
//! already has; `libc` (already built for the workspace) ends the browser's
//! process group. The maintained crate, `headless_chrome` 1.0.22, was weighed
//! and left:
//! - its build script generates Rust types for the whole protocol (about 600
//!   types, 640 commands and 216 events, from 1.5 MB of JSON) and runs
//!   rustfmt over them, and it needs `ureq`, `rustls` and `ring` (C code) to
//!   do so even offline: about 120 crates in all, with the URL, regex,
//!   `derive_builder` and ICU crates; minutes more of build on CI's 2 cores;
//! - without its default `offline` feature that script downloads the
//!   protocol from GitHub, which these machines cannot reach;
//! - it waits for the browser's address, and for elements, by polling with
//!   sleeps, and by default drops a browser left idle for 30 s (a page
//!   drawing in software can be quiet for longer).
//!
//! # Waiting
//! Nothing here sleeps. Every wait is a blocking read bounded by a deadline:
//! the `DevTools listening on ws://…` line on Chromium's stderr at launch, the
//! answer to a command, or a console message that a test asks for. A deadline
//! that passes is an error that says what was seen so far.
// Each test binary that declares `mod browser;` uses its own part of this.
#![allow(dead_code)]

use std::cell::RefCell;
use std::collections::VecDeque;
use std::fmt;
use std::fs;
use std::io::{self, BufRead, BufReader, Cursor, Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, mpsc};
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use serde_json::{Value, json};
use tungstenite::{Message, WebSocket};

/// The browser used when `CHROMIUM` is not set: Debian's `chromium` package.
pub const DEFAULT_CHROMIUM: &str = "/usr/bin/chromium";

/// How long Chromium may take to print its DevTools address. Generous: a
/// first start on a busy two-core machine takes seconds.
pub const LAUNCH_TIMEOUT: Duration = Duration::from_secs(60);

/// How long one protocol command may take to be answered (a screenshot of a
/// software-rendered page on a busy machine is the slowest).
pub const COMMAND_TIMEOUT: Duration = Duration::from_secs(60);

/// The size of the browser's window, in CSS pixels (device scale factor 1).
pub const WINDOW_SIZE: (u32, u32) = (1024, 768);

/// The flags Chromium is started with, besides `--user-data-dir`.
pub const CHROMIUM_FLAGS: &[&str] = &[
    "--headless=new",
    // Root in a container has no user namespace for the sandbox.
    "--no-sandbox",
    // WebGPU and WebGL2 on the CPU (SwiftShader).
    "--enable-unsafe-webgpu",
    "--use-webgpu-adapter=swiftshader",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    // Chromium's own compositing on SwiftShader's Vulkan: without it a
    // WebGPU canvas shows (and screenshots) blank white, whatever was drawn.
    "--use-vulkan=swiftshader",
    "--enable-features=Vulkan",
    // The address is printed on stderr; 0 lets the OS choose the port.
    "--remote-debugging-port=0",
    // Screenshots are in CSS pixels.
    "--force-device-scale-factor=1",
    "--window-size=1024,768",
    // Nothing that reaches out to the network or asks questions.
    "--no-first-run",
    "--no-default-browser-check",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--mute-audio",
    // A tab that is not in front keeps its timers and animation frames.
    "--disable-background-timer-throttling",
    "--disable-renderer-backgrounding",
    "--disable-backgrounding-occluded-windows",
];

// ---------------------------------------------------------------------------
// The file server
// ---------------------------------------------------------------------------

/// The most bytes of a request's line and headers that the server reads.
const MAX_REQUEST_HEAD: usize = 16 * 1024;

/// The most bytes of an oversized request read (and dropped) before its
/// connection is closed.
const MAX_DRAINED: u64 = 1024 * 1024;

/// The most connections served at once; more are closed unanswered.
const MAX_CONNECTIONS: usize = 64;

/// How long a connection may wait for its request, or for its response to
/// be taken, before the server drops it.
const CONNECTION_TIMEOUT: Duration = Duration::from_secs(30);

/// A static HTTP/1.1 file server on 127.0.0.1, on a port the OS chose, that
/// serves the files under one folder on its own thread. It answers `GET` and
/// `HEAD` with the file and its content type, 404 for a missing file, 403 for
/// a path with `..` (or one that leads out of the folder through a link),
/// and closes every connection after one response. Dropping it stops it.
pub struct Server {
    /// Where it listens.
    addr: SocketAddr,
    /// Set when it is dropped; the accept loop checks it after each accept.
    stop: Arc<AtomicBool>,
    /// The accept loop.
    thread: Option<JoinHandle<()>>,
}

impl Server {
    /// Starts serving the files under `root` (which must be a folder).
    pub fn start(root: &Path) -> io::Result<Server> {
        let root = root
            .canonicalize()
            .map_err(|e| io::Error::new(e.kind(), format!("serving {}: {e}", root.display())))?;
        if !root.is_dir() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("serving {}: not a folder", root.display()),
            ));
        }
        let listener = TcpListener::bind(("127.0.0.1", 0))?;
        let addr = listener.local_addr()?;
        let stop = Arc::new(AtomicBool::new(false));
        let thread = {
            let stop = Arc::clone(&stop);
            thread::Builder::new()
                .name("test-file-server".into())
                .spawn(move || accept_loop(&listener, &root, &stop))?
        };
        Ok(Server {
            addr,
            stop,
            thread: Some(thread),
        })
    }

    /// The URL of `path` (relative to the root, query string allowed) on
    /// this server: `server.url("index.html?backend=webgpu")`.
    pub fn url(&self, path: &str) -> String {
        format!("http://{}/{}", self.addr, path.trim_start_matches('/'))
    }

    /// The address the server listens on.
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        // Wakes the accept loop, which sees the flag and returns. If the
        // connection fails the loop is already gone.
        let _ = TcpStream::connect(self.addr);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// Accepts connections until `stop` is set, each served on its own thread.
fn accept_loop(listener: &TcpListener, root: &Path, stop: &AtomicBool) {
    let active = Arc::new(AtomicUsize::new(0));
    for stream in listener.incoming() {
        if stop.load(Ordering::SeqCst) {
            return;
        }
        let Ok(stream) = stream else { continue };
        if active.fetch_add(1, Ordering::SeqCst) >= MAX_CONNECTIONS {
            active.fetch_sub(1, Ordering::SeqCst);
            continue;
        }
        let root = root.to_path_buf();
        let active_in_thread = Arc::clone(&active);
        let spawned = thread::Builder::new()
            .name("test-file-server-connection".into())
            .spawn(move || {
                // A connection that fails midway has nobody to tell.
                let _ = serve_connection(stream, &root);
                active_in_thread.fetch_sub(1, Ordering::SeqCst);
            });
        if spawned.is_err() {
            active.fetch_sub(1, Ordering::SeqCst);
        }
    }
}

/// Reads one request from `stream` and answers it.
fn serve_connection(mut stream: TcpStream, root: &Path) -> io::Result<()> {
    stream.set_read_timeout(Some(CONNECTION_TIMEOUT))?;
    stream.set_write_timeout(Some(CONNECTION_TIMEOUT))?;
    let Some(head) = read_request_head(&mut stream)? else {
        respond_status(&mut stream, 431, "Request Header Fields Too Large")?;
        // Closing with the rest of the request unread would reset the
        // connection and lose the answer: read it first, within bounds.
        stream.shutdown(std::net::Shutdown::Write)?;
        let _ = io::copy(&mut (&stream).take(MAX_DRAINED), &mut io::sink());
        return Ok(());
    };
    let Some(request_line) = head.lines().next() else {
        return respond_status(&mut stream, 400, "Bad Request");
    };
    let mut parts = request_line.split_whitespace();
    let (Some(method), Some(target), Some(version)) = (parts.next(), parts.next(), parts.next()) else {
        return respond_status(&mut stream, 400, "Bad Request");
    };
    if !version.starts_with("HTTP/1.") {
        return respond_status(&mut stream, 505, "HTTP Version Not Supported");
    }
    let head_only = match method {
        "GET" => false,
        "HEAD" => true,
        _ => return respond_status(&mut stream, 405, "Method Not Allowed"),
    };
    let path = target.split(['?', '#']).next().unwrap_or_default();
    let Some(path) = percent_decode(path) else {
        return respond_status(&mut stream, 400, "Bad Request");
    };
    if !path.starts_with('/') {
        return respond_status(&mut stream, 400, "Bad Request");
    }
    if path.contains("..") || path.contains('\\') || path.contains('\0') {
        return respond_status(&mut stream, 403, "Forbidden");
    }
    let mut file = root.join(path.trim_start_matches('/'));
    if path.ends_with('/') {
        file.push("index.html");
    }
    // Links inside the root may not lead out of it.
    let file = match file.canonicalize() {
        Ok(file) if file.starts_with(root) => file,
        Ok(_) => return respond_status(&mut stream, 403, "Forbidden"),
        Err(_) => return respond_status(&mut stream, 404, "Not Found"),
    };
    if !file.is_file() {
        return respond_status(&mut stream, 404, "Not Found");
    }
    let body = fs::read(&file)?;
    let header = format!(
        "HTTP/1.1 200 OK\r\nContent-Type: {}\r\nContent-Length: {}\r\n\
         Cache-Control: no-store\r\nConnection: close\r\n\r\n",
        content_type(&file),
        body.len()
    );
    stream.write_all(header.as_bytes())?;
    if !head_only {
        stream.write_all(&body)?;
    }
    stream.flush()
}

/// Reads up to the blank line that ends a request's headers. `None` when the
/// head is longer than [`MAX_REQUEST_HEAD`]; an error when the peer closes
/// or stalls first.
fn read_request_head(stream: &mut TcpStream) -> io::Result<Option<String>> {
    let mut head = Vec::with_capacity(1024);
    let mut chunk = [0u8; 1024];
    loop {
        let n = stream.read(&mut chunk)?;
        if n == 0 {
            return Err(io::Error::new(
                io::ErrorKind::UnexpectedEof,
                "connection closed before the request's end",
            ));
        }
        head.extend_from_slice(&chunk[..n]);
        if let Some(end) = head.windows(4).position(|w| w == b"\r\n\r\n") {
            head.truncate(end);
            return Ok(Some(String::from_utf8_lossy(&head).into_owned()));
        }
        if head.len() > MAX_REQUEST_HEAD {
            return Ok(None);
        }
    }
}

/// Answers with a status and a one-line text body.
fn respond_status(stream: &mut TcpStream, code: u16, reason: &str) -> io::Result<()> {
    let body = format!("{code} {reason}\n");
    let response = format!(
        "HTTP/1.1 {code} {reason}\r\nContent-Type: text/plain; charset=utf-8\r\n\
         Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    );
    stream.write_all(response.as_bytes())?;
    stream.flush()
}

/// Decodes `%XX` escapes; `None` for a broken escape or bytes that are not
/// UTF-8.
fn percent_decode(path: &str) -> Option<String> {
    let bytes = path.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// The `Content-Type` of a file, by its extension.
pub fn content_type(path: &Path) -> &'static str {
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("html" | "htm") => "text/html; charset=utf-8",
        Some("js" | "mjs") => "text/javascript; charset=utf-8",
        Some("wasm") => "application/wasm",
        Some("png") => "image/png",
        Some("css") => "text/css; charset=utf-8",
        Some("json") => "application/json",
        // RON has no registered type; the page fetches it as text.
        Some("ron" | "txt") => "text/plain; charset=utf-8",
        _ => "application/octet-stream",
    }
}

// ---------------------------------------------------------------------------
// The protocol connection
// ---------------------------------------------------------------------------

/// One websocket to Chromium's DevTools endpoint, for the browser itself or
/// for one page.
struct Connection {
    /// The socket; its stream's read timeout is set before each read.
    ws: WebSocket<TcpStream>,
    /// The id of the next command.
    next_id: u64,
    /// The endpoint, for messages.
    url: String,
}

impl Connection {
    /// Connects to a `ws://host:port/path` endpoint.
    fn open(url: &str) -> Result<Connection, String> {
        let authority = url
            .strip_prefix("ws://")
            .and_then(|rest| rest.split('/').next())
            .ok_or_else(|| format!("not a ws:// address: {url}"))?;
        let stream =
            TcpStream::connect(authority).map_err(|e| format!("connecting to the DevTools endpoint {url}: {e}"))?;
        stream
            .set_read_timeout(Some(COMMAND_TIMEOUT))
            .map_err(|e| format!("setting a read timeout on {url}: {e}"))?;
        let (ws, _response) =
            tungstenite::client(url, stream).map_err(|e| format!("websocket handshake with {url}: {e}"))?;
        Ok(Connection {
            ws,
            next_id: 1,
            url: url.to_owned(),
        })
    }

    /// Sends a command and returns its id.
    fn send(&mut self, method: &str, params: Value) -> Result<u64, String> {
        let id = self.next_id;
        self.next_id += 1;
        let text = json!({"id": id, "method": method, "params": params}).to_string();
        self.ws
            .send(Message::Text(text.into()))
            .map_err(|e| format!("sending {method} to {}: {e}", self.url))?;
        Ok(id)
    }

    /// The next message, or `None` once `deadline` has passed without one.
    fn next_message(&mut self, deadline: Instant) -> Result<Option<Value>, String> {
        loop {
            let Some(left) = deadline.checked_duration_since(Instant::now()) else {
                return Ok(None);
            };
            if left.is_zero() {
                return Ok(None);
            }
            self.ws
                .get_mut()
                .set_read_timeout(Some(left))
                .map_err(|e| format!("setting a read timeout on {}: {e}", self.url))?;
            match self.ws.read() {
                Ok(Message::Text(text)) => {
                    return serde_json::from_str(text.as_str())
                        .map(Some)
                        .map_err(|e| format!("a message from {} is not JSON: {e}", self.url));
                }
                Ok(Message::Binary(bytes)) => {
                    return serde_json::from_slice(&bytes)
                        .map(Some)
                        .map_err(|e| format!("a message from {} is not JSON: {e}", self.url));
                }
                Ok(Message::Close(frame)) => {
                    return Err(format!("{} closed the connection ({frame:?})", self.url));
                }
                // Pings are answered by tungstenite itself.
                Ok(Message::Ping(_) | Message::Pong(_) | Message::Frame(_)) => {}
                Err(tungstenite::Error::Io(e))
                    if matches!(e.kind(), io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut) =>
                {
                    // The read timed out: the loop checks the deadline.
                }
                Err(e) => return Err(format!("reading from {}: {e}", self.url)),
            }
        }
    }

    /// Sends a command and waits for its answer, handing each event that
    /// arrives meanwhile to `on_event`, whose error ends the wait (a crashed
    /// page answers nothing).
    fn call(
        &mut self,
        method: &str,
        params: Value,
        timeout: Duration,
        on_event: &mut dyn FnMut(&Value) -> Result<(), String>,
    ) -> Result<Value, String> {
        let deadline = Instant::now() + timeout;
        let id = self.send(method, params)?;
        loop {
            let Some(message) = self.next_message(deadline)? else {
                return Err(format!("{method}: no answer from {} within {timeout:?}", self.url));
            };
            if message.get("id").and_then(Value::as_u64) == Some(id) {
                if let Some(error) = message.get("error") {
                    return Err(format!("{method} failed: {error}"));
                }
                return Ok(message.get("result").cloned().unwrap_or(Value::Null));
            }
            if message.get("method").is_some() {
                on_event(&message).map_err(|e| format!("{method}: {e}"))?;
            }
        }
    }
}

// ---------------------------------------------------------------------------
// The browser
// ---------------------------------------------------------------------------

/// How many of Chromium's last stderr lines are kept for diagnostics.
const STDERR_TAIL: usize = 200;

/// A headless Chromium, with a fresh profile folder, that the tests drive
/// over the DevTools protocol. Dropping it kills the browser and its helper
/// processes and removes the profile.
pub struct Browser {
    /// The connection to the browser itself (targets, version).
    connection: RefCell<Connection>,
    /// `host:port` of the DevTools endpoint.
    endpoint: String,
    /// The browser's download events not yet waited on (they can arrive
    /// while a command waits for its answer).
    downloads: RefCell<VecDeque<Value>>,
    /// Chromium's last stderr lines, kept by a thread that drains the pipe.
    stderr_tail: Arc<Mutex<VecDeque<String>>>,
    /// The process and its profile folder (dropped after `connection`).
    process: Process,
}

/// The Chromium process and its profile folder: killed and removed on drop,
/// also when a launch fails halfway.
struct Process {
    /// The browser (Debian's `/usr/bin/chromium` wrapper execs the real one,
    /// so this is the browser process, leader of its own process group).
    child: Child,
    /// The `--user-data-dir`.
    profile: PathBuf,
    /// How the browser ended, once [`Process::end`] has reaped it.
    status: Option<ExitStatus>,
}

impl Process {
    /// Kills the browser's whole process group and reaps the browser;
    /// returns its exit status. The browser's helpers (GPU process,
    /// renderers, network service) outlive it by a moment and keep writing
    /// the profile, so they go at once too. Nothing is saved: the profile
    /// is removed afterwards.
    fn end(&mut self) -> Option<ExitStatus> {
        if self.status.is_none() {
            // The group is killed before its leader is reaped: until then
            // no other process can have been given its id.
            if let Ok(pid) = i32::try_from(self.child.id()) {
                // SAFETY: kill(2) takes no pointers; a negative pid names the
                // process group the browser leads (it was started in its own).
                unsafe {
                    libc::kill(-pid, libc::SIGKILL);
                }
            }
            let _ = self.child.kill();
            self.status = self.child.wait().ok();
        }
        self.status
    }
}

impl Drop for Process {
    fn drop(&mut self) {
        self.end();
        // A helper killed in the middle of a write may finish that write:
        // a second pass removes what it made.
        if fs::remove_dir_all(&self.profile).is_err() {
            let _ = fs::remove_dir_all(&self.profile);
        }
    }
}

impl Browser {
    /// Starts headless Chromium (`CHROMIUM`, or `/usr/bin/chromium`) with
    /// [`CHROMIUM_FLAGS`] and a fresh profile, and connects to it.
    pub fn launch() -> Result<Browser, String> {
        Self::launch_with(&[])
    }

    /// As [`Browser::launch`], with `extra` flags after [`CHROMIUM_FLAGS`]
    /// (`--disable-webgl`, to see a page whose GPU cannot start).
    pub fn launch_with(extra: &[&str]) -> Result<Browser, String> {
        let program = std::env::var_os("CHROMIUM")
            .map(PathBuf::from)
            .unwrap_or_else(|| PathBuf::from(DEFAULT_CHROMIUM));
        let missing = || {
            format!(
                "no browser at {}: the browser tests need Debian's `chromium` \
                 package (apt-get install chromium), or CHROMIUM set to a \
                 Chromium or Chrome program",
                program.display()
            )
        };
        if !program.is_file() {
            return Err(missing());
        }
        let profile = make_profile_dir()?;
        let spawned = Command::new(&program)
            .args(CHROMIUM_FLAGS)
            .args(extra)
            .arg(format!("--user-data-dir={}", profile.display()))
            .arg("about:blank")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            // Its own process group, so that dropping it ends its helpers too.
            .process_group(0)
            .spawn();
        let mut child = match spawned {
            Ok(child) => child,
            Err(e) => {
                let _ = fs::remove_dir_all(&profile);
                if e.kind() == io::ErrorKind::NotFound {
                    return Err(missing());
                }
                return Err(format!("starting {}: {e}", program.display()));
            }
        };
        let stderr = child.stderr.take();
        let mut process = Process {
            child,
            profile,
            status: None,
        };
        let Some(stderr) = stderr else {
            return Err("chromium's stderr was not piped".into());
        };

        // A thread drains stderr for the browser's whole life (it is chatty,
        // and a full pipe would block it), keeps its tail, and hands each
        // line to the launch until the launch has the address.
        let stderr_tail = Arc::new(Mutex::new(VecDeque::with_capacity(STDERR_TAIL)));
        let (lines_tx, lines_rx) = mpsc::channel::<String>();
        {
            let tail = Arc::clone(&stderr_tail);
            thread::Builder::new()
                .name("chromium-stderr".into())
                .spawn(move || drain_stderr(stderr, &tail, &lines_tx))
                .map_err(|e| format!("starting the thread that reads chromium's stderr: {e}"))?;
        }
        let deadline = Instant::now() + LAUNCH_TIMEOUT;
        let url = loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match lines_rx.recv_timeout(left) {
                Ok(line) => {
                    if let Some(at) = line.find("DevTools listening on ") {
                        break line[at + "DevTools listening on ".len()..].trim().to_owned();
                    }
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    return Err(format!(
                        "chromium printed no DevTools address within {LAUNCH_TIMEOUT:?}; \
                         its stderr:\n{}",
                        tail_text(&stderr_tail)
                    ));
                }
                Err(mpsc::RecvTimeoutError::Disconnected) => {
                    let status = process.end().map_or_else(|| "status unknown".into(), |s| s.to_string());
                    return Err(format!(
                        "chromium exited ({status}) before printing its DevTools \
                         address; its stderr:\n{}",
                        tail_text(&stderr_tail)
                    ));
                }
            }
        };
        // The thread keeps draining; the launch no longer listens.
        drop(lines_rx);
        let endpoint = url
            .strip_prefix("ws://")
            .and_then(|rest| rest.split('/').next())
            .ok_or_else(|| format!("chromium printed an odd DevTools address: {url}"))?
            .to_owned();
        let connection = Connection::open(&url)?;
        Ok(Browser {
            connection: RefCell::new(connection),
            endpoint,
            downloads: RefCell::new(VecDeque::new()),
            stderr_tail,
            process,
        })
    }

    /// The browser's product and protocol version, e.g. `Chrome/…`.
    pub fn version(&self) -> Result<String, String> {
        let result = self.call("Browser.getVersion", json!({}))?;
        Ok(format!(
            "{} (protocol {})",
            result["product"].as_str().unwrap_or("?"),
            result["protocolVersion"].as_str().unwrap_or("?")
        ))
    }

    /// Opens a new tab, starts listening to its console, and navigates it
    /// to `url`. Returns once the navigation is under way (not when the page
    /// has loaded): wait for what the page prints with
    /// [`Page::wait_console`].
    pub fn open(&self, url: &str) -> Result<Page<'_>, String> {
        self.open_with(url, None)
    }

    /// As [`Browser::open`], running `script` in the page before any of
    /// its own (`Page.addScriptToEvaluateOnNewDocument`): a test's stand-in
    /// for a device the machine lacks, or its ear on one.
    pub fn open_with(&self, url: &str, script: Option<&str>) -> Result<Page<'_>, String> {
        let target = self.call("Target.createTarget", json!({"url": "about:blank"}))?;
        let target_id = target["targetId"]
            .as_str()
            .ok_or_else(|| format!("Target.createTarget gave no targetId: {target}"))?
            .to_owned();
        let connection = Connection::open(&format!("ws://{}/devtools/page/{target_id}", self.endpoint));
        let connection = match connection {
            Ok(connection) => connection,
            Err(e) => {
                let _ = self.call("Target.closeTarget", json!({"targetId": target_id}));
                return Err(e);
            }
        };
        let mut page = Page {
            browser: self,
            target_id,
            connection,
            console: Console::default(),
            touch_enabled: false,
        };
        // Listening starts before the navigation, so no line is missed.
        for domain in ["Runtime", "Log", "Page", "Inspector"] {
            page.call(&format!("{domain}.enable"), json!({}))?;
        }
        if let Some(script) = script {
            page.call("Page.addScriptToEvaluateOnNewDocument", json!({"source": script}))?;
        }
        page.navigate(url)?;
        Ok(page)
    }

    /// Chromium's last stderr lines (at most 200), for diagnostics. Mostly
    /// harmless D-Bus errors on a machine without a session bus.
    pub fn stderr_tail(&self) -> String {
        tail_text(&self.stderr_tail)
    }

    /// Saves what pages offer as downloads into `folder` (under the name
    /// the page suggests), and reports them to [`Browser::wait_download`].
    pub fn allow_downloads(&self, folder: &Path) -> Result<(), String> {
        self.call(
            "Browser.setDownloadBehavior",
            json!({"behavior": "allow", "downloadPath": folder, "eventsEnabled": true}),
        )?;
        Ok(())
    }

    /// Waits for the next download to complete and returns the file name
    /// the page suggested (the file is in the folder given to
    /// [`Browser::allow_downloads`]). `timeout` bounds the wait for that
    /// signal; an error if the download is cancelled.
    pub fn wait_download(&self, timeout: Duration) -> Result<String, String> {
        let deadline = Instant::now() + timeout;
        let mut names = std::collections::HashMap::new();
        loop {
            let event = match self.downloads.borrow_mut().pop_front() {
                Some(event) => event,
                None => {
                    let mut connection = self
                        .connection
                        .try_borrow_mut()
                        .map_err(|_| "waiting for a download: the browser connection is busy".to_owned())?;
                    match connection.next_message(deadline)? {
                        Some(message) => message,
                        None => return Err(format!("no download completed within {timeout:?}")),
                    }
                }
            };
            let params = &event["params"];
            let guid = params["guid"].as_str().unwrap_or_default().to_owned();
            match event["method"].as_str() {
                Some("Browser.downloadWillBegin") => {
                    names.insert(
                        guid,
                        params["suggestedFilename"].as_str().unwrap_or_default().to_owned(),
                    );
                }
                Some("Browser.downloadProgress") => match params["state"].as_str() {
                    Some("completed") => {
                        return names
                            .remove(&guid)
                            .ok_or_else(|| format!("download {guid} completed without having begun"));
                    }
                    Some("canceled") => return Err(format!("download {guid} ({:?}) was cancelled", names.get(&guid))),
                    _ => {}
                },
                _ => {}
            }
        }
    }

    /// A command to the browser itself; download events that arrive
    /// meanwhile are kept for [`Browser::wait_download`].
    fn call(&self, method: &str, params: Value) -> Result<Value, String> {
        let mut connection = self
            .connection
            .try_borrow_mut()
            .map_err(|_| format!("{method}: the browser connection is busy"))?;
        let downloads = &self.downloads;
        connection.call(method, params, COMMAND_TIMEOUT, &mut |event| {
            if event["method"]
                .as_str()
                .is_some_and(|m| m.starts_with("Browser.download"))
            {
                downloads.borrow_mut().push_back(event.clone());
            }
            Ok(())
        })
    }
}

/// Reads Chromium's stderr to its end, keeping the last lines in `tail` and
/// sending each line on `lines` while someone listens.
fn drain_stderr(stderr: impl Read, tail: &Mutex<VecDeque<String>>, lines: &mpsc::Sender<String>) {
    for line in BufReader::new(stderr).lines() {
        let Ok(line) = line else { return };
        if let Ok(mut tail) = tail.lock() {
            if tail.len() == STDERR_TAIL {
                tail.pop_front();
            }
            tail.push_back(line.clone());
        }
        // Fails once the launch has its address; the draining goes on.
        let _ = lines.send(line);
    }
}

/// The kept stderr lines, one per line.
fn tail_text(tail: &Mutex<VecDeque<String>>) -> String {
    match tail.lock() {
        Ok(tail) => tail.iter().cloned().collect::<Vec<_>>().join("\n"),
        Err(_) => "(unavailable)".into(),
    }
}

/// Makes a new, empty profile folder under the temporary folder.
fn make_profile_dir() -> Result<PathBuf, String> {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let base = std::env::temp_dir();
    for _ in 0..100 {
        let n = COUNTER.fetch_add(1, Ordering::SeqCst);
        let dir = base.join(format!("tickwork-chromium-{}-{nanos}-{n}", std::process::id()));
        match fs::create_dir(&dir) {
            Ok(()) => return Ok(dir),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(format!("making a profile folder {}: {e}", dir.display())),
        }
    }
    Err(format!("no free profile folder name under {}", base.display()))
}

// ---------------------------------------------------------------------------
// A page
// ---------------------------------------------------------------------------

/// One message from a page: a `console.*` call, an uncaught exception, or a
/// browser log entry (a failed load, a deprecation, a WebGL warning).
#[derive(Clone, Debug)]
pub struct ConsoleLine {
    /// `log`, `error`, `warning`, … for a console call; `exception` for an
    /// uncaught exception or rejection; `<source> <level>` (e.g.
    /// `network error`) for a log entry.
    pub kind: String,
    /// The message: a console call's arguments joined by spaces (strings as
    /// they are, other values as JSON or as the browser describes them); an
    /// exception's text and description (with its stack).
    pub text: String,
}

impl fmt::Display for ConsoleLine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{}] {}", self.kind, self.text)
    }
}

/// What a page has printed so far.
#[derive(Default)]
struct Console {
    /// Every message, in order.
    lines: Vec<ConsoleLine>,
    /// Set when the page's renderer crashed.
    crashed: bool,
}

impl Console {
    /// Records an event if it is a message; returns its index.
    fn record(&mut self, event: &Value) -> Option<usize> {
        let params = &event["params"];
        let line = match event["method"].as_str()? {
            "Runtime.consoleAPICalled" => ConsoleLine {
                kind: params["type"].as_str().unwrap_or("log").to_owned(),
                text: params["args"]
                    .as_array()
                    .map(|args| args.iter().map(describe).collect::<Vec<_>>().join(" "))
                    .unwrap_or_default(),
            },
            "Runtime.exceptionThrown" => {
                let details = &params["exceptionDetails"];
                let mut text = details["text"].as_str().unwrap_or("Uncaught").to_owned();
                if details["exception"].is_object() {
                    text.push(' ');
                    text.push_str(&describe(&details["exception"]));
                }
                if let Some(url) = details["url"].as_str().filter(|u| !u.is_empty()) {
                    text.push_str(&format!(
                        " ({url}:{}:{})",
                        details["lineNumber"].as_u64().unwrap_or(0) + 1,
                        details["columnNumber"].as_u64().unwrap_or(0) + 1
                    ));
                }
                ConsoleLine {
                    kind: "exception".into(),
                    text,
                }
            }
            "Log.entryAdded" => {
                let entry = &params["entry"];
                let mut text = entry["text"].as_str().unwrap_or_default().to_owned();
                if let Some(url) = entry["url"].as_str().filter(|u| !u.is_empty()) {
                    text.push_str(&format!(" ({url})"));
                }
                ConsoleLine {
                    kind: format!(
                        "{} {}",
                        entry["source"].as_str().unwrap_or("other"),
                        entry["level"].as_str().unwrap_or("info")
                    ),
                    text,
                }
            }
            "Inspector.targetCrashed" => {
                self.crashed = true;
                ConsoleLine {
                    kind: "crash".into(),
                    text: "the page's renderer crashed".into(),
                }
            }
            _ => return None,
        };
        self.lines.push(line);
        Some(self.lines.len() - 1)
    }

    /// The lines so far, one per line, for an error message: all of them,
    /// or for a chatty page the first 50 (where the cause usually is) and
    /// the last 150.
    fn listing(&self) -> String {
        const FIRST: usize = 50;
        const LAST: usize = 150;
        if self.lines.is_empty() {
            return "(the page printed nothing)".into();
        }
        let indented = |line: &ConsoleLine| format!("  {line}");
        let n = self.lines.len();
        if n <= FIRST + LAST {
            return self.lines.iter().map(indented).collect::<Vec<_>>().join("\n");
        }
        let mut out: Vec<String> = self.lines[..FIRST].iter().map(indented).collect();
        out.push(format!("  … {} more lines …", n - FIRST - LAST));
        out.extend(self.lines[n - LAST..].iter().map(indented));
        out.join("\n")
    }
}

/// A `Runtime.RemoteObject` as text: a string as it is, a value as JSON,
/// anything else as the browser describes it.
fn describe(object: &Value) -> String {
    if let Some(text) = object["value"].as_str() {
        return text.to_owned();
    }
    if let Some(value) = object.get("value") {
        return value.to_string();
    }
    for key in ["unserializableValue", "description"] {
        if let Some(text) = object[key].as_str() {
            return text.to_owned();
        }
    }
    object["type"].as_str().unwrap_or("?").to_owned()
}

/// A rectangle of the page, in CSS pixels from the document's top left.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clip {
    /// Left edge.
    pub x: f64,
    /// Top edge.
    pub y: f64,
    /// Width.
    pub width: f64,
    /// Height.
    pub height: f64,
}

/// A screenshot: 8-bit RGBA, rows top to bottom.
#[derive(Clone, Debug)]
pub struct Rgba {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height * 4` bytes.
    pub pixels: Vec<u8>,
}

impl Rgba {
    /// The pixel at (`x`, `y`), from the top left. Panics outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside a {}x{} image",
            self.width,
            self.height
        );
        let i = (y as usize * self.width as usize + x as usize) * 4;
        [
            self.pixels[i],
            self.pixels[i + 1],
            self.pixels[i + 2],
            self.pixels[i + 3],
        ]
    }
}

/// A tab of the browser, with its own protocol connection. Every console
/// message of its current document is kept. Dropping it closes the tab.
pub struct Page<'b> {
    /// The browser, which must outlive the page.
    browser: &'b Browser,
    /// The tab's target id.
    target_id: String,
    /// The tab's own connection.
    connection: Connection,
    /// What it has printed.
    console: Console,
    /// Whether touch input has been switched on ([`Page::touch`]).
    touch_enabled: bool,
}

impl Page<'_> {
    /// Navigates to `url`; returns once the navigation is under way. What
    /// the previous document printed is forgotten, so [`Page::wait_console`]
    /// sees only the new one's messages. An error if the browser could not
    /// navigate (a refused connection, a bad address); an HTTP error page is
    /// not one (a 404 shows in the console).
    pub fn navigate(&mut self, url: &str) -> Result<(), String> {
        self.console = Console::default();
        let result = self.call("Page.navigate", json!({"url": url}))?;
        match result["errorText"].as_str() {
            Some(error) if !error.is_empty() => Err(format!("navigating to {url}: {error}")),
            _ => Ok(()),
        }
    }

    /// Waits for the first message (among all the document has printed,
    /// before this call too) whose text satisfies `matches`, and returns
    /// that text. `timeout` bounds the wait for that signal; it is no sleep,
    /// so make it generous (a software-rendered page on CI's two cores is
    /// slow). The error, on a timeout, a crash or a lost connection, lists
    /// the messages seen (the first 50 and the last 150 of a chatty page).
    pub fn wait_console(&mut self, mut matches: impl FnMut(&str) -> bool, timeout: Duration) -> Result<String, String> {
        if let Some(line) = self.console.lines.iter().find(|l| matches(&l.text)) {
            return Ok(line.text.clone());
        }
        let deadline = Instant::now() + timeout;
        loop {
            if self.console.crashed {
                return Err(format!(
                    "the page crashed; what it printed:\n{}",
                    self.console.listing()
                ));
            }
            let message = match self.connection.next_message(deadline) {
                Ok(Some(message)) => message,
                Ok(None) => {
                    return Err(format!(
                        "no console message matched within {timeout:?}; what the page \
                         printed:\n{}",
                        self.console.listing()
                    ));
                }
                Err(e) => {
                    return Err(format!("{e}; what the page printed:\n{}", self.console.listing()));
                }
            };
            if let Some(i) = self.console.record(&message)
                && matches(&self.console.lines[i].text)
            {
                return Ok(self.console.lines[i].text.clone());
            }
        }
    }

    /// Everything the document has printed so far.
    pub fn console(&self) -> &[ConsoleLine] {
        &self.console.lines
    }

    /// Evaluates `js` in the page (awaiting it if it is a promise) and
    /// returns its value as JSON (`null` for `undefined`). An error if it
    /// throws or rejects.
    pub fn eval(&mut self, js: &str) -> Result<Value, String> {
        let result = self.call(
            "Runtime.evaluate",
            json!({"expression": js, "awaitPromise": true, "returnByValue": true}),
        )?;
        if let Some(details) = result.get("exceptionDetails") {
            let description = details["exception"]["description"]
                .as_str()
                .or_else(|| details["text"].as_str())
                .unwrap_or("an exception");
            return Err(format!("evaluating `{js}` threw: {description}"));
        }
        let object = &result["result"];
        if let Some(value) = object.get("value") {
            return Ok(value.clone());
        }
        Ok(object.get("unserializableValue").cloned().unwrap_or(Value::Null))
    }

    /// The bounding box of the first element that matches a CSS `selector`.
    pub fn element_clip(&mut self, selector: &str) -> Result<Clip, String> {
        let quoted = Value::from(selector).to_string();
        let js = format!(
            "(() => {{ const e = document.querySelector({quoted}); if (!e) return null; \
             const r = e.getBoundingClientRect(); \
             return [r.left + window.scrollX, r.top + window.scrollY, r.width, r.height]; }})()"
        );
        let value = self.eval(&js)?;
        let Some(numbers) = value.as_array() else {
            return Err(format!("no element matches `{selector}`"));
        };
        let number = |i: usize| {
            numbers
                .get(i)
                .and_then(Value::as_f64)
                .ok_or_else(|| format!("odd bounding box for `{selector}`: {value}"))
        };
        let clip = Clip {
            x: number(0)?,
            y: number(1)?,
            width: number(2)?,
            height: number(3)?,
        };
        if clip.width < 1.0 || clip.height < 1.0 {
            return Err(format!("`{selector}` has an empty bounding box: {clip:?}"));
        }
        Ok(clip)
    }

    /// A screenshot of the first element that matches a CSS `selector` (a
    /// canvas, say), at device scale factor 1: one pixel per CSS pixel. The
    /// element must be inside the window ([`WINDOW_SIZE`]).
    pub fn screenshot(&mut self, selector: &str) -> Result<Rgba, String> {
        let clip = self.element_clip(selector)?;
        self.screenshot_clip(clip)
    }

    /// A screenshot of a rectangle of the page, at scale 1. It shows what
    /// the compositor shows (a WebGL canvas's last presented frame).
    pub fn screenshot_clip(&mut self, clip: Clip) -> Result<Rgba, String> {
        let result = self.call(
            "Page.captureScreenshot",
            json!({
                "format": "png",
                "fromSurface": true,
                "clip": {
                    "x": clip.x, "y": clip.y,
                    "width": clip.width, "height": clip.height,
                    "scale": 1,
                },
            }),
        )?;
        let data = result["data"].as_str().ok_or("Page.captureScreenshot gave no data")?;
        let png = base64_decode(data).ok_or("Page.captureScreenshot gave bad base64")?;
        decode_png(&png)
    }

    /// Makes the page's viewport `width` x `height` CSS pixels, as a
    /// resized window would, at `scale` device pixels a CSS pixel (0: the
    /// screen's own). An emulated scale changes `devicePixelRatio` but not
    /// the sizes a ResizeObserver reports: for a high-density screen start
    /// the browser with `--force-device-scale-factor`.
    pub fn set_viewport(&mut self, width: u32, height: u32, scale: f64) -> Result<(), String> {
        self.call(
            "Emulation.setDeviceMetricsOverride",
            json!({"width": width, "height": height, "deviceScaleFactor": scale, "mobile": false}),
        )?;
        Ok(())
    }

    /// Waits until the page has shown `frames` more animation frames (a
    /// signal from the page, not a time): input sent after it arrives
    /// while the game runs.
    pub fn animation_frames(&mut self, frames: u32) -> Result<(), String> {
        self.eval(&format!(
            "new Promise((done) => {{ let left = {frames}; \
             const frame = () => (--left <= 0 ? done() : requestAnimationFrame(frame)); \
             requestAnimationFrame(frame); }})"
        ))?;
        Ok(())
    }

    /// Presses (`down`) or releases a key, as the keyboard would, on the
    /// focused element: `key` and `code` as in a DOM `KeyboardEvent`
    /// ("ArrowUp", "ArrowUp"), `key_code` its Windows virtual-key code.
    pub fn key(&mut self, down: bool, key: &str, code: &str, key_code: u32) -> Result<(), String> {
        self.call(
            "Input.dispatchKeyEvent",
            json!({
                "type": if down { "keyDown" } else { "keyUp" },
                "key": key,
                "code": code,
                "windowsVirtualKeyCode": key_code,
            }),
        )?;
        Ok(())
    }

    /// A mouse event at `(x, y)` in CSS pixels of the page: `kind` is
    /// "mouseMoved", "mousePressed" or "mouseReleased" (the left button).
    pub fn mouse(&mut self, kind: &str, x: f64, y: f64) -> Result<(), String> {
        self.call(
            "Input.dispatchMouseEvent",
            json!({
                "type": kind,
                "x": x, "y": y,
                "button": if kind == "mouseMoved" { "none" } else { "left" },
                "buttons": u32::from(kind == "mousePressed"),
                "clickCount": 1,
            }),
        )?;
        Ok(())
    }

    /// A touch event with one finger at `(x, y)` in CSS pixels (none for
    /// "touchEnd"): `kind` is "touchStart", "touchMove" or "touchEnd".
    /// Touch input is switched on for the page the first time.
    pub fn touch(&mut self, kind: &str, at: Option<(f64, f64)>) -> Result<(), String> {
        if !self.touch_enabled {
            self.call(
                "Emulation.setTouchEmulationEnabled",
                json!({"enabled": true, "maxTouchPoints": 1}),
            )?;
            self.touch_enabled = true;
        }
        let points: Vec<Value> = at.iter().map(|(x, y)| json!({"x": x, "y": y})).collect();
        self.call("Input.dispatchTouchEvent", json!({"type": kind, "touchPoints": points}))?;
        Ok(())
    }

    /// A command to this page, recording the messages that arrive meanwhile.
    /// An error at once if the page crashes before it answers.
    fn call(&mut self, method: &str, params: Value) -> Result<Value, String> {
        let console = &mut self.console;
        self.connection.call(method, params, COMMAND_TIMEOUT, &mut |event| {
            console.record(event);
            if console.crashed {
                return Err(format!("the page crashed; what it printed:\n{}", console.listing()));
            }
            Ok(())
        })
    }
}

impl Drop for Page<'_> {
    fn drop(&mut self) {
        let _ = self
            .browser
            .call("Target.closeTarget", json!({"targetId": self.target_id}));
    }
}

/// Decodes standard base64 (with or without padding); `None` if malformed.
fn base64_decode(text: &str) -> Option<Vec<u8>> {
    fn value(c: u8) -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    }
    let bytes = text.trim_end_matches('=').as_bytes();
    let mut out = Vec::with_capacity(bytes.len() * 3 / 4);
    for chunk in bytes.chunks(4) {
        let mut n = 0u32;
        for (i, &c) in chunk.iter().enumerate() {
            n |= value(c)? << (18 - 6 * i);
        }
        let decoded = [(n >> 16) as u8, (n >> 8) as u8, n as u8];
        match chunk.len() {
            4 => out.extend_from_slice(&decoded),
            3 => out.extend_from_slice(&decoded[..2]),
            2 => out.push(decoded[0]),
            _ => return None,
        }
    }
    Some(out)
}

/// Decodes a PNG into 8-bit RGBA.
fn decode_png(bytes: &[u8]) -> Result<Rgba, String> {
    let mut decoder = png::Decoder::new(Cursor::new(bytes));
    decoder.set_transformations(png::Transformations::normalize_to_color8());
    let mut reader = decoder
        .read_info()
        .map_err(|e| format!("the screenshot is no PNG: {e}"))?;
    let size = reader
        .output_buffer_size()
        .ok_or("the screenshot is too large to decode")?;
    let mut buffer = vec![0; size];
    let info = reader
        .next_frame(&mut buffer)
        .map_err(|e| format!("decoding the screenshot: {e}"))?;
    buffer.truncate(info.buffer_size());
    let pixels = match info.color_type {
        png::ColorType::Rgba => buffer,
        png::ColorType::Rgb => buffer.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect(),
        png::ColorType::GrayscaleAlpha => buffer.chunks_exact(2).flat_map(|p| [p[0], p[0], p[0], p[1]]).collect(),
        png::ColorType::Grayscale => buffer.iter().flat_map(|&g| [g, g, g, 255]).collect(),
        png::ColorType::Indexed => {
            return Err("the screenshot stayed indexed after expansion".into());
        }
    };
    Ok(Rgba {
        width: info.width,
        height: info.height,
        pixels,
    })
}
