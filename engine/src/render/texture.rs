//! Images to draw sprites from: RGBA8 pixels in sRGB, decoded on the CPU
//! once (from a PNG file natively, or PNG bytes embedded with
//! `include_bytes!` or fetched by a page) and uploaded by the renderer the
//! first frame they are drawn.

use core::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// The largest side a texture may have, in pixels: what every adapter
/// draws, WebGL2's included (its `max_texture_dimension_2d` is at least
/// 2048 there and 8192 natively).
pub const MAX_TEXTURE_SIDE: u32 = 2048;

/// An image for sprites: cheap to clone (the pixels are shared), drawn
/// with [`Draw::sprite`](crate::app::Draw::sprite).
#[derive(Clone)]
pub struct Texture {
    id: u64,
    width: u32,
    height: u32,
    pixels: Arc<[u8]>,
}

impl fmt::Debug for Texture {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Texture #{} ({} x {})", self.id, self.width, self.height)
    }
}

impl PartialEq for Texture {
    fn eq(&self, other: &Self) -> bool {
        self.id == other.id
    }
}

/// A texture that could not be made.
#[derive(Debug)]
pub enum TextureError {
    /// The file could not be read.
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        error: std::io::Error,
    },
    /// The bytes are not a PNG image the decoder reads.
    Decode {
        /// The decoder's message.
        message: String,
    },
    /// A side is 0 or past [`MAX_TEXTURE_SIDE`].
    Size {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// RGBA pixels of the wrong length for the size.
    Length {
        /// Bytes given.
        bytes: usize,
        /// Bytes the size needs (4 a pixel).
        expected: usize,
    },
}

impl fmt::Display for TextureError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Read { path, error } => write!(f, "texture {}: {error}", path.display()),
            Self::Decode { message } => write!(f, "texture: not a PNG image the decoder reads: {message}"),
            Self::Size { width, height } => write!(
                f,
                "texture of {width} x {height} pixels: each side must be 1 to {MAX_TEXTURE_SIDE} \
                 (MAX_TEXTURE_SIDE, what every adapter draws); split it into an atlas of smaller ones"
            ),
            Self::Length { bytes, expected } => write!(
                f,
                "texture: {bytes} bytes of RGBA pixels, but its size needs {expected} (4 a pixel)"
            ),
        }
    }
}

impl std::error::Error for TextureError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Read { error, .. } => Some(error),
            _ => None,
        }
    }
}

impl Texture {
    /// A texture of `width` x `height` pixels, `pixels` in rows from the
    /// top, 4 bytes a pixel (sRGB red, green, blue, straight alpha).
    ///
    /// # Errors
    /// [`TextureError::Size`] or [`TextureError::Length`].
    pub fn from_rgba(width: u32, height: u32, pixels: Vec<u8>) -> Result<Self, TextureError> {
        if !(1..=MAX_TEXTURE_SIDE).contains(&width) || !(1..=MAX_TEXTURE_SIDE).contains(&height) {
            return Err(TextureError::Size { width, height });
        }
        // Both sides at most 2048: the product fits any usize.
        let expected = width as usize * height as usize * 4;
        if pixels.len() != expected {
            return Err(TextureError::Length {
                bytes: pixels.len(),
                expected,
            });
        }
        static NEXT: AtomicU64 = AtomicU64::new(0);
        Ok(Self {
            id: NEXT.fetch_add(1, Ordering::Relaxed),
            width,
            height,
            pixels: pixels.into(),
        })
    }

    /// A texture from a PNG image's bytes (embedded with `include_bytes!`,
    /// or fetched by a page).
    ///
    /// # Errors
    /// [`TextureError::Decode`] for bytes that are not a PNG image,
    /// [`TextureError::Size`] for one too large.
    pub fn from_png(bytes: &[u8]) -> Result<Self, TextureError> {
        let image = image::load_from_memory_with_format(bytes, image::ImageFormat::Png)
            .map_err(|e| TextureError::Decode { message: e.to_string() })?;
        let (width, height) = (image.width(), image.height());
        if !(1..=MAX_TEXTURE_SIDE).contains(&width) || !(1..=MAX_TEXTURE_SIDE).contains(&height) {
            return Err(TextureError::Size { width, height });
        }
        Self::from_rgba(width, height, image.into_rgba8().into_raw())
    }

    /// A texture from a PNG asset file: natively read from disk, in a page
    /// the bytes it fetched for `path` (list the path in
    /// [`Game::assets`](crate::app::Game::assets)); a relative path is
    /// found as [`platform::read_asset`](crate::platform::read_asset) says.
    ///
    /// # Errors
    /// [`TextureError::Read`] naming the file, or as
    /// [`from_png`](Self::from_png).
    pub fn load(path: impl AsRef<Path>) -> Result<Self, TextureError> {
        let path = path.as_ref();
        let bytes = crate::platform::read_asset(path).map_err(|error| TextureError::Read {
            path: path.to_path_buf(),
            error,
        })?;
        Self::from_png(&bytes)
    }

    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The pixels, RGBA8 sRGB, rows from the top.
    #[must_use]
    pub fn pixels(&self) -> &[u8] {
        &self.pixels
    }

    /// This texture's identity (clones share it): what the renderer keys
    /// its upload by.
    pub(crate) fn id(&self) -> u64 {
        self.id
    }
}
