"""The two checks of the stream format (core/src/stream/digest.rs).

* Every frame carries a CRC-32/ISO-HDLC of its record bytes: the zlib /
  Ethernet CRC, which the standard library's :func:`zlib.crc32` computes.
* The stream digest (fixture summaries, the firmware's report) and the
  header's parameter digest are CRC-64/XZ: polynomial 0x42F0E1EBA9EA3693
  reflected, init and xor-out all ones (check value of ``b"123456789"``:
  0x995DC9BBDF1939FA).
"""

from __future__ import annotations

import zlib

__all__ = ["crc32", "crc64_xz", "Crc64"]

_POLY64_REFLECTED = 0xC96C5795D7870F42  # 0x42F0E1EBA9EA3693 bit-reversed
_MASK64 = 0xFFFFFFFFFFFFFFFF


def _table() -> list:
    table = []
    for byte in range(256):
        crc = byte
        for _ in range(8):
            crc = (crc >> 1) ^ _POLY64_REFLECTED if crc & 1 else crc >> 1
        table.append(crc)
    return table


_T0 = _table()
# Slicing-by-8 tables: _TABLES[k][b] is the CRC state of byte b followed by
# k zero bytes, so eight bytes are folded in one step.
_TABLES = [_T0]
for _k in range(1, 8):
    _prev = _TABLES[-1]
    _TABLES.append([(_prev[b] >> 8) ^ _T0[_prev[b] & 0xFF] for b in range(256)])
del _k, _prev


def crc32(data: bytes) -> int:
    """CRC-32/ISO-HDLC of ``data`` (the per-frame check)."""
    return zlib.crc32(data) & 0xFFFFFFFF


def _update64(state: int, data: bytes) -> int:
    """Feeds ``data`` into a CRC-64/XZ register (pre-inverted state)."""
    t0, t1, t2, t3, t4, t5, t6, t7 = _TABLES
    n = len(data)
    whole = n - n % 8
    if whole:
        from_bytes = int.from_bytes
        mv = memoryview(data)
        for i in range(0, whole, 8):
            x = state ^ from_bytes(mv[i:i + 8], "little")
            state = (
                t7[x & 0xFF]
                ^ t6[(x >> 8) & 0xFF]
                ^ t5[(x >> 16) & 0xFF]
                ^ t4[(x >> 24) & 0xFF]
                ^ t3[(x >> 32) & 0xFF]
                ^ t2[(x >> 40) & 0xFF]
                ^ t1[(x >> 48) & 0xFF]
                ^ t0[x >> 56]
            )
    for b in data[whole:]:
        state = t0[(state ^ b) & 0xFF] ^ (state >> 8)
    return state


def crc64_xz(data: bytes) -> int:
    """CRC-64/XZ of ``data``: the stream digest of a whole stream file."""
    return _update64(_MASK64, data) ^ _MASK64


class Crc64:
    """A running CRC-64/XZ, like the Rust ``StreamDigest``."""

    __slots__ = ("_state",)

    def __init__(self, data: bytes = b"") -> None:
        self._state = _MASK64
        if data:
            self.update(data)

    def update(self, data: bytes) -> None:
        """Feeds more bytes."""
        self._state = _update64(self._state, data)

    def value(self) -> int:
        """The digest of everything fed so far."""
        return self._state ^ _MASK64
