#!/usr/bin/env bash
# Firmware check: builds firmware-example for thumbv7m, thumbv6m and
# thumbv7em, runs each in QEMU's lm3s6965evb with `-icount
# shift=0` (UART0 → capture file, defmt over semihosting → defmt-print),
# verifies every capture bit for bit with `morphogen verify --stream`, takes
# the emulated OLED's picture after each preset (QEMU `screendump` through
# QMP, with the firmware's `--screen-sync` handshake on UART1:
# scripts/oled-screens.py) and compares it pixel for pixel with the host's
# `--rig 128x64:grey4` picture of the same stream (`morphogen listen`; both
# land in target/rig-screens/), feeds the thumbv7m capture to the receiver
# (`morphogen-receiver`, UART0 from a socket) and compares its OLED with the
# sender's picture for picture, feeds it a stream with two flipped bits and
# checks that exactly those frames are skipped (and that it shows what the
# host's `listen` shows of that stream), checks that a flipped bit fails
# verification, builds and runs the firmware with two user scenarios
# (MORPHOGEN_SCENARIOS: a changed ram-horn made on the fly and the user body
# examples/wagging-tail.toml, verified against fixtures blessed on the host),
# sends four scenarios to the built-in firmware over UART0 (`morphogen send`,
# the firmware's `--serve 4`) and checks its capture and OLED,
# and writes the report of the sizes and costs of the built-in presets
# (firmware-example/REPORT.md's form) into its work folder and prints it.
#
# Usage: scripts/firmware-check.sh [--capture FILE] [--flip BYTE[:BIT]] [--write-report]
#   --capture FILE    only verify FILE (e.g. a capture from real hardware)
#   --flip BYTE[:BIT] where the negative check flips a bit (default: middle
#                     of the capture, bit 0)
#   --write-report    also rewrite firmware-example/REPORT.md (a tracked file:
#                     CI leaves the tree as it found it)
# Environment:
#   MORPHOGEN_VERIFY  the verify command, given the capture as last argument
#                     (default: cargo run --release -q -p morphogen-cli -- verify --stream;
#                     the user-scenario step appends `--fixtures DIR` after the capture)
#   MORPHOGEN_BLESS   the bless command, given `FILE.toml … --fixtures DIR`
#                     (default: cargo run --release -q -p morphogen-cli -- bless)
#   MORPHOGEN_LISTEN  the listen command, given `CAPTURE --rig 128x64:grey4 --out DIR`
#                     (default: cargo run --release -q -p morphogen-cli -- listen)
#   MORPHOGEN_SEND    the send command, given `SCENARIO FILE`
#                     (default: cargo run --release -q -p morphogen-cli -- send)
#   MORPHOGEN_BIN     the morphogen binary whose `list` names the host-only
#                     presets in the report (default: cargo run --release)
#   CARGO_TARGET_DIR  honoured (default: firmware-example/target)
#   QEMU_STALL        seconds QEMU may run without a sign of progress (default 300)
#
# Installs what is missing, and only that: rustup targets, qemu-system-arm
# (apt-get), defmt-print (cargo install --locked), binutils' `size`.
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
fw="$root/firmware-example"
# Cortex-M builds name their sources by fixed paths (flash figures within
# a few bytes on any machine: docs/embedding.md).
. "$root/scripts/fixed-paths.sh"
capture_only=""
flip=""
write_report=0
while [ $# -gt 0 ]; do
  case "$1" in
    --capture) capture_only="$2"; shift 2 ;;
    --flip) flip="$2"; shift 2 ;;
    --write-report) write_report=1; shift ;;
    -h|--help) sed -n '2,42p' "$0"; exit 0 ;;
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

if [ -n "${MORPHOGEN_SEND:-}" ]; then
  read -r -a send_cmd <<<"$MORPHOGEN_SEND"
