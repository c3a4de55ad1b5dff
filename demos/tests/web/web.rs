//! The web build in a real browser: every demo's page (built by
//! `scripts/web build` into `target/web/`, which `scripts/test` runs first)
//! played in headless Chromium, under WebGPU and under WebGL2, ends in the
//! same state as the native binary given the same options, to the bit of
//! its checksum; a page's last frame under WebGPU and under WebGL2 matches
//! the native golden image; keys and a finger on the canvas reach the game,
//! and the recording the page offers as a download replays natively to the
//! page's tick and checksum; so does a gamepad's (a stand-in the page's
//! Gamepad API reports), and the game's sounds reach the page's audio
//! output after the first key press; breakout's last frame, its ball a
//! sprite the page fetched, matches the native golden image; a missing
//! asset stops the page with its URL; the control panel takes the mouse;
//! the canvas fills the page in device pixels and follows a resize; a bad
//! option shows the native error text; a page whose GPU cannot start says
//! so.
//!
//! Nothing here waits on time: each page is waited on for the line it
//! prints (`the final state at tick N has checksum X`), within a generous
//! deadline that only bounds a page that never prints it.

use crate::browser;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use browser::{Browser, Server};
use tickwork::engine::render::{Tolerance, compare, diff_image};
use tickwork::prelude::{PadAxis, PadButton};

/// How long a page may take to print its last line: software WebGPU on
/// CI's two cores draws the fountain's 60 000 particles slowly. The wait
/// ends at the line.
const PAGE_TIMEOUT: Duration = Duration::from_secs(300);

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The web build's folder; a missing build fails the test with the
/// command that makes it (never a skip).
fn site() -> PathBuf {
    let site = root().join("target/web");
    for demo in DEMOS.iter().map(|d| d.demo) {
        let page = site.join(demo).join("index.html");
        assert!(
            page.is_file(),
            "{} is missing: build the pages with `scripts/web build` (scripts/test does it before the tests)",
            page.display()
        );
    }
    site
}

/// One demo's run: the page's query and the same options natively.
struct Case {
    demo: &'static str,
    binary: &'static str,
    /// Options, as `name=value` pairs (a flag alone is `name`), given to
    /// the page as its query and to the native binary as `--name value`.
    options: &'static [&'static str],
}

/// Every demo, with a shipped recording where one exists, or the input it
/// takes alone (breakout's autopilot), for enough frames to collide,
/// emit, switch and score.
const DEMOS: &[Case] = &[
    Case {
        demo: "orbits",
        binary: env!("CARGO_BIN_EXE_orbits"),
        options: &["frames=120"],
    },
    Case {
        demo: "fountain",
        binary: env!("CARGO_BIN_EXE_fountain"),
        options: &["frames=40", "seed=3"],
    },
    Case {
        demo: "cloth",
        binary: env!("CARGO_BIN_EXE_cloth"),
        options: &["frames=90"],
    },
    Case {
        demo: "tops",
        binary: env!("CARGO_BIN_EXE_tops"),
        options: &["frames=120"],
    },
    Case {
        demo: "lander",
        binary: env!("CARGO_BIN_EXE_lander"),
        options: &["replay=recordings/lander_land_then_crash.ron", "frames=1500"],
    },
    Case {
        demo: "rally",
        binary: env!("CARGO_BIN_EXE_rally"),
        options: &["replay=recordings/rally_left.ron", "frames=320"],
    },
    Case {
        demo: "breakout",
        binary: env!("CARGO_BIN_EXE_breakout"),
        options: &["autopilot", "frames=600"],
    },
    Case {
        demo: "platformer",
        binary: env!("CARGO_BIN_EXE_platformer"),
        options: &["autopilot", "frames=400"],
    },
];

/// The page's URL query for `options` (a replay's path is relative to the
/// site's root, one folder up from the page).
fn query(options: &[&str], extra: &[&str]) -> String {
    options
        .iter()
        .chain(extra)
        .map(|o| o.replacen("replay=", "replay=../", 1))
        .collect::<Vec<_>>()
        .join("&")
}

/// `options` as native arguments (`replay=` a path in `assets/`).
fn native_args(options: &[&str]) -> Vec<String> {
    let mut args = Vec::new();
    for option in options {
        match option.split_once('=') {
            Some(("replay", file)) => {
                args.push("--replay".into());
                args.push(root().join("assets").join(file).to_string_lossy().into_owned());
            }
            Some((name, value)) => {
                args.push(format!("--{name}"));
                args.push(value.into());
            }
            None => args.push(format!("--{option}")),
        }
    }
    args
}

