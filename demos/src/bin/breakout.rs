//! Breakout: Left/Right or the mouse move the paddle, Space serves; clear
//! the bricks. `--autopilot` plays by itself. See `tickwork_demos::breakout`.

use std::process::ExitCode;

use clap::Parser;
use tickwork::prelude::*;
use tickwork_demos::breakout::Breakout;

/// The shared options and the game's own.
#[derive(Parser)]
#[command(about = "Breakout on Tickwork: clear the bricks with a kinematic paddle.")]
struct Options {
    #[command(flatten)]
    run: RunOptions,
    /// Let the game move the paddle and serve by itself.
    #[arg(long)]
    autopilot: bool,
}

fn main() -> ExitCode {
    let options = Options::parse();
    exit_code(run(Breakout::new(options.autopilot), options.run))
}
