//! The site a web build writes: a folder to upload as it is.
//!
//! One game: `index.html` (its page), `<bin>.js` and `<bin>_bg.wasm`, its
//! assets at the paths the game loads them by, and `recordings/`. Several
//! (the demos): a folder per game (`<bin>/index.html`) and a landing
//! `index.html` linking them, the assets and `recordings/` beside them.
//! The folder carries a marker file, so a later build replaces only a
//! folder a build wrote, never the user's files.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use super::error::{WebError, io_error};
use super::toolchain::run;
use crate::cli::project::Project;

/// The page every game gets: `@DEMO@` its binary, `@ASSETS@` where its
/// asset paths are fetched from (the page's `data-assets`).
const PAGE: &str = include_str!("../../../../assets/web/page.html");
/// The landing page of a site of several games: `@TITLE@`, `@FIRST@` (a
/// game, for the examples) and `@LINKS@`.
const LANDING: &str = include_str!("../../../../assets/web/index.html");
/// The file that marks a folder as a web build's own.
pub const MARKER: &str = ".tickwork-web";
/// A string only Tickwork's page runner puts in a wasm (it reads the
/// page's `data-assets`): its absence means `main` never runs a `Game`.
const RUNNER_MARK: &[u8] = b"data-assets";

/// One built page: its binary, and its wasm and JS gzipped, in bytes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BuiltPage {
    /// The binary.
    pub bin: String,
    /// The page's `index.html`.
    pub page: PathBuf,
    /// Its wasm and JS, gzipped (what a browser downloads).
    pub gzipped_bytes: u64,
}

/// Refuses an `out` folder that holds files no web build wrote; a
/// folder a build wrote is emptied. Called before building, so a refusal
/// costs nothing.
///
/// # Errors
/// [`WebError::NotOurs`].
pub fn check_out(out: &Path) -> Result<(), WebError> {
    if out.join(MARKER).is_file() {
        return Ok(());
    }
    match std::fs::read_dir(out) {
        Ok(mut entries) => match entries.next() {
            Some(_) => Err(WebError::NotOurs(out.to_path_buf())),
            None => Ok(()),
        },
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotADirectory => Err(WebError::NotOurs(out.to_path_buf())),
        Err(source) => Err(WebError::Io {
            doing: format!("cannot read --out {}", out.display()),
            source,
        }),
    }
}

/// Writes the site for `bins` (built into `wasm_dir`) into `out`, with
/// `bindgen`'s JS glue.
///
/// # Errors
/// [`WebError`] with the file or command that failed; [`WebError::NoRun`]
/// for a binary that never starts a `Game`.
pub fn write(
    project: &Project,
    bins: &[String],
    wasm_dir: &Path,
    bindgen: &Path,
    out: &Path,
) -> Result<Vec<BuiltPage>, WebError> {
    check_out(out)?;
    // Every wasm checked before anything is removed.
    for bin in bins {
        let wasm = wasm_dir.join(format!("{bin}.wasm"));
        let bytes = std::fs::read(&wasm).map_err(io_error(format!("cannot read {}", wasm.display())))?;
        if !bytes.windows(RUNNER_MARK.len()).any(|w| w == RUNNER_MARK) {
            return Err(WebError::NoRun { bin: bin.clone() });
        }
    }
    if out.exists() {
        std::fs::remove_dir_all(out).map_err(io_error(format!("cannot empty {}", out.display())))?;
    }
    std::fs::create_dir_all(out.join("recordings")).map_err(io_error(format!("cannot create {}", out.display())))?;
    std::fs::write(
        out.join(MARKER),
        "written by `tickwork web build`; the next build replaces this folder\n",
    )
    .map_err(io_error(format!("cannot write in {}", out.display())))?;
    let several = bins.len() > 1;
    let mut pages = Vec::new();
    for bin in bins {
        let dir = if several { out.join(bin) } else { out.to_path_buf() };
        let mut glue = Command::new(bindgen);
        glue.args([
            "--target",
            "web",
            "--no-typescript",
            "--remove-producers-section",
            "--out-dir",
        ])
        .arg(&dir)
        .arg(wasm_dir.join(format!("{bin}.wasm")));
        run(&mut glue)?;
        let page = dir.join("index.html");
        let html = PAGE
            .replace("@DEMO@", bin)
            .replace("@ASSETS@", if several { "../" } else { "./" });
        std::fs::write(&page, html).map_err(io_error(format!("cannot write {}", page.display())))?;
        let mut gzipped = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
        for file in [dir.join(format!("{bin}_bg.wasm")), dir.join(format!("{bin}.js"))] {
            let bytes = std::fs::read(&file).map_err(io_error(format!("cannot read {}", file.display())))?;
            gzipped
                .write_all(&bytes)
                .map_err(io_error("cannot gzip the page's files"))?;
        }
        let gzipped = gzipped.finish().map_err(io_error("cannot gzip the page's files"))?;
        pages.push(BuiltPage {
            bin: bin.clone(),
            page,
            gzipped_bytes: gzipped.len() as u64,
        });
    }
    if several {
        write_landing(project, bins, out)?;
    }
    copy_files(project, out)?;
    Ok(pages)
}

