"""Consistent Overhead Byte Stuffing, as the ``cobs`` 0.3 crate does it.

A frame's body (the bytes before its ``0x00`` delimiter) is a run of
blocks: a code byte ``n`` (1 to 255) followed by ``n - 1`` data bytes; each
block except the last and except one with code ``0xFF`` stands for its data
followed by one zero byte.
"""

from __future__ import annotations

__all__ = ["cobs_decode", "cobs_encode", "CobsDecodeError"]


class CobsDecodeError(ValueError):
    """The bytes are not valid COBS (empty, a zero inside, or a block that
    runs past the end)."""


def cobs_decode(body: bytes) -> bytes:
    """Decodes one frame's body (without its delimiter)."""
    n = len(body)
    if n == 0:
        raise CobsDecodeError("empty frame")
    if n <= 255:
        # The common case: a single block (no zero byte in the data).
        code = body[0]
        if code == n:
            return bytes(body[1:])
    out = bytearray()
    i = 0
    while i < n:
        code = body[i]
        if code == 0:
            raise CobsDecodeError("zero byte inside a frame")
        end = i + code
        if end > n:
            raise CobsDecodeError("a block runs past the end of the frame")
        block = body[i + 1:end]
        if 0 in block:
            raise CobsDecodeError("zero byte inside a frame")
        out += block
        i = end
        if i < n and code != 0xFF:
            out.append(0)
    return bytes(out)


def cobs_encode(data: bytes) -> bytes:
    """Encodes ``data`` (without the trailing delimiter)."""
    out = bytearray()
    block = bytearray()
    for b in data:
        if b == 0:
            out.append(len(block) + 1)
            out += block
            block.clear()
        else:
            block.append(b)
            if len(block) == 254:
                out.append(0xFF)
                out += block
                block.clear()
    out.append(len(block) + 1)
    out += block
    return bytes(out)
