#!/usr/bin/env python3
"""Writes firmware-example/REPORT.md (stdout) from a firmware-check work dir.

Usage: report.py WORKDIR TARGET... — reads WORKDIR/TARGET.elf (sizes via
binutils `size -A`) and WORKDIR/TARGET.log (the defmt lines that start with
`report`, see src/main.rs) of the built-in presets, WORKDIR/host-presets.txt
(`morphogen list`) and, when present, WORKDIR/user.log (the firmware built
with MORPHOGEN_SCENARIOS). Called by scripts/firmware-check.sh.
"""
import os
import re
import subprocess
import sys

work, targets = sys.argv[1], sys.argv[2:]


def sections(elf):
    out = subprocess.run(["size", "-A", elf], check=True, capture_output=True, text=True).stdout
    sizes = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) >= 2 and parts[0].startswith(".") and parts[1].isdigit():
            sizes[parts[0]] = int(parts[1])
    return sizes


def kib(n):
    return f"{n:,} B ({n / 1024:.1f} KiB)"


def preset_runs(name):
    """The text of WORKDIR/NAME.log ("" if absent) and its `report preset=` lines."""
    try:
        text = open(f"{work}/{name}.log", encoding="utf-8", errors="replace").read()
    except OSError:
        text = ""
    runs = [m.groupdict() for m in re.finditer(
        r"report preset=(?P<name>\S+) seed=(?P<seed>\d+) frames=(?P<frames>\d+) "
        r"bytes=(?P<bytes>\d+) digest=(?P<digest>[0-9a-f]+) systicks=(?P<ticks>\d+)", text)]
    return text, runs


def version(cmd):
    try:
        return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.splitlines()[0].strip()
    except (OSError, subprocess.CalledProcessError, IndexError):
        return "unknown"


runs = {}
for t in targets:
    text = open(f"{work}/{t}.log", encoding="utf-8", errors="replace").read()
    clock = re.search(r"report clock qemu_cpu_hz=(\d+) runner_bytes=(\d+)", text)
    stack = re.search(r"report stack peak=(\d+) region=(\d+) static=(\d+)", text)
    presets = [m.groupdict() for m in re.finditer(
        r"report preset=(?P<name>\S+) seed=(?P<seed>\d+) frames=(?P<frames>\d+) "
        r"bytes=(?P<bytes>\d+) digest=(?P<digest>[0-9a-f]+) systicks=(?P<ticks>\d+) "
        r"fit_systicks=(?P<fit>\d+)", text)]
    if not (clock and stack and presets):
        sys.exit(f"report.py: {t}.log lacks report lines")
    state = re.search(r"report state (.*)", text)
    models = dict(kv.split("=") for kv in state[1].split()) if state else {}
    runs[t] = dict(hz=int(clock[1]), runner=int(clock[2]), peak=int(stack[1]), models=models,
                   region=int(stack[2]), presets=presets, sizes=sections(f"{work}/{t}.elf"))

main = runs[targets[0]]
ns_per_tick = 10**9 // main["hz"]
w = sys.stdout.write
w("# Firmware size and cost report\n\n")
w("Written by `scripts/firmware-check.sh` — do not edit; rerun the script and\n"
  "commit the result, so that a change in size or cost shows in review.\n\n")
w(f"- toolchain: `{version(['rustc', '--version'])}`, release profile (`opt-level = \"s\"`, fat LTO)\n")
w(f"- emulator: `{version(['qemu-system-arm', '--version'])}`, machine `lm3s6965evb`\n")
w("- board: TI LM3S6965 — 256 KiB flash, 64 KiB SRAM (the RAM budget of every target below)\n\n")

w("## Size per target\n\n")
w("Flash = `.vector_table` + `.text` + `.rodata` (+ the `.data` load image);\n"
  "static RAM = `.data` + `.bss` + `.uninit`. Peak stack from stack painting\n"
  "(`cortex-m-rt` feature `paint-stack`), measured after all presets ran in\n"
  "QEMU (`thumbv7em` on `-cpu cortex-m4`, the others on `cortex-m3`).\n\n")
