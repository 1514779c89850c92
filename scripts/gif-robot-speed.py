#!/usr/bin/python3
"""How far a robot moves per agent step in a recorded Safety Gym GIF (issue 12, cause 7).

The original's repository shows its agents in screen recordings (media/*.gif): a free camera
over the checkered floor, the scene redrawn once per agent step (run.py renders after every
wrapper step) and recorded at a fixed rate, so each redraw spans a few identical frames. This
script turns such a recording into the robot's displacement per agent step, in metres:

  - Floor calibration from the checker itself: the floor is 7 m wide with 10 texture repeats of
    a 2 x 2 checker (Safety Gym's world.py), so cell edges lie every 0.35 m. Along image rows the
    cell edges give pixels per metre across the view, s(r) = k (r - r_h), with r_h the horizon
    row; down the image they give the depth Y(r) = c0 + c1 / (r - r_h) of a floor row.
  - The robot is the only saturated red object: its centroid in each redraw, mapped to the
    floor, is its position at one agent step (motion_stats.py: displacements, tightest turns).
    Jumps of more than --reset metres are episode resets and dropped.
Run it on the Point's recording as a control, and compare with our agents' displacements from
scripts/agent-step-displacement.py (results/ablation-level2/README.md).

Usage (Debian's python3 with python3-numpy and python3-pil, not dependencies of cmbrl):
  scripts/gif-robot-speed.py cg1_random.gif [--reset 0.8]
Prints the calibration, the redraw regularity and motion_stats.summary of the track.
"""
import argparse

import numpy as np
from PIL import Image, ImageSequence

import motion_stats

CELL = 0.35  # metres: 7 m floor, 10 texture repeats, 2 cells per repeat


def load(path):
    with Image.open(path) as gif:
        return np.stack([np.asarray(frame.convert("RGB")) for frame in ImageSequence.Iterator(gif)])


def edges(profile):
    """Positions (fractional) where a 0/1 profile crosses 0.5."""
    s = profile - 0.5
    idx = np.flatnonzero(np.sign(s[:-1]) * np.sign(s[1:]) < 0)
    return idx + s[idx] / (s[idx] - s[idx + 1])


def smooth(a, k):
    kernel = np.ones(k) / k
    return np.apply_along_axis(lambda v: np.convolve(v, kernel, mode="same"), 0, a)


def calibrate(frames):
    """k, r_h and c1 of the floor mapping, from the median frame's checker."""
    f = np.median(frames[:: max(1, len(frames) // 15)], axis=0).astype(int)
    floor = (f[:, :, 0] == f[:, :, 1]) & (f[:, :, 0] >= 140) & (f[:, :, 2] >= 170)
    # The darker cells are drawn solid, the lighter ones dithered: the dark-cell fraction,
    # smoothed over the dithering, is a clean square wave over the floor.
    dark = (f[:, :, 0] == 180) & (f[:, :, 1] == 180) & (f[:, :, 2] == 170)
    frac = smooth(smooth(dark.astype(float), 5).T, 5).T
    height, width = floor.shape
    rows, scales = [], []
    for r in range(0, height, 4):
        cols = np.flatnonzero(floor[r])
        if len(cols) < width // 3:
            continue
        e = edges(frac[r, cols.min():cols.max()])
        gaps = np.diff(e)
        gaps = gaps[(gaps > 4)]
        if len(gaps) >= 4:
            rows.append(r)
            scales.append(np.median(gaps) / CELL)
    k, b = np.polyfit(rows, scales, 1)
    horizon = -b / k
    # Depth: on a floor seen from above, Y(r) = c0 + c1 / (r - r_h), so a cell spans
    # CELL (r - r_h)^2 / c1 rows at row r. Each gap between cell edges down a column estimates
    # c1; the median over all columns ignores the gaps that objects and dithering split.
    estimates = []
    for c in range(0, width, 3):
        cells = np.flatnonzero(floor[:, c])
        if len(cells) < height // 3:
            continue
        e = edges(frac[cells.min():cells.max(), c]) + cells.min()
        gaps = np.diff(e)
        mid = (e[1:] + e[:-1]) / 2
        keep = gaps > 4
        estimates += list(CELL * (mid[keep] - horizon) ** 2 / gaps[keep])
    c1 = float(np.median(estimates))
    spread = np.percentile(estimates, 75) / np.percentile(estimates, 25)
    return k, horizon, c1, len(rows), len(estimates), spread


def track(frames):
    """(frame, column, row) of the red robot's centroid at each redraw."""
    redraws, last = [], None
    for i, f in enumerate(frames):
        red = (f[:, :, 0] >= 72) & (f[:, :, 1] == 0) & (f[:, :, 2] == 0)
        ys, xs = np.nonzero(red)
        if len(xs) < 20:
            continue
        c = (xs.mean(), ys.mean())
        if last is None or abs(c[0] - last[0]) + abs(c[1] - last[1]) > 0.3:
            redraws.append((i, *c))
            last = c
    return np.array(redraws)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("gif")
    parser.add_argument("--reset", type=float, default=0.8,
                        help="a jump longer than this (m) is an episode reset, dropped")
    args = parser.parse_args()
    frames = load(args.gif)
    k, horizon, c1, nrows, ngaps, spread = calibrate(frames)
    redraws = track(frames)
    col, row = redraws[:, 1], redraws[:, 2]
    # The camera looks along the floor's y axis with its principal point at the image centre
    # (the floor's side edges meet there in the original's recordings), so a floor point's x is
    # its column's offset from the centre over the row's scale.
    positions = np.stack([(col - frames.shape[2] / 2) / (k * (row - horizon)),
                          c1 / (row - horizon)], axis=1)
    print(f"{args.gif}: {len(frames)} frames, {len(redraws)} redraws; floor: {k:.4f} px/m per row "
          f"below the horizon at row {horizon:.1f} ({nrows} rows); depth from {ngaps} cell "
          f"heights (interquartile ratio {spread:.2f})")
    # A steady recording redraws every few frames; a gap twice the usual one means a missed
    # redraw (two agent steps merged into one move), so the quantiles would be too high.
    gaps = np.bincount(np.diff(redraws[:, 0]).astype(int))
    print("frames between redraws (count by gap): " +
          ", ".join(f"{g}: {n}" for g, n in enumerate(gaps) if n))
    print(motion_stats.summary([positions], reset=args.reset))


if __name__ == "__main__":
    main()
