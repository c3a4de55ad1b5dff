//! [`CliError`]: why a `tickwork` subcommand stopped, with the engine's
//! error kept as its source; and [`report`], the lines the binary prints
//! for it (the error, then each cause).

use std::error::Error;
use std::fmt::{self, Write as _};
use std::io;
use std::path::PathBuf;

use tickwork_engine::app::{PlaybackError, RunError};
use tickwork_engine::clock::{ClockError, Number, Rate};
use tickwork_engine::render::RenderError;
use tickwork_engine::{SceneError, SimulationError};
use tickwork_integrators::UnknownMethod;

use crate::lab::LabError;

/// Why a subcommand of `tickwork` stopped. Each variant says what the
/// command was doing (the option, the file); the engine's error that made
/// it stop is its [`source`](Error::source), which says where and why (the
/// line and field of a scene, the accepted range of a rate).
#[derive(Debug)]
pub enum CliError {
    /// The scene file could not be read or parsed: the source's `file` is
    /// the path as given, with the line, field and fault.
    SceneLoad(SceneError),
    /// The scene was read, but no world could be built from it.
    SceneBuild(SceneError),
    /// The scene's own rate is not one the fixed clock can run at.
    SceneRate(SceneError),
    /// The scene could not be set up to be drawn (`render`, `view`).
    Playback {
        /// The scene file as given.
        path: PathBuf,
        /// What the engine refused (boxed: it is large).
        source: Box<PlaybackError>,
    },
    /// `--integrator` names no registered method.
    Integrator(UnknownMethod),
    /// `--hz` or `--dt` is not a step the fixed clock accepts.
    Rate {
        /// `--hz` or `--dt`.
        option: &'static str,
        /// The value given.
        value: f64,
        /// The accepted range.
        source: ClockError,
    },
    /// `--every 0`: a trace of every 0th step.
    EveryZero,
    /// `--steps` past the steps one run may take.
    TooManySteps {
        /// The steps asked for.
        steps: u64,
        /// The most a run may take.
        limit: u64,
    },
    /// `--until` a time that is more steps at the rate than one run may take.
    TooLong {
        /// The time asked for, in seconds.
        seconds: f64,
        /// The steps that is at `rate`.
        steps: f64,
        /// The fixed rate.
        rate: Rate,
        /// The most a run may take.
        limit: u64,
    },
    /// `--until` a time that is not finite or is negative.
    BadUntil(f64),
    /// `render --frames 0`: nothing would be drawn.
    NoFrames,
    /// An output option names a directory where a file is wanted.
    IsDirectory {
        /// The option (`--trace`, `--gif`).
        option: &'static str,
        /// The directory.
        path: PathBuf,
        /// What to name instead ("a file", "a .gif file").
        wanted: &'static str,
    },
    /// An output file's directory does not exist.
    MissingDirectory {
        /// The option (`--trace`).
        option: &'static str,
        /// The file.
        path: PathBuf,
        /// Its directory, which does not exist.
        parent: PathBuf,
    },
    /// An output file exists and `--force` was not given.
    Exists(PathBuf),
    /// The trace file could not be created.
    TraceCreate {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: io::Error,
    },
    /// The trace file could not be written.
    TraceWrite {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: io::Error,
    },
    /// A step of the headless run failed (non-finite state, an integrator
    /// that could not step).
    Simulation {
        /// The scene file as given.
        path: PathBuf,
        /// Which step failed, and why.
        source: SimulationError,
    },
    /// No graphics device to render on.
    Gpu(RenderError),
    /// The GPU step cannot take the scene (or failed).
    GpuStep(tickwork_engine::gpu_step::GpuStepError),
    /// The off-screen frames could not be set up (size, GPU memory).
    RenderSetup {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
        /// What the engine refused (boxed: it is large).
        source: Box<RunError>,
    },
    /// Rendering off-screen stopped (an output that exists, a file that
    /// cannot be written, a step that failed).
    Render {
        /// The scene file as given.
        path: PathBuf,
        /// Why it stopped (boxed: it is large).
        source: Box<RunError>,
    },
    /// The window could not be opened, or its run stopped.
    Window {
        /// The scene file as given.
        path: PathBuf,
        /// Why (no display, no adapter, a step that failed; boxed: it is
        /// large).
        source: Box<RunError>,
    },
    /// The listing or summary could not be written to the output.
    Output(io::Error),
    /// `tickwork lab` failed: shown as the [`LabError`] itself (its message
    /// and its source), since the lab's messages name the option or file.
    Lab(LabError),
    /// `tickwork new` or `tickwork web` stopped: shown as the
    /// [`WebError`](super::web::WebError) itself, which says what to change.
    Web(super::web::WebError),
    /// `tickwork signal` could not listen or serve: what failed, and why.
    Signal(String),
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::SceneLoad(e) => write!(f, "cannot load the scene {}", e.file),
            Self::SceneBuild(e) => write!(f, "cannot build a world from the scene {}", e.file),
            Self::SceneRate(e) => write!(f, "cannot run the scene {} at its rate", e.file),
            Self::Playback { path, .. } => write!(f, "cannot play the scene {}", path.display()),
            Self::Integrator(e) => write!(f, "--integrator {}: no such method", e.name),
            Self::Rate { option, value, .. } => {
                write!(f, "{option} {}: not a step the fixed clock accepts", Number(*value))
            }
            Self::EveryZero => f.write_str("--every: must be at least 1"),
            Self::TooManySteps { steps, limit } => {
                write!(
                    f,
                    "--steps: {steps} steps, past the limit of {limit} steps a run; run fewer"
                )
            }
            Self::TooLong {
                seconds,
                steps,
                rate,
                limit,
            } => write!(
                f,
                "--until: {} s is {} steps at {rate}, past the limit of {limit} steps a run; \
                 simulate less time, or pass --steps",
                Number(*seconds),
                Number(*steps)
            ),
            Self::BadUntil(t) => write!(f, "--until: {t} is not a finite time, not negative"),
            Self::NoFrames => f.write_str("--frames: 0 frames; pass at least 1"),
            Self::IsDirectory { option, path, wanted } => {
                write!(f, "{option}: {} is a directory; name {wanted}", path.display())
            }
            Self::MissingDirectory { option, path, parent } => write!(
                f,
                "{option}: {}: the directory {} does not exist",
                path.display(),
                parent.display()
            ),
            Self::Exists(path) => write!(f, "{}: exists; pass --force to overwrite it", path.display()),
            Self::TraceCreate { path, .. } => write!(f, "cannot create the trace file {}", path.display()),
            Self::TraceWrite { path, .. } => write!(f, "cannot write the trace file {}", path.display()),
            Self::Simulation { path, .. } => write!(f, "the simulation of {} stopped", path.display()),
            Self::Gpu(_) => f.write_str("no graphics device to render on"),
            Self::GpuStep(e) => write!(f, "--gpu: {e}"),
            Self::RenderSetup { width, height, .. } => {
                write!(f, "cannot set up {width}x{height} off-screen frames")
            }
            Self::Render { path, .. } => write!(f, "cannot render the scene {}", path.display()),
            Self::Window { path, .. } => write!(f, "cannot show the scene {} in a window", path.display()),
            Self::Output(_) => f.write_str("cannot write the output"),
            Self::Lab(e) => e.fmt(f),
            Self::Web(e) => e.fmt(f),
            Self::Signal(why) => write!(f, "tickwork signal: {why}"),
        }
    }
}

