"""Steps per second from Python against the C++ figure, in one process:

    python3 -m cmbrl.bench [--tasks PointGoal1 ...] [--variant paper] [--steps 3000] [--runs 5]

For each task, three figures, medians of the runs, one JSON line each:
- `cmbrl bench env`'s own loop in C++ (random actions, resets included);
- one environment stepped from Python (cmbrl.make; actions drawn beforehand, resets included),
  with its ratio to the C++ figure;
- a vector of --num-envs environments (cmbrl.make_vec, one thread each), agent steps of all of
  them per second, with its ratio to the single environment from Python.
"""
import argparse
import json
import statistics
import time

import numpy as np

import cmbrl
from . import _cmbrl


def single_env_rate(task, variant, steps, seed):
    env = cmbrl.make(task, variant=variant)
    actions = np.random.default_rng(seed).uniform(
        env.action_space.low, env.action_space.high, size=(steps,) + env.action_space.shape)
    env.reset(seed=seed)
    start = time.perf_counter()
    for t in range(steps):
        _, _, _, terminated, truncated, _ = env.step(actions[t])
        if terminated or truncated:
            env.reset()
    return steps / (time.perf_counter() - start)


def vector_rate(task, variant, steps, seed, num_envs):
    envs = cmbrl.make_vec(task, num_envs=num_envs, variant=variant, threads=num_envs)
    rounds = max(1, steps // num_envs)
    actions = np.random.default_rng(seed).uniform(
        envs.single_action_space.low, envs.single_action_space.high,
        size=(rounds, num_envs) + envs.single_action_space.shape)
    envs.reset(seed=seed)
    start = time.perf_counter()
    for t in range(rounds):
        envs.step(actions[t])
    return rounds * num_envs / (time.perf_counter() - start)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--tasks", nargs="+", default=["PointGoal1"])
    parser.add_argument("--variant", default="paper")
    parser.add_argument("--steps", type=int, default=3000, help="agent steps per run")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--num-envs", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    for task in args.tasks:
        cpp = json.loads(_cmbrl.bench_env(task, args.variant, args.steps, args.runs, args.seed))
        cpp_rate = cpp["agent_steps_per_second"]
        print(json.dumps({"bench": "env", "from": "c++", "task": task, "variant": args.variant,
                          "agent_steps_per_second": cpp_rate,
                          "ratio_to_ceiling": cpp["ratio_to_ceiling"]}), flush=True)
        single = statistics.median(
            single_env_rate(task, args.variant, args.steps, args.seed + r) for r in range(args.runs))
        print(json.dumps({"bench": "env", "from": "python", "task": task,
                          "variant": args.variant, "agent_steps_per_second": single,
                          "ratio_to_cpp": single / cpp_rate}), flush=True)
        vector = statistics.median(
            vector_rate(task, args.variant, args.steps, args.seed + r, args.num_envs)
            for r in range(args.runs))
        print(json.dumps({"bench": "env", "from": "python-vector", "task": task,
                          "variant": args.variant, "num_envs": args.num_envs,
                          "agent_steps_per_second": vector,
                          "ratio_to_single_env": vector / single}), flush=True)


if __name__ == "__main__":
    main()
