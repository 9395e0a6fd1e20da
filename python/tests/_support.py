"""Shared helpers of the Python reader's tests: paths, the Morphogen binary,
summary.toml, and record normalisation (16.16 values compared as bits)."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path
from typing import Dict, List, Optional

TESTS = Path(__file__).resolve().parent
PYTHON_DIR = TESTS.parent
REPO = PYTHON_DIR.parent
FIXTURES = REPO / "fixtures"
DOC = REPO / "docs" / "stream-format.md"

# Test the package of this source tree (installed or not).
if str(PYTHON_DIR) not in sys.path:
    sys.path.insert(0, str(PYTHON_DIR))

import morphogen_stream as ms  # noqa: E402


def morphogen_bin() -> Optional[Path]:
    """The Morphogen binary: $MORPHOGEN_BIN, default target/release/morphogen
    (relative paths are taken from the repository root); None if absent."""
    name = os.environ.get("MORPHOGEN_BIN", "target/release/morphogen")
    path = Path(name)
    if not path.is_absolute():
        path = REPO / path
    return path if path.is_file() and os.access(path, os.X_OK) else None


BIN = morphogen_bin()
NO_BIN = (
    "the morphogen binary is missing: set MORPHOGEN_BIN or build target/release/morphogen "
    f"(looked for {os.environ.get('MORPHOGEN_BIN', 'target/release/morphogen')})"
)


def run_bin(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Runs the Morphogen binary (bytes out)."""
    assert BIN is not None, NO_BIN
    proc = subprocess.run([str(BIN), *args], cwd=REPO, capture_output=True)
    if check and proc.returncode != 0:
        raise AssertionError(
            f"morphogen {' '.join(args)} exited {proc.returncode}: {proc.stderr.decode(errors='replace')}"
        )
    return proc


def bin_decode(path: Path) -> subprocess.CompletedProcess:
    """`morphogen decode PATH` (may exit 2 for a damaged stream)."""
    return run_bin("decode", str(path), check=False)


def run_cli(*args: str, stdin: bytes = b"") -> subprocess.CompletedProcess:
    """`python -m morphogen_stream ARGS` with this source tree."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(PYTHON_DIR) + os.pathsep + env.get("PYTHONPATH", "")
    return subprocess.run(
        [sys.executable, "-m", "morphogen_stream", *args],
        cwd=REPO,
        capture_output=True,
        input=stdin,
        env=env,
    )


def preset_names() -> List[str]:
    """The presets of `morphogen list` (first column)."""
    out = run_bin("list").stdout.decode()
    return [line.split()[0] for line in out.splitlines() if line.strip()]


def fixture_names() -> List[str]:
    """Every fixture folder holding a stream.bin."""
    return sorted(p.parent.name for p in FIXTURES.glob("*/stream.bin"))


def read_summary(path: Path) -> Dict[str, object]:
    """summary.toml as a dict (tomllib when there is one; else the flat
    `key = value` / `[table]` subset fixtures use)."""
    text = path.read_text(encoding="utf-8")
    try:
        import tomllib  # Python 3.11+

        return tomllib.loads(text)
    except ImportError:
        pass
    out: Dict[str, object] = {}
    table = out
    for line in text.splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        m = re.fullmatch(r"\[([A-Za-z0-9_.-]+)\]", line)
        if m:
            table = out.setdefault(m.group(1), {})
            continue
        m = re.fullmatch(r'([A-Za-z0-9_-]+|"[^"]*")\s*=\s*(.+)', line)
        if not m:
            continue
        key, value = m.group(1).strip('"'), m.group(2).strip()
        try:
            table[key] = json.loads(value)  # ints and basic strings
        except ValueError:
            table[key] = value
    return out


def _bits(v: object, where: str) -> int:
    if type(v) not in (int, float):
        raise AssertionError(f"{where}: {v!r} is not a number")
    return int(round(v * 65536))


def normalise(obj: Dict[str, object]) -> object:
    """A JSON record object as a comparable tuple: fixed-point values as
    their 16.16 bits (round(value * 65536)), integers checked to be
    integers, the exact set of fields. error/unknown objects stay dicts."""
    kind = obj.get("kind")
    schema = ms.SCHEMA.get(kind)  # type: ignore[arg-type]
    if schema is None:
        return obj
    if set(obj) != {"kind", *(name for name, _ in schema)}:
        return ("fields differ", obj)
    out: List[object] = [kind]
    for name, ty in schema:
        v = obj[name]
        if ty == "fx":
            out.append(_bits(v, name))
        elif ty in ("fx2", "fx3"):
            out.append(tuple(_bits(x, name) for x in v))  # type: ignore[union-attr]
        elif ty == "u32x3":
            out.append(tuple(v))  # type: ignore[arg-type]
            if not all(type(x) is int for x in v):  # type: ignore[union-attr]
                return ("not integers", obj)
        elif kind == "header" and name == "params":
            out.append(v)  # 16 hex digits
        elif ty == "str":
            out.append(v)
        else:
            if type(v) is not int:
                return ("not an integer", name, obj)
            out.append(v)
    return tuple(out)


def fixture_bytes(name: str) -> bytes:
    return (FIXTURES / name / "stream.bin").read_bytes()
