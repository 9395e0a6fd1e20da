"""Read Morphogen record streams (``stream.bin``, device captures) from
Python: every frame's CRC-32 checked, the stream's CRC-64/XZ digest
computed, records as dataclasses named like ``records.jsonl``.

The format is docs/stream-format.md; this package mirrors the reference
decoder, core/src/stream/ (``morphogen::stream::Decoder``).

>>> import morphogen_stream as ms
>>> records = ms.read_records("fixtures/growth-curve/stream.bin")  # doctest: +SKIP
>>> records[0]                                                      # doctest: +SKIP
Header(version=1, preset='growth-curve', seed=0, params=457745025669775367)
"""

from .crc import Crc64, crc32, crc64_xz
from .decode import (
    MAX_FRAME,
    MAX_RECORD,
    RECORD_KINDS,
    CobsError,
    CrcError,
    Frame,
    FrameError,
    RecordError,
    Stream,
    TooLongError,
    TooShortError,
    TruncatedError,
    UnknownKindError,
    UnsupportedVersionError,
    decode_frame,
    decode_record,
    iter_frames,
    read_bytes,
    read_capture,
    read_records,
    stream_digest,
)
from .encode import encode_frame, encode_record, encode_stream, frame_bytes
from .records import (
    FORMAT_VERSION,
    KINDS,
    RECORD_TYPES,
    SCHEMA,
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
    fx_bits,
    fx_from_bits,
    fx_text,
)

__version__ = "0.1.0"


def to_arrays(records, bits=False, kinds=None):
    """numpy structured arrays per record kind (needs numpy); see
    :func:`morphogen_stream.arrays.to_arrays`."""
    from .arrays import to_arrays as _to_arrays

    return _to_arrays(records, bits=bits, kinds=kinds)


__all__ = [
    "__version__",
    "FORMAT_VERSION",
    "MAX_FRAME",
    "MAX_RECORD",
    "RECORD_KINDS",
    "KINDS",
    "RECORD_TYPES",
    "SCHEMA",
    "Record",
    "Header",
    "FrameStart",
    "FrameEnd",
    "Point",
    "Segment",
    "Polygon",
    "MeshVertex",
    "Triangle",
    "Cell",
    "SurfaceCell",
    "Extent",
    "Sample",
    "Ring",
    "Frame",
    "Stream",
    "FrameError",
    "CobsError",
    "TooLongError",
    "TooShortError",
    "CrcError",
    "RecordError",
    "UnknownKindError",
    "TruncatedError",
    "UnsupportedVersionError",
    "iter_frames",
    "read_bytes",
    "read_records",
    "read_capture",
    "decode_frame",
    "decode_record",
    "stream_digest",
    "crc32",
    "crc64_xz",
    "Crc64",
    "encode_record",
    "encode_frame",
    "encode_stream",
    "frame_bytes",
    "fx_bits",
    "fx_from_bits",
    "fx_text",
    "to_arrays",
]
