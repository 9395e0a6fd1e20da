//! Embeds the built-in scenarios (`scenarios/*.toml`) and the files they
//! name (grammars, masks, body meshes and cylinders) so that the host needs no files at run time.

#![allow(
    clippy::expect_used,
    reason = "a build script reports a failure by panicking"
)]

use std::env;
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

fn main() {
    let root = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets it"))
        .join("..")
        .canonicalize()
        .expect("the workspace root exists");
    let mut out = String::from("/// Repository-relative path and bytes of every embedded file.\n");
    out.push_str("pub static FILES: &[(&str, &[u8])] = &[\n");
    for dir in [
        "scenarios",
        "scenarios/masks",
        "scenarios/bodies",
        "grammars",
    ] {
        println!("cargo:rerun-if-changed={}", root.join(dir).display());
        let mut names: Vec<PathBuf> = fs::read_dir(root.join(dir))
            .map(|entries| entries.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default();
        names.retain(|p| p.is_file());
        names.sort();
        for path in names {
            println!("cargo:rerun-if-changed={}", path.display());
            let rel = rel(&root, &path);
            writeln!(
                out,
                "    ({rel:?}, include_bytes!({:?})),",
                path.display().to_string()
            )
            .expect("writing to a String");
        }
    }
    out.push_str("];\n");
    let dest = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets it")).join("embedded.rs");
    fs::write(dest, out).expect("OUT_DIR is writable");
}

fn rel(root: &Path, path: &Path) -> String {
    path.strip_prefix(root)
        .expect("under the root")
        .to_string_lossy()
        .replace('\\', "/")
}
