//! The renderer's settings: how particles are composited and interpolated,
//! what is drawn besides them, and the frame's look.

use crate::interpolation::Interpolation;

/// How particles are composited.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Blend {
    /// "Over", with depth testing (default): solid discs that hide what is
    /// behind them.
    #[default]
    Alpha,
    /// Colours add up, no depth writes: sparks, fire, dense clouds.
    Additive,
}

/// Renderer settings.
#[derive(Clone, Debug, PartialEq)]
pub struct RendererConfig {
    /// Clear colour, sRGB RGBA (default: near-black blue `[12, 14, 22, 255]`).
    pub background: [u8; 4],
    /// Compositing of particles (default: [`Blend::Alpha`]).
    pub blend: Blend,
    /// Interpolation between steps (default: [`Interpolation::Interpolate`],
    /// lerp from a 32-byte record per particle; [`Interpolation::Hermite`]
    /// draws arcs as arcs from the velocities too, 44 bytes a particle).
    pub interpolation: Interpolation,
    /// Samples per pixel: 4 (MSAA, default) or 1.
    pub samples: u32,
    /// Smallest drawn disc radius in pixels; smaller particles are dimmed by
    /// the area ratio instead (default 0.75).
    pub min_radius_px: f32,
    /// Draw springs as lines (default true).
    pub springs: bool,
    /// Draw rigid bodies as oriented boxes with their axes (default true).
    pub rigid_bodies: bool,
    /// Colour of spring lines, sRGB RGBA (default `[150, 150, 170, 200]`).
    pub spring_colour: [u8; 4],
    /// HUD text size in pixels (default 16).
    pub hud_size: f32,
    /// Particle count from which a 2D view of small particles (drawn radius
    /// 4 px or less) is drawn by the compute splat path instead of one quad
    /// per particle (`usize::MAX`: never). Default `None`: chosen by the
    /// adapter, 2 000 on a software (CPU) adapter, where every primitive
    /// costs about a microsecond and MSAA a dozen milliseconds a frame, and
    /// 250 000 on a GPU, where quads are cheap.
    pub splat_threshold: Option<usize>,
}

impl Default for RendererConfig {
    fn default() -> Self {
        Self {
            background: [12, 14, 22, 255],
            blend: Blend::Alpha,
            interpolation: Interpolation::Interpolate,
            samples: 4,
            min_radius_px: 0.75,
            springs: true,
            rigid_bodies: true,
            spring_colour: [150, 150, 170, 200],
            hud_size: 16.0,
            splat_threshold: None,
        }
    }
}
