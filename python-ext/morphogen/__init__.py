"""Morphogen in Python: run its growth models and read their streams.

>>> import morphogen
>>> horn = morphogen.scenario("ram-horn", {"horn.modules[0].bend": 80}, horn__years=4)
>>> run = morphogen.run(horn)                 # doctest: +SKIP
>>> run.digest, run.records["ring"]["p"]     # doctest: +SKIP

Settings are the keys of ``morphogen run --set KEY=VALUE``: in a dict
(any key, ``"horn.modules[0].bend"`` too) or as keyword arguments with
``__`` for each dot (``horn__years=4`` is ``horn.years=4``). A bad value
raises ``ValueError`` with the command line's message, which names the key
and the allowed range.
"""

from __future__ import annotations

import math
import os
import warnings
from pathlib import Path
from concurrent.futures import Executor
from typing import Any, Dict, Iterable, List, Mapping, Optional, Union

from . import _native

__all__ = ["Run", "Scenario", "presets", "run", "scenario", "sweep", "__version__"]

#: The Morphogen this package runs: ``0.1.0``, or ``0.1.0 (git 0123456789ab)``
#: when built from a checkout (as ``morphogen --version`` prints it).
__version__ = _native.VERSION

Scenario = _native.Scenario


def presets() -> List[str]:
    """The built-in presets' names, in ``morphogen list`` order."""
    return _native.presets()


def scenario(
    target: Union[str, os.PathLike, Scenario],
    settings: Optional[Mapping[str, Any]] = None,
    /,
    **kwargs: Any,
) -> Scenario:
    """A preset (by name), a scenario file (a path ending in ``.toml``, or
    any path with a folder) or a scenario, with ``settings`` then
    ``kwargs`` applied as ``--set KEY=VALUE`` (``__`` in a keyword is a
    dot). A file key (``bones.grammar``, ``mosaic.mask``, ...) given a path
    reads that file, relative to the current folder.

    Raises ``ValueError`` for an unknown preset, an unreadable or invalid
    file, or a bad setting, with the command line's message."""
    sets = [f"{key}={_value(value)}" for key, value in (settings or {}).items()]
    sets += [f"{key.replace('__', '.')}={_value(value)}" for key, value in kwargs.items()]
    if isinstance(target, Scenario):
        return target.with_sets(sets)
    return Scenario(os.fspath(target), sets)


