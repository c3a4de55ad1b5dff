//! What a game draws with its worlds: line segments, filled triangles
//! (rectangles, polygons, thick lines) and text placed in the world, all in
//! world coordinates. Shapes are drawn by layer (lowest first) and, within
//! a layer, in the order they were drawn ([`Batch`]); the worlds (their
//! outlines, trails and particles) come after the shapes of their layer,
//! and text last, over everything. They are few and built on the CPU each
//! frame.

use glam::Vec3;

/// A line segment in world space, drawn one pixel wide.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    /// One end.
    pub a: Vec3,
    /// The other end.
    pub b: Vec3,
    /// Colour, sRGB RGBA.
    pub colour: [u8; 4],
}

/// A filled triangle in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// Its corners, in any winding.
    pub corners: [Vec3; 3],
    /// Colour, sRGB RGBA (alpha below 255 blends over what is behind).
    pub colour: [u8; 4],
}

/// The kind of shape a [`Batch`] draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shapes {
    /// Filled triangles.
    Fills,
    /// Line segments.
    Lines,
}

/// A run of shapes of one kind drawn one after the other on one layer:
/// items `start..end` of the frame's triangles or lines. A frame's batches,
/// in the order they were drawn, are what makes a fill drawn after a line
/// cover it (and the other way round), whatever their kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Batch {
    /// Triangles or lines.
    pub shapes: Shapes,
    /// The layer: lower layers are drawn first (default 0).
    pub layer: i32,
    /// The first item (an index into the frame's triangles or lines).
    pub start: usize,
    /// One past the last item.
    pub end: usize,
}

/// Adds item `index` of kind `shapes` on `layer` to `batches`: to the last
/// batch where it continues it, else as a new batch.
pub(crate) fn extend_batches(batches: &mut Vec<Batch>, shapes: Shapes, layer: i32, index: usize) {
    if let Some(last) = batches.last_mut()
        && last.shapes == shapes
        && last.layer == layer
        && last.end == index
    {
        last.end = index + 1;
        return;
    }
    batches.push(Batch {
        shapes,
        layer,
        start: index,
        end: index + 1,
    });
}

/// Which point of a text's box sits at its position.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Anchor {
    /// The centre of the text (default): a title, "YOU WIN".
    #[default]
    Centre,
    /// The top-left corner: a label to the right of and below a point.
    TopLeft,
    /// The middle of the top edge: a caption under a point.
    Top,
}

/// Text at a place in the world, a size in pixels (it does not scale with
/// the camera's zoom) and a colour.
#[derive(Clone, Debug, PartialEq)]
pub struct Text {
    /// The text (several lines with `\n`).
    pub text: String,
    /// Where its [`anchor`](Self::anchor) goes, in world space.
    pub at: Vec3,
    /// Font size in pixels (default 24).
    pub size: f32,
    /// Colour, sRGB RGBA (default light grey `[235, 235, 235, 255]`).
    pub colour: [u8; 4],
    /// Which point of the text is at `at` (default [`Anchor::Centre`]).
    pub anchor: Anchor,
}

impl Text {
    /// `text` centred at `at`, 24 px, light grey.
    #[must_use]
    pub fn new(text: impl Into<String>, at: Vec3) -> Self {
        Self {
            text: text.into(),
            at,
            size: 24.0,
            colour: [235, 235, 235, 255],
            anchor: Anchor::Centre,
        }
    }

    /// Sets the size in pixels.
    pub fn size(&mut self, pixels: f32) -> &mut Self {
        self.size = pixels;
        self
    }

    /// Sets the colour.
    pub fn colour(&mut self, colour: [u8; 4]) -> &mut Self {
        self.colour = colour;
        self
    }

    /// Sets the anchor.
    pub fn anchor(&mut self, anchor: Anchor) -> &mut Self {
        self.anchor = anchor;
        self
    }
}
