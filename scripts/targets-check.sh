#!/usr/bin/env bash
# Every preset on a big-endian machine: builds `morphogen` for
# s390x-unknown-linux-gnu (IBM Z, big-endian), runs `morphogen verify` under
# qemu-user (qemu-s390x) over every built-in preset, host-only ones too, and
# prints one line per preset: the target, `ok`, the preset, its frames and
# its stream digest, which must equal the fixture's. The stream is meant to
# be endian-neutral (docs/stream-format.md): this is where that is checked.
#
# The Cortex-M targets run in scripts/firmware-check.sh and the browser's
# wasm32 in scripts/web-check.sh; the README's "Targets" table lists all.
#
# Usage: scripts/targets-check.sh
# Environment:
#   CARGO_TARGET_DIR  honoured (default: target)
#
# Installs what is missing, and only that: the rustup target, the s390x
# cross linker and C library (crossbuild-essential-s390x) and qemu-user
# (apt-get).
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
say() { printf '%s\n' "$*" >&2; }
as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }
apt_updated=0
apt_install() {
  [ $apt_updated -eq 1 ] || { as_root apt-get update -qq; apt_updated=1; }
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@"
}

target=s390x-unknown-linux-gnu
sysroot=/usr/s390x-linux-gnu
rustup target list --installed | grep -qx "$target" || { say "rustup target add $target"; rustup target add "$target"; }
command -v s390x-linux-gnu-gcc >/dev/null || { say "installing crossbuild-essential-s390x"; apt_install crossbuild-essential-s390x; }
command -v qemu-s390x >/dev/null || { say "installing qemu-user"; apt_install qemu-user; }

# The release build without debug information (profile `cross`).
export CARGO_TARGET_S390X_UNKNOWN_LINUX_GNU_LINKER=s390x-linux-gnu-gcc
cargo build --profile cross -p morphogen-cli --target "$target"
bin="${CARGO_TARGET_DIR:-$root/target}/$target/cross/morphogen"

# `verify` re-runs every fixture's scenario and compares its digest; it
# exits non-zero on any mismatch or missing fixture.
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
if ! qemu-s390x -L "$sysroot" "$bin" verify >"$log" 2>&1; then
  sed "s/^/$target  /" "$log"
  say "targets-check: a preset's stream on $target differs from its fixture"
  exit 1
fi
grep -v '^[0-9]* ok, ' "$log" | sed "s/^/$target  /"
tally=$(grep '^[0-9]* ok, ' "$log")
say "$target (big-endian, qemu-s390x): $tally"