else
  send_cmd=(cargo run --release -q --manifest-path "$root/Cargo.toml" -p morphogen-cli -- send)
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
# A mosaic on a surface: the feature `surface` puts it in the
# runner (cells and mesh inline, no more RAM); built with the one built-in
# surface preset that fits the MCU.
say "build thumbv7m-none-eabi with the feature surface, MORPHOGEN_SCENARIOS=scenarios/watermelon-mcu.toml"
MORPHOGEN_SCENARIOS="$root/scenarios/watermelon-mcu.toml" cargo build --release --features surface --target thumbv7m-none-eabi
cp "$tdir/thumbv7m-none-eabi/release/morphogen-firmware" "$work/surface.elf"

# The RTT variant (real hardware; it shares the ELF path of the default
# thumbv7m build, which the loop below then rebuilds) and the stream-only one
# (no `extent`, `oled` or `serve`, built for size: the flash figure).
say "build (rtt feature, thumbv7m-none-eabi)"
env -u MORPHOGEN_SCENARIOS cargo build --release --no-default-features --features rtt,extent,oled,serve --target thumbv7m-none-eabi
say "build (stream only: no extent, oled or serve; bitwise frame CRC; profile small, opt-level z; thumbv7m-none-eabi)"
env -u MORPHOGEN_SCENARIOS cargo build --profile small --no-default-features --features semihosting,bitwise-crc --target thumbv7m-none-eabi
cp "$tdir/thumbv7m-none-eabi/small/morphogen-firmware" "$work/stream-only.elf"
# Every MCU preset, streamed, fits a part with 96 KB of flash
# when built for size: under 96,000 B, the stricter reading of "96 KB".
stream_only_flash="$(size -A "$work/stream-only.elf" | awk '$1 ~ /^\.(vector_table|text|rodata|data)$/ {s += $2} END {print s}')"
[ "$stream_only_flash" -lt 96000 ] \
  || die "stream-only firmware (profile small): $stream_only_flash B of flash, not under 96 KB (96,000 B)"
# An idle model with one non-zero byte would be copied into the runner from
# a constant of its whole size in flash (core/src/preset.rs, IDLE_*): no
# constant that big may be there (the largest, the CRC-64 table, is 2 KB).
big="$(nm -S --size-sort -t d -C "$work/stream-only.elf" | awk '$3 ~ /^[rR]$/ && $2 + 0 >= 4096 {print $2 + 0 " B: " $4}')"
[ -z "$big" ] || die "stream-only firmware: a constant of an idle model's size in flash (a non-zero byte in an IDLE_ model?): $big"
for t in "${targets[@]}"; do
  say "build $t"
  env -u MORPHOGEN_SCENARIOS cargo build --release --target "$t"
done

