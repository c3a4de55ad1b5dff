//! `tickwork sim`: run a scene headless, with no window: on the CPU, or
//! with `--gpu` on the GPU step (the state read back at the end, and at
//! each traced step with `--trace`).

use std::fs::File;
use std::io::{BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use tickwork_engine::clock::{FixedClock, Rate};
use tickwork_engine::gpu_step::GpuWorld;
use tickwork_engine::render::Gpu;
use tickwork_engine::{HeadlessError, HeadlessSummary, Scene, TraceWriter, World, run_headless};

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
    /// Step the scene on the GPU (explicit and semi-implicit Euler,
    /// midpoint, Heun, RK4, Forest-Ruth, velocity Verlet, leapfrog,
    /// position Verlet, Beeman, Adams-Bashforth 2-4; gravity, wind, drag,
    /// attractors, n-body; planes along an axis and boxes, at rest or
    /// kinematic, their contacts inside the step or at its end; anything
    /// else is refused by name). The state is read back at the end, and with
    /// `--trace` at each traced step (a copy and a wait each: `--every`
    /// keeps them few; the summary says how many and their time): the
    /// checksum and the trace are then the CPU's where the adapter computes
    /// as the CPU does (lavapipe does), the adapter's own elsewhere.
    #[arg(long)]
    pub gpu: bool,
}

/// The most fixed steps recorded into one GPU submission.
const GPU_BATCH: u32 = 1024;

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
    let mut backend = "cpu".to_owned();
    // `--gpu`, or a scene whose backend is the GPU.
    let summary = if args.gpu || world.config().backend == tickwork_engine::world::Backend::Gpu {
        let traced = trace.as_mut().map(|t| (t, args.every));
        let run = run_on_gpu(&mut world, rate, steps, &args.scene, traced, |done| {
            bar.set_position(done)
        })
        .map_err(|e| match e {
            GpuRunError::Cli(e) => e,
            GpuRunError::Trace(source) => CliError::TraceWrite {
                path: args.trace.clone().unwrap_or_default(),
                source,
            },
        })?;
        backend = match run.read_backs {
            (0, _) => format!("gpu: {} (read back once, at the end)", run.adapter),
            (n, seconds) => format!(
                "gpu: {} (read back at the end and for the trace {n} times, {seconds:.3} s of the wall time)",
                run.adapter
            ),
        };
        run.summary
    } else {
        run_headless(&mut world, rate, steps, trace.as_mut(), args.every, |done| {
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
        })?
    };
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
        writeln!(out, "backend     {backend}")?;
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
        writeln!(out, "checksum    {:016x}", world.state_hash())?;
        if let Some(path) = &args.trace {
            writeln!(out, "trace       {} (every {} steps)", path.display(), args.every)?;
        }
        Ok(())
    };
    write(out).map_err(CliError::Output)
}

/// What a run on the GPU step did: the summary, the adapter's name, and
/// the read-backs the trace took (how many, and their seconds of the wall
/// time, the trace's writing included).
struct GpuRun {
    summary: HeadlessSummary,
    adapter: String,
    read_backs: (u64, f64),
}

/// Why a run on the GPU step stopped: the command's error, or the trace's.
enum GpuRunError {
    Cli(CliError),
    Trace(std::io::Error),
}

impl From<CliError> for GpuRunError {
    fn from(e: CliError) -> Self {
        Self::Cli(e)
    }
}

/// Runs `steps` frames of one fixed step each, as [`run_headless`] does, on
/// the GPU step, and stores the final state into `world` (the scene's
/// file, `scene`, names it in an error). With `trace` (a writer and
/// `every`), the state is read back into `world` and written at the start
/// and every `every` steps, as `run_headless` writes the CPU's.
fn run_on_gpu(
    world: &mut World,
    rate: Rate,
    steps: u64,
    scene: &Path,
    mut trace: Option<(&mut TraceWriter<BufWriter<File>>, u64)>,
    mut progress: impl FnMut(u64),
) -> Result<GpuRun, GpuRunError> {
    let gpu = Gpu::headless().map_err(CliError::Gpu)?;
    let info = gpu.adapter.get_info();
    let adapter = format!("{} ({:?})", info.name, info.backend);
    let mut on_gpu = GpuWorld::new(&gpu, world).map_err(CliError::GpuStep)?;
    let mut clock = FixedClock::default();
    clock.set_rate(rate);
    let particles = world.len();
    let simulation = |source| CliError::Simulation {
        path: scene.to_path_buf(),
        source,
    };
    let start_energy = world.energy().map_err(simulation)?.total();
    if let Some((t, _)) = trace.as_mut() {
        t.write(world).map_err(GpuRunError::Trace)?;
    }
    let started = std::time::Instant::now();
    let (mut pending, mut last) = (0u32, None);
    let (mut peak, mut particle_steps) = (particles, 0u64);
    let (mut read_backs, mut reading) = (0u64, std::time::Duration::ZERO);
    let report_every = (steps / 100).max(1);
    for done in 0..steps {
        for step in clock.step(1).fixed_steps() {
            if !on_gpu.steps_in_batches() {
                // Emitters, lifetimes: the world's rows change, step by step.
                particle_steps += world.len() as u64;
                on_gpu.advance(&gpu, world, step).map_err(CliError::GpuStep)?;
                peak = peak.max(world.len());
                last = Some(step);
                if (step.tick + 1).is_multiple_of(u64::from(GPU_BATCH)) {
                    on_gpu.finish(&gpu).map_err(CliError::GpuStep)?;
                }
                continue;
            }
            particle_steps += particles as u64;
            pending += 1;
            last = Some(step);
            if pending == GPU_BATCH {
                on_gpu.step(&gpu, step.dt as f32, pending).map_err(CliError::GpuStep)?;
                pending = 0;
                // The GPU finishes each batch before the next is recorded:
                // the queue stays bounded and the progress is true.
                on_gpu.finish(&gpu).map_err(CliError::GpuStep)?;
            }
        }
        if let Some((t, every)) = trace.as_mut()
            && (done + 1) % *every == 0
        {
            // The steps so far, read back into the world and written.
            let reading_from = std::time::Instant::now();
            if let Some(last) = last {
                if pending > 0 {
                    on_gpu.step(&gpu, last.dt as f32, pending).map_err(CliError::GpuStep)?;
                    pending = 0;
                }
                on_gpu.store_into(&gpu, world, last).map_err(CliError::GpuStep)?;
            }
            t.write(world).map_err(GpuRunError::Trace)?;
            read_backs += 1;
            reading += reading_from.elapsed();
        }
        if (done + 1) % report_every == 0 {
            progress(done + 1);
        }
    }
    if let Some(last) = last {
        if pending > 0 {
            on_gpu.step(&gpu, last.dt as f32, pending).map_err(CliError::GpuStep)?;
        }
        on_gpu.store_into(&gpu, world, last).map_err(CliError::GpuStep)?;
    }
    let summary = HeadlessSummary {
        steps,
        time: clock.time(),
        particles: (particles, world.len(), peak),
        energy: (start_energy, world.energy().map_err(simulation)?.total()),
        wall_seconds: started.elapsed().as_secs_f64(),
        particle_steps,
    };
    Ok(GpuRun {
        summary,
        adapter,
        read_backs: (read_backs, reading.as_secs_f64()),
    })
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
