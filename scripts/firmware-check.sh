#!/usr/bin/env bash
# Firmware check (issues 3 and 17): builds firmware-example for thumbv7m,
# thumbv6m and thumbv7em, runs each in QEMU's lm3s6965evb with `-icount
# shift=0` (UART0 → capture file, defmt over semihosting → defmt-print),
# verifies every capture bit for bit with `morphogen verify --stream`, takes
# the emulated OLED's picture after each preset (QEMU `screendump` through
# QMP, with the firmware's `--screen-sync` handshake on UART1:
# scripts/oled-screens.py) and compares it pixel for pixel with the host's
# `--rig 128x64:grey4` picture of the same stream (`morphogen listen`; both
# land in target/rig-screens/), checks that a flipped bit is caught, builds and runs the firmware with two user scenarios
# (MORPHOGEN_SCENARIOS: a changed ram-horn made on the fly and the user body
# examples/wagging-tail.toml, verified against fixtures blessed on the host),
# and rewrites firmware-example/REPORT.md (sizes and costs of the built-in
# presets).
#
# Usage: scripts/firmware-check.sh [--capture FILE] [--flip BYTE[:BIT]] [--no-report]
#   --capture FILE    only verify FILE (e.g. a capture from real hardware)
#   --flip BYTE[:BIT] where the negative check flips a bit (default: middle
#                     of the capture, bit 0)
#   --no-report       do not rewrite REPORT.md
# Environment:
#   MORPHOGEN_VERIFY  the verify command, given the capture as last argument
#                     (default: cargo run --release -q -p morphogen-cli -- verify --stream;
#                     the user-scenario step appends `--fixtures DIR` after the capture)
#   MORPHOGEN_BLESS   the bless command, given `FILE.toml … --fixtures DIR`
#                     (default: cargo run --release -q -p morphogen-cli -- bless)
#   MORPHOGEN_LISTEN  the listen command, given `CAPTURE --rig 128x64:grey4 --out DIR`
#                     (default: cargo run --release -q -p morphogen-cli -- listen)
#   CARGO_TARGET_DIR  honoured (default: firmware-example/target)
#   QEMU_TIMEOUT      seconds per QEMU run (default 600)
#
# Installs what is missing, and only that: rustup targets, qemu-system-arm
# (apt-get), defmt-print (cargo install --locked), binutils' `size`.
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
fw="$root/firmware-example"
capture_only=""
flip=""
write_report=1
while [ $# -gt 0 ]; do
  case "$1" in
    --capture) capture_only="$2"; shift 2 ;;
    --flip) flip="$2"; shift 2 ;;
    --no-report) write_report=0; shift ;;
    -h|--help) sed -n '2,27p' "$0"; exit 0 ;;
    *) echo "firmware-check: unknown argument $1" >&2; exit 2 ;;
  esac
done

say() { printf '\n== %s\n' "$*"; }
die() { printf 'firmware-check: FAIL: %s\n' "$*" >&2; exit 1; }

# Default: the CLI's `verify --stream`, built from the workspace at the root.
if [ -n "${MORPHOGEN_VERIFY:-}" ]; then
  read -r -a verify_cmd <<<"$MORPHOGEN_VERIFY"
else
  verify_cmd=(cargo run --release -q --manifest-path "$root/Cargo.toml" -p morphogen-cli -- verify --stream)
fi

if [ -n "${MORPHOGEN_LISTEN:-}" ]; then
  read -r -a listen_cmd <<<"$MORPHOGEN_LISTEN"
else
  listen_cmd=(cargo run --release -q --manifest-path "$root/Cargo.toml" -p morphogen-cli -- listen)
fi

if [ -n "${MORPHOGEN_BLESS:-}" ]; then
  read -r -a bless_cmd <<<"$MORPHOGEN_BLESS"
else
  bless_cmd=(cargo run --release -q --manifest-path "$root/Cargo.toml" -p morphogen-cli -- bless)
fi

verify() { # verify CAPTURE LOG [ARG...] → exit status of the verifier
  local capture="$1" log="$2"; shift 2
  (cd "$root" && "${verify_cmd[@]}" "$capture" "$@") >"$log" 2>&1
}

