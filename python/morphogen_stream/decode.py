"""Reading frames back, as ``morphogen::stream::Decoder`` does
(core/src/stream/decode.rs): the same checks in the same order, the same
error kinds and messages, resynchronisation at the next zero byte.
"""

from __future__ import annotations

import os
from typing import IO, Iterator, List, NamedTuple, Optional, Union

from .cobs import CobsDecodeError, cobs_decode
from .crc import crc32, crc64_xz
from .records import (
    FORMAT_VERSION,
    Cell,
    Extent,
    SurfaceCell,
    FrameEnd,
    FrameStart,
    Header,
    MeshVertex,
    Point,
    Polygon,
    Record,
    Ring,
    Sample,
    Segment,
    Triangle,
)

__all__ = [
    "MAX_RECORD",
    "MAX_FRAME",
    "RECORD_KINDS",
    "FrameError",
    "CobsError",
    "TooLongError",
    "TooShortError",
    "CrcError",
    "RecordError",
    "UnknownKindError",
    "TruncatedError",
    "UnsupportedVersionError",
    "Frame",
    "Stream",
    "decode_frame",
    "decode_record",
    "iter_frames",
    "read_bytes",
    "read_records",
    "read_capture",
    "stream_digest",
]

#: The largest encoded record in bytes (postcard, before CRC and COBS).
MAX_RECORD = 96
#: The largest frame on the wire including its zero delimiter:
#: the record, its 4-byte CRC, COBS overhead and the delimiter.
MAX_FRAME = MAX_RECORD + 4 + (MAX_RECORD + 4) // 254 + 2
#: Record kinds of format version 1 (tags 0 to 11).
RECORD_KINDS = 13

Source = Union[bytes, bytearray, memoryview, str, "os.PathLike[str]", IO[bytes]]


# --- errors -----------------------------------------------------------------


class FrameError(ValueError):
    """Why a frame could not be decoded (Rust ``FrameError``). ``offset`` is
    the byte offset of the frame's first byte when known; ``str(error)`` is
    the Rust ``Display`` text, the ``error`` field of a JSON error line."""

    #: The Rust variant's name.
    variant = "FrameError"
    #: Whether the frame is damaged (and not merely of a newer kind).
    is_corrupt = True

    def __init__(self, message: str, offset: Optional[int] = None) -> None:
        super().__init__(message)
        self.message = message
        self.offset = offset

    def __str__(self) -> str:
        return self.message

    def located(self) -> str:
        """The message with the byte offset, for people."""
        if self.offset is None:
            return self.message
        return f"frame at byte {self.offset}: {self.message}"


class CobsError(FrameError):
    """The bytes between two delimiters are not valid COBS."""

    variant = "Cobs"

    def __init__(self, offset: Optional[int] = None) -> None:
        super().__init__("invalid COBS encoding", offset)


class TooLongError(FrameError):
    """Longer than ``MAX_FRAME``: not a frame of this format."""

    variant = "TooLong"

    def __init__(self, offset: Optional[int] = None) -> None:
        super().__init__(f"frame longer than MAX_FRAME = {MAX_FRAME} bytes", offset)


class TooShortError(FrameError):
    """Fewer than 5 decoded bytes: no room for a record and its CRC."""

    variant = "TooShort"

    def __init__(self, offset: Optional[int] = None) -> None:
        super().__init__("frame too short for a record and its CRC", offset)


class CrcError(FrameError):
    """The CRC-32 does not match the record bytes."""

    variant = "Crc"

    def __init__(self, carried: int, computed: int, offset: Optional[int] = None) -> None:
        super().__init__(
            f"CRC mismatch (frame carries {carried:#010x}, bytes give {computed:#010x})", offset
        )
        self.carried = carried
        self.computed = computed


class RecordError(FrameError):
    """The CRC matches but the bytes are not a record of this version."""

    variant = "Record"

    def __init__(self, offset: Optional[int] = None) -> None:
        super().__init__("CRC is valid but the bytes are not a known record", offset)


