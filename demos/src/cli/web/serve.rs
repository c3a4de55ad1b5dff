//! Serving a built site on localhost (`tickwork web serve`): files only,
//! with the content types a browser insists on (`application/wasm` for
//! streaming compilation), nothing outside the folder.

use std::path::{Component, Path, PathBuf};

use super::error::WebError;

/// Serves `site` on `127.0.0.1:port` (0: any free port) until the process
/// ends, first printing the URL. Each request is answered with the file
/// it names (a folder's `index.html`), 404 where there is none.
///
/// # Errors
/// [`WebError::Io`] where the port cannot be bound.
pub fn serve(site: &Path, port: u16) -> Result<(), WebError> {
    let server = tiny_http::Server::http(("127.0.0.1", port)).map_err(|e| WebError::Io {
        doing: format!("cannot serve on 127.0.0.1:{port}"),
        source: std::io::Error::other(e.to_string()),
    })?;
    let port = server.server_addr().to_ip().map_or(port, |a| a.port());
    println!(
        "tickwork web: serving {} on http://127.0.0.1:{port}/ (Ctrl-C stops)",
        site.display()
    );
    for request in server.incoming_requests() {
        let response = match file_for(site, request.url()) {
            Some(path) => match std::fs::File::open(&path) {
                Ok(file) => {
                    let header = tiny_http::Header::from_bytes("Content-Type", content_type(&path))
                        .unwrap_or_else(|()| unreachable!("a constant header is valid"));
                    request.respond(tiny_http::Response::from_file(file).with_header(header))
                }
                Err(_) => request.respond(tiny_http::Response::from_string("not found").with_status_code(404)),
            },
            None => request.respond(tiny_http::Response::from_string("not found").with_status_code(404)),
        };
        // A browser that went away mid-response is no reason to stop serving.
        drop(response);
    }
    Ok(())
}

/// The file `url` names inside `site`: its query dropped, a folder's
/// `index.html`, nothing that climbs out (`..`) or is absent.
pub fn file_for(site: &Path, url: &str) -> Option<PathBuf> {
    let path = url.split(['?', '#']).next().unwrap_or_default();
    let relative = Path::new(path.trim_start_matches('/'));
    if relative.components().any(|c| !matches!(c, Component::Normal(_))) {
        return None;
    }
    let mut file = site.join(relative);
    if file.is_dir() {
        file = file.join("index.html");
    }
    file.is_file().then_some(file)
}

/// A file's content type by its extension.
pub fn content_type(path: &Path) -> &'static str {
    match path.extension().and_then(|e| e.to_str()).unwrap_or_default() {
        "html" => "text/html; charset=utf-8",
        "js" => "text/javascript",
        "wasm" => "application/wasm",
        "png" => "image/png",
        "wav" => "audio/wav",
        "ogg" => "audio/ogg",
        "json" => "application/json",
        "css" => "text/css",
        "ron" | "txt" => "text/plain; charset=utf-8",
        _ => "application/octet-stream",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_url_names_a_file_in_the_site_and_never_one_outside_it() {
        let site = std::env::temp_dir().join(format!("tickwork-serve-test-{}", std::process::id()));
        std::fs::create_dir_all(site.join("game")).unwrap();
        std::fs::write(site.join("index.html"), "").unwrap();
        std::fs::write(site.join("game/index.html"), "").unwrap();
        std::fs::write(site.join("game/game_bg.wasm"), "").unwrap();
        assert_eq!(file_for(&site, "/"), Some(site.join("index.html")));
        assert_eq!(file_for(&site, "/game/?hz=120"), Some(site.join("game/index.html")));
        assert_eq!(
            file_for(&site, "/game/game_bg.wasm"),
            Some(site.join("game/game_bg.wasm"))
        );
        assert_eq!(file_for(&site, "/../etc/passwd"), None);
        assert_eq!(file_for(&site, "/game/../../x"), None);
        assert_eq!(file_for(&site, "/missing.js"), None);
        assert_eq!(content_type(Path::new("a_bg.wasm")), "application/wasm");
        assert_eq!(content_type(Path::new("a.js")), "text/javascript");
        std::fs::remove_dir_all(&site).unwrap();
    }
}
