//! Reading a text file the user names (a scene, a recording) with a size
//! limit: `/dev/zero`, or a file of gigabytes, was once read until memory
//! ran out, taking the process (or the machine) with it.

use std::io::Read;
use std::path::Path;

/// Reads `path` as UTF-8 text of at most `limit` bytes; `limit_name` (the
/// constant that sets it) is named when the file is larger.
///
/// # Errors
/// What went wrong, for the caller to prefix with the file: unreadable,
/// larger than the limit, or not UTF-8 (with the byte where it stops being).
pub(crate) fn read_limited(path: &Path, limit: u64, limit_name: &str) -> Result<String, String> {
    // Read at most one byte past the limit, to tell "at the limit" from "past it".
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(limit + 1).read_to_end(&mut bytes))
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > limit {
        return Err(format!("it is larger than the limit of {limit} bytes ({limit_name})"));
    }
    String::from_utf8(bytes).map_err(|e| format!("not UTF-8 text (at byte {})", e.utf8_error().valid_up_to()))
}
