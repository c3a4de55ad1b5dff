//! The off-screen runner: a [`FrameSource`] (a game or a scene's playback) advanced by a simulated display's
//! frame durations and drawn into an [`OffscreenTarget`], frame by frame,
//! written as PNG files and optionally an animated GIF.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, RgbaImage};

use crate::app::api::error::RunError;
use crate::app::session::source::FrameSource;
use crate::clock::TimeSource;
use crate::render::{Gpu, OFFSCREEN_FORMAT, OffscreenTarget, Renderer, RendererConfig};

/// Where an off-screen run writes its frames.
#[derive(Clone, Debug, Default)]
pub struct FrameOutput {
    /// Directory for `frame_00000.png`, ... (default: none written).
    pub dir: Option<PathBuf>,
    /// Animated GIF file (default: none).
    pub gif: Option<PathBuf>,
    /// Overwrite existing frames or GIF (default false: refuse).
    pub overwrite: bool,
    /// Draw the HUD (default false).
    pub hud: bool,
}

/// What an off-screen run did.
#[derive(Clone, Debug, PartialEq)]
pub struct OffscreenSummary {
    /// Frames drawn.
    pub frames: u64,
    /// Fixed steps run.
    pub steps: u64,
    /// PNG files written.
    pub pngs: Vec<PathBuf>,
    /// The GIF written, if any.
    pub gif: Option<PathBuf>,
    /// The adapter used.
    pub adapter: String,
}

/// A GPU, a renderer and a target of one size, drawing playback frames.
#[derive(Debug)]
pub struct OffscreenRun<'g> {
    gpu: &'g Gpu,
    renderer: Renderer,
    target: OffscreenTarget,
}

impl<'g> OffscreenRun<'g> {
    /// A runner drawing `width` x `height` frames on `gpu`.
    ///
    /// # Errors
    /// [`RunError::Render`] for a bad size or renderer setting.
    pub fn new(gpu: &'g Gpu, width: u32, height: u32, config: RendererConfig) -> Result<Self, RunError> {
        let target = OffscreenTarget::new(gpu, width, height, config.samples)?;
        let renderer = Renderer::new(gpu, OFFSCREEN_FORMAT, config)?;
        Ok(Self { gpu, renderer, target })
    }

    /// Advances `source` by one frame of `seconds` and draws it.
    ///
    /// # Errors
    /// [`RunError::Playback`] for a bad duration or failed step,
    /// [`RunError::Render`] if drawing fails.
    pub fn frame(&mut self, source: &mut dyn FrameSource, seconds: f64, hud: bool) -> Result<RgbaImage, RunError> {
        source.attach_gpu(self.gpu);
        source.advance(seconds)?;
        self.draw(source, hud)
    }

    /// Draws `source` as it is, without advancing it.
    ///
    /// # Errors
    /// [`RunError::Render`] if drawing fails.
    pub fn draw(&mut self, source: &mut dyn FrameSource, hud: bool) -> Result<RgbaImage, RunError> {
        let mut image = None;
        let (target, renderer, gpu) = (&self.target, &mut self.renderer, self.gpu);
        if let Some(interpolation) = source.interpolation() {
            renderer.set_interpolation(interpolation);
        }
        source.with_view(hud, (self.target.width(), self.target.height()), &mut |view| {
            image = Some(target.render(gpu, renderer, view)?);
            Ok(())
        })?;
        image.ok_or_else(|| crate::render::RenderError::Device("the frame was not drawn".into()).into())
    }

    /// Runs `frames` frames with durations from `display`, writing them to
    /// `output`; `progress` is called after each frame with its number.
    ///
    /// # Errors
    /// [`RunError::Limit`] for more than [`MAX_OFFSCREEN_FRAMES`](MAX_OFFSCREEN_FRAMES)
    /// frames, [`RunError::Exists`] if an output file exists and `overwrite` is
    /// off (checked before anything is drawn), [`RunError::Io`] for a file
    /// that cannot be written, and as [`OffscreenRun::frame`].
    pub fn run(
        &mut self,
        source: &mut dyn FrameSource,
        display: &mut dyn TimeSource,
        frames: u64,
        output: &FrameOutput,
        progress: &mut dyn FnMut(u64),
    ) -> Result<OffscreenSummary, RunError> {
        check_output(frames, output.dir.as_deref())?;
        let png = |k: u64| output.dir.as_ref().map(|dir| dir.join(format!("frame_{k:05}.png")));
        if !output.overwrite {
            for path in (0..frames).filter_map(png).chain(output.gif.clone()) {
                if path.exists() {
                    return Err(RunError::Exists(path));
                }
            }
        }
        if let Some(dir) = &output.dir {
            std::fs::create_dir_all(dir).map_err(|e| RunError::io(dir, &e))?;
        }
        let mut gif = match &output.gif {
            Some(path) => {
                if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
                    std::fs::create_dir_all(parent).map_err(|e| RunError::io(parent, &e))?;
                }
                let file = File::create(path).map_err(|e| RunError::io(path, &e))?;
                // Speed 10 of 1-30: good colours at a few ms per frame.
                let mut encoder = GifEncoder::new_with_speed(BufWriter::new(file), 10);
                encoder
                    .set_repeat(Repeat::Infinite)
                    .map_err(|e| RunError::io(path, &e))?;
                Some((encoder, path))
            }
            None => None,
        };
        let steps_before = source.ticks();
        let mut summary = OffscreenSummary {
            frames: 0,
            steps: 0,
            pngs: Vec::new(),
            gif: output.gif.clone(),
            adapter: self.gpu.describe(),
        };
        for k in 0..frames {
            let seconds = display.next_frame();
            let image = self.frame(source, seconds, output.hud)?;
            if let Some(path) = png(k) {
                image.save(&path).map_err(|e| RunError::io(&path, &e))?;
                summary.pngs.push(path);
            }
            if let Some((encoder, path)) = &mut gif {
                // GIF delays are in hundredths of a second.
                let delay = Delay::from_numer_denom_ms((seconds * 1000.0).round().max(10.0) as u32, 1);
                encoder
                    .encode_frame(image::Frame::from_parts(image, 0, 0, delay))
                    .map_err(|e| RunError::io(path, &e))?;
            }
            summary.frames += 1;
            progress(k + 1);
        }
        summary.steps = source.ticks() - steps_before;
        Ok(summary)
    }
}

/// The most frames an off-screen run draws: a million (over four hours at
/// 60 frames per second; `--frames 100000000` once stalled the run).
pub const MAX_OFFSCREEN_FRAMES: u64 = 1_000_000;

/// Refuses more than [`MAX_OFFSCREEN_FRAMES`] frames, and a frames'
/// directory that is a file; [`OffscreenRun::run`] checks, and
/// [`run`](crate::app::run) before a session starts.
pub(crate) fn check_output(frames: u64, dir: Option<&Path>) -> Result<(), RunError> {
    if frames > MAX_OFFSCREEN_FRAMES {
        return Err(RunError::Limit(format!(
            "--frames {frames} is past the limit of {} off-screen frames (MAX_OFFSCREEN_FRAMES); \
             draw a shorter run",
            MAX_OFFSCREEN_FRAMES
        )));
    }
    if let Some(dir) = dir.filter(|dir| dir.exists() && !dir.is_dir()) {
        return Err(RunError::Io {
            path: dir.to_path_buf(),
            message: "is a file; name a directory for the frames".into(),
        });
    }
    Ok(())
}
