//! Breakout's `main`: the shared options and the game's own `--autopilot`.

use clap::Parser;
use tickwork::prelude::*;
use tickwork_demos::breakout::Breakout;

/// Breakout on Tickwork: clear the bricks with a kinematic paddle.
#[derive(Parser)]
struct Options {
    #[command(flatten)]
    run: RunOptions,
    /// Let the game move the paddle and serve by itself.
    #[arg(long)]
    autopilot: bool,
}

fn main() -> std::process::ExitCode {
    let options = parse_args::<Options>();
    exit_code(run(Breakout::new(options.autopilot), options.run))
}
