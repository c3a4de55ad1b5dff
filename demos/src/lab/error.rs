//! [`LabError`]: why `tickwork lab` stopped, with the system's or the
//! registry's error kept as its source.

use std::error::Error;
use std::fmt;
use std::io;
use std::path::PathBuf;

use tickwork_integrators::UnknownMethod;

/// Why a study of the lab stopped.
#[derive(Debug)]
pub enum LabError {
    /// `--problem` names no problem of the lab.
    UnknownProblem {
        /// The name as given.
        name: String,
        /// The problems' names.
        valid: Vec<&'static str>,
    },
    /// `--out` names a file, not a directory.
    OutIsFile(PathBuf),
    /// The output directory could not be created.
    CreateDir {
        /// The directory.
        path: PathBuf,
        /// What the system said.
        source: io::Error,
    },
    /// A file of an earlier run exists and `--force` was not given.
    Exists(PathBuf),
    /// A CSV or Markdown file could not be written.
    Write {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: io::Error,
    },
    /// The shipped chart font could not be read (a broken build).
    Font,
    /// A chart could not be drawn or written.
    Plot {
        /// The PNG file.
        path: PathBuf,
        /// What the plotting library said.
        source: Box<dyn Error + Send + Sync + 'static>,
    },
    /// A method of the registry could not be built.
    Method(UnknownMethod),
    /// The GPU column's step failed (the adapter's message).
    Gpu(String),
}

impl fmt::Display for LabError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::UnknownProblem { name, valid } => {
                write!(f, "unknown problem '{name}'; valid problems are: {}", valid.join(", "))
            }
            Self::OutIsFile(path) => write!(f, "--out: {} is a file; name a directory", path.display()),
            Self::CreateDir { path, .. } => write!(f, "cannot create the directory {}", path.display()),
            Self::Exists(path) => write!(
                f,
                "{}: exists; pass --force to overwrite the lab's files",
                path.display()
            ),
            Self::Write { path, .. } => write!(f, "cannot write {}", path.display()),
            Self::Font => f.write_str("the shipped font engine/fonts/DejaVuSans.ttf could not be read"),
            Self::Plot { path, .. } => write!(f, "cannot draw the chart {}", path.display()),
            Self::Method(e) => write!(f, "cannot build the method '{}'", e.name),
            Self::Gpu(message) => write!(f, "the GPU column: {message}"),
        }
    }
}

impl Error for LabError {
    fn source(&self) -> Option<&(dyn Error + 'static)> {
        match self {
            Self::CreateDir { source, .. } | Self::Write { source, .. } => Some(source),
            Self::Plot { source, .. } => Some(source.as_ref()),
            Self::Method(e) => Some(e),
            Self::UnknownProblem { .. } | Self::OutIsFile(_) | Self::Exists(_) | Self::Font | Self::Gpu(_) => None,
        }
    }
}

impl From<UnknownMethod> for LabError {
    fn from(e: UnknownMethod) -> Self {
        Self::Method(e)
    }
}
