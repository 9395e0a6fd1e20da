#!/usr/bin/env python3
"""Reads `plot.svg` back with vpype, one preset per model, and checks it
against the model's own stream: the paper (A4, in millimetres), the layers,
the drawing inside the paper less its margin, and the number of paths the
model gives:

- abop-2d-plant: the last frame's segments joined as the turtle drew them
  (a segment continues its colour's last path when it starts where that
  path ends), a layer per colour index;
- ram-horn: the outline, and at least one arc per growth ring (a ring
  where one monthly band meets the next, J rings a module);
- long-bone, horse-growth: the outline;
- croton-mcu (a torus): the Voronoi diagram of the last day's N cells
  has 3N edges; cut at the picture's sides, each crossing adds a path
  and two ends facing each other across the picture;
- watermelon-mcu (on a mesh): its type borders and its outline.

Each file is then made into HPGL with vpype's command line (`read
linemerge linesort write -d hp7475a -p a4`). Needs vpype (`pip install
vpype`; scripts/check.sh installs it) and the morphogen binary:

    python3 scripts/plot-check.py --bin target/release/morphogen
"""

import argparse
import os
import re
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
import morphogen_stream as ms  # noqa: E402
import vpype  # noqa: E402

MM = 25.4 / 96.0  # vpype's unit is the CSS pixel
A4 = (210.0, 297.0)
MARGIN = 15.0
# Path data is rounded to a hundredth of a millimetre.
SLACK = 0.011


def run(binary, preset, out):
    subprocess.run(
        [binary, "run", preset, "--out", out, "--only", "plot", "--quiet"],
        check=True,
    )
    return os.path.join(out, "plot.svg")


def last_frame(records):
    """The records of the last frame (all of them when there are no frames)."""
    starts = [k for k, r in enumerate(records) if isinstance(r, ms.FrameStart)]
    return records[starts[-1] :] if starts else records


def read(path):
    """The document vpype reads, the layer names in the file and its paths
    of a single point."""
    doc = vpype.read_multilayer_svg(path, quantization=0.1)
    root = ET.parse(path).getroot()
    label = "{http://www.inkscape.org/namespaces/inkscape}label"
    mode = "{http://www.inkscape.org/namespaces/inkscape}groupmode"
    names = [g.get(label) for g in root if g.get(mode) == "layer"]
    data = [e.get("d") for e in root.iter("{http://www.w3.org/2000/svg}path")]
    # Paths of a single point (after rounding), which vpype leaves out.
    dots = sum(len(set(re.findall(r"[-\d.]+,[-\d.]+", d))) == 1 for d in data)
    assert len(paths(doc)) == len(names), (paths(doc), names)
    assert sum(paths(doc)) + dots == len(data), (paths(doc), dots, len(data))
    fills = {e.get("fill") for e in root.iter() if e.get("fill") is not None}
    assert fills == {"none"}, f"{path}: fills {fills}"
    assert root.get("width", "").endswith("mm"), root.get("width")
    return doc, names, dots


def check_paper(path, doc):
    size = tuple(v * MM for v in doc.page_size)
    # vpype's millimetre is 3.7795 of its pixels, a hair off 96 / 25.4.
    assert all(abs(a - b) < 0.01 for a, b in zip(sorted(size), sorted(A4))), f"{path}: page {size}"
    x0, y0, x1, y1 = (v * MM for v in doc.bounds())
    w, h = size
    inside = (
        x0 >= MARGIN - SLACK
        and y0 >= MARGIN - SLACK
        and x1 <= w - MARGIN + SLACK
        and y1 <= h - MARGIN + SLACK
    )
    assert inside, f"{path}: extent {(x0, y0, x1, y1)} outside {w}x{h} less {MARGIN}"
    # Fitted: the drawing touches the margin on one axis at least.
    touches = min(x0 - MARGIN, y0 - MARGIN, w - MARGIN - x1, h - MARGIN - y1)
    assert touches < 0.05, f"{path}: not fitted to the margin ({touches} mm)"
    return (x0, y0, x1, y1)


def paths(doc):
    return [len(doc.layers[k]) for k in sorted(doc.layers)]


def plant_paths(records):
    """The paths the plant's segments make, per colour, as the turtle drew them."""
    ends = {}
    counts = {}
    for r in last_frame(records):
        if isinstance(r, ms.Polygon):
            raise AssertionError("a plant with polygons: pick one without")
        if not isinstance(r, ms.Segment):
            continue
        colour = min(r.colour, 12)
        if ends.get(colour) != r.a[:2]:
            counts[colour] = counts.get(colour, 0) + 1
        ends[colour] = r.b[:2]
    return counts


