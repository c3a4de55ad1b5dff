//! Rally: two paddles, one ball, first to five. Alone the right paddle
//! plays itself; `--host PORT` and `--join ADDR` play a match over the
//! network with rollback. See `tickwork_demos::rally`.

use std::process::ExitCode;

use tickwork::prelude::*;
use tickwork_demos::rally::Rally;

fn main() -> ExitCode {
    exit_code(run(Rally::default(), RunOptions::from_args()))
}