# ---- run in QEMU and verify ----------------------------------------------------
qemu_cpu() { case "$1" in thumbv7em-*) echo cortex-m4 ;; *) echo cortex-m3 ;; esac; }
sockets="$(mktemp -d)" # short paths: UNIX sockets allow ~100 bytes
trap 'rm -rf "$user_dir" "$sockets"' EXIT
# boot NAME ELF CPU FEED DONE [ARG...]: boots ELF on QEMU's -cpu CPU with the
# semihosting arguments `--screen-sync ARG…`; UART0 goes to $work/NAME.bin
# and, unless FEED is empty, is fed FEED through a socket
# (`oled-screens.py feed`); the OLED after each stream's last frame →
# $work/screens-NAME/, the defmt log → $work/NAME.log. Fails unless the log
# has the line DONE, every picture was taken and the stack kept its margin.
# QEMU runs for as long as it makes progress (watch_progress): no deadline.
boot() {
  local name="$1" elf="$2" cpu="$3" feed="$4" done="$5" serial0 qemu qemu_status capturer feeder="" capture_status feed_status=0 arg
  local sock="$sockets/$name"
  shift 5
  local semihosting="enable=on,target=native,arg=$(basename "$elf" .elf),arg=--screen-sync"
  for arg in "$@"; do semihosting+=",arg=$arg"; done
  say "QEMU lm3s6965evb -cpu $cpu: $name${feed:+, fed $(basename "$feed") ($(stat -c %s "$feed") bytes)}"
  rm -rf "$sock" "$work/$name.bin" "$work/$name.feed.log"
  mkdir -p "$sock"
  serial0="file:$work/$name.bin"
  [ -z "$feed" ] || serial0="unix:$sock/rx,server=on,wait=on"
  set +e
  # defmt over semihosting to a file, decoded once QEMU is done: its size
  # is one of the signs of progress.
  qemu-system-arm -machine lm3s6965evb -cpu "$cpu" \
    -display none -monitor none -parallel none \
    -semihosting-config "$semihosting" \
    -icount shift=0 \
    -serial "$serial0" -serial "unix:$sock/sync,server=on,wait=on" \
    -qmp "unix:$sock/qmp,server=on,wait=off" \
    -kernel "$elf" >"$work/$name.defmt" 2>"$work/$name.qemu.err" &
  qemu=$!
  python3 "$root/scripts/oled-screens.py" capture --while "$qemu" "$sock/sync" "$sock/qmp" "$work/screens-$name" \
    >"$work/$name.screens.log" 2>&1 &
  capturer=$!
  if [ -n "$feed" ]; then
    python3 "$root/scripts/oled-screens.py" feed --while "$qemu" "$sock/rx" "$feed" "$work/$name.bin" >"$work/$name.feed.log" 2>&1 &
    feeder=$!
  fi
  watch_progress "$name" "$qemu" "$work/$name.defmt" "$work/$name.bin" "$work/$name.feed.log"
  wait "$qemu"; qemu_status=$?
  wait "$capturer"; capture_status=$?
  [ -z "$feeder" ] || { wait "$feeder"; feed_status=$?; }
  defmt-print -e "$elf" <"$work/$name.defmt" >"$work/$name.log" 2>&1
  set -e
  cat "$work/$name.log" "$work/$name.screens.log"
  [ -z "$feeder" ] || tail -n 1 "$work/$name.feed.log"
  [ ! -e "$work/$name.stalled" ] || die "$name: $(cat "$work/$name.stalled")"
  [ "$qemu_status" -eq 0 ] || { cat "$work/$name.qemu.err" >&2; die "$name: QEMU exited $qemu_status (panic, fault or failed run)"; }
  grep -q "$done" "$work/$name.log" || die "$name: no \"$done\" in the log"
  [ "$capture_status" -eq 0 ] || die "$name: the OLED pictures could not be taken"
  [ "$feed_status" -eq 0 ] || die "$name: $(basename "$feed") could not be fed"
  stack_check "$name"
}

# boot_start NAME ELF CPU FEED DONE [ARG...]: `boot` in the background, its
# output kept in $work/NAME.boot; boot_wait NAME prints it once that boot is
# done and fails if it failed. QEMU is single-threaded, so the boots that
# do not need each other's output run at once, as many as there are.
declare -A boot_pid=()
# A failed check stops the boots still running (each boot's QEMU and
# helpers are its subshell's children).
trap 'for pid in "${boot_pid[@]}"; do pkill -P "$pid" 2>/dev/null || true; kill "$pid" 2>/dev/null || true; done
rm -rf "$user_dir" "$sockets"' EXIT
boot_start() {
  (boot "$@") >"$work/$1.boot" 2>&1 &
  boot_pid[$1]=$!
}
boot_wait() {
  local status=0
  wait "${boot_pid[$1]}" || status=$?
  cat "$work/$1.boot"
  [ "$status" -eq 0 ] || die "$1: its boot failed (above)"
}

# watch_progress NAME PID FILE...: waits while QEMU (PID) runs. Its signs of
# progress are FILE… growing: the defmt log, the UART capture, the feeder's
# count of bytes taken. When none has grown for $QEMU_STALL seconds (default
# 300; the longest silence of a whole check is a few seconds), QEMU is
# stopped and $work/NAME.stalled says why. Prints how long QEMU ran and its
# longest silence.
watch_progress() {
  local name="$1" pid="$2" stall="${QEMU_STALL:-300}" size last=-1 since=$SECONDS longest=0 started=$SECONDS
  shift 2
  rm -f "$work/$name.stalled"
  while kill -0 "$pid" 2>/dev/null; do
    size="$(stat -c %s "$@" 2>/dev/null | awk '{s += $1} END {print s + 0}')"
    if [ "$size" != "$last" ]; then
      last="$size"; since=$SECONDS
    elif [ $((SECONDS - since)) -ge "$stall" ]; then
      echo "no progress for $stall s (no byte of defmt log, UART capture or feed; QEMU_STALL): stopped" >"$work/$name.stalled"
      kill "$pid" 2>/dev/null
      break
    fi
    [ $((SECONDS - since)) -le "$longest" ] || longest=$((SECONDS - since))
    sleep 1
  done
  echo "QEMU ran $((SECONDS - started)) s, its longest silence $longest s (stopped after $stall s)"
}

