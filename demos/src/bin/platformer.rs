//! The platformer's `main`: the shared options and the game's own `--autopilot`.

use clap::Parser;
use tickwork::prelude::*;
use tickwork_demos::platformer::Platformer;

/// A platformer on Tickwork: a Tiled level, coins, spikes, a ferry, a flag.
#[derive(Parser)]
struct Options {
    #[command(flatten)]
    run: RunOptions,
    /// Let the game play itself.
    #[arg(long)]
    autopilot: bool,
}

fn main() -> std::process::ExitCode {
    let options = parse_args::<Options>();
    exit_code(run(Platformer::new(options.autopilot), options.run))
}
