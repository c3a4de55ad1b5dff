//! Golden-image comparison for headless render tests.
//!
//! Software and hardware rasterisers, and Vulkan and GL, differ in a few
//! edge pixels, so images match when at most `max_fraction` of the pixels
//! differ by more than `channel` in any channel. On a mismatch the actual
//! image and a diff (differing pixels in red over the dimmed golden image)
//! are written beside each other and the error names both.
//! `TICKWORK_BLESS=1` writes the actual image as the new golden image.

use std::fmt;
use std::path::{Path, PathBuf};

use image::{Rgba, RgbaImage};

/// How different two images may be and still match.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    /// Largest per-channel difference (0-255) that does not count (default 24).
    pub channel: u8,
    /// Largest fraction of pixels allowed to differ by more (default 0.005).
    pub max_fraction: f64,
}

impl Default for Tolerance {
    fn default() -> Self {
        Self {
            channel: 24,
            max_fraction: 0.005,
        }
    }
}

/// How two images of the same size differ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comparison {
    /// Pixels differing by more than the tolerance's channel threshold.
    pub differing: u64,
    /// Pixels compared.
    pub total: u64,
    /// Largest difference in any channel of any pixel.
    pub max_channel_difference: u8,
}

impl Comparison {
    /// Fraction of pixels that differ.
    #[must_use]
    pub fn fraction(&self) -> f64 {
        self.differing as f64 / self.total.max(1) as f64
    }
}

/// Compares two images. `None` if their sizes differ.
#[must_use]
pub fn compare(actual: &RgbaImage, expected: &RgbaImage, tolerance: Tolerance) -> Option<Comparison> {
    if actual.dimensions() != expected.dimensions() {
        return None;
    }
    let mut comparison = Comparison {
        differing: 0,
        total: u64::from(actual.width()) * u64::from(actual.height()),
        max_channel_difference: 0,
    };
    for (a, e) in actual.pixels().zip(expected.pixels()) {
        let d = channel_difference(a, e);
        comparison.max_channel_difference = comparison.max_channel_difference.max(d);
        if d > tolerance.channel {
            comparison.differing += 1;
        }
    }
    Some(comparison)
}

fn channel_difference(a: &Rgba<u8>, b: &Rgba<u8>) -> u8 {
    a.0.iter()
        .zip(b.0.iter())
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap_or(0)
}

/// Why an image did not match its golden image. Its `Debug` form is its
/// message, so a test's `expect` or `?` prints what to do (bless with
/// `TICKWORK_BLESS=1`, look at the diff image), not the fields.
pub enum GoldenError {
    /// There is no golden image yet.
    Missing {
        /// Where it was looked for.
        golden: PathBuf,
        /// Where the actual image was written.
        actual: PathBuf,
    },
    /// The sizes differ.
    Size {
        /// The golden image.
        golden: PathBuf,
        /// Its size.
        expected: (u32, u32),
        /// The actual image's size.
        actual: (u32, u32),
    },
    /// Too many pixels differ.
    Mismatch {
        /// The golden image.
        golden: PathBuf,
        /// The actual image, written for inspection.
        actual: PathBuf,
        /// The diff image.
        diff: PathBuf,
        /// How they differ.
        comparison: Comparison,
        /// The tolerance applied.
        tolerance: Tolerance,
    },
    /// An image could not be read or written.
    Io {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

impl fmt::Debug for GoldenError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

impl fmt::Display for GoldenError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Missing { golden, actual } => write!(
                f,
                "golden image {} does not exist (actual image written to {}); run with TICKWORK_BLESS=1 to create it",
                golden.display(),
                actual.display()
            ),
            Self::Size {
                golden,
                expected,
                actual,
            } => write!(
                f,
                "image is {}x{} but golden image {} is {}x{}",
                actual.0,
                actual.1,
                golden.display(),
                expected.0,
                expected.1
            ),
            Self::Mismatch {
                golden,
                actual,
                diff,
                comparison,
                tolerance,
            } => write!(
                f,
                "image differs from {}: {} of {} pixels ({:.3}%, allowed {:.3}%) differ by more than {} \
                 (largest difference {}); actual image: {}, diff: {}; if the change is intended, rerun with TICKWORK_BLESS=1",
                golden.display(),
                comparison.differing,
                comparison.total,
                100.0 * comparison.fraction(),
                100.0 * tolerance.max_fraction,
                tolerance.channel,
                comparison.max_channel_difference,
                actual.display(),
                diff.display()
            ),
            Self::Io { path, message } => write!(f, "{}: {message}", path.display()),
        }
    }
}

impl std::error::Error for GoldenError {}

/// A directory of golden images and one for failed comparisons' output.
#[derive(Clone, Debug)]
pub struct GoldenImages {
    /// Where golden images live (`NAME.png`).
    pub dir: PathBuf,
    /// Where actual and diff images of mismatches are written.
    pub output: PathBuf,
    /// The tolerance (default: [`Tolerance::default`]).
    pub tolerance: Tolerance,
}

