//! [`Project`]: a game crate as cargo describes it (`cargo metadata`): its
//! package, binaries, workspace, target directory, whether it depends on
//! Tickwork, and what it asks of a web build (`[package.metadata.tickwork.web]`).
//! `tickwork web` reads it before it builds anything, so a crate that
//! cannot become a page is refused at once, with what to change.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

use super::web::WebError;

/// A game crate, read from `cargo metadata`.
#[derive(Clone, Debug)]
pub struct Project {
    /// The package's name.
    pub name: String,
    /// The package's `Cargo.toml`.
    pub manifest: PathBuf,
    /// The workspace's root folder: where `Cargo.lock` is, and where a
    /// game is run from natively (its asset paths are relative to it).
    pub workspace_root: PathBuf,
    /// The workspace's target directory.
    pub target_directory: PathBuf,
    /// The package's binaries, by name.
    pub bins: Vec<String>,
    /// Whether the package depends on `tickwork` or `tickwork-engine`.
    pub depends_on_tickwork: bool,
    /// `[package.metadata.tickwork.web]`: what a web build copies.
    pub web: WebMetadata,
}

/// `[package.metadata.tickwork.web]` of a game's `Cargo.toml`: the files a
/// page fetches, relative to the workspace root (where the game runs
/// natively). Every field is optional.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WebMetadata {
    /// Files and folders the page fetches (the paths the game lists in
    /// `Game::assets` lie under them), copied to the same paths in the
    /// site. Default: `assets`, where that folder exists.
    pub assets: Option<Vec<String>>,
    /// A folder of recordings (`.ron`) copied to the site's
    /// `recordings/`, where a page's `?replay=` finds them. Default:
    /// `recordings`, where that folder exists.
    pub recordings: Option<String>,
    /// The landing page's line for each binary of a site of several pages.
    pub about: Vec<(String, String)>,
    /// The landing page's heading. Default: the package's name.
    pub title: Option<String>,
}

impl Project {
    /// Reads the crate of `manifest` (default: the `Cargo.toml` cargo finds
    /// from the current folder, as `cargo build` does).
    ///
    /// # Errors
    /// [`WebError::NoManifest`] where there is no such file,
    /// [`WebError::Cargo`] where cargo cannot read it (its message kept),
    /// [`WebError::VirtualManifest`] for a workspace without a package.
    pub fn read(manifest: Option<&Path>) -> Result<Self, WebError> {
        let manifest = match manifest {
            Some(path) if path.is_dir() => path.join("Cargo.toml"),
            Some(path) => path.to_path_buf(),
            None => locate_manifest()?,
        };
        if !manifest.is_file() {
            return Err(WebError::NoManifest(manifest));
        }
        let manifest = manifest.canonicalize().map_err(|source| WebError::Io {
            doing: format!("cannot read {}", manifest.display()),
            source,
        })?;
        let output = Command::new(cargo())
            .args(["metadata", "--format-version", "1", "--no-deps", "--manifest-path"])
            .arg(&manifest)
            .output()
            .map_err(|source| WebError::Spawn {
                program: "cargo".into(),
                source,
            })?;
        if !output.status.success() {
            return Err(WebError::Cargo {
                doing: format!("cargo metadata --manifest-path {}", manifest.display()),
                message: String::from_utf8_lossy(&output.stderr).trim().to_owned(),
            });
        }
        let metadata: Value = serde_json::from_slice(&output.stdout).map_err(|e| WebError::Cargo {
            doing: "cargo metadata".into(),
            message: format!("unreadable output: {e}"),
        })?;
        Self::from_metadata(&metadata, &manifest)
    }

    /// The project of `manifest` in `cargo metadata`'s JSON.
    fn from_metadata(metadata: &Value, manifest: &Path) -> Result<Self, WebError> {
        let text = |value: &Value, key: &str| value.get(key).and_then(Value::as_str).map(str::to_owned);
        let packages = metadata
            .get("packages")
            .and_then(Value::as_array)
            .cloned()
            .unwrap_or_default();
        let package = packages
            .iter()
            .find(|p| text(p, "manifest_path").is_some_and(|m| Path::new(&m) == manifest))
            .ok_or_else(|| WebError::VirtualManifest(manifest.to_path_buf()))?;
        let bins = package
            .get("targets")
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
            .filter(|t| {
                t.get("kind")
                    .and_then(Value::as_array)
                    .is_some_and(|kinds| kinds.iter().any(|k| k == "bin"))
            })
            .filter_map(|t| text(t, "name"))
            .collect();
        let depends_on_tickwork = package
            .get("dependencies")
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
            .filter(|d| d.get("kind").is_none_or(Value::is_null))
            .filter_map(|d| text(d, "name"))
            .any(|name| name == "tickwork" || name == "tickwork-engine");
        let web = package
            .get("metadata")
            .and_then(|m| m.get("tickwork"))
            .and_then(|m| m.get("web"))
            .map(web_metadata)
            .transpose()
            .map_err(|field| WebError::Metadata {
                manifest: manifest.to_path_buf(),
                field,
            })?
            .unwrap_or_default();
        Ok(Self {
            name: text(package, "name").unwrap_or_default(),
            manifest: manifest.to_path_buf(),
            workspace_root: text(metadata, "workspace_root").map(PathBuf::from).unwrap_or_default(),
            target_directory: text(metadata, "target_directory")
                .map(PathBuf::from)
                .unwrap_or_default(),
            bins,
            depends_on_tickwork,
            web,
        })
    }

