//! `tickwork render` and `tickwork view` as a user runs them: frames, GIF,
//! errors, and a real window under Xvfb compared with the off-screen frame.
//!
//! Needs a graphics adapter (Mesa's software Vulkan driver) and, for the
//! window, Xvfb and ImageMagick's `import`: `scripts/test` installs them.
//! Nothing here skips when they are missing; the tests fail and say what.

use crate::support;

use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use tickwork_engine::render::{Tolerance, compare};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn scene(name: &str) -> String {
    root().join("assets/scenes").join(name).display().to_string()
}

fn scratch(name: &str) -> PathBuf {
    let dir = root().join("target/test-render").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

fn tickwork(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_tickwork"))
        .args(args)
        .output()
        .expect("runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn render_writes_frames_and_a_gif_and_refuses_to_overwrite_them() {
    let dir = scratch("frames");
    let out = dir.join("png");
    let gif = dir.join("run.gif");
    let args = [
        "render",
        &scene("projectile.ron"),
        "--frames",
        "12",
        "--size",
        "161x91",
        "--out",
        out.to_str().expect("utf-8"),
        "--gif",
        gif.to_str().expect("utf-8"),
        "--display-hz",
        "20",
    ];
    let output = tickwork(&args);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let stdout = text(&output.stdout);
    // 12 frames of 50 ms on a 60 Hz scene: 0.6 s, 36 steps.
    assert!(stdout.contains("rendered 12 frames (36 steps, 161x91)"), "{stdout}");
    for k in 0..12 {
        let frame = image::open(out.join(format!("frame_{k:05}.png")))
            .expect("frame")
            .to_rgba8();
        assert_eq!(frame.dimensions(), (161, 91));
    }
    let decoder = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(std::fs::File::open(&gif).expect("gif")))
        .expect("a GIF");
    let frames = image::AnimationDecoder::into_frames(decoder)
        .collect_frames()
        .expect("frames");
    assert_eq!(frames.len(), 12);
    let (numer, denom) = frames[0].delay().numer_denom_ms();
    assert_eq!(f64::from(numer) / f64::from(denom), 50.0, "GIF delay");
    // Again without --force: refused, nothing overwritten.
    let before = std::fs::metadata(out.join("frame_00000.png"))
        .and_then(|m| m.modified())
        .expect("mtime");
    let output = tickwork(&args);
    assert!(!output.status.success());
    let stderr = text(&output.stderr);
    assert!(
        stderr.contains("frame_00000.png: exists; pass --force to overwrite it"),
        "{stderr}"
    );
    let after = std::fs::metadata(out.join("frame_00000.png"))
        .and_then(|m| m.modified())
        .expect("mtime");
    assert_eq!(before, after);
}

#[test]
fn a_million_particles_render_on_the_gpu_as_they_render_on_the_cpu() {
    // The GPU step's scene: a million particles onto a floor, drawn by the
    // splat on either backend; its floor finds contacts at the end of the
    // step, so the GPU's states are the CPU's on lavapipe, and the frames
    // are the same pixels.
    let mut last = Vec::new();
    for backend in ["cpu", "gpu"] {
        let dir = scratch(&format!("downpour_{backend}"));
        let scene_path = scene("downpour.ron");
        let mut args = vec![
            "render",
            &scene_path,
            "--frames",
            "3",
            "--size",
            "320x180",
            "--no-hud",
            "--display-hz",
            "20",
            "--out",
            dir.to_str().expect("utf-8"),
        ];
        if backend == "gpu" {
            args.push("--gpu");
        }
        let output = tickwork(&args);
        assert!(output.status.success(), "{backend}: {}", text(&output.stderr));
        let stdout = text(&output.stdout);
        // 3 frames of 50 ms at 60 Hz: 9 steps.
        assert!(stdout.contains("rendered 3 frames (9 steps, 320x180)"), "{stdout}");
        last.push(image::open(dir.join("frame_00002.png")).expect("frame").to_rgba8());
    }
    // Something is drawn: the lattice's blue over the background's 22.
    let lit = last[0].pixels().filter(|p| p[2] > 40).count();
    assert!(lit > 10_000, "{lit} lit pixels");
    let differing = last[0].pixels().zip(last[1].pixels()).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "pixels differing between the CPU's and the GPU's frame");
}

