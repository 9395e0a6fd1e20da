#!/usr/bin/env bash
# Prints the README's tables of speed and size figures (Morphogen against
# its peers first: scripts/bench-peers.sh), all measured in this one run
# (this machine is noisy: times are medians of several runs, and
# each ratio compares runs made side by side). Not part of CI.
#
#   bash scripts/bench.sh [RUNS]      RUNS per timed figure (default 5)
#
# Needs valgrind and gungraun-runner 0.20.0 for the instruction counts
# (installed here when missing) and the thumbv7m target for the flash.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
runs="${1:-5}"
say() { printf '\033[1m== %s\033[0m\n' "$*" >&2; }

command -v valgrind >/dev/null || { say "install valgrind"; sudo apt-get install -y valgrind; }
if [ "$(gungraun-runner --version 2>/dev/null | awk '{print $2}')" != "0.20.0" ]; then
  say "install gungraun-runner 0.20.0"
  cargo install gungraun-runner --version 0.20.0 --locked
fi
rustup target add thumbv7m-none-eabi >/dev/null 2>&1

say "build (release)"
cargo build --release -p morphogen-cli
bin="${CARGO_TARGET_DIR:-$root/target}/release/morphogen"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT

# median SECONDS of the wall time (or, with cpu, of the user+system CPU
# time) of RUNS runs of a command.
median() {
  python3 - "$runs" "$@" <<'PY'
import os, resource, statistics, subprocess, sys, time
runs, mode, cmd = int(sys.argv[1]), sys.argv[2], sys.argv[3:]
env = dict(os.environ)
while cmd and "=" in cmd[0] and not cmd[0].startswith("/"):
    k, v = cmd.pop(0).split("=", 1)
    env[k] = v
times = []
for _ in range(runs):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    subprocess.run(cmd, env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    times.append(cpu if mode == "cpu" else wall)
print(f"{statistics.median(times):.3f}")
PY
}
ratio() { python3 -c "print(f'{$1 / $2:.2f}')"; }

# ---- flash ------------------------------------------------------------------
# The stream-only build for size (every MCU preset streamed; no `extent`,
# `oled` or `serve`; profile `small`, opt-level "z") is the goal's figure,
# the default build (profile `release`; it also draws and serves) beside it.
say "flash: firmware, thumbv7m-none-eabi"
# As firmware-check.sh builds (and REPORT.md records) it: fixed paths.
. "$root/scripts/fixed-paths.sh"
fw_target="${CARGO_TARGET_DIR:-$root/firmware-example/target}/thumbv7m-none-eabi"
flash_of() { llvm-size -A "$1" | awk '$1 ~ /^\.(vector_table|text|rodata|data)$/ {s += $2} END {print s}'; }
(cd firmware-example && env -u MORPHOGEN_SCENARIOS cargo build --profile small --target thumbv7m-none-eabi \
  --no-default-features --features semihosting,bitwise-crc)
flash="$(flash_of "$fw_target/small/morphogen-firmware")"
(cd firmware-example && env -u MORPHOGEN_SCENARIOS cargo build --release --target thumbv7m-none-eabi)
flash_full="$(flash_of "$fw_target/release/morphogen-firmware")"

# ---- outputs ----------------------------------------------------------------
# CPU for every preset; instructions (callgrind) for those whose simulation
# takes under 0.1 s, below what a CPU clock resolves.
say "writing the outputs (run ÷ verify, run − verify), every preset"
ratios="$work/ratios.md"
bash scripts/bench-outputs.sh --runs "$runs" --bin "$bin" | tee "$ratios" >&2
fast=$(awk -F'|' '/^\|/ && NR > 2 && $3 + 0 < 0.1 {gsub(/ /, "", $2); print $2}' "$ratios")
# shellcheck disable=SC2086
bash scripts/bench-outputs.sh --instructions --bin "$bin" $fast | tee "$work/ratios-ir.md" >&2
# "min R (preset), median R, max R (preset); K of N presets <= 1.3"
summary() { sed -n 's/^run \/ verify ([^)]*): //p' "$1"; }

# ---- memory of a long grammar run -------------------------------------------
say "peak RSS, run --grammar shrub n = 7..11"
rss=""
for n in 7 8 9 10 11; do
  sed "s/^n = 7$/n = $n/" grammars/abop-shrub.lsys >"$work/shrub-$n.lsys"
  kb="$(/usr/bin/time -f %M "$bin" run --grammar "$work/shrub-$n.lsys" --out "$work/g" --max-stream-mb 4096 2>&1 >/dev/null | tail -1)"
  rss="$rss n=$n $((kb / 1024)) MB;"
done
rss10="$(echo "$rss" | sed -n 's/.*n=10 \([0-9]*\) MB.*/\1/p')"

# ---- threads ----------------------------------------------------------------
say "relaxation on 1 and 2 threads (croton-ageing)"
# The bench times the relaxation apart from the run, pair by pair; the
# whole `verify` (start-up, divisions, the digest: one thread) beside it.
threads="$(cargo bench -q -p morphogen-benches --bench threads 2>/dev/null | sed -n 's/^croton-ageing relaxation: //p')"
relax1="$(median wall RAYON_NUM_THREADS=1 "$bin" verify croton-ageing)"
relax2="$(median wall RAYON_NUM_THREADS=2 "$bin" verify croton-ageing)"
say "verify every preset, --jobs 1 and --jobs 2"
verify1="$(median wall "$bin" verify --jobs 1)"
verify2="$(median wall "$bin" verify --jobs 2)"

# ---- kernels ------------------------------------------------------------------
say "instruction counts (valgrind, gungraun)"
counts="$work/instructions.txt"
cargo bench -p morphogen-benches --bench model_instructions 2>&1 | tee "$counts" >&2
instructions() { # the Instructions line after the bench named $1
  awk -v b="$1" 'index($0, b) {found = 1} found && /Instructions:/ {gsub(/\|.*/, "", $2); print $2; exit}' "$counts"
}
relax_ir="$(instructions relaxation_step)"
relax_mcu_ir="$(instructions relaxation_step_per_cell)"
surface_ir="$(instructions surface_relaxation_step)"
surface_mcu_ir="$(instructions surface_relaxation_step_per_cell)"
shrub_ir="$(instructions "shrub n7")"
per_cell="$(python3 -c "print(round($relax_ir / 2000))")"
surface_per_cell="$(python3 -c "print(round($surface_ir / 2000))")"
say "shrinkwrap: bone-growth"
triangles="$("$bin" decode fixtures/bone-growth/stream.bin | grep -c '"kind":"triangle"')"
wrap_s="$(median cpu "$bin" verify bone-growth)"

# ---- against the peers ------------------------------------------------------
say "against the peers (scripts/bench-peers.sh)"
peers="$(bash scripts/bench-peers.sh --bin "$bin")"


cat <<EOF2

$peers

| figure | now | goal |
|---|---|---|
| flash, thumbv7m, all MCU presets | $flash B ($(python3 -c "print(f'{$flash / 1024:.1f}')") KiB) streamed (profile \`small\`); $flash_full B with \`oled\` and \`serve\` (profile \`release\`) | < 96 KB |
| \`run\` ÷ \`verify\` CPU, every preset | $(summary "$ratios") | ≤ 1.3× |
| \`run\` ÷ \`verify\` instructions, presets simulating in < 0.1 s | $(summary "$work/ratios-ir.md") | ≤ 1.3× |
| peak RSS, \`run --grammar\` shrub n = 10 | $rss10 MB ($rss) | < 24 MB, flat in n |
| relaxation, 2 threads ÷ 1 thread (croton-ageing) | relaxation alone (\`cargo bench -p morphogen-benches --bench threads\`): $threads; the whole \`verify\`: $(ratio "$relax1" "$relax2")× ($relax1 s / $relax2 s) | ≥ 1.7×, same bytes |
| \`verify\` of all presets, 2 cores | $(ratio "$verify1" "$verify2")× faster ($verify1 s / $verify2 s) | ≥ 1.7× faster |
| instructions per cell-relaxation step (croton, 2 000 cells) | $per_cell (each pair once, the host's step); $(python3 -c "print(round($relax_mcu_ir / 2000))") per cell one after another (the MCU's) | ≤ 700 |
| the same on a mesh (2 000 cells on watermelon-fruit's ellipsoid, w_r 1) | $surface_per_cell: $(python3 -c "print(f'{$surface_ir / $relax_ir:.2f}')")× the plane's; per cell (the MCU's) $(python3 -c "print(round($surface_mcu_ir / 2000))"): $(python3 -c "print(f'{$surface_mcu_ir / $relax_mcu_ir:.2f}')")× the plane's per cell | ≤ 2× |
| shrinkwrap triangles/s (bone-growth, \`verify\` CPU) | $(python3 -c "print(f'{$triangles / $wrap_s / 1000:.0f} K')") ($triangles in $wrap_s s) | ≥ 150 K |
| shrub n = 7 derive + turtle instructions | $(python3 -c "print(f'{$shrub_ir / 1e6:.1f} M')") | ≤ 20 M |

Times are medians of $runs runs; $(nproc) cores, $(date -u +%F).

writing the outputs, CPU (median of $runs): run ÷ verify, run − verify, and the presets within 1.3× or 0.3 s

$(cat "$ratios")

run ÷ verify, instructions (callgrind), for the presets that simulate in under 0.1 s:

$(cat "$work/ratios-ir.md")
EOF2
