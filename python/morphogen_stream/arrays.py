"""numpy arrays per record kind (numpy is optional: only this module
needs it)."""

from __future__ import annotations

from typing import Dict, Iterable, List, Optional

from .records import SCHEMA, Header, Record, fx_bits

__all__ = ["to_arrays", "dtype"]

_NP_TYPES = {"u8": "u1", "u16": "u2", "u32": "u4", "u64": "u8"}


def _np():
    try:
        import numpy
    except ImportError as e:  # pragma: no cover - depends on the machine
        raise ImportError(
            "morphogen_stream.to_arrays needs numpy (pip install numpy, "
            "or pip install morphogen-stream[numpy])"
        ) from e
    return numpy


def dtype(kind: str, bits: bool = False):
    """The structured dtype of ``kind``'s array: its fields, then
    ``in_frame`` (the frame number of the enclosing ``frame_start``, -1
    outside a frame) and ``index`` (the record's position in the input).
    Fixed-point fields are ``float64`` (exact), or their raw ``int32``
    16.16 bits when ``bits`` is true; ``header.preset`` is a Python
    object (str)."""
    np = _np()
    fields = []
    for name, ty in SCHEMA[kind]:
        fx = "i4" if bits else "f8"
        if ty == "fx":
            fields.append((name, fx))
        elif ty == "fx2":
            fields.append((name, fx, (2,)))
        elif ty == "fx3":
            fields.append((name, fx, (3,)))
        elif ty == "u32x3":
            fields.append((name, "u4", (3,)))
        elif ty == "i64x2":
            fields.append((name, "i8", (2,)))
        elif ty == "bool":
            fields.append((name, "?"))
        elif ty == "str":
            fields.append((name, object))
        else:
            fields.append((name, _NP_TYPES[ty]))
    fields += [("in_frame", "i8"), ("index", "i8")]
    return np.dtype(fields)


def to_arrays(records: Iterable[Record], bits: bool = False, kinds: Optional[Iterable[str]] = None) -> Dict[str, object]:
    """The records as one numpy structured array per kind (only the kinds
    present, or those named by ``kinds``): ``arrays["cell"]["type"]``,
    ``arrays["cell"]["p"][:, 0]``, ``arrays["cell"]["in_frame"]``.
    ``in_frame`` restarts at -1 after each header."""
    np = _np()
    wanted = None if kinds is None else set(kinds)
    rows: Dict[str, List[tuple]] = {}
    frame = -1
    for index, rec in enumerate(records):
        kind = rec.kind
        if kind == "frame_start":
            frame = rec.frame
        elif isinstance(rec, Header):
            frame = -1
        if wanted is not None and kind not in wanted:
            continue
        values = []
        for name, ty in rec.FIELDS:
            v = getattr(rec, name)
            if bits and ty == "fx":
                v = fx_bits(v)
            elif bits and ty in ("fx2", "fx3"):
                v = tuple(fx_bits(x) for x in v)
            values.append(v)
        values += [frame, index]
        rows.setdefault(kind, []).append(tuple(values))
    return {kind: np.array(r, dtype=dtype(kind, bits)) for kind, r in rows.items()}
