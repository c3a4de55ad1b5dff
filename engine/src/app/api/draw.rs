//! What a game draws with its worlds each frame: filled rectangles and
//! polygons, lines thin and thick, text placed in the world, and the HUD,
//! told the frame's size and scale so it can place them. Shapes are drawn
//! in the order the game draws them, by layer above that.

use glam::{Vec2, Vec3};

#[cfg(feature = "text")]
use crate::render::measure_text;
use crate::render::tessellate;
use crate::render::{Batch, Line, Shapes, Sprite, Stroke, Text, Texture, Triangle, Width, extend_batches};
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
/// (metres), cleared before each [`Game::draw`](crate::app::Game::draw).
///
/// Shapes are drawn in the order they are added, on the current
/// [`layer`](Self::layer) (lower layers first; default 0); the worlds'
/// particles come after the shapes of [`particle_layer`](Self::particle_layer)
/// (default 0; a world may have its own:
/// [`WorldBuilder::layer`](crate::app::WorldBuilder::layer)), so a background
/// drawn on layer 0 is behind them and a panel on layer 1 over them. Texts
/// are ordered with the shapes; only the HUD line is drawn over everything.
#[derive(Debug, Default)]
pub struct Draw {
    /// Line segments, one pixel wide.
    pub lines: Vec<Line>,
    /// Filled triangles.
    pub triangles: Vec<Triangle>,
    /// The order of `triangles`, `lines`, `sprites` and `texts`: runs of
    /// each on a layer, in the order they were added (what the methods
    /// below keep). Shapes pushed onto the vectors directly are drawn
    /// after those batches, on layer 0; texts over every shape.
    pub batches: Vec<Batch>,
    /// Sprites, ordered with the shapes by `batches`.
    pub sprites: Vec<Sprite>,
    /// Text placed in the world.
    pub texts: Vec<Text>,
    /// HUD text, top-left (`write!` into it).
    pub hud: String,
    /// Colour changes in `hud`: (byte offset, colour); see [`Draw::colour`].
    pub hud_colours: Vec<(usize, Colour)>,
    viewport: Viewport,
    layer: i32,
    particle_layer: i32,
    clip: Option<(Vec2, Vec2)>,
    /// The first problem a call met this frame.
    problem: Option<String>,
    /// Tessellated triangles, reused.
    scratch: Vec<[Vec2; 3]>,
}

/// A point a drawing call takes: a `Vec3`, or a `Vec2` on the z = 0 plane
/// (so 2D games pass `Vec2` everywhere).
pub trait DrawPoint {
    /// The point in 3D.
    fn point(self) -> Vec3;
}

impl DrawPoint for Vec3 {
    fn point(self) -> Vec3 {
        self
    }
}

impl DrawPoint for Vec2 {
    fn point(self) -> Vec3 {
        self.extend(0.0)
    }
}

