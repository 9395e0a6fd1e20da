//! `morphogen review` on a pseudo-terminal, for the tests that answer it.

use std::fs;
use std::io::Read;
use std::path::Path;
use std::process::{Child, Command, Stdio};

/// `morphogen review ARGS` in `dir` on a new pseudo-terminal, and its
/// master side.
pub fn review_on_a_terminal(args: &[&str], dir: &Path) -> (Child, fs::File) {
    let pty = nix::pty::openpty(None, None).unwrap();
    let slave = fs::File::from(pty.slave);
    let child = Command::new(env!("CARGO_BIN_EXE_morphogen"))
        .arg("review")
        .args(args)
        .current_dir(dir)
        .env_remove("MORPHOGEN_FIXTURES")
        .env_remove("CI")
        .stdin(Stdio::from(slave.try_clone().unwrap()))
        .stdout(Stdio::from(slave.try_clone().unwrap()))
        .stderr(Stdio::from(slave))
        .spawn()
        .unwrap();
    // Our copies of the slave side are closed: the master reads the end
    // of output once the child has ended.
    (child, fs::File::from(pty.master))
}

/// Reads the terminal until it has shown `text` `times` times in all
/// (blocking: the question comes when the fixture before it is done),
/// and returns all it has shown.
pub fn read_until(master: &mut fs::File, shown: &mut String, text: &str, times: usize) -> String {
    let mut buf = [0u8; 4096];
    while shown.matches(text).count() < times {
        match master.read(&mut buf) {
            Ok(0) | Err(_) => panic!("review ended before asking ({times}): {shown}"),
            Ok(n) => shown.push_str(&String::from_utf8_lossy(&buf[..n])),
        }
    }
    shown.clone()
}

/// The rest of what the terminal shows, to the child's end.
pub fn read_to_end(master: &mut fs::File, shown: &mut String) -> String {
    let mut buf = [0u8; 4096];
    // Linux answers EIO once every slave side is closed.
    while let Ok(n) = master.read(&mut buf) {
        if n == 0 {
            break;
        }
        shown.push_str(&String::from_utf8_lossy(&buf[..n]));
    }
    shown.replace("\r\n", "\n")
}
