//! [`WebError`]: why `tickwork web` or `tickwork new` stopped, saying what
//! to change.

use std::error::Error;
use std::fmt;
use std::io;
use std::path::PathBuf;

/// Why `tickwork web build|serve` (or `tickwork new`) stopped.
#[derive(Debug)]
pub enum WebError {
    /// `--manifest-path` names no file.
    NoManifest(PathBuf),
    /// The manifest is a workspace's without a package of its own.
    VirtualManifest(PathBuf),
    /// `[package.metadata.tickwork.web]` has a field of the wrong kind.
    Metadata {
        /// The manifest.
        manifest: PathBuf,
        /// The field and what it should be.
        field: String,
    },
    /// The crate depends on neither `tickwork` nor `tickwork-engine`: it
    /// has no `Game` to make a page of.
    NotAGame {
        /// The package.
        package: String,
        /// Its manifest.
        manifest: PathBuf,
    },
    /// The built wasm never starts Tickwork's runner: `main` does not call
    /// `tickwork::run` with a `Game`.
    NoRun {
        /// The binary.
        bin: String,
    },
    /// The package has no binary.
    NoBin {
        /// The package.
        package: String,
        /// Its manifest.
        manifest: PathBuf,
    },
    /// The package has several binaries and `--bin` names none.
    SeveralBins {
        /// The package.
        package: String,
        /// Its binaries.
        bins: Vec<String>,
    },
    /// `--bin` names a binary the package does not have.
    NoSuchBin {
        /// The name given.
        name: String,
        /// The package.
        package: String,
        /// Its binaries.
        bins: Vec<String>,
    },
    /// The output folder holds files that no web build wrote.
    NotOurs(PathBuf),
    /// The folder `tickwork new` was asked to write into is not empty.
    NotEmpty(PathBuf),
    /// A name that cannot be a crate's.
    BadName {
        /// The name.
        name: String,
        /// Why not.
        why: &'static str,
    },
    /// `tickwork new` has no checkout of Tickwork to point a path
    /// dependency at.
    NoCheckout(PathBuf),
    /// A program could not be started.
    Spawn {
        /// The program.
        program: String,
        /// What the system said.
        source: io::Error,
    },
    /// A command ran and failed.
    Failed {
        /// The command line.
        command: String,
        /// Its exit status.
        status: std::process::ExitStatus,
    },
    /// Cargo could not do what was asked; its message is kept.
    Cargo {
        /// The command.
        doing: String,
        /// What cargo said.
        message: String,
    },
    /// `Cargo.lock` pins no `wasm-bindgen`, so the glue's version is unknown.
    NoBindgen(PathBuf),
    /// A file or folder could not be read or written.
    Io {
        /// What was being done, with the path.
        doing: String,
        /// What the system said.
        source: io::Error,
    },
}

impl fmt::Display for WebError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let list = |names: &[String]| names.join(", ");
        match self {
            Self::NoManifest(path) => write!(
                f,
                "{}: no such file; pass --manifest-path to a game's Cargo.toml",
                path.display()
            ),
            Self::VirtualManifest(path) => write!(
                f,
                "{} is a workspace without a package; pass --manifest-path to the game's own Cargo.toml",
                path.display()
            ),
            Self::Metadata { manifest, field } => {
                write!(f, "{}: [package.metadata.tickwork.web] {field}", manifest.display())
            }
            Self::NotAGame { package, manifest } => write!(
                f,
                "{package} ({}) depends on neither tickwork nor tickwork-engine, so it has no Game to build a page \
                 of; add tickwork to its [dependencies] (`tickwork new` writes a game that does)",
                manifest.display()
            ),
            Self::NoRun { bin } => write!(
                f,
                "{bin}: its main never calls tickwork::run with a Game, so its page would show nothing; \
                 end main with `exit_code(run(MyGame::default(), RunOptions::from_args()))`"
            ),
            Self::NoBin { package, manifest } => write!(
                f,
                "{package} has no binary ({}): a page runs a binary's main; add src/main.rs calling tickwork::run",
                manifest.display()
            ),
            Self::SeveralBins { package, bins } => write!(
                f,
                "{package} has {} binaries ({}): pass --bin NAME for each page to build",
                bins.len(),
                list(bins)
            ),
            Self::NoSuchBin { name, package, bins } => {
                write!(f, "--bin {name}: {package} has no such binary (it has: {})", list(bins))
            }
            Self::NotOurs(path) => write!(
                f,
                "--out {}: the folder holds files no web build wrote, and nothing was overwritten; \
                 name a new or empty folder",
                path.display()
            ),
            Self::NotEmpty(path) => write!(
                f,
                "{}: the folder is not empty, and nothing was written; name a new or empty folder",
                path.display()
            ),
            Self::BadName { name, why } => write!(f, "{name:?} cannot name a crate: {why}; pass --name NAME"),
            Self::NoCheckout(path) => write!(
                f,
                "this tickwork was built from {}, which is no longer a Tickwork checkout; pass --git URL or \
                 --version VERSION (or --tickwork-path PATH) for the game's dependency",
                path.display()
            ),
            Self::Spawn { program, .. } => write!(f, "cannot run {program}"),
            Self::Failed { command, status } => write!(f, "{command}: failed ({status})"),
            Self::Cargo { doing, message } => write!(f, "{doing}: {message}"),
            Self::NoBindgen(lock) => write!(
                f,
                "{}: no wasm-bindgen is pinned, so the JS glue's version is unknown; does the game depend on \
                 tickwork?",
                lock.display()
            ),
            Self::Io { doing, .. } => f.write_str(doing),
        }
    }
}

impl Error for WebError {
    fn source(&self) -> Option<&(dyn Error + 'static)> {
        match self {
            Self::Spawn { source, .. } | Self::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// [`WebError::Io`] for `doing` (a sentence naming the path).
pub(crate) fn io_error(doing: impl Into<String>) -> impl FnOnce(io::Error) -> WebError {
    let doing = doing.into();
    move |source| WebError::Io { doing, source }
}
