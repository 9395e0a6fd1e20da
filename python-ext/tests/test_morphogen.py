"""The `morphogen` package (the built wheel) against the golden fixtures and
the command line: every preset's stream and digest, the `--set` errors,
the files `.write` makes, provenance, and a run stopped by Ctrl-C.

Comparisons with the command line need its binary: $MORPHOGEN_BIN (default
target/release/morphogen); they are skipped with a message without it."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest
import multiprocessing
import pickle
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from pathlib import Path
from typing import Dict, List, Optional

import numpy

import morphogen
import morphogen_stream as ms
from morphogen_stream.arrays import dtype

REPO = Path(__file__).resolve().parents[2]
FIXTURES = REPO / "fixtures"


def morphogen_bin() -> Optional[Path]:
    """The Morphogen binary: $MORPHOGEN_BIN, default target/release/morphogen
    (relative to the repository root); None if absent."""
    path = Path(os.environ.get("MORPHOGEN_BIN", "target/release/morphogen"))
    if not path.is_absolute():
        path = REPO / path
    return path if path.is_file() and os.access(path, os.X_OK) else None


BIN = morphogen_bin()
NO_BIN = "the morphogen binary is missing: set MORPHOGEN_BIN or build target/release/morphogen"


def cli(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    """The command line's output (text)."""
    assert BIN is not None, NO_BIN
    proc = subprocess.run([str(BIN), *args], cwd=REPO, capture_output=True, text=True)
    if check and proc.returncode != 0:
        raise AssertionError(f"morphogen {' '.join(args)} exited {proc.returncode}: {proc.stderr}")
    return proc


def fixture_summary(name: str) -> Dict[str, object]:
    """fixtures/NAME/summary.toml's top-level `key = value` lines (the
    digest and the counts this test reads)."""
    text = (FIXTURES / name / "summary.toml").read_text(encoding="utf-8")
    try:
        import tomllib  # Python 3.11+

        return tomllib.loads(text)
    except ImportError:
        pairs = re.findall(r'^([a-z_]+) = "?([^"\n]*)"?$', text, re.M)
        return {k: int(v) if v.isdigit() else v for k, v in pairs}


def files(folder: Path) -> List[str]:
    """The files in `folder`, but its lock (`.morphogen.lock`)."""
    return sorted(name for name in os.listdir(folder) if not name.startswith("."))


class Presets(unittest.TestCase):
    def test_every_preset_has_a_fixture_and_morphogen_list_names_the_same(self):
        names = morphogen.presets()
        self.assertIn("ram-horn", names)
        missing = [n for n in names if not (FIXTURES / n / "stream.bin").is_file()]
        self.assertEqual(missing, [], "presets without a fixture")
        if BIN is None:
            self.skipTest(NO_BIN)
        listed = [line.split()[0] for line in cli("list").stdout.splitlines() if line.strip()]
        self.assertEqual(names, listed)


class EveryPreset(unittest.TestCase):
    """One test per preset: its run's bytes are its fixture's stream and
    its digest the fixture's (generated below)."""

    def check(self, name: str) -> None:
        result = morphogen.run(morphogen.scenario(name))
        summary = fixture_summary(name)
        self.assertEqual(result.digest, summary["stream_digest"], f"{name}: digest")
        self.assertEqual(result.frames, summary["frames"], f"{name}: frames")
        self.assertEqual(result.bytes, (FIXTURES / name / "stream.bin").read_bytes(), f"{name}: stream")


def _make(name: str):
    def test(self: EveryPreset) -> None:
        self.check(name)

    test.__doc__ = f"{name}: the stream and digest of fixtures/{name}"
    return test


for _name in morphogen.presets():
    setattr(EveryPreset, "test_" + _name.replace("-", "_"), _make(_name))


