"""The pieces: CRCs, COBS, varints, 16.16 decimals, every record kind
through the Python encoder and decoder."""

from __future__ import annotations

import json
import random
import tempfile
import unittest
from pathlib import Path

from _support import BIN, bin_decode, ms, normalise
from morphogen_stream.cobs import CobsDecodeError, cobs_decode, cobs_encode


def every_kind():
    fx = ms.fx_from_bits
    return [
        ms.Header(1, 'a "quoted" name', 2**64 - 1, 0x65A4353),
        ms.FrameStart(3, fx(65536)),
        ms.Point((fx(1), fx(-98304), fx(0))),
        ms.Segment((fx(-(2**31)), fx(2**31 - 1), fx(7)), (0.0, 0.0, 0.0), fx(100), 9),
        ms.Polygon(4, 2),
        ms.MeshVertex(12, (fx(65537), fx(2), fx(3))),
        ms.Triangle((1, 2, 2**32 - 1)),
        ms.Cell(5, 255, (fx(3), fx(4))),
        ms.Sample(65535, 0.0, fx(3)),
        ms.Ring(1, 2, 3),
        ms.FrameEnd(3),
        ms.SurfaceCell(6, 1, (fx(-1), fx(0), fx(2))),
        ms.Extent((-(2**63), 5), (2**63 - 1, -7), True, 4),
    ]


