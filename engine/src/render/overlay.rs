//! What a game draws with its worlds: line segments, filled triangles
//! (rectangles, polygons, thick lines) and text placed in the world, all in
//! world coordinates. Shapes are drawn by layer (lowest first) and, within
//! a layer, in the order they were drawn ([`Batch`]); the worlds (their
//! outlines, trails and particles) come after the shapes of their layer.
//! Texts are ordered as shapes are; only the HUD is drawn over everything.
//! They are few and built on the CPU each frame.

use glam::{Vec2, Vec3};

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
    /// Sprites.
    Sprites,
    /// Texts (items of the frame's texts).
    Texts,
}

/// The most runs of text a frame may have (texts drawn together, with no
/// other shape between them, on one layer and clip, are one run): each is
/// a draw of its own with its own vertex buffer. A frame past it is an
/// error naming this constant; draw a frame's texts together (or on one
/// layer) to need fewer. Runs side by side once sorted by layer (labels on
/// a layer of their own) count as one.
pub const MAX_TEXT_RUNS: usize = 1024;

/// A run of shapes of one kind drawn one after the other on one layer:
/// items `start..end` of the frame's triangles, lines, sprites or texts
/// (a batch of texts is drawn as one run). A frame's batches,
/// in the order they were drawn, are what makes a fill drawn after a line
/// cover it (and the other way round), whatever their kinds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Batch {
    /// Which kind: triangles, lines, sprites or texts.
    pub shapes: Shapes,
    /// The layer: lower layers are drawn first (default 0).
    pub layer: i32,
    /// The first item (an index into the frame's items of its kind).
    pub start: usize,
    /// One past the last item.
    pub end: usize,
    /// The world rectangle `(min, max)` (on the z = 0 plane) outside which
    /// nothing of the batch is drawn (default `None`: no clip).
    pub clip: Option<(Vec2, Vec2)>,
}

/// Adds item `index` of kind `shapes` on `layer` to `batches`: to the last
/// batch where it continues it, else as a new batch.
pub(crate) fn extend_batches(
    batches: &mut Vec<Batch>,
    shapes: Shapes,
    layer: i32,
    clip: Option<(Vec2, Vec2)>,
    index: usize,
) {
    if let Some(last) = batches.last_mut()
        && last.shapes == shapes
        && last.layer == layer
        && last.clip == clip
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
        clip,
    });
}

/// Which point of a text's box sits at its position; its lines are
/// aligned the same way (left, centred or right).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Anchor {
    /// The top-left corner: a label to the right of and below a point.
    TopLeft,
    /// The middle of the top edge: a caption under a point.
    Top,
    /// The top-right corner: a score in a frame's top-right corner.
    TopRight,
    /// The middle of the left edge.
    Left,
    /// The centre of the text (default): a title, "YOU WIN".
    #[default]
    Centre,
    /// The middle of the right edge: a column of numbers, right-aligned.
    Right,
    /// The bottom-left corner.
    BottomLeft,
    /// The middle of the bottom edge: a label above a point.
    Bottom,
    /// The bottom-right corner.
    BottomRight,
}

impl Anchor {
    /// Where the anchor is in the text's box, as fractions of its width
    /// and height from the top left (`(1, 0)`: the top-right corner).
    #[must_use]
    pub fn fractions(self) -> (f32, f32) {
        let x = match self {
            Self::TopLeft | Self::Left | Self::BottomLeft => 0.0,
            Self::Top | Self::Centre | Self::Bottom => 0.5,
            Self::TopRight | Self::Right | Self::BottomRight => 1.0,
        };
        let y = match self {
            Self::TopLeft | Self::Top | Self::TopRight => 0.0,
            Self::Left | Self::Centre | Self::Right => 0.5,
            Self::BottomLeft | Self::Bottom | Self::BottomRight => 1.0,
        };
        (x, y)
    }

    /// How the text's lines are aligned within its box.
    #[cfg(feature = "text")]
    pub(crate) fn align(self) -> glyphon::cosmic_text::Align {
        use glyphon::cosmic_text::Align;
        match self.fractions().0 {
            0.0 => Align::Left,
            1.0 => Align::Right,
            _ => Align::Center,
        }
    }
}

/// What a text's [`size`](Text::size) is measured in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TextUnit {
    /// Pixels (default): the same size at any zoom and window size, in
    /// `(0, 1000]`.
    #[default]
    Pixels,
    /// World units (metres): the text scales with the camera's zoom, as
    /// the world does.
    Metres,
    /// A fraction of the frame's height (of the field's, letterboxed): the
    /// text scales with the window.
    FrameHeight,
}

/// Text at a place in the world, a size (in pixels by default, or in world
/// units or a fraction of the frame's height: [`TextUnit`]) and a colour.
/// Drawn sizes are capped at 1000 pixels; a text drawn less than a pixel
/// high is left out.
#[derive(Clone, Debug, PartialEq)]
pub struct Text {
    /// The text (several lines with `\n`).
    pub text: String,
    /// Where its [`anchor`](Self::anchor) goes, in world space.
    pub at: Vec3,
    /// Font size, in [`unit`](Self::unit)s (default 24 pixels).
    pub size: f32,
    /// What `size` is measured in (default [`TextUnit::Pixels`]).
    pub unit: TextUnit,
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
            unit: TextUnit::Pixels,
            colour: [235, 235, 235, 255],
            anchor: Anchor::Centre,
        }
    }

    /// Sets the size in pixels.
    pub fn size(&mut self, pixels: f32) -> &mut Self {
        self.size = pixels;
        self.unit = TextUnit::Pixels;
        self
    }

    /// Sets the size in world units (metres): the text zooms with the world.
    pub fn size_metres(&mut self, metres: f32) -> &mut Self {
        self.size = metres;
        self.unit = TextUnit::Metres;
        self
    }

    /// Sets the size as a fraction of the frame's height (`0.05`: a
    /// twentieth): the text grows with the window.
    pub fn size_of_frame(&mut self, fraction: f32) -> &mut Self {
        self.size = fraction;
        self.unit = TextUnit::FrameHeight;
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

/// A game's text as the frame places it: its anchor point in pixels from
/// the top-left corner.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct PlacedText {
    pub text: String,
    pub x: f32,
    pub y: f32,
    pub size: f32,
    pub colour: [u8; 4],
    pub anchor: Anchor,
}