class UnknownKindError(FrameError):
    """A well-formed frame of a record kind this reader does not know (a
    newer writer's): receivers skip it, it is not corrupt."""

    variant = "UnknownKind"
    is_corrupt = False

    def __init__(self, tag: int, offset: Optional[int] = None) -> None:
        super().__init__(f"a record of unknown kind (tag {tag}), skipped", offset)
        self.tag = tag


class TruncatedError(FrameError):
    """The input ended without a closing zero byte."""

    variant = "Truncated"

    def __init__(self, offset: Optional[int] = None) -> None:
        super().__init__("truncated: the stream ends inside a frame", offset)


class UnsupportedVersionError(ValueError):
    """A header of a format version this reader does not know (``morphogen
    decode`` refuses such a stream)."""

    def __init__(self, version: int, offset: int) -> None:
        super().__init__(
            f"the stream at byte {offset} is format version {version}; "
            f"this reader knows version {FORMAT_VERSION} (docs/stream-format.md)"
        )
        self.version = version
        self.offset = offset


# --- postcard ---------------------------------------------------------------


class _Bad(Exception):
    """The record bytes do not parse (becomes RecordError/UnknownKindError)."""


def _varint(buf: bytes, pos: int, nmax: int, lastmax: int):
    """postcard's varint: at most ``nmax`` bytes, the last one at most
    ``lastmax`` (non-minimal encodings are accepted, as postcard does)."""
    out = 0
    shift = 0
    end = len(buf)
    for i in range(nmax):
        if pos >= end:
            raise _Bad
        b = buf[pos]
        pos += 1
        out |= (b & 0x7F) << shift
        if b < 0x80:
            if i == nmax - 1 and b > lastmax:
                raise _Bad
            return out, pos
        shift += 7
    raise _Bad


def _u16(buf, pos):
    """A u16 varint (at most 3 bytes, the third at most 0x03)."""
    b = buf[pos]
    if b < 0x80:
        return b, pos + 1
    n = b & 0x7F
    b = buf[pos + 1]
    if b < 0x80:
        return n | b << 7, pos + 2
    b2 = buf[pos + 2]
    if b2 > 0x03:
        raise _Bad
    return n | (b & 0x7F) << 7 | b2 << 14, pos + 3


def _u32(buf, pos):
    """A u32 varint (at most 5 bytes, the fifth at most 0x0F), unrolled."""
    b = buf[pos]
    if b < 0x80:
        return b, pos + 1
    n = b & 0x7F
    b = buf[pos + 1]
    if b < 0x80:
        return n | b << 7, pos + 2
    n |= (b & 0x7F) << 7
    b = buf[pos + 2]
    if b < 0x80:
        return n | b << 14, pos + 3
    n |= (b & 0x7F) << 14
    b = buf[pos + 3]
    if b < 0x80:
        return n | b << 21, pos + 4
    b4 = buf[pos + 4]
    if b4 > 0x0F:
        raise _Bad
    return n | (b & 0x7F) << 21 | b4 << 28, pos + 5


def _u64(buf, pos):
    """A u64 varint (at most 10 bytes, the tenth at most 0x01)."""
    return _varint(buf, pos, 10, 0x01)


_SCALE = 1.0 / 65536.0


def _fx(buf, pos):
    """An Fx: its i32 bits, zigzag then varint; returned as bits/65536."""
    n, pos = _u32(buf, pos)
    return ((n >> 1) ^ -(n & 1)) * _SCALE, pos


def _header(buf, pos):
    version, pos = _u16(buf, pos)
    length, pos = _u64(buf, pos)
    end = pos + length
    if end > len(buf):
        raise _Bad
    try:
        preset = bytes(buf[pos:end]).decode("utf-8")
    except UnicodeDecodeError:
        raise _Bad from None
    if length > 32:  # heapless::String<32>
        raise _Bad
    seed, pos = _u64(buf, end)
    params, pos = _u64(buf, pos)
    return Header(version, preset, seed, params), pos


def _frame_start(buf, pos):
    frame, pos = _u32(buf, pos)
    time, pos = _fx(buf, pos)
    return FrameStart(frame, time), pos