# stack_check NAME: fails when the painted stack of $work/NAME.log came
# within 64 bytes of its region's end: below it lies static RAM, which an
# overflow corrupts without a fault (the region is what the statics leave).
stack_check() {
  local peak region
  # No report line (the receiver measures no stack): nothing to check.
  read -r peak region < <(sed -n 's/.*report stack peak=\([0-9]*\) region=\([0-9]*\).*/\1 \2/p' "$work/$1.log") \
    || return 0
  [ "$peak" -le $((region - 64)) ] \
    || die "$1: the stack peak ($peak B) reaches the end of its region ($region B): it overflows into static RAM"
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

# Every boot whose firmware and input are ready starts now, at once: the
# three targets, the stream-only build, the surface and user-scenario
# builds and the built-in firmware serving the scenarios `morphogen send`
# wrote (below); the receiver's boots start once the first target's capture
# they are fed is there. Each is checked in turn as it ends.
for t in "${targets[@]}"; do
  cp "$tdir/$t/release/morphogen-firmware" "$work/$t.elf"
  boot_start "$t" "$work/$t.elf" "$(qemu_cpu "$t")" "" "all .* presets streamed"
done
boot_start stream-only "$work/stream-only.elf" cortex-m3 "" "all .* presets streamed"
boot_start surface "$work/surface.elf" cortex-m3 "" "all 1 presets streamed"
boot_start user "$work/user.elf" cortex-m3 "" "all .* presets streamed"

# ---- scenarios sent over UART0 (morphogen send) ------------------------------------
# The built-in firmware, started with `--serve 4`, waits for scenarios on
# UART0 and runs what `morphogen send` wrote: my-horn (the user scenario
# above), abop-shrub (an L-system), long-bone-random (a bone: the largest
# message) and growth-curve. Its capture must match the fixtures bit for bit
# and its OLED the host's pictures pixel for pixel.
sent_feed="$work/sent.feed"
: >"$sent_feed"
: >"$work/send.log"
for scenario in "$user_toml" abop-shrub long-bone-random growth-curve; do
  (cd "$root" && "${send_cmd[@]}" "$scenario" "$work/sent.one") >>"$work/send.log" 2>&1 \
    || { cat "$work/send.log"; die "morphogen send $scenario failed"; }
  cat "$work/sent.one" >>"$sent_feed"
done
cat "$work/send.log"
boot_start served "$work/thumbv7m-none-eabi.elf" cortex-m3 "$sent_feed" "all 4 presets streamed" --serve 4

# ---- the receiver ------------------------------------------------------------
# start_receivers: the receiver's two boots, fed the first target's capture
# and a damaged stream of ram-horn made from it.
start_receivers() {
  cp "$tdir/thumbv7m-none-eabi/release/morphogen-receiver" "$work/receiver.elf"

  # Every stream of the sender's capture, drawn exactly as the sender drew it.
  sent="${targets[0]}"
  streams=$(wc -l <"$work/screens-$sent/captured.txt")
  boot_start receiver "$work/receiver.elf" cortex-m3 "$work/$sent.bin" "all $streams streams received" --streams "$streams"

  # ram-horn with a bit flipped in its middle frame and in its last: those two
  # frames are skipped, so the OLED ends on the frame before the last, as the
  # host's `listen` draws the same damaged stream.
  damaged="$work/ram-horn.damaged.bin"
  read -r frames mid last < <(PYTHONPATH="$root/python" python3 - "$work/$sent.bin" ram-horn "$damaged" <<'PY'
import sys
import morphogen_stream as ms
capture, name, out = sys.argv[1:]
data = open(capture, "rb").read()
stream = next(s for s in ms.read_capture(data) if s.header and s.header.preset == name)
starts = [i for i, f in enumerate(stream.frames) if isinstance(f.record, ms.FrameStart)]
if len(starts) < 3:
    sys.exit(f"{name} has {len(starts)} frames; the damaged-stream check needs 3 or more")
damaged = bytearray(data[stream.start:stream.end])
hit = (len(starts) // 2, len(starts) - 1)
for k in hit:
    f = stream.frames[starts[k] + 2]  # a record inside frame k
    damaged[f.offset - stream.start + f.length // 2] ^= 0x10
open(out, "wb").write(bytes(damaged))
print(len(starts), *hit)
PY
  )
  boot_start damaged "$work/receiver.elf" cortex-m3 "$damaged" "all 1 streams received" --streams 1
}

# ---- the Cortex-M targets ---------------------------------------------------------
for t in "${targets[@]}"; do
  boot_wait "$t"
  say "verify $t capture ($(stat -c %s "$work/$t.bin") bytes)"
  verify "$work/$t.bin" "$work/$t.verify.log" || { cat "$work/$t.verify.log"; die "$t: capture does not match the fixtures"; }
  cat "$work/$t.verify.log"
  oled_check "$t"
  [ "$t" != "${targets[0]}" ] || start_receivers
done
# The stream-only build (no `extent`, `oled` or `serve`) writes the default
# build's streams without their extent frames: `morphogen run`'s stream.bin
# of every preset, back to back.
boot_wait stream-only
PYTHONPATH="$root/python" python3 -c 'import sys, morphogen_stream as ms
sys.stdout.buffer.write(b"".join(s.bytes for s in ms.read_capture(sys.argv[1])))' \
  "$work/${targets[0]}.bin" >"$work/${targets[0]}.streams.bin"
cmp "$work/stream-only.bin" "$work/${targets[0]}.streams.bin" \
  || die "stream-only: its capture differs from the ${targets[0]} build's streams"
say "stream-only: the same $(stat -c %s "$work/stream-only.bin") bytes as ${targets[0]}'s streams"

# ---- the receiver's checks ---------------------------------------------------
boot_wait receiver
[ "$(grep -c "report received .* skipped=0 bad=0" "$work/receiver.log")" -eq "$streams" ] \
  || die "receiver: a frame of an intact capture was skipped"
say "OLED: the receiver against the sender"
# shellcheck disable=SC2046 # one name per line, no spaces
python3 "$root/scripts/oled-screens.py" compare "$work/screens-receiver" "$work/screens-$sent" \
  $(cat "$work/screens-$sent/captured.txt") | tee "$work/receiver-oled.log" \
  || die "receiver: its OLED differs from the sender's (see $work/screens-receiver)"

boot_wait damaged
for k in "$mid" "$last"; do
  grep -q "frame $k skipped (damaged)" "$work/damaged.log" || die "damaged stream: frame $k was not skipped"
done
grep -q "report received preset=ram-horn shown=$((frames - 2)) skipped=2 bad=2" "$work/damaged.log" \
  || die "damaged stream: the receiver did not skip exactly the two damaged frames"
(cd "$root" && "${listen_cmd[@]}" "$damaged" --rig 128x64:grey4 --out "$work/host-screens-damaged") \
  >"$work/damaged.listen.log" 2>&1 || true # the stream differs from its fixture: exit 1
python3 "$root/scripts/oled-screens.py" compare "$work/screens-damaged" "$work/host-screens-damaged" ram-horn \
  | tee "$work/damaged-oled.log" || die "damaged stream: the receiver's OLED differs from the host's"
if python3 "$root/scripts/oled-screens.py" compare "$work/screens-damaged" "$work/screens-$sent" ram-horn \
  >>"$work/damaged-oled.log" 2>&1; then
  die "damaged stream: the OLED shows the damaged last frame"
fi
echo "damaged stream: frames $mid and $last of $frames skipped; the OLED shows frame $((last - 1)), as the host does"

# The pictures of the first target, beside the host's, where a reviewer
# looks: target/rig-screens/PRESET.{qemu,host}.png.
screens="$root/target/rig-screens"
rm -rf "$screens"; mkdir -p "$screens"
cp "$work/screens-${targets[0]}"/*.png "$screens/"
echo "OLED pictures: $screens"

# ---- a mosaic on a surface (the feature `surface`) ------------------------------
boot_wait surface
grep -q "report preset=watermelon-mcu " "$work/surface.log" || die "surface: the firmware did not run watermelon-mcu"
say "verify the surface capture ($(stat -c %s "$work/surface.bin") bytes)"
verify "$work/surface.bin" "$work/surface.verify.log" \
  || { cat "$work/surface.verify.log"; die "surface: the capture does not match the fixture"; }
cat "$work/surface.verify.log"
oled_check surface

# ---- user scenarios (MORPHOGEN_SCENARIOS) -----------------------------------------
# The firmware built above from the two user scenarios alone streams exactly
# what the host blesses from the same files.
boot_wait user
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
# The capture's streams without the extent frames (link records, not part
# of a stream).
PYTHONPATH="$root/python" python3 -c 'import sys, morphogen_stream as ms
sys.stdout.buffer.write(b"".join(s.bytes for s in ms.read_capture(sys.argv[1])))' "$work/user.bin" >"$work/user.streams.bin"
cmp -s "$work/user.streams.bin" "$work/user.expected.bin" \
  || die "user scenarios: the capture differs from the blessed stream.bin files"
echo "user scenarios: $user_name and wagging-tail streamed on the firmware match the host's bless, byte for byte"
oled_check user --fixtures "$user_dir/fixtures"

# ---- the scenarios sent over UART0: checks ---------------------------------------
for name in abop-shrub long-bone-random growth-curve; do
  cp -r "$root/fixtures/$name" "$user_dir/fixtures/"
done
boot_wait served
say "verify the capture of the sent scenarios ($(stat -c %s "$work/served.bin") bytes)"
verify "$work/served.bin" "$work/served.verify.log" --fixtures "$user_dir/fixtures" \
  || { cat "$work/served.verify.log"; die "sent scenarios: the capture does not match the fixtures"; }
cat "$work/served.verify.log"
oled_check served --fixtures "$user_dir/fixtures"

# The flipped bit lands in the preset whose stream holds the byte.
main_capture="$work/thumbv7m-none-eabi.bin"
expected="$(PYTHONPATH="$root/python" python3 - "$main_capture" "${flip%%:*}" <<'PY'
import os, sys
import morphogen_stream as ms
capture, flip = sys.argv[1], sys.argv[2]
at = int(flip) if flip else os.path.getsize(capture) // 2
for s in ms.read_capture(capture):
    if s.start <= at < s.end and s.header:
        print(s.header.preset)
PY
)"
negative_check "$main_capture" "$expected" "$work"

# ---- report ------------------------------------------------------------------
# Every preset the host knows (core, then the host presets of
# host-cli/src/host_presets.rs, marked "host only"), to name the host-only
# presets: `morphogen list` from the verify command's binary.
if [ -n "${MORPHOGEN_BIN:-}" ]; then
  "$MORPHOGEN_BIN" list >"$work/host-presets.txt" 2>/dev/null || rm -f "$work/host-presets.txt"
else
  (cd "$root" && cargo run --release -q -p morphogen-cli -- list) >"$work/host-presets.txt" 2>/dev/null \
    || rm -f "$work/host-presets.txt"
fi
say "the report ($work/REPORT.md)"
VERIFY_COMMAND="${verify_cmd[*]}" python3 "$fw/report.py" "$work" "${targets[@]}" >"$work/REPORT.md"
cat "$work/REPORT.md"
if [ $write_report -eq 1 ]; then
  cp "$work/REPORT.md" "$fw/REPORT.md"
  echo "written to firmware-example/REPORT.md"
fi
say "firmware check passed"
