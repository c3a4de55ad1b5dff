//! What a game draws with its worlds each frame: filled rectangles and
//! polygons, lines thin and thick, text placed in the world, and the HUD,
//! told the frame's size and scale so it can place them. Shapes are drawn
//! in the order the game draws them, by layer above that.

use glam::{Vec2, Vec3};

use crate::render::{Batch, Line, Shapes, Text, Triangle, extend_batches};
use crate::world::Colour;

/// The frame a game draws into: its size and how many pixels a metre is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewport {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixels per metre at the camera's focus (a 2D camera: everywhere).
    pub pixels_per_metre: f32,
}

impl Default for Viewport {
    fn default() -> Self {
        Self {
            width: 640,
            height: 360,
            pixels_per_metre: 36.0,
        }
    }
}

/// What a game draws with its worlds this frame, in world coordinates
/// (metres), cleared before each [`Game::draw`](super::Game::draw).
///
/// Shapes are drawn in the order they are added, on the current
/// [`layer`](Self::layer) (lower layers first; default 0); the worlds'
/// particles come after the shapes of [`particle_layer`](Self::particle_layer)
/// (default 0), so a background drawn on layer 0 is behind them and a panel
/// on layer 1 over them. Text is drawn last, over everything.
#[derive(Debug, Default)]
pub struct Draw {
    /// Line segments, one pixel wide.
    pub lines: Vec<Line>,
    /// Filled triangles.
    pub triangles: Vec<Triangle>,
    /// The order of `triangles` and `lines`: runs of each on a layer, in
    /// the order they were added (what the methods below keep). Items
    /// pushed onto the vectors directly are drawn after those batches, on
    /// layer 0.
    pub batches: Vec<Batch>,
    /// Text placed in the world.
    pub texts: Vec<Text>,
    /// HUD text, top-left (`write!` into it).
    pub hud: String,
    /// Colour changes in `hud`: (byte offset, colour); see [`Draw::colour`].
    pub hud_colours: Vec<(usize, Colour)>,
    viewport: Viewport,
    layer: i32,
    particle_layer: i32,
}

impl Draw {
    /// The frame being drawn: its size in pixels and its scale.
    #[must_use]
    pub fn viewport(&self) -> Viewport {
        self.viewport
    }

    /// Shapes added from now on go on `layer` (lower layers are drawn
    /// first; within a layer, shapes are drawn in the order added). Each
    /// frame starts on layer 0.
    pub fn layer(&mut self, layer: i32) {
        self.layer = layer;
    }

    /// The layer shapes are being added on.
    #[must_use]
    pub fn current_layer(&self) -> i32 {
        self.layer
    }

    /// Draws the worlds (outlines, trails, particles) after the shapes of
    /// `layer` and before those of higher layers (default 0, each frame).
    pub fn particle_layer(&mut self, layer: i32) {
        self.particle_layer = layer;
    }

    /// The layer the worlds are drawn on.
    #[must_use]
    pub fn particles_on(&self) -> i32 {
        self.particle_layer
    }

    /// Adds a segment from `a` to `b`, one pixel wide.
    pub fn line(&mut self, a: Vec3, b: Vec3, colour: Colour) {
        extend_batches(&mut self.batches, Shapes::Lines, self.layer, self.lines.len());
        self.lines.push(Line { a, b, colour });
    }

    /// Adds segments joining `points` in order; `closed` joins the last to the first.
    pub fn polyline(&mut self, points: &[Vec3], colour: Colour, closed: bool) {
        for pair in points.windows(2) {
            self.line(pair[0], pair[1], colour);
        }
        if closed && points.len() > 2 {
            self.line(points[points.len() - 1], points[0], colour);
        }
    }

    /// Adds a segment `width` metres wide in the xy plane (a filled quad).
    pub fn thick_line(&mut self, a: Vec2, b: Vec2, width: f32, colour: Colour) {
        let Some(along) = (b - a).try_normalize() else {
            return;
        };
        let side = along.perp() * (0.5 * width);
        self.polygon(&[a - side, b - side, b + side, a + side], colour);
    }

    /// Adds a filled axis-aligned rectangle from `min` to `max` in the xy plane.
    pub fn rect(&mut self, min: Vec2, max: Vec2, colour: Colour) {
        self.polygon(&[min, Vec2::new(max.x, min.y), max, Vec2::new(min.x, max.y)], colour);
    }

    /// Adds a filled convex polygon in the xy plane (corners in order,
    /// either winding), as a fan of triangles from the first corner.
    pub fn polygon(&mut self, corners: &[Vec2], colour: Colour) {
        let Some((&first, rest)) = corners.split_first() else {
            return;
        };
        for pair in rest.windows(2) {
            extend_batches(&mut self.batches, Shapes::Fills, self.layer, self.triangles.len());
            self.triangles.push(Triangle {
                corners: [first.extend(0.0), pair[0].extend(0.0), pair[1].extend(0.0)],
                colour,
            });
        }
    }

    /// Adds `text` centred at `at` (24 px, light grey); the returned text
    /// sets its size, colour and anchor:
    /// `draw.text("YOU WIN", Vec3::ZERO).size(48.0).colour(GREEN);`
    pub fn text(&mut self, text: impl Into<String>, at: Vec3) -> &mut Text {
        self.texts.push(Text::new(text, at));
        let last = self.texts.len() - 1;
        &mut self.texts[last]
    }

    /// HUD text written from now on is drawn in `colour` (a legend's entries).
    pub fn colour(&mut self, colour: Colour) {
        self.hud_colours.push((self.hud.len(), colour));
    }

    /// Empties the frame's drawing for the next, keeping the buffers.
    pub(crate) fn clear(&mut self, viewport: Viewport) {
        self.lines.clear();
        self.triangles.clear();
        self.batches.clear();
        self.layer = 0;
        self.particle_layer = 0;
        self.texts.clear();
        self.hud.clear();
        self.hud_colours.clear();
        self.viewport = viewport;
    }
}
