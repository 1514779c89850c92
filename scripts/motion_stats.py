"""Shared by gif-robot-speed.py and agent-step-displacement.py: how a robot's floor positions,
one per agent step, move and turn."""
import numpy as np


def circumradius(a, b, c):
    """Radius of the circle through three floor points (inf when they are in line)."""
    ab, bc, ca = np.linalg.norm(b - a), np.linalg.norm(c - b), np.linalg.norm(a - c)
    cross = abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
    return np.inf if cross < 1e-12 else ab * bc * ca / (2 * cross)


def summary(tracks, reset=np.inf, turning_move=0.15):
    """One line on a list of tracks (arrays of floor positions, one row per agent step):
    displacement quantiles per agent step, moves of `reset` metres or more dropped as episode
    resets; and the turns, percentiles (5th to 50th) of the radius through three
    consecutive positions whose two moves are at least `turning_move` metres (slower moves
    leave the radius to position noise); and how often the robot reverses its direction of
    travel between two agent steps."""
    moves, radii, turns_back = [], [], []
    for track in tracks:
        delta = np.diff(track, axis=0)
        step = np.linalg.norm(delta, axis=1)
        moves += list(step[step < reset])
        for i in range(1, len(delta)):
            shorter, longer = sorted((step[i - 1], step[i]))
            if longer >= reset:
                continue
            # Direction reversals: consecutive moves of 5 cm or more at more than 120 degrees.
            if shorter >= 0.05:
                cosine = delta[i - 1] @ delta[i] / (step[i - 1] * step[i])
                turns_back.append(cosine < -0.5)
            if shorter >= turning_move:
                radii.append(circumradius(track[i - 1], track[i], track[i + 1]))
    q = np.percentile(moves, [25, 50, 75, 90, 95, 99])
    r = np.percentile(radii, [5, 10, 25, 50])
    return (f"{len(moves)} agent steps; metres per agent step: p25 {q[0]:.3f}, median "
            f"{q[1]:.3f}, p75 {q[2]:.3f}, p90 {q[3]:.3f}, p95 {q[4]:.3f}, p99 {q[5]:.3f}, mean "
            f"{np.mean(moves):.3f}; turning radius at moves >= {turning_move} m: p5 {r[0]:.2f}, "
            f"p10 {r[1]:.2f}, p25 {r[2]:.2f}, median {r[3]:.2f} m ({len(radii)} turns); "
            f"direction reversed at {np.mean(turns_back):.3f} of consecutive moves")