def horn_rings(records, j):
    """The growth rings: rings where the monthly band changes."""
    rings = []
    for r in last_frame(records):
        if isinstance(r, ms.Ring):
            rings.append([r.module, r.ring, []])
        elif isinstance(r, ms.Point) and rings:
            rings[-1][2].append(r.p)
    count = 0
    for k, (module, ring, points) in enumerate(rings):
        if k > 0:
            before = rings[k - 1]
            same_band = before[0] == module and before[1] * 12 // j == ring * 12 // j
            if same_band or before[2] == points:
                continue
        count += 1
    return count


def torus_edges(doc, extent, dots):
    """Voronoi edges on a torus from the cut paths: the paths less the
    pairs of ends facing each other across the picture (at the same height
    on its left and right sides, or across on its top and bottom)."""
    x0, y0, x1, y1 = (v / MM for v in extent)
    tol = 0.015 / MM
    ends = [p for layer in doc.layers.values() for line in layer for p in (line[0], line[-1])]
    # vpype drops a path of one point: an edge shorter than the file's
    # hundredth of a millimetre.
    count = sum(len(layer) for layer in doc.layers.values()) + dots

    def pairs(near_a, near_b, along):
        a = sorted(along(p) for p in ends if near_a(p))
        b = sorted(along(p) for p in ends if near_b(p))
        return sum(any(abs(u - v) < tol for v in b) for u in a)

    across = pairs(
        lambda p: abs(p.real - x0) < tol, lambda p: abs(p.real - x1) < tol, lambda p: p.imag
    )
    down = pairs(
        lambda p: abs(p.imag - y0) < tol, lambda p: abs(p.imag - y1) < tol, lambda p: p.real
    )
    return count - across - down, (across, down)


def hpgl(path, out):
    subprocess.run(
        [sys.executable, "-m", "vpype_cli", "read", path, "linemerge", "linesort"]
        + ["write", "-d", "hp7475a", "-p", "a4", out],
        check=True,
        capture_output=True,
    )
    text = open(out).read()
    assert text.startswith("IN;") and "PD" in text, text[:200]
    return text.count("PU")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bin", default="target/release/morphogen")
    binary = parser.parse_args().bin
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        presets = (
            "abop-2d-plant",
            "ram-horn",
            "long-bone",
            "horse-growth",
            "croton-mcu",
            "watermelon-mcu",
        )
        for preset in presets:
            out = os.path.join(tmp, preset)
            try:
                path = run(binary, preset, out)
                records = ms.read_records(os.path.join(out, "stream.bin"))
                doc, names, dots = read(path)
                extent = check_paper(path, doc)
                counts = paths(doc)
                if preset == "abop-2d-plant":
                    expected = plant_paths(records)
                    want = [f"{n + 1} colour {c}" for n, c in enumerate(sorted(expected))]
                    assert names == want, names
                    assert counts == [expected[c] for c in sorted(expected)], (counts, expected)
                    said = f"{sum(counts)} paths (segments joined as drawn)"
                elif preset == "ram-horn":
                    shown = subprocess.run(
                        [binary, "show", preset], check=True, capture_output=True, text=True
                    ).stdout
                    j = int(re.search(r"rings_per_module\s*=\s*(\d+)", shown).group(1))
                    rings = horn_rings(records, j)
                    assert names == ["1 outline", "2 rings"], names
                    assert counts[0] >= 1 and rings <= counts[1] <= 2 * rings, (counts, rings)
                    said = f"outline {counts[0]} paths, {counts[1]} ring arcs of {rings} rings"
                elif preset == "watermelon-mcu":
                    assert names == ["1 type borders", "2 outline"], names
                    assert min(counts) >= 1, counts
                    said = f"type borders {counts[0]} paths, outline {counts[1]} paths"
                elif preset in ("long-bone", "horse-growth"):
                    assert names == ["1 outline"] and counts[0] >= 1, (names, counts)
                    said = f"outline {counts[0]} paths"
                else:
                    cells = sum(isinstance(r, ms.Cell) for r in last_frame(records))
                    assert names == ["1 type borders", "2 cell edges"], names
                    edges, cut = torus_edges(doc, extent, dots)
                    assert edges == 3 * cells, (edges, cells, cut)
                    said = (
                        f"{sum(counts)} paths and {dots} dots, {sum(cut)} cut at the sides:"
                        f" {edges} edges = 3 x {cells} cells"
                    )
                pens = hpgl(path, os.path.join(out, "out.hpgl"))
                print(f"plot-check: {preset}: {said}; {len(names)} layers; HPGL {pens} pen-ups")
            except (AssertionError, subprocess.CalledProcessError) as e:
                failures += 1
                print(f"plot-check: {preset}: FAILED: {e!r}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