class Settings(unittest.TestCase):
    def test_a_value_out_of_range_is_a_value_error_naming_the_key_and_the_range(self):
        with self.assertRaises(ValueError) as raised:
            morphogen.scenario("ram-horn", horn__years=40)
        self.assertEqual(
            str(raised.exception), "--set horn.years=40: horn.years: 40 is out of range (allowed: 1 to 8)"
        )

    def test_a_dotted_key_with_an_index_in_a_dict_gives_the_command_lines_message(self):
        with self.assertRaises(ValueError) as raised:
            morphogen.scenario("ram-horn", {"horn.modules[0].bend": 1e9})
        message = str(raised.exception)
        self.assertIn("horn.modules[0].bend", message)
        self.assertIn("allowed", message)
        if BIN is None:
            self.skipTest(NO_BIN)
        proc = cli("run", "ram-horn", "--set", "horn.modules[0].bend=1000000000.0", "--quiet", check=False)
        self.assertEqual(proc.returncode, 2)
        self.assertEqual(proc.stderr.strip(), f"error: {message}")

    def test_an_unknown_preset_or_key_is_a_value_error(self):
        with self.assertRaisesRegex(ValueError, r"unknown preset 'ram-hron' \(did you mean 'ram-horn'\?"):
            morphogen.scenario("ram-hron")
        with self.assertRaisesRegex(ValueError, r"horn\.yaers.*did you mean `years`"):
            morphogen.scenario("ram-horn", horn__yaers=4)

    def test_settings_change_the_run_as_the_command_lines_do(self):
        changed = morphogen.scenario("ram-horn", {"horn.modules[0].bend": 80}, horn__years=4)
        self.assertNotEqual(changed.text, morphogen.scenario("ram-horn").text)
        again = morphogen.scenario(morphogen.scenario("ram-horn", horn__years=4), {"horn.modules[0].bend": 80})
        self.assertEqual(again.text, changed.text)
        result = morphogen.run(changed)
        self.assertNotEqual(result.digest, fixture_summary("ram-horn")["stream_digest"])
        if BIN is None:
            self.skipTest(NO_BIN)
        with tempfile.TemporaryDirectory() as tmp:
            cli("run", "ram-horn", "--set", "horn.modules[0].bend=80", "--set", "horn.years=4",
                "--only", "csv", "--quiet", "--out", tmp)
            self.assertEqual(result.bytes, Path(tmp, "stream.bin").read_bytes())


class Results(unittest.TestCase):
    def test_records_are_the_readers_arrays_and_counts(self):
        result = morphogen.run("croton-mcu")
        arrays = result.records
        expected = ms.to_arrays(ms.read_records(FIXTURES / "croton-mcu" / "stream.bin"))
        self.assertEqual(sorted(arrays), sorted(expected))
        for kind, array in arrays.items():
            self.assertEqual(array.dtype, dtype(kind), kind)
            numpy.testing.assert_array_equal(array, expected[kind], err_msg=kind)
        counts = {kind: len(a) for kind, a in arrays.items()}
        self.assertEqual(counts, fixture_summary("croton-mcu")["records"])

    def test_provenance_is_the_version_and_the_scenario_as_shown(self):
        with self.assertWarnsRegex(UserWarning, "seed has no effect on growth-curve"):
            result = morphogen.run("growth-curve", seed=3)
        self.assertEqual(result.seed, 3)
        self.assertEqual(result.version, morphogen.__version__)
        self.assertRegex(result.version, r"^\d+\.\d+\.\d+")
        self.assertIn('name = "growth-curve"', result.scenario_text)
        if BIN is None:
            self.skipTest(NO_BIN)
        self.assertEqual(result.scenario_text, cli("show", "growth-curve").stdout)
        # `morphogen 0.1.0 (git …)`: the same release (the commit may differ).
        self.assertEqual(result.version.split()[0], cli("--version").stdout.split()[1])

    def test_the_picture_for_a_notebook_is_the_models_png(self):
        for name in ["growth-curve", "abop-shrub"]:
            png = morphogen.run(name)._repr_png_()
            self.assertEqual(png[:8], b"\x89PNG\r\n\x1a\n", name)
            self.assertGreater(len(png), 1000, name)


