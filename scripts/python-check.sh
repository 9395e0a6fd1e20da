#!/usr/bin/env bash
# The Python stream reader's tests (python/, docs/stream-format.md's worked
# example and Python session): standard library only, plus numpy for the
# to_arrays tests (installed with apt-get when missing, as CI needs). Record-for-record comparisons need the
# release binary: CI passes it as MORPHOGEN_BIN after building it; locally
# the default is target/release/morphogen (those comparisons are skipped,
# with a message, when it is missing and MORPHOGEN_BIN is not set).
#
#   scripts/python-check.sh            # PYTHON=python3.9 scripts/python-check.sh
set -euo pipefail
cd "$(dirname "$0")/.."

python="${PYTHON:-python3}"
if ! "$python" -c 'import sys; sys.exit(sys.version_info < (3, 9))' 2>/dev/null; then
    echo "python-check: $python is missing or older than 3.9" >&2
    exit 2
fi

if [[ -n "${MORPHOGEN_BIN:-}" ]]; then
    if [[ ! -x "$MORPHOGEN_BIN" ]]; then
        echo "python-check: MORPHOGEN_BIN=$MORPHOGEN_BIN is not an executable file" >&2
        exit 2
    fi
    echo "python-check: comparing with $MORPHOGEN_BIN"
elif [[ -x target/release/morphogen ]]; then
    echo "python-check: comparing with target/release/morphogen"
else
    echo "python-check: warning: no morphogen binary (set MORPHOGEN_BIN); record comparisons will be skipped" >&2
fi

# numpy is optional for users, not here: CI tests the to_arrays path too.
# From PyPI into this Python (a pyenv or venv one), else from apt-get
# (Debian's own python3, whose environment pip must not touch).
if ! "$python" -c 'import numpy' 2>/dev/null; then
    echo "python-check: installing numpy"
    if ! "$python" -m pip install --quiet --disable-pip-version-check numpy 2>/dev/null; then
        as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }
        as_root apt-get update -qq
        as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3-numpy
    fi
fi
if numpy_version=$("$python" -c 'import numpy; print(numpy.__version__)' 2>/dev/null); then
    echo "python-check: numpy $numpy_version: the to_arrays tests run"
else
    echo "python-check: numpy is not installed: the to_arrays tests are skipped"
fi

"$python" --version
# -b: keep the output of passing tests quiet.
"$python" -m unittest discover -b -s python/tests -t python/tests
