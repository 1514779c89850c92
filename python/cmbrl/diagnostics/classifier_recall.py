"""How often a trained run's constraint classifier calls a hazard's inside unsafe, on layouts it
never saw: its recall inside hazards, and its false alarms near them and farther away.

States come from episodes of uniform random actions (one per agent step, the pre-training's) on
layouts reset with seed + k, none of them the run's own. Each state is sorted by the robot's
distance to the nearest hazard's centre (the simulator's): inside (within the hazard's radius,
where the cost is paid), near (up to NEAR m) or farther, the last split by whether a vase is
within NEAR m (a vase pushed too fast also costs, so its neighbourhood can be labelled unsafe);
the table gives the share of each that the classifier calls unsafe. RCE's worst case cannot see
a hazard its classifier calls safe: a robot inside one that the classifier misses has nothing
that pushes it out.

Usage:
  PYTHONPATH=build/python python3 -m cmbrl.diagnostics.classifier_recall RUN_DIR [RUN_DIR ...] \\
      [--episodes 150] [--seed 5000]
Prints a Markdown table, one row per run.
"""
import argparse
import os

import numpy as np

from cmbrl.diagnostics.runs import load_mpc_run

NEAR = 0.5  # metres from a hazard's centre: "near" ends here


def states_by_distance(env, episodes, seed):
    """Observations of random-action episodes, split into (inside, near, farther with a vase
    near, farther without) arrays."""
    rng = np.random.default_rng(seed)
    groups = ([], [], [], [])
    for k in range(episodes):
        obs, _ = env.reset(seed=seed + k)
        done = False
        while not done:
            obs, _, _, terminated, truncated, _ = env.step(
                rng.uniform(-1.0, 1.0, size=env.action_space.shape[0]))
            done = terminated or truncated
            truth = env.ground_truth()
            gap = np.hypot(*(truth["hazards"] - truth["robot_position"]).T).min()
            robot = np.asarray(truth["robot_position"])
            vases = np.asarray(truth["vases"]).reshape(-1, 3)[:, :2]
            by_vase = len(vases) > 0 and np.hypot(*(vases - robot).T).min() <= NEAR
            group = (0 if gap <= truth["hazard_radius"] else 1 if gap <= NEAR
                     else 2 if by_vase else 3)
            groups[group].append(obs)
    width = env.observation_space.shape[0]
    return tuple(np.array(g, dtype=float).reshape(-1, width) for g in groups)


def called_unsafe(predict, groups):
    """Share of each group that `predict` (states -> bools) calls unsafe (NaN for an empty
    group)."""
    return [float(np.mean(predict(g))) if len(g) else float("nan") for g in groups]


def recall(agent, groups):
    """(size, share the run's classifier calls unsafe) of each group."""
    return list(zip((len(g) for g in groups), called_unsafe(agent.predict_violation, groups)))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--episodes", type=int, default=150)
    parser.add_argument("--seed", type=int, default=5000)
    args = parser.parse_args(argv)
    if args.episodes < 1:
        parser.error(f"--episodes {args.episodes}: expected at least 1")
    print(f"Classifier verdicts on {args.episodes} random-action episodes a run (layouts of seeds "
          f"{args.seed} + k): the share of states called unsafe.\n")
    print(f"| run | task | inside a hazard (recall) | states | within {NEAR:g} m (false alarms) | "
          f"states | farther, a vase within {NEAR:g} m | states | farther, no vase | states |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for run in args.runs:
        agent = load_mpc_run(run, "classifier")
        env = agent.make_env()
        cells = recall(agent, states_by_distance(env, args.episodes, args.seed))
        env.close()
        print(f"| {os.path.basename(os.path.normpath(run))} | {agent.task} | "
              + " | ".join(f"{share:.3f} | {n}" for n, share in cells) + " |", flush=True)


if __name__ == "__main__":
    main()
