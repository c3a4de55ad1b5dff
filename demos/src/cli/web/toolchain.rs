//! The tools a page is built with, found or installed: a Rust that builds
//! for `wasm32-unknown-unknown` ([`Toolchain`]) and `wasm-bindgen` at the
//! version the game's `Cargo.lock` pins ([`bindgen`]).
//!
//! Why two toolchains: rustup's `wasm32-unknown-unknown` target is the
//! usual one (`rustup target add wasm32-unknown-unknown`); where it cannot
//! be downloaded (CI's machines reach package registries only), Debian's
//! web-browser Rust (`rustc-web`) can be installed, and it builds the
//! standard library from its own source (`-Zbuild-std`).

use std::path::{Path, PathBuf};
use std::process::Command;

use super::error::{WebError, io_error};

/// The target a page's wasm is built for.
pub const WASM_TARGET: &str = "wasm32-unknown-unknown";

/// Debian's packages of the web-browser Rust, and the linker it needs
/// (`rust-lld` links to `lld-22`, which nothing else pulls in).
const DEBIAN_WEB_RUST: [&str; 5] = [
    "rustc-web",
    "cargo-web",
    "libstd-rust-web-dev",
    "rust-web-src",
    "lld-22",
];

/// The same SIMD width as x86_64's SSE2, so glam takes its vector paths on
/// both and a page's checksums are the native build's (ARCHITECTURE,
/// "Determinism across platforms").
pub const SIMD_FLAG: &str = "-C target-feature=+simd128";

/// Which Rust builds the wasm.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Toolchain {
    /// rustup's toolchain with its `wasm32-unknown-unknown` target.
    Rustup,
    /// Debian's `rustc-web`, building the standard library from source.
    DebianWeb,
}

impl Toolchain {
    /// rustup's target where installed, else Debian's web Rust (installed
    /// here if missing, through apt-get).
    ///
    /// # Errors
    /// [`WebError`] where apt-get cannot install the packages.
    pub fn choose() -> Result<Self, WebError> {
        let rustup_has_target = Command::new("rustup")
            .args(["target", "list", "--installed"])
            .output()
            .is_ok_and(|o| {
                o.status.success()
                    && String::from_utf8_lossy(&o.stdout)
                        .lines()
                        .any(|l| l.trim() == WASM_TARGET)
            });
        if rustup_has_target {
            say(&format!("toolchain: rustup's {WASM_TARGET} target"));
            return Ok(Self::Rustup);
        }
        say(&format!(
            "toolchain: rustup has no {WASM_TARGET} target here; using Debian's rustc-web with -Zbuild-std"
        ));
        apt_install(&DEBIAN_WEB_RUST)?;
        Ok(Self::DebianWeb)
    }

    /// `cargo build` for the browser, with every flag a page's determinism
    /// needs; the caller adds the package, binaries and profile.
    pub fn cargo_build(self, target_dir: &Path) -> Command {
        let mut rustflags = std::env::var("RUSTFLAGS").unwrap_or_default();
        if !rustflags.contains("+simd128") {
            rustflags = format!("{rustflags} {SIMD_FLAG}").trim().to_owned();
        }
        let mut command = match self {
            Self::Rustup => {
                let mut command = Command::new(crate::cli::project::cargo());
                command.arg("build");
                command
            }
            Self::DebianWeb => {
                let mut command = Command::new("/usr/bin/cargo");
                let path = std::env::var("PATH").unwrap_or_default();
                command
                    .env("PATH", format!("/usr/bin:{path}"))
                    .env("RUSTC_BOOTSTRAP", "1")
                    .env(
                        "CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_LINKER",
                        "/usr/lib/llvm-22/bin/wasm-ld",
                    )
                    // rustup's choices would point Debian's cargo at rustup's rustc.
                    .env_remove("RUSTC")
                    .env_remove("RUSTDOC")
                    .env_remove("RUSTUP_TOOLCHAIN")
                    .args(["build", "-Zbuild-std=std,panic_abort"]);
                command
            }
        };
        command
            .env("RUSTFLAGS", rustflags)
            .env_remove("CARGO_ENCODED_RUSTFLAGS")
            .args(["--target", WASM_TARGET, "--target-dir"])
            .arg(target_dir);
        command
    }
}

