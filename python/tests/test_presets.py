"""Every preset's golden stream, read by the Python reader, against
`morphogen decode` (record for record, 16.16 values compared as bits) and
against its fixtures/<preset>/summary.toml (digest, sizes, counts)."""

from __future__ import annotations

import json
import sys
import tempfile
import time
import unittest
from collections import Counter
from pathlib import Path

from _support import (
    BIN,
    FIXTURES,
    NO_BIN,
    bin_decode,
    fixture_bytes,
    fixture_names,
    ms,
    normalise,
    preset_names,
    read_summary,
    run_bin,
)

PRESETS = preset_names() if BIN is not None else []
NAMES = sorted(set(PRESETS) | set(fixture_names()))
TIMES = {}


def compare_with_binary(test: unittest.TestCase, frames, stdout: bytes, label: str) -> int:
    """Asserts that `frames` and the JSON lines `stdout` are the same
    records; returns how many were compared.

    The first records of each kind are compared field by field after
    `normalise` (16.16 values as bits = round(value * 65536), integers
    checked to be integers, the exact set of fields). The rest are compared
    as dicts: the reader's fixed-point floats are exactly bits / 65536, so
    a float equal to one is the same 16.16 value; a record that is not
    equal as a dict is normalised before it is reported (a printed decimal
    that only rounds to the same bits still passes)."""
    lines = stdout.decode("utf-8").splitlines()
    test.assertEqual(len(lines), len(frames), f"{label}: number of records")
    # One json.loads for all lines: much faster than one per line.
    objects = json.loads("[" + ",".join(lines) + "]")
    strict: Counter = Counter()
    for i, (want, frame) in enumerate(zip(objects, frames)):
        got = frame.to_dict()
        kind = got["kind"]
        if strict[kind] < STRICT_PER_KIND or got != want:
            strict[kind] += 1
            if normalise(want) != normalise(got):
                test.fail(
                    f"{label}: record {i} (byte {frame.offset}) differs:\n"
                    f"  morphogen: {lines[i]}\n  python:    {frame.to_json()}"
                )
    return len(lines)


#: Records of each kind compared field by field, per stream.
STRICT_PER_KIND = 200


class EveryPreset(unittest.TestCase):
    """One test per preset and fixture (generated below)."""

    def test_every_listed_preset_has_a_fixture(self):
        if BIN is None:
            self.skipTest(NO_BIN)
        self.assertTrue(PRESETS, "morphogen list printed no presets")
        missing = [p for p in PRESETS if not (FIXTURES / p / "stream.bin").is_file()]
        self.assertEqual(missing, [], "presets without fixtures/<preset>/stream.bin")

    def check(self, name: str) -> None:
        start = time.perf_counter()
        path = FIXTURES / name / "stream.bin"
        data = fixture_bytes(name)
        frames = list(ms.iter_frames(data))
        self.assertTrue(frames, f"{name}: no frames")
        bad = [f for f in frames if f.error is not None]
        self.assertEqual(bad, [], f"{name}: frames that do not decode")
        summary = read_summary(FIXTURES / name / "summary.toml")

        # The digest and the header, as the summary records them.
        digest = ms.stream_digest(data)
        self.assertEqual(f"{digest:016x}", summary["stream_digest"], f"{name}: stream digest")
        header = frames[0].record
        self.assertIsInstance(header, ms.Header)
        self.assertEqual(header.version, summary["format_version"])
        self.assertEqual(header.preset, summary["preset"])
        self.assertEqual(header.seed, summary["seed"])
        self.assertEqual(f"{header.params:016x}", summary["params_digest"])
        self.assertEqual(len(data), summary["bytes"])
        self.assertEqual(len(frames), summary["frames"])
        counts = Counter(f.record.kind for f in frames)
        self.assertEqual(dict(counts), summary["records"], f"{name}: records per kind")
        self.assertEqual(sum(f.record.tag == 0 for f in frames), 1, "one stream")

        if BIN is None:
            self.skipTest(f"{name}: digest and summary checked; record comparison skipped: {NO_BIN}")
        proc = bin_decode(path)
        self.assertEqual(proc.returncode, 0, proc.stderr.decode(errors="replace"))
        n = compare_with_binary(self, frames, proc.stdout, name)
        TIMES[name] = (n, time.perf_counter() - start)


def _make(name: str):
    def test(self: EveryPreset) -> None:
        self.check(name)

    test.__doc__ = f"fixtures/{name}: digest, summary and records against `morphogen decode`"
    return test


for _name in NAMES:
    setattr(EveryPreset, "test_fixture_" + _name.replace("-", "_"), _make(_name))


class RunOutput(unittest.TestCase):
    """`morphogen run` writes stream.bin and records.jsonl: the Python
    reading of the first is the second (one cheap preset)."""

    def test_run_growth_curve_records_jsonl(self):
        if BIN is None:
            self.skipTest(NO_BIN)
        with tempfile.TemporaryDirectory() as tmp:
            out = Path(tmp) / "out"
            run_bin("run", "growth-curve", "--out", str(out))
            frames = list(ms.iter_frames((out / "stream.bin").read_bytes()))
            compare_with_binary(self, frames, (out / "records.jsonl").read_bytes(), "records.jsonl")
            self.assertEqual((out / "stream.bin").read_bytes(), fixture_bytes("growth-curve"))


def tearDownModule() -> None:
    if TIMES:
        n = sum(v[0] for v in TIMES.values())
        t = sum(v[1] for v in TIMES.values())
        # sys.__stderr__: not swallowed by `unittest -b`.
        sys.__stderr__.write(
            f"\n[presets] {len(TIMES)} fixtures compared with `morphogen decode`: {n} records in {t:.1f} s\n"
        )


if __name__ == "__main__":
    unittest.main()