/// The lines of a native off-screen run of `case` that name its end state
/// (its frames in a scratch folder of its own, named after `test`: the
/// tests run at once).
fn native_ends(case: &Case, test: &str) -> Vec<String> {
    let out = std::env::temp_dir().join(format!(
        "tickwork-web-native-{}-{test}-{}",
        std::process::id(),
        case.demo
    ));
    let _ = std::fs::remove_dir_all(&out);
    let stdout = run_headless(case.binary, &out, &native_args(case.options));
    let _ = std::fs::remove_dir_all(&out);
    end_lines(&stdout)
}

/// Runs a native demo off-screen at 64x36, its frames into `out`, with
/// `args`; returns what it printed (it must succeed).
fn run_headless(binary: &str, out: &Path, args: &[String]) -> String {
    let output = Command::new(binary)
        .args(["--headless", "--size", "64x36", "--out"])
        .arg(out)
        .args(args)
        .output()
        .expect("the native demo runs");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "{binary} {args:?}: {stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}

/// The replay's end and the final state's checksum, the lines a page and a
/// native run print alike.
fn end_lines(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| l.contains("the replay ended at tick") || l.contains("the final state at tick"))
        .map(str::to_owned)
        .collect()
}

/// Plays every demo's page under `backend` and checks its end against the
/// native run's.
fn every_demo_matches_native(backend: &str, expected_adapter: &str) {
    let site = site();
    let server = Server::start(&site).expect("the file server starts");
    let browser = Browser::launch().unwrap_or_else(|e| panic!("{e}"));
    let mut failures = Vec::new();
    for case in DEMOS {
        let native = native_ends(case, backend);
        assert!(!native.is_empty(), "{}: the native run printed no end line", case.demo);
        let url = server.url(&format!(
            "{}/index.html?{}",
            case.demo,
            query(case.options, &[&format!("backend={backend}"), "size=64x36"])
        ));
        let mut page = browser.open(&url).unwrap_or_else(|e| panic!("{e}"));
        let ended = page.wait_console(
            |l| {
                l.contains("the final state at tick")
                    || l.contains("the replay ended at tick")
                    || l.starts_with("error")
            },
            PAGE_TIMEOUT,
        );
        let printed: Vec<String> = page.console().iter().map(|l| l.text.clone()).collect();
        match ended {
            Ok(line) if line.starts_with("error") => failures.push(format!("{}: {line}", case.demo)),
            Ok(_) => {
                let adapter = printed.iter().find(|l| l.starts_with("tickwork: drawing with"));
                assert!(
                    adapter.is_some_and(|l| l.contains(expected_adapter)),
                    "{}: drawn with {adapter:?}, expected {expected_adapter}",
                    case.demo
                );
                let page_ends = end_lines(&printed.join("\n"));
                if page_ends != native {
                    failures.push(format!("{}: page {page_ends:?}, native {native:?}", case.demo));
                }
            }
            Err(error) => failures.push(format!("{}: {error}", case.demo)),
        }
    }
    assert!(failures.is_empty(), "under {backend}:\n{}", failures.join("\n"));
}

#[test]
fn every_demo_ends_in_the_native_state_under_webgpu() {
    every_demo_matches_native("webgpu", "BrowserWebGpu");
}

#[test]
fn every_demo_ends_in_the_native_state_under_webgl2() {
    every_demo_matches_native("webgl2", "Gl");
}

/// The lander's last frame in the page, at the native golden test's size
/// and frame, against the same golden image.
fn last_frame_matches_the_golden(backend: &str) {
    // demos.rs draws the lander's golden frame at 480x270, as many frames
    // as the recording needs (its last tick, plus one).
    let frames = lander_frames();
    page_frame_matches_golden(
        &format!("lander/index.html?replay=../recordings/lander_land_then_crash.ron&frames={frames}&size=480x270"),
        "demo_lander",
        backend,
        Tolerance::default(),
    );
}

