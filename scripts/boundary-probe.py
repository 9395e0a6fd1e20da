#!/usr/bin/env python3
"""Run presets with every numeric parameter at the ends of its allowed range.

For each preset (default: all of `morphogen list`), every number in its
scenario (`morphogen show NAME`) is set with `--set`, first far out of range
to read the allowed range from the door's message (`allowed: A to B`), then
to A and to B, and the run's outcome is classed:

  ok        exit 0
  refused   exit 2 with a message (a limit that depends on other keys;
            printed with --verbose)
  PANIC     a panic (exit 101 or "panicked" on standard error)
  TIMEOUT   still running after --timeout seconds (slow, not necessarily wrong)
  OTHER     any other exit code, or exit 2 without a message
  no-range  refused far out of range without saying the range (so its ends
            are not tried; printed with --verbose)

A key whose far-out value is accepted is reported as UNBOUNDED. The exit
code is 1 when anything is PANIC, OTHER or UNBOUNDED. By hand, after a change
to the scenario checks (docs/robustness.md): a full pass of all presets
takes about an hour on two cores.

    python3 scripts/boundary-probe.py [--bin target/release/morphogen]
        [--timeout 40] [--jobs 2] [PRESET ...]
"""

import argparse
import concurrent.futures
import os
import re
import subprocess
import sys
import tempfile
import tomllib

ALLOWED = re.compile(r"allowed: (-?[0-9.e+-]+) (?:%|°)? ?to (-?[0-9.e+-]+)")
FAR = {int: (99_999_999_999_999, -99_999_999_999_999), float: (1e30, -1e30)}


def leaves(value, path):
    """Every number in a scenario table: (path, value) with path a list of
    keys and indices."""
    if isinstance(value, bool) or isinstance(value, str):
        return
    if isinstance(value, (int, float)):
        yield path, value
    elif isinstance(value, dict):
        for key, inner in value.items():
            yield from leaves(inner, path + [key])
    elif isinstance(value, list):
        for i, inner in enumerate(value):
            yield from leaves(inner, path + [i])


def toml_value(value):
    """An inline TOML value (numbers, booleans, strings, arrays, tables)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return "{" + ", ".join(f"{k} = {toml_value(v)}" for k, v in value.items()) + "}"


def setting(scenario, path, new):
    """The `--set KEY=VALUE` that puts `new` at `path`. `--set` indexes
    arrays of tables (`types[1].division_days`) and of numbers
    (`values[3]`) but not arrays of arrays (`outline[0][0]`): those are
    written whole, inline."""
    key, node = "", scenario
    for i, step in enumerate(path):
        if isinstance(step, int):
            if any(isinstance(v, list) for v in node):
                return f"{key}={toml_value(replaced(node, path[i:], new))}"
            key += f"[{step}]"
        else:
            key += ("." if key else "") + step
        node = node[step]
    return f"{key}={toml_value(new)}"


def replaced(value, path, new):
    if not path:
        return new
    copy = list(value) if isinstance(value, list) else dict(value)
    copy[path[0]] = replaced(value[path[0]], path[1:], new)
    return copy


def run(args, preset, assignment, out):
    command = [args.bin, "run", preset, "--set", assignment, "--out", out, "-q"]
    try:
        done = subprocess.run(
            command, capture_output=True, text=True, timeout=args.timeout
        )
    except subprocess.TimeoutExpired:
        return "TIMEOUT", ""
    error = done.stderr.strip()
    if done.returncode == 101 or "panicked" in error:
        return "PANIC", error
    if done.returncode == 0:
        return "ok", ""
    if done.returncode == 2 and error:
        return "refused", error
    return "OTHER", f"exit {done.returncode}: {error}"


def shown(value, like):
    """A range's end as the scenario's number: an integer where the key
    holds one and the end is whole (`0.01 to 10000 %` stays fractional)."""
    number = float(value)
    if isinstance(like, int) and number.is_integer():
        return int(number)
    return number


def probe_key(args, preset, scenario, path, original, out):
    """The outcomes of one key: [(what, value, outcome, message)]."""
    name = ".".join(str(p) for p in path)
    results = []
    range_seen, refusal = None, ""
    for far in FAR[type(original)]:
        outcome, message = run(args, preset, setting(scenario, path, far), out)
        if outcome == "ok":
            results.append((name, far, "UNBOUNDED", ""))
        elif outcome != "refused":
            results.append((name, far, outcome, message))
        else:
            refusal = message
            found = ALLOWED.search(message)
            if found:
                range_seen = found.groups()
    if range_seen is None:
        if refusal:
            results.append((name, FAR[type(original)][0], "no-range", refusal))
        return results
    for end in range_seen:
        try:
            value = shown(end, original)
        except ValueError:
            continue
        outcome, message = run(args, preset, setting(scenario, path, value), out)
        results.append((name, value, outcome, message))
    return results


def probe(args, preset):
    shown_toml = subprocess.run(
        [args.bin, "show", preset], capture_output=True, text=True, check=True
    ).stdout
    scenario = tomllib.loads(shown_toml)
    model = [k for k, v in scenario.items() if isinstance(v, dict)]
    results = []
    with tempfile.TemporaryDirectory() as out:
        for path, value in leaves({k: scenario[k] for k in model}, []):
            results += probe_key(args, preset, scenario, path, value, out)
    return preset, results


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bin", default="target/release/morphogen")
    parser.add_argument("--timeout", type=float, default=40)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument(
        "--verbose", action="store_true", help="also print what was refused, and why"
    )
    parser.add_argument("presets", nargs="*")
    args = parser.parse_args()
    args.bin = os.path.abspath(args.bin)
    presets = args.presets or [
        line.split()[0]
        for line in subprocess.run(
            [args.bin, "list"], capture_output=True, text=True, check=True
        ).stdout.splitlines()
        if line.strip()
    ]
    bad = 0
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        for preset, results in pool.map(lambda p: probe(args, p), presets):
            counts = {}
            for _, _, outcome, _ in results:
                counts[outcome] = counts.get(outcome, 0) + 1
            print(f"{preset}: " + ", ".join(f"{n} {o}" for o, n in sorted(counts.items())))
            for name, value, outcome, message in results:
                quiet = outcome in ("refused", "no-range") and not args.verbose
                if outcome == "ok" or quiet:
                    continue
                print(f"  {outcome:9} {name} = {value}: {message[:300]}")
                bad += outcome in ("PANIC", "OTHER", "UNBOUNDED")
            sys.stdout.flush()
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
