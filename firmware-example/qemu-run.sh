#!/usr/bin/env bash
# Cargo runner: boots the firmware ELF ($1) in QEMU's lm3s6965evb with a
# deterministic instruction clock, UART0 captured to $MORPHOGEN_CAPTURE
# (default: target/uart0.bin next to this file) and the defmt log (semihosting
# stdout) decoded by defmt-print. Exits with QEMU's code (0 = all presets ok).
set -euo pipefail
elf="$1"
here="$(cd "$(dirname "$0")" && pwd)"
capture="${MORPHOGEN_CAPTURE:-$here/target/uart0.bin}"
mkdir -p "$(dirname "$capture")"
set +e
qemu-system-arm -machine lm3s6965evb -cpu cortex-m3 \
  -display none -monitor none -parallel none \
  -semihosting-config enable=on,target=native \
  -icount shift=0 \
  -serial "file:$capture" \
  -kernel "$elf" | defmt-print -e "$elf"
status=("${PIPESTATUS[@]}")
set -e
[ "${status[1]}" -eq 0 ] || echo "qemu-run: defmt-print exited ${status[1]}" >&2
exit "${status[0]}"
