#!/usr/bin/env bash
# The Python package `morphogen` (python-ext/): its wheel built once with
# maturin in release mode, into the Cargo target folder ($CARGO_TARGET_DIR,
# else target/), where the CLI's release build has left every dependency
# compiled; installed into a virtual environment of the Python that
# python-check uses (its own pip and numpy, whatever Debian's Python
# allows), then its tests: every preset against its fixture, the --set
# errors, the written files (compared with MORPHOGEN_BIN's, default
# target/release/morphogen, when there is one), sweeps on a process pool
# and on a Dask LocalCluster, and Ctrl-C; then docs/notebook.ipynb,
# executed headless (nbclient's `jupyter execute`).
#
#   scripts/python-ext-check.sh        # PYTHON=python3.9 scripts/python-ext-check.sh
set -euo pipefail
cd "$(dirname "$0")/.."

python="${PYTHON:-python3}"
if ! "$python" -c 'import sys; sys.exit(sys.version_info < (3, 9))' 2>/dev/null; then
    echo "python-ext-check: $python is missing or older than 3.9" >&2
    exit 2
fi
target="${CARGO_TARGET_DIR:-target}"
venv="$target/python-ext-venv"
wheels="$target/wheels"

# The environment, kept in the target folder for the next run. Debian's
# Python makes one only with python3-venv installed.
if [[ ! -x "$venv/bin/python" ]]; then
    if ! "$python" -m venv "$venv" 2>/dev/null; then
        rm -rf "$venv"
        echo "python-ext-check: installing python3-venv"
        as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }
        as_root apt-get update -qq
        as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3-venv
        "$python" -m venv "$venv"
    fi
fi
venv_python="$venv/bin/python"
pip=("$venv_python" -m pip --quiet --disable-pip-version-check)
"$venv_python" -c 'import numpy' 2>/dev/null || "${pip[@]}" install numpy
"$venv/bin/maturin" --version >/dev/null 2>&1 || "${pip[@]}" install 'maturin>=1.9.4,<2'
# The tests' Dask cluster; the notebook's kernel, runner and plots.
"$venv_python" -c 'import dask.distributed, nbclient, ipykernel, matplotlib' 2>/dev/null ||
    "${pip[@]}" install 'dask[distributed]' nbclient ipykernel matplotlib

started=$SECONDS
rm -rf "$wheels"
"$venv/bin/maturin" build --release --quiet --manifest-path python-ext/Cargo.toml \
    --interpreter "$venv_python" --out "$wheels"
built=$((SECONDS - started))
"${pip[@]}" install --force-reinstall --no-deps "$wheels"/morphogen-*.whl
echo "python-ext-check: $(cd "$wheels" && ls) built in ${built} s"

# From the repository root, as python-check's tests run; the package is
# the installed wheel's (python-ext/ is not on the path).
"$venv_python" --version
"$venv_python" -m unittest discover -b -s python-ext/tests -t python-ext/tests
"$venv/bin/jupyter-execute" docs/notebook.ipynb
echo "python-ext-check: build and tests took $((SECONDS - started)) s"
