#!/usr/bin/env bash
# Builds everything the web page needs into web/dist/ (docs/web.md), on a
# fresh clone: installs the wasm32-unknown-unknown target and the
# wasm-bindgen-cli of exactly the wasm-bindgen version in Cargo.lock when
# missing, builds the morphogen-web crate to WebAssembly (release), writes
# its JS glue with wasm-bindgen (--target web), installs three.js with
# `npm ci` and copies the page, its modules and three.js beside them. The
# page needs no network once built. Then: `morphogen serve`.
set -euo pipefail
cd "$(dirname "$0")/.."

step() { printf '\n==> web: %s\n' "$*"; }

target=wasm32-unknown-unknown
if ! rustup target list --installed | grep -qx "$target"; then
    step "installing the $target target"
    rustup target add "$target"
fi

# The version of the wasm-bindgen crate the lockfile pins: the CLI must be
# the same, or the glue it writes does not match the module.
version=$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/version = |"/, ""); print; exit }' Cargo.lock)
if [[ -z "$version" ]]; then
    echo "web-build: no wasm-bindgen in Cargo.lock" >&2
    exit 2
fi
if [[ "$(wasm-bindgen --version 2>/dev/null)" != "wasm-bindgen $version" ]]; then
    step "installing wasm-bindgen-cli $version (cargo install, a few minutes)"
    # --locked first; the CLI's own lockfile may name a crate version the
    # registry no longer serves (webpki-roots 1.0.11 here), then the newest
    # compatible versions are taken.
    cargo install wasm-bindgen-cli --version "=$version" --locked ||
        cargo install wasm-bindgen-cli --version "=$version"
fi

step "building the WebAssembly module (release)"
# Without the workspace's release debug info: wasm-bindgen drops it anyway.
CARGO_PROFILE_RELEASE_DEBUG=0 cargo build --release -p morphogen-web --target "$target"
target_dir="${CARGO_TARGET_DIR:-target}"
wasm="$target_dir/$target/release/morphogen_web.wasm"

dist=web/dist
rm -rf "$dist"
mkdir -p "$dist/pkg" "$dist/three/addons/controls"
step "wasm-bindgen --target web"
wasm-bindgen --target web --no-typescript --out-dir "$dist/pkg" "$wasm"

step "npm ci (three.js)"
(cd web && PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --no-audit --no-fund)

step "assembling $dist"
cp web/index.html web/style.css web/main.js web/view.js web/worker.js "$dist/"
cp web/node_modules/three/build/three.module.js "$dist/three/"
cp web/node_modules/three/build/three.core.js "$dist/three/"
cp web/node_modules/three/examples/jsm/controls/OrbitControls.js "$dist/three/addons/controls/"
ls -l "$dist" "$dist/pkg"
echo "web page built in $dist: morphogen serve --dir $dist"
