"""The shrinkwrap's peer in scripts/bench.sh: scikit-image's marching cubes
on the field Morphogen wraps, at as many triangles as Morphogen's mesh.

For every frame of a bone stream (`morphogen decode` of, say,
fixtures/bone-growth/stream.bin), the skeleton's distinct vertices (the
ends of its segments) give the paper's field V(r) = Σ u_i² / Σ u_i with
u_i = 1/|r − R_i| (bones paper, eqs. (1)–(2) in (6)); it is sampled on a
grid and `skimage.measure.marching_cubes` extracts the level V0.

    python marching_cubes.py calibrate DECODED.jsonl SPACINGS.json [V0]
    python marching_cubes.py run DECODED.jsonl SPACINGS.json STAGE

`calibrate` finds, per frame, the grid spacing whose surface has as many
triangles as the frame's mesh in the stream, and prints the totals and the
worst |V − V0| / V0 at the surface's vertices and at the stream's mesh
vertices, both in f64. `run` does the work up to
STAGE (`read`, `field`: the grids sampled, `cubes`: the surfaces too), so
that instruction counts of two stages differ by that stage's work alone.
"""

import json
import sys

import numpy as np
from skimage.measure import marching_cubes

LEAST = 1.0 / 4096  # a distance counts as at least 2⁻¹², as in Morphogen
MARGIN = 2.0  # beyond the skeleton's box: the level 0.8 lies within 1.25


def frames(path):
    """Per frame: the skeleton's distinct vertices, the mesh's triangles
    and its vertices."""
    out = []
    with open(path) as f:
        for line in f:
            r = json.loads(line)
            kind = r["kind"]
            if kind == "frame_start":
                vertices, seen, triangles, mesh = [], set(), 0, []
            elif kind == "segment":
                for p in (tuple(r["a"]), tuple(r["b"])):
                    if p not in seen:
                        seen.add(p)
                        vertices.append(p)
            elif kind == "mesh_vertex":
                mesh.append(r["p"])
            elif kind == "triangle":
                triangles += 1
            elif kind == "frame_end":
                out.append((np.array(vertices), triangles, np.array(mesh)))
    return out


def field(vertices, points):
    """V at each of `points` (n × 3)."""
    d = np.linalg.norm(points[:, None, :] - vertices[None, :, :], axis=2)
    u = 1.0 / np.maximum(d, LEAST)
    return (u * u).sum(axis=1) / u.sum(axis=1)


def grid(vertices, h):
    """The sampled field on a grid of spacing h around the skeleton, and
    the grid's origin."""
    low = vertices.min(axis=0) - MARGIN
    high = vertices.max(axis=0) + MARGIN
    axes = [np.arange(low[k], high[k] + h, h) for k in range(3)]
    x, y, z = np.meshgrid(*axes, indexing="ij")
    points = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    return field(vertices, points).reshape(x.shape), low


def cubes(volume, h, level):
    return marching_cubes(volume, level=level, spacing=(h, h, h))


def level_error(vertices, points, level):
    """The largest |V − V0| / V0 at `points`."""
    return float((np.abs(field(vertices, points) - level) / level).max())


def calibrate(decoded, spacings_path, level):
    spacings, found, wanted, worst, worst_mesh = [], 0, 0, 0.0, 0.0
    for vertices, triangles, mesh in frames(decoded):
        # Triangles fall as the spacing grows: bisect its logarithm.
        lo, hi = np.log(0.01), np.log(2.0)
        best = None
        for _ in range(24):
            h = float(np.exp((lo + hi) / 2))
            volume, origin = grid(vertices, h)
            verts, faces, _, _ = cubes(volume, h, level)
            if best is None or abs(len(faces) - triangles) < abs(best[1] - triangles):
                best = (h, len(faces), verts + origin)
            if len(faces) == triangles:
                break
            if len(faces) > triangles:
                lo = np.log(h)
            else:
                hi = np.log(h)
        h, count, verts = best
        spacings.append(h)
        found += count
        wanted += triangles
        worst = max(worst, level_error(vertices, verts, level))
        worst_mesh = max(worst_mesh, level_error(vertices, mesh, level))
    with open(spacings_path, "w") as f:
        json.dump({"level": level, "spacings": spacings}, f)
    print(
        f"{found} triangles for the stream's {wanted}, V off V0 by at most "
        f"{100 * worst:.2f} % at their vertices (at the stream's mesh vertices: "
        f"{100 * worst_mesh:.2f} %)"
    )


def run(decoded, spacings_path, stage):
    with open(spacings_path) as f:
        setting = json.load(f)
    count = 0
    for (vertices, _, _), h in zip(frames(decoded), setting["spacings"]):
        if stage == "read":
            continue
        volume, _ = grid(vertices, h)
        if stage == "cubes":
            _, faces, _, _ = cubes(volume, h, setting["level"])
            count += len(faces)
    print(f"{stage}: {count} triangles")


def main():
    if len(sys.argv) >= 4 and sys.argv[1] == "calibrate":
        level = float(sys.argv[4]) if len(sys.argv) > 4 else 0.8
        calibrate(sys.argv[2], sys.argv[3], level)
    elif len(sys.argv) == 5 and sys.argv[1] == "run" and sys.argv[4] in ("read", "field", "cubes"):
        run(sys.argv[2], sys.argv[3], sys.argv[4])
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
