//! The contract between a frame's source and the renderer: everything one
//! frame shows, borrowed for the time of the draw (the renderer only reads).

use super::camera::Camera;
use super::overlay::{Batch, Line, Text, Triangle};
use super::sprite::Sprite;
use super::trails::Trails;
use crate::world::World;

/// What one frame shows.
#[derive(Clone, Copy, Debug)]
pub struct FrameView<'a> {
    /// The world, read only.
    pub world: &'a World,
    /// The clock's alpha: how far the frame is past the current step, in
    /// steps, in [0, 1).
    pub alpha: f32,
    /// The camera.
    pub camera: Camera,
    /// Trails to draw, if any.
    pub trails: Option<&'a Trails>,
    /// `world`'s particles are drawn as sprites (in `sprites`), not discs.
    pub as_sprites: bool,
    /// The layer `world` is drawn on (default `None`: `particle_layer`).
    pub layer: Option<i32>,
    /// More worlds drawn in the same frame, after `world` (an integrator
    /// race: one world per method, side by side or overlaid).
    pub others: &'a [WorldView<'a>],
    /// Extra lines (a game's own drawing).
    pub lines: &'a [Line],
    /// Filled triangles (a game's rectangles and polygons).
    pub triangles: &'a [Triangle],
    /// The order of `triangles` and `lines` (see [`Batch`]); items no batch
    /// covers are drawn after the batches, on layer 0 (all of them, fills
    /// first, when there are no batches).
    pub batches: &'a [Batch],
    /// Sprites (a game's images), ordered by `batches` with the shapes.
    pub sprites: &'a [Sprite],
    /// The worlds are drawn after the shapes of this layer (default 0),
    /// but those with a layer of their own.
    pub particle_layer: i32,
    /// Text placed in the world, ordered by `batches` with the shapes
    /// (those no batch covers are drawn after every shape, on layer
    /// `i32::MAX`, before the HUD).
    pub texts: &'a [Text],
    /// HUD text, drawn top-left; empty for none.
    pub hud: &'a str,
    /// Colour changes in the HUD text: from each byte offset on, the text
    /// is drawn in that sRGB colour (default: none, all light grey).
    pub hud_colours: &'a [(usize, [u8; 4])],
    /// Particles stepped on the GPU, drawn from their own buffers after
    /// the worlds' (each on its `layer`), interpolated between their
    /// previous and current positions as any world's (Hermite too, from
    /// their velocities), as quads or by the splat: a compute pass gathers
    /// them into the frame's particle records on the GPU, nothing is
    /// uploaded.
    pub gpu_particles: &'a [GpuParticles<'a>],
}

/// A GPU world's particles as the renderer reads them
/// ([`GpuWorld::particles`](crate::gpu_step::GpuWorld::particles)): each
/// buffer one record a particle, in row order.
#[derive(Clone, Copy, Debug)]
pub struct GpuParticles<'a> {
    /// `(x, y, z, radius)` at the start of the last step.
    pub previous: &'a wgpu::Buffer,
    /// `(x, y, z, radius)` now.
    pub current: &'a wgpu::Buffer,
    /// `(vx, vy, vz, inverse mass)` now (Hermite interpolation's).
    pub velocities: &'a wgpu::Buffer,
    /// sRGB RGBA colours, one `u32` (little-endian bytes) a particle.
    pub colours: &'a wgpu::Buffer,
    /// How many particles.
    pub count: u32,
    /// At least the largest radius among them (the splat path draws
    /// particles up to a few pixels wide).
    pub max_radius: f32,
    /// The layer they are drawn on, as a world's
    /// ([`WorldView::layer`]); `None` (default): the frame's
    /// `particle_layer`.
    pub layer: Option<i32>,
}

impl<'a> FrameView<'a> {
    /// A view of `world` at `alpha` through `camera`, with no trails, lines
    /// or HUD.
    #[must_use]
    pub fn new(world: &'a World, alpha: f32, camera: Camera) -> Self {
        Self {
            world,
            alpha,
            camera,
            trails: None,
            as_sprites: false,
            layer: None,
            others: &[],
            lines: &[],
            triangles: &[],
            batches: &[],
            sprites: &[],
            particle_layer: 0,
            texts: &[],
            hud: "",
            hud_colours: &[],
            gpu_particles: &[],
        }
    }

    /// Every world of the frame with its trails: `world` first, then `others`.
    pub fn worlds(&self) -> impl Iterator<Item = WorldView<'a>> + '_ {
        std::iter::once(WorldView {
            world: self.world,
            trails: self.trails,
            as_sprites: self.as_sprites,
            layer: self.layer,
        })
        .chain(self.others.iter().copied())
    }
}

/// One more world in a frame, with its trails.
#[derive(Clone, Copy, Debug)]
pub struct WorldView<'a> {
    /// The world, read only.
    pub world: &'a World,
    /// Its trails, if any.
    pub trails: Option<&'a Trails>,
    /// Its particles are drawn as sprites (in the frame's `sprites`), not
    /// discs.
    pub as_sprites: bool,
    /// The layer it is drawn on (`None`: the frame's `particle_layer`).
    pub layer: Option<i32>,
}
