//! `tickwork render` (a scene off-screen, to PNG frames and a GIF) and
//! `tickwork view` (the same scene in a window), with the options they share.

use std::io::IsTerminal;
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use tickwork_engine::Scene;
use tickwork_engine::app::{
    FrameOutput, OffscreenRun, Playback, PlaybackError, WindowOptions, display_hz, non_negative_seconds, parse_size,
    run_window,
};
use tickwork_engine::clock::{FixedCadence, JitteryCadence, TimeSource};
use tickwork_engine::render::{Blend, Gpu, Interpolation, RendererConfig};
use tickwork_engine::world::Backend;

use super::error::CliError;

/// How particles are composited (`--blend`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum BlendArg {
    /// Solid discs, depth-tested.
    #[default]
    Alpha,
    /// Colours add up (sparks, clouds).
    Additive,
}

/// Where particles are drawn between steps (`--interpolation`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum InterpolationArg {
    /// Between the last two steps (one step of latency, smooth).
    #[default]
    Interpolate,
    /// Ahead of the last step (no latency, overshoots at bounces).
    Extrapolate,
    /// At the last step (shows the fixed-step judder).
    None,
}

/// Options shared by `render` and `view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// The scene file (RON), for example assets/scenes/fountain.ron.
    pub scene: PathBuf,
    /// Integrator to use instead of the scene's (see `tickwork integrators`).
    #[arg(long)]
    pub integrator: Option<String>,
    /// Image or window size in pixels, WIDTHxHEIGHT.
    #[arg(long, value_parser = parse_size, allow_hyphen_values = true)]
    pub size: Option<(u32, u32)>,
    /// Particle compositing.
    #[arg(long, value_enum, default_value_t)]
    pub blend: BlendArg,
    /// Where particles are drawn between fixed steps.
    #[arg(long, value_enum, default_value_t)]
    pub interpolation: InterpolationArg,
    /// Turn MSAA off (one sample per pixel instead of four).
    #[arg(long)]
    pub no_msaa: bool,
    /// Hide the HUD (fps, steps, dropped time, integrator, particles, energy).
    #[arg(long)]
    pub no_hud: bool,
    /// Step the particles on the GPU (compute shaders), drawn from the
    /// GPU's buffers, whatever the scene's `backend`.
    #[arg(long)]
    pub gpu: bool,
}

impl ViewArgs {
    fn playback(&self) -> Result<Playback, CliError> {
        let scene = Scene::load(&self.scene).map_err(CliError::SceneLoad)?;
        let backend = self.gpu.then_some(Backend::Gpu);
        Playback::from_scene_on(&scene, self.integrator.as_deref(), backend).map_err(|e| match e {
            PlaybackError::Integrator(e) => CliError::Integrator(e),
            source => CliError::Playback {
                path: self.scene.clone(),
                source: Box::new(source),
            },
        })
    }

    fn renderer(&self) -> RendererConfig {
        RendererConfig {
            blend: match self.blend {
                BlendArg::Alpha => Blend::Alpha,
                BlendArg::Additive => Blend::Additive,
            },
            interpolation: match self.interpolation {
                InterpolationArg::Interpolate => Interpolation::Interpolate,
                InterpolationArg::Extrapolate => Interpolation::Extrapolate,
                InterpolationArg::None => Interpolation::None,
            },
            samples: if self.no_msaa { 1 } else { 4 },
            ..RendererConfig::default()
        }
    }
}

/// Arguments of `tickwork render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The scene and how to draw it.
    #[command(flatten)]
    pub view: ViewArgs,
    /// Frames to draw.
    #[arg(long, default_value_t = 120, allow_negative_numbers = true)]
    pub frames: u64,
    /// Directory for the PNG frames (frame_00000.png, ...).
    #[arg(long, default_value = "frames")]
    pub out: PathBuf,
    /// Also write an animated GIF.
    #[arg(long)]
    pub gif: Option<PathBuf>,
    /// Refresh rate of the simulated display, frames per second.
    #[arg(long, default_value_t = 60.0, value_parser = display_hz, allow_hyphen_values = true)]
    pub display_hz: f64,
    /// Jitter the frame times by +-50% around 1/display-hz (seeded, so
    /// reproducible), as a real display under load would.
    #[arg(long)]
    pub jitter: bool,
    /// Seed of the jitter.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub jitter_seed: u64,
    /// Overwrite existing frames and GIF.
    #[arg(long)]
    pub force: bool,
}

