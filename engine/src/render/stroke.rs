//! How a game's thick lines are drawn: their width (in world units or
//! pixels), how segments join, and how open ends are capped.

/// A stroke's width.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Width {
    /// In world units (metres): the line zooms with the world.
    Metres(f32),
    /// In pixels: the same at any zoom (converted at the frame's scale,
    /// [`Viewport::pixels_per_metre`](crate::app::Viewport)).
    Pixels(f32),
}

/// How two segments of a stroke meet.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Join {
    /// A pointed corner (cut flat where it would reach past four times
    /// the width).
    Miter,
    /// A rounded corner (default).
    #[default]
    Round,
    /// A corner cut flat.
    Bevel,
}

/// How an open stroke's ends look.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Cap {
    /// Flat, at the end point (default).
    #[default]
    Butt,
    /// Rounded, half the width past the end point.
    Round,
    /// Flat, half the width past the end point.
    Square,
}

/// A thick line's look: [`Draw::stroke`](crate::app::Draw::stroke).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stroke {
    /// Its width (default 2 pixels).
    pub width: Width,
    /// How segments join (default [`Join::Round`]).
    pub join: Join,
    /// How open ends are capped (default [`Cap::Butt`]).
    pub cap: Cap,
}

impl Default for Stroke {
    fn default() -> Self {
        Self {
            width: Width::Pixels(2.0),
            join: Join::Round,
            cap: Cap::Butt,
        }
    }
}

impl Stroke {
    /// A stroke `metres` wide, round joins, flat ends.
    #[must_use]
    pub fn metres(metres: f32) -> Self {
        Self {
            width: Width::Metres(metres),
            ..Self::default()
        }
    }

    /// A stroke `pixels` wide, round joins, flat ends.
    #[must_use]
    pub fn pixels(pixels: f32) -> Self {
        Self {
            width: Width::Pixels(pixels),
            ..Self::default()
        }
    }

    /// The same stroke with joins `join`.
    #[must_use]
    pub fn join(self, join: Join) -> Self {
        Self { join, ..self }
    }

    /// The same stroke with ends `cap`.
    #[must_use]
    pub fn cap(self, cap: Cap) -> Self {
        Self { cap, ..self }
    }
}
