#!/usr/bin/python3
"""The environments under a uniform random policy: violations, speeds and goals per 100 agent
steps, for each task and spawn. A check of the simulation that needs no learning, e.g. whether
spawning the rover as the original did (model-origin: wheels in the floor) changes what random
pre-training sees.

Usage (Debian's python3, with python3-numpy):
  PYTHONPATH=build/python scripts/random-policy-stats.py [--tasks CarGoal1 CarGoal2]
      [--spawns standing model-origin] [--episodes 150] [--seed 1000]
"""
import argparse

import numpy as np

import cmbrl


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--tasks", nargs="+", default=["CarGoal1", "CarGoal2"])
    parser.add_argument("--spawns", nargs="+", default=["standing", "model-origin"])
    parser.add_argument("--episodes", type=int, default=150)
    parser.add_argument("--seed", type=int, default=1000)
    args = parser.parse_args()

    print(f"Uniform random actions, {args.episodes} episodes per row (environment seeds "
          f"{args.seed} on, actions from numpy seed 0).\n")
    print("| task | spawn | violations per 100 steps | median speed (m/s) | 90th percentile | "
          "mean speed over each episode's first 3 steps | goals per 100 steps |")
    print("|---|---|---|---|---|---|---|")
    for task in args.tasks:
        for spawn in args.spawns:
            env = cmbrl.make(task, spawn=spawn)
            rng = np.random.default_rng(0)
            low, high = env.action_space.low, env.action_space.high
            steps = violations = goals = 0
            speeds, first = [], []
            for k in range(args.episodes):
                obs, _ = env.reset(seed=args.seed + k)
                done, t = False, 0
                while not done:
                    obs, _, cost, terminated, truncated, info = env.step(rng.uniform(low, high))
                    done = terminated or truncated
                    speed = float(np.hypot(obs[0], obs[1]))  # velocimeter x, y (facts B1)
                    speeds.append(speed)
                    if t < 3:
                        first.append(speed)
                    steps += 1
                    t += 1
                    violations += cost > 0
                    goals += bool(info.get("goal_met"))
            print(f"| {task} | {spawn} | {100 * violations / steps:.2f} | "
                  f"{np.median(speeds):.3f} | {np.percentile(speeds, 90):.3f} | "
                  f"{np.mean(first):.3f} | {100 * goals / steps:.2f} |")


if __name__ == "__main__":
    main()
