//! `tickwork sim`: run a scene headless, with no window and no GPU.

use std::fs::File;
use std::io::{BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use tickwork_engine::clock::Rate;
use tickwork_engine::{HeadlessError, Scene, TraceWriter, run_headless};

use super::error::CliError;

/// Arguments of `tickwork sim`.
#[derive(Debug, Args)]
pub struct SimArgs {
    /// The scene file (RON), for example assets/scenes/projectile.ron.
    pub scene: PathBuf,
    /// Integrator to use instead of the scene's (see `tickwork integrators`).
    #[arg(long)]
    pub integrator: Option<String>,
    /// Fixed steps per second instead of the scene's rate.
    #[arg(long, conflicts_with = "dt", allow_hyphen_values = true)]
    pub hz: Option<f64>,
    /// Fixed step in seconds instead of the scene's rate.
    #[arg(long, allow_hyphen_values = true)]
    pub dt: Option<f64>,
    /// Number of steps to run (default: the scene's duration).
    #[arg(long, conflicts_with = "until", allow_negative_numbers = true)]
    pub steps: Option<u64>,
    /// Simulated seconds to run to (default: the scene's duration).
    #[arg(long, allow_hyphen_values = true)]
    pub until: Option<f64>,
    /// Write a CSV trace (step, t, entity, position, velocity, orientation,
    /// angular velocity) to this file.
    #[arg(long)]
    pub trace: Option<PathBuf>,
    /// Trace every K-th step (default: every step).
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub every: u64,
    /// Overwrite the trace file if it exists.
    #[arg(long)]
    pub force: bool,
}

/// The most steps `--steps` or `--until` may ask for: ten billion (about five years at
/// 60 Hz); `--until 1e300` once became `u64::MAX` steps in silence.
const MAX_STEPS: u64 = 10_000_000_000;

/// Runs the scene and prints the summary to `out`.
///
/// # Errors
/// A [`CliError`] for a bad scene, integrator, rate, duration, trace file,
/// a simulation that failed, or an output that cannot be written.
pub fn run(args: &SimArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let scene = Scene::load(&args.scene).map_err(CliError::SceneLoad)?;
    let (mut world, _) = scene.build().map_err(CliError::SceneBuild)?;
    if let Some(name) = &args.integrator {
        world.set_integrator(name)?;
    }
    let rate = match (args.hz, args.dt) {
        (Some(hz), _) => Rate::hz_f64(hz).map_err(|source| CliError::Rate {
            option: "--hz",
            value: hz,
            source,
        })?,
        (_, Some(dt)) => Rate::seconds(dt).map_err(|source| CliError::Rate {
            option: "--dt",
            value: dt,
            source,
        })?,
        _ => scene.rate().map_err(CliError::SceneRate)?,
    };
    if args.every == 0 {
        return Err(CliError::EveryZero);
    }
    let steps = match (args.steps, args.until) {
        (Some(n), _) if n > MAX_STEPS => {
            return Err(CliError::TooManySteps {
                steps: n,
                limit: MAX_STEPS,
            });
        }
        (Some(n), _) => n,
        (_, Some(t)) if t.is_finite() && t >= 0.0 => {
            let steps = (t / rate.step_seconds()).round();
            if steps > MAX_STEPS as f64 {
                return Err(CliError::TooLong {
                    seconds: t,
                    steps,
                    rate,
                    limit: MAX_STEPS,
                });
            }
            steps as u64
        }
        (_, Some(t)) => return Err(CliError::BadUntil(t)),
        _ => (f64::from(scene.spec.duration.0) / rate.step_seconds()).round() as u64,
    };
    let mut trace = match &args.trace {
        Some(path) => Some(open_trace(path, args.force)?),
        None => None,
    };
    let bar = if std::io::stderr().is_terminal() && steps >= 1000 {
        let bar = ProgressBar::new(steps);
        let style = ProgressStyle::with_template("{spinner} {wide_bar} {pos}/{len} steps, {per_sec}, eta {eta}");
        if let Ok(style) = style {
            bar.set_style(style);
        }
        bar
    } else {
        ProgressBar::hidden()
    };
    let summary = run_headless(&mut world, rate, steps, trace.as_mut(), args.every, |done| {
        bar.set_position(done)
    })
    .map_err(|e| match e {
        HeadlessError::Simulation(source) => CliError::Simulation {
            path: args.scene.clone(),
            source,
        },
        HeadlessError::Trace(source) => CliError::TraceWrite {
            path: args.trace.clone().unwrap_or_default(),
            source,
        },
    })?;
    bar.finish_and_clear();
    if let (Some(trace), Some(path)) = (trace, &args.trace) {
        trace.finish().map_err(|source| CliError::TraceWrite {
            path: path.clone(),
            source,
        })?;
    }
    let (start, end, peak) = summary.particles;
    let write = |out: &mut dyn Write| -> std::io::Result<()> {
        writeln!(out, "scene       {} ({})", scene.name(), args.scene.display())?;
        writeln!(out, "integrator  {}", world.integrator().info().name)?;
        writeln!(out, "rate        {rate}")?;
        writeln!(out, "steps       {} (t = {:.6} s)", summary.steps, summary.time)?;
        writeln!(out, "particles   {start} at start, {end} at end, {peak} at most")?;
        let drift = summary
            .energy_drift()
            .map_or_else(|| "n/a: starts at zero".into(), |d| format!("{d:+.3e}"));
        writeln!(
            out,
            "energy      {:.9e} J -> {:.9e} J (drift {drift})",
            summary.energy.0, summary.energy.1
        )?;
        writeln!(out, "wall time   {:.3} s", summary.wall_seconds)?;
        writeln!(out, "throughput  {:.3e} particle-steps/s", summary.throughput())?;
        if let Some(path) = &args.trace {
            writeln!(out, "trace       {} (every {} steps)", path.display(), args.every)?;
        }
        Ok(())
    };
    write(out).map_err(CliError::Output)
}

/// Opens the trace file at `path`, refusing a directory, a missing
/// directory, and an existing file unless `force`.
fn open_trace(path: &Path, force: bool) -> Result<TraceWriter<BufWriter<File>>, CliError> {
    if path.is_dir() {
        return Err(CliError::IsDirectory {
            option: "--trace",
            path: path.to_path_buf(),
            wanted: "a file",
        });
    }
    if path.exists() && !force {
        return Err(CliError::Exists(path.to_path_buf()));
    }
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty() && !p.is_dir()) {
        return Err(CliError::MissingDirectory {
            option: "--trace",
            path: path.to_path_buf(),
            parent: parent.to_path_buf(),
        });
    }
    let file = File::create(path).map_err(|source| CliError::TraceCreate {
        path: path.to_path_buf(),
        source,
    })?;
    TraceWriter::new(BufWriter::new(file)).map_err(|source| CliError::TraceWrite {
        path: path.to_path_buf(),
        source,
    })
}
