#!/usr/bin/env bash
# Prints the table of Morphogen against its peers, all measured in this one
# run, as instructions under callgrind net of each program's start-up:
# Morphogen's `verify` less `morphogen --version`; the L-system peer less
# its run of the axiom alone; the marching-cubes peer stage by stage
# (reading the stream, sampling the field, extracting the surfaces: each
# stage's count less the one before). Called by scripts/bench.sh; not part
# of CI.
#
#   bash scripts/bench-peers.sh [--bin MORPHOGEN]
#
# The peers are built beside the project from the registries, none of
# their code in it (scripts/peers/): the `lindenmayer` crate with an f64
# turtle (cargo, into <target>/peers) and scikit-image's marching cubes
# (pip, into a virtual environment <target>/peers/venv). The original
# MClone is measured by hand (docs/performance.md). Needs valgrind.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
bin=""
case "${1:-}" in
  --bin) bin="$2" ;;
  "") ;;
  *) echo "usage: bash scripts/bench-peers.sh [--bin MORPHOGEN]" >&2; exit 2 ;;
esac
say() { printf '\033[1m== %s\033[0m\n' "$*" >&2; }
command -v valgrind >/dev/null || { say "install valgrind"; sudo apt-get install -y valgrind; }
if [ -z "$bin" ]; then
  cargo build -q --release -p morphogen-cli
  bin="${CARGO_TARGET_DIR:-$root/target}/release/morphogen"
fi
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT

say "build the peers: the lindenmayer crate with an f64 turtle; scikit-image"
peer_dir="${CARGO_TARGET_DIR:-$root/target}/peers"
CARGO_TARGET_DIR="$peer_dir" cargo build -q --release --manifest-path scripts/peers/lsystem/Cargo.toml
peer_lsys="$peer_dir/release/lsystem-peer"
venv="$peer_dir/venv"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/pip" install -q -r scripts/peers/requirements.txt
py="$venv/bin/python"

# ir COMMAND…: the instructions it runs under callgrind.
ir() { valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 >/dev/null | sed -n 's/.*I *refs: *//p' | tr -d ,; }
startup="$(ir "$bin" --version)"
net() { echo $(( $(ir "$bin" verify "$1") - startup )); }
millions() { python3 -c "print(f'{$1 / 1e6:,.1f} M')"; }
ratio() { python3 -c "print(f'{$1 / $2:.2f}')"; }

say "ABOP shrub n = 7"
# The same grammar, derived and drawn by both: the same segments and
# polygons (`morphogen decode` of the fixture against the peer's counts).
shrub_counts="$("$peer_lsys" grammars/abop-shrub.lsys)"
"$bin" decode fixtures/abop-shrub/stream.bin | grep -o '"kind":"[a-z_]*"' | sort | uniq -c >"$work/shrub-kinds"
for k in segment polygon; do
  ours="$(awk -v k="\"kind\":\"$k\"" '$2 == k {print $1}' "$work/shrub-kinds")"
  case "$shrub_counts" in
    *"$ours ${k}s"*) ;;
    *) echo "bench-peers: the L-system peer drew other work ($shrub_counts; Morphogen: $ours ${k}s)" >&2; exit 1 ;;
  esac
done
peer_shrub=$(( $(ir "$peer_lsys" grammars/abop-shrub.lsys) - $(ir "$peer_lsys" grammars/abop-shrub.lsys 0) ))
shrub_net="$(net abop-shrub)"

say "bone-growth"
# The bone's field at every frame's skeleton, sampled at the spacing that
# gives the frame's triangle count, then marching cubes.
"$bin" decode fixtures/bone-growth/stream.bin >"$work/bone.jsonl"
cubes_fit="$("$py" scripts/peers/marching_cubes.py calibrate "$work/bone.jsonl" "$work/spacings.json")"
stage() { ir "$py" scripts/peers/marching_cubes.py run "$work/bone.jsonl" "$work/spacings.json" "$1"; }
read_ir="$(stage read)"
field_ir="$(stage field)"
cubes_ir="$(stage cubes)"
peer_field=$((field_ir - read_ir))
peer_cubes=$((cubes_ir - field_ir))
bone_net="$(net bone-growth)"

say "croton"
croton_net="$(net croton)"
# croton-mcu's simulation on the Cortex-M3, as the firmware check last
# wrote it (REPORT.md, `scripts/firmware-check.sh --write-report`).
mcu_ticks="$(awk -F'|' '$2 ~ /^ croton-mcu / {gsub(/[ ,]/, "", $7); sub(/\(.*/, "", $7); print $7; exit}' firmware-example/REPORT.md)"

cat <<EOF2
Against the peers (instructions under callgrind, net of start-up; $(date -u +%F)):

| figure | peer, same work | Morphogen | goal |
|---|---|---|---|
| ABOP shrub n = 7, derive + 3D turtle | \`lindenmayer\` 0.3 + f64 turtle: $(millions "$peer_shrub") ($shrub_counts) | $(millions "$shrub_net") with the stream encoded and checked (\`verify abop-shrub\`), $(ratio "$shrub_net" "$peer_shrub")× the peer | ≤ 9 M |
| bone-growth's 12 wraps at equal triangles | scikit-image \`marching_cubes\`: $(millions "$peer_cubes"), on the field sampled on its grids by numpy: $(millions "$peer_field"); $cubes_fit | $(millions "$bone_net") (\`verify bone-growth\`, every evaluation of the field included), $(ratio "$bone_net" "$((peer_field + peer_cubes))")× the peer's sampling and cubes | ≤ 218 M |
| croton, on the CPU | the original MClone, by hand (docs/performance.md) | $(millions "$croton_net") (\`verify croton\`) | ≤ 730 M |
| croton-mcu on a Cortex-M3, simulate ticks (REPORT.md) | — | $(millions "$mcu_ticks") | ≤ 5.9 M |
EOF2
