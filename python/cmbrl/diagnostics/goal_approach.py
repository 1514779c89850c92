"""How well each run's final models predict the robot's approach to the goal: the one-step
error of the goal's ego-frame position, and of the whole state, near the goal and away from it,
on one set of transitions that all runs are judged on.

The transitions come from one run's agent (--collector, default the first run) acting for
--episodes episodes on layouts reset with seed + k. Steps that met a goal are left out: the goal
then jumps to a new place, which no model can predict (they are in every run's training data).

Usage:
  PYTHONPATH=build/python python3 -m cmbrl.diagnostics.goal_approach RUN_DIR [RUN_DIR ...] \\
      [--collector RUN_DIR] [--episodes 4] [--seed 100] [--near 1.0]

Prints a Markdown table: one row per run.
"""
import argparse
import os

import numpy as np

import cmbrl


def collect(run, episodes, seed):
    """(states, actions, next_states, goal_met) of `episodes` episodes of run's agent."""
    agent = cmbrl.load_run(run, seed=seed)
    env = agent.make_env()
    states, actions, next_states, met = [], [], [], []
    for k in range(episodes):
        obs, _ = env.reset(seed=seed + k)
        agent.begin_episode()
        done = False
        while not done:
            action = agent.act(obs)
            nxt, _, _, terminated, truncated, info = env.step(action)
            states.append(obs)
            actions.append(action)
            next_states.append(nxt)
            met.append(info["goal_met"])
            obs, done = nxt, terminated or truncated
    goal = env.observation_names.index("goal_x")
    env.close()
    return np.array(states), np.array(actions), np.array(next_states), np.array(met), goal


def errors(run, states, actions, next_states, goal):
    """Per transition: the members' mean prediction's goal-position error (m) and state MSE."""
    predicted = cmbrl.load_run(run).predict_next(states, actions).mean(axis=0)  # (N, S)
    goal_error = np.hypot(predicted[:, goal] - next_states[:, goal],
                          predicted[:, goal + 1] - next_states[:, goal + 1])
    return goal_error, np.mean((predicted - next_states) ** 2, axis=1)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--collector", help="the run whose agent acts (default: the first)")
    parser.add_argument("--episodes", type=int, default=4)
    parser.add_argument("--seed", type=int, default=100)
    parser.add_argument("--near", type=float, default=1.0, help="metres: near the goal")
    args = parser.parse_args(argv)
    collector = args.collector or args.runs[0]
    states, actions, next_states, met, goal = collect(collector, args.episodes, args.seed)
    distance = np.hypot(states[:, goal], states[:, goal + 1])
    near = (distance < args.near) & ~met
    far = (distance >= args.near) & ~met
    print(f"{len(states)} transitions of {os.path.basename(os.path.normpath(collector))}'s agent "
          f"({args.episodes} episodes, seeds {args.seed} + k): {int(met.sum())} met a goal (left "
          f"out), {int(near.sum())} began within {args.near:g} m of the goal, {int(far.sum())} "
          "farther.\n")
    print(f"| run (whose models) | goal position error near (m) | far (m) | state MSE near | far |")
    print("|---|---|---|---|---|")
    for run in args.runs:
        goal_error, mse = errors(run, states, actions, next_states, goal)
        mean = lambda values, mask: float(values[mask].mean()) if mask.any() else float("nan")
        print(f"| {os.path.basename(os.path.normpath(run))} | {mean(goal_error, near):.4f} | "
              f"{mean(goal_error, far):.4f} | {mean(mse, near):.5f} | {mean(mse, far):.5f} |")


if __name__ == "__main__":
    main()
