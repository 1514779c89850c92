"""Open-loop motion error of trained runs' dynamics models along their own real episodes: where
each ensemble member puts the robot 1, 4 and 8 agent steps ahead under the executed actions,
against where it went, by robot, inside or outside a hazard, speed and turning.

The models' state holds no position: the paper variant's observation gives every object in the
robot's frame (docs/ENVIRONMENTS.md). The hazards do not move, so a state's ego-frame hazard
coordinates fix the robot's pose in the world: the rigid motion that best carries them onto the
hazards' true places (least squares, `pose_from_ego`). The same fit gives the real pose from the
real observation and the predicted pose from each member's predicted state; its residual says
how far a prediction is from any rigid placement of the hazards. (The goal is not used: it jumps
when met. Vases move.)

Each episode is the run's own agent acting (its planner, its models), reset with seed + k. From
every step t with t + 8 steps still in the episode, each member rolls out its own trajectory from
the real state under the executed actions (as RCE's members do), and the table compares, per
horizon k:
  - position error: members' mean distance from the real position at t + k (m), and the
    distance of the members' mean position (how much of the error the members share);
  - heading error: members' mean absolute heading error (degrees);
  - real move / predicted move: distance from the real position at t to the real / predicted
    position at t + k (m), and their ratio: above 1, the models predict moves the robot does
    not make;
  - spread: members' mean distance from their mean position (m), the disagreement RCE's worst
    case reads; against the position error, how well it covers the error;
  - residual: RMS of the rigid fit of the predicted hazards (m).
Breakdowns (each start state t): inside a hazard or not (the robot's centre within a hazard's
radius), speed (the velocimeter's norm, m/s: below 0.1, 0.1 to 0.3, 0.3 and above), turning (the
real heading change over the k steps above TURN_RATE rad/s, or not).

Usage:
  PYTHONPATH=build/python python3 -m cmbrl.diagnostics.open_loop RUN_DIR [RUN_DIR ...] \\
      [--episodes 10] [--seed 100] [--out DIR]
Runs of one robot are pooled; the robot is the task's (CarGoal2: Car). Writes DIR/table.md and
DIR/summary.json when --out is given, and prints the table.
"""
import argparse
import os
import re

import numpy as np

from cmbrl.diagnostics.runs import load_mpc_run
from cmbrl.diagnostics.tables import write_table

HORIZONS = (1, 4, 8)
SPEED_BINS = ((0.0, 0.1), (0.1, 0.3), (0.3, float("inf")))  # m/s, of the velocimeter's norm
TURN_RATE = 0.5  # rad/s: a window whose real heading changes faster than this is "turning"


def wrap(angle):
    """Angles to (-pi, pi]."""
    return np.angle(np.exp(1j * np.asarray(angle)))


def pose_from_ego(ego, world):
    """The robot poses (x, y, yaw) that carry ego-frame points onto their world places.

    ego (..., K, 2): the points in the robot's frame, world = position + R(yaw) ego; world (K, 2).
    Returns (position (..., 2), yaw (...), residual (...): the RMS distance (m) of the fitted
    points from their world places). Needs K >= 2 distinct points."""
    ego = np.asarray(ego, dtype=float)
    world = np.asarray(world, dtype=float)
    e = ego - ego.mean(axis=-2, keepdims=True)
    w = world - world.mean(axis=-2, keepdims=True)
    cross = np.sum(e[..., 0] * w[..., 1] - e[..., 1] * w[..., 0], axis=-1)
    dot = np.sum(e[..., 0] * w[..., 0] + e[..., 1] * w[..., 1], axis=-1)
    yaw = np.arctan2(cross, dot)
    c, s = np.cos(yaw)[..., None], np.sin(yaw)[..., None]
    rotated = np.stack([c * ego[..., 0] - s * ego[..., 1], s * ego[..., 0] + c * ego[..., 1]],
                       axis=-1)  # (..., K, 2)
    position = (world - rotated).mean(axis=-2)
    residual = np.sqrt(np.mean(np.sum((rotated + position[..., None, :] - world) ** 2, axis=-1),
                               axis=-1))
    return position, yaw, residual


def hazard_slots(names):
    """Indices of the hazards' (x, y) in the observation, (K, 2)."""
    slots = [(names.index(f"hazard{i}_x"), names.index(f"hazard{i}_y"))
             for i in range(len(names)) if f"hazard{i}_x" in names]
    if len(slots) < 2:
        raise SystemExit("the open-loop fit needs an observation with two or more hazards in the "
                         f"robot's frame (hazard<i>_x, hazard<i>_y); this one has {len(slots)}")
    return np.array(slots)