#[test]
fn a_jittery_display_runs_the_steps_its_frame_times_add_up_to() {
    // 50 frames of a jittery 50 Hz display (+-50%, seed 1) on the scene's
    // 240 Hz clock: as many steps as fit in the frames' total duration.
    let mut display = tickwork_engine::clock::JitteryCadence::new(1.0 / 50.0, 1);
    let total: f64 = (0..50)
        .map(|_| tickwork_engine::clock::TimeSource::next_frame(&mut display))
        .sum();
    let expected = (total * 240.0).floor() as u64;
    let dir = scratch("jitter");
    let output = tickwork(&[
        "render",
        &scene("bouncing_ball.ron"),
        "--frames",
        "50",
        "--jitter",
        "--display-hz",
        "50",
        "--size",
        "64x64",
        "--out",
        dir.to_str().expect("utf-8"),
    ]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let stdout = text(&output.stdout);
    let steps: u64 = stdout
        .split("frames (")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .expect("steps in the summary");
    assert!(
        steps.abs_diff(expected) <= 1 && expected != 240,
        "{steps} steps, expected {expected}: {stdout}"
    );
}

#[test]
fn bad_options_are_errors_that_say_what_was_wrong() {
    let cases: [(&[&str], &str); 4] = [
        (
            &["--size", "0x100"],
            "\"0\" in \"0x100\" is not a positive whole number of pixels",
        ),
        (&["--size", "big"], "expected WIDTHxHEIGHT, e.g. 1280x720, got \"big\""),
        (
            &["--display-hz", "-5"],
            "invalid value '-5' for '--display-hz <DISPLAY_HZ>': \"-5\" is outside the accepted range, from 1/3600 (MIN_DISPLAY_HZ) to 1e6 (MAX_DISPLAY_HZ) frames per second",
        ),
        (
            &["--integrator", "rk5"],
            "unknown integrator 'rk5'; valid names are: explicit_euler",
        ),
    ];
    for (extra, message) in cases {
        let dir = scratch("bad");
        let mut args = vec!["render", &*Box::leak(scene("projectile.ron").into_boxed_str())];
        args.extend_from_slice(&[
            "--frames",
            "1",
            "--out",
            Box::leak(dir.display().to_string().into_boxed_str()),
        ]);
        args.extend_from_slice(extra);
        let output = tickwork(&args);
        assert!(!output.status.success(), "{extra:?} should fail");
        assert!(
            text(&output.stderr).contains(message),
            "{extra:?}: {}",
            text(&output.stderr)
        );
    }
}

#[test]
fn no_adapter_is_an_error_naming_the_backends_and_the_package() {
    // Metal does not exist on Linux: wgpu finds no adapter at all.
    let dir = scratch("no-adapter");
    let output = Command::new(env!("CARGO_BIN_EXE_tickwork"))
        .args(["render", &scene("projectile.ron"), "--frames", "1", "--out"])
        .arg(&dir)
        .env("WGPU_BACKEND", "metal")
        .output()
        .expect("runs");
    assert_eq!(output.status.code(), Some(1), "a clean non-zero exit, not a panic");
    let stderr = text(&output.stderr);
    assert!(
        stderr.starts_with(
            "tickwork: no graphics device to render on\n  caused by: no graphics adapter found (backends tried: Metal;"
        ),
        "{stderr}"
    );
    assert!(
        stderr.contains("apt-get install mesa-vulkan-drivers libvulkan1"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn view_without_a_display_says_so_and_what_to_do() {
    let output = Command::new(env!("CARGO_BIN_EXE_tickwork"))
        .args(["view", &scene("tops.ron")])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .expect("runs");
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        text(&output.stderr).trim_end(),
        format!(
            "tickwork: cannot show the scene {} in a window\n  caused by: ",
            scene("tops.ron")
        ) + "cannot open a window: no display (neither DISPLAY nor WAYLAND_DISPLAY is set): run it in a \
         desktop session or under `xvfb-run`, or draw frames without a window with `tickwork render`"
    );
}

/// An X server on a free display, killed when dropped.
struct Xvfb {
    child: Child,
    display: String,
}

impl Xvfb {
    fn start(width: u32, height: u32) -> Self {
        let mut child = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                &format!("{width}x{height}x24"),
                "-nolisten",
                "tcp",
                // No autorepeat: on a busy machine xdotool's press and
                // release of F1 could be far enough apart for the server to
                // repeat the press, and the panel toggled twice.
                "-r",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start Xvfb ({e}): scripts/test installs the `xvfb` package"));
        let mut number = String::new();
        BufReader::new(child.stdout.take().expect("stdout"))
            .read_line(&mut number)
            .expect("Xvfb prints its display number");
        Self {
            child,
            display: format!(":{}", number.trim()),
        }
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn screenshot(display: &str, path: &Path) {
    let status = Command::new("import")
        .args(["-display", display, "-window", "root"])
        .arg(path)
        .status()
        .unwrap_or_else(|e| panic!("cannot run ImageMagick's import ({e}): scripts/test installs `imagemagick`"));
    assert!(status.success(), "import failed");
}

#[test]
fn a_window_on_vulkan_shows_what_the_offscreen_renderer_draws() {
    window_matches_offscreen("vulkan", "tops.ron", 40);
}

#[test]
fn a_window_on_gl_shows_what_the_offscreen_renderer_draws() {
    window_matches_offscreen("gl", "tops.ron", 40);
}

#[test]
fn a_window_drawing_by_splat_shows_what_the_offscreen_renderer_draws() {
    // The fountain passes 2 000 particles within its first second: the
    // splat resolves straight into the (BGRA) surface.
    window_matches_offscreen("vulkan", "fountain.ron", 90);
}

/// Runs `scene_file` in a window on `backend` under Xvfb for `frames` frames
/// of a simulated 60 Hz display, photographs the screen, compares it with
/// the same off-screen frame, then resizes the window (down to 1x1 and back)
/// and checks it is still running.
fn window_matches_offscreen(backend: &str, scene_file: &str, frames: u32) {
    let frames_arg = frames.to_string();
    let (width, height) = (480, 270);
    let dir = scratch(&format!("window-{backend}-{scene_file}"));
    let xvfb = Xvfb::start(width, height);
    let size = format!("{width}x{height}");
    let mut view = Command::new(env!("CARGO_BIN_EXE_tickwork"))
        .args([
            "view",
            &scene(scene_file),
            "--size",
            &size,
            "--frames",
            &frames_arg,
            // The screen is compared with the off-screen frame, which never
            // has the panel.
            "--no-panel",
            // Long enough for any machine: the test closes the window itself.
            "--hold",
            "600",
        ])
        .args(["--display-hz", "60", "--screenshots"])
        .arg(&dir)
        .env("DISPLAY", &xvfb.display)
        .env("WGPU_BACKEND", backend)
        .env_remove("WAYLAND_DISPLAY")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("tickwork view starts");
    let mut stdout = BufReader::new(view.stdout.take().expect("stdout"));
    let deadline = Instant::now() + Duration::from_secs(120);
    let mut line = String::new();
    while !line.contains(&format!("frame {frames} shown")) {
        line.clear();
        if stdout.read_line(&mut line).expect("read") == 0 || Instant::now() > deadline {
            let _ = view.kill();
            let mut stderr = String::new();
            let _ = view.stderr.take().expect("stderr").read_to_string(&mut stderr);
            panic!("the window never showed frame {frames}: {stderr}");
        }
    }
    // The window says "shown" once the held frame has been presented twice,
    // so it is on the screen: photograph the screen.
    let shot = dir.join("window.png");
    screenshot(&xvfb.display, &shot);
    let window = image::open(&shot).expect("screenshot").to_rgba8();
    // F12 writes a screenshot of the window's frame (through XTEST, to the
    // focused window, as a real key press).
    let status = Command::new("xdotool")
        .args(["search", "--name", "^Tickwork", "windowfocus", "--sync", "key", "F12"])
        .env("DISPLAY", &xvfb.display)
        .status()
        .unwrap_or_else(|e| panic!("cannot run xdotool ({e}): scripts/test installs `xdotool`"));
    assert!(status.success(), "xdotool key F12");
    let mut line = String::new();
    while !line.starts_with("tickwork: screenshot ") {
        line.clear();
        if stdout.read_line(&mut line).expect("read") == 0 || Instant::now() > deadline {
            panic!("F12 wrote no screenshot");
        }
    }
    let f12 = image::open(line.trim_start_matches("tickwork: screenshot ").trim())
        .expect("the F12 screenshot is a PNG")
        .to_rgba8();
    let f12_vs_screen = compare(&f12, &window, Tolerance::default()).expect("the window's size");
    assert!(
        f12_vs_screen.fraction() < 0.01,
        "F12 screenshot differs from the screen: {f12_vs_screen:?}"
    );
    // Resizing, even to a single pixel, neither crashes nor errors.
    for size in [["1", "1"], ["200", "120"], [&*width.to_string(), &*height.to_string()]] {
        let status = Command::new("xdotool")
            .args(["search", "--name", "^Tickwork", "windowsize", size[0], size[1]])
            .env("DISPLAY", &xvfb.display)
            .status()
            .unwrap_or_else(|e| panic!("cannot run xdotool ({e}): scripts/test installs `xdotool`"));
        assert!(status.success(), "xdotool windowsize {size:?}");
        // The window says when it has presented at the new size (a failure
        // ends its output, and the wait reports its standard error).
        wait_for_line(&mut view, &mut stdout, &format!("resized to {}x{}", size[0], size[1]));
    }
    let _ = view.kill();
    let _ = view.wait();
    // The same frames off-screen.
    let out = dir.join("offscreen");
    let output = Command::new(env!("CARGO_BIN_EXE_tickwork"))
        .args([
            "render",
            &scene(scene_file),
            "--size",
            &size,
            "--frames",
            &frames_arg,
            "--display-hz",
            "60",
            "--out",
        ])
        .arg(&out)
        .env("WGPU_BACKEND", backend)
        .output()
        .expect("runs");
    assert!(output.status.success(), "{}", text(&output.stderr));
    let offscreen = image::open(out.join(format!("frame_{:05}.png", frames - 1)))
        .expect("frame")
        .to_rgba8();
    let tolerance = Tolerance {
        channel: 32,
        max_fraction: 0.01,
    };
    let comparison = compare(&window, &offscreen, tolerance).expect("same size");
    assert!(
        comparison.fraction() <= tolerance.max_fraction,
        "window screenshot {} differs from the off-screen frame: {comparison:?}",
        shot.display()
    );
    // And it is not an empty screen: the frame has drawn pixels.
    let drawn = window.pixels().filter(|p| p.0[0] > 100 || p.0[1] > 100).count();
    assert!(drawn > 200, "only {drawn} drawn pixels in the window");
}

fn lander_recording() -> String {
    root()
        .join("assets/recordings/lander_land_then_crash.ron")
        .display()
        .to_string()
}

/// Starts the lander in a window on `display` with `args`.
fn lander_window(display: &str, args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_lander"))
        .args(args)
        .env("DISPLAY", display)
        .env("WGPU_BACKEND", "vulkan")
        .env_remove("WAYLAND_DISPLAY")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the lander starts")
}

/// Reads `child`'s output until a line contains `wanted`; fails with its
/// standard error after two minutes or if it exits.
fn wait_for_line(child: &mut Child, stdout: &mut impl BufRead, wanted: &str) -> String {
    let deadline = Instant::now() + Duration::from_secs(120);
    let mut line = String::new();
    let mut seen = String::new();
    while !line.contains(wanted) {
        line.clear();
        if stdout.read_line(&mut line).expect("read") == 0 || Instant::now() > deadline {
            let _ = child.kill();
            let mut stderr = String::new();
            let _ = child.stderr.take().expect("stderr").read_to_string(&mut stderr);
            panic!("no line with {wanted:?}; standard output:\n{seen}\nstandard error:\n{stderr}");
        }
        seen.push_str(&line);
    }
    line
}

fn xdotool(display: &str, args: &[&str]) {
    let status = Command::new("xdotool")
        .args(args)
        .env("DISPLAY", display)
        .status()
        .unwrap_or_else(|e| panic!("cannot run xdotool ({e}): scripts/test installs `xdotool`"));
    assert!(status.success(), "xdotool {args:?}");
}

#[test]
fn a_game_window_draws_the_control_panel_over_the_frame_and_f1_hides_it() {
    let (width, height) = (640, 360);
    let size = format!("{width}x{height}");
    let dir = scratch("game-window");
    let xvfb = Xvfb::start(width, height);
    // A replay makes the window's frames reproducible off-screen.
    let recording = lander_recording();
    let args = [
        "--replay",
        &recording,
        "--frames",
        "240",
        "--display-hz",
        "60",
        "--hold",
        "120",
        "--size",
        &size,
        // A game's panel is off unless asked for.
        "--panel",
    ];
    // The same frames off-screen first, so nothing slow runs while the
    // window is up.
    let out = dir.join("offscreen");
    let output = Command::new(env!("CARGO_BIN_EXE_lander"))
        .args([
            "--headless",
            "--replay",
            &recording,
            "--frames",
            "240",
            "--size",
            &size,
            "--out",
        ])
        .arg(&out)
        .output()
        .expect("runs");
    assert!(output.status.success(), "{}", text(&output.stderr));
    let offscreen = image::open(out.join("frame_00239.png")).expect("frame").to_rgba8();
    let tolerance = Tolerance {
        channel: 32,
        max_fraction: 0.01,
    };
    let mut game = lander_window(&xvfb.display, &args);
    let mut stdout = BufReader::new(game.stdout.take().expect("stdout"));
    // Each line is said once the change has been presented twice: on screen.
    wait_for_line(&mut game, &mut stdout, "frame 240 shown");
    let with_panel = dir.join("with_panel.png");
    screenshot(&xvfb.display, &with_panel);
    // F1 hides the panel. The window says each toggle once it is on screen;
    // xdotool sometimes delivers one press twice on a busy machine (the
    // window then says "hidden" and "shown"), so press again until it says
    // the panel is hidden: driven by the window's lines, never by time.
    let mut hidden = false;
    for _ in 0..3 {
        xdotool(
            &xvfb.display,
            &[
                "search",
                "--limit",
                "1",
                "--name",
                "^Tickwork",
                "windowfocus",
                "--sync",
                "key",
                "F1",
            ],
        );
        let line = wait_for_line(&mut game, &mut stdout, "(F1) and presented");
        if line.contains("panel hidden") {
            hidden = true;
            break;
        }
    }
    assert!(hidden, "three F1 presses never left the panel hidden");
    let without_panel = dir.join("without_panel.png");
    screenshot(&xvfb.display, &without_panel);
    let hidden = image::open(&without_panel).expect("screenshot").to_rgba8();
    let comparison = compare(&hidden, &offscreen, tolerance).expect("same size");
    let _ = game.kill();
    let _ = game.wait();
    assert!(
        comparison.fraction() <= tolerance.max_fraction,
        "with the panel hidden, the window {} shows the off-screen frame: {comparison:?}",
        without_panel.display()
    );
    let shown = image::open(&with_panel).expect("screenshot").to_rgba8();
    let comparison = compare(&shown, &offscreen, tolerance).expect("same size");
    assert!(
        comparison.fraction() > 0.03,
        "the panel covers part of the window {}: {comparison:?}",
        with_panel.display()
    );
}

#[test]
fn keys_pressed_in_a_game_window_reach_its_fixed_steps_and_the_recording() {
    let dir = scratch("game-keys");
    let xvfb = Xvfb::start(480, 270);
    let record = dir.join("keys.ron");
    let record_arg = record.display().to_string();
    // No frame limit: the window runs until the keys below close it, so
    // it cannot close before they arrive however fast its frames go.
    let args = ["--record", &record_arg, "--display-hz", "60", "--size", "480x270"];
    let mut game = lander_window(&xvfb.display, &args);
    let mut stdout = BufReader::new(game.stdout.take().expect("stdout"));
    // Waits for the window, then holds Up for half a second, and taps Left.
    xdotool(
        &xvfb.display,
        &[
            "search",
            "--sync",
            "--name",
            "^Tickwork",
            "windowfocus",
            "--sync",
            "keydown",
            "Up",
            "sleep",
            "0.5",
            "keyup",
            "Up",
            "key",
            "Left",
            // The runner's key: the window closes and saves the recording.
            "key",
            "Escape",
        ],
    );
    let line = wait_for_line(&mut game, &mut stdout, "recorded");
    assert!(line.contains(&record_arg), "{line}");
    let status = game.wait().expect("exits");
    assert!(status.success(), "Escape closes the window");
    let recording = tickwork_engine::app::Recording::load(&record).expect("the recording loads");
    let held: Vec<u64> = recording
        .inputs
        .iter()
        .filter(|(_, input)| input.held(tickwork_engine::app::Key::Up))
        .map(|(tick, _)| *tick)
        .collect();
    assert!(!held.is_empty(), "Up was held: {recording:?}");
    assert!(
        recording
            .inputs
            .iter()
            .any(|(_, input)| input.pressed(tickwork_engine::app::Key::Left)),
        "Left was pressed: {recording:?}"
    );
    assert!(
        held.iter().all(|&tick| tick < recording.ticks),
        "the recording's {} ticks cover the keys: {recording:?}",
        recording.ticks
    );
}

#[test]
fn a_scene_window_with_the_control_panel_runs_and_closes_after_its_frames() {
    let xvfb = Xvfb::start(480, 270);
    let output = Command::new(env!("CARGO_BIN_EXE_tickwork"))
        .args([
            "view",
            &scene("kepler.ron"),
            "--panel",
            "--size",
            "480x270",
            "--frames",
            "30",
        ])
        .args(["--display-hz", "60"])
        .env("DISPLAY", &xvfb.display)
        .env("WGPU_BACKEND", "vulkan")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("runs");
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert!(
        text(&output.stdout).contains("showed 30 frames"),
        "{}",
        text(&output.stdout)
    );
}

/// The checksum in a side's "the match ended at tick 300: checksum X;" line.
fn match_checksum(stdout: &str) -> String {
    stdout
        .lines()
        .find_map(|l| l.strip_prefix("tickwork: rally: the match ended at tick 300: checksum "))
        .and_then(|rest| rest.split(';').next())
        .unwrap_or_else(|| panic!("no end of match in:\n{stdout}"))
        .to_owned()
}

#[test]
fn a_match_played_in_a_window_ends_where_its_headless_opponent_does() {
    // The host in a window under Xvfb, the joiner headless, each from its
    // script: the window's clock, frame pacing and rendering change when
    // ticks run, never what they compute.
    let xvfb = Xvfb::start(320, 180);
    let script = |side: &str| root().join(format!("assets/recordings/rally_{side}.ron"));
    let support::Host {
        child: host,
        output: mut host_out,
        first,
        port,
    } = support::start_host(
        Command::new(env!("CARGO_BIN_EXE_rally"))
            .args(["--host", "0", "--frames", "300", "--size", "320x180", "--script"])
            .arg(script("left"))
            .env("DISPLAY", &xvfb.display)
            .env_remove("WAYLAND_DISPLAY")
            .stdout(Stdio::piped())
            .stderr(Stdio::piped()),
    );
    let joiner = Command::new(env!("CARGO_BIN_EXE_rally"))
        .args([
            "--headless",
            "--frames",
            "300",
            "--join",
            &format!("127.0.0.1:{port}"),
            "--script",
        ])
        .arg(script("right"))
        .output()
        .expect("the joiner runs");
    let mut hosted = first;
    host_out.read_to_string(&mut hosted).expect("the host's output");
    let host = host.wait_with_output().expect("the host ends");
    let joined = String::from_utf8_lossy(&joiner.stdout);
    assert!(
        host.status.success(),
        "{hosted}\n{}",
        String::from_utf8_lossy(&host.stderr)
    );
    assert!(
        joiner.status.success(),
        "{joined}\n{}",
        String::from_utf8_lossy(&joiner.stderr)
    );
    assert_eq!(match_checksum(&hosted), match_checksum(&joined), "{hosted}\n{joined}");
}

#[test]
fn the_platformer_runs_in_a_window_and_plays_itself() {
    let xvfb = Xvfb::start(480, 270);
    let output = Command::new(env!("CARGO_BIN_EXE_platformer"))
        .args([
            "--autopilot",
            "--size",
            "480x270",
            "--frames",
            "120",
            "--display-hz",
            "60",
        ])
        .env("DISPLAY", &xvfb.display)
        .env("WGPU_BACKEND", "vulkan")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("runs");
    let stdout = text(&output.stdout);
    assert!(output.status.success(), "{stdout}\n{}", text(&output.stderr));
    // 120 frames of a simulated 60 Hz display: two seconds of play, the
    // gap jumped and two coins taken, in a window.
    assert!(
        stdout.contains("platformer: stopped before the flag with 2 coins and 0 deaths"),
        "{stdout}"
    );
}