/// The landing page linking each game, with its line from
/// `[package.metadata.tickwork.web.about]`.
fn write_landing(project: &Project, bins: &[String], out: &Path) -> Result<(), WebError> {
    let mut links = String::new();
    for bin in bins {
        let about = project
            .web
            .about
            .iter()
            .find(|(b, _)| b == bin)
            .map(|(_, line)| line.as_str());
        match about {
            Some(line) => links.push_str(&format!("<li><a href=\"{bin}/\">{bin}</a>: {line}</li>\n")),
            None => links.push_str(&format!("<li><a href=\"{bin}/\">{bin}</a></li>\n")),
        }
    }
    let title = project.web.title.clone().unwrap_or_else(|| project.name.clone());
    let html = LANDING
        .replace("@TITLE@", &title)
        .replace("@FIRST@", bins.first().map_or("", String::as_str))
        .replace("@LINKS@\n", &links);
    let path = out.join("index.html");
    std::fs::write(&path, html).map_err(io_error(format!("cannot write {}", path.display())))
}

/// Copies the game's assets (at the same paths, relative to the workspace
/// root) and recordings (into `recordings/`).
fn copy_files(project: &Project, out: &Path) -> Result<(), WebError> {
    let root = &project.workspace_root;
    let assets = match &project.web.assets {
        Some(listed) => {
            for path in listed {
                if !root.join(path).exists() {
                    return Err(WebError::Io {
                        doing: format!(
                            "{}: [package.metadata.tickwork.web] assets lists {path}, which is not in {}",
                            project.manifest.display(),
                            root.display()
                        ),
                        source: std::io::ErrorKind::NotFound.into(),
                    });
                }
            }
            listed.clone()
        }
        None if root.join("assets").is_dir() => vec!["assets".to_owned()],
        None => Vec::new(),
    };
    for path in &assets {
        copy(&root.join(path), &out.join(path))?;
    }
    let recordings = match &project.web.recordings {
        Some(path) => Some(root.join(path)),
        None => Some(root.join("recordings")).filter(|p| p.is_dir()),
    };
    if let Some(folder) = recordings {
        let entries = std::fs::read_dir(&folder)
            .map_err(io_error(format!("cannot read the recordings in {}", folder.display())))?;
        for entry in entries {
            let path = entry
                .map_err(io_error(format!("cannot read {}", folder.display())))?
                .path();
            if path.extension().is_some_and(|e| e == "ron")
                && let Some(name) = path.file_name()
            {
                copy(&path, &out.join("recordings").join(name))?;
            }
        }
    }
    Ok(())
}

/// Copies a file, or a folder with everything in it.
fn copy(from: &Path, to: &Path) -> Result<(), WebError> {
    if from.is_dir() {
        std::fs::create_dir_all(to).map_err(io_error(format!("cannot create {}", to.display())))?;
        let entries = std::fs::read_dir(from).map_err(io_error(format!("cannot read {}", from.display())))?;
        for entry in entries {
            let entry = entry.map_err(io_error(format!("cannot read {}", from.display())))?;
            copy(&entry.path(), &to.join(entry.file_name()))?;
        }
        Ok(())
    } else {
        if let Some(parent) = to.parent() {
            std::fs::create_dir_all(parent).map_err(io_error(format!("cannot create {}", parent.display())))?;
        }
        std::fs::copy(from, to).map(drop).map_err(io_error(format!(
            "cannot copy {} to {}",
            from.display(),
            to.display()
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_of_other_files_is_refused_and_left_alone() {
        let dir = std::env::temp_dir().join(format!("tickwork-site-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        assert!(check_out(&dir).is_ok(), "an empty folder is fine");
        assert!(check_out(&dir.join("new")).is_ok(), "a new folder is fine");
        std::fs::write(dir.join("notes.txt"), "mine").unwrap();
        let error = check_out(&dir).unwrap_err().to_string();
        assert!(error.contains("nothing was overwritten"), "{error}");
        assert_eq!(std::fs::read_to_string(dir.join("notes.txt")).unwrap(), "mine");
        assert!(check_out(&dir.join("notes.txt")).is_err(), "a file is not a site");
        std::fs::write(dir.join(MARKER), "").unwrap();
        assert!(check_out(&dir).is_ok(), "a build's own folder is replaced");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
