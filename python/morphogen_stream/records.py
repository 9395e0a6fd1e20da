"""The record vocabulary (core/src/stream/record.rs) as Python dataclasses.

One class per record kind. The attribute names are the field names of
``records.jsonl`` / ``morphogen decode`` (a cell's type is ``type``, as in
the JSON), and :meth:`Record.to_dict` gives exactly the JSON object:

* fixed-point values (``Fx``, I16F16 on the wire) are Python floats equal
  to ``bits / 65536`` -- exactly, a float holds every 16.16 value; the raw
  bits are ``fx_bits(value)``;
* arrays (``p``, ``a``, ``b``, ``v``) are tuples (lists in ``to_dict``);
* ``Header.params`` is an ``int``; ``to_dict`` writes it as the JSON does,
  16 lower-case hex digits.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import ClassVar, Dict, List, Tuple

__all__ = [
    "FORMAT_VERSION",
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
    "Sample",
    "Ring",
    "RECORD_TYPES",
    "KINDS",
    "SCHEMA",
    "fx_bits",
    "fx_from_bits",
    "fx_text",
]

#: The wire format version in every header (``FORMAT_VERSION`` in record.rs).
FORMAT_VERSION = 1

_FX_SCALE = 65536.0
# 10**16 / 2**16 = 5**16: a 16-bit fraction times this is its exact decimal
# expansion in 16 digits.
_FIVE_16 = 152587890625


def fx_from_bits(bits: int) -> float:
    """The value of 16.16 fixed-point ``bits`` (exact: a float holds it)."""
    return bits / _FX_SCALE


def fx_bits(value: float) -> int:
    """The 16.16 bits of a fixed-point value: ``round(value * 65536)``."""
    return int(round(value * _FX_SCALE))


def fx_text(bits: int) -> str:
    """The exact decimal of ``bits / 65536`` as ``morphogen decode`` prints
    it: all digits of the fraction, ``.0`` for a whole number."""
    sign = "-" if bits < 0 else ""
    magnitude = -bits if bits < 0 else bits
    whole, fraction = magnitude >> 16, magnitude & 0xFFFF
    if not fraction:
        return f"{sign}{whole}.0"
    digits = f"{fraction * _FIVE_16:016d}".rstrip("0")
    return f"{sign}{whole}.{digits}"


def _fx_json(value: float) -> str:
    return fx_text(fx_bits(value))


def _fxs_json(values) -> str:
    return "[" + ",".join(fx_text(fx_bits(v)) for v in values) + "]"


def _str_json(s: str) -> str:
    # serde_json's escaping: the same as Python's without ensure_ascii.
    return json.dumps(s, ensure_ascii=False)


class Record:
    """Base class of every record. ``kind`` is the JSON ``kind`` and
    ``tag`` the wire tag; ``FIELDS`` lists ``(name, type)`` in wire order,
    the types being ``u8``, ``u16``, ``u32``, ``u64``, ``str``, ``fx``,
    ``fx2``, ``fx3``, ``u32x3``, ``i64x2`` and ``bool``."""

    __slots__ = ()
    kind: ClassVar[str] = ""
    tag: ClassVar[int] = -1
    FIELDS: ClassVar[Tuple[Tuple[str, str], ...]] = ()

    def to_dict(self) -> Dict[str, object]:
        """The record as the JSON object of ``records.jsonl``."""
        out: Dict[str, object] = {"kind": self.kind}
        for name, ty in self.FIELDS:
            value = getattr(self, name)
            if isinstance(value, tuple):
                value = list(value)
            out[name] = value
        return out

    def to_json(self) -> str:
        """The record as one line of ``morphogen decode`` (no newline)."""
        parts = ['{"kind":"', self.kind, '"']
        for name, ty in self.FIELDS:
            value = getattr(self, name)
            if ty == "fx":
                text = _fx_json(value)
            elif ty in ("fx2", "fx3"):
                text = _fxs_json(value)
            elif ty in ("u32x3", "i64x2"):
                text = "[" + ",".join(str(v) for v in value) + "]"
            elif ty == "bool":
                text = "true" if value else "false"
            elif ty == "str":
                text = _str_json(value)
            else:
                text = str(value)
            parts += [',"', name, '":', text]
        parts.append("}")
        return "".join(parts)


@dataclass
class Header(Record):
    """Starts every stream (tag 0); ``params`` is the CRC-64/XZ of the
    preset's postcard-encoded parameters."""

    __slots__ = ("version", "preset", "seed", "params")
    kind: ClassVar[str] = "header"
    tag: ClassVar[int] = 0
    FIELDS: ClassVar = (("version", "u16"), ("preset", "str"), ("seed", "u64"), ("params", "u64"))
    version: int
    preset: str
    seed: int
    params: int

    def to_dict(self) -> Dict[str, object]:
        return {
            "kind": "header",
            "version": self.version,
            "preset": self.preset,
            "seed": self.seed,
            "params": f"{self.params:016x}",
        }

    def to_json(self) -> str:
        return (
            f'{{"kind":"header","version":{self.version},"preset":{_str_json(self.preset)},'
            f'"seed":{self.seed},"params":"{self.params:016x}"}}'
        )


@dataclass
class FrameStart(Record):
    """Starts frame ``frame`` at model time ``time`` (tag 1)."""

    __slots__ = ("frame", "time")
    kind: ClassVar[str] = "frame_start"
    tag: ClassVar[int] = 1
    FIELDS: ClassVar = (("frame", "u32"), ("time", "fx"))
    frame: int
    time: float