def _frame_end(buf, pos):
    frame, pos = _u32(buf, pos)
    return FrameEnd(frame), pos


def _fx3(buf, pos):
    x, pos = _u32(buf, pos)
    y, pos = _u32(buf, pos)
    z, pos = _u32(buf, pos)
    s = _SCALE
    return (((x >> 1) ^ -(x & 1)) * s, ((y >> 1) ^ -(y & 1)) * s, ((z >> 1) ^ -(z & 1)) * s), pos


def _point(buf, pos):
    p, pos = _fx3(buf, pos)
    return Point(p), pos


def _segment(buf, pos):
    a, pos = _fx3(buf, pos)
    b, pos = _fx3(buf, pos)
    width, pos = _fx(buf, pos)
    colour, pos = _u16(buf, pos)
    return Segment(a, b, width, colour), pos


def _polygon(buf, pos):
    vertices, pos = _u16(buf, pos)
    colour, pos = _u16(buf, pos)
    return Polygon(vertices, colour), pos


def _mesh_vertex(buf, pos):
    id_, pos = _u32(buf, pos)
    p, pos = _fx3(buf, pos)
    return MeshVertex(id_, p), pos


def _triangle(buf, pos):
    a, pos = _u32(buf, pos)
    b, pos = _u32(buf, pos)
    c, pos = _u32(buf, pos)
    return Triangle((a, b, c)), pos


def _cell(buf, pos):
    id_, pos = _u32(buf, pos)
    cell_type = buf[pos]  # a u8 is one raw byte
    u, pos = _u32(buf, pos + 1)
    v, pos = _u32(buf, pos)
    return Cell(id_, cell_type, (((u >> 1) ^ -(u & 1)) * _SCALE, ((v >> 1) ^ -(v & 1)) * _SCALE)), pos


def _surface_cell(buf, pos):
    id_, pos = _u32(buf, pos)
    cell_type = buf[pos]  # a u8 is one raw byte
    p, pos = _fx3(buf, pos + 1)
    return SurfaceCell(id_, cell_type, p), pos


def _i64(buf, pos):
    """An i64: zigzag, then a u64 varint."""
    n, pos = _u64(buf, pos)
    return (n >> 1) ^ -(n & 1), pos


def _extent(buf, pos):
    lo0, pos = _i64(buf, pos)
    lo1, pos = _i64(buf, pos)
    hi0, pos = _i64(buf, pos)
    hi1, pos = _i64(buf, pos)
    if pos >= len(buf) or buf[pos] > 1:  # a bool is one byte, 0 or 1
        raise _Bad
    chart = buf[pos] == 1
    frames, pos = _u32(buf, pos + 1)
    return Extent((lo0, lo1), (hi0, hi1), chart, frames), pos


def _sample(buf, pos):
    series, pos = _u16(buf, pos)
    x, pos = _fx(buf, pos)
    y, pos = _fx(buf, pos)
    return Sample(series, x, y), pos


def _ring(buf, pos):
    module, pos = _u16(buf, pos)
    ring, pos = _u16(buf, pos)
    points, pos = _u16(buf, pos)
    return Ring(module, ring, points), pos


_PARSERS = (
    _header,
    _frame_start,
    _frame_end,
    _point,
    _segment,
    _polygon,
    _mesh_vertex,
    _triangle,
    _cell,
    _sample,
    _ring,
    _surface_cell,
    _extent,
)
assert len(_PARSERS) == RECORD_KINDS


def _tag(record: bytes) -> Optional[int]:
    """The record's tag: postcard's leading varint, read as the Rust
    decoder's ``tag()`` does (at most 5 bytes, 32 bits)."""
    value = 0
    for i, b in enumerate(record[:5]):
        value = (value | ((b & 0x7F) << (7 * i))) & 0xFFFFFFFF
        if b < 0x80:
            return value
    return None


