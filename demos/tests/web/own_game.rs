//! A game outside this repository, as a newcomer makes it: `scripts/test`
//! runs `tickwork new` into a folder outside the checkout, runs the new
//! game's own tests, plays its recording off-screen natively, and builds
//! its page with `tickwork web build` (`target/own-game/`). Here the page,
//! played in headless Chromium under WebGPU and under WebGL2 with the same
//! recording, ends in the native run's state, to the bit of its checksum;
//! and `tickwork web serve` serves that site with the types a browser needs.
//!
//! Nothing here waits on time: the page is waited on for the line it prints
//! (`the final state at tick N has checksum X`), within a deadline that
//! only bounds a page that never prints it; the server on its first line.

use crate::browser;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

use browser::{Browser, Server};

const PAGE_TIMEOUT: Duration = Duration::from_secs(300);

/// What `scripts/test` made; missing, the test fails with the command that
/// makes it (never a skip).
fn own_game() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/own-game");
    for file in ["site/index.html", "native.txt", "manifest.txt"] {
        assert!(
            dir.join(file).is_file(),
            "{} is missing: scripts/test makes it (tickwork new, cargo test, the native replay, tickwork web build) \
             before the tests",
            dir.join(file).display()
        );
    }
    dir
}

/// The lines of a run that name its end state.
fn end_lines(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| l.contains("the replay ended at tick") || l.contains("the final state at tick"))
        .map(|l| l.trim().to_owned())
        .collect()
}

fn page_matches_native(backend: &str, expected_adapter: &str) {
    let dir = own_game();
    // native.txt is the game's `cargo test` (whose replays end too), then
    // its off-screen run: that run's lines follow its "drawing" line.
    let text = std::fs::read_to_string(dir.join("native.txt")).expect("native.txt");
    let run = text.rfind("off-screen on").map_or(text.as_str(), |at| &text[at..]);
    let native = end_lines(run);
    assert!(
        native
            .iter()
            .any(|l| l.contains("the replay ended at tick 240 with checksum")),
        "the native replay printed its end: {native:?}"
    );
    let server = Server::start(&dir.join("site")).expect("the file server starts");
    let browser = Browser::launch().unwrap_or_else(|e| panic!("{e}"));
    let url = server.url(&format!(
        "index.html?replay=recordings/kicks.ron&frames=240&size=64x36&backend={backend}"
    ));
    let mut page = browser.open(&url).unwrap_or_else(|e| panic!("{e}"));
    let ended = page
        .wait_console(
            |l| l.contains("the replay ended at tick") || l.starts_with("error"),
            PAGE_TIMEOUT,
        )
        .unwrap_or_else(|e| panic!("{e}"));
    let printed: Vec<String> = page.console().iter().map(|l| l.text.clone()).collect();
    assert!(
        !ended.starts_with("error"),
        "the page stopped: {ended}\n{}",
        printed.join("\n")
    );
    let adapter = printed.iter().find(|l| l.starts_with("tickwork: drawing with"));
    assert!(
        adapter.is_some_and(|l| l.contains(expected_adapter)),
        "drawn with {adapter:?}, expected {expected_adapter}"
    );
    assert_eq!(
        end_lines(&printed.join("\n")),
        native,
        "the page's end against the native run's"
    );
}

#[test]
fn the_new_games_page_ends_in_its_native_state_under_webgpu() {
    page_matches_native("webgpu", "BrowserWebGpu");
}

#[test]
fn the_new_games_page_ends_in_its_native_state_under_webgl2() {
    page_matches_native("webgl2", "Gl");
}

/// A GET of `path` from `port` on localhost: the status line, the
/// content type and the body's length.
fn get(port: &str, path: &str) -> (String, String, usize) {
    let mut stream = TcpStream::connect(format!("127.0.0.1:{port}")).expect("the server takes a connection");
    write!(
        stream,
        "GET {path} HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n"
    )
    .expect("the request");
    let mut response = Vec::new();
    stream.read_to_end(&mut response).expect("the response");
    let text = String::from_utf8_lossy(&response);
    let (head, body) = text.split_once("\r\n\r\n").unwrap_or((&text, ""));
    let status = head.lines().next().unwrap_or_default().to_owned();
    let content_type = head
        .lines()
        .find_map(|l| l.strip_prefix("Content-Type: "))
        .unwrap_or_default()
        .to_owned();
    (status, content_type, body.len())
}

#[test]
fn web_serve_builds_and_serves_the_page_with_the_types_a_browser_needs() {
    let dir = own_game();
    let manifest = std::fs::read_to_string(dir.join("manifest.txt")).expect("manifest.txt");
    // The game itself lives outside the checkout only while scripts/test
    // runs (it removes it when it ends).
    assert!(
        Path::new(manifest.trim()).is_file(),
        "the new game's {} is gone: run this test through scripts/test, which makes the game and removes it at its end",
        manifest.trim()
    );
    let out = std::env::temp_dir().join(format!("tickwork-own-game-serve-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let mut serve = Command::new(env!("CARGO_BIN_EXE_tickwork"))
        .args(["web", "serve", "--release", "--port", "0", "--target-dir"])
        .arg(dir.join("../wasm"))
        .arg("--manifest-path")
        .arg(manifest.trim())
        .arg("--out")
        .arg(&out)
        .stdout(Stdio::piped())
        .spawn()
        .expect("tickwork web serve starts");
    let mut lines = BufReader::new(serve.stdout.take().expect("piped"));
    let mut seen = Vec::new();
    // The build's lines, then the one that says where it serves (the
    // signal that it listens); bounded by the output ending.
    let port = loop {
        let mut line = String::new();
        if lines.read_line(&mut line).expect("a line") == 0 {
            let _ = serve.kill();
            panic!("serve ended before serving:\n{}", seen.join(""));
        }
        if let Some(rest) = line.split("on http://127.0.0.1:").nth(1) {
            break rest.split('/').next().unwrap_or_default().to_owned();
        }
        seen.push(line);
    };
    let page = get(&port, "/?replay=recordings/kicks.ron");
    let wasm_name = format!("/{}_bg.wasm", manifest_bin(manifest.trim()));
    let wasm = get(&port, &wasm_name);
    let recording = get(&port, "/recordings/kicks.ron");
    let outside = get(&port, "/../Cargo.toml");
    let _ = serve.kill();
    let _ = serve.wait();
    let _ = std::fs::remove_dir_all(&out);
    assert_eq!(
        (page.0.as_str(), page.1.as_str()),
        ("HTTP/1.1 200 OK", "text/html; charset=utf-8")
    );
    assert_eq!(
        (wasm.0.as_str(), wasm.1.as_str()),
        ("HTTP/1.1 200 OK", "application/wasm")
    );
    assert!(wasm.2 > 100_000, "the wasm is whole: {} bytes", wasm.2);
    assert_eq!(recording.0, "HTTP/1.1 200 OK");
    assert!(outside.0.contains("404"), "nothing outside the site: {}", outside.0);
}

/// The binary of the game whose manifest is `manifest` (its package name).
fn manifest_bin(manifest: &str) -> String {
    Path::new(manifest)
        .parent()
        .and_then(Path::file_name)
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}
