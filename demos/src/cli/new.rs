//! `tickwork new PATH`: a game crate to start from. A small `Game` (keep
//! the ball in the air), its `main`, a headless test against a golden
//! image, a recording and its replay test, a README with the commands, and
//! a dependency on Tickwork the user chooses: a path to this checkout (the
//! default, with its `Cargo.lock`, so the game builds the versions Tickwork
//! was tested with), a git URL, or a version.

use std::path::{Path, PathBuf};

use clap::Args;

use super::web::WebError;
use super::web::error::io_error;

/// `tickwork new`'s arguments.
#[derive(Debug, Args)]
pub struct NewArgs {
    /// The folder to write the game into (new, or empty).
    pub path: PathBuf,
    /// The crate's name (default: the folder's name).
    #[arg(long)]
    pub name: Option<String>,
    /// Depend on Tickwork from this checkout (default: the one this
    /// `tickwork` was built from).
    #[arg(long, conflicts_with_all = ["git", "version"])]
    pub tickwork_path: Option<PathBuf>,
    /// Depend on Tickwork from this git repository.
    #[arg(long, conflicts_with = "version")]
    pub git: Option<String>,
    /// With `--git`: the branch to follow.
    #[arg(long, requires = "git", conflicts_with = "rev")]
    pub branch: Option<String>,
    /// With `--git`: the commit to pin.
    #[arg(long, requires = "git")]
    pub rev: Option<String>,
    /// Depend on this version of Tickwork from crates.io.
    #[arg(long)]
    pub version: Option<String>,
}

/// The template's files: path in the new crate, text.
const TEMPLATE: [(&str, &str); 7] = [
    ("Cargo.toml", include_str!("../../templates/game/Cargo.toml.in")),
    ("src/lib.rs", include_str!("../../templates/game/src/lib.rs")),
    ("src/main.rs", include_str!("../../templates/game/src/main.rs")),
    ("tests/game.rs", include_str!("../../templates/game/tests/game.rs")),
    (
        "recordings/kicks.ron",
        include_str!("../../templates/game/recordings/kicks.ron"),
    ),
    ("README.md", include_str!("../../templates/game/README.md")),
    (".gitignore", include_str!("../../templates/game/gitignore")),
];
/// The golden image of the template's first second (lavapipe and every
/// conforming adapter draw it within the default tolerance).
const GOLDEN: &[u8] = include_bytes!("../../templates/game/tests/golden/first_second.png");

/// Where Tickwork comes from, as the game's `[dependencies]` line says.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// A checkout on this machine.
    Path(PathBuf),
    /// A git repository, at a branch or commit.
    Git {
        /// The URL.
        url: String,
        /// `branch = ...` or `rev = ...`, if any.
        at: Option<(&'static str, String)>,
    },
    /// A version on crates.io.
    Version(String),
}

impl Source {
    /// The `tickwork = ...` line of the game's `Cargo.toml`.
    #[must_use]
    pub fn dependency(&self) -> String {
        match self {
            Self::Path(path) => format!("tickwork = {{ path = {:?} }}", path.display().to_string()),
            Self::Git { url, at: None } => format!("tickwork = {{ git = {url:?} }}"),
            Self::Git {
                url,
                at: Some((key, value)),
            } => format!("tickwork = {{ git = {url:?}, {key} = {value:?} }}"),
            Self::Version(version) => format!("tickwork = {version:?}"),
        }
    }
}

/// What `tickwork new` wrote.
#[derive(Clone, Debug)]
pub struct NewGame {
    /// The crate's folder.
    pub path: PathBuf,
    /// The crate's name.
    pub name: String,
    /// Where Tickwork comes from.
    pub source: Source,
}

/// Writes the game crate `args` asks for, then says what to run.
///
/// # Errors
/// [`WebError::NotEmpty`] (nothing written), [`WebError::BadName`],
/// [`WebError::NoCheckout`], or the file that could not be written.
pub fn run(args: &NewArgs) -> Result<NewGame, WebError> {
    let game = write(args)?;
    let shown = game.path.display();
    println!(
        "tickwork new: wrote the game {} into {shown}, depending on {}",
        game.name,
        game.source.dependency()
    );
    println!("  cd {shown}");
    println!("  cargo run --release                 # play it in a window (--headless: frames off-screen)");
    println!("  cargo test                          # its golden image and its recording");
    println!("  tickwork web serve --release        # play it in a browser");
    Ok(game)
}