impl GoldenImages {
    /// Golden images in `dir`, mismatches written to `output`.
    #[must_use]
    pub fn new(dir: impl Into<PathBuf>, output: impl Into<PathBuf>) -> Self {
        Self {
            dir: dir.into(),
            output: output.into(),
            tolerance: Tolerance::default(),
        }
    }

    /// The same directories with another tolerance.
    #[must_use]
    pub fn with_tolerance(mut self, tolerance: Tolerance) -> Self {
        self.tolerance = tolerance;
        self
    }

    /// Whether `TICKWORK_BLESS=1` asks for golden images to be rewritten.
    #[must_use]
    pub fn blessing() -> bool {
        crate::platform::env_var("TICKWORK_BLESS").is_some_and(|v| v == "1")
    }

    /// Checks `image` against golden image `name`, or (when blessing)
    /// writes it as the golden image.
    ///
    /// # Errors
    /// [`GoldenError`] naming the golden image, the actual image and the
    /// diff written for inspection.
    pub fn check(&self, name: &str, image: &RgbaImage) -> Result<Comparison, GoldenError> {
        let golden = self.dir.join(format!("{name}.png"));
        if Self::blessing() {
            save(&golden, image)?;
            return Ok(Comparison {
                differing: 0,
                total: u64::from(image.width()) * u64::from(image.height()),
                max_channel_difference: 0,
            });
        }
        let actual_path = self.output.join(format!("{name}.actual.png"));
        if !golden.exists() {
            save(&actual_path, image)?;
            return Err(GoldenError::Missing {
                golden,
                actual: actual_path,
            });
        }
        let expected = image::open(&golden)
            .map_err(|error| GoldenError::Io {
                path: golden.clone(),
                message: error.to_string(),
            })?
            .to_rgba8();
        let Some(comparison) = compare(image, &expected, self.tolerance) else {
            return Err(GoldenError::Size {
                golden,
                expected: expected.dimensions(),
                actual: image.dimensions(),
            });
        };
        if comparison.fraction() <= self.tolerance.max_fraction {
            return Ok(comparison);
        }
        let diff_path = self.output.join(format!("{name}.diff.png"));
        save(&actual_path, image)?;
        save(&diff_path, &diff_image(image, &expected, self.tolerance.channel))?;
        Err(GoldenError::Mismatch {
            golden,
            actual: actual_path,
            diff: diff_path,
            comparison,
            tolerance: self.tolerance,
        })
    }
}

/// Differing pixels in red over the dimmed grey golden image.
#[must_use]
pub fn diff_image(actual: &RgbaImage, expected: &RgbaImage, channel: u8) -> RgbaImage {
    RgbaImage::from_fn(expected.width(), expected.height(), |x, y| {
        let e = expected.get_pixel(x, y);
        if channel_difference(actual.get_pixel(x, y), e) > channel {
            Rgba([255, 0, 0, 255])
        } else {
            let grey = ((u16::from(e.0[0]) + u16::from(e.0[1]) + u16::from(e.0[2])) / 9) as u8;
            Rgba([grey, grey, grey, 255])
        }
    })
}

fn save(path: &Path, image: &RgbaImage) -> Result<(), GoldenError> {
    let io = |message: String| GoldenError::Io {
        path: path.to_path_buf(),
        message,
    };
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).map_err(|e| io(e.to_string()))?;
    }
    image.save(path).map_err(|e| io(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_golden_image_says_how_to_bless_it_even_in_debug_form() {
        let missing = GoldenError::Missing {
            golden: PathBuf::from("tests/golden/ball.png"),
            actual: PathBuf::from("target/ball.actual.png"),
        };
        let shown = format!("{missing:?}");
        assert_eq!(shown, missing.to_string());
        assert!(
            shown.contains("tests/golden/ball.png") && shown.contains("TICKWORK_BLESS=1"),
            "{shown}"
        );
    }

    #[test]
    fn counts_pixels_beyond_the_channel_threshold() {
        let a = RgbaImage::from_pixel(10, 10, Rgba([100, 100, 100, 255]));
        let mut b = a.clone();
        b.put_pixel(0, 0, Rgba([110, 100, 100, 255])); // within 24
        b.put_pixel(1, 0, Rgba([100, 160, 100, 255])); // beyond
        let c = compare(&a, &b, Tolerance::default()).expect("same size");
        assert_eq!((c.differing, c.total, c.max_channel_difference), (1, 100, 60));
        assert!(compare(&a, &RgbaImage::new(9, 10), Tolerance::default()).is_none());
        let diff = diff_image(&a, &b, 24);
        assert_eq!(diff.get_pixel(1, 0), &Rgba([255, 0, 0, 255]));
        assert_eq!(diff.get_pixel(0, 0), &Rgba([34, 34, 34, 255])); // (110 + 100 + 100) / 9
    }
}
