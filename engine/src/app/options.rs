//! [`run`]: a game in a window when a display is available, off-screen
//! otherwise, with the command-line options every demo shares
//! ([`RunOptions`], a clap `Args` to flatten into a game's own parser).

use std::path::{Path, PathBuf};

use clap::Args;

use super::game::Game;
use super::session::{GameSession, SessionOptions};
use super::stage::Settings;
use super::stage::Stage;
use super::window::display_available;
use super::{FrameOutput, OffscreenRun, RunError, WindowOptions, run_window};
use crate::clock::FixedCadence;
use crate::input::Recording;
use crate::render::{Gpu, RendererConfig};

/// The options every game shares on the command line.
#[derive(Args, Clone, Debug, PartialEq)]
pub struct RunOptions {
    /// Integrator by registry name (see `tickwork integrators`); a game that
    /// races integrators takes a comma-separated list.
    #[arg(long)]
    pub integrator: Option<String>,
    /// Fixed steps per second (default: the game's, usually 60).
    #[arg(long, value_parser = positive_f64, allow_hyphen_values = true)]
    pub hz: Option<f64>,
    /// Simulated seconds per real second.
    #[arg(long, default_value_t = 1.0, value_parser = positive_f64, allow_hyphen_values = true)]
    pub time_scale: f64,
    /// Draw off-screen even when a display is available.
    #[arg(long)]
    pub headless: bool,
    /// Frames to run (default: until the window is closed; 300 off-screen,
    /// or as many as a replayed recording needs).
    #[arg(long, allow_negative_numbers = true)]
    pub frames: Option<u64>,
    /// Off-screen: directory for the PNG frames (default: a new
    /// `tickwork-out/<game>` directory).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Off-screen: the animated GIF (default: `<game>.gif` in the frames'
    /// directory).
    #[arg(long)]
    pub gif: Option<PathBuf>,
    /// Window or frame size, WIDTHxHEIGHT (default: 1280x720 in a window,
    /// 640x360 off-screen).
    #[arg(long, value_parser = parse_size, allow_hyphen_values = true)]
    pub size: Option<(u32, u32)>,
    /// Seed of the worlds' random generators.
    #[arg(long, default_value_t = 0, allow_negative_numbers = true)]
    pub seed: u64,
    /// Record the keys of every tick to this file (RON) when the run ends.
    #[arg(long, conflicts_with = "replay")]
    pub record: Option<PathBuf>,
    /// Replay a recording instead of the keyboard, with its rate and seed.
    #[arg(long)]
    pub replay: Option<PathBuf>,
    /// Frame durations from a simulated display at this rate (default: the
    /// real clock in a window, 60 Hz off-screen).
    #[arg(long, value_parser = display_hz, allow_hyphen_values = true)]
    pub display_hz: Option<f64>,
    /// Window: after `--frames`, keep showing the last frame this many
    /// seconds before closing (for a screenshot from outside).
    #[arg(long, default_value_t = 0.0, value_parser = non_negative_seconds, allow_hyphen_values = true)]
    pub hold: f64,
    /// Overwrite existing frames, GIF or recording.
    #[arg(long)]
    pub force: bool,
    /// Start with the control panel shown (F1 toggles it; default: as the
    /// game says, hidden for games, shown for the lab's demos).
    #[arg(long, conflicts_with = "no_panel")]
    pub panel: bool,
    /// Start with the control panel hidden (F1 toggles it).
    #[arg(long)]
    pub no_panel: bool,
}

impl Default for RunOptions {
    fn default() -> Self {
        Self {
            integrator: None,
            hz: None,
            time_scale: 1.0,
            headless: false,
            frames: None,
            out: None,
            gif: None,
            size: None,
            seed: 0,
            record: None,
            replay: None,
            display_hz: None,
            hold: 0.0,
            force: false,
            panel: false,
            no_panel: false,
        }
    }
}

