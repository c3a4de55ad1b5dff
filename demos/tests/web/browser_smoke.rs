//! The browser harness itself (`tests/web/browser/mod.rs`), before any page of
//! the web build: the file server answers as a browser needs, and headless
//! Chromium on this machine gives a page both a WebGPU adapter (and device)
//! and a WebGL2 context whose drawing a screenshot shows. If this fails, the
//! web build's tests cannot pass either, and its message says which part of
//! the machine is missing (the `chromium` package, SwiftShader's adapters).

use crate::browser;

use std::fs;
use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::PathBuf;
use std::time::Duration;

use browser::{Browser, Server};

/// How long a page may take to print what a test waits for. The wait ends
/// at the line; this only bounds a page that never prints it.
const PAGE_TIMEOUT: Duration = Duration::from_secs(120);

/// The WebGL2 canvas's clear colour, exact in 8 bits: 0.2, 0.4, 0.6 of 255.
const CLEAR: [u8; 4] = [51, 102, 153, 255];

/// The page: asks for a WebGPU adapter and device, clears a WebGL2 canvas,
/// and says how each went on the console.
const PAGE: &str = r#"<!doctype html>
<html><head><meta charset="utf-8"><title>browser smoke</title>
<style>body { margin: 0; background: #fff; } canvas { display: block; }</style>
</head><body>
<canvas id="gl" width="64" height="48"></canvas>
<script src="smoke.js"></script>
</body></html>
"#;

const SCRIPT: &str = r#"
(async () => {
  try {
    if (!navigator.gpu) throw new Error("navigator.gpu is missing");
    const adapter = await navigator.gpu.requestAdapter();
    if (!adapter) throw new Error("requestAdapter() gave null");
    const device = await adapter.requestDevice();
    if (!device) throw new Error("requestDevice() gave null");
    const i = adapter.info;
    console.log(`webgpu ok vendor=${i.vendor} architecture=${i.architecture} ` +
      `device=${i.device} description=${i.description} ` +
      `fallback=${adapter.isFallbackAdapter ?? i.isFallbackAdapter}`);
  } catch (e) {
    console.error(`webgpu failed: ${e}`);
  }
})();
try {
  const gl = document.getElementById("gl").getContext("webgl2");
  if (!gl) throw new Error("getContext('webgl2') gave null");
  gl.clearColor(0.2, 0.4, 0.6, 1.0);
  gl.clear(gl.COLOR_BUFFER_BIT);
  const debug = gl.getExtension("WEBGL_debug_renderer_info");
  const renderer = debug ? gl.getParameter(debug.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
  console.log(`webgl2 ok version=${gl.getParameter(gl.VERSION)} renderer=${renderer}`);
} catch (e) {
  console.error(`webgl2 failed: ${e}`);
}
"#;

/// A fresh folder with the page, its script, and a file of each type the
/// web build serves; removed on drop, also when the test fails.
struct Site(PathBuf);

impl Site {
    fn new(test: &str) -> Site {
        let dir = std::env::temp_dir().join(format!("tickwork-browser-smoke-{}-{test}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).expect("the site folder");
        fs::write(dir.join("index.html"), PAGE).expect("index.html");
        fs::write(dir.join("smoke.js"), SCRIPT).expect("smoke.js");
        fs::write(dir.join("module.wasm"), b"\0asm\x01\0\0\0").expect("module.wasm");
        fs::write(dir.join("scene.ron"), "(particles: [])").expect("scene.ron");
        Site(dir)
    }
}

impl Drop for Site {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.0);
    }
}

/// Sends `request` as it is and returns the whole response.
fn raw(server: &Server, request: &[u8]) -> String {
    let mut stream = TcpStream::connect(server.addr()).expect("connects to the server");
    stream.write_all(request).expect("sends the request");
    let mut response = Vec::new();
    stream.read_to_end(&mut response).expect("reads the response");
    String::from_utf8_lossy(&response).into_owned()
}

#[test]
fn the_server_answers_as_a_browser_needs_and_refuses_the_rest() {
    let site = Site::new("server");
    let server = Server::start(&site.0).expect("the server starts");

    let wasm = raw(&server, b"GET /module.wasm HTTP/1.1\r\nHost: x\r\n\r\n");
    assert!(wasm.starts_with("HTTP/1.1 200 OK\r\n"), "{wasm}");
    assert!(wasm.contains("Content-Type: application/wasm\r\n"), "{wasm}");
    assert!(wasm.contains("Content-Length: 8\r\n"), "{wasm}");
    assert!(wasm.ends_with("\0asm\x01\0\0\0"), "{wasm:?}");

    let index = raw(&server, b"GET /?backend=webgl2 HTTP/1.1\r\n\r\n");
    assert!(index.contains("Content-Type: text/html; charset=utf-8\r\n"), "{index}");
    let head = raw(&server, b"HEAD /smoke.js HTTP/1.1\r\n\r\n");
    assert!(
        head.contains("Content-Type: text/javascript; charset=utf-8\r\n"),
        "{head}"
    );
    assert!(head.ends_with("\r\n\r\n"), "HEAD has no body: {head}");

    for (request, status) in [
        (&b"GET /missing.png HTTP/1.1\r\n\r\n"[..], "404"),
        (b"GET /../etc/passwd HTTP/1.1\r\n\r\n", "403"),
        (b"GET /%2e%2e/etc/passwd HTTP/1.1\r\n\r\n", "403"),
        (b"POST /index.html HTTP/1.1\r\n\r\n", "405"),
    ] {
        let response = raw(&server, request);
        assert!(
            response.starts_with(&format!("HTTP/1.1 {status} ")),
            "{}: {response}",
            String::from_utf8_lossy(request)
        );
    }
    let long = format!("GET /{} HTTP/1.1\r\n\r\n", "a".repeat(64 * 1024));
    let response = raw(&server, long.as_bytes());
    assert!(response.starts_with("HTTP/1.1 431 "), "{response}");

    // A connection that never sends its request does not keep the server
    // from stopping.
    let _idle = TcpStream::connect(server.addr()).expect("connects");
    drop(server);
}

#[test]
fn headless_chromium_gives_a_page_webgpu_and_webgl2() {
    let site = Site::new("browser");
    let server = Server::start(&site.0).expect("the server starts");
    let browser = Browser::launch().unwrap_or_else(|e| panic!("{e}"));
    println!("{}", browser.version().unwrap_or_else(|e| panic!("{e}")));
    let mut page = browser
        .open(&server.url("index.html"))
        .unwrap_or_else(|e| panic!("{e}"));

    let webgl2 = page
        .wait_console(|line| line.starts_with("webgl2 "), PAGE_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}"));
    println!("{webgl2}");
    assert!(webgl2.starts_with("webgl2 ok "), "{webgl2}");

    let webgpu = page
        .wait_console(|line| line.starts_with("webgpu "), PAGE_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}"));
    println!("{webgpu}");
    assert!(webgpu.starts_with("webgpu ok "), "{webgpu}");

    let shot = page.screenshot("#gl").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((shot.width, shot.height), (64, 48));
    for (x, y) in [(0, 0), (32, 24), (63, 47)] {
        let pixel = shot.pixel(x, y);
        let close = pixel.iter().zip(CLEAR).all(|(&a, b)| a.abs_diff(b) <= 1);
        assert!(close, "pixel ({x}, {y}) is {pixel:?}, the clear colour {CLEAR:?}");
    }

    // eval awaits promises and reports what the server sent.
    let fetched = page
        .eval("fetch('scene.ron').then(r => r.headers.get('content-type') + ' ' + r.status)")
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(fetched, "text/plain; charset=utf-8 200");
    let thrown = page.eval("Promise.reject(new Error('on purpose'))");
    assert!(thrown.as_ref().is_err_and(|e| e.contains("on purpose")), "{thrown:?}");

    // An uncaught exception is a console line too.
    page.eval("setTimeout(() => { throw new Error('uncaught on purpose') }, 0)")
        .unwrap_or_else(|e| panic!("{e}"));
    let exception = page
        .wait_console(|line| line.contains("uncaught on purpose"), PAGE_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(exception.starts_with("Uncaught"), "{exception}");
}