def decode_record(record: bytes) -> Record:
    """Parses postcard record bytes (no CRC) into a :class:`Record`.

    Raises :class:`UnknownKindError` for a tag of a newer kind and
    :class:`RecordError` for bytes that are not a record (including bytes
    left over after it)."""
    try:
        tag, pos = _u32(record, 0)
        rec, pos = _PARSERS[tag](record, pos)
        if pos != len(record):
            raise _Bad
        return rec
    except (_Bad, IndexError):
        # IndexError: the bytes end inside a field, or the tag is unknown.
        tag = _tag(record)
        if tag is not None and tag >= RECORD_KINDS:
            raise UnknownKindError(tag) from None
        raise RecordError() from None


def decode_frame(body: bytes) -> Record:
    """Decodes one frame's bytes (without its delimiter; they hold no zero
    byte) as ``Decoder::decode_frame`` does: length, COBS, length, CRC-32,
    record. Raises a :class:`FrameError` (without ``offset``)."""
    if len(body) > MAX_FRAME - 1:
        raise TooLongError()
    if 0 in body:
        # Not a frame body: the delimiter splits frames.
        raise CobsError()
    try:
        raw = cobs_decode(body)
    except CobsDecodeError:
        raise CobsError() from None
    n = len(raw)
    if n < 5:
        raise TooShortError()
    if n > MAX_RECORD + 4:
        raise TooLongError()
    record = raw[:-4]
    carried = int.from_bytes(raw[-4:], "little")
    computed = crc32(record)
    if carried != computed:
        raise CrcError(carried, computed)
    return decode_record(record)


# --- frames and streams -----------------------------------------------------


class Frame(NamedTuple):
    """One frame read from a byte string (Rust ``Decoded``): its offset, its
    length including the delimiter, and the record or the error."""

    offset: int
    length: int
    record: Optional[Record]
    error: Optional[FrameError]

    @property
    def ok(self) -> bool:
        """Whether the frame holds a record."""
        return self.error is None

    def to_json(self) -> str:
        """The frame as one line of ``morphogen decode``: the record, or an
        ``unknown`` / ``error`` object naming the byte offset."""
        if self.record is not None:
            return self.record.to_json()
        err = self.error
        if isinstance(err, UnknownKindError):
            return f'{{"kind":"unknown","offset":{self.offset},"tag":{err.tag}}}'
        import json

        return f'{{"kind":"error","offset":{self.offset},"error":{json.dumps(str(err), ensure_ascii=False)}}}'

    def to_dict(self) -> dict:
        """The JSON object of :meth:`to_json`."""
        if self.record is not None:
            return self.record.to_dict()
        err = self.error
        if isinstance(err, UnknownKindError):
            return {"kind": "unknown", "offset": self.offset, "tag": err.tag}
        return {"kind": "error", "offset": self.offset, "error": str(err)}


def read_bytes(source: Source) -> bytes:
    """The bytes of ``source``: bytes-like, a path, or a binary file."""
    if isinstance(source, (bytes, bytearray, memoryview)):
        return bytes(source)
    if isinstance(source, (str, os.PathLike)):
        with open(source, "rb") as f:
            return f.read()
    if hasattr(source, "read"):
        return bytes(source.read())
    raise TypeError(f"cannot read a stream from {type(source).__name__}")


def iter_frames(source: Source) -> Iterator[Frame]:
    """Iterates over the frames of an encoded stream or capture, like the
    Rust ``Decoder``: a damaged frame becomes a :class:`Frame` with an
    ``error`` (whose ``offset`` is set) and decoding resumes after the
    next zero byte; bytes after the last zero are a truncated frame."""
    data = read_bytes(source)
    bodies = data.split(b"\x00")
    rest = bodies.pop()
    offset = 0
    # decode_frame inlined for the common case (a well-formed frame).
    for body in bodies:
        length = len(body) + 1
        n = len(body)
        try:
            if 5 < n < MAX_FRAME and body[0] == n:
                raw = body[1:]
                record = raw[:-4]
                if int.from_bytes(raw[-4:], "little") != crc32(record):
                    raise CrcError(int.from_bytes(raw[-4:], "little"), crc32(record))
                rec = decode_record(record)
            else:
                rec = decode_frame(body)
        except FrameError as e:
            e.offset = offset
            yield Frame(offset, length, None, e)
        else:
            yield Frame(offset, length, rec, None)
        offset += length
    if rest:
        yield Frame(offset, len(rest), None, TruncatedError(offset))