def collect(agent, env, seed, plans=False):
    """One episode of the agent, reset with `seed`: observations (T + 1, S), actions (T, A),
    inside-a-hazard flags (T + 1), the hazards' world places (K, 2) and radius (m), violations;
    with `plans`, also each step's executed plan (T, H, A) as "plans"."""
    obs, _ = env.reset(seed=seed)
    agent.begin_episode()
    truth = env.ground_truth()
    hazards, radius = np.array(truth["hazards"]), truth["hazard_radius"]

    def inside():
        position = np.array(env.ground_truth()["robot_position"])
        return bool(np.hypot(*(hazards - position).T).min() <= radius)

    observations, actions, flags, violations, executed = [obs], [], [inside()], 0, []
    done = False
    while not done:
        action = agent.act(obs)
        if plans:
            executed.append(np.asarray(agent.last_plan()["actions"]))
        obs, _, cost, terminated, truncated, _ = env.step(action)
        observations.append(obs)
        actions.append(action)
        flags.append(inside())
        violations += cost > 0
        done = terminated or truncated
    episode = {"observations": np.array(observations), "actions": np.array(actions),
               "inside": np.array(flags), "hazards": hazards, "hazard_radius": radius,
               "violations": int(violations)}
    if plans:
        episode["plans"] = np.array(executed)
    return episode


def roll_out(agent, states, actions):
    """Each member's own trajectory: states (N, S) and actions (N, H, A) -> (E, N, H, S)."""
    first = agent.predict_next(states, actions[:, 0])  # (E, N, S)
    members, n = first.shape[0], states.shape[0]
    path, current = [first], first
    for h in range(1, actions.shape[1]):
        # Every member predicts from every member's state; each keeps its own (the diagonal).
        flat = current.reshape(members * n, -1)
        nxt = agent.predict_next(flat, np.tile(actions[:, h], (members, 1)))
        current = nxt.reshape(members, members, n, -1)[np.arange(members), np.arange(members)]
        path.append(current)
    return np.stack(path, axis=2)


def episode_samples(agent, episode, slots, speed_index, step_seconds):
    """Per start t and horizon k, the measures of the module's docstring (dict of arrays)."""
    obs, actions = episode["observations"], episode["actions"]
    longest = max(HORIZONS)
    starts = np.arange(len(actions) - longest + 1)
    if len(starts) == 0:
        return []
    windows = np.stack([actions[t:t + longest] for t in starts])  # (N, H, A)
    predicted = roll_out(agent, obs[starts], windows)  # (E, N, H, S)
    real_pos, real_yaw, _ = pose_from_ego(obs[:, slots], episode["hazards"])  # (T + 1, 2), (T + 1)
    speed = np.hypot(obs[starts, speed_index[0]], obs[starts, speed_index[1]])
    rows = []
    for k in HORIZONS:
        pos, yaw, residual = pose_from_ego(predicted[:, :, k - 1][..., slots], episode["hazards"])
        truth_pos, truth_yaw = real_pos[starts + k], real_yaw[starts + k]  # (N, 2), (N)
        start_pos = real_pos[starts]
        real_turn = np.abs(wrap(truth_yaw - real_yaw[starts]))
        rows.append({
            "k": k,
            "position_error": np.linalg.norm(pos - truth_pos, axis=-1).mean(axis=0),
            "mean_position_error": np.linalg.norm(pos.mean(axis=0) - truth_pos, axis=-1),
            "heading_error": np.degrees(np.abs(wrap(yaw - truth_yaw)).mean(axis=0)),
            "real_move": np.linalg.norm(truth_pos - start_pos, axis=-1),
            "predicted_move": np.linalg.norm(pos - start_pos, axis=-1).mean(axis=0),
            "spread": np.linalg.norm(pos - pos.mean(axis=0), axis=-1).mean(axis=0),
            "residual": residual.mean(axis=0),
            "inside": episode["inside"][starts],
            "speed": speed,
            "turning": real_turn / (k * step_seconds) > TURN_RATE,
        })
    return rows


def robot_of(task):
    match = re.match(r"[A-Z][a-z]+", task)
    return match.group(0) if match else task