/// A command line of only the shared options.
#[derive(clap::Parser)]
#[command(
    about = "Runs a Tickwork game: in a window when a display is available, else off-screen into PNG frames and \
             a GIF.",
    after_help = "Window keys: F1 control panel, P pause, . single step, +/- time scale, Tab or 1-9 integrator, \
                  F5 restart, F12 screenshot, Escape quit; the arrows, Space, Enter and letters go to the game."
)]
struct SharedCommandLine {
    #[command(flatten)]
    options: RunOptions,
}

impl RunOptions {
    /// Parses the program's command line (exits with clap's message and
    /// usage for bad options, `--help` lists them). Games with options of
    /// their own flatten [`RunOptions`] into their parser instead.
    #[must_use]
    pub fn from_args() -> Self {
        <SharedCommandLine as clap::Parser>::parse().options
    }
}

/// Parses `WIDTHxHEIGHT` (`1280x720`) into positive pixel counts.
///
/// # Errors
/// A message quoting the text for anything else.
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT, e.g. 1280x720, got {text:?}"))?;
    let side = |s: &str| {
        s.trim()
            .parse::<u32>()
            .ok()
            .filter(|&v| v > 0)
            .ok_or_else(|| format!("{s:?} in {text:?} is not a positive whole number of pixels"))
    };
    Ok((side(w)?, side(h)?))
}

/// Parses a finite number of seconds, 0 or more (a command-line value
/// parser: the error names the value; clap adds the option).
///
/// # Errors
/// A message naming the value.
pub fn non_negative_seconds(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("{text:?} is not a finite number of seconds, 0 or more")),
    }
}

/// The slowest simulated display: a frame an hour (the clock's longest frame).
pub const MIN_DISPLAY_HZ: f64 = 1.0 / crate::clock::FixedClock::MAX_FRAME_TIME;
/// The fastest simulated display: a million frames a second (a microsecond,
/// the shortest fixed step; `1e300` once made every frame last no time).
pub const MAX_DISPLAY_HZ: f64 = crate::clock::Rate::MAX_HZ;

/// Parses a simulated display's rate (`--display-hz`), within
/// [`MIN_DISPLAY_HZ`] and [`MAX_DISPLAY_HZ`].
///
/// # Errors
/// A message naming the value and the accepted range.
pub fn display_hz(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if (MIN_DISPLAY_HZ..=MAX_DISPLAY_HZ).contains(&v) => Ok(v),
        Ok(_) => Err(format!(
            "{text:?} is outside the accepted range, from 1/3600 (MIN_DISPLAY_HZ) to 1e6 (MAX_DISPLAY_HZ) \
             frames per second"
        )),
        Err(_) => Err(format!("{text:?} is not a number of frames per second")),
    }
}

fn positive_f64(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("{text:?} is not a positive, finite number")),
    }
}

/// What a run did.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSummary {
    /// Whether it ran in a window (else off-screen).
    pub windowed: bool,
    /// Frames shown or drawn.
    pub frames: u64,
    /// Fixed steps run.
    pub ticks: u64,
    /// Off-screen: the frames' directory.
    pub out: Option<PathBuf>,
    /// Off-screen: the GIF.
    pub gif: Option<PathBuf>,
    /// The recording written, if any.
    pub recording: Option<PathBuf>,
    /// The game's outcome line, if it has one.
    pub outcome: Option<String>,
}

/// The renderer settings [`run`] draws a stage's frames `height` pixels
/// tall with (for a test that draws a game as `run` does): the stage's
/// background, and its HUD size from 540 px up, shrinking with smaller
/// frames down to 10/16 of it, so a legend that fits a window fits a small
/// GIF.
#[must_use]
pub fn renderer_config(stage: &Stage, height: u32) -> RendererConfig {
    RendererConfig {
        background: stage.background,
        hud_size: stage.hud_size * (height as f32 / 540.0).clamp(10.0 / 16.0, 1.0),
        ..RendererConfig::default()
    }
}

