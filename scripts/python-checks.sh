#!/usr/bin/env bash
# Every Python check, in order: the stream reader against every preset
# (python/), the Python package (python-ext/: its wheel, every preset, a
# sweep on Dask, the notebook), plot.svg read back with vpype, and the
# cluster recipes of docs/sweeps.md. Each prints a `==> ` line, then how
# long it took; with CHECK_TIMINGS=FILE each also appends "SECONDS<TAB>NAME"
# to FILE (scripts/check.sh runs this beside its next steps and lists the
# times with its own). Installs what they need when missing.
#
#   MORPHOGEN_BIN=target/release/morphogen bash scripts/python-checks.sh
set -euo pipefail
cd "$(dirname "$0")/.."

morphogen="${MORPHOGEN_BIN:-target/release/morphogen}"
export MORPHOGEN_BIN="$morphogen"
name=""
started=$SECONDS
done_with() {
    [ -n "$name" ] || return 0
    local took=$((SECONDS - started))
    printf '(%s: %d s)\n' "$name" "$took"
    [ -z "${CHECK_TIMINGS:-}" ] || printf '%d\t%s\n' "$took" "$name" >>"$CHECK_TIMINGS"
}
part() {
    done_with
    name="${*%%:*}"
    name="${name%% (*}"
    started=$SECONDS
    printf '\n==> %s\n' "$*"
}

part "the Python stream reader against every preset (python/)"
bash scripts/python-check.sh

part "the Python package: its wheel built once (maturin, release, reusing the release build), every preset against its fixture, a sweep on Dask, the notebook (python-ext/, docs/notebook.ipynb)"
bash scripts/python-ext-check.sh

part "plot.svg read back with vpype, one preset per model (scripts/plot-check.py)"
# In the Python package's environment (python-ext-check made it): vpype is
# on PyPI only, and a Debian python3 refuses pip outside an environment.
venv_python="${CARGO_TARGET_DIR:-target}/python-ext-venv/bin/python"
if ! "$venv_python" -c 'import vpype' 2>/dev/null; then
    echo "plot-check: installing vpype"
    "$venv_python" -m pip install --quiet --disable-pip-version-check vpype
fi
"$venv_python" scripts/plot-check.py --bin "$morphogen"

part "the cluster recipes of docs/sweeps.md (Slurm array job, GNU parallel, Snakemake) merge into the one-machine table"
if ! command -v parallel >/dev/null; then
    as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }
    as_root apt-get update -qq
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq parallel
fi
if ! "$venv_python" -c 'import snakemake' 2>/dev/null; then
    echo "sweep-recipes-check: installing snakemake"
    "$venv_python" -m pip install --quiet --disable-pip-version-check snakemake
fi
PATH="$(dirname "$venv_python"):$PATH" "$venv_python" scripts/sweep-recipes-check.py --bin "$morphogen"
done_with
