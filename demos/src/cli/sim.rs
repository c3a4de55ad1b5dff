//! `tickwork sim`: run a scene headless, with no window and no GPU.

use std::fs::File;
use std::io::{BufWriter, IsTerminal, Write};
use std::path::PathBuf;

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use tickwork_engine::clock::{Number, Rate};
use tickwork_engine::{Scene, TraceWriter, run_headless};

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
/// A message for a bad scene, integrator, rate, duration, trace file or a
/// simulation that failed.
pub fn run(args: &SimArgs, out: &mut dyn Write) -> Result<(), String> {
    let scene = Scene::load(&args.scene).map_err(|e| e.to_string())?;
    let (mut world, _) = scene.build().map_err(|e| e.to_string())?;
    if let Some(name) = &args.integrator {
        world.set_integrator(name).map_err(|e| e.to_string())?;
    }
    let rate = match (args.hz, args.dt) {
        (Some(hz), _) => Rate::hz_f64(hz).map_err(|e| format!("--hz: {e}"))?,
        (_, Some(dt)) => Rate::seconds(dt).map_err(|e| format!("--dt: {e}"))?,
        _ => scene.rate().map_err(|e| e.to_string())?,
    };
    if args.every == 0 {
        return Err("--every: must be at least 1".into());
    }
    let steps = match (args.steps, args.until) {
        (Some(n), _) if n > MAX_STEPS => {
            return Err(format!(
                "--steps: {n} steps, past the limit of {MAX_STEPS} steps a run; run fewer"
            ));
        }
        (Some(n), _) => n,
        (_, Some(t)) if t.is_finite() && t >= 0.0 => {
            let steps = (t / rate.step_seconds()).round();
            if steps > MAX_STEPS as f64 {
                return Err(format!(
                    "--until: {} s is {} steps at {rate}, past the limit of {MAX_STEPS} steps a run; \
                     simulate less time, or pass --steps",
                    Number(t),
                    Number(steps)
                ));
            }
            steps as u64
        }
        (_, Some(t)) => return Err(format!("--until: {t} is not a finite time, not negative")),
        _ => (f64::from(scene.spec.duration.0) / rate.step_seconds()).round() as u64,
    };
    let mut trace = match &args.trace {
        Some(path) => {
            if path.is_dir() {
                return Err(format!("--trace: {} is a directory; name a file", path.display()));
            }
            if path.exists() && !args.force {
                return Err(format!("{}: exists; pass --force to overwrite it", path.display()));
            }
            if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty() && !p.is_dir()) {
                return Err(format!(
                    "--trace: {}: the directory {} does not exist",
                    path.display(),
                    parent.display()
                ));
            }
            let file = File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
            Some(TraceWriter::new(BufWriter::new(file)).map_err(|e| format!("{}: {e}", path.display()))?)
        }
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
    .map_err(|e| e.to_string())?;
    bar.finish_and_clear();
    if let Some(trace) = trace {
        trace.finish().map_err(|e| format!("writing the trace: {e}"))?;
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
    write(out).map_err(|e| e.to_string())
}
