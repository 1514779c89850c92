"""Frozen-model comparison of planners on the same states: each planner plans from every state of
one driver's episodes with one trained run's models, and the same objective judges every plan.

Each setting is a planner with its settings, as `cmbrl eval --set` overrides (planner=...,
planning.*). Every setting's agent loads the same run (the same dynamics ensemble and
classifier) and keeps its own memory across the episode (warm starts, iCEM's kept elites). At
each state all of them plan; the driver's action is executed. The run's own objective (its
config, no overrides) scores each setting's chosen sequence (Agent.score): the predicted reward
cost (the discounted goal distance, lower is better) and feasibility (no member predicts a
violation over the horizon). Against the first setting, the reference:
  - no worse: where the reference's plan is feasible, its plan is feasible with a reward cost at
    most the reference's; where the reference's is infeasible, its constraint cost is at most
    the reference's (a feasible plan's is 0);
  - reward gap: its reward cost minus the reference's, over the states where both are feasible.

Usage:
  PYTHONPATH=build/python python3 -m cmbrl.diagnostics.planner_compare RUN_DIR \\
      --setting rce-500=planner=rce,planning.population=500 \\
      --setting rce-icem=planner=rce-icem,planning.population=100,planning.max_iterations=4 \\
      [--driver rce-500] [--episodes 3] [--seed 100] [--out DIR]
Episode k is reset with seed + k. Prints (and with --out writes DIR/table.md) a Markdown table.
"""
import argparse
import os
import statistics

import numpy as np

from cmbrl.diagnostics.planner_study import parse_setting
from cmbrl.diagnostics.runs import load_mpc_run, load_settings
from cmbrl.diagnostics.tables import write_table

TOLERANCE = 1e-6  # float32 scores: equal plans score equal, up to this


def compare(run, settings, driver, episodes, seed):
    """Per setting, arrays over the states: reward_cost, constraint_cost, feasible and ms a plan;
    and the steps and violating steps of the driver's episodes."""
    judge = load_mpc_run(run, "planner to compare", seed=seed)
    agents = load_settings(run, settings, seed=seed)
    env = judge.make_env()
    records = {name: {"reward_cost": [], "constraint_cost": [], "feasible": [], "ms": []}
               for name in agents}
    violations = steps = 0
    for k in range(episodes):
        obs, _ = env.reset(seed=seed + k)
        for agent in agents.values():
            agent.begin_episode()
        done = False
        while not done:
            actions, plans = {}, []
            for name, agent in agents.items():
                actions[name] = agent.act(obs)
                plan = agent.last_plan()
                plans.append(plan["actions"])
                records[name]["ms"].append(plan["milliseconds"])
            scores = judge.score(obs, np.stack(plans))
            for i, name in enumerate(agents):
                records[name]["reward_cost"].append(scores["reward_cost"][i])
                records[name]["constraint_cost"].append(scores["constraint_cost"][i])
                records[name]["feasible"].append(bool(scores["feasible"][i]))
            obs, _, cost, terminated, truncated, _ = env.step(actions[driver])
            violations += cost > 0
            steps += 1
            done = terminated or truncated
    env.close()
    return ({name: {key: np.array(value) for key, value in record.items()}
             for name, record in records.items()}, steps, int(violations))


def summarise(records, reference):
    ref = records[reference]
    rows = []
    for name, r in records.items():
        both = r["feasible"] & ref["feasible"]
        no_worse = np.where(ref["feasible"],
                            r["feasible"] & (r["reward_cost"] <= ref["reward_cost"] + TOLERANCE),
                            r["constraint_cost"] <= ref["constraint_cost"] + TOLERANCE)
        gap = r["reward_cost"][both] - ref["reward_cost"][both]
        rows.append({"setting": name, "feasible": float(r["feasible"].mean()),
                     "reward_cost": float(r["reward_cost"].mean()),
                     "no_worse": float(no_worse.mean()),
                     "gap_mean": float(gap.mean()) if len(gap) else float("nan"),
                     "gap_median": float(np.median(gap)) if len(gap) else float("nan"),
                     "ms": float(statistics.median(r["ms"]))})
    return rows


def table(run, rows, reference, driver, steps, violations, episodes, seed):
    name = os.path.basename(os.path.normpath(run))
    lines = [f"Frozen-model planner comparison: {name}'s models, "
             f"{steps} states of {episodes} episodes driven by {driver} (reset with seed {seed} + "
             f"k; {violations} violating steps), every plan scored by the run's own objective "
             f"(`python3 -m cmbrl.diagnostics.planner_compare`).\n",
             f"| setting | chosen plan feasible | mean reward cost | no worse than {reference} | "
             f"reward gap where both feasible, mean | median | ms a plan (median) |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['setting']} | {r['feasible']:.1%} | {r['reward_cost']:.3f} | "
                     f"{r['no_worse']:.1%} | {r['gap_mean']:+.3f} | {r['gap_median']:+.3f} | "
                     f"{r['ms']:.0f} |")
    return "\n".join(lines) + "\n"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("run")
    parser.add_argument("--setting", action="append", required=True, type=parse_setting,
                        help="NAME=OVERRIDE[,OVERRIDE...]; the first is the reference")
    parser.add_argument("--driver", help="the setting whose actions are executed (the first)")
    parser.add_argument("--episodes", type=int, default=3)
    parser.add_argument("--seed", type=int, default=100)
    parser.add_argument("--out")
    args = parser.parse_args(argv)
    names = [name for name, _ in args.setting]
    if len(set(names)) != len(names):
        parser.error(f"--setting names repeat: {names}")
    driver = args.driver or names[0]
    if driver not in names:
        parser.error(f"--driver {driver}: expected one of the settings, {names}")
    if args.episodes < 1:
        parser.error(f"--episodes {args.episodes}: expected at least 1")
    records, steps, violations = compare(args.run, args.setting, driver, args.episodes, args.seed)
    text = table(args.run, summarise(records, names[0]), names[0], driver, steps, violations,
                 args.episodes, args.seed)
    if args.out:
        write_table(args.out, text)
    print(text)


if __name__ == "__main__":
    main()
