//! @NAME@'s `main`: a window where there is a display, else off-screen
//! frames (`--headless`); a page in a browser (`tickwork web serve`).

use tickwork::prelude::*;

fn main() -> std::process::ExitCode {
    exit_code(run(@CRATE@::@TYPE@::default(), RunOptions::from_args()))
}