def _check_version(frame: Frame) -> None:
    rec = frame.record
    if isinstance(rec, Header) and rec.version != FORMAT_VERSION:
        raise UnsupportedVersionError(rec.version, frame.offset)


def read_records(source: Source, errors: str = "raise", check_version: bool = True) -> List[Record]:
    """All records of a stream file or capture, in order (headers
    included, as in ``records.jsonl``). Frames of unknown kinds are
    skipped. ``errors``: ``"raise"`` raises the first corrupt frame's
    :class:`FrameError` (its ``offset`` set), ``"skip"`` drops corrupt
    frames. A header of another format version raises
    :class:`UnsupportedVersionError` unless ``check_version`` is false."""
    if errors not in ("raise", "skip"):
        raise ValueError('errors must be "raise" or "skip"')
    out: List[Record] = []
    append = out.append
    for frame in iter_frames(source):
        rec = frame.record
        if rec is not None:
            if check_version and rec.tag == 0:
                _check_version(frame)
            append(rec)
        elif frame.error.is_corrupt and errors == "raise":
            raise frame.error
    return out


class Stream:
    """One stream of a capture: from a header to the next header (or the
    end). ``frames`` holds every frame (errors included); ``header`` is
    ``None`` for bytes before the first readable header."""

    def __init__(self, data: bytes, header: Optional[Header], frames: List[Frame]) -> None:
        self._data = data
        self.header = header
        self.frames = frames
        self.start = frames[0].offset
        self.end = frames[-1].offset + frames[-1].length
        self._digest: Optional[int] = None

    def __repr__(self) -> str:
        name = self.header.preset if self.header else None
        return (
            f"<Stream {name!r} bytes {self.start}..{self.end}: {len(self.frames)} frames, "
            f"{len(self.errors)} errors>"
        )

    @property
    def records(self) -> List[Record]:
        """The decoded records (header first)."""
        return [f.record for f in self.frames if f.record is not None]

    @property
    def errors(self) -> List[Frame]:
        """The corrupt or truncated frames."""
        return [f for f in self.frames if f.error is not None and f.error.is_corrupt]

    @property
    def unknown(self) -> List[Frame]:
        """Well-formed frames of unknown (newer) kinds."""
        return [f for f in self.frames if f.error is not None and not f.error.is_corrupt]

    @property
    def bytes(self) -> bytes:
        """The stream's bytes within the capture, without the frames of
        link records (:class:`Extent`), which are not part of it."""
        links = [f for f in self.frames if isinstance(f.record, Extent)]
        if not links:
            return self._data[self.start:self.end]
        return b"".join(self._data[f.offset:f.offset + f.length] for f in self.frames if f not in links)

    @property
    def digest(self) -> int:
        """CRC-64/XZ of the stream's bytes: a fixture's ``stream_digest``."""
        if self._digest is None:
            self._digest = crc64_xz(self.bytes)
        return self._digest


def read_capture(source: Source, check_version: bool = True) -> List[Stream]:
    """Splits a stream file or device capture into its streams (each starts
    with a header record, back to back), as ``morphogen verify --stream``
    does. Bytes before the first readable header form a stream whose
    ``header`` is ``None``. Corrupt frames stay in their stream's
    ``errors``."""
    data = read_bytes(source)
    streams: List[Stream] = []
    header: Optional[Header] = None
    frames: List[Frame] = []
    for frame in iter_frames(data):
        if isinstance(frame.record, Header):
            if check_version:
                _check_version(frame)
            if frames:
                streams.append(Stream(data, header, frames))
            header, frames = frame.record, [frame]
        else:
            frames.append(frame)
    if frames:
        streams.append(Stream(data, header, frames))
    return streams


def stream_digest(source: Source) -> int:
    """CRC-64/XZ over every byte of a stream, delimiters included."""
    return crc64_xz(read_bytes(source))
