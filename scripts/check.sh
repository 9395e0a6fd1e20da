#!/usr/bin/env bash
# Every check Morphogen has, in the order CI runs them (the README's test
# command; .ci/run calls exactly this). Installs what it needs when missing.
set -euo pipefail
cd "$(dirname "$0")/.."

step() { printf '\n==> %s\n' "$*"; }

step "toolchain: rustfmt, clippy and the Cortex-M targets"
installed_components=$(rustup component list --installed)
for c in rustfmt clippy; do
    grep -q "^$c" <<<"$installed_components" || rustup component add "$c"
done
installed_targets=$(rustup target list --installed)
for t in thumbv6m-none-eabi thumbv7m-none-eabi thumbv7em-none-eabihf; do
    grep -qx "$t" <<<"$installed_targets" || rustup target add "$t"
done

step "format"
cargo fmt --all --check
(cd firmware-example && cargo fmt --check)

step "lint"
cargo clippy --workspace --all-targets -- -D warnings
cargo clippy -p morphogen --all-targets --features rig,defmt -- -D warnings
(cd firmware-example && cargo clippy --release -- -D warnings)

step "core builds for Cortex-M0+ and Cortex-M3 (no_std, no alloc)"
for t in thumbv6m-none-eabi thumbv7m-none-eabi; do
    cargo build -p morphogen --target "$t"
    cargo build -p morphogen --target "$t" --features defmt,rig
done

step "tests"
cargo test --workspace

step "golden fixtures (release build)"
cargo run --release -p morphogen-cli -- verify

step "firmware in QEMU, bit-exact against the fixtures"
bash scripts/firmware-check.sh

printf '\nall checks passed\n'
