"""``python -m morphogen_stream FILE``: the JSON Lines of ``morphogen
decode FILE``, from Python.

Exit status as ``morphogen decode``: 0 when every frame reads (frames of
unknown kinds included), 2 for corrupt or truncated frames (shown as
``"kind":"error"`` lines, then reported on standard error), an empty or
unreadable file, or a stream of another format version.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from collections import Counter
from typing import List, Optional

from .decode import UnsupportedVersionError, iter_frames, read_bytes, read_capture
from .records import FORMAT_VERSION, Header


class _Fail(Exception):
    """A message for standard error and exit status 2."""


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="python -m morphogen_stream",
        description="Decode a Morphogen stream file or device capture into JSON Lines "
        "(the same lines as `morphogen decode`), checking every frame's CRC.",
    )
    p.add_argument("file", help="the stream file (stream.bin) or capture")
    p.add_argument("--out", help="write to this file instead of standard output")
    p.add_argument(
        "--streams",
        action="store_true",
        help="print one JSON line per stream instead: its header, byte range, frame "
        "and record counts, errors and CRC-64/XZ stream digest (as fixtures' summary.toml)",
    )
    return p


def _write(text_lines, out: Optional[str]) -> None:
    if out is None:
        write = sys.stdout.write
        batch: List[str] = []
        for line in text_lines:
            batch.append(line)
            if len(batch) >= 4096:
                write("\n".join(batch) + "\n")
                batch.clear()
        if batch:
            write("\n".join(batch) + "\n")
        sys.stdout.flush()
        return
    directory = os.path.dirname(os.path.abspath(out))
    fd, tmp = tempfile.mkstemp(dir=directory, prefix=".morphogen-stream-")
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as f:
            for line in text_lines:
                f.write(line)
                f.write("\n")
        os.replace(tmp, out)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def _stream_lines(data: bytes):
    for s in read_capture(data, check_version=False):
        h = s.header
        counts = Counter(r.kind for r in s.records)
        yield json.dumps(
            {
                "preset": h.preset if h else None,
                "seed": h.seed if h else None,
                "params_digest": f"{h.params:016x}" if h else None,
                "start": s.start,
                "end": s.end,
                "bytes": len(s.bytes),
                "frames": len(s.frames),
                "records": dict(sorted(counts.items())),
                "errors": len(s.errors),
                "unknown": len(s.unknown),
                "stream_digest": f"{s.digest:016x}",
            },
            ensure_ascii=False,
        )


def _run(args: argparse.Namespace) -> int:
    try:
        data = read_bytes(args.file)
    except OSError as e:
        raise _Fail(f"cannot read {args.file}: {e.strerror or e}") from None
    if not data:
        raise _Fail(f"{args.file} holds no frames")
    frames = list(iter_frames(data))
    for f in frames:
        rec = f.record
        if isinstance(rec, Header) and rec.version != FORMAT_VERSION:
            raise _Fail(f"{args.file}: {UnsupportedVersionError(rec.version, f.offset)}")
    if args.streams:
        _write(_stream_lines(data), args.out)
    else:
        _write((f.to_json() for f in frames), args.out)
    corrupt = sum(1 for f in frames if f.error is not None and f.error.is_corrupt)
    if corrupt:
        first = next(f for f in frames if f.error is not None and f.error.is_corrupt)
        raise _Fail(
            f'{corrupt} corrupt or truncated frame(s) in {args.file} (shown as "kind":"error" '
            f"lines; the first at byte {first.offset}: {first.error})"
        )
    return 0


def main(argv: Optional[List[str]] = None) -> int:
    """Runs the command line; returns the exit status."""
    args = _parser().parse_args(argv)
    try:
        return _run(args)
    except _Fail as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        # `... | head`: the reader has gone, as with `morphogen decode`.
        try:
            sys.stdout = open(os.devnull, "w")
        except OSError:
            pass
        return 0
    except KeyboardInterrupt:
        return 130
    except Exception as e:  # never a traceback for bad input
        print(f"error: cannot decode {args.file}: {type(e).__name__}: {e}", file=sys.stderr)
        return 2
