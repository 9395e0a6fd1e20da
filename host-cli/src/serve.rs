//! `morphogen serve`: the web page (`web/`, built by
//! `scripts/web-build.sh` into `web/dist`) over HTTP on 127.0.0.1, with
//! each file's MIME type (`application/wasm` for the module, which
//! browsers require to compile it streaming). docs/web.md.

use std::fs;
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;
use std::thread;

use anyhow::{Result, anyhow, bail};
use tiny_http::{Header, Method, Request, Response, Server};

use crate::Outcome;

/// Arguments of `morphogen serve`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The port on 127.0.0.1 (0: any free port, printed).
    #[arg(long, default_value_t = 8000)]
    pub port: u16,
    /// The folder to serve: the page `bash scripts/web-build.sh` builds.
    #[arg(long, default_value = "web/dist")]
    pub dir: PathBuf,
}

/// Threads answering requests: the page loads a few files at once.
const THREADS: usize = 4;

/// Runs `serve` until the process is stopped.
///
/// # Errors
/// A folder without the built page, or a port that cannot be bound.
pub fn run(args: &Args) -> Result<Outcome> {
    let server = bind(&args.dir, args.port)?;
    let port = server.server_addr().to_ip().map_or(args.port, |a| a.port());
    eprintln!(
        "serving {} on http://127.0.0.1:{port}/ (Ctrl-C stops)",
        args.dir.display()
    );
    let workers: Vec<_> = (0..THREADS)
        .map(|_| {
            let (server, dir) = (Arc::clone(&server), args.dir.clone());
            thread::spawn(move || {
                for request in server.incoming_requests() {
                    answer(&dir, request);
                }
            })
        })
        .collect();
    for w in workers {
        w.join().map_err(|_| anyhow!("a server thread panicked"))?;
    }
    Ok(Outcome::Ok)
}

/// Binds 127.0.0.1:`port` to serve `dir`, which must hold the built page.
///
/// # Errors
/// `dir` has no `index.html`, or the port is taken.
pub fn bind(dir: &Path, port: u16) -> Result<Arc<Server>> {
    if !dir.join("index.html").is_file() {
        bail!(
            "{} has no index.html: run bash scripts/web-build.sh first (or give --dir)",
            dir.display()
        );
    }
    Server::http(("127.0.0.1", port))
        .map(Arc::new)
        .map_err(|e| anyhow!("cannot listen on 127.0.0.1:{port}: {e}"))
}

/// The file under `dir` that the request path `url` names (`/` is
/// `index.html`; the query is ignored), or `None` when it leaves `dir`.
fn file_for(dir: &Path, url: &str) -> Option<PathBuf> {
    let path = url.split(['?', '#']).next().unwrap_or("");
    let path = path.trim_start_matches('/');
    let path = if path.is_empty() || path.ends_with('/') {
        format!("{path}index.html")
    } else {
        path.to_string()
    };
    let relative = Path::new(&path);
    relative
        .components()
        .all(|c| matches!(c, Component::Normal(_)))
        .then(|| dir.join(relative))
}

fn header(name: &str, value: &str) -> Header {
    Header::from_bytes(name.as_bytes(), value.as_bytes()).expect("ASCII header")
}

/// Answers one request: the file with its type, 404, or 405.
fn answer(dir: &Path, request: Request) {
    let head = *request.method() == Method::Head;
    if !head && *request.method() != Method::Get {
        let _ = request.respond(Response::from_string("GET only").with_status_code(405));
        return;
    }
    let found = file_for(dir, request.url()).and_then(|p| Some((fs::read(&p).ok()?, p)));
    let Some((bytes, path)) = found else {
        let _ = request.respond(Response::from_string("not found").with_status_code(404));
        return;
    };
    let mime = mime_guess::from_path(&path).first_or_octet_stream();
    let response = Response::from_data(if head { Vec::new() } else { bytes })
        .with_header(header("Content-Type", mime.essence_str()))
        // A rebuilt page is seen at once.
        .with_header(header("Cache-Control", "no-cache"));
    let _ = request.respond(response);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_stay_in_the_folder() {
        let d = Path::new("/srv");
        assert_eq!(file_for(d, "/"), Some(d.join("index.html")));
        assert_eq!(file_for(d, "/?preset=croton"), Some(d.join("index.html")));
        assert_eq!(
            file_for(d, "/pkg/morphogen_web_bg.wasm"),
            Some(d.join("pkg/morphogen_web_bg.wasm"))
        );
        assert_eq!(file_for(d, "/../etc/passwd"), None);
        assert_eq!(file_for(d, "/pkg/../../x"), None);
    }
}
