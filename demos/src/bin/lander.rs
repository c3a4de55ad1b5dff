//! Lunar lander: Left/Right rotate, Up fires the engine, land gently on the
//! green pad; Enter flies again. See `tickwork_demos::lander`.

use std::process::ExitCode;

use tickwork::prelude::*;
use tickwork_demos::lander::Lander;

fn main() -> ExitCode {
    exit_code(run(Lander::default(), RunOptions::from_args()))
}
