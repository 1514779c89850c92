#!/usr/bin/env python3
"""experiments/custom-tasks: RCE, CEM and random shooting, and a random policy, on a pure-Python
environment and a MuJoCo task file, 3 seeds each (README.md has the protocol).

    PYTHONPATH=build/python python3 experiments/custom-tasks/run.py --jobs 2   # runs, resumable
    PYTHONPATH=build/python python3 experiments/custom-tasks/run.py --report   # report/ again

Runs go to runs/runs/<name> (not committed); --report (also done after the runs) writes
report/ from the runs, or, without them, again from report/run-logs: the sweep report of
`cmbrl report` (report.md, its tables and curves, run-logs/) and summary.md, this experiment's
table of violations and returns with bootstrap intervals.
"""
import argparse
import importlib.util
import os
import pathlib
import shutil
import subprocess
import sys

import numpy as np

import cmbrl

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
SEEDS = [0, 1, 2]
STEPS = 2000
# Both tasks' sizes: examples/arm-reach/task.yaml's keys.
COMMON = {
    "training": {"pretrain_episodes": 20, "pretrain_steps": 100, "episodes_per_epoch": 2,
                 "total_steps": STEPS},
    "ensemble": {"hidden_sizes": [200, 200], "max_epochs": 30},
    "classifier": {"rounds": 100},
    "planning": {"horizon": 10, "population": 200, "elites": 10, "max_iterations": 5},
}
# The methods: a planner, and the random policy (random shooting with one sample).
METHODS = {"rce": {"planner": "rce"}, "cem": {"planner": "cem"},
           "random": {"planner": "random"},
           "random-policy": {"planner": "random", "planning": {"random_samples": 1}}}
TASKS = ["DoubleIntegrator", "ArmReach"]


def custom_env():
    spec = importlib.util.spec_from_file_location("custom_env", ROOT / "examples" / "custom_env.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["custom_env"] = module  # pickled envs find their class again
    spec.loader.exec_module(module)
    return module


def config_of(method):
    config = {key: dict(value) for key, value in COMMON.items()}
    for key, value in METHODS[method].items():
        if isinstance(value, dict):
            config[key] = {**config.get(key, {}), **value}
        else:
            config[key] = value
    return config


def run_names():
    return [f"{task.lower()}-{method}-s{seed}" for seed in SEEDS for task in TASKS
            for method in METHODS]


def train_one(name):
    """Trains (or resumes) one run in this process."""
    task, rest = name.split("-", 1)
    method, seed = rest.rsplit("-s", 1)
    out = HERE / "runs" / "runs" / name
    task = next(t for t in TASKS if t.lower() == task)
    config = config_of(method)
    kwargs = {}
    if task == "DoubleIntegrator":
        module = custom_env()
        kwargs = {"env": module.DoubleIntegrator, "reward": module.reward}
        source = config
    else:  # the task file, then the sizes and the method over it
        overrides = out.parent / f"{name}.yaml"
        overrides.parent.mkdir(parents=True, exist_ok=True)
        import json
        overrides.write_text(json.dumps(config))
        source = [str(ROOT / "examples" / "arm-reach" / "task.yaml"), str(overrides)]
    if (out / "config.yaml").exists():
        cmbrl.train(resume=out, **kwargs)
    else:
        cmbrl.train(config=source, out=out, seed=int(seed), **kwargs)


def run_all(jobs):
    """Every run not finished, `jobs` at a time, each in a process of its own on one core."""
    logs = HERE / "runs" / "logs"
    logs.mkdir(parents=True, exist_ok=True)
    pending = list(run_names())
    free = list(range(min(jobs, os.cpu_count() or 1)))  # cores without a run
    running = {}
    while pending or running:
        while pending and free:
            name, core = pending.pop(0), free.pop(0)
            log = open(logs / f"{name}.log", "a")
            process = subprocess.Popen(
                ["taskset", "-c", str(core), sys.executable, __file__, "--one", name],
                stdout=log, stderr=subprocess.STDOUT)
            running[process.pid] = (name, core, log)
            print(f"started {name} on core {core}", flush=True)
        pid, status = os.wait()
        if pid not in running:
            continue
        name, core, log = running.pop(pid)
        log.close()
        free.append(core)
        print(f"{name}: exit status {status >> 8}", flush=True)


def bootstrap(values, resamples=10_000, seed=0):
    values = np.asarray(values, dtype=float)
    rng = np.random.default_rng(seed)
    means = rng.choice(values, size=(resamples, len(values)), replace=True).mean(axis=1)
    return values.mean(), np.percentile(means, 5), np.percentile(means, 95)


def summary(runs):
    lines = ["# custom-tasks: violations and returns over the first 2000 agent steps", "",
             "Per cell: each seed's violations (steps with cost 1) and mean return of its last "
             "10 episodes in the window, then the mean over seeds with a bootstrap 90% interval "
             "(10,000 resamples of the seeds). random-policy: a uniformly random action each "
             "step (random shooting with one sample). Made by experiments/custom-tasks/run.py "
             "from the runs' logs (run-logs/).", "",
             "| task | method | seeds | violations per seed | mean [90%] | return per seed | "
             "mean [90%] |", "|---|---|---|---|---|---|---|"]
    for task in TASKS:
        for method in METHODS:
            cell = [r for r in runs if r["name"].startswith(f"{task.lower()}-{method}-s")]
            if not cell:
                continue
            violations, returns = [], []
            for run in sorted(cell, key=lambda r: r["name"]):
                inside = run["end_step"] <= STEPS
                violations.append(float(np.sum(run["episode_cost"][inside])))
                returns.append(float(np.mean(run["episode_return"][inside][-10:])))
            v = bootstrap(violations)
            g = bootstrap(returns)
            lines.append(
                f"| {task} | {method} | {len(cell)} | {', '.join(f'{x:.0f}' for x in violations)}"
                f" | {v[0]:.1f} [{v[1]:.1f}, {v[2]:.1f}] | "
                f"{', '.join(f'{x:.2f}' for x in returns)} | {g[0]:.2f} [{g[1]:.2f}, {g[2]:.2f}] |")
    return "\n".join(lines) + "\n"


def report(out=HERE / "report", runs_dir=HERE / "runs"):
    """Writes report/ (into `out`) from the runs in runs_dir, or from out's run-logs alone."""
    out, runs_dir = pathlib.Path(out), pathlib.Path(runs_dir)
    if (runs_dir / "runs").is_dir():  # the runs' logs into report/run-logs
        if out.exists():
            shutil.rmtree(out)
        cmbrl.report(runs_dir, out, window=STEPS)
    # Always made from the committed logs, so that it is the same made again from them alone.
    cmbrl.report(out, out, window=STEPS)
    runs = cmbrl.read_runs(out)  # named by their folders
    (out / "summary.md").write_text(summary(runs))
    return (out / "summary.md").read_text()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--one", help=argparse.SUPPRESS)
    parser.add_argument("--report", action="store_true", help="only write report/ again")
    args = parser.parse_args()
    if args.one:
        return train_one(args.one)
    if not args.report:
        run_all(args.jobs)
    print(report())


if __name__ == "__main__":
    main()
