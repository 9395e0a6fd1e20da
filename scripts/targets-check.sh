#!/usr/bin/env bash
# Every preset on targets other than the host's, bit-exact against the
# fixtures, one line per preset: the target, `ok`, the preset, its frames
# and its stream digest, which must equal the fixture's.
#
# - s390x: builds the scenario crate's example `fixtures` for
#   s390x-unknown-linux-gnu (IBM Z, big-endian) and runs it under qemu-user
#   (qemu-s390x): every built-in preset, host-only ones too, run and its
#   stream compared byte for byte with its fixture, as `morphogen verify`
#   does, without the CLI's picture, mesh and chart dependencies to
#   cross-build. The stream is meant to be endian-neutral
#   (docs/stream-format.md): this is where that is checked.
# - riscv32: builds the firmware (firmware-example, the same program as on
#   the Cortex-M, its board `src/board/virt.rs`) for
#   riscv32imac-unknown-none-elf, stream only, with every MCU preset and
#   the `surface` ones; boots it in QEMU's RISC-V `virt` machine
#   (qemu-system-riscv32), its UART captured to a file, and checks the
#   capture with `morphogen verify --stream`.
# - pico: builds firmware-rp2040 (the Raspberry Pi Pico's firmware, as
#   flashed on a board) with one MCU preset per model ($PICO_PRESETS) and
#   runs it in rp2040js, a Raspberry Pi Pico emulator in Node.js
#   (scripts/pico/run.mjs: UART0 captured to a file, the defmt log read
#   from RTT, the SSD1306 on I2C0 modelled, the WS2812 chain's words
#   taken from PIO0); checks the capture with `morphogen verify --stream`
#   and the digests the firmware logged, every frame its OLED showed
#   against `morphogen run … --rig 128x64:mono` and every byte its LED
#   chain received against `morphogen run … --rig 16x16:ws2812`. Its
#   emulator is single-threaded: with the other targets, it runs beside
#   them, its lines printed after theirs.
#
# The Cortex-M targets run in scripts/firmware-check.sh and the browser's
# wasm32 in scripts/web-check.sh; the README's "Targets" table lists all.
#
# Usage: scripts/targets-check.sh [s390x] [riscv32] [pico]   (default: all three)
#        scripts/targets-check.sh --prepare pico
#          installs what the Pico's check needs and exits (scripts/check.sh
#          does this before it runs the Pico's check in the background, so
#          that no two apt-get run at once)
# Environment:
#   CARGO_TARGET_DIR       honoured (default: target, and firmware-example/target
#                          for the firmware)
#   MORPHOGEN_BIN          the host's `morphogen` that verifies the RISC-V
#                          capture (default: $MORPHOGEN_RELEASE_BIN, which
#                          scripts/check.sh sets, else target/release/morphogen)
#   QEMU_STALL             seconds QEMU may run without a sign of progress
#                          (a byte of log or capture; default 300)
#   PICO_STALL             emulated seconds the Pico may run without a byte of
#                          UART0, RTT, I2C0 or the LEDs (default 120; the emulator's own
#                          clock, so a slow machine only takes longer)
#
# Installs what is missing, and only that: the rustup targets, the s390x
# cross linker and C library (crossbuild-essential-s390x), qemu-user and
# qemu-system-misc (apt-get), defmt-print (cargo install --locked), Node.js
# (apt-get nodejs npm) and rp2040js (npm ci from scripts/pico's
# package-lock.json).
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

prepare_only=0
if [ "${1:-}" = --prepare ]; then
  prepare_only=1
  shift
fi
wanted=("$@")
[ ${#wanted[@]} -gt 0 ] || wanted=(s390x riscv32 pico)
for w in "${wanted[@]}"; do
  case "$w" in s390x | riscv32 | pico) ;; *) say "targets-check: unknown target $w (s390x, riscv32 or pico)"; exit 2 ;; esac
