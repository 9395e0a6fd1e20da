"""Writing frames, as ``morphogen::stream::Encoder`` does: postcard bytes,
their CRC-32 (little-endian), COBS, a zero delimiter. Useful to build test
streams (a capture, a frame of a newer kind) without the Rust tools."""

from __future__ import annotations

from typing import Iterable

from .cobs import cobs_encode
from .crc import crc32
from .records import Record, fx_bits

__all__ = ["encode_varint", "encode_record", "frame_bytes", "encode_frame", "encode_stream"]

_LIMITS = {"u16": 1 << 16, "u32": 1 << 32, "u64": 1 << 64}


def encode_varint(n: int) -> bytes:
    """LEB128: 7 bits a byte, least significant group first."""
    if n < 0:
        raise ValueError("a varint is unsigned")
    out = bytearray()
    while n >= 0x80:
        out.append((n & 0x7F) | 0x80)
        n >>= 7
    out.append(n)
    return bytes(out)


def _fx(value: float) -> bytes:
    bits = fx_bits(value)
    if not -(1 << 31) <= bits < (1 << 31):
        raise ValueError(f"{value} is outside the 16.16 range")
    return encode_varint(((bits << 1) ^ (bits >> 31)) & 0xFFFFFFFF)


def _uint(value: int, ty: str) -> bytes:
    if not 0 <= value < _LIMITS[ty]:
        raise ValueError(f"{value} does not fit a {ty}")
    return encode_varint(value)


def encode_record(record: Record) -> bytes:
    """The record's postcard bytes: its tag, then its fields in order."""
    out = bytearray(encode_varint(record.tag))
    for name, ty in record.FIELDS:
        value = getattr(record, name)
        if ty == "fx":
            out += _fx(value)
        elif ty in ("fx2", "fx3"):
            for v in value:
                out += _fx(v)
        elif ty == "u32x3":
            for v in value:
                out += _uint(v, "u32")
        elif ty == "i64x2":
            for v in value:
                if not -(1 << 63) <= v < (1 << 63):
                    raise ValueError(f"{v} does not fit an i64")
                out += encode_varint(((v << 1) ^ (v >> 63)) & 0xFFFFFFFFFFFFFFFF)
        elif ty == "bool":
            out.append(1 if value else 0)
        elif ty == "u8":
            if not 0 <= value < 256:
                raise ValueError(f"{value} does not fit a u8")
            out.append(value)
        elif ty == "str":
            raw = value.encode("utf-8")
            if len(raw) > 32:
                raise ValueError("a preset name holds at most 32 bytes")
            out += encode_varint(len(raw)) + raw
        else:
            out += _uint(value, ty)
    return bytes(out)


def frame_bytes(record_bytes: bytes) -> bytes:
    """Frames raw record bytes: CRC-32, COBS, delimiter."""
    raw = record_bytes + crc32(record_bytes).to_bytes(4, "little")
    return cobs_encode(raw) + b"\x00"


def encode_frame(record: Record) -> bytes:
    """One record as a frame on the wire."""
    body = encode_record(record)
    if len(body) > 96:
        raise ValueError("the record exceeds MAX_RECORD = 96 bytes")
    return frame_bytes(body)


def encode_stream(records: Iterable[Record]) -> bytes:
    """Records as a stream (or a capture, with several headers)."""
    return b"".join(encode_frame(r) for r in records)
