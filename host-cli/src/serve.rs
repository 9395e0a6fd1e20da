//! `morphogen serve`: the web page (`web/`, built by
//! `scripts/web-build.sh` into `web/dist`) over HTTP on 127.0.0.1, with
//! each file's MIME type (`application/wasm` for the module, which
//! browsers require to compile it streaming). docs/web.md.
//!
//! hyper's HTTP/1 server on a one-thread tokio runtime: a request's body
//! is never read (a declared length allocates nothing), its headers must
//! fit [`MAX_HEADER_BYTES`] and arrive within [`HEADER_TIME`], and a slow
//! client holds its own connection only, of at most [`MAX_CONNECTIONS`].

use std::convert::Infallible;
use std::net::SocketAddr;
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;

use anyhow::{Context, Result, anyhow, bail};
use http_body_util::Full;
use hyper::body::{Bytes, Incoming};
use hyper::header::{CACHE_CONTROL, CONTENT_TYPE};
use hyper::{Method, Request, Response, StatusCode};
use hyper_util::rt::{TokioIo, TokioTimer};
use tokio::net::TcpListener;
use tokio::sync::Semaphore;

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

/// Connections served at once; more wait to be accepted.
pub const MAX_CONNECTIONS: usize = 64;

/// The most bytes of a request's line and headers (hyper's smallest
/// buffer).
pub const MAX_HEADER_BYTES: usize = 8192;

/// How long a client may take to send a request's headers.
pub const HEADER_TIME: Duration = Duration::from_secs(10);

/// Runs `serve` until the process is stopped.
///
/// # Errors
/// A folder without the built page, or a port that cannot be bound.
pub fn run(args: &Args) -> Result<Outcome> {
    if !args.dir.join("index.html").is_file() {
        bail!(
            "{} has no index.html: run bash scripts/web-build.sh first (or give --dir)",
            args.dir.display()
        );
    }
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .context("cannot start the server's runtime")?;
    runtime.block_on(serve(args))
}

async fn serve(args: &Args) -> Result<Outcome> {
    let listener = TcpListener::bind(("127.0.0.1", args.port))
        .await
        .map_err(|e| anyhow!("cannot listen on 127.0.0.1:{}: {e}", args.port))?;
    let port = listener.local_addr().map_or(args.port, |a| a.port());
    eprintln!(
        "serving {} on http://127.0.0.1:{port}/ (Ctrl-C stops)",
        args.dir.display()
    );
    let dir = Arc::new(args.dir.clone());
    let open = Arc::new(Semaphore::new(MAX_CONNECTIONS));
    loop {
        let Ok(permit) = Arc::clone(&open).acquire_owned().await else {
            return Ok(Outcome::Ok); // never closed
        };
        let (stream, _): (_, SocketAddr) = match listener.accept().await {
            Ok(accepted) => accepted,
            // A connection that failed as it was accepted is its own.
            Err(_) => continue,
        };
        let dir = Arc::clone(&dir);
        tokio::spawn(async move {
            let service = hyper::service::service_fn(move |request| {
                let dir = Arc::clone(&dir);
                async move { Ok::<_, Infallible>(answer(&dir, &request).await) }
            });
            // A client that fails or goes away ends its connection only.
            let _ = hyper::server::conn::http1::Builder::new()
                .timer(TokioTimer::new())
                .header_read_timeout(HEADER_TIME)
                .max_buf_size(MAX_HEADER_BYTES)
                .serve_connection(TokioIo::new(stream), service)
                .await;
            drop(permit);
        });
    }
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

fn status(code: StatusCode, text: &'static str) -> Response<Full<Bytes>> {
    let mut response = Response::new(Full::new(Bytes::from_static(text.as_bytes())));
    *response.status_mut() = code;
    response
}

/// Answers one request: the file with its type, 404, or 405.
async fn answer(dir: &Path, request: &Request<Incoming>) -> Response<Full<Bytes>> {
    let head = request.method() == Method::HEAD;
    if !head && request.method() != Method::GET {
        return status(StatusCode::METHOD_NOT_ALLOWED, "GET only");
    }
    let Some(path) = file_for(dir, request.uri().path()) else {
        return status(StatusCode::NOT_FOUND, "not found");
    };
    let Ok(bytes) = tokio::fs::read(&path).await else {
        return status(StatusCode::NOT_FOUND, "not found");
    };
    let mime = mime_guess::from_path(&path).first_or_octet_stream();
    let mut response = Response::new(Full::new(if head {
        Bytes::new()
    } else {
        Bytes::from(bytes)
    }));
    let headers = response.headers_mut();
    if let Ok(value) = mime.essence_str().parse() {
        headers.insert(CONTENT_TYPE, value);
    }
    // A rebuilt page is seen at once.
    headers.insert(
        CACHE_CONTROL,
        hyper::header::HeaderValue::from_static("no-cache"),
    );
    response
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
