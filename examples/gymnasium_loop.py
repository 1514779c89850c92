#!/usr/bin/env python3
"""Gymnasium-style loops over cmbrl's environments, as a Safety-Gymnasium user writes them: one
environment stepped by a random agent for an episode, then a vector of environments with
same-step autoreset, seeded per environment, and the violations and returns of the episodes
that ended.

    PYTHONPATH=build/python python3 examples/gymnasium_loop.py
    PYTHONPATH=build/python python3 examples/gymnasium_loop.py --env SafetyCarGoal1-v0 --steps 3000

A Safety-Gymnasium id ("SafetyPointGoal1-v0") gives that task's stock variant; a task name
("PointGoal1") the paper's.
"""
import argparse

import numpy as np

import cmbrl


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--env", default="SafetyPointGoal1-v0", help="a task or Safety-Gymnasium id")
    parser.add_argument("--num-envs", type=int, default=4)
    parser.add_argument("--steps", type=int, default=1000, help="vector steps")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    # One environment, one episode: Safety-Gymnasium's step gives the cost beside the reward.
    env = cmbrl.make(args.env)
    env.action_space.seed(args.seed)
    obs, info = env.reset(seed=args.seed)
    episode_return, episode_cost, done = 0.0, 0.0, False
    while not done:
        obs, reward, cost, terminated, truncated, info = env.step(env.action_space.sample())
        episode_return += reward
        episode_cost += cost
        done = terminated or truncated
    env.close()
    print(f"{env.spec.id}: one episode, return {episode_return:.2f}, violations "
          f"{episode_cost:.0f}")

    # A vector of them.
    envs = cmbrl.make_vec(args.env, num_envs=args.num_envs)
    envs.action_space.seed(args.seed)
    obs, _ = envs.reset(seed=[args.seed + k for k in range(args.num_envs)])
    returns, costs = np.zeros(args.num_envs), np.zeros(args.num_envs)
    ended: list[tuple[float, float]] = []  # (return, violations) of each finished episode
    for _ in range(args.steps):
        obs, rewards, step_costs, terminations, truncations, info = envs.step(
            envs.action_space.sample())
        returns += rewards
        costs += step_costs
        for k in np.flatnonzero(terminations | truncations):
            # Next-step autoreset (Gymnasium's default): obs[k] is the ended episode's last
            # observation; the next step resets environment k (its action unread, reward 0).
            ended.append((float(returns[k]), float(costs[k])))
            returns[k] = costs[k] = 0.0
    envs.close()
    print(f"{args.env} ({envs.task}, {envs.variant}): {len(ended)} episodes ended in "
          f"{args.steps} steps of {args.num_envs} environments")
    if ended:
        table = np.array(ended)
        print(f"  mean return {table[:, 0].mean():.2f}, mean violations {table[:, 1].mean():.1f}")


if __name__ == "__main__":
    main()
