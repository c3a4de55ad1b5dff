//! `tickwork web build|serve`: any game crate as a web page.
//!
//! Reads the crate ([`Project`]), refuses at once what cannot become a
//! page (no binary, two and no `--bin`, no Tickwork, an `--out` folder of
//! other files), picks the toolchain ([`Toolchain`]), builds the wasm with
//! every flag a page's determinism needs, runs `wasm-bindgen` at the
//! version the game's `Cargo.lock` pins, and writes the site ([`site`]);
//! `serve` then serves it on localhost. `scripts/web` builds the demos
//! through this same code.

pub mod error;
pub mod serve;
pub mod site;
pub mod toolchain;

use std::path::PathBuf;

use clap::{Args, Subcommand};

pub use error::WebError;
pub use site::BuiltPage;
pub use toolchain::Toolchain;

use crate::cli::project::Project;

/// `tickwork web`'s arguments.
#[derive(Debug, Args)]
pub struct WebArgs {
    /// Build, or build and serve.
    #[command(subcommand)]
    pub action: WebAction,
}

/// What `tickwork web` does.
#[derive(Debug, Subcommand)]
pub enum WebAction {
    /// Build a game's page into a folder to upload as it is.
    Build(BuildArgs),
    /// Build a game's page, then serve it on localhost.
    Serve(ServeArgs),
}

/// Which game to build, and how (what `build` and `serve` share).
#[derive(Debug, Clone, Args)]
pub struct GameArgs {
    /// The game crate's Cargo.toml (default: the one cargo finds from here).
    #[arg(long)]
    pub manifest_path: Option<PathBuf>,
    /// The binary to build (default: the crate's only one); given several
    /// times, a page each and a landing page linking them.
    #[arg(long = "bin", value_name = "NAME")]
    pub bins: Vec<String>,
    /// Build with the release profile (smaller, faster pages).
    #[arg(long)]
    pub release: bool,
    /// Features of the game crate to turn on (as cargo's `--features`).
    #[arg(long)]
    pub features: Option<String>,
    /// Cargo's target directory for the wasm build (default: `wasm` in the
    /// game's target directory).
    #[arg(long)]
    pub target_dir: Option<PathBuf>,
}

/// `tickwork web build`'s arguments: the game, and where its site goes.
#[derive(Debug, Clone, Args)]
pub struct BuildArgs {
    /// The game and how to build it.
    #[command(flatten)]
    pub game: GameArgs,
    /// The folder to write the site into (a folder a build wrote is
    /// replaced; one holding other files is refused).
    #[arg(long)]
    pub out: PathBuf,
}

/// `tickwork web serve`'s arguments.
#[derive(Debug, Args)]
pub struct ServeArgs {
    /// The game and how to build it.
    #[command(flatten)]
    pub game: GameArgs,
    /// The folder to write the site into (default: `web` in the game's
    /// target directory).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// The port on localhost (0: any free port, printed).
    #[arg(long, default_value_t = 8000)]
    pub port: u16,
}

/// Runs `tickwork web`.
///
/// # Errors
/// [`WebError`] with what to change.
pub fn run(args: WebArgs) -> Result<(), WebError> {
    match args.action {
        WebAction::Build(build_args) => build(&build_args).map(drop),
        WebAction::Serve(serve_args) => {
            let out = match serve_args.out {
                Some(out) => out,
                None => Project::read(serve_args.game.manifest_path.as_deref())?
                    .target_directory
                    .join("web"),
            };
            let build_args = BuildArgs {
                game: serve_args.game,
                out,
            };
            build(&build_args)?;
            serve::serve(&build_args.out, serve_args.port)
        }
    }
}

/// Builds the site `args` asks for; returns its pages.
///
/// # Errors
/// [`WebError`]: a crate that cannot become a page (before anything is
/// built), a failed build, a file that cannot be written.
pub fn build(args: &BuildArgs) -> Result<Vec<BuiltPage>, WebError> {
    let started = std::time::Instant::now();
    let game = &args.game;
    let project = Project::read(game.manifest_path.as_deref())?;
    if !project.depends_on_tickwork {
        return Err(WebError::NotAGame {
            package: project.name.clone(),
            manifest: project.manifest.clone(),
        });
    }
    let bins = project.choose_bins(&game.bins)?;
    site::check_out(&args.out)?;
    let toolchain = Toolchain::choose()?;
    let target_dir = args
        .game
        .target_dir
        .clone()
        .unwrap_or_else(|| project.target_directory.join("wasm"));
    let profile = if game.release { "release" } else { "debug" };
    toolchain::say(&format!(
        "building {} for {} ({profile})",
        bins.join(" "),
        toolchain::WASM_TARGET
    ));
    let mut cargo = toolchain.cargo_build(&target_dir);
    cargo.arg("--manifest-path").arg(&project.manifest);
    for bin in &bins {
        cargo.args(["--bin", bin]);
    }
    if game.release {
        cargo.arg("--release");
    }
    if let Some(features) = &game.features {
        cargo.args(["--features", features]);
    }
    toolchain::run(&mut cargo)?;
    // The lock file exists now (the build wrote it where it was missing).
    let bindgen = toolchain::bindgen(&project.workspace_root.join("Cargo.lock"))?;
    let wasm_dir = target_dir.join(toolchain::WASM_TARGET).join(profile);
    let pages = site::write(&project, &bins, &wasm_dir, &bindgen, &args.out)?;
    toolchain::say(&format!(
        "built {} page{} into {} in {} s",
        pages.len(),
        if pages.len() == 1 { "" } else { "s" },
        args.out.display(),
        started.elapsed().as_secs()
    ));
    for page in &pages {
        toolchain::say(&format!(
            "  {}: {} ({} KiB gzipped, wasm + JS)",
            page.bin,
            page.page.display(),
            page.gzipped_bytes / 1024
        ));
    }
    Ok(pages)
}
