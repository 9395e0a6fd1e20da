//! `morphogen serve`: the page's files over HTTP with their MIME types, and
//! a clear error when the page is not built.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "a test stops at the first thing that is not as it expects"
)]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Command, Stdio};

/// The status line, headers and body of `GET path` on 127.0.0.1:`port`.
fn get(port: u16, path: &str) -> (String, Vec<u8>) {
    let mut s = TcpStream::connect(("127.0.0.1", port)).expect("connect");
    write!(
        s,
        "GET {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n"
    )
    .expect("request");
    let mut all = Vec::new();
    s.read_to_end(&mut all).expect("response");
    let split = all
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("headers end");
    (
        String::from_utf8_lossy(&all[..split]).to_lowercase(),
        all[split + 4..].to_vec(),
    )
}

#[test]
fn serves_the_page_with_mime_types() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::create_dir(dir.path().join("pkg")).expect("pkg");
    let wasm = b"\0asm\x01\0\0\0";
    std::fs::write(dir.path().join("pkg/m_bg.wasm"), wasm).expect("wasm");
    std::fs::write(dir.path().join("main.js"), "export {};").expect("js");
    let (mut child, port) = start(dir.path());
    let (head, body) = get(port, "/");
    assert!(head.starts_with("http/1.1 200"), "{head}");
    assert!(head.contains("content-type: text/html"), "{head}");
    assert_eq!(body, b"<!doctype html>page");
    let (head, body) = get(port, "/pkg/m_bg.wasm");
    assert!(head.contains("content-type: application/wasm"), "{head}");
    assert_eq!(body, wasm);
    let (head, _) = get(port, "/main.js?v=1");
    assert!(
        head.contains("content-type: text/javascript")
            || head.contains("content-type: application/javascript"),
        "{head}"
    );
    let (head, _) = get(port, "/nothing.js");
    assert!(head.starts_with("http/1.1 404"), "{head}");
    let (head, _) = get(port, "/../Cargo.toml");
    assert!(head.starts_with("http/1.1 404"), "{head}");
    child.kill().expect("stop the server");
    child.wait().expect("reaped");
}

/// `morphogen serve` on a folder with a page; its port.
fn start(dir: &std::path::Path) -> (std::process::Child, u16) {
    std::fs::write(dir.join("index.html"), "<!doctype html>page").expect("index");
    let mut child = Command::new(env!("CARGO_BIN_EXE_morphogen"))
        .args(["serve", "--port", "0", "--dir"])
        .arg(dir)
        .stderr(Stdio::piped())
        .spawn()
        .expect("morphogen serve starts");
    let mut line = String::new();
    BufReader::new(child.stderr.take().expect("stderr"))
        .read_line(&mut line)
        .expect("the address line");
    let port = line
        .split("http://127.0.0.1:")
        .nth(1)
        .and_then(|rest| rest.split('/').next())
        .and_then(|p| p.parse().ok())
        .unwrap_or_else(|| panic!("no port in {line:?}"));
    (child, port)
}

#[test]
fn hostile_requests_neither_crash_nor_block_the_server() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (mut child, port) = start(dir.path());
    // A body declared at 100 GB and never sent: answered, nothing
    // allocated for it.
    let mut s = TcpStream::connect(("127.0.0.1", port)).expect("connect");
    write!(
        s,
        "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 100000000000\r\n\r\nabc"
    )
    .expect("request");
    let mut status = [0u8; 12];
    s.read_exact(&mut status).expect("a response");
    assert_eq!(&status, b"HTTP/1.1 200");
    drop(s);
    // Headers past the cap: refused, the server goes on.
    let mut s = TcpStream::connect(("127.0.0.1", port)).expect("connect");
    let huge = format!("GET / HTTP/1.1\r\nX: {}\r\n\r\n", "x".repeat(100_000));
    let _ = s.write_all(huge.as_bytes());
    drop(s);
    // Clients that never finish their headers hold only themselves.
    let slow: Vec<TcpStream> = (0..16)
        .map(|_| {
            let mut s = TcpStream::connect(("127.0.0.1", port)).expect("connect");
            write!(s, "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n").expect("a start");
            s
        })
        .collect();
    let (head, body) = get(port, "/");
    assert!(head.starts_with("http/1.1 200"), "{head}");
    assert_eq!(body, b"<!doctype html>page");
    assert!(child.try_wait().expect("status").is_none(), "serve ended");
    drop(slow);
    child.kill().expect("stop the server");
    child.wait().expect("reaped");
}

#[test]
fn a_missing_page_says_how_to_build_it() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = Command::new(env!("CARGO_BIN_EXE_morphogen"))
        .args(["serve", "--dir"])
        .arg(dir.path().join("dist"))
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("run bash scripts/web-build.sh first"), "{err}");
}

#[test]
fn help_names_the_port_and_the_folder() {
    let out = Command::new(env!("CARGO_BIN_EXE_morphogen"))
        .args(["serve", "--help"])
        .output()
        .expect("runs");
    let help = String::from_utf8_lossy(&out.stdout);
    assert!(help.contains("--port") && help.contains("--dir"), "{help}");
    assert!(help.contains("web/dist") && help.contains("8000"), "{help}");
}