class Write(unittest.TestCase):
    def test_write_makes_the_files_of_morphogen_run_only(self):
        result = morphogen.run("ram-horn")
        with tempfile.TemporaryDirectory() as tmp:
            written = result.write(Path(tmp) / "py", only=["png", "csv"])
            self.assertEqual(written[0], Path(tmp) / "py" / "stream.bin")
            self.assertEqual(written[0].read_bytes(), result.bytes)
            names = sorted(p.name for p in written)
            self.assertIn("horn.png", names)
            self.assertNotIn("records.jsonl", names)
            self.assertEqual(files(Path(tmp) / "py"), names)
            if BIN is None:
                self.skipTest(NO_BIN)
            cli("run", "ram-horn", "--only", "png,csv", "--quiet", "--out", str(Path(tmp) / "cli"))
            self.assertEqual(files(Path(tmp) / "cli"), names)
            for name in names:
                self.assertEqual(
                    (Path(tmp) / "py" / name).read_bytes(), (Path(tmp) / "cli" / name).read_bytes(), name
                )

    def test_write_all_kinds_gives_records_jsonl_as_the_command_line(self):
        result = morphogen.run("growth-curve")
        with tempfile.TemporaryDirectory() as tmp:
            written = result.write(tmp)
            self.assertIn(Path(tmp) / "records.jsonl", written)
            if BIN is None:
                self.skipTest(NO_BIN)
            decoded = cli("decode", str(Path(tmp) / "stream.bin")).stdout
            self.assertEqual((Path(tmp) / "records.jsonl").read_text(), decoded)

    def test_an_unknown_kind_is_a_value_error_and_nothing_is_written(self):
        result = morphogen.run("growth-curve")
        with tempfile.TemporaryDirectory() as tmp:
            with self.assertRaisesRegex(ValueError, "pdf"):
                result.write(Path(tmp) / "out", only="png,pdf")
            self.assertFalse((Path(tmp) / "out").exists())


def cli_sweep(target: str, sets: List[str]) -> str:
    """The ``sweep.csv`` of ``morphogen sweep TARGET --set … --out TMP``."""
    with tempfile.TemporaryDirectory() as tmp:
        cli("sweep", target, *[a for s in sets for a in ("--set", s)], "--out", tmp)
        return Path(tmp, "sweep.csv").read_text()


def same_table(test: unittest.TestCase, table: str, expected: str) -> None:
    """``table`` equals the command line's ``expected`` byte for byte when
    the wheel and the binary are the same Morphogen (as in CI); otherwise
    in all but the last column, the Morphogen that ran each run."""
    if morphogen.__version__ == cli("--version").stdout.split(" ", 1)[1].strip():
        test.assertEqual(table, expected)
    else:
        def cut(text: str) -> List[str]:
            return [line.rsplit(",", 1)[0] for line in text.splitlines()]

        test.assertEqual(cut(table), cut(expected))


class Sweeps(unittest.TestCase):
    def check_against_the_command_line(self, target: str, grid: Dict[str, list], sets: List[str]) -> None:
        with ThreadPoolExecutor(max_workers=2) as pool:
            table = morphogen.sweep(target, grid, pool)
        self.assertEqual(table, morphogen.sweep(target, grid), "on an executor and one after the other")
        runs = 1
        for values in grid.values():
            runs *= len(values)
        self.assertEqual(len(table.splitlines()), 1 + runs)
        if BIN is None:
            self.skipTest(NO_BIN)
        same_table(self, table, cli_sweep(target, sets))

    def test_a_sweep_of_values_and_seeds_is_the_table_of_morphogen_sweep(self):
        grid = {"horn.years": [2, 4], "horn.modules[0].bend": [60, 80.5], "seed": range(1, 3)}
        sets = ["horn.years=2,4", "horn.modules[0].bend=60,80.5", "seed=1..2"]
        self.check_against_the_command_line("ram-horn", grid, sets)

    def test_a_mosaics_sweep_counts_the_last_days_cells_by_type(self):
        self.check_against_the_command_line("croton-mcu", {"seed": [1, 2]}, ["seed=1,2"])

    def test_a_bad_combination_is_a_value_error_before_any_run(self):
        with self.assertRaisesRegex(ValueError, r"^the combination horn\.years=40: --set horn\.years=40: .*allowed: 1 to 8"):
            morphogen.sweep("ram-horn", {"horn.years": [2, 40]})

    def test_a_process_pool_gives_the_same_table(self):
        grid = {"lsystem.delta": [20, 25.5], "seed": [3, 4]}
        context = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(max_workers=2, mp_context=context) as pool:
            table = morphogen.sweep("abop-stochastic", grid, pool)
        self.assertEqual(table, morphogen.sweep("abop-stochastic", grid))