# A copy of $1 with one bit flipped at byte $2 (bit $3) written to $4.
flip_bit() {
  python3 - "$1" "$2" "$3" "$4" <<'PY'
import sys
src, at, bit, dst = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
data = bytearray(open(src, 'rb').read())
if not 0 <= at < len(data):
    sys.exit(f"--flip: byte {at} is outside the {len(data)}-byte capture")
data[at] ^= 1 << bit
open(dst, 'wb').write(bytes(data))
PY
}

# Negative check: a flipped bit must fail verification, naming the preset
# (when known) and a frame.
negative_check() { # CAPTURE EXPECTED_PRESET(or empty) WORKDIR
  local capture="$1" expected="$2" work="$3" at bit size
  size=$(stat -c %s "$capture")
  if [ -n "$flip" ]; then at="${flip%%:*}"; bit="${flip#*:}"; [ "$bit" = "$flip" ] && bit=0
  else at=$((size / 2)); bit=0; fi
  flip_bit "$capture" "$at" "$bit" "$work/flipped.bin"
  say "negative check: bit $bit of byte $at flipped"
  if verify "$work/flipped.bin" "$work/verify-flipped.log"; then
    cat "$work/verify-flipped.log"
    die "a capture with a flipped bit passed verification"
  fi
  cat "$work/verify-flipped.log"
  if [ -n "$expected" ] && ! grep -q -- "$expected" "$work/verify-flipped.log"; then
    die "the verifier failed but did not name preset $expected"
  fi
  grep -qi "frame" "$work/verify-flipped.log" || die "the verifier failed but did not name a frame"
  echo "negative check: rejected as expected"
}

if [ -n "$capture_only" ]; then
  work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
  say "verify $capture_only"
  verify "$capture_only" "$work/verify.log" || { cat "$work/verify.log"; die "verification of $capture_only failed"; }
  cat "$work/verify.log"
  negative_check "$capture_only" "" "$work"
  exit 0
fi

# ---- tools -----------------------------------------------------------------
targets=(thumbv7m-none-eabi thumbv6m-none-eabi thumbv7em-none-eabihf)
as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }
apt_updated=0
apt_install() {
  [ $apt_updated -eq 1 ] || { as_root apt-get update -qq; apt_updated=1; }
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@"
}
installed_targets="$(rustup target list --installed)"
for t in "${targets[@]}"; do
  grep -qx "$t" <<<"$installed_targets" || { say "rustup target add $t"; rustup target add "$t"; }
done
command -v qemu-system-arm >/dev/null || { say "installing qemu-system-arm"; apt_install qemu-system-arm; }
command -v size >/dev/null || { say "installing binutils (size)"; apt_install binutils; }
command -v python3 >/dev/null || { say "installing python3"; apt_install python3; }
command -v defmt-print >/dev/null || { say "cargo install defmt-print --locked"; cargo install defmt-print --locked; }

# ---- build -------------------------------------------------------------------
tdir="${CARGO_TARGET_DIR:-$fw/target}"
work="$tdir/firmware-check"
rm -rf "$work"; mkdir -p "$work"
user_dir="$(mktemp -d)"; trap 'rm -rf "$user_dir"' EXIT
cd "$fw"

# Two user scenarios: ram-horn renamed and shortened (3 years, one frame a
# year), made on the fly, and examples/wagging-tail.toml, a user's body (an
# OBJ mesh and a cylinder file of its own, compiled into flash).
user_name="my-horn"
user_toml="$user_dir/$user_name.toml"
python3 - "$root/scenarios/ram-horn.toml" "$user_toml" "$user_name" <<'PY'
import re, sys
src, dst, name = sys.argv[1:]
text = open(src, encoding="utf-8").read()
for key, value in [("name", f'"{name}"'),
                   ("summary", '"ram-horn for 3 years, one frame a year (firmware-check user scenario)"'),
                   ("years", "3"), ("frames_per_year", "1")]:
    text, n = re.subn(rf"^{key} = [^#\n]*?(\s*(#.*)?)$", rf"{key} = {value}\1", text, count=1, flags=re.M)
    if n != 1:
        sys.exit(f"user scenario: no `{key} = ` line in {src}")
