//! Records the git commit a checkout builds from, for the provenance that
//! fixtures and sweeps keep (`MORPHOGEN_GIT_COMMIT`; unset outside a
//! checkout or without git).

use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

fn main() {
    println!("cargo::rerun-if-env-changed=MORPHOGEN_GIT_COMMIT");
    let Some(commit) = git(&["rev-parse", "HEAD"]) else {
        return;
    };
    // HEAD moves on a checkout, its log on every commit too.
    for file in ["HEAD", "logs/HEAD"] {
        if let Some(path) = git(&["rev-parse", "--path-format=absolute", "--git-path", file]) {
            println!("cargo::rerun-if-changed={path}");
        }
    }
    println!("cargo::rustc-env=MORPHOGEN_GIT_COMMIT={commit}");
}
