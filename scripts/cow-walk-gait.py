#!/usr/bin/env python3
"""Derives the cow-walk gait table (scenarios/cow-walk.toml) from measured
keypoints of walking dairy cows.

Source data: the 272 keypoint trajectories published with
  H. Russello, R. van der Tol, E. J. van Henten, G. Kootstra (2026),
  "Lameness detection in dairy cows using pose estimation and bidirectional
  LSTMs", Smart Agricultural Technology 101831,
  https://doi.org/10.1016/j.atech.2026.101831,
  data: https://github.com/hrussel/lstm-lameness-detection, folder data/
  (commit c9e2f6d558912589220d91de985a79851d6e2c97):
  data/videos_keypoints/NNN.csv (one side-view video each, pixel
  coordinates per frame, extracted with T-LEAP: Russello, van der Tol,
  Kootstra 2022, Computers and Electronics in Agriculture 192, 106559) and
  data/videos_lameness_scores.csv (the hard-vote locomotion score of each
  video: Russello et al. 2024, Computers and Electronics in Agriculture
  223, 109040).

Per leg the data has three keypoints -- Hoof, Ankle (fetlock) and Knee
(carpus on the fore leg, tarsus/hock on the hind leg) -- and the back has
Spine1 (front) and Spine2 (rear). So two segments of each leg are measured:
the cannon (Knee -> Ankle) and the pastern (Ankle -> Hoof). The forearm and
gaskin (elbow, stifle) are not in the data.

Derivation, all of it in this script (python3, standard library only):
 1. Videos with score 1 (sound) only.
 2. Trunk axis u = Spine2 -> Spine1 (rear to front), in the image plane;
    "down" d = the perpendicular of u pointing to the image bottom. The
    inclination of a segment vector v is atan2(v.u, v.d) in degrees:
    0 = perpendicular to the back, positive = its lower end forward.
 3. Per frame and leg: cannon = inclination(Ankle - Knee);
    fetlock = inclination(Hoof - Ankle) - cannon (the pastern's bend from
    the cannon's line, positive = hoof forward).
 4. Hoof contact: the hoof x (3-frame median) moves less than STILL_PX
    pixels per frame for at least STILL_FRAMES frames; the first such frame
    is the contact. A stride is one contact to the next of the same hoof,
    kept when it lasts MIN_STRIDE..MAX_STRIDE frames.
 5. Each stride's cannon and fetlock series are sampled at SAMPLES equal
    phases from its contact (linear interpolation between frames), and the
    samples are averaged over all kept strides of the fore legs (LF, RF)
    and of the hind legs (LH, RH).
 6. Phase of each hoof's contact within the left-fore stride (LF contact to
    next LF contact), averaged over all LF strides: the 4-beat walk's limb
    phases.
 7. The model's bends are measured from its rest pose (core/src/body/
    quadruped.rs, the cow at 36 months): the trunk axis is horizontal, the
    cannons are perpendicular to it, the fore pastern points 12.9 degrees
    (atan(31/135)) and the hind pastern 11.7 degrees (atan(28/135)) forward
    of its cannon. So cannon bend = cannon, pastern bend = fetlock - rest;
    the forearm and gaskin have no channel and keep their rest pose, so the
    cannon's bend about the knee/hock gives the cannon its measured
    inclination to the back. Rounded to whole degrees (half away from 0).
 8. shift = (SAMPLES - round(phase * SAMPLES)) mod SAMPLES, so that each leg
    reaches its contact sample at its measured phase of the stride.

Usage: scripts/cow-walk-gait.py DATA_DIR   (DATA_DIR holds videos_keypoints/
and videos_lameness_scores.csv); prints the numbers and the TOML channels.
"""

import csv
import math
import os
import statistics
import sys

SAMPLES = 12
STILL_PX = 6.0
STILL_FRAMES = 5
MIN_STRIDE = 20
MAX_STRIDE = 60
LEGS = ["LF", "RF", "LH", "RH"]
REST_PASTERN = {"F": math.degrees(math.atan2(31, 135)), "H": math.degrees(math.atan2(28, 135))}
CYLINDER = {"F": ("fore", "cannon", "pastern"), "H": ("hind", "cannon", "pastern")}


def whole(v):
    """Rounds half away from zero (as Rust's f64::round, which the test uses)."""
    return int(math.copysign(math.floor(abs(v) + 0.5), v))


def inclination(v, u, d):
    return math.degrees(math.atan2(v[0] * u[0] + v[1] * u[1], v[0] * d[0] + v[1] * d[1]))


def frames_of(path):
    rows = list(csv.DictReader(open(path, newline="")))
    rows.sort(key=lambda r: int(r["frame"]))
    return rows


def point(r, name):
    return (float(r[name + "_x"]), float(r[name + "_y"]))