@dataclass
class FrameEnd(Record):
    """Ends frame ``frame`` (tag 2)."""

    __slots__ = ("frame",)
    kind: ClassVar[str] = "frame_end"
    tag: ClassVar[int] = 2
    FIELDS: ClassVar = (("frame", "u32"),)
    frame: int


@dataclass
class Point(Record):
    """A point (tag 3); also the vertices following a polygon or ring."""

    __slots__ = ("p",)
    kind: ClassVar[str] = "point"
    tag: ClassVar[int] = 3
    FIELDS: ClassVar = (("p", "fx3"),)
    p: Tuple[float, float, float]


@dataclass
class Segment(Record):
    """A drawn segment (tag 4)."""

    __slots__ = ("a", "b", "width", "colour")
    kind: ClassVar[str] = "segment"
    tag: ClassVar[int] = 4
    FIELDS: ClassVar = (("a", "fx3"), ("b", "fx3"), ("width", "fx"), ("colour", "u16"))
    a: Tuple[float, float, float]
    b: Tuple[float, float, float]
    width: float
    colour: int


@dataclass
class Polygon(Record):
    """A filled polygon whose ``vertices`` point records follow (tag 5)."""

    __slots__ = ("vertices", "colour")
    kind: ClassVar[str] = "polygon"
    tag: ClassVar[int] = 5
    FIELDS: ClassVar = (("vertices", "u16"), ("colour", "u16"))
    vertices: int
    colour: int


@dataclass
class MeshVertex(Record):
    """A mesh vertex (tag 6); ids count from 0 within a frame."""

    __slots__ = ("id", "p")
    kind: ClassVar[str] = "mesh_vertex"
    tag: ClassVar[int] = 6
    FIELDS: ClassVar = (("id", "u32"), ("p", "fx3"))
    id: int
    p: Tuple[float, float, float]


@dataclass
class Triangle(Record):
    """A mesh triangle by vertex ids, counter-clockwise from outside (tag 7)."""

    __slots__ = ("v",)
    kind: ClassVar[str] = "triangle"
    tag: ClassVar[int] = 7
    FIELDS: ClassVar = (("v", "u32x3"),)
    v: Tuple[int, int, int]


@dataclass
class Cell(Record):
    """A cell of a 2D mosaic (tag 8); ``type`` is the cell type index."""

    __slots__ = ("id", "type", "p")
    kind: ClassVar[str] = "cell"
    tag: ClassVar[int] = 8
    FIELDS: ClassVar = (("id", "u32"), ("type", "u8"), ("p", "fx2"))
    id: int
    type: int
    p: Tuple[float, float]


@dataclass
class Sample(Record):
    """A sample ``(x, y)`` of curve ``series`` (tag 9)."""

    __slots__ = ("series", "x", "y")
    kind: ClassVar[str] = "sample"
    tag: ClassVar[int] = 9
    FIELDS: ClassVar = (("series", "u16"), ("x", "fx"), ("y", "fx"))
    series: int
    x: float
    y: float


@dataclass
class Ring(Record):
    """A closed ring whose ``points`` point records follow (tag 10)."""

    __slots__ = ("module", "ring", "points")
    kind: ClassVar[str] = "ring"
    tag: ClassVar[int] = 10
    FIELDS: ClassVar = (("module", "u16"), ("ring", "u16"), ("points", "u16"))
    module: int
    ring: int
    points: int


@dataclass
class SurfaceCell(Record):
    """A cell of a mosaic on a surface (tag 11); ``p`` is its point on the mesh."""

    __slots__ = ("id", "type", "p")
    kind: ClassVar[str] = "surface_cell"
    tag: ClassVar[int] = 11
    FIELDS: ClassVar = (("id", "u32"), ("type", "u8"), ("p", "fx3"))
    id: int
    type: int
    p: Tuple[float, float, float]


@dataclass
class Extent(Record):
    """A link record (tag 12): the extent of what the stream draws, in the
    rig's projected I16F16 bits, and its number of frames; sent by the
    firmware right after a header. Not part of the stream: its frame is left
    out of :attr:`Stream.bytes` and digests."""

    __slots__ = ("min", "max", "chart", "frames")
    kind: ClassVar[str] = "extent"
    tag: ClassVar[int] = 12
    FIELDS: ClassVar = (("min", "i64x2"), ("max", "i64x2"), ("chart", "bool"), ("frames", "u32"))
    min: Tuple[int, int]
    max: Tuple[int, int]
    chart: bool
    frames: int


#: The record classes by wire tag (tags 0 to 12 are version 1's kinds).
RECORD_TYPES: Tuple[type, ...] = (
    Header,
    FrameStart,
    FrameEnd,
    Point,
    Segment,
    Polygon,
    MeshVertex,
    Triangle,
    Cell,
    Sample,
    Ring,
    SurfaceCell,
    Extent,
)

#: The record classes by JSON ``kind``.
KINDS: Dict[str, type] = {cls.kind: cls for cls in RECORD_TYPES}

#: ``kind`` -> ``[(field, type), ...]`` in wire order.
SCHEMA: Dict[str, List[Tuple[str, str]]] = {cls.kind: list(cls.FIELDS) for cls in RECORD_TYPES}

assert all(cls.tag == i for i, cls in enumerate(RECORD_TYPES))
