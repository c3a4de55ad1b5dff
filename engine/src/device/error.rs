//! [`RenderError`]: why a frame could not be drawn (no adapter, a device
//! failure, a size, a setting, a window surface or a file), each said in
//! words a user can act on.

use std::fmt;

/// Why a frame could not be drawn.
#[derive(Debug)]
pub enum RenderError {
    /// No adapter on any backend tried.
    NoAdapter {
        /// The backends tried.
        backends: Vec<&'static str>,
        /// wgpu's reason.
        reason: String,
    },
    /// The adapter refused a device, or the device failed.
    Device(String),
    /// A target size that cannot be drawn.
    Size {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// The device's largest texture side.
        max: u32,
    },
    /// A renderer setting or frame input out of range.
    Config(String),
    /// A window surface could not be created or configured.
    Surface(String),
    /// A file could not be written.
    Io {
        /// The file.
        path: std::path::PathBuf,
        /// What went wrong.
        message: String,
    },
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoAdapter { backends, reason } => {
                write!(
                    f,
                    "no graphics adapter found (backends tried: {}; wgpu says: {reason})",
                    if backends.is_empty() {
                        "none: is WGPU_BACKEND set to an empty or unknown value?".to_string()
                    } else {
                        backends.join(", ")
                    }
                )?;
                if cfg!(target_os = "linux") {
                    write!(
                        f,
                        "; for a software adapter install Mesa's Vulkan driver \
                         (Debian/Ubuntu: `apt-get install mesa-vulkan-drivers libvulkan1`) \
                         or its GL driver (`libegl1 libegl-mesa0 libgl1-mesa-dri`)"
                    )?;
                }
                Ok(())
            }
            Self::Device(message) => write!(f, "graphics device error: {message}"),
            Self::Size { width, height, max } => write!(
                f,
                "cannot render a {width}x{height} image: both sides must be between 1 and {max} pixels"
            ),
            Self::Config(message) => write!(f, "renderer: {message}"),
            Self::Surface(message) => write!(f, "window surface: {message}"),
            Self::Io { path, message } => write!(f, "{}: {message}", path.display()),
        }
    }
}

impl std::error::Error for RenderError {}