def angles(r, leg):
    s1, s2 = point(r, "Spine1"), point(r, "Spine2")
    u = (s1[0] - s2[0], s1[1] - s2[1])
    n = math.hypot(*u)
    u = (u[0] / n, u[1] / n)
    d = (-u[1], u[0]) if u[0] >= 0 else (u[1], -u[0])
    if d[1] < 0:
        d = (-d[0], -d[1])
    hoof, ankle, knee = point(r, leg + "Hoof"), point(r, leg + "Ankle"), point(r, leg + "Knee")
    cannon = inclination((ankle[0] - knee[0], ankle[1] - knee[1]), u, d)
    pastern = inclination((hoof[0] - ankle[0], hoof[1] - ankle[1]), u, d)
    fetlock = (pastern - cannon + 180.0) % 360.0 - 180.0
    return cannon, fetlock


def contacts(xs):
    med = [statistics.median(xs[max(0, i - 1): i + 2]) for i in range(len(xs))]
    still = [abs(med[i + 1] - med[i]) < STILL_PX for i in range(len(med) - 1)] + [False]
    found, run = [], 0
    for i, s in enumerate(still):
        run = run + 1 if s else 0
        if run == STILL_FRAMES:
            found.append(i - STILL_FRAMES + 1)
    return found


def sample(series, start, end):
    out = []
    for k in range(SAMPLES):
        t = start + (end - start) * k / SAMPLES
        i = int(math.floor(t))
        f = t - i
        a, b = series[i], series[min(i + 1, end)]
        out.append(a + (b - a) * f)
    return out


def main(data_dir):
    scores = {r["Video"]: int(r["hard_vote"]) for r in csv.DictReader(open(os.path.join(data_dir, "videos_lameness_scores.csv")))}
    sums = {"F": [[0.0] * SAMPLES, [0.0] * SAMPLES, 0], "H": [[0.0] * SAMPLES, [0.0] * SAMPLES, 0]}
    phases = {leg: [] for leg in LEGS}
    videos = 0
    durations = []
    for video in sorted(scores):
        if scores[video] != 1:
            continue
        rows = frames_of(os.path.join(data_dir, "videos_keypoints", video + ".csv"))
        numbers = [int(r["frame"]) for r in rows]
        if numbers != list(range(numbers[0], numbers[0] + len(numbers))):
            continue  # a gap in the frames: skipped
        videos += 1
        cont = {leg: contacts([point(r, leg + "Hoof")[0] for r in rows]) for leg in LEGS}
        for leg in LEGS:
            end = leg[1]
            series = [angles(r, leg) for r in rows]
            cannon = [a[0] for a in series]
            fetlock = [a[1] for a in series]
            for a, b in zip(cont[leg], cont[leg][1:]):
                if not MIN_STRIDE <= b - a <= MAX_STRIDE:
                    continue
                durations.append(b - a)
                for k, v in enumerate(sample(cannon, a, b)):
                    sums[end][0][k] += v
                for k, v in enumerate(sample(fetlock, a, b)):
                    sums[end][1][k] += v
                sums[end][2] += 1
        for a, b in zip(cont["LF"], cont["LF"][1:]):
            if not MIN_STRIDE <= b - a <= MAX_STRIDE:
                continue
            for leg in LEGS:
                hits = [c for c in cont[leg] if a <= c < b]
                if len(hits) == 1:
                    phases[leg].append((hits[0] - a) / (b - a))

    print(f"sound videos used: {videos}; strides: fore {sums['F'][2]}, hind {sums['H'][2]}; "
          f"stride {statistics.mean(durations):.1f} frames (median {statistics.median(durations)})")
    shifts = {}
    for leg in LEGS:
        p = statistics.mean(phases[leg])
        shifts[leg] = (SAMPLES - whole(p * SAMPLES)) % SAMPLES
        print(f"{leg} contact at {p:.3f} of the LF stride (n={len(phases[leg])}, sd {statistics.pstdev(phases[leg]):.3f}) -> shift {shifts[leg]}")
    table = {}
    for end in "FH":
        n = sums[end][2]
        cannon = [v / n for v in sums[end][0]]
        fetlock = [v / n for v in sums[end][1]]
        print(f"{end} cannon inclination (deg): " + " ".join(f"{v:.2f}" for v in cannon))
        print(f"{end} fetlock bend from the cannon's line (deg): " + " ".join(f"{v:.2f}" for v in fetlock))
        table[end] = ([whole(v) for v in cannon], [whole(v - REST_PASTERN[end]) for v in fetlock])
    print()
    for leg in LEGS:
        side = "l" if leg[0] == "L" else "r"
        end = leg[1]
        limb = CYLINDER[end][0]
        for name, degrees in zip(CYLINDER[end][1:], table[end]):
            print("[[body.gait.channels]]")
            print(f'cylinder = "{side}-{limb}-{name}"')
            print(f"shift = {shifts[leg]}")
            print("degrees = [" + ", ".join(str(v) for v in degrees) + "]")
            print()


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