def _value(value: Any) -> str:
    """A Python value as ``--set`` takes it: TOML for booleans, numbers and
    lists; a string or path as it is."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float) and not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_item(v) for v in value) + "]"
    return os.fspath(value) if isinstance(value, os.PathLike) else str(value)


def _item(value: Any) -> str:
    """A list item in TOML: a string quoted."""
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    return _value(value)


def run(scenario: Union[Scenario, str], seed: Optional[int] = None, *, max_stream_mb: int = _native.DEFAULT_MAX_STREAM_MB) -> "Run":
    """Runs ``scenario`` (or the preset named) with ``seed`` (default: the
    scenario's own, the one fixtures use) into memory. Other Python threads
    go on meanwhile; Ctrl-C stops the run at its next record (a model's
    step, such as a mosaic's day, may take a while) and raises
    ``KeyboardInterrupt``.
    A stream past ``max_stream_mb`` MiB is stopped (``MemoryError``). A
    seed given to a model that draws no random numbers is warned about, as
    ``morphogen run --seed`` warns."""
    if not isinstance(scenario, Scenario):
        scenario = Scenario(os.fspath(scenario), [])
    if seed is not None and not scenario.uses_seed:
        warnings.warn(
            f"seed has no effect on {scenario.name}: its model draws no random numbers "
            "(only the stream header records the seed)",
            stacklevel=2,
        )
    used = scenario.seed if seed is None else seed
    data, digest, frames = _native.run(scenario, used, max_stream_mb)
    return Run(scenario, used, data, digest, frames)


def sweep(
    scenario: Union[Scenario, str],
    grid: Mapping[str, Iterable[Any]],
    executor: Optional[Executor] = None,
) -> str:
    """Every combination of ``grid``'s values (a ``--set`` key, or
    ``"seed"``, and its values; the first key changing slowest) run over
    ``scenario``, on ``executor``: any ``concurrent.futures.Executor``,
    such as a ``ThreadPoolExecutor`` (runs release the interpreter), a
    ``ProcessPoolExecutor``, a Dask cluster's
    ``Client(...).get_executor()``; default: one run after the
    other here. A run sent to another process takes its scenario as one
    self-contained file and sends back one line of the table. Returns the
    table ``morphogen sweep --set KEY=V1,V2,…`` writes as ``sweep.csv``: a
    line per run with its values, seed, frames, bytes, digest, records per
    kind, the last frame's cells per type and the Morphogen that ran it.
    Every combination is checked before any runs (``ValueError``)."""
    if not isinstance(scenario, Scenario):
        scenario = Scenario(os.fspath(scenario), [])
    sets = [f"{key}={','.join(_value(v) for v in values)}" for key, values in grid.items()]
    plan = _native.Sweep(scenario, sets)
    for k in range(plan.runs):
        plan.scenario(k)
    if executor is None:
        lines = [_sweep_line(scenario, sets, k) for k in range(plan.runs)]
    else:
        futures = [executor.submit(_sweep_line, scenario, sets, k) for k in range(plan.runs)]
        lines = [f.result() for f in futures]
    return plan.header + "".join(lines)


def _sweep_line(scenario: Scenario, sets: List[str], k: int) -> str:
    """Run ``k`` of the sweep of ``scenario`` over ``sets``: its line of the
    table. A function of its arguments alone, so that any executor's
    worker can run it."""
    plan = _native.Sweep(scenario, sets)
    chosen, seed = plan.scenario(k)
    data, _, _ = _native.run(chosen, seed, _native.DEFAULT_MAX_STREAM_MB)
    return plan.line(k, data)


class Run:
    """A finished run: its stream and what can be made of it.

    * ``digest``: the stream's CRC-64/XZ as 16 hex digits, as ``morphogen
      run`` prints it and fixtures record it (``summary.toml``'s
      ``stream_digest``);
    * ``bytes``: the stream, byte for byte what ``stream.bin`` holds;
    * ``frames``: its number of frames (one record each), as ``morphogen
      run`` counts them;
    * ``records``: one numpy structured array per record kind (numpy
      needed), as ``morphogen_stream.to_arrays`` makes them;
    * ``version`` and ``scenario_text``: the Morphogen that ran it and the
      scenario as ``morphogen show`` prints it, for provenance.
    """

    def __init__(self, scenario: Scenario, seed: int, data: bytes, digest: int, frames: int) -> None:
        self.scenario = scenario
        self.seed = seed
        self.bytes = data
        self.digest = f"{digest:016x}"
        self.frames = frames
        self.version = _native.VERSION
        self.scenario_text = scenario.text
        self._records: Optional[Dict[str, Any]] = None

    @property
    def records(self) -> Dict[str, Any]:
        """The records as numpy structured arrays, one per kind present:
        ``records["cell"]["p"]``, ``records["cell"]["in_frame"]``
        (dtypes: ``morphogen_stream.dtype``). Read once, then kept."""
        if self._records is None:
            import morphogen_stream

            self._records = morphogen_stream.to_arrays(morphogen_stream.read_records(self.bytes))
        return self._records

    def write(self, dir: Union[str, os.PathLike], only: Optional[Union[str, List[str]]] = None) -> List[Path]:
        """Writes the run's files into ``dir`` as ``morphogen run --out DIR
        --only KINDS`` does: ``stream.bin`` always, then the kinds named
        (``"png,obj"`` or a list: png, obj, glb, anim, svg, csv, jsonl;
        default all). Returns the paths written, ``stream.bin`` first.
        An unknown kind raises ``ValueError``; an unwritable folder
        ``OSError``."""
        if only is not None and not isinstance(only, str):
            only = ",".join(only)
        written = _native.write(self.scenario, self.bytes, os.fspath(dir), only)
        return [Path(p) for p in written]

    def _repr_png_(self) -> bytes:
        """The model's main picture, for Jupyter."""
        return bytes(_native.picture(self.scenario, self.bytes))

    def __repr__(self) -> str:
        return (
            f"<Run {self.scenario.name} seed {self.seed}: {self.frames} frames, "
            f"{len(self.bytes)} bytes, digest {self.digest}>"
        )
