//! `tickwork`: the command line (see `tickwork --help`).

use clap::Parser;

fn main() -> std::process::ExitCode {
    // No threads yet: the environment may change.
    tickwork_engine::render::quiet_device_select_layer();
    // This thread steps the worlds: as the pool's thread 0, its parallel
    // steps allocate nothing.
    let _ = tickwork_engine::threads::join_thread_pool();
    tickwork_demos::cli::run(tickwork_demos::cli::Cli::parse())
}