w("| target | flash | of which .text | .rodata | static RAM | peak stack | RAM used |\n")
w("|---|---:|---:|---:|---:|---:|---:|\n")
for t in targets:
    s = runs[t]["sizes"]
    flash = s.get(".vector_table", 0) + s.get(".text", 0) + s.get(".rodata", 0) + s.get(".data", 0)
    ram = s.get(".data", 0) + s.get(".bss", 0) + s.get(".uninit", 0)
    used = ram + runs[t]["peak"]
    w(f"| {t} | {kib(flash)} | {s.get('.text', 0):,} | {s.get('.rodata', 0):,} | {ram:,} B "
      f"| {runs[t]['peak']:,} B | {used:,} B of 65,536 ({100 * used / 65536:.1f} %) |\n")
if os.path.exists(f"{work}/stream-only.elf"):
    s = sections(f"{work}/stream-only.elf")
    flash = s.get(".vector_table", 0) + s.get(".text", 0) + s.get(".rodata", 0) + s.get(".data", 0)
    ram = s.get(".data", 0) + s.get(".bss", 0) + s.get(".uninit", 0)
    peak = int(re.search(r"report stack peak=(\d+)", open(f"{work}/stream-only.log", encoding="utf-8",
                                                             errors="replace").read())[1])
    used = ram + peak
    full = runs[targets[0]]["sizes"]
    full_flash = sum(full.get(k, 0) for k in (".vector_table", ".text", ".rodata", ".data"))
    w(f"| {targets[0]}, stream only (profile small) | {kib(flash)} | {s.get('.text', 0):,} | {s.get('.rodata', 0):,} "
      f"| {ram:,} B | {peak:,} B | {used:,} B of 65,536 ({100 * used / 65536:.1f} %) |\n")
    w(f"\n*Stream only* is the sender built for size without its features `extent`,\n"
      f"`oled` and `serve`, its frame CRC bit by bit (`--profile small\n"
      f"--no-default-features --features semihosting,bitwise-crc`; the profile\n"
      f"`small` is `release` at `opt-level = \"z\"` without overflow checks): every\n"
      f"preset, streamed to UART0 exactly as `morphogen run` writes `stream.bin`\n"
      f"(the default build's capture without its extent frames, checked). It must\n"
      f"stay under 96 KB (96,000 B) of flash (the check fails\n"
      f"otherwise): {96000 - flash:,} B to spare.\n"
      f"The default build (profile `release`, with extents, drawing on the OLED\n"
      f"and serving sent scenarios) takes {full_flash:,} B.\n")
w(f"\nThe preset runner (`morphogen::preset::Runner`, one `static`) takes {main['runner']:,} B.\n")
if main["models"]:
    w("It holds one model at a time; each model's state (`size_of`, the RAM a\n"
      "preset of that model needs beyond the firmware's baseline, besides stack):\n\n"
      "| model | state |\n|---|---:|\n")
    for model, size in main["models"].items():
        w(f"| {model} | {int(size):,} B |\n")
w("\n")

w("## Cost per preset\n\n")
w(f"SysTick deltas under `-icount shift=0`: QEMU advances 1 ns per instruction\n"
  f"and models a {main['hz'] // 10**6} MHz core clock, so one tick ≈ {ns_per_tick}\n"
  "instructions. The counts repeat to within one tick from run to run; they\n"
  "are a proxy\n"
  "(QEMU does not model cycles; DWT CYCCNT reads 0).\n\n"
  "Each preset runs twice: *simulate* is the first run, into the `Bounds`\n"
  "that fit the OLED's view (the simulation alone, nothing written); the\n"
  "target columns are the second run, which also encodes the stream to\n"
  "UART0 and draws every frame on the OLED.\n\n")
header = (f"| preset | seed | records | bytes | digest | simulate ({targets[0]}) |"
          + "".join(f" {t}: simulate + stream + draw |" for t in targets))
