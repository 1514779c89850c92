#!/usr/bin/python3
"""How far a trained run's robot moves and how tightly it turns per agent step.

The counterpart of scripts/gif-robot-speed.py for our own agents: plays episodes of a run
(cmbrl.load_run, optionally with another planner) and prints motion_stats.summary of the
robot's positions from the simulator's ground truth.

Usage (Debian's python3, with python3-numpy):
  PYTHONPATH=build/python scripts/agent-step-displacement.py RUN_DIR [--planner random]
      [--episodes 3] [--seed 11]
Episode k is reset with seed + k.
"""
import argparse

import numpy as np

import cmbrl
import motion_stats


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("run")
    parser.add_argument("--planner", help="plan with this planner instead of the run's")
    parser.add_argument("--episodes", type=int, default=3)
    parser.add_argument("--seed", type=int, default=11)
    args = parser.parse_args()

    overrides = [f"planner={args.planner}"] if args.planner else []
    agent = cmbrl.load_run(args.run, seed=args.seed, overrides=overrides)
    env = agent.make_env()
    tracks = []
    for k in range(args.episodes):
        obs, _ = env.reset(seed=args.seed + k)
        agent.begin_episode()
        track = [env.ground_truth()["robot_position"][:2]]
        done = False
        while not done:
            obs, _, _, terminated, truncated, _ = env.step(agent.act(obs))
            done = terminated or truncated
            track.append(env.ground_truth()["robot_position"][:2])
        tracks.append(np.array(track))
    print(f"{args.run} ({agent.task}, planner {args.planner or 'of the run'}): "
          + motion_stats.summary(tracks))


if __name__ == "__main__":
    main()
