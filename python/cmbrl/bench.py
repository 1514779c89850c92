"""Steps per second from Python against the C++ figure, in one process:

    python3 -m cmbrl.bench [--tasks PointGoal1 ...] [--variant paper] [--steps 3000] [--runs 5]
    python3 -m cmbrl.bench adapter [--steps 20000] [--rows 16000] [--runs 5]

For each task, three figures, medians of the runs, one JSON line each:
- `cmbrl bench env`'s own loop in C++ (random actions, resets included);
- one environment stepped from Python (cmbrl.make; actions drawn beforehand, resets included),
  with its ratio to the C++ figure;
- a vector of --num-envs environments (cmbrl.make_vec, one thread each), agent steps of all of
  them per second, with its ratio to the single environment from Python.

`adapter`: what cmbrl adds to an environment given from Python (cmbrl.train(env=...)), medians
of the runs, one JSON line each:
- per step: a minimal Python env (preallocated arrays, 100-step episodes) stepped by a Python
  loop, and the same env stepped by the C++ adapter as a learner steps it; the difference is the
  adapter's overhead (goal: at most 20 us);
- per planner iteration: a numpy reward of --rows predicted steps called on float64 arrays, and
  the same function called through the planner's reward term (float32 tensors to arrays and
  back); --rows defaults to RCE's 8 steps x 4 members x 500 samples.
"""
import argparse
import json
import statistics
import time

import numpy as np

import cmbrl
from . import _cmbrl


def _loop_seconds(env, steps, seed):
    """Seconds of `steps` steps of env (six-value step) in a Python loop, resets included; the
    actions are drawn beforehand."""
    actions = np.random.default_rng(seed).uniform(
        env.action_space.low, env.action_space.high, size=(steps,) + env.action_space.shape)
    env.reset(seed=seed)
    start = time.perf_counter()
    for t in range(steps):
        _, _, _, terminated, truncated, _ = env.step(actions[t])
        if terminated or truncated:
            env.reset()
    return time.perf_counter() - start


def single_env_rate(task, variant, steps, seed):
    return steps / _loop_seconds(cmbrl.make(task, variant=variant), steps, seed)


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


class _MinimalEnv:
    """The cheapest Gymnasium-style env: its step only counts and hands back arrays."""

    def __init__(self):
        self.observation_space = cmbrl.Box(np.full(8, -np.inf), np.full(8, np.inf))
        self.action_space = cmbrl.Box(-np.ones(2), np.ones(2))
        self._observation = np.zeros(8)
        self._t = 0

    def reset(self, seed=None, options=None):
        self._t = 0
        return self._observation, {}

    def step(self, action):
        self._t += 1
        return self._observation, 0.0, 0.0, False, self._t >= 100, {}


def _goal_distance_reward(states, actions, next_states):
    return -np.hypot(next_states[:, 0], next_states[:, 1])


def python_loop_seconds(steps, seed):
    return _loop_seconds(_MinimalEnv(), steps, seed)


def direct_reward_seconds(rows, seed):
    rng = np.random.default_rng(seed)
    states, next_states = rng.normal(size=(rows, 24)), rng.normal(size=(rows, 24))
    actions = rng.uniform(-1.0, 1.0, size=(rows, 2))
    seconds = []
    for _ in range(6):  # the median of 5 calls after a first, as the term's figure
        start = time.perf_counter()
        _goal_distance_reward(states, actions, next_states)
        seconds.append(time.perf_counter() - start)
    return statistics.median(seconds[1:])


def adapter_main(args):
    runs = range(args.runs)
    own = statistics.median(python_loop_seconds(args.steps, args.seed + r) for r in runs)
    through = statistics.median(
        _cmbrl.bench_python_env_steps(_MinimalEnv(), args.steps, args.seed + r) for r in runs)
    print(json.dumps({"bench": "adapter", "part": "env step", "steps": args.steps,
                      "python_loop_us": 1e6 * own / args.steps,
                      "through_adapter_us": 1e6 * through / args.steps,
                      "overhead_us": 1e6 * (through - own) / args.steps}), flush=True)
    direct = statistics.median(direct_reward_seconds(args.rows, args.seed + r) for r in runs)
    term = statistics.median(
        _cmbrl.bench_python_reward_call(_goal_distance_reward, args.rows, 24, 2, args.seed + r)
        for r in runs)
    print(json.dumps({"bench": "adapter", "part": "python reward", "rows": args.rows,
                      "direct_ms": 1e3 * direct, "through_term_ms": 1e3 * term,
                      "overhead_ms": 1e3 * (term - direct)}), flush=True)


def main(argv=None):
    import sys
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["adapter"]:
        parser = argparse.ArgumentParser(description="the adapter of Python environments")
        parser.add_argument("--steps", type=int, default=20000, help="env steps per run")
        parser.add_argument("--rows", type=int, default=16000, help="predicted steps per call")
        parser.add_argument("--runs", type=int, default=5)
        parser.add_argument("--seed", type=int, default=0)
        return adapter_main(parser.parse_args(argv[1:]))
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