w(header + "\n|---|---:|---:|---:|---|---:|" + "---:|" * len(targets) + "\n")
for i, p in enumerate(main["presets"]):
    fit = int(p["fit"])
    row = (f"| {p['name']} | {p['seed']} | {int(p['frames']):,} | {int(p['bytes']):,} | `{p['digest']}` "
           f"| {fit:,} (≈ {fit * ns_per_tick / 1e6:.2f} M) |")
    for t in targets:
        q = runs[t]["presets"][i]
        if q["name"] != p["name"] or q["digest"] != p["digest"]:
            sys.exit(f"report.py: {t} disagrees with {targets[0]} on preset {p['name']}")
        ticks = int(q["ticks"])
        row += f" {ticks:,} (≈ {ticks * ns_per_tick / 1e6:.2f} M) |"
    w(row + "\n")
verifier = os.environ.get("VERIFY_COMMAND", "morphogen verify --stream")
verifier = re.sub(r"^cargo run .*? -- ", "morphogen ", verifier)
verifier = re.sub(r"^/\S*/", "", verifier)
w("\nEvery target streamed the same bytes (same digests), and each capture\n"
  f"passed `{verifier} CAPTURE`.\n\n")

try:
    oled = [m.groups() for m in re.finditer(
        r"oled-screens: (\S+): (\d+) pixels drawn, (\d+) differ", open(f"{work}/oled.log", encoding="utf-8").read())]
except OSError:
    oled = []
if oled:
    w("## The OLED\n\n"
      "Each target drew every preset on the emulated SSD0323 (128×64, 16 greys);\n"
      "after each preset's last frame the script took QEMU's `screendump` and\n"
      "compared it with the host's `--rig 128x64:grey4` picture of the same\n"
      "stream (`target/rig-screens/`), pixel for pixel:\n\n"
      "| preset | pixels drawn | pixels that differ (all targets) |\n|---|---:|---:|\n")
    for name, drawn, differ in oled[: len(main["presets"])]:
        total = sum(int(d) for n, _, d in oled if n == name)
        w(f"| {name} | {int(drawn):,} of 8,192 | {total} |\n")
    w("\n")

if os.path.exists(f"{work}/receiver.elf"):
    s = sections(f"{work}/receiver.elf")
    flash = s.get(".vector_table", 0) + s.get(".text", 0) + s.get(".rodata", 0) + s.get(".data", 0)
    ram = s.get(".data", 0) + s.get(".bss", 0) + s.get(".uninit", 0)
    same = re.findall(r"oled-screens: \S+: \d+ pixels drawn, 0 differ from the sender",
                      open(f"{work}/receiver-oled.log", encoding="utf-8").read())
    damaged = re.search(r"report received preset=(\S+) shown=(\d+) skipped=(\d+) bad=(\d+)",
                        open(f"{work}/damaged.log", encoding="utf-8", errors="replace").read())
    w("## The receiver\n\n"
      f"`morphogen-receiver` ({targets[0]}: flash {kib(flash)}, static RAM {ram:,} B) read\n"
      f"the {targets[0]} capture on its UART0 and drew {len(same)} streams on its OLED,\n"
      "each picture identical to the sender's, pixel for pixel.\n")
    if damaged:
        w(f"Fed {damaged[1]} with two flipped bits, it skipped {damaged[3]} frames\n"
          f"({damaged[4]} bad frames), showed the other {damaged[2]}, and ended on the same\n"
          "picture as the host's `morphogen listen` of that stream.\n")
    w("\n")

w("## Presets at reduced size, and host-only presets\n\n")
w(f"The firmware runs every built-in scenario (`scenarios/*.toml`) that fits the\n"
  f"MCU (`Model::fits_mcu`; the core has no heap), compiled in as `static`\n"
  f"presets by `build.rs`; the big mosaics are host only:\n"
  f"{len(main['presets'])} presets here, none skipped (an error fails the run).\n\n")