/// Writes the game crate without printing.
///
/// # Errors
/// As [`run`].
pub fn write(args: &NewArgs) -> Result<NewGame, WebError> {
    let path = &args.path;
    let empty = match std::fs::read_dir(path) {
        Ok(mut entries) => entries.next().is_none(),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => true,
        Err(_) => false,
    };
    if !empty {
        return Err(WebError::NotEmpty(path.clone()));
    }
    let name = match &args.name {
        Some(name) => name.clone(),
        None => path
            .canonicalize()
            .unwrap_or_else(|_| path.clone())
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
    };
    check_name(&name)?;
    let source = source(args)?;
    let ty = type_name(&name);
    let url = match &source {
        Source::Git { url, .. } => url.clone(),
        Source::Path(path) => path.display().to_string(),
        Source::Version(_) => "https://crates.io/crates/tickwork".to_owned(),
    };
    let fill = |text: &str| {
        text.replace("@NAME@", &name)
            .replace("@CRATE@", &name.replace('-', "_"))
            .replace("@TYPE@", &ty)
            .replace("@DEPENDENCY@", &source.dependency())
            .replace("@TICKWORK_URL@", &url)
    };
    let mut files: Vec<(PathBuf, Vec<u8>)> = TEMPLATE
        .iter()
        .map(|(file, text)| (path.join(file), fill(text).into_bytes()))
        .collect();
    files.push((path.join("tests/golden/first_second.png"), GOLDEN.to_vec()));
    if let Source::Path(checkout) = &source {
        // The versions Tickwork was tested with; cargo drops what the game
        // does not use on its first build.
        let lock = checkout.join("Cargo.lock");
        if let Ok(text) = std::fs::read(&lock) {
            files.push((path.join("Cargo.lock"), text));
        }
    }
    for (file, bytes) in files {
        if let Some(parent) = file.parent() {
            std::fs::create_dir_all(parent).map_err(io_error(format!("cannot create {}", parent.display())))?;
        }
        std::fs::write(&file, bytes).map_err(io_error(format!("cannot write {}", file.display())))?;
    }
    Ok(NewGame {
        path: path.clone(),
        name,
        source,
    })
}

/// Where the game's Tickwork comes from.
fn source(args: &NewArgs) -> Result<Source, WebError> {
    if let Some(url) = &args.git {
        let at = match (&args.branch, &args.rev) {
            (Some(branch), _) => Some(("branch", branch.clone())),
            (None, Some(rev)) => Some(("rev", rev.clone())),
            (None, None) => None,
        };
        return Ok(Source::Git { url: url.clone(), at });
    }
    if let Some(version) = &args.version {
        return Ok(Source::Version(version.clone()));
    }
    let checkout = args
        .tickwork_path
        .clone()
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join(".."));
    let is_tickwork = std::fs::read_to_string(checkout.join("Cargo.toml"))
        .is_ok_and(|text| text.lines().any(|l| l.trim() == "name = \"tickwork\""));
    if !is_tickwork {
        return Err(WebError::NoCheckout(checkout));
    }
    let checkout = checkout
        .canonicalize()
        .map_err(io_error(format!("cannot read {}", checkout.display())))?;
    Ok(Source::Path(checkout))
}

/// Refuses a name cargo would refuse, or that would shadow the dependency.
fn check_name(name: &str) -> Result<(), WebError> {
    let bad = |why| {
        Err(WebError::BadName {
            name: name.to_owned(),
            why,
        })
    };
    let Some(first) = name.chars().next() else {
        return bad("it is empty");
    };
    if !first.is_ascii_alphabetic() {
        return bad("it must start with a letter");
    }
    if !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_') {
        return bad("only ASCII letters, digits, - and _ may name a crate");
    }
    if name.len() > 64 {
        return bad("cargo takes at most 64 characters");
    }
    if matches!(name, "tickwork" | "tickwork-engine" | "tickwork-integrators") {
        return bad("it is the name of a Tickwork crate the game depends on");
    }
    if matches!(
        name,
        "test" | "core" | "std" | "alloc" | "proc_macro" | "self" | "crate" | "super"
    ) {
        return bad("the name is reserved by Rust");
    }
    Ok(())
}

/// The game's type: the name in CamelCase, ending in `Game` (so it never
/// shadows a prelude type such as `World`).
fn type_name(name: &str) -> String {
    let mut ty: String = name
        .split(['-', '_'])
        .filter(|part| !part.is_empty())
        .map(|part| {
            let mut chars = part.chars();
            chars
                .next()
                .map(|first| first.to_ascii_uppercase().to_string() + chars.as_str())
                .unwrap_or_default()
        })
        .collect();
    if !ty.ends_with("Game") {
        ty.push_str("Game");
    }
    ty
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_become_types_that_shadow_nothing() {
        assert_eq!(type_name("my-game"), "MyGame");
        assert_eq!(type_name("keepy"), "KeepyGame");
        assert_eq!(type_name("world"), "WorldGame");
        assert_eq!(type_name("space__race"), "SpaceRaceGame");
    }

    #[test]
    fn names_cargo_would_refuse_are_refused_with_why() {
        assert!(check_name("my-game").is_ok());
        let why = |name: &str| check_name(name).unwrap_err().to_string();
        assert_eq!(
            why("1up"),
            "\"1up\" cannot name a crate: it must start with a letter; pass --name NAME"
        );
        assert!(why("my game").contains("only ASCII letters"));
        assert!(why("tickwork").contains("a Tickwork crate"));
        assert!(why("").contains("empty"));
        assert!(why("test").contains("reserved"));
    }

    #[test]
    fn each_source_is_a_dependency_line_cargo_reads() {
        assert_eq!(
            Source::Path("/src/tickwork".into()).dependency(),
            "tickwork = { path = \"/src/tickwork\" }"
        );
        let git = Source::Git {
            url: "https://example.org/tickwork.git".into(),
            at: Some(("rev", "abc123".into())),
        };
        assert_eq!(
            git.dependency(),
            "tickwork = { git = \"https://example.org/tickwork.git\", rev = \"abc123\" }"
        );
        assert_eq!(Source::Version("0.1".into()).dependency(), "tickwork = \"0.1\"");
    }
}
