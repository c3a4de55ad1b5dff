//! `tickwork`: the command line (see `tickwork --help`).

use clap::Parser;

fn main() -> std::process::ExitCode {
    tickwork_demos::cli::run(tickwork_demos::cli::Cli::parse())
}
