#!/usr/bin/env bash
# Cargo runner: boots the firmware ELF ($1) in QEMU's lm3s6965evb (or, for
# riscv32imac-unknown-none-elf, its RISC-V `virt` machine: the stream-only
# build) with a deterministic instruction clock, UART0 captured to $MORPHOGEN_CAPTURE
# (default: target/uart0.bin next to this file) and the defmt log (semihosting
# stdout) decoded by defmt-print. Exits with QEMU's code (0 = all presets ok).
#
# With MORPHOGEN_FEED=FILE, UART0 also reads FILE, fed through a UNIX socket
# by scripts/oled-screens.py: a capture for the receiver (`cargo run
# --release --bin morphogen-receiver -- --streams 14`), or scenarios from
# `morphogen send` for the firmware (`cargo run --release -- --serve 1`).
# Arguments after the ELF (`cargo run … -- --streams 14`) are the program's
# semihosting arguments.
set -euo pipefail
elf="$1"
shift
semihosting="enable=on,target=native,arg=$(basename "$elf")"
for arg in "$@"; do semihosting+=",arg=$arg"; done
here="$(cd "$(dirname "$0")" && pwd)"
capture="${MORPHOGEN_CAPTURE:-$here/target/uart0.bin}"
mkdir -p "$(dirname "$capture")"
uart0=("file:$capture")
if [ -n "${MORPHOGEN_FEED:-}" ]; then
  sockets="$(mktemp -d)"
  trap 'rm -rf "$sockets"' EXIT
  python3 "$here/../scripts/oled-screens.py" feed "$sockets/uart0" "$MORPHOGEN_FEED" "$capture" >&2 &
  feeder=$!
  uart0=("unix:$sockets/uart0,server=on,wait=on")
fi
case "$elf" in
  */riscv32imac-unknown-none-elf/*) machine=(qemu-system-riscv32 -machine virt -bios none) ;;
  *) machine=(qemu-system-arm -machine lm3s6965evb -cpu cortex-m3) ;;
esac
set +e
"${machine[@]}" \
  -display none -monitor none -parallel none \
  -semihosting-config "$semihosting" \
  -icount shift=0 \
  -serial "${uart0[0]}" \
  -kernel "$elf" | defmt-print -e "$elf"
status=("${PIPESTATUS[@]}")
[ -z "${feeder:-}" ] || wait "$feeder"
set -e
[ "${status[1]}" -eq 0 ] || echo "qemu-run: defmt-print exited ${status[1]}" >&2
exit "${status[0]}"