    /// The binaries to build: those named (each must exist), else the
    /// crate's only one.
    ///
    /// # Errors
    /// [`WebError::NoSuchBin`], [`WebError::NoBin`] or [`WebError::SeveralBins`].
    pub fn choose_bins(&self, named: &[String]) -> Result<Vec<String>, WebError> {
        if let Some(missing) = named.iter().find(|n| !self.bins.contains(n)) {
            return Err(WebError::NoSuchBin {
                name: missing.clone(),
                package: self.name.clone(),
                bins: self.bins.clone(),
            });
        }
        match (named, self.bins.as_slice()) {
            ([], []) => Err(WebError::NoBin {
                package: self.name.clone(),
                manifest: self.manifest.clone(),
            }),
            ([], [one]) => Ok(vec![one.clone()]),
            ([], several) => Err(WebError::SeveralBins {
                package: self.name.clone(),
                bins: several.to_vec(),
            }),
            (named, _) => {
                let mut bins = Vec::new();
                for name in named {
                    if !bins.contains(name) {
                        bins.push(name.clone());
                    }
                }
                Ok(bins)
            }
        }
    }
}

/// `[package.metadata.tickwork.web]`, or the name of the field that is not
/// what it should be.
fn web_metadata(table: &Value) -> Result<WebMetadata, String> {
    let assets = match table.get("assets") {
        None => None,
        Some(Value::Array(items)) => Some(
            items
                .iter()
                .map(|i| i.as_str().map(str::to_owned))
                .collect::<Option<Vec<_>>>()
                .ok_or("assets: a list of paths (strings)")?,
        ),
        Some(_) => return Err("assets: a list of paths (strings)".into()),
    };
    let recordings = match table.get("recordings") {
        None => None,
        Some(Value::String(path)) => Some(path.clone()),
        Some(_) => return Err("recordings: a path (a string)".into()),
    };
    let about = match table.get("about") {
        None => Vec::new(),
        Some(Value::Object(lines)) => lines
            .iter()
            .map(|(bin, line)| line.as_str().map(|l| (bin.clone(), l.to_owned())))
            .collect::<Option<Vec<_>>>()
            .ok_or("about: a table of binary = \"line\"")?,
        Some(_) => return Err("about: a table of binary = \"line\"".into()),
    };
    let title = match table.get("title") {
        None => None,
        Some(Value::String(title)) => Some(title.clone()),
        Some(_) => return Err("title: a string".into()),
    };
    Ok(WebMetadata {
        assets,
        recordings,
        about,
        title,
    })
}

/// The `Cargo.toml` cargo would build from the current folder.
fn locate_manifest() -> Result<PathBuf, WebError> {
    let output = Command::new(cargo())
        .args(["locate-project", "--message-format", "plain"])
        .output()
        .map_err(|source| WebError::Spawn {
            program: "cargo".into(),
            source,
        })?;
    if !output.status.success() {
        return Err(WebError::Cargo {
            doing: "cargo locate-project (no --manifest-path given)".into(),
            message: String::from_utf8_lossy(&output.stderr).trim().to_owned(),
        });
    }
    Ok(PathBuf::from(String::from_utf8_lossy(&output.stdout).trim()))
}

/// The cargo that runs this program (`cargo run` says which), else the
/// one on the `PATH`.
pub fn cargo() -> std::ffi::OsString {
    std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn project(bins: &[&str]) -> Project {
        Project {
            name: "game".into(),
            manifest: "/g/Cargo.toml".into(),
            workspace_root: "/g".into(),
            target_directory: "/g/target".into(),
            bins: bins.iter().map(|b| (*b).to_owned()).collect(),
            depends_on_tickwork: true,
            web: WebMetadata::default(),
        }
    }

    #[test]
    fn one_binary_is_chosen_alone_and_two_need_a_name() {
        assert_eq!(project(&["game"]).choose_bins(&[]).unwrap(), ["game"]);
        let error = project(&["a", "b"]).choose_bins(&[]).unwrap_err().to_string();
        assert_eq!(
            error,
            "game has 2 binaries (a, b): pass --bin NAME for each page to build"
        );
        let error = project(&[]).choose_bins(&[]).unwrap_err().to_string();
        assert!(error.starts_with("game has no binary"), "{error}");
        let error = project(&["a"]).choose_bins(&["c".into()]).unwrap_err().to_string();
        assert_eq!(error, "--bin c: game has no such binary (it has: a)");
        assert_eq!(
            project(&["a", "b"]).choose_bins(&["b".into(), "b".into()]).unwrap(),
            ["b"]
        );
    }

    #[test]
    fn metadata_is_read_and_a_wrong_field_is_named() {
        let table = serde_json::json!({
            "assets": ["assets/sprites"], "recordings": "assets/recordings", "about": {"a": "the a game"}
        });
        let read = web_metadata(&table).unwrap();
        assert_eq!(read.assets, Some(vec!["assets/sprites".to_owned()]));
        assert_eq!(read.recordings.as_deref(), Some("assets/recordings"));
        assert_eq!(read.about, [("a".to_owned(), "the a game".to_owned())]);
        let error = web_metadata(&serde_json::json!({"assets": "assets"})).unwrap_err();
        assert_eq!(error, "assets: a list of paths (strings)");
        let error = web_metadata(&serde_json::json!({"recordings": 3})).unwrap_err();
        assert_eq!(error, "recordings: a path (a string)");
    }
}