done
wants() { [[ " ${wanted[*]} " == *" $1 "* ]]; }
rustup_target() {
  rustup target list --installed | grep -qx "$1" || { say "rustup target add $1"; rustup target add "$1"; }
}
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# ---- s390x: `morphogen verify` under qemu-user ----------------------------------
check_s390x() {
  local target=s390x-unknown-linux-gnu
  local sysroot=/usr/s390x-linux-gnu
  rustup_target "$target"
  command -v s390x-linux-gnu-gcc >/dev/null || { say "installing crossbuild-essential-s390x"; apt_install crossbuild-essential-s390x; }
  command -v qemu-s390x >/dev/null || { say "installing qemu-user"; apt_install qemu-user; }

  # The release build without debug information (profile `cross`).
  export CARGO_TARGET_S390X_UNKNOWN_LINUX_GNU_LINKER=s390x-linux-gnu-gcc
  cargo build --profile cross -p morphogen-scenario --example fixtures --target "$target"
  local bin="${CARGO_TARGET_DIR:-$root/target}/$target/cross/examples/fixtures"

  # Every built-in scenario re-run and its stream compared with its
  # fixture's; exits non-zero on any mismatch or missing fixture.
  local log="$work/s390x.log" tally
  if ! qemu-s390x -L "$sysroot" "$bin" "$root/fixtures" >"$log" 2>&1; then
    sed "s/^/$target  /" "$log"
    say "targets-check: a preset's stream on $target differs from its fixture"
    exit 1
  fi
  grep -v '^[0-9]* ok, ' "$log" | sed "s/^ok /ok        /; s/^/$target  /"
  tally=$(grep '^[0-9]* ok, ' "$log")
  say "$target (big-endian, qemu-s390x): $tally"
}

# ---- riscv32: the firmware in qemu-system-riscv32 -machine virt -----------------
# watch_progress PID FILE...: waits while QEMU (PID) runs; when none of
# FILE… (the defmt log, the UART capture) has grown for $QEMU_STALL
# seconds, stops it and says so in $work/stalled. No wall-clock deadline:
# a busy machine only runs slower.
watch_progress() {
  local pid="$1" stall="${QEMU_STALL:-300}" size last=-1 since=$SECONDS
  shift
  while kill -0 "$pid" 2>/dev/null; do
    size="$(stat -c %s "$@" 2>/dev/null | awk '{s += $1} END {print s + 0}')"
    if [ "$size" != "$last" ]; then
      last="$size"; since=$SECONDS
    elif [ $((SECONDS - since)) -ge "$stall" ]; then
      echo "no progress for $stall s (no byte of defmt log or UART capture; QEMU_STALL): stopped" >"$work/stalled"
      kill "$pid" 2>/dev/null
      break
    fi
    sleep 1
  done
}

# The host's `morphogen`, which verifies the captures.
morphogen_bin() {
  local morphogen="${MORPHOGEN_BIN:-${MORPHOGEN_RELEASE_BIN:-${CARGO_TARGET_DIR:-$root/target}/release/morphogen}}"
  [ -x "$morphogen" ] || {
    say "targets-check: no morphogen binary at $morphogen (cargo build --release -p morphogen-cli, or set MORPHOGEN_BIN)"
    exit 1
  }
  printf '%s\n' "$morphogen"
}

# Checks a device's UART capture: every stream in it against its fixture,
# bit for bit (`morphogen verify --stream`), then the frames and digest the
# device logged for each, which must be the fixture's; prints a line per
# preset and sets `verified` to how many were ok.
#   verify_capture MORPHOGEN TARGET CAPTURE LOG SED
# SED is the sed script that prints "FRAMES DIGEST" from the log's line of
# a preset, `{}` standing for its name.
verify_capture() {
  local morphogen="$1" target="$2" capture="$3" log="$4" pattern="$5"
  local log_of_verify="$work/$target.verify.log"
  if ! (cd "$root" && "$morphogen" verify --stream "$capture") >"$log_of_verify" 2>&1; then
    sed "s/^/$target  /" "$log_of_verify"
    say "targets-check: a preset's stream on $target differs from its fixture"
    exit 1
  fi
  local status name rest frames digest fixture_frames fixture_digest ok=0
  while read -r status name rest; do
    [ "$status" = ok ] || continue
    read -r frames digest < <(sed -n "${pattern//\{\}/$name}" "$log") || true
    fixture_frames="$(sed -n 's/^frames = \([0-9]*\)$/\1/p' "$root/fixtures/$name/summary.toml")"
    fixture_digest="$(sed -n 's/^stream_digest = "\([0-9a-f]*\)"$/\1/p' "$root/fixtures/$name/summary.toml")"
    if [ -z "${digest:-}" ] || [ "$frames" != "$fixture_frames" ] || [ "$digest" != "$fixture_digest" ]; then
      say "targets-check: $name on $target logged ${frames:-no} frames, digest ${digest:-none}; its fixture has $fixture_frames, $fixture_digest"
      exit 1
    fi
    printf '%s  ok        %s (%s frames, digest %s)\n' "$target" "$name" "$frames" "$digest"
    ok=$((ok + 1))
    unset frames digest
  done <"$log_of_verify"
  verified=$ok
}