impl Error for CliError {
    fn source(&self) -> Option<&(dyn Error + 'static)> {
        match self {
            Self::SceneLoad(e) | Self::SceneBuild(e) | Self::SceneRate(e) => Some(e),
            Self::Playback { source, .. } => Some(source.as_ref()),
            Self::Integrator(e) => Some(e),
            Self::Rate { source, .. } => Some(source),
            Self::TraceCreate { source, .. } | Self::TraceWrite { source, .. } => Some(source),
            Self::Simulation { source, .. } => Some(source),
            Self::Gpu(e) => Some(e),
            Self::RenderSetup { source, .. } | Self::Render { source, .. } | Self::Window { source, .. } => {
                Some(source.as_ref())
            }
            Self::Output(e) => Some(e),
            // Transparent: the lab's message is shown as this error's own.
            Self::Lab(e) => e.source(),
            Self::Web(e) => e.source(),
            Self::EveryZero
            | Self::Signal(_)
            | Self::TooManySteps { .. }
            | Self::TooLong { .. }
            | Self::BadUntil(_)
            | Self::NoFrames
            | Self::IsDirectory { .. }
            | Self::MissingDirectory { .. }
            | Self::Exists(_)
            | Self::GpuStep(_) => None,
        }
    }
}

impl From<UnknownMethod> for CliError {
    fn from(e: UnknownMethod) -> Self {
        Self::Integrator(e)
    }
}

impl From<LabError> for CliError {
    fn from(e: LabError) -> Self {
        Self::Lab(e)
    }
}

/// The text the `tickwork` binary prints for `error`: `tickwork: ` and the
/// error, then a `  caused by: ` line for each source in turn, so the
/// command's context and the engine's details (file, line, field, value)
/// are both shown. A source whose message only repeats the line above (a
/// wrapper that forwards its source's message) is left out.
#[must_use]
pub fn report(error: &(dyn Error + 'static)) -> String {
    let mut text = format!("tickwork: {error}");
    let mut last = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        let line = cause.to_string();
        if line != last {
            let _ = write!(text, "\n  caused by: {line}");
        }
        last = line;
        source = cause.source();
    }
    text
}