/// The last frame of the page at `page` (a path and query, held after
/// its `frames`) under `backend`, against the native golden image `golden`
/// within `tolerance`; the frame and the golden image.
fn page_frame_matches_golden(
    page: &str,
    golden: &str,
    backend: &str,
    tolerance: Tolerance,
) -> (image::RgbaImage, image::RgbaImage) {
    let site = site();
    let server = Server::start(&site).expect("the file server starts");
    let browser = Browser::launch().unwrap_or_else(|e| panic!("{e}"));
    let url = server.url(&format!("{page}&backend={backend}"));
    let mut page = browser.open(&url).unwrap_or_else(|e| panic!("{e}"));
    // The page's last line comes after its last frame (a replay's end
    // line may come before it).
    page.wait_console(|l| l.contains("s of wall time"), PAGE_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}"));
    let shot = page.screenshot("#tickwork-canvas").unwrap_or_else(|e| panic!("{e}"));
    let image = image::RgbaImage::from_raw(shot.width, shot.height, shot.pixels)
        .expect("the screenshot's pixels fill its size");
    // The native test's golden image, never re-blessed from a page.
    let golden_path = root().join(format!("assets/golden/{golden}.png"));
    let expected = image::open(&golden_path).expect("the golden image decodes").to_rgba8();
    let comparison = compare(&image, &expected, tolerance);
    if comparison.is_none_or(|c| c.fraction() > tolerance.max_fraction) {
        let out = root().join("target/golden");
        std::fs::create_dir_all(&out).expect("target/golden");
        let actual = out.join(format!("web_{backend}_{golden}.actual.png"));
        image.save(&actual).expect("the page's frame saves");
        if comparison.is_some() {
            diff_image(&image, &expected, tolerance.channel)
                .save(out.join(format!("web_{backend}_{golden}.diff.png")))
                .expect("the diff saves");
        }
        panic!(
            "under {backend} the page's last frame differs from {}: {comparison:?}; see {}",
            golden_path.display(),
            actual.display()
        );
    }
    (image, expected)
}

#[test]
fn breakouts_last_frame_with_its_fetched_sprite_matches_its_golden_image_under_webgpu() {
    // demos/tests/demos/breakout.rs draws it: the autopilot, 150 frames, 480x270.
    // The bricks' edges lie on pixel rows, which Dawn and lavapipe round
    // apart (0.7% of the frame): 1% over the frame, and at most 4 pixels
    // around the ball, the sprite the page fetched (its edge rounds apart
    // in 2 of its window's 196 pixels; drawn as a plain disc, 61 differ).
    let (page, golden) = page_frame_matches_golden(
        "breakout/index.html?autopilot&frames=150&size=480x270",
        "demo_breakout",
        "webgpu",
        Tolerance {
            max_fraction: 0.01,
            ..Tolerance::default()
        },
    );
    let ball = |image: &image::RgbaImage| image::imageops::crop_imm(image, 371, 108, 14, 14).to_image();
    let strict = Tolerance {
        max_fraction: 0.0,
        ..Tolerance::default()
    };
    let around = compare(&ball(&page), &ball(&golden), strict).expect("the same size");
    assert!(around.differing <= 4, "around the ball: {around:?}");
}

/// The frames the native lander test draws: as many as the recording
/// needs, as `run` counts them (its ticks at one step a frame, plus one).
fn lander_frames() -> u64 {
    let text = std::fs::read_to_string(root().join("assets/recordings/lander_land_then_crash.ron"))
        .expect("the recording reads");
    let recording = tickwork::engine::Recording::parse(&text, Path::new("lander_land_then_crash.ron"))
        .expect("the recording parses");
    recording.ticks + 1
}

#[test]
fn the_landers_last_frame_matches_its_golden_image_under_webgpu() {
    last_frame_matches_the_golden("webgpu");
}

#[test]
fn the_landers_last_frame_matches_its_golden_image_under_webgl2() {
    last_frame_matches_the_golden("webgl2");
}

#[test]
fn a_bad_option_in_the_url_shows_the_native_error() {
    let site = site();
    let server = Server::start(&site).expect("the file server starts");
    let browser = Browser::launch().unwrap_or_else(|e| panic!("{e}"));
    for (query, args) in [
        ("hz=-1", vec!["--hz", "-1"]),
        (
            "integrator=nope",
            vec!["--integrator", "nope", "--headless", "--frames", "1"],
        ),
        ("host=7000", vec!["--host", "7000", "--headless", "--frames", "1"]),
    ] {
        let output = Command::new(env!("CARGO_BIN_EXE_lander"))
            .args(&args)
            .output()
            .expect("the native lander runs");
        assert!(!output.status.success(), "{args:?} is refused natively");
        let stderr = String::from_utf8_lossy(&output.stderr);
        let native = stderr
            .lines()
            .find(|l| l.starts_with("error"))
            .unwrap_or_else(|| panic!("{stderr}"));
        let mut page = browser
            .open(&server.url(&format!("lander/index.html?{query}")))
            .unwrap_or_else(|e| panic!("{e}"));
        let shown = page
            .wait_console(|l| l.starts_with("error"), PAGE_TIMEOUT)
            .unwrap_or_else(|e| panic!("{e}"));
        // The host option is refused differently in a page (no UDP there).
        if query.starts_with("host") {
            assert!(shown.contains("UDP"), "{shown}");
        } else {
            assert_eq!(shown.lines().next(), Some(native), "{query}");
        }
        let message = page
            .eval("document.getElementById('tickwork-message').textContent")
            .unwrap_or_else(|e| panic!("{e}"));
        let message = message.as_str().unwrap_or_default();
        assert!(
            message.contains(shown.lines().next().unwrap_or_default()),
            "{query}: the page shows {message:?}"
        );
    }
}