/// `Ok` if every point of `points` is finite, else the problem, naming the
/// call and the point.
fn check_points(call: &str, points: &[Vec2]) -> Result<(), String> {
    match points.iter().position(|p| !p.is_finite()) {
        None => Ok(()),
        Some(k) => Err(format!(
            "Draw::{call}: point {k} is {}: every point must be finite",
            points[k]
        )),
    }
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

    /// Shapes and sprites added from now on are drawn only inside the
    /// world rectangle from `min` to `max` (a scrolling panel, a minimap);
    /// `None` lifts the clip. Each frame starts unclipped. (A letterboxed
    /// [`Camera::Field`](crate::render::Camera::Field) clips to its field
    /// by itself.)
    pub fn clip(&mut self, rect: Option<(Vec2, Vec2)>) {
        self.clip = rect;
    }

    /// The layer shapes are being added on.
    #[must_use]
    pub fn current_layer(&self) -> i32 {
        self.layer
    }

    /// Draws the worlds (outlines, trails, particles) after the shapes of
    /// `layer` and before those of higher layers (default 0, each frame);
    /// a world given its own layer ([`WorldBuilder::layer`](crate::app::WorldBuilder::layer))
    /// keeps it.
    pub fn particle_layer(&mut self, layer: i32) {
        self.particle_layer = layer;
    }

    /// The layer the worlds are drawn on.
    #[must_use]
    pub fn particles_on(&self) -> i32 {
        self.particle_layer
    }

    /// Adds a segment from `a` to `b`, one pixel wide (a `Vec2` lies on
    /// the z = 0 plane, as every 2D call's points do).
    pub fn line(&mut self, a: impl DrawPoint, b: impl DrawPoint, colour: Colour) {
        extend_batches(
            &mut self.batches,
            Shapes::Lines,
            self.layer,
            self.clip,
            self.lines.len(),
        );
        self.lines.push(Line {
            a: a.point(),
            b: b.point(),
            colour,
        });
    }

    /// Adds one-pixel segments joining `points` in order; `closed` joins
    /// the last to the first.
    pub fn polyline<P: DrawPoint + Copy>(&mut self, points: &[P], colour: Colour, closed: bool) {
        for pair in points.windows(2) {
            self.line(pair[0], pair[1], colour);
        }
        if closed && points.len() > 2 {
            self.line(points[points.len() - 1], points[0], colour);
        }
    }

    /// Adds a segment `width` metres wide in the xy plane, flat ended.
    pub fn thick_line(&mut self, a: Vec2, b: Vec2, width: f32, colour: Colour) {
        self.stroke(&[a, b], false, Stroke::metres(width), colour);
    }

    /// Adds a thick line through `points` in the xy plane (closed back to
    /// the first if `closed`): its width in metres or pixels, its joins
    /// and its end caps as `stroke` says:
    /// `draw.stroke(&outline, true, Stroke::pixels(3.0), WHITE);`
    pub fn stroke(&mut self, points: &[Vec2], closed: bool, stroke: Stroke, colour: Colour) {
        let width = match stroke.width {
            Width::Metres(metres) => metres,
            Width::Pixels(pixels) => pixels / self.viewport.pixels_per_metre,
        };
        if let Err(problem) = check_points("stroke", points).and_then(|()| match width.is_finite() && width > 0.0 {
            true => Ok(()),
            false => Err(format!(
                "Draw::stroke: width {:?} is not a finite size above 0",
                stroke.width
            )),
        }) {
            self.fail(problem);
            return;
        }
        let mut out = core::mem::take(&mut self.scratch);
        out.clear();
        let tolerance = self.tolerance();
        match tessellate::stroke(points, closed, width, stroke.join, stroke.cap, tolerance, &mut out) {
            Ok(()) => self.push_triangles(&out, colour),
            Err(error) => self.fail(format!("Draw::stroke: {error}")),
        }
        self.scratch = out;
    }

    /// Adds a filled axis-aligned rectangle from `min` to `max` in the xy plane.
    pub fn rect(&mut self, min: Vec2, max: Vec2, colour: Colour) {
        self.polygon(&[min, Vec2::new(max.x, min.y), max, Vec2::new(min.x, max.y)], colour);
    }

    /// Adds a filled polygon in the xy plane: corners in order, either
    /// winding, convex or not (a jagged rock), even crossing itself (the
    /// even-odd rule: a pentagram's centre is left empty).
    pub fn polygon(&mut self, corners: &[Vec2], colour: Colour) {
        self.polygon_with_holes(corners, &[], colour);
    }

    /// Adds a filled polygon with holes: `outline`'s corners, less each of
    /// `holes` (each a ring of corners, either winding).
    pub fn polygon_with_holes(&mut self, outline: &[Vec2], holes: &[&[Vec2]], colour: Colour) {
        let checked = check_points("polygon", outline).and_then(|()| {
            holes
                .iter()
                .enumerate()
                .try_for_each(|(k, hole)| check_points(&format!("polygon's hole {k}"), hole))
        });
        if let Err(problem) = checked {
            self.fail(problem);
            return;
        }
        if outline.len() < 3 {
            return;
        }
        let mut rings: Vec<&[Vec2]> = Vec::with_capacity(holes.len() + 1);
        rings.push(outline);
        rings.extend_from_slice(holes);
        let mut out = core::mem::take(&mut self.scratch);
        out.clear();
        match tessellate::fill(&rings, self.tolerance(), &mut out) {
            Ok(()) => self.push_triangles(&out, colour),
            Err(error) => self.fail(format!("Draw::polygon: {error}")),
        }
        self.scratch = out;
    }

    /// The frame's first drawing problem (a NaN corner, a zero width), if
    /// any: the runner fails the frame with it rather than drawing a
    /// wrong picture.
    #[must_use]
    pub fn problem(&self) -> Option<&str> {
        self.problem.as_deref()
    }

    fn fail(&mut self, problem: String) {
        self.problem.get_or_insert(problem);
    }

    /// A quarter of a pixel in metres: how closely curves (round joins and
    /// caps) are followed.
    fn tolerance(&self) -> f32 {
        let scale = self.viewport.pixels_per_metre;
        if scale.is_finite() && scale > 0.0 {
            0.25 / scale
        } else {
            0.01
        }
    }

    fn push_triangles(&mut self, triangles: &[[Vec2; 3]], colour: Colour) {
        for t in triangles {
            extend_batches(
                &mut self.batches,
                Shapes::Fills,
                self.layer,
                self.clip,
                self.triangles.len(),
            );
            self.triangles.push(Triangle {
                corners: t.map(|c| c.extend(0.0)),
                colour,
            });
        }
    }

    /// Adds `texture` drawn `size` metres large centred at `at` (a world
    /// position: interpolate an entity's with `alpha` as its particle is);
    /// the returned sprite sets its rotation, pivot, tint, atlas region
    /// and filtering:
    /// `draw.sprite(&ship, at, Vec2::splat(1.0)).rotation(heading).tint(RED);`
    pub fn sprite(&mut self, texture: &Texture, at: Vec2, size: Vec2) -> &mut Sprite {
        extend_batches(
            &mut self.batches,
            Shapes::Sprites,
            self.layer,
            self.clip,
            self.sprites.len(),
        );
        self.sprites.push(Sprite::new(texture, at, size));
        let last = self.sprites.len() - 1;
        &mut self.sprites[last]
    }

    /// Adds the tile layer `layer` of `map` as it is in Tiled (its tiles,
    /// flips, offset and opacity; nothing if Tiled hides it): one sprite a
    /// filled cell, in one batch a tileset, so a layer of one tileset is one
    /// draw call however many tiles it has. A layer of another map is this
    /// frame's problem, as a bad point is.
    #[cfg(feature = "tiled")]
    pub fn tiles(&mut self, map: &crate::tilemap::TileMap, layer: crate::tilemap::TileLayerId) {
        let first = self.sprites.len();
        if let Err(error) = map.sprites_of(layer, &mut self.sprites) {
            self.problem.get_or_insert_with(|| format!("Draw::tiles: {error}"));
            return;
        }
        for k in first..self.sprites.len() {
            extend_batches(&mut self.batches, Shapes::Sprites, self.layer, self.clip, k);
        }
    }

    /// Adds `text` centred at `at` (24 px, light grey); the returned text
    /// sets its size, colour and anchor:
    /// `draw.text("YOU WIN", Vec3::ZERO).size(48.0).colour(GREEN);`
    #[cfg(feature = "text")]
    pub fn text(&mut self, text: impl Into<String>, at: Vec3) -> &mut Text {
        extend_batches(
            &mut self.batches,
            Shapes::Texts,
            self.layer,
            self.clip,
            self.texts.len(),
        );
        self.texts.push(Text::new(text, at));
        let last = self.texts.len() - 1;
        &mut self.texts[last]
    }

    /// The width and height in pixels of `text` drawn `pixels` high (as
    /// [`text`](Self::text) draws it): to fit a box or place a column.
    #[cfg(feature = "text")]
    #[must_use]
    pub fn measure(&self, text: &str, pixels: f32) -> Vec2 {
        measure_text(text, pixels)
    }

    /// The width and height in metres of `text` drawn `metres` high
    /// ([`Text::size_metres`]) at this frame's scale.
    #[cfg(feature = "text")]
    #[must_use]
    pub fn measure_metres(&self, text: &str, metres: f32) -> Vec2 {
        let scale = self.viewport.pixels_per_metre;
        measure_text(text, metres * scale) / scale
    }

    /// HUD text written from now on is drawn in `colour` (a legend's entries).
    #[cfg(feature = "text")]
    pub fn colour(&mut self, colour: Colour) {
        self.hud_colours.push((self.hud.len(), colour));
    }

    /// Empties the frame's drawing for the next, keeping the buffers.
    pub(crate) fn clear(&mut self, viewport: Viewport) {
        self.lines.clear();
        self.triangles.clear();
        self.batches.clear();
        self.sprites.clear();
        self.layer = 0;
        self.particle_layer = 0;
        self.clip = None;
        self.problem = None;
        self.texts.clear();
        self.hud.clear();
        self.hud_colours.clear();
        self.viewport = viewport;
    }
}
