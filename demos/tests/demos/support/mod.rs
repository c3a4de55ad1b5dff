//! What the networked tests share: starting a Rally host and learning its
//! port from what it prints.

use std::io::{BufRead, BufReader};
use std::process::{Child, ChildStdout, Command};

/// A started host, its output after the first line, that line, and the
/// port it listens on.
pub struct Host {
    pub child: Child,
    pub output: BufReader<ChildStdout>,
    pub first: String,
    pub port: String,
}

/// Starts `command` (a `--host 0` run with piped stdout) and reads its
/// first line, where it says which port it listens on before it waits:
/// the signal for a joiner to start.
pub fn start_host(command: &mut Command) -> Host {
    let mut child = command.spawn().expect("the host starts");
    let mut output = BufReader::new(child.stdout.take().expect("stdout piped"));
    let mut first = String::new();
    output.read_line(&mut first).expect("the host's first line");
    let port = first
        .split("hosting on port ")
        .nth(1)
        .and_then(|s| s.split(';').next())
        .unwrap_or_else(|| panic!("no port in {first:?}"))
        .to_owned();
    Host {
        child,
        output,
        first,
        port,
    }
}