/// Arguments of `tickwork view`.
#[derive(Debug, Args)]
pub struct WindowArgs {
    /// The scene and how to draw it.
    #[command(flatten)]
    pub view: ViewArgs,
    /// Present without waiting for the display's refresh.
    #[arg(long)]
    pub no_vsync: bool,
    /// Show the control panel at the start (the default; F1 toggles it).
    #[arg(long, conflicts_with = "no_panel")]
    pub panel: bool,
    /// Start with the control panel hidden (F1 shows it).
    #[arg(long)]
    pub no_panel: bool,
    /// Close after this many frames.
    #[arg(long, allow_negative_numbers = true)]
    pub frames: Option<u64>,
    /// After --frames, keep the last frame on screen this many seconds.
    #[arg(long, default_value_t = 0.0, value_parser = non_negative_seconds, allow_hyphen_values = true)]
    pub hold: f64,
    /// Drive the clock from a simulated display at this rate instead of the
    /// real clock (reproducible frames, for tests).
    #[arg(long, value_parser = display_hz, allow_hyphen_values = true)]
    pub display_hz: Option<f64>,
    /// Directory for F12 screenshots.
    #[arg(long, default_value = ".")]
    pub screenshots: PathBuf,
}

/// Runs `tickwork render`.
///
/// # Errors
/// A [`CliError`] for a bad scene or option, no adapter, an output that
/// exists, or a run that stopped.
pub fn render(args: &RenderArgs) -> Result<(), CliError> {
    if args.frames == 0 {
        // Refused before anything is written: an empty GIF named as written
        // helped no one.
        return Err(CliError::NoFrames);
    }
    if let Some(gif) = args.gif.as_ref().filter(|gif| gif.is_dir()) {
        return Err(CliError::IsDirectory {
            option: "--gif",
            path: gif.clone(),
            wanted: "a .gif file",
        });
    }
    let mut playback = args.view.playback()?;
    let (width, height) = args.view.size.unwrap_or((640, 360));
    let gpu = Gpu::headless().map_err(CliError::Gpu)?;
    let mut run =
        OffscreenRun::new(&gpu, width, height, args.view.renderer()).map_err(|source| CliError::RenderSetup {
            width,
            height,
            source: Box::new(source),
        })?;
    let mut display: Box<dyn TimeSource> = if args.jitter {
        Box::new(JitteryCadence::new(1.0 / args.display_hz, args.jitter_seed))
    } else {
        Box::new(FixedCadence::hz(args.display_hz))
    };
    let output = FrameOutput {
        dir: Some(args.out.clone()),
        gif: args.gif.clone(),
        overwrite: args.force,
        hud: !args.view.no_hud,
    };
    let bar = (std::io::stderr().is_terminal() && args.frames >= 60).then(|| {
        let bar = ProgressBar::new(args.frames);
        if let Ok(style) = ProgressStyle::with_template("{bar:40} {pos}/{len} frames {eta}") {
            bar.set_style(style);
        }
        bar
    });
    let start = std::time::Instant::now();
    let summary = run
        .run(&mut playback, display.as_mut(), args.frames, &output, &mut |k| {
            if let Some(bar) = &bar {
                bar.set_position(k);
            }
        })
        .map_err(|source| CliError::Render {
            path: args.view.scene.clone(),
            source: Box::new(source),
        })?;
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    let seconds = start.elapsed().as_secs_f64();
    println!(
        "rendered {} frames ({} steps, {}x{}) on {} in {:.2} s ({:.1} ms/frame)",
        summary.frames,
        summary.steps,
        width,
        height,
        summary.adapter,
        seconds,
        1000.0 * seconds / summary.frames.max(1) as f64
    );
    println!("frames: {}/frame_00000.png ...", args.out.display());
    if let Some(gif) = &summary.gif {
        println!("gif: {}", gif.display());
    }
    Ok(())
}

impl WindowArgs {
    /// The window these options ask for: 1280x720 unless `--size` says
    /// otherwise, and the control panel shown at the start unless
    /// `--no-panel` (the lab's scenes are watched with their controls).
    #[must_use]
    pub fn window_options(&self) -> WindowOptions {
        let (width, height) = self.view.size.unwrap_or((1280, 720));
        WindowOptions {
            width,
            height,
            vsync: !self.no_vsync,
            frames: self.frames,
            hold_seconds: self.hold,
            display_hz: self.display_hz,
            screenshot_dir: self.screenshots.clone(),
            hud: !self.view.no_hud,
            renderer: self.view.renderer(),
            panel: !self.no_panel,
            ..WindowOptions::default()
        }
    }
}

/// Runs `tickwork view`.
///
/// # Errors
/// A [`CliError`] for a bad scene or option, no display, no adapter, or a
/// run that stopped.
pub fn view(args: &WindowArgs) -> Result<(), CliError> {
    let mut playback = args.view.playback()?;
    let summary = run_window(&mut playback, args.window_options()).map_err(|source| CliError::Window {
        path: args.view.scene.clone(),
        source: Box::new(source),
    })?;
    println!(
        "showed {} frames on {} ({})",
        summary.frames, summary.adapter, summary.surface
    );
    Ok(())
}