/// A title as a file name: lower-case ASCII letters, digits and dashes.
fn slug(title: &str) -> String {
    title
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect()
}

/// `tickwork-out/<slug>`, or `-2`, `-3`, ... if that holds earlier frames.
fn fresh_output_dir(title: &str) -> PathBuf {
    let slug = slug(title);
    let base = Path::new("tickwork-out");
    (1..)
        .map(|k| {
            if k == 1 {
                base.join(&slug)
            } else {
                base.join(format!("{slug}-{k}"))
            }
        })
        .find(|dir| !dir.exists())
        .unwrap_or_else(|| base.join(&slug))
}

/// Whether a file can be written at `path`: not a directory, in a directory
/// that exists, and new unless `overwrite`.
fn check_output_file(path: &std::path::Path, overwrite: bool) -> Result<(), RunError> {
    let io = |message: String| RunError::Io {
        path: path.to_path_buf(),
        message,
    };
    if path.is_dir() {
        return Err(io("is a directory; name a file".into()));
    }
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty())
        && !parent.is_dir()
    {
        return Err(io(format!("the directory {} does not exist", parent.display())));
    }
    if path.exists() && !overwrite {
        return Err(RunError::Exists(path.to_path_buf()));
    }
    Ok(())
}

/// The most frames an off-screen run draws: a million (over four hours at
/// 60 frames per second; `--frames 100000000` once stalled the run).
pub const MAX_OFFSCREEN_FRAMES: u64 = 1_000_000;

/// Runs `game` with `options`: in a window when a display is available
/// (and `--headless` is not given), else off-screen into PNG frames and a
/// GIF, saying where. Both go through [`GameSession`]'s per-frame path.
/// Prints where files went and the game's outcome. Call it from `main`
/// before starting threads of your own: it may quiet a Vulkan layer
/// through the environment ([`quiet_device_select_layer`](crate::render::quiet_device_select_layer)).
///
/// # Errors
/// [`RunError`] with what went wrong: a bad option or recording, no GPU
/// adapter, a failed step, a file that exists (without `--force`).
pub fn run<G: Game>(game: G, options: RunOptions) -> Result<RunSummary, RunError> {
    // Before any thread starts (a game's `main` calls `run` first).
    crate::render::quiet_device_select_layer();
    // Parallel steps from this thread then allocate nothing. An existing
    // pool (the game used rayon first) is fine: steps run on it.
    let _ = crate::threads::join_thread_pool();
    // Where the recording goes is checked before the run: a run that failed
    // to save at its end lost all the input it had taken.
    if let Some(path) = &options.record {
        check_output_file(path, options.force)?;
    }
    // So are the GIF, the frames' directory and their count.
    if let Some(path) = &options.gif {
        check_output_file(path, options.force)?;
    }
    let windowed = !options.headless && display_available();
    if !windowed {
        crate::app::offscreen::check_output(options.frames.unwrap_or(0), options.out.as_deref())?;
    }
    let replay = options.replay.as_deref().map(Recording::load).transpose()?;
    let replay_ticks = replay.as_ref().map(|r| (r.ticks, r.hz));
    let mut session = GameSession::new(
        game,
        SessionOptions {
            settings: Settings {
                integrator: options.integrator.clone(),
                seed: options.seed,
            },
            hz: options.hz,
            time_scale: options.time_scale,
            record: options.record.clone(),
            replay,
            overwrite: options.force,
        },
    )?;
    let title = session.game().title().to_owned();
    let mut summary = RunSummary {
        windowed,
        frames: 0,
        ticks: 0,
        out: None,
        gif: None,
        recording: None,
        outcome: None,
    };
    let shown = show(&mut session, &options, replay_ticks, &mut summary);
    // The input so far is kept even when the run failed (a recording of the
    // failure is what a bug report needs).
    summary.ticks = crate::app::FrameSource::ticks(&session);
    summary.recording = session.save_recording()?;
    if let Some(path) = &summary.recording {
        println!(
            "tickwork: recorded {} ticks of input to {}",
            summary.ticks,
            path.display()
        );
    }
    shown?;
    summary.outcome = session.outcome();
    if let Some(outcome) = &summary.outcome {
        println!("{title}: {outcome}");
    }
    Ok(summary)
}

