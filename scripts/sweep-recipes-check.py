#!/usr/bin/env python3
"""The cluster recipes of docs/sweeps.md, run as they are written there.

The document's fenced blocks whose info string names them (```sh parallel,
```bash sweep.sbatch, ```python Snakefile) are taken verbatim: files are
written, commands run with bash, each recipe in a folder of its own with
`morphogen` on the PATH. The one-machine sweep (`one-machine`) gives the
reference table; the Slurm array job (`sweep.sbatch`, submitted by `slurm`
through an `sbatch` that runs the array's tasks here one after the
other with the variables Slurm sets), GNU parallel (`parallel`) and
Snakemake (`Snakefile`, run by `snakemake`) must each merge into an
`all/sweep.csv` equal to it byte for byte.

Needs GNU parallel and Snakemake on the PATH (scripts/check.sh installs
them).

    python3 scripts/sweep-recipes-check.py --bin target/release/morphogen
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Dict

REPO = Path(__file__).resolve().parents[1]
DOC = REPO / "docs" / "sweeps.md"

#: An `sbatch` for a machine without Slurm: `--wrap CMD` runs CMD; a
#: script runs once per task of its `#SBATCH --array=A-B`, with the
#: variables an array task sees, one task after the other.
SBATCH = r'''#!/usr/bin/env python3
import os, re, subprocess, sys
args = sys.argv[1:]
if "--wrap" in args:
    sys.exit(subprocess.call(["bash", "-c", args[args.index("--wrap") + 1]]))
script = [a for a in args if not a.startswith("-")][-1]
text = open(script).read()
array = re.search(r"^#SBATCH --array=(\d+)-(\d+)\s*$", text, re.M)
cpus = re.search(r"^#SBATCH --cpus-per-task=(\d+)\s*$", text, re.M)
first, last = (int(array[1]), int(array[2])) if array else (0, 0)
for task in range(first, last + 1):
    env = dict(os.environ, SLURM_ARRAY_TASK_ID=str(task),
               SLURM_ARRAY_TASK_COUNT=str(last - first + 1),
               SLURM_CPUS_PER_TASK=cpus[1] if cpus else "1")
    subprocess.run(["bash", script], env=env, check=True)
print("1" if "--parsable" in args else "Submitted batch job 1")
'''


def named_blocks(markdown: str) -> Dict[str, str]:
    """The fenced blocks whose info string is a language and a name."""
    blocks = {}
    for match in re.finditer(r"^```(\w+) (\S+)\n(.*?)^```$", markdown, re.M | re.S):
        blocks[match[2]] = match[3]
    return blocks


def run_block(name: str, text: str, folder: Path, env: Dict[str, str]) -> None:
    """Runs a block of shell in `folder`; a failure names the block."""
    proc = subprocess.run(["bash", "-euo", "pipefail", "-c", text], cwd=folder, env=env,
                          capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"sweep-recipes-check: `{name}` exited {proc.returncode}:\n{proc.stdout}{proc.stderr}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--bin", default=str(REPO / "target" / "release" / "morphogen"),
                        help="the morphogen binary (default: target/release/morphogen)")
    args = parser.parse_args()
    binary = Path(args.bin).resolve()
    if not os.access(binary, os.X_OK):
        sys.exit(f"sweep-recipes-check: no morphogen binary at {binary}")
    # Each recipe runs in a folder of its own: the tools' folders go on its
    # PATH as absolute paths.
    tools_found = []
    for tool in ("parallel", "snakemake"):
        found = shutil.which(tool)
        if found is None:
            sys.exit(f"sweep-recipes-check: `{tool}` is not on the PATH (scripts/check.sh installs it)")
        tools_found.append(str(Path(found).absolute().parent))

    blocks = named_blocks(DOC.read_text(encoding="utf-8"))
    recipes = {
        "Slurm array job": ("slurm", ["sweep.sbatch"]),
        "GNU parallel": ("parallel", []),
        "Snakemake": ("snakemake", ["Snakefile"]),
    }
    needed = {"one-machine"} | {n for command, files in recipes.values() for n in [command, *files]}
    missing = sorted(needed - blocks.keys())
    if missing:
        sys.exit(f"sweep-recipes-check: docs/sweeps.md has no block named {', '.join(missing)}")

    with tempfile.TemporaryDirectory(prefix="morphogen-recipes-") as tmp:
        tools = Path(tmp, "bin")
        tools.mkdir()
        (tools / "morphogen").symlink_to(binary)
        (tools / "sbatch").write_text(SBATCH)
        (tools / "sbatch").chmod(0o755)
        env = dict(os.environ, PATH=os.pathsep.join([str(tools), *tools_found, os.environ["PATH"]]))

        reference = Path(tmp, "one-machine")
        reference.mkdir()
        run_block("one-machine", blocks["one-machine"], reference, env)
        expected = (reference / "sweep" / "sweep.csv").read_bytes()
        runs = len(expected.splitlines()) - 1
        print(f"sweep-recipes-check: one machine: {runs} runs")

        failed = []
        for recipe, (command, files) in recipes.items():
            folder = Path(tmp, command)
            folder.mkdir()
            for name in files:
                (folder / name).write_text(blocks[name])
            run_block(command, blocks[command], folder, env)
            merged = folder / "all" / "sweep.csv"
            same = merged.is_file() and merged.read_bytes() == expected
            print(f"sweep-recipes-check: {recipe}: {'ok' if same else 'DIFFERENT'} (all/sweep.csv)")
            if not same:
                failed.append(recipe)
    if failed:
        print(f"sweep-recipes-check: {', '.join(failed)}: the merged table is not the one-machine sweep's",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
