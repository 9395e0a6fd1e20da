"""numpy arrays per record kind (skipped when numpy is not installed)."""

from __future__ import annotations

import unittest
from collections import Counter

from _support import fixture_bytes, ms

try:
    import numpy as np
except ImportError:  # the reader needs no numpy; only to_arrays does
    np = None


@unittest.skipIf(np is None, "numpy is not installed: to_arrays not tested")
class Arrays(unittest.TestCase):
    def test_mosaic_cells(self):
        records = ms.read_records(fixture_bytes("croton-mcu"))
        arrays = ms.to_arrays(records)
        self.assertEqual(set(arrays), {r.kind for r in records})
        cells = [r for r in records if isinstance(r, ms.Cell)]
        cell = arrays["cell"]
        self.assertEqual(len(cell), len(cells))
        self.assertEqual(cell["id"].tolist(), [c.id for c in cells])
        self.assertEqual(cell["type"].tolist(), [c.type for c in cells])
        self.assertEqual(cell["p"].shape, (len(cells), 2))
        self.assertEqual([tuple(p) for p in cell["p"].tolist()], [c.p for c in cells])
        self.assertEqual(cell.dtype["p"].base, np.float64)
        self.assertEqual(cell["index"].tolist(), [i for i, r in enumerate(records) if isinstance(r, ms.Cell)])
        # in_frame: the frame of the enclosing frame_start.
        frame, want = -1, []
        for r in records:
            if isinstance(r, ms.FrameStart):
                frame = r.frame
            elif isinstance(r, ms.Cell):
                want.append(frame)
        self.assertEqual(cell["in_frame"].tolist(), want)
        per = Counter(zip(want, (c.type for c in cells)))
        counts = np.zeros((max(want) + 1, 2), dtype=int)
        np.add.at(counts, (cell["in_frame"], cell["type"]), 1)
        self.assertEqual({k: v for k, v in per.items()}, {(f, t): int(counts[f, t]) for f, t in per})

    def test_bits_and_every_kind(self):
        from test_codec import every_kind

        records = every_kind()
        arrays = ms.to_arrays(records, bits=True)
        self.assertEqual(arrays["segment"]["a"][0].tolist(), [-(2**31), 2**31 - 1, 7])
        self.assertEqual(arrays["segment"].dtype["a"].base, np.int32)
        self.assertEqual(arrays["sample"]["y"].tolist(), [3])
        self.assertEqual(arrays["triangle"]["v"][0].tolist(), [1, 2, 2**32 - 1])
        self.assertEqual(arrays["header"]["seed"].tolist(), [2**64 - 1])
        self.assertEqual(arrays["header"]["preset"].tolist(), ['a "quoted" name'])
        floats = ms.to_arrays(records)
        self.assertEqual(floats["point"]["p"][0].tolist(), [1 / 65536, -1.5, 0.0])
        self.assertEqual(floats["cell"]["type"].tolist(), [255])
        self.assertEqual(ms.to_arrays(records, kinds=["ring"]).keys(), {"ring"})
        self.assertEqual(arrays["extent"]["min"][0].tolist(), [-(2**63), 5])
        self.assertEqual(arrays["extent"]["chart"].tolist(), [True])


if __name__ == "__main__":
    unittest.main()
