//! Laying out a game's text: one font and one rule, shared by the renderer
//! (which draws the text) and [`measure_text`] (which a game asks before it
//! draws, to fit a box or right-align a column), so both agree to the
//! pixel.

use std::sync::{Mutex, OnceLock};

use glam::Vec2;
use glyphon::cosmic_text::Align;
use glyphon::{Attrs, Buffer, Family, FontSystem, Metrics, Shaping};

/// DejaVu Sans, shipped with its licence in `engine/fonts/` (never the
/// machine's fonts, so golden images are the same everywhere).
const FONT: &[u8] = include_bytes!("../../fonts/DejaVuSans.ttf");

/// Line height as a multiple of the size, for a game's placed text.
pub(crate) const LINE_HEIGHT: f32 = 1.2;

/// A font system holding only the shipped font.
pub(crate) fn font_system() -> FontSystem {
    let mut db = glyphon::fontdb::Database::new();
    db.load_font_data(FONT.to_vec());
    db.set_sans_serif_family("DejaVu Sans");
    FontSystem::new_with_locale_and_db("en-US".into(), db)
}

/// Lays `text` out in `buffer` at `size` pixels, its lines aligned within
/// the widest as `align` says, and returns its width and height in pixels.
pub(crate) fn lay_out(fonts: &mut FontSystem, buffer: &mut Buffer, text: &str, size: f32, align: Align) -> Vec2 {
    buffer.set_metrics(Metrics::new(size, size * LINE_HEIGHT));
    buffer.set_size(None, None);
    let attrs = Attrs::new().family(Family::SansSerif);
    // One line needs no aligning (and is placed to the pixel as it was).
    let align = if text.contains('\n') { align } else { Align::Left };
    buffer.set_text(text, &attrs, Shaping::Basic, (align != Align::Left).then_some(align));
    buffer.shape_until_scroll(fonts, false);
    let extent = extent(buffer);
    if align != Align::Left {
        // Aligned within the box the widest line sets.
        buffer.set_size(Some(extent.x.ceil()), None);
        buffer.shape_until_scroll(fonts, false);
    }
    extent
}

fn extent(buffer: &Buffer) -> Vec2 {
    let (mut width, mut height) = (0.0f32, 0.0f32);
    for run in buffer.layout_runs() {
        width = width.max(run.line_w);
        height = height.max(run.line_top + run.line_height);
    }
    Vec2::new(width, height)
}

/// The width and height in pixels of `text` drawn `size` pixels high (as
/// [`Draw::text`](crate::app::Draw::text) draws it; several lines with
/// `\n`): what a game asks to fit a box, or to place a column of numbers.
/// A size that is not in `(0, 1000]` measures nothing (zero).
#[must_use]
pub fn measure_text(text: &str, size: f32) -> Vec2 {
    if !(size.is_finite() && size > 0.0 && size <= 1000.0) {
        return Vec2::ZERO;
    }
    static FONTS: OnceLock<Mutex<FontSystem>> = OnceLock::new();
    let fonts = FONTS.get_or_init(|| Mutex::new(font_system()));
    // A panic elsewhere while measuring leaves the fonts as they were.
    let mut fonts = fonts.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let mut buffer = Buffer::new(&mut fonts, Metrics::new(size, size * LINE_HEIGHT));
    lay_out(&mut fonts, &mut buffer, text, size, Align::Left)
}
