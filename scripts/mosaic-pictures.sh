#!/usr/bin/env bash
# Redraws the pictures of docs/mosaics.md: the last day of every mosaic
# preset of the thesis's Table 4.1 (the object itself where the cells grow
# on a mesh or a cylinder, else the Voronoi picture), 260 pixels high.
# Needs the release binary (cargo build --release -p morphogen-cli) and
# python3 (scripts/thumbnail.py scales the pictures).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=target/release/morphogen
out=docs/mosaics
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
presets=(croton croton-individual croton-ageing croton-yellow cactus-spots cactus-uniform
  cactus-stem philodendron philodendron-ageing philodendron-leaf cactus-structured mushroom
  amanita amanita-df8 amanita-df20 amanita-mushroom watermelon-narrow watermelon watermelon-wide
  watermelon-fruit watermelon-mcu watermelon-sphere watermelon-square sansevieria sansevieria-leaf)
for p in "${presets[@]}"; do
  "$bin" run "$p" --only png --quiet --out "$tmp/$p"
  src="$tmp/$p/surface.png"
  [ -f "$src" ] || src="$tmp/$p/mosaic.png"
  python3 scripts/thumbnail.py "$src" "$out/$p.png" 260
  echo "$out/$p.png"
done
