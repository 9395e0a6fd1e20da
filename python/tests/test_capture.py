"""A device capture: several streams back to back, each starting with its
header; each stream's digest is its fixture's."""

from __future__ import annotations

import json
import tempfile
import unittest
from pathlib import Path

from _support import BIN, FIXTURES, bin_decode, fixture_bytes, ms, normalise, read_summary, run_cli

FIRST, SECOND = "growth-curve", "long-bone"


class Capture(unittest.TestCase):
    @classmethod
    def setUpClass(cls) -> None:
        cls.a = fixture_bytes(FIRST)
        cls.b = fixture_bytes(SECOND)
        cls.capture = cls.a + cls.b

    def test_two_streams_split_with_their_digests(self):
        streams = ms.read_capture(self.capture)
        self.assertEqual([s.header.preset for s in streams], [FIRST, SECOND])
        self.assertEqual((streams[0].start, streams[0].end), (0, len(self.a)))
        self.assertEqual((streams[1].start, streams[1].end), (len(self.a), len(self.capture)))
        for s, name in zip(streams, (FIRST, SECOND)):
            summary = read_summary(FIXTURES / name / "summary.toml")
            self.assertEqual(f"{s.digest:016x}", summary["stream_digest"], name)
            self.assertEqual(len(s.frames), summary["frames"], name)
            self.assertEqual(s.errors, [])
            self.assertEqual(s.records, ms.read_records(fixture_bytes(name)))
        # The whole capture's digest is of all its bytes, not a combination.
        self.assertEqual(ms.stream_digest(self.capture), ms.crc64_xz(self.a + self.b))
        running = ms.Crc64()
        running.update(self.a)
        running.update(self.b)
        self.assertEqual(running.value(), ms.stream_digest(self.capture))
        # read_records gives both streams' records, headers included.
        records = ms.read_records(self.capture)
        self.assertEqual(sum(isinstance(r, ms.Header) for r in records), 2)
        self.assertEqual(len(records), len(streams[0].frames) + len(streams[1].frames))

    def test_bytes_before_the_first_header_and_a_damaged_second_stream(self):
        junk = b"\x13\x37" + b"\x00" + ms.encode_frame(ms.FrameEnd(5))
        damaged = bytearray(self.b)
        frames = list(ms.iter_frames(self.b))
        damaged[frames[10].offset + frames[10].length - 2] ^= 0x40  # a CRC byte
        streams = ms.read_capture(junk + self.a + bytes(damaged))
        self.assertIsNone(streams[0].header)
        self.assertEqual((streams[0].start, streams[0].end), (0, len(junk)))
        self.assertEqual(len(streams[0].errors), 1)
        self.assertEqual(streams[1].digest, ms.stream_digest(self.a))
        self.assertEqual(len(streams[2].errors), 1)
        self.assertEqual(streams[2].errors[0].offset, len(junk) + len(self.a) + frames[10].offset)
        self.assertNotEqual(streams[2].digest, ms.stream_digest(self.b))

    def test_cli_on_a_capture(self):
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "capture.bin"
            path.write_bytes(self.capture)
            summary = run_cli("--streams", str(path))
            self.assertEqual(summary.returncode, 0, summary.stderr)
            lines = [json.loads(l) for l in summary.stdout.decode().splitlines()]
            self.assertEqual([l["preset"] for l in lines], [FIRST, SECOND])
            for line in lines:
                want = read_summary(FIXTURES / line["preset"] / "summary.toml")
                self.assertEqual(line["stream_digest"], want["stream_digest"])
                self.assertEqual(line["records"], want["records"])
                self.assertEqual(line["bytes"], want["bytes"])
            py = run_cli(str(path))
            self.assertEqual(py.returncode, 0)
            out = Path(tmp) / "capture.jsonl"
            written = run_cli("--out", str(out), str(path))
            self.assertEqual((written.returncode, written.stdout), (0, b""))
            self.assertEqual(out.read_bytes(), py.stdout)
            if BIN is not None:
                rs = bin_decode(path)
                self.assertEqual(rs.returncode, 0)
                self.assertEqual(
                    [normalise(json.loads(l)) for l in py.stdout.decode().splitlines()],
                    [normalise(json.loads(l)) for l in rs.stdout.decode().splitlines()],
                )


if __name__ == "__main__":
    unittest.main()