check_riscv32() {
  local target=riscv32imac-unknown-none-elf fw="$root/firmware-example"
  local morphogen
  morphogen="$(morphogen_bin)"
  rustup_target "$target"
  command -v qemu-system-riscv32 >/dev/null || { say "installing qemu-system-misc"; apt_install qemu-system-misc; }
  command -v defmt-print >/dev/null || { say "cargo install defmt-print --locked"; cargo install defmt-print --locked; }

  # Stream only (the OLED is the LM3S6965's), every MCU preset and the
  # surface ones: the firmware's own build of its presets (build.rs).
  say "build firmware-example for $target (--no-default-features --features semihosting,surface)"
  (cd "$fw" && env -u MORPHOGEN_SCENARIOS cargo build --release --target "$target" \
    --no-default-features --features semihosting,surface)
  local elf="${CARGO_TARGET_DIR:-$fw/target}/$target/release/morphogen-firmware"
  local capture="$work/riscv32.bin" defmt="$work/riscv32.defmt" log="$work/riscv32.log" qemu qemu_status started=$SECONDS

  # The UART to the capture, defmt over semihosting to a file (decoded once
  # QEMU is done), the exit code over semihosting. `-icount shift=0`: one
  # instruction per ns, so that `mcycle` (the report's ticks) counts
  # instructions.
  say "QEMU virt (qemu-system-riscv32): $(basename "$elf")"
  set +e
  qemu-system-riscv32 -machine virt -bios none \
    -display none -monitor none -parallel none \
    -semihosting-config "enable=on,target=native,arg=morphogen-firmware" \
    -icount shift=0 \
    -serial "file:$capture" \
    -kernel "$elf" >"$defmt" 2>"$work/riscv32.qemu.err" &
  qemu=$!
  watch_progress "$qemu" "$defmt" "$capture"
  wait "$qemu"; qemu_status=$?
  defmt-print -e "$elf" <"$defmt" >"$log" 2>&1
  set -e
  say "QEMU ran $((SECONDS - started)) s"
  if [ -e "$work/stalled" ] || [ "$qemu_status" -ne 0 ] || ! grep -q "all .* presets streamed" "$log"; then
    cat "$log" "$work/riscv32.qemu.err" >&2
    say "targets-check: the firmware on $target $(cat "$work/stalled" 2>/dev/null || echo "exited $qemu_status")"
    exit 1
  fi

  verify_capture "$morphogen" "$target" "$capture" "$log" \
    "s/.*report preset={} seed=[0-9]* frames=\([0-9]*\) bytes=[0-9]* digest=\([0-9a-f]*\) .*/\1 \2/p"
  local ok=$verified
  grep -q "all $ok presets streamed" "$log" || { say "targets-check: $ok streams verified, not every preset the firmware ran"; exit 1; }
  say "$target (QEMU virt, qemu-system-riscv32): $ok ok, $(stat -c %s "$capture") bytes captured"
}

# ---- pico: firmware-rp2040 in rp2040js (Node.js) ----------------------------------
# One MCU preset per model, the cheaper ones (rp2040js runs some 40
# million instructions a second): growth curve, horn, L-system, body,
# bones, plane mosaic. (The Pico's runner has no surface mosaics.)
PICO_PRESETS=(growth-curve sulaiman-markhor lsys-flower horse-growth long-bone croton-mcu)

# What the Pico's check needs, installed before it starts (it may run
# beside the other targets' checks, which install theirs).
prepare_pico() {
  rustup_target thumbv6m-none-eabi
  command -v node >/dev/null || { say "installing nodejs"; apt_install nodejs npm; }
  command -v defmt-print >/dev/null || { say "cargo install defmt-print --locked"; cargo install defmt-print --locked; }
  # rp2040js at the version package-lock.json names (npm ci installs
  # exactly the lockfile, from npm's cache when it has it).
  say "npm ci (scripts/pico: rp2040js)"
  (cd "$root/scripts/pico" && npm ci --no-audit --no-fund --silent)
}