class Codec(unittest.TestCase):
    def test_check_values(self):
        self.assertEqual(ms.crc32(b"123456789"), 0xCBF43926)
        self.assertEqual(ms.crc64_xz(b"123456789"), 0x995DC9BBDF1939FA)
        self.assertEqual(ms.crc64_xz(b""), 0)
        data = bytes(random.Random(1).randrange(256) for _ in range(1000))
        for split in (0, 1, 7, 8, 9, 500, 999):
            c = ms.Crc64(data[:split])
            c.update(data[split:])
            self.assertEqual(c.value(), ms.crc64_xz(data))
        # Slicing by 8 agrees with the byte-at-a-time definition.
        def slow(data):
            crc = 0xFFFFFFFFFFFFFFFF
            for b in data:
                crc ^= b
                for _ in range(8):
                    crc = (crc >> 1) ^ 0xC96C5795D7870F42 if crc & 1 else crc >> 1
            return crc ^ 0xFFFFFFFFFFFFFFFF
        self.assertEqual(ms.crc64_xz(data[:77]), slow(data[:77]))

    def test_cobs(self):
        rng = random.Random(7)
        for n in list(range(0, 12)) + [253, 254, 255, 300, 600]:
            for _ in range(20):
                data = bytes(rng.choice((0, rng.randrange(1, 256))) for _ in range(n))
                enc = cobs_encode(data)
                self.assertNotIn(0, enc)
                self.assertEqual(cobs_decode(enc), data)
        for bad in (b"", b"\x03\x01", b"\x05"):
            with self.assertRaises(CobsDecodeError):
                cobs_decode(bad)

    def test_fx_text(self):
        cases = {
            0: "0.0",
            65536: "1.0",
            -65536: "-1.0",
            3: "0.0000457763671875",
            1: "0.0000152587890625",
            -98304: "-1.5",
            2**31 - 1: "32767.9999847412109375",
            -(2**31): "-32768.0",
            7: "0.0001068115234375",
        }
        for bits, text in cases.items():
            self.assertEqual(ms.fx_text(bits), text)
            self.assertEqual(ms.fx_bits(float(text)), bits)
            self.assertEqual(ms.fx_bits(ms.fx_from_bits(bits)), bits)

    def test_every_kind_round_trips(self):
        records = every_kind()
        data = ms.encode_stream(records)
        frames = list(ms.iter_frames(data))
        self.assertEqual([f.record for f in frames], records)
        for r in records:
            line = r.to_json()
            self.assertEqual(normalise(json.loads(line)), normalise(r.to_dict()))
            self.assertEqual(list(json.loads(line)), ["kind"] + [n for n, _ in r.FIELDS])
        self.assertEqual(
            records[3].to_json(),
            '{"kind":"segment","a":[-32768.0,32767.9999847412109375,0.0001068115234375],'
            '"b":[0.0,0.0,0.0],"width":0.00152587890625,"colour":9}',
        )
        self.assertEqual(
            records[0].to_json(),
            '{"kind":"header","version":1,"preset":"a \\"quoted\\" name",'
            '"seed":18446744073709551615,"params":"00000000065a4353"}',
        )
        self.assertEqual(records[7].to_dict(), {"kind": "cell", "id": 5, "type": 255, "p": [3 / 65536, 4 / 65536]})
        self.assertEqual(
            records[12].to_json(),
            '{"kind":"extent","min":[-9223372036854775808,5],"max":[9223372036854775807,-7],'
            '"chart":true,"frames":4}',
        )
        if BIN is not None:
            # The Rust decoder reads every kind to the same JSON.
            with tempfile.TemporaryDirectory() as tmp:
                path = Path(tmp) / "every.bin"
                path.write_bytes(data)
                rs = bin_decode(path)
                self.assertEqual(rs.returncode, 0, rs.stderr)
                self.assertEqual(rs.stdout.decode().splitlines(), [r.to_json() for r in records])

    def test_varint_limits_follow_postcard(self):
        def record(*raw):
            try:
                return ms.decode_record(bytes(raw))
            except ms.FrameError as e:
                return type(e)

        # u16: 3 bytes at most, the third at most 0x03.
        self.assertEqual(record(2, 0xFF, 0xFF, 0x0F), ms.FrameEnd(2**18 - 1))
        self.assertEqual(record(2, 0xFF, 0xFF, 0xFF, 0xFF, 0x0F), ms.FrameEnd(2**32 - 1))
        self.assertEqual(record(5, 0xFF, 0xFF, 0x03, 0), ms.Polygon(65535, 0))
        self.assertEqual(record(5, 0xFF, 0xFF, 0x04, 0), ms.RecordError)
        self.assertEqual(record(5, 0x80, 0x80, 0x80, 0x00, 0), ms.RecordError)
        # Non-minimal encodings are accepted, as postcard accepts them.
        self.assertEqual(record(5, 0x81, 0x00, 0), ms.Polygon(1, 0))
        # u32: 5 bytes at most, the fifth at most 0x0F.
        self.assertEqual(record(2, 0xFF, 0xFF, 0xFF, 0xFF, 0x10), ms.RecordError)
        self.assertEqual(record(2, 0x80, 0x80, 0x80, 0x80, 0x80, 0x00), ms.RecordError)
        # Bytes left over after a record: not a record.
        self.assertEqual(record(2, 1, 0), ms.RecordError)
        # Tags: 13 and up are newer kinds; an overlong tag is not a record.
        self.assertEqual(record(13), ms.UnknownKindError)
        self.assertEqual(record(0x80, 0x01), ms.UnknownKindError)
        self.assertEqual(record(0x80, 0x80, 0x80, 0x80, 0x80, 0x00), ms.RecordError)
        # Header strings: UTF-8, at most 32 bytes.
        name = "x" * 32
        self.assertEqual(record(0, 1, 32, *name.encode(), 0, 0), ms.Header(1, name, 0, 0))
        self.assertEqual(record(0, 1, 33, *(name + "x").encode(), 0, 0), ms.RecordError)
        self.assertEqual(record(0, 1, 2, 0xC3, 0x28, 0, 0), ms.RecordError)
        self.assertEqual(record(0, 1, 2, 0xC3, 0xA9, 0, 0), ms.Header(1, "é", 0, 0))
        # u64: 10 bytes at most, the tenth at most 0x01.
        self.assertEqual(
            record(0, 1, 0, *([0xFF] * 9), 0x01, 0), ms.Header(1, "", 2**64 - 1, 0)
        )
        self.assertEqual(record(0, 1, 0, *([0xFF] * 9), 0x02, 0), ms.RecordError)


if __name__ == "__main__":
    unittest.main()