def subsets(samples):
    """(name, mask) of every breakdown of one horizon's pooled samples."""
    yield "all", np.ones_like(samples["inside"])
    yield "inside a hazard", samples["inside"]
    yield "outside hazards", ~samples["inside"]
    for low, high in SPEED_BINS:
        label = f"speed {low:g}-{high:g} m/s" if np.isfinite(high) else f"speed >= {low:g} m/s"
        yield label, (samples["speed"] >= low) & (samples["speed"] < high)
    yield "turning", samples["turning"]
    yield "not turning", ~samples["turning"]


def summarise(samples, mask):
    n = int(mask.sum())
    if n == 0:
        return {"samples": 0}
    mean = lambda key: float(samples[key][mask].mean())
    real, predicted = mean("real_move"), mean("predicted_move")
    return {"samples": n, "position_error": mean("position_error"),
            "position_error_median": float(np.median(samples["position_error"][mask])),
            "mean_position_error": mean("mean_position_error"),
            "heading_error": mean("heading_error"), "real_move": real,
            "predicted_move": predicted, "move_ratio": predicted / real if real > 0 else None,
            "spread": mean("spread"), "residual": mean("residual")}


def pooled(rows_per_episode, k):
    rows = [row for rows in rows_per_episode for row in rows if row["k"] == k]
    return {key: np.concatenate([row[key] for row in rows]) for key in rows[0] if key != "k"}


def study(runs, episodes, seed):
    """{robot: {"runs", "episodes", "violations", "steps", "by_k": {k: [(subset, summary)]}}}."""
    per_robot = {}
    for run in runs:
        agent = load_mpc_run(run, "dynamics models to judge", seed=seed)
        env = agent.make_env()
        names = env.observation_names
        slots = hazard_slots(names)
        speed_index = (names.index("velocimeter_x"), names.index("velocimeter_y"))
        entry = per_robot.setdefault(robot_of(agent.task),
                                     {"runs": [], "rows": [], "violations": [], "steps": 0})
        entry["runs"].append(os.path.basename(os.path.normpath(run)))
        for e in range(episodes):
            episode = collect(agent, env, seed + e)
            entry["violations"].append(episode["violations"])
            entry["steps"] += len(episode["actions"])
            rows = episode_samples(agent, episode, slots, speed_index, env.agent_step_seconds)
            if rows:
                entry["rows"].append(rows)
        env.close()
    result = {}
    for robot, entry in per_robot.items():
        by_k = {}
        for k in HORIZONS:
            samples = pooled(entry["rows"], k)
            by_k[k] = [(name, summarise(samples, mask)) for name, mask in subsets(samples)]
        result[robot] = {"runs": entry["runs"], "episodes": len(entry["violations"]),
                         "violations": entry["violations"], "steps": entry["steps"],
                         "by_k": by_k}
    return result


def table(result, episodes, seed):
    fmt = lambda v, spec: "-" if v is None else format(v, spec)
    lines = []
    for robot, entry in result.items():
        lines.append(f"**{robot}**: runs {', '.join(entry['runs'])}; {entry['episodes']} "
                     f"episodes ({episodes} a run, reset with seed {seed} + k), {entry['steps']} "
                     f"steps; violations per episode {entry['violations']}.\n")
    lines.append("| robot | k | start states | samples | position error (m), mean | median | "
                 "members' mean's error (m) | heading error (deg) | real move (m) | predicted move "
                 "(m) | predicted / real | spread (m) | fit residual (m) |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for robot, entry in result.items():
        for k in HORIZONS:
            for name, s in entry["by_k"][k]:
                if s["samples"] == 0:
                    lines.append(f"| {robot} | {k} | {name} | 0 |" + " - |" * 9)
                    continue
                lines.append(
                    f"| {robot} | {k} | {name} | {s['samples']} | {s['position_error']:.3f} | "
                    f"{s['position_error_median']:.3f} | {s['mean_position_error']:.3f} | "
                    f"{s['heading_error']:.1f} | "
                    f"{s['real_move']:.3f} | {s['predicted_move']:.3f} | "
                    f"{fmt(s['move_ratio'], '.2f')} | {s['spread']:.3f} | {s['residual']:.3f} |")
    return "\n".join(lines) + "\n"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--episodes", type=int, default=10)
    parser.add_argument("--seed", type=int, default=100)
    parser.add_argument("--out", help="folder for table.md and summary.json")
    args = parser.parse_args(argv)
    if args.episodes < 1:
        parser.error(f"--episodes {args.episodes}: expected at least 1")
    result = study(args.runs, args.episodes, args.seed)
    text = table(result, args.episodes, args.seed)
    if args.out:
        write_table(args.out, text, result)
    print(text)


if __name__ == "__main__":
    main()