check_pico() {
  local target=thumbv6m-none-eabi fw="$root/firmware-rp2040" harness="$root/scripts/pico"
  local morphogen
  morphogen="$(morphogen_bin)"

  # The firmware as a board runs it, built with these presets only
  # (MORPHOGEN_SCENARIOS), in firmware-example's target folder as
  # scripts/check.sh builds it.
  local scenarios=() name
  for name in "${PICO_PRESETS[@]}"; do scenarios+=("$root/scenarios/$name.toml"); done
  say "build firmware-rp2040 with ${PICO_PRESETS[*]}"
  (cd "$fw" && MORPHOGEN_SCENARIOS="$(IFS=,; echo "${scenarios[*]}")" \
    CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/firmware-example/target}" cargo build --release)
  local elf="${CARGO_TARGET_DIR:-$root/firmware-example/target}/$target/release/morphogen-rp2040"
  local capture="$work/pico.bin" rtt="$work/pico.rtt" log="$work/pico.log" started=$SECONDS

  say "rp2040js (scripts/pico/run.mjs): $(basename "$elf")"
  if ! node "$harness/run.mjs" "$elf" --uart "$capture" --rtt "$rtt" --oled "$work/pico-oled.bin" \
    --leds "$work/pico-leds.bin" \
    --stall "${PICO_STALL:-120}" 2>"$work/pico.err"; then
    defmt-print -e "$elf" <"$rtt" >&2 2>&1 || true
    cat "$work/pico.err" >&2
    say "targets-check: the firmware on the emulated Pico did not finish"
    exit 1
  fi
  defmt-print -e "$elf" <"$rtt" >"$log" 2>&1
  say "rp2040js ran $((SECONDS - started)) s: $(tail -n 1 "$work/pico.err")"
  grep -q "all ${#PICO_PRESETS[@]} presets streamed" "$log" || {
    cat "$log" >&2
    say "targets-check: the emulated Pico did not stream all ${#PICO_PRESETS[@]} presets"
    exit 1
  }

  verify_capture "$morphogen" pico "$capture" "$log" \
    "s/.*INFO  {}: \([0-9]*\) frames, [0-9]* bytes, digest \([0-9a-f]*\)$/\1 \2/p"
  local ok=$verified
  [ "$ok" -eq "${#PICO_PRESETS[@]}" ] || { say "targets-check: $ok streams verified, not the ${#PICO_PRESETS[@]} presets the Pico ran"; exit 1; }

  # Every frame the emulated SSD1306 showed against the host's drawing of
  # the same preset on a monochrome 128x64 OLED, display RAM byte for byte
  # (`run --rig 128x64:mono` writes rig-128x64-ssd1306.bin); every byte the
  # LED chain received against the host's 16x16 serpentine WS2812 matrix
  # (`run --rig 16x16:ws2812`, rig-16x16-ws2812.bin).
  local shown=() lit=()
  for name in "${PICO_PRESETS[@]}"; do
    "$morphogen" run "$name" --rig 128x64:mono --only csv --quiet --out "$work/pico-host/$name"
    "$morphogen" run "$name" --rig 16x16:ws2812 --only csv --quiet --out "$work/pico-host/$name"
    shown+=("$name=$work/pico-host/$name/rig-128x64-ssd1306.bin")
    lit+=("$name=$work/pico-host/$name/rig-16x16-ws2812.bin")
  done
  node "$harness/compare.mjs" --frame-bytes 1024 --label "OLED frames" "$work/pico-oled.bin" "${shown[@]}" \
    | sed "s/^/pico  ok        /" || { say "targets-check: the emulated Pico's OLED differs from the host's rig-128x64-ssd1306.bin"; exit 1; }
  node "$harness/compare.mjs" --frame-bytes 768 --label "LED frames" "$work/pico-leds.bin" "${lit[@]}" \
    | sed "s/^/pico  ok        /" || { say "targets-check: the emulated Pico's LED chain differs from the host's rig-16x16-ws2812.bin"; exit 1; }
  say "pico (RP2040 in rp2040js): $ok ok, $(stat -c %s "$capture") bytes captured"
}

if [ "$prepare_only" -eq 1 ]; then
  if wants pico; then prepare_pico; fi
  exit 0
fi

# The Pico's emulator is single-threaded and the longest of the three: it
# runs beside the others, its output kept and printed after theirs.
pico_pid=""
if wants pico; then
  prepare_pico
  if wants s390x || wants riscv32; then
    (check_pico) >"$work/pico.out" 2>&1 &
    pico_pid=$!
    trap 'pkill -P "$pico_pid" 2>/dev/null || true; kill "$pico_pid" 2>/dev/null || true; rm -rf "$work"' EXIT
  else
    check_pico
  fi
fi
if wants s390x; then check_s390x; fi
if wants riscv32; then check_riscv32; fi
if [ -n "$pico_pid" ]; then
  pico_status=0
  wait "$pico_pid" || pico_status=$?
  cat "$work/pico.out"
  exit "$pico_status"
fi
