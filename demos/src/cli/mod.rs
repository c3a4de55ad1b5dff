//! The `tickwork` command line: one file per subcommand, and `error.rs`
//! for [`CliError`], what they all return.

pub mod error;
pub mod integrators;
pub mod new;
pub mod project;
pub mod render;
pub mod signal;
pub mod sim;
pub mod web;

use clap::{Parser, Subcommand};

pub use error::{CliError, report};

/// Tickwork: a fixed-timestep game loop with verified numerical integrators.
#[derive(Debug, Parser)]
#[command(
    name = "tickwork",
    version,
    about = "Tickwork: a fixed-timestep game loop with verified, comparable numerical integrators.",
    long_about = None
)]
pub struct Cli {
    /// What to do (default: list the integrators).
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// List every integration method with its order, cost and properties.
    Integrators(integrators::IntegratorsArgs),
    /// Run a scene headless (no window, no GPU): a CSV trace and a summary.
    Sim(sim::SimArgs),
    /// Compare every method: convergence, energy, stability, cost and bouncing plots and tables.
    Lab(crate::lab::LabArgs),
    /// Draw a scene off-screen through the fixed clock and interpolation:
    /// PNG frames and an optional GIF.
    Render(render::RenderArgs),
    /// Play a scene in a window (Space pause, . step, +/- speed, Tab or 1-9
    /// integrator, R reset, F12 screenshot).
    View(render::WindowArgs),
    /// Write a new game crate: a Game, its tests, a recording, a README.
    New(new::NewArgs),
    /// Build any game crate as a web page (`build`), or build and serve it
    /// on localhost (`serve`).
    Web(web::WebArgs),
    /// Run the signalling server players meet through for a match over
    /// WebRTC (`--room ws://HOST:PORT/ROOM`, a page's `?room=`).
    Signal(signal::SignalArgs),
}

/// Runs the command line; returns the process exit code. An error is
/// printed as [`report`] writes it: the error, then each of its causes.
pub fn run(cli: Cli) -> std::process::ExitCode {
    match execute(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("{}", report(&error));
            std::process::ExitCode::FAILURE
        }
    }
}

/// Runs the command line's subcommand, printing its output.
///
/// # Errors
/// The [`CliError`] of the subcommand that failed.
pub fn execute(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Some(Command::Integrators(args)) => {
            integrators::run(&args, &mut std::io::stdout().lock()).map_err(CliError::Output)
        }
        Some(Command::Sim(args)) => sim::run(&args, &mut std::io::stdout().lock()),
        Some(Command::Lab(args)) => {
            let written = crate::lab::run(&args)?;
            for file in written.files {
                println!("wrote {}", file.display());
            }
            Ok(())
        }
        Some(Command::Render(args)) => render::render(&args),
        Some(Command::View(args)) => render::view(&args),
        Some(Command::New(args)) => new::run(&args).map(drop).map_err(CliError::Web),
        Some(Command::Web(args)) => web::run(args).map_err(CliError::Web),
        Some(Command::Signal(args)) => signal::run(&args),
        None => integrators::run(&integrators::IntegratorsArgs::default(), &mut std::io::stdout().lock())
            .map_err(CliError::Output),
    }
}