fw_names = [p["name"] for p in main["presets"]]
surface_log, runs_surface = preset_runs("surface")
surface_names = [p["name"] for p in runs_surface]
host = []
why = {}
try:
    for line in open(f"{work}/host-presets.txt", encoding="utf-8"):
        # `NAME  seed N  SUMMARY`, then `  (host only: WHY)` on host presets.
        m = re.match(r"(\S+)\s+seed\s+\d+\s+(.*?)(?:\s+\((host only: .*)\))?$", line.strip())
        if m:
            host.append((m[1], m[2]))
            if m[3]:
                why[m[1]] = m[3][len("host only: "):]
except OSError:
    pass
if not host:
    w("(`morphogen list` was not available: host-only presets not listed.)\n")
else:
    summaries = dict(host)
    reduced = [n for n in fw_names if "mcu" in n.lower() or "MCU" in summaries.get(n, "")]
    host_only = [(n, s) for n, s in host if n not in fw_names or n in why]
    w("| preset | on the firmware | why |\n|---|---|---|\n")
    for n in reduced:
        w(f"| {n} | yes, reduced size, own fixture | {summaries.get(n, '')} |\n")
    for n in surface_names:
        w(f"| {n} | yes, built with the feature `surface` (below) | {summaries.get(n, '')} |\n")
    for n, s in host_only:
        if n in surface_names:
            continue
        reason = why.get(n, "its state exceeds the 64 KiB RAM")
        w(f"| {n} | no: host only | {reason}; {s} |\n")
    if not reduced and not host_only:
        w("None: every host preset runs on the firmware at full size.\n")

_, runs_user = preset_runs("user")
if runs_user:
    w("\n## A user scenario\n\n"
      "The script also builds the firmware (thumbv7m) with `MORPHOGEN_SCENARIOS` naming a\n"
      "scenario file it writes on the fly (`scenarios/ram-horn.toml` renamed, 3 years,\n"
      "one frame a year), runs it in QEMU and verifies the capture bit for bit\n"
      "against the fixture `morphogen bless` writes from the same file on the host:\n\n")
    w("| preset | seed | records | bytes | digest | ticks (≈ instr.) |\n|---|---:|---:|---:|---|---:|\n")
    for p in runs_user:
        ticks = int(p["ticks"])
        w(f"| {p['name']} | {p['seed']} | {int(p['frames']):,} | {int(p['bytes']):,} | `{p['digest']}` |"
          f" {ticks:,} (≈ {ticks * ns_per_tick / 1e6:.2f} M) |\n")

if runs_surface:
    s = sections(f"{work}/surface.elf")
    flash = s.get(".vector_table", 0) + s.get(".text", 0) + s.get(".rodata", 0) + s.get(".data", 0)
    ram = s.get(".data", 0) + s.get(".bss", 0) + s.get(".uninit", 0)
    peak = int(re.search(r"report stack peak=(\d+)", surface_log)[1])
    state = re.search(r"report surface-state surface-mosaic=(\d+)", surface_log)
    w("\n## A mosaic on a surface\n\n"
      "Built with the feature `surface` (the core's `surface-runner`: the runner\n"
      "also holds a surface mosaic, its cells and mesh inline) and\n"
      "`MORPHOGEN_SCENARIOS=scenarios/watermelon-mcu.toml`, the firmware grows\n"
      "the watermelon on its ellipsoid in QEMU (thumbv7m); the capture passed\n"
      f"`{verifier} CAPTURE` against the fixture the host blessed:\n\n"
      f"- flash {kib(flash)} (every model's code and this one preset); static RAM\n"
      f"  {ram:,} B (as the default build's); peak stack {peak:,} B\n"
      + (f"- surface mosaic state: {int(state[1]):,} B (cells and mesh), within the runner's\n"
         f"  {main['runner']:,} B\n" if state else "")
      + "\n| preset | seed | records | bytes | digest | ticks (≈ instr.) |\n|---|---:|---:|---:|---|---:|\n")
    for p in runs_surface:
        ticks = int(p["ticks"])
        w(f"| {p['name']} | {p['seed']} | {int(p['frames']):,} | {int(p['bytes']):,} | `{p['digest']}` |"
          f" {ticks:,} (≈ {ticks * ns_per_tick / 1e6:.2f} M) |\n")
