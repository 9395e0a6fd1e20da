"""docs/stream-format.md cannot drift from the code: its worked example is
parsed out of the markdown and checked against the golden stream and the
decoder, its constants against core/src/stream/encode.rs, and its Python
session is run (output compared)."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import unittest

from _support import DOC, PYTHON_DIR, REPO, fixture_bytes, ms
from morphogen_stream.cobs import cobs_decode

WORDS = {"one": 1, "two": 2, "three": 3, "four": 4, "five": 5, "six": 6, "seven": 7, "eight": 8}


def doc_text() -> str:
    return DOC.read_text(encoding="utf-8")


def section(text: str, title: str) -> str:
    start = text.index(f"\n## {title}\n")
    end = text.find("\n## ", start + 1)
    return text[start : end if end >= 0 else len(text)]


def fenced_blocks(text: str):
    """(info string, body, text before the block) of every fenced block."""
    out = []
    for m in re.finditer(r"^```([^\n]*)\n(.*?)^```\s*$", text, re.S | re.M):
        out.append((m.group(1).strip(), m.group(2), text[: m.start()]))
    return out


def checked_blocks(text: str):
    """Blocks announced by a `<!-- python/tests/test_doc.py ... -->` comment."""
    return [body for info, body, before in fenced_blocks(text) if before.rstrip().endswith("-->") and "test_doc.py" in before.rstrip().rsplit("<!--", 1)[-1]]


def hex_bytes(s: str) -> bytes:
    return bytes.fromhex(s.replace(" ", ""))


def rust_constants():
    """MAX_RECORD and MAX_FRAME as core/src/stream/encode.rs defines them."""
    src = (REPO / "core" / "src" / "stream" / "encode.rs").read_text(encoding="utf-8")
    record = int(re.search(r"pub const MAX_RECORD: usize = (\d+);", src).group(1))
    expr = re.search(r"pub const MAX_FRAME: usize = ([^;]+);", src).group(1)
    if not re.fullmatch(r"[A-Z_0-9+/*() -]+", expr):
        raise AssertionError(f"cannot evaluate MAX_FRAME = {expr}")
    frame = eval(expr.replace("MAX_RECORD", str(record)).replace("/", "//"), {"__builtins__": {}})
    return record, frame


class Constants(unittest.TestCase):
    def test_max_record_and_max_frame(self):
        record, frame = rust_constants()
        self.assertEqual((ms.MAX_RECORD, ms.MAX_FRAME), (record, frame))
        text = doc_text()
        for name, value in (("MAX_RECORD", record), ("MAX_FRAME", frame)):
            stated = [int(n) for n in re.findall(rf"`{name}` = (\d+)", text)]
            self.assertTrue(stated, f"the doc does not state {name}")
            self.assertEqual(set(stated), {value}, f"{name} in {DOC.name}")
        stated = re.findall(r"`MAX_FRAME` − 1 = (\d+)", text)
        self.assertEqual([int(n) for n in stated], [frame - 1])

    def test_format_version_and_kinds(self):
        src = (REPO / "core" / "src" / "stream" / "record.rs").read_text(encoding="utf-8")
        self.assertEqual(int(re.search(r"FORMAT_VERSION: u16 = (\d+);", src).group(1)), ms.FORMAT_VERSION)
        self.assertIn(f"# Morphogen stream format, version {ms.FORMAT_VERSION}", doc_text())
        # The table of kinds: tag, kind and field names in order.
        rows = re.findall(r"^\| (\d+) \| `(\w+)` \| (.*) \|$", doc_text(), re.M)
        self.assertEqual([int(r[0]) for r in rows], list(range(ms.RECORD_KINDS)))
        for tag, kind, fields in rows:
            cls = ms.RECORD_TYPES[int(tag)]
            self.assertEqual(kind, cls.kind)
            names = re.findall(r"`(\w+):", fields)
            wire = [n if n != "type" else "kind" for n, _ in cls.FIELDS]
            self.assertEqual(names, wire, kind)


class WorkedExample(unittest.TestCase):
    @classmethod
    def setUpClass(cls) -> None:
        cls.text = section(doc_text(), "Worked example")
        cls.blocks = checked_blocks(cls.text)
        cls.stream = fixture_bytes("growth-curve")
        cls.frames = list(ms.iter_frames(cls.stream))

    def test_frames_are_the_golden_stream(self):
        lines = [l for l in self.blocks[0].splitlines() if l.strip()]
        count = re.search(r"The first (\w+) frames", self.text).group(1)
        self.assertEqual(len(lines), WORDS[count])
        for line, frame in zip(lines, self.frames):
            self.assertEqual(hex_bytes(line), self.stream[frame.offset : frame.offset + frame.length])

    def test_frame_1_decoded(self):
        first = self.frames[0]
        wire = self.stream[first.offset : first.offset + first.length]
        decoded = cobs_decode(wire[:-1])
        rows = []
        for line in self.blocks[1].splitlines():
            m = re.fullmatch(r"((?:[0-9a-f]{2} )*[0-9a-f]{2})\s{2,}(.*)", line.strip())
            self.assertIsNotNone(m, f"not `hex  comment`: {line!r}")
            rows.append((hex_bytes(m.group(1)), m.group(2)))
        self.assertEqual(b"".join(b for b, _ in rows), decoded)
        m = re.search(r"Frame 1 \((\d+) bytes on the wire\)", self.text)
        self.assertEqual(int(m.group(1)), len(wire))
        m = re.search(r"The (\d+) decoded\s+bytes", self.text)
        self.assertEqual(int(m.group(1)), len(decoded))
        # The COBS walk-through: codes and their data-byte counts.
        codes = re.findall(r"code\s+`([0-9a-f]{2})`\s+→\s+(no|\d+)\s+data\s+bytes", self.text)
        i = 0
        for code, n in codes:
            self.assertEqual(wire[i], int(code, 16))
            self.assertEqual(0 if n == "no" else int(n), wire[i] - 1)
            i += wire[i]
        self.assertEqual(i, len(wire) - 1, "the walk-through covers every block")
        # Comments: the CRC and the byte count it covers, the params, the name.
        record = decoded[:-4]
        m = re.search(r"CRC-32 0x([0-9a-f]{8}) of the (\d+) bytes above", self.blocks[1])
        self.assertEqual(int(m.group(1), 16), ms.crc32(record))
        self.assertEqual(int(m.group(1), 16), int.from_bytes(decoded[-4:], "little"))
        self.assertEqual(int(m.group(2)), len(record))
        header = first.record
        m = re.search(r"params 0x([0-9a-f]{16})", self.blocks[1])
        self.assertEqual(int(m.group(1), 16), header.params)
        m = re.search(r'"([^"]+)" \((\d+) bytes\)', self.blocks[1])
        self.assertEqual(m.group(1), header.preset)
        self.assertEqual(int(m.group(2)), len(header.preset.encode()))
        # The JSON line shown for it.
        line = re.search(r"`(\{\"kind\":\"header\".*?\})`", self.text).group(1)
        self.assertEqual(json.loads(line), header.to_dict())

    def test_prose_about_frames_2_to_5(self):
        stated = re.findall(r"Frame (\d) decodes to `([0-9a-f ]+)` \+ CRC", self.text)
        self.assertEqual([int(k) for k, _ in stated], [2, 3, 4, 5])
        for k, hexes in stated:
            frame = self.frames[int(k) - 1]
            wire = self.stream[frame.offset : frame.offset + frame.length]
            self.assertEqual(hex_bytes(hexes), cobs_decode(wire[:-1])[:-4], f"frame {k}")
        self.assertEqual(self.frames[3].record, ms.Sample(1, 0.0, 3 / 65536))
        self.assertEqual(self.frames[4].record, ms.Sample(0, 1.0, 3 / 65536))
        self.assertIn(ms.fx_text(3), self.text)


HARNESS = r"""
import contextlib, io, json, sys
blocks = json.load(sys.stdin)
namespace = {"__name__": "__doc_example__"}
outputs = []
for code in blocks:
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        exec(compile(code, "<docs/stream-format.md>", "exec"), namespace)
    outputs.append(buf.getvalue())
json.dump(outputs, sys.stdout)
"""


class PythonSection(unittest.TestCase):
    def test_session_runs_and_prints_what_the_doc_shows(self):
        blocks = fenced_blocks(section(doc_text(), "Reading a stream from Python"))
        code, expected = [], {}
        for info, body, _ in blocks:
            if info == "python":
                code.append(body)
            elif info == "text" and code:
                expected[len(code) - 1] = body
        self.assertGreaterEqual(len(code), 3)
        self.assertTrue(expected)
        env = dict(os.environ, MPLBACKEND="Agg")
        env["PYTHONPATH"] = str(PYTHON_DIR) + os.pathsep + env.get("PYTHONPATH", "")
        proc = subprocess.run(
            [sys.executable, "-c", HARNESS],
            input=json.dumps(code).encode(),
            capture_output=True,
            cwd=REPO,
            env=env,
        )
        self.assertEqual(proc.returncode, 0, proc.stderr.decode(errors="replace"))
        outputs = json.loads(proc.stdout)
        for i, want in expected.items():
            self.assertEqual(outputs[i].rstrip(), want.rstrip(), f"output of Python block {i + 1}")


if __name__ == "__main__":
    unittest.main()
