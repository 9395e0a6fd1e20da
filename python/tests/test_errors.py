"""Damaged input: a flipped byte, a truncated file, frames of a newer kind
or version, garbage. Offsets and error kinds as the Rust decoder reports
them (compared with `morphogen decode` when the binary is there); the
command line never shows a traceback."""

from __future__ import annotations

import json
import random
import tempfile
import unittest
from pathlib import Path

from _support import BIN, NO_BIN, bin_decode, fixture_bytes, ms, normalise, run_cli  # noqa: F401


def frame_offsets(data: bytes):
    return [f.offset for f in ms.iter_frames(data)]


def data_byte(data: bytes, frame) -> int:
    """The offset of the first byte of `frame` that is not a COBS code."""
    codes = set()
    i = frame.offset
    while i < frame.offset + frame.length - 1:
        codes.add(i)
        i += data[i]
    return next(j for j in range(frame.offset, frame.offset + frame.length - 1) if j not in codes)


class Damage(unittest.TestCase):
    def setUp(self) -> None:
        self.data = fixture_bytes("growth-curve")
        self.frames = list(ms.iter_frames(self.data))
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)

    def write(self, name: str, data: bytes) -> Path:
        path = Path(self.tmp.name) / name
        path.write_bytes(data)
        return path

    def same_as_binary(self, path: Path) -> None:
        """The Python CLI's lines and exit status are morphogen decode's."""
        py = run_cli(str(path))
        self.assertNotIn(b"Traceback", py.stderr)
        if BIN is None:
            return
        rs = bin_decode(path)
        self.assertEqual(py.returncode, rs.returncode, (py.stderr, rs.stderr))
        a = [normalise(json.loads(l)) for l in py.stdout.decode().splitlines()]
        b = [normalise(json.loads(l)) for l in rs.stdout.decode().splitlines()]
        self.assertEqual(a, b)

    def test_flipped_byte_is_a_crc_error_at_its_frame(self):
        target = self.frames[100]
        # A data byte inside the frame (not one of its COBS code bytes, not
        # the delimiter), flipped to another non-zero value.
        i = data_byte(self.data, target)
        damaged = bytearray(self.data)
        damaged[i] ^= 0x01 if damaged[i] != 0x01 else 0x02
        frames = list(ms.iter_frames(bytes(damaged)))
        self.assertEqual(len(frames), len(self.frames))
        bad = [f for f in frames if f.error is not None]
        self.assertEqual(len(bad), 1)
        self.assertIsInstance(bad[0].error, ms.CrcError)
        self.assertEqual(bad[0].offset, target.offset)
        self.assertEqual(bad[0].error.offset, target.offset)
        self.assertTrue(bad[0].error.is_corrupt)
        self.assertIn("CRC mismatch (frame carries 0x", str(bad[0].error))
        # Resynchronised: every other frame reads as before.
        for f, g in zip(frames, self.frames):
            if f.offset != target.offset:
                self.assertEqual(f, g)
        with self.assertRaises(ms.CrcError) as caught:
            ms.read_records(bytes(damaged))
        self.assertEqual(caught.exception.offset, target.offset)
        self.assertEqual(len(ms.read_records(bytes(damaged), errors="skip")), len(self.frames) - 1)
        # The stream digest no longer matches the fixture's.
        self.assertNotEqual(ms.stream_digest(bytes(damaged)), ms.stream_digest(self.data))

        path = self.write("flipped.bin", bytes(damaged))
        cli = run_cli(str(path))
        self.assertEqual(cli.returncode, 2)
        self.assertNotIn(b"Traceback", cli.stderr)
        self.assertIn(f"at byte {target.offset}".encode(), cli.stderr)
        line = cli.stdout.decode().splitlines()[100]
        self.assertEqual(json.loads(line)["kind"], "error")
        self.assertEqual(json.loads(line)["offset"], target.offset)
        self.same_as_binary(path)

    def test_every_byte_flip_in_a_frame_is_caught(self):
        # Each byte of a few frames, each bit: never a silent wrong record.
        for k in (0, 3, 400):
            f = self.frames[k]
            for i in range(f.offset, f.offset + f.length):
                for bit in range(8):
                    damaged = bytearray(self.data)
                    damaged[i] ^= 1 << bit
                    got = list(ms.iter_frames(bytes(damaged)))
                    clean = len(got) == len(self.frames) and all(
                        g.error is None and g.record == h.record for g, h in zip(got, self.frames)
                    )
                    self.assertFalse(clean, f"flip of bit {bit} at byte {i} went unnoticed")

    def test_truncated_file(self):
        for cut in (3, self.frames[-1].length - 1, len(self.data) // 2 + 1):
            data = self.data[: len(self.data) - cut]
            frames = list(ms.iter_frames(data))
            last = frames[-1]
            self.assertIsInstance(last.error, ms.TruncatedError, cut)
            self.assertEqual(last.offset + last.length, len(data))
            self.assertEqual(last.offset, data.rindex(b"\x00") + 1)
            self.assertTrue(all(f.error is None for f in frames[:-1]))
            self.assertEqual(str(last.error), "truncated: the stream ends inside a frame")
            with self.assertRaises(ms.TruncatedError):
                ms.read_records(data)
        path = self.write("truncated.bin", self.data[:-3])
        cli = run_cli(str(path))
        self.assertEqual(cli.returncode, 2)
        self.assertIn(b"corrupt or truncated", cli.stderr)
        self.same_as_binary(path)

    def test_unknown_kind_is_skipped_not_corrupt(self):
        newer = ms.frame_bytes(bytes([13, 1, 2]))
        data = self.data[:100] + newer + self.data[100:]
        # Splice at a frame boundary.
        cut = next(o for o in frame_offsets(self.data) if o >= 100)
        data = self.data[:cut] + newer + self.data[cut:]
        frames = list(ms.iter_frames(data))
        unknown = [f for f in frames if f.error is not None]
        self.assertEqual(len(unknown), 1)
        self.assertIsInstance(unknown[0].error, ms.UnknownKindError)
        self.assertEqual(unknown[0].error.tag, 13)
        self.assertFalse(unknown[0].error.is_corrupt)
        self.assertEqual(unknown[0].to_dict(), {"kind": "unknown", "offset": cut, "tag": 13})
        self.assertEqual(len(ms.read_records(data)), len(self.frames))
        path = self.write("newer.bin", data)
        self.assertEqual(run_cli(str(path)).returncode, 0)
        self.same_as_binary(path)

    def test_known_tag_with_bad_payload_is_a_record_error(self):
        for raw in (bytes([9, 1]), bytes([9, 0, 0, 0, 0]), bytes([8, 0, 0, 0]), bytes([0, 1, 0x80])):
            with self.assertRaises(ms.RecordError, msg=raw.hex()):
                ms.decode_frame(ms.frame_bytes(raw)[:-1])

    def test_other_version_is_refused(self):
        header = ms.Header(2, "growth-curve", 0, 0)
        data = ms.encode_frame(header) + self.data[self.frames[1].offset:]
        with self.assertRaises(ms.UnsupportedVersionError):
            ms.read_records(data)
        self.assertEqual(len(ms.read_records(data, check_version=False)), len(self.frames))
        path = self.write("v2.bin", data)
        cli = run_cli(str(path))
        self.assertEqual(cli.returncode, 2)
        self.assertEqual(cli.stdout, b"")
        self.assertIn(b"format version 2", cli.stderr)
        if BIN is not None:
            self.assertEqual(bin_decode(path).returncode, 2)

    def test_empty_and_missing_files(self):
        empty = self.write("empty.bin", b"")
        for args in ([str(empty)], [str(Path(self.tmp.name) / "absent.bin")], [self.tmp.name]):
            cli = run_cli(*args)
            self.assertEqual(cli.returncode, 2, args)
            self.assertTrue(cli.stderr.startswith(b"error: "), cli.stderr)
            self.assertNotIn(b"Traceback", cli.stderr)
        self.assertEqual(ms.read_records(b""), [])

    def test_frame_length_limits(self):
        # A body of MAX_FRAME - 1 bytes is the longest; one more is TooLong.
        self.assertEqual(ms.MAX_FRAME, 102)
        longest = bytes([0x65]) + bytes(range(1, 101))  # 100 decoded bytes
        self.assertNotIsInstance(_error(longest), ms.TooLongError)
        self.assertIsInstance(_error(longest + b"\x01"), ms.TooLongError)
        self.assertIsInstance(_error(b"\x05\x01\x02\x03\x04"), ms.TooShortError)
        self.assertIsInstance(_error(b"\x07\x01\x02"), ms.CobsError)
        frames = list(ms.iter_frames(b"\x00\x00"))
        self.assertEqual([type(f.error) for f in frames], [ms.CobsError, ms.CobsError])
        self.assertEqual([f.offset for f in frames], [0, 1])

    def test_garbage_never_raises(self):
        rng = random.Random(99)
        for _ in range(2000):
            n = rng.randrange(300)
            junk = bytes(0 if rng.randrange(8) == 0 else rng.randrange(256) for _ in range(n))
            total = 0
            for f in ms.iter_frames(junk):
                self.assertGreater(f.length, 0)
                self.assertEqual(f.offset, total)
                total += f.length
                if f.error is not None:
                    self.assertIsInstance(f.error, ms.FrameError)
            self.assertEqual(total, len(junk))
        # A damaged real stream: many random flips, the CLI stays calm.
        damaged = bytearray(self.data)
        for _ in range(200):
            damaged[rng.randrange(len(damaged))] = rng.randrange(256)
        path = self.write("garbage.bin", bytes(damaged))
        cli = run_cli(str(path))
        self.assertIn(cli.returncode, (0, 2))
        self.assertNotIn(b"Traceback", cli.stderr)
        self.same_as_binary(path)


def _error(body: bytes):
    try:
        ms.decode_frame(body)
    except ms.FrameError as e:
        return e
    return None


@unittest.skipIf(BIN is None, NO_BIN)
class ErrorLinesMatchTheBinary(unittest.TestCase):
    """Error messages are the Rust Display texts: the whole JSON line of a
    damaged frame is compared, not only its offset."""

    def test_error_texts(self):
        data = fixture_bytes("growth-curve")
        data = data[: next(o for o in frame_offsets(data) if o >= 2000)]
        pieces = [
            data,
            ms.frame_bytes(bytes([9, 1])),  # Record
            b"\x05\x01\x02\x03\x04\x00",  # TooShort
            bytes([0x65]) + bytes(range(1, 102)) + b"\x00",  # TooLong
            b"\x07\x01\x02\x00",  # Cobs
            b"\x00",  # empty: Cobs
            b"\x03\x01",  # Truncated
        ]
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "bad.bin"
            path.write_bytes(b"".join(pieces))
            rs = bin_decode(path)
            py = run_cli(str(path))
        self.assertEqual(rs.returncode, 2)
        self.assertEqual(py.returncode, 2)
        rs_lines = [json.loads(l) for l in rs.stdout.decode().splitlines()]
        py_lines = [json.loads(l) for l in py.stdout.decode().splitlines()]
        self.assertEqual(len(rs_lines), len(py_lines))
        errors = [(a, b) for a, b in zip(rs_lines, py_lines) if a["kind"] == "error"]
        self.assertEqual(len(errors), 6)
        for a, b in errors:
            self.assertEqual(a, b)
        self.assertEqual([normalise(a) for a in rs_lines], [normalise(b) for b in py_lines])


if __name__ == "__main__":
    unittest.main()