/// `wasm-bindgen` at the version of the `wasm-bindgen` crate in `lock`
/// (the JS glue must match the crate exactly), installed into cargo's
/// `bin` folder with `cargo install` if missing.
///
/// # Errors
/// [`WebError::NoBindgen`] where the lock file pins none; the install's failure.
pub fn bindgen(lock: &Path) -> Result<PathBuf, WebError> {
    let text = std::fs::read_to_string(lock).map_err(io_error(format!("cannot read {}", lock.display())))?;
    let version = locked_version(&text, "wasm-bindgen").ok_or_else(|| WebError::NoBindgen(lock.to_path_buf()))?;
    let cargo_home = std::env::var_os("CARGO_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|home| Path::new(&home).join(".cargo")))
        .unwrap_or_else(|| PathBuf::from(".cargo"));
    let bindgen = cargo_home.join("bin").join("wasm-bindgen");
    let installed = Command::new(&bindgen).arg("--version").output().is_ok_and(|o| {
        String::from_utf8_lossy(&o.stdout)
            .trim()
            .ends_with(&format!(" {version}"))
    });
    if !installed {
        say(&format!("installing wasm-bindgen-cli {version} (cargo install)"));
        let mut install = Command::new(crate::cli::project::cargo());
        install
            .args(["install", "wasm-bindgen-cli", "--version"])
            .arg(format!("={version}"))
            .arg("--root")
            .arg(&cargo_home)
            .env_remove("CARGO_TARGET_DIR");
        run(&mut install)?;
    }
    Ok(bindgen)
}

/// The version `Cargo.lock` pins for package `name` (the first, where
/// there are several).
pub fn locked_version(lock: &str, name: &str) -> Option<String> {
    let mut lines = lock.lines();
    while let Some(line) = lines.next() {
        if line.trim() == format!("name = \"{name}\"") {
            let version = lines.next()?.trim().strip_prefix("version = \"")?.strip_suffix('"')?;
            return Some(version.to_owned());
        }
    }
    None
}

/// Installs the Debian `packages` that are missing (apt-get, through sudo
/// when not root).
///
/// # Errors
/// [`WebError`] where apt-get fails.
pub fn apt_install(packages: &[&str]) -> Result<(), WebError> {
    let missing: Vec<&str> = packages
        .iter()
        .copied()
        .filter(|package| {
            !Command::new("dpkg-query")
                .args(["-W", "-f=${Status}", package])
                .output()
                .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).contains("install ok installed"))
        })
        .collect();
    if missing.is_empty() {
        return Ok(());
    }
    say(&format!("installing missing packages: {}", missing.join(" ")));
    let root = Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0");
    let apt = |args: &[&str]| {
        let mut command = if root {
            Command::new("apt-get")
        } else {
            Command::new("sudo")
        };
        if !root {
            command.arg("apt-get");
        }
        command.args(args).env("DEBIAN_FRONTEND", "noninteractive");
        command
    };
    run(&mut apt(&["update", "-qq"]))?;
    let mut install = apt(&["install", "-y", "-qq", "--no-install-recommends"]);
    install.args(&missing);
    run(&mut install)
}

/// Runs `command`, its output going to this program's.
///
/// # Errors
/// [`WebError::Spawn`] or [`WebError::Failed`].
pub fn run(command: &mut Command) -> Result<(), WebError> {
    let status = command.status().map_err(|source| WebError::Spawn {
        program: command.get_program().to_string_lossy().into_owned(),
        source,
    })?;
    if status.success() {
        Ok(())
    } else {
        let line = std::iter::once(command.get_program())
            .chain(command.get_args())
            .map(|a| a.to_string_lossy())
            .collect::<Vec<_>>()
            .join(" ");
        Err(WebError::Failed { command: line, status })
    }
}

/// One line of progress, named.
pub fn say(line: &str) {
    println!("tickwork web: {line}");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lock_files_version_of_a_package_is_read() {
        let lock = "[[package]]\nname = \"wasm-bindgen\"\nversion = \"0.2.130\"\nsource = \"x\"\n\n\
                    [[package]]\nname = \"wasm-bindgen-futures\"\nversion = \"0.4.1\"\n";
        assert_eq!(locked_version(lock, "wasm-bindgen").as_deref(), Some("0.2.130"));
        assert_eq!(locked_version(lock, "wasm-bindgen-futures").as_deref(), Some("0.4.1"));
        assert_eq!(locked_version(lock, "wasm"), None);
    }
}