#[test]
fn the_fountain_steps_on_the_gpu_under_webgpu_and_draws_its_golden_frame() {
    // `gpu` in the query is `--gpu`: the fountain's world steps in compute
    // shaders under WebGPU, drawn from the GPU's buffers. The page cannot
    // wait for a read-back, so it ends without a checksum, and says so;
    // the frame is the native golden image (demos.rs: seed 3, 120 frames,
    // 480x270), within the golden tolerance.
    let (page, _) = page_frame_matches_golden(
        "fountain/index.html?gpu&no-panel&seed=3&frames=120&size=480x270",
        "demo_fountain",
        "webgpu",
        Tolerance::default(),
    );
    assert_eq!(page.dimensions(), (480, 270));
}

#[test]
fn the_gpu_step_under_webgl2_is_refused_with_the_reason() {
    let site = site();
    let server = Server::start(&site).expect("the file server starts");
    let browser = Browser::launch().unwrap_or_else(|e| panic!("{e}"));
    let mut page = browser
        .open(&server.url("fountain/index.html?gpu&backend=webgl2"))
        .unwrap_or_else(|e| panic!("{e}"));
    let shown = page
        .wait_console(|l| l.starts_with("error"), PAGE_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(
        shown.contains("world \"fountain\": the GPU step needs compute shaders, which this adapter (WebGL2) lacks"),
        "{shown}"
    );
}

#[test]
fn a_page_whose_gpu_cannot_start_says_so() {
    let site = site();
    let server = Server::start(&site).expect("the file server starts");
    // No WebGL at all: the page's WebGL2 backend finds no context.
    let browser = Browser::launch_with(&["--disable-webgl", "--disable-3d-apis"]).unwrap_or_else(|e| panic!("{e}"));
    let mut page = browser
        .open(&server.url("lander/index.html?backend=webgl2"))
        .unwrap_or_else(|e| panic!("{e}"));
    let shown = page
        .wait_console(|l| l.starts_with("error"), PAGE_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(
        shown.contains("graphics") || shown.contains("adapter") || shown.contains("surface"),
        "the error names the GPU's start: {shown}"
    );
    let message = page
        .eval("document.getElementById('tickwork-message').textContent")
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(
        message.as_str().is_some_and(|m| m.contains(&shown)),
        "the page shows {message}"
    );
}

/// A scratch folder of this test's own (the tests run at once).
fn scratch(test: &str) -> PathBuf {
    let folder = std::env::temp_dir().join(format!("tickwork-web-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(&folder).expect("the scratch folder");
    folder
}

/// The tick and checksum of a `the final state at tick N has checksum X`
/// line.
fn final_state(line: &str) -> (u64, String) {
    tick_and_checksum(line, "the final state at tick ", " has checksum ")
        .unwrap_or_else(|| panic!("not a final-state line: {line}"))
}

/// The tick after `before` and the hexadecimal checksum after `between` in
/// `line`, if it has them.
fn tick_and_checksum(line: &str, before: &str, between: &str) -> Option<(u64, String)> {
    let (tick, checksum) = line.split(before).nth(1)?.split_once(between)?;
    let checksum = checksum.split(|c: char| !c.is_ascii_hexdigit()).next()?;
    Some((tick.parse().ok()?, checksum.to_owned()))
}

/// Plays `demo`'s page with `query` plus `record=<test>.ron`, lets `play`
/// give it input once it draws, and returns the page's final-state line
/// and the recording the page offered as a download.
fn record_in_page(demo: &str, query: &str, test: &str, play: impl FnOnce(&mut browser::Page<'_>)) -> (String, String) {
    record_in_page_with(demo, query, test, None, play)
}

/// As [`record_in_page`], with `script` run in the page before its own.
fn record_in_page_with(
    demo: &str,
    query: &str,
    test: &str,
    script: Option<&str>,
    play: impl FnOnce(&mut browser::Page<'_>),
) -> (String, String) {
    let site = site();
    let server = Server::start(&site).expect("the file server starts");
    let browser = Browser::launch().unwrap_or_else(|e| panic!("{e}"));
    let downloads = scratch(test);
    browser.allow_downloads(&downloads).unwrap_or_else(|e| panic!("{e}"));
    let name = format!("{test}.ron");
    let mut page = browser
        .open_with(&server.url(&format!("{demo}/index.html?{query}&record={name}")), script)
        .unwrap_or_else(|e| panic!("{e}"));
    page.wait_console(|l| l.starts_with("tickwork: drawing with"), PAGE_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}"));
    play(&mut page);
    let end = page
        .wait_console(|l| l.contains("the final state at tick"), PAGE_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}"));
    let offered = page
        .wait_console(|l| l.contains("offered as a download"), PAGE_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(offered.contains(&name), "{offered}");
    let saved = browser.wait_download(PAGE_TIMEOUT).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(saved, name, "the download keeps the name given in the URL");
    let text = std::fs::read_to_string(downloads.join(&saved)).expect("the downloaded recording reads");
    let _ = std::fs::remove_dir_all(&downloads);
    (end, text)
}

/// Replays `recording` (a page's) with the native `binary` and returns the
/// tick and checksum at the recording's end (its `the replay ended at tick
/// N with checksum X` line).
fn replay_natively(binary: &str, recording: &str, test: &str) -> (u64, String) {
    let folder = scratch(&format!("{test}-native"));
    let path = folder.join("recording.ron");
    std::fs::write(&path, recording).expect("the recording writes");
    let replay = ["--replay".to_owned(), path.to_string_lossy().into_owned()];
    let stdout = run_headless(binary, &folder.join("frames"), &replay);
    let _ = std::fs::remove_dir_all(&folder);
    stdout
        .lines()
        .find_map(|l| tick_and_checksum(l, "the replay ended at tick ", " with checksum "))
        .unwrap_or_else(|| panic!("the native replay printed no end:\n{stdout}"))
}

#[test]
fn keys_pressed_in_a_page_are_recorded_and_replay_natively_to_the_same_state() {
    let test = "keys";
    let (end, text) = record_in_page("lander", "frames=240&size=480x270", test, |page| {
        // The canvas has the focus from the start: keys reach the game.
        page.animation_frames(10).unwrap_or_else(|e| panic!("{e}"));
        page.key(true, "ArrowUp", "ArrowUp", 38)
            .unwrap_or_else(|e| panic!("{e}"));
        page.animation_frames(30).unwrap_or_else(|e| panic!("{e}"));
        page.key(false, "ArrowUp", "ArrowUp", 38)
            .unwrap_or_else(|e| panic!("{e}"));
        page.key(true, "ArrowLeft", "ArrowLeft", 37)
            .unwrap_or_else(|e| panic!("{e}"));
        page.animation_frames(10).unwrap_or_else(|e| panic!("{e}"));
        page.key(false, "ArrowLeft", "ArrowLeft", 37)
            .unwrap_or_else(|e| panic!("{e}"));
    });
    let recording = tickwork::engine::Recording::parse(&text, Path::new("keys.ron")).expect("the recording parses");
    let held = |key| recording.inputs.iter().any(|(_, input)| input.held.contains(key));
    assert!(
        held(tickwork::engine::Key::Up) && held(tickwork::engine::Key::Left),
        "the page's keys are in its recording:\n{text}"
    );
    let native = replay_natively(env!("CARGO_BIN_EXE_lander"), &text, test);
    assert_eq!(native, final_state(&end), "the native replay's end against the page's");
}

#[test]
fn a_finger_on_the_canvas_is_the_mouse_and_replays_natively_to_the_same_state() {
    let test = "touch";
    // Breakout's paddle follows the pointer; a press launches the ball.
    let (end, text) = record_in_page("breakout", "frames=240&size=480x270", test, |page| {
        page.animation_frames(10).unwrap_or_else(|e| panic!("{e}"));
        page.touch("touchStart", Some((240.0, 200.0)))
            .unwrap_or_else(|e| panic!("{e}"));
        page.animation_frames(5).unwrap_or_else(|e| panic!("{e}"));
        for x in [220.0, 190.0, 160.0] {
            page.touch("touchMove", Some((x, 200.0)))
                .unwrap_or_else(|e| panic!("{e}"));
            page.animation_frames(5).unwrap_or_else(|e| panic!("{e}"));
        }
        page.touch("touchEnd", None).unwrap_or_else(|e| panic!("{e}"));
    });
    let recording = tickwork::engine::Recording::parse(&text, Path::new("touch.ron")).expect("the recording parses");
    let pressed = recording
        .inputs
        .iter()
        .any(|(_, input)| input.held.contains(tickwork::engine::Key::MouseLeft));
    let pointers: Vec<f32> = recording
        .inputs
        .iter()
        .filter_map(|(_, input)| input.pointer.map(|p| p[0]))
        .collect();
    assert!(pressed, "the finger down is the left button in the recording:\n{text}");
    assert!(
        pointers.windows(2).any(|w| w[1] < w[0]),
        "the finger's moves to the left are the pointer's in the recording: {pointers:?}"
    );
    let native = replay_natively(env!("CARGO_BIN_EXE_breakout"), &text, test);
    assert_eq!(native, final_state(&end), "the native replay's end against the page's");
}

#[test]
fn the_control_panel_takes_the_mouse_in_a_page() {
    let site = site();
    let server = Server::start(&site).expect("the file server starts");
    let browser = Browser::launch().unwrap_or_else(|e| panic!("{e}"));
    // The integrator race, running until the test is done with it: every
    // step below waits on what the page says, never on the time.
    let mut page = browser
        .open(&server.url("orbits/index.html?size=960x540"))
        .unwrap_or_else(|e| panic!("{e}"));
    page.wait_console(|l| l.starts_with("tickwork: drawing with"), PAGE_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}"));
    page.animation_frames(10).unwrap_or_else(|e| panic!("{e}"));
    let canvas = page.element_clip("#tickwork-canvas").unwrap_or_else(|e| panic!("{e}"));
    // The panel's "Pause (P)" button, where egui lays it out at this size
    // (the panel's third row, at its left; "Resume (P)" there once paused).
    let (x, y) = (canvas.x + 53.0, canvas.y + 69.0);
    let click = |page: &mut browser::Page<'_>| {
        for kind in ["mouseMoved", "mousePressed", "mouseReleased"] {
            page.mouse(kind, x, y).unwrap_or_else(|e| panic!("{e}"));
        }
    };
    // Each click that egui takes toggles the clock, and the page says so.
    // egui takes a press and release as a click only within 0.8 s of each
    // other, which two events sent to a busy machine's page can miss: the
    // test clicks again, 20 frames after each click, until the page has
    // paused and resumed (at most 10 clicks).
    let toggles = |page: &browser::Page<'_>| -> Vec<(bool, u64)> {
        page.console()
            .iter()
            .filter_map(|l| {
                let paused = l.text.strip_prefix("tickwork: paused at tick ").map(|t| (true, t));
                let resumed = l.text.strip_prefix("tickwork: resumed at tick ").map(|t| (false, t));
                paused.or(resumed)
            })
            .map(|(paused, tick)| {
                let tick = tick.parse().unwrap_or_else(|_| panic!("a tick: {tick:?}"));
                (paused, tick)
            })
            .collect()
    };
    let mut clicks = 0;
    while toggles(&page).len() < 2 {
        assert!(
            clicks < 10,
            "after {clicks} clicks on the panel's pause button the page said only {:?}",
            toggles(&page)
        );
        click(&mut page);
        clicks += 1;
        page.animation_frames(20).unwrap_or_else(|e| panic!("{e}"));
    }
    let toggles = toggles(&page);
    assert!(
        toggles[0].0 && toggles[0].1 > 0,
        "the first click paused the clock after it ran: {toggles:?}"
    );
    for pair in toggles.windows(2).filter(|pair| pair[0].0) {
        assert_eq!(
            pair[1].1, pair[0].1,
            "the clock stood still for at least 20 frames between a pause and a resume: {toggles:?}"
        );
    }
}

#[test]
fn the_canvas_fills_the_page_at_its_pixel_ratio_and_follows_a_resize() {
    let site = site();
    let server = Server::start(&site).expect("the file server starts");
    // A screen of two device pixels a CSS pixel. (Emulating the ratio
    // through the DevTools protocol changes `devicePixelRatio` but not the
    // sizes a ResizeObserver reports, so the browser's own flag it is.)
    let scale = 2;
    let browser = Browser::launch_with(&["--force-device-scale-factor=2"]).unwrap_or_else(|e| panic!("{e}"));
    let mut page = browser
        .open(&server.url("lander/index.html"))
        .unwrap_or_else(|e| panic!("{e}"));
    page.wait_console(|l| l.starts_with("tickwork: drawing with"), PAGE_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}"));
    for (width, height) in [(640, 360), (500, 400)] {
        // 0: the screen's own ratio.
        page.set_viewport(width, height, 0.0).unwrap_or_else(|e| panic!("{e}"));
        // The engine says when a new size has reached the screen.
        let (device_width, device_height) = (width * scale, height * scale);
        let line = format!("tickwork: resized to {device_width}x{device_height} and presented");
        page.wait_console(|l| l == line, PAGE_TIMEOUT)
            .unwrap_or_else(|e| panic!("{e}"));
        let sizes = page
            .eval(
                "(() => { const c = document.getElementById('tickwork-canvas'); \
                 return [c.width, c.height, c.clientWidth, c.clientHeight]; })()",
            )
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            sizes,
            serde_json::json!([device_width, device_height, width, height]),
            "the canvas fills the {width}x{height} page in device pixels at {scale}x"
        );
    }
}

/// Set up before a page's own script: a standard gamepad that
/// `navigator.getGamepads()` reports (`window.tickworkPad`; a test presses
/// its buttons and moves its sticks by changing it, as a browser updates a
/// real one), and an ear on the page's audio output: every buffer the page
/// fills for its audio context (`AudioBuffer.copyToChannel`, how kira's
/// Web Audio host plays) is counted in `window.tickworkBuffers`, and its
/// loudest sample kept in `window.tickworkHeard`.
const PAD_AND_EAR: &str = r#"(() => {
  const buttons = Array.from({ length: 17 }, () => ({ pressed: false, touched: false, value: 0 }));
  window.tickworkPad = {
    id: "Tickwork test pad (STANDARD GAMEPAD Vendor: 045e Product: 028e)",
    index: 0, connected: true, mapping: "standard", timestamp: 0, buttons, axes: [0, 0, 0, 0],
  };
  Navigator.prototype.getGamepads = function () { return [window.tickworkPad, null, null, null]; };
  window.tickworkHeard = 0;
  window.tickworkBuffers = 0;
  const copy = AudioBuffer.prototype.copyToChannel;
  AudioBuffer.prototype.copyToChannel = function (source, channel, start) {
    window.tickworkBuffers += 1;
    for (const x of source) { window.tickworkHeard = Math.max(window.tickworkHeard, Math.abs(x)); }
    return copy.call(this, source, channel, start ?? 0);
  };
})();"#;

/// Runs `js` in `page` (a statement or an expression), failing the test on
/// an error; its value.
fn run_js(page: &mut browser::Page<'_>, js: &str) -> serde_json::Value {
    page.eval(js).unwrap_or_else(|e| panic!("{js}: {e}"))
}

#[test]
fn a_gamepad_in_a_page_plays_and_replays_natively_and_the_games_sounds_reach_the_pages_audio_output() {
    let test = "pad";
    let mut before_any_sound = serde_json::Value::Null;
    let mut opened = String::new();
    let mut heard = 0.0;
    let (end, text) = record_in_page_with("breakout", "frames=360&size=480x270", test, Some(PAD_AND_EAR), |page| {
        page.animation_frames(5).unwrap_or_else(|e| panic!("{e}"));
        // The first key press is the gesture a browser wants before sound.
        page.key(true, "ArrowRight", "ArrowRight", 39)
            .unwrap_or_else(|e| panic!("{e}"));
        page.animation_frames(3).unwrap_or_else(|e| panic!("{e}"));
        page.key(false, "ArrowRight", "ArrowRight", 39)
            .unwrap_or_else(|e| panic!("{e}"));
        opened = page
            .wait_console(
                |l| l.starts_with("tickwork: sound plays") || l.starts_with("tickwork: sound is silent"),
                PAGE_TIMEOUT,
            )
            .unwrap_or_else(|e| panic!("{e}"));
        page.animation_frames(10).unwrap_or_else(|e| panic!("{e}"));
        // The device plays silence until the game starts a sound.
        before_any_sound = run_js(page, "[window.tickworkBuffers, window.tickworkHeard]");
        // The pad's South button serves; its stick moves the paddle left.
        run_js(
            page,
            "tickworkPad.buttons[0].pressed = true; tickworkPad.buttons[0].value = 1;",
        );
        page.animation_frames(4).unwrap_or_else(|e| panic!("{e}"));
        run_js(
            page,
            "tickworkPad.buttons[0].pressed = false; tickworkPad.buttons[0].value = 0;",
        );
        run_js(page, "tickworkPad.axes[0] = -0.75;");
        page.animation_frames(20).unwrap_or_else(|e| panic!("{e}"));
        run_js(page, "tickworkPad.axes[0] = 0;");
        // The ball served meets the bricks about a second later, and their
        // sound reaches the output; looked for every ten frames, until the
        // page's last.
        for _ in 0..36 {
            heard = run_js(page, "window.tickworkHeard").as_f64().unwrap_or(0.0);
            if heard > 0.05 {
                break;
            }
            page.animation_frames(10).unwrap_or_else(|e| panic!("{e}"));
        }
    });
    assert_eq!(
        opened, "tickwork: sound plays through the audio device",
        "the page opens its audio device at the first key"
    );
    let recording = tickwork::engine::Recording::parse(&text, Path::new("pad.ron")).expect("the recording parses");
    let pad = |input: &tickwork::engine::TickInput| input.pads[0];
    assert!(
        recording.inputs.iter().any(|(_, i)| pad(i).pressed(PadButton::South)),
        "the pad's South press is in the page's recording:\n{text}"
    );
    assert!(
        recording.inputs.iter().any(|(_, i)| pad(i).axis(PadAxis::LeftX) < -0.7),
        "the stick's move is in the page's recording:\n{text}"
    );
    let native = replay_natively(env!("CARGO_BIN_EXE_breakout"), &text, test);
    assert_eq!(native, final_state(&end), "the native replay's end against the page's");
    // Silence went to the output before the game started a sound, and its
    // sounds after (the page's replay hits a brick natively too).
    let [buffers, before] = [0, 1].map(|k| before_any_sound[k].as_f64().unwrap_or(f64::NAN));
    assert!(
        buffers >= 1.0,
        "the device was fed before the serve: {before_any_sound}"
    );
    assert!(before < 1e-3, "silence before any sound: {before_any_sound}");
    assert!(
        heard > 0.05,
        "the game's sounds reached the page's output: loudest sample {heard}"
    );
    let native_sounds = native_sounds(&text, test);
    assert!(
        native_sounds.iter().any(|s| s == "brick"),
        "the native replay hit a brick: {native_sounds:?}"
    );
}

/// The sounds a native replay of `recording` started, by name (breakout
/// in-process, through its session's log).
fn native_sounds(recording: &str, test: &str) -> Vec<String> {
    use tickwork::engine::app::FrameSource;
    let recording =
        tickwork::engine::Recording::parse(recording, Path::new(&format!("{test}.ron"))).expect("the recording parses");
    let ticks = recording.ticks;
    let mut session = tickwork::engine::app::GameSession::new(
        tickwork_demos::breakout::Breakout::new(false),
        tickwork::engine::app::SessionOptions {
            replay: Some(recording),
            ..tickwork::engine::app::SessionOptions::default()
        },
    )
    .expect("the session starts");
    while session.ticks() < ticks {
        session.advance(1.0 / 60.0).expect("steps");
    }
    session.played_sounds().map(|p| p.sound.to_string()).collect()
}

#[test]
fn a_page_whose_asset_is_missing_says_which() {
    // The breakout page alone, without the site's assets beside it.
    let site = scratch("missing-asset");
    std::fs::create_dir_all(site.join("breakout")).expect("a folder");
    for file in std::fs::read_dir(root().join("target/web/breakout")).expect("the built page") {
        let file = file.expect("a file");
        std::fs::copy(file.path(), site.join("breakout").join(file.file_name())).expect("copied");
    }
    let server = Server::start(&site).expect("the file server starts");
    let browser = Browser::launch().unwrap_or_else(|e| panic!("{e}"));
    let mut page = browser
        .open(&server.url("breakout/index.html"))
        .unwrap_or_else(|e| panic!("{e}"));
    let shown = page
        .wait_console(|l| l.starts_with("error"), PAGE_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        shown,
        "error: an asset the game lists (Game::assets): cannot fetch ../assets/sprites/ball.png: HTTP 404 Not Found"
    );
    let _ = std::fs::remove_dir_all(&site);
}