class Pickling(unittest.TestCase):
    """A scenario goes to another process as one self-contained file."""

    def test_every_preset_comes_back_the_same(self):
        for name in morphogen.presets():
            with self.subTest(name):
                scenario = morphogen.scenario(name)
                back = pickle.loads(pickle.dumps(scenario))
                self.assertEqual((back.name, back.seed, back.text), (scenario.name, scenario.seed, scenario.text))

    def test_settings_and_named_files_travel_with_it(self):
        scenario = morphogen.scenario(REPO / "examples" / "wagging-tail.toml", body__frames=12)
        back = pickle.loads(pickle.dumps(scenario))
        self.assertEqual(back.text, scenario.text)
        self.assertEqual(morphogen.run(back).digest, morphogen.run(scenario).digest)


@unittest.skipUnless(os.environ.get("MORPHOGEN_DASK", "1") != "0", "MORPHOGEN_DASK=0")
class Dask(unittest.TestCase):
    """A sweep on a Dask cluster of two worker processes on this machine
    (``LocalCluster``), through its ``concurrent.futures`` face, against
    ``morphogen sweep``'s table."""

    def test_a_sweep_on_a_local_cluster_is_the_table_of_morphogen_sweep(self):
        from dask.distributed import Client, LocalCluster

        grid = {"mosaic.days": [6, 9], "seed": [1, 2, 3]}
        sets = ["mosaic.days=6,9", "seed=1..3"]
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
            with Client(cluster) as client:
                table = morphogen.sweep("croton-mcu", grid, client.get_executor())
        self.assertEqual(len(table.splitlines()), 1 + 6)
        if BIN is None:
            self.skipTest(NO_BIN)
        same_table(self, table, cli_sweep("croton-mcu", sets))


class Interrupt(unittest.TestCase):
    """A run of many seconds (croton-ageing, 10 000 cells, with ten times
    its relaxations a day): other threads go on while it runs, and Ctrl-C
    stops it at its next record. Nothing here is timed: another thread
    sends Ctrl-C once it has run five times during the run, which it can
    only do with the interpreter released."""

    @staticmethod
    def long():
        return morphogen.scenario("croton-ageing", {"mosaic.daily_relaxations": 80})

    @unittest.skipIf(threading.current_thread() is not threading.main_thread(), "signals reach the main thread")
    def test_ctrl_c_from_a_thread_running_meanwhile_stops_the_run(self):
        # Ctrl-C raises KeyboardInterrupt whatever this process started
        # with: a shell starts its background jobs with SIGINT ignored, and
        # Python then installs no handler for it.
        previous = signal.signal(signal.SIGINT, signal.default_int_handler)
        self.addCleanup(signal.signal, signal.SIGINT, previous)
        long = self.long()
        running, done = threading.Event(), threading.Event()
        ticks = []

        def tick():
            running.wait()
            while not done.is_set() and len(ticks) < 5:
                ticks.append(time.perf_counter())
                time.sleep(0.01)
            if not done.is_set():
                os.kill(os.getpid(), signal.SIGINT)

        ticker = threading.Thread(target=tick)
        ticker.start()
        try:
            with self.assertRaises(KeyboardInterrupt):
                running.set()
                morphogen.run(long)
        finally:
            done.set()
            ticker.join()
        self.assertEqual(len(ticks), 5)
        # The next run is unaffected.
        self.assertEqual(morphogen.run("growth-curve").digest, fixture_summary("growth-curve")["stream_digest"])


if __name__ == "__main__":
    sys.exit(unittest.main())