/// The window or off-screen part of [`run`].
fn show<G: Game>(
    session: &mut GameSession<G>,
    options: &RunOptions,
    replay_ticks: Option<(u64, f64)>,
    summary: &mut RunSummary,
) -> Result<(), RunError> {
    let title = session.game().title().to_owned();
    if summary.windowed {
        let (width, height) = options.size.unwrap_or((1280, 720));
        let panel = !options.no_panel && (options.panel || session.stage().panel);
        let renderer = renderer_config(session.stage(), height);
        let window = run_window(
            session,
            WindowOptions {
                width,
                height,
                frames: options.frames,
                hold_seconds: options.hold,
                display_hz: options.display_hz,
                screenshot_dir: PathBuf::from("."),
                panel,
                renderer,
                ..WindowOptions::default()
            },
        )?;
        summary.frames = window.frames;
    } else {
        let (width, height) = options.size.unwrap_or((640, 360));
        let display_hz = options.display_hz.unwrap_or(60.0);
        let frames = match (options.frames, replay_ticks) {
            (Some(frames), _) => frames,
            // Enough frames for every recorded tick: steps per frame are
            // hz * time scale / display rate.
            (None, Some((ticks, hz))) => {
                let needed = (ticks as f64 * display_hz / (hz * options.time_scale)).ceil() + 1.0;
                if needed.is_nan() || needed > MAX_OFFSCREEN_FRAMES as f64 {
                    return Err(RunError::Io {
                        path: options.replay.clone().unwrap_or_default(),
                        message: format!(
                            "replaying {ticks} ticks at {hz} Hz needs {} frames at {display_hz} frames per second, \
                             past the limit of {MAX_OFFSCREEN_FRAMES} off-screen frames; replay with a higher \
                             --time-scale or a lower --display-hz, or pass --frames",
                            crate::clock::Number(needed)
                        ),
                    });
                }
                needed as u64
            }
            (None, None) => 300,
        };
        let out = options.out.clone().unwrap_or_else(|| fresh_output_dir(&title));
        let gif = options
            .gif
            .clone()
            .or_else(|| Some(out.join(format!("{}.gif", slug(&title)))));
        let gpu = Gpu::headless()?;
        let mut runner = OffscreenRun::new(&gpu, width, height, renderer_config(session.stage(), height))?;
        println!(
            "tickwork: {title}: no display{}; drawing {frames} frames of {width}x{height} off-screen on {}",
            if options.headless { " wanted (--headless)" } else { "" },
            gpu.describe()
        );
        let done = runner.run(
            session,
            &mut FixedCadence::hz(display_hz),
            frames,
            &FrameOutput {
                dir: Some(out.clone()),
                gif: gif.clone(),
                overwrite: options.force,
                hud: true,
            },
            &mut |_| {},
        )?;
        summary.frames = done.frames;
        println!(
            "tickwork: wrote {} frames to {}/ and the GIF {}",
            done.frames,
            out.display(),
            gif.as_deref().map_or_else(String::new, |g| g.display().to_string())
        );
        summary.out = Some(out);
        summary.gif = gif;
    }
    Ok(())
}

/// The exit code of a run for a game's `main`: success, or the error
/// printed to standard error (`error: ...`) and failure.
pub fn exit_code(result: Result<RunSummary, RunError>) -> std::process::ExitCode {
    match result {
        Ok(_) => std::process::ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error}");
            std::process::ExitCode::FAILURE
        }
    }
}