open(dst, "w", encoding="utf-8").write(text)
PY
# First, so that the built-in builds below leave the target dir (the same
# ELF path for thumbv7m) with the built-in presets: build.rs reruns when
# MORPHOGEN_SCENARIOS changes. Its ELF is kept aside for the run below.
user_body="$root/examples/wagging-tail.toml"
say "build thumbv7m-none-eabi with MORPHOGEN_SCENARIOS=$user_toml,$user_body"
MORPHOGEN_SCENARIOS="$user_toml,$user_body" cargo build --release --target thumbv7m-none-eabi
cp "$tdir/thumbv7m-none-eabi/release/morphogen-firmware" "$work/user.elf"

# The RTT variant (real hardware) next: it shares the ELF path of the
# default thumbv7m build, which the loop below then rebuilds.
say "build (rtt feature, thumbv7m-none-eabi)"
env -u MORPHOGEN_SCENARIOS cargo build --release --no-default-features --features rtt --target thumbv7m-none-eabi
for t in "${targets[@]}"; do
  say "build $t"
  env -u MORPHOGEN_SCENARIOS cargo build --release --target "$t"
done

# ---- run in QEMU and verify ----------------------------------------------------
qemu_cpu() { case "$1" in thumbv7em-*) echo cortex-m4 ;; *) echo cortex-m3 ;; esac; }
# qemu_run TARGET ELF NAME: boots ELF, UART0 → $work/NAME.bin, defmt log →
# $work/NAME.log, the OLED after each preset → $work/screens-NAME/; fails
# unless every preset streamed and was photographed.
sockets="$(mktemp -d)" # short paths: UNIX sockets allow ~100 bytes
trap 'rm -rf "$user_dir" "$sockets"' EXIT
qemu_run() {
  local t="$1" elf="$2" name="$3" status capturer capture_status
  say "QEMU lm3s6965evb -cpu $(qemu_cpu "$t"): $name"
  rm -f "$sockets"/*
  python3 "$root/scripts/oled-screens.py" capture "$sockets/sync" "$sockets/qmp" "$work/screens-$name" \
    >"$work/$name.screens.log" 2>&1 &
  capturer=$!
  set +e
  timeout "${QEMU_TIMEOUT:-600}" qemu-system-arm -machine lm3s6965evb -cpu "$(qemu_cpu "$t")" \
    -display none -monitor none -parallel none \
    -semihosting-config enable=on,target=native,arg=morphogen-firmware,arg=--screen-sync \
    -icount shift=0 \
    -serial "file:$work/$name.bin" -serial "unix:$sockets/sync,server=on,wait=on" \
    -qmp "unix:$sockets/qmp,server=on,wait=off" \
    -kernel "$elf" 2>"$work/$name.qemu.err" \
    | defmt-print -e "$elf" >"$work/$name.log" 2>&1
  status=("${PIPESTATUS[@]}")
  wait "$capturer"; capture_status=$?
  set -e
  cat "$work/$name.log" "$work/$name.screens.log"
  [ "${status[0]}" -eq 0 ] || { cat "$work/$name.qemu.err" >&2; die "$name: QEMU exited ${status[0]} (firmware panic, fault, failed preset or timeout)"; }
  grep -q "all .* presets streamed" "$work/$name.log" || die "$name: the firmware did not report completion"
  [ "$capture_status" -eq 0 ] || die "$name: the OLED pictures could not be taken"
}

# oled_check NAME [LISTEN ARG...]: the host draws each stream of
# $work/NAME.bin as a 128×64 grey OLED (`morphogen listen`, which also
# verifies it), and every picture QEMU took must match it pixel for pixel.
oled_check() {
  local name="$1"; shift
  say "OLED: $name against the host's pictures"
  (cd "$root" && "${listen_cmd[@]}" "$work/$name.bin" --rig 128x64:grey4 --out "$work/host-screens-$name" "$@") \
    >"$work/$name.listen.log" 2>&1 || { cat "$work/$name.listen.log"; die "$name: the host could not draw the capture"; }
  # shellcheck disable=SC2046 # one name per line, no spaces
  python3 "$root/scripts/oled-screens.py" compare "$work/screens-$name" "$work/host-screens-$name" \
    $(cat "$work/screens-$name/captured.txt") | tee -a "$work/oled.log" \
    || die "$name: the emulated OLED differs from the host's picture (see $work/screens-$name)"
}

for t in "${targets[@]}"; do
  elf="$tdir/$t/release/morphogen-firmware"
  cp "$elf" "$work/$t.elf"
  qemu_run "$t" "$elf" "$t"
  say "verify $t capture ($(stat -c %s "$work/$t.bin") bytes)"
  verify "$work/$t.bin" "$work/$t.verify.log" || { cat "$work/$t.verify.log"; die "$t: capture does not match the fixtures"; }
  cat "$work/$t.verify.log"
  oled_check "$t"
done
# The pictures of the first target, beside the host's, where a reviewer
# looks: target/rig-screens/PRESET.{qemu,host}.png.
screens="$root/target/rig-screens"
rm -rf "$screens"; mkdir -p "$screens"
cp "$work/screens-${targets[0]}"/*.png "$screens/"
echo "OLED pictures: $screens"


# ---- user scenarios (MORPHOGEN_SCENARIOS) -----------------------------------------
# The firmware built above from the two user scenarios alone streams exactly
# what the host blesses from the same files.
qemu_run thumbv7m-none-eabi "$work/user.elf" user
grep -q "all 2 presets streamed" "$work/user.log" || die "user scenarios: the firmware did not run exactly two presets"
for name in "$user_name" wagging-tail; do
  grep -q "report preset=$name " "$work/user.log" || die "user scenarios: the firmware did not run $name"
done
say "bless $user_name and wagging-tail on the host"
(cd "$root" && "${bless_cmd[@]}" "$user_toml" "$user_body" --fixtures "$user_dir/fixtures") >"$work/user.bless.log" 2>&1 \
  || { cat "$work/user.bless.log"; die "user scenarios: bless failed"; }
cat "$work/user.bless.log"
for name in "$user_name" wagging-tail; do
  [ -f "$user_dir/fixtures/$name/stream.bin" ] || die "user scenarios: bless wrote no $name/stream.bin"
done
say "verify the user-scenario capture ($(stat -c %s "$work/user.bin") bytes)"
verify "$work/user.bin" "$work/user.verify.log" --fixtures "$user_dir/fixtures" \
  || { cat "$work/user.verify.log"; die "user scenario: the capture does not match the blessed fixture"; }
cat "$work/user.verify.log"
cat "$user_dir/fixtures/$user_name/stream.bin" "$user_dir/fixtures/wagging-tail/stream.bin" >"$work/user.expected.bin"
cmp -s "$work/user.bin" "$work/user.expected.bin" \
  || die "user scenarios: the capture differs from the blessed stream.bin files"
echo "user scenarios: $user_name and wagging-tail streamed on the firmware match the host's bless, byte for byte"
oled_check user --fixtures "$user_dir/fixtures"

# The flipped bit lands in the preset that owns the byte (from the firmware's
# per-preset byte counts, in stream order).
main_capture="$work/thumbv7m-none-eabi.bin"
expected="$(python3 - "$work/thumbv7m-none-eabi.log" "$(stat -c %s "$main_capture")" "${flip%%:*}" <<'PY'
import re, sys
log, size, flip = sys.argv[1], int(sys.argv[2]), sys.argv[3]
at = int(flip) if flip else size // 2
offset = 0
for m in re.finditer(r"report preset=(\S+) .*?bytes=(\d+)", open(log).read()):
    if offset <= at < offset + int(m.group(2)):
        print(m.group(1)); break
    offset += int(m.group(2))
PY
)"
negative_check "$main_capture" "$expected" "$work"

# ---- report ------------------------------------------------------------------
if [ $write_report -eq 1 ]; then
  # Every preset the host knows (core, then the host presets of
  # host-cli/src/host_presets.rs, marked "host only"), to name the
  # host-only presets.
  (cd "$root" && cargo run --release -q -p morphogen-cli -- list) >"$work/host-presets.txt" 2>/dev/null \
    || rm -f "$work/host-presets.txt"
  say "writing firmware-example/REPORT.md"
  VERIFY_COMMAND="${verify_cmd[*]}" python3 "$fw/report.py" "$work" "${targets[@]}" >"$fw/REPORT.md"
  cat "$fw/REPORT.md"
fi
say "firmware check passed"
