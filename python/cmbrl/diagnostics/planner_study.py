"""Frozen-model planner study: the same trained runs' models, planned with other settings.

Each setting is a list of `cmbrl eval --set` overrides (planning.*, objective.*,
classifier.threshold, planner). Every run is evaluated under every setting with the same
environment and planner seed: the first episode's layout is the same for all settings; later
layouts come from the same generator but differ once settings reach different numbers of goals
(each goal met draws a new one). With --reseed (`cmbrl eval --reseed`) episode k is reset with
seed + k, so every setting meets the same layouts. This separates
the planner's share of the violations from the training loop's (which states the models saw),
at a fraction of a training ablation's cost.

Usage:
  python3 -m cmbrl.diagnostics.planner_study --cmbrl build/bin/cmbrl --out DIR --episodes 10 --seed 11 \\
      --runs runs/cpu-grid/runs/pointgoal2-rce-s{0,1,2,3} \\
      --setting preset= --setting threshold-0.3=classifier.threshold=0.3

A setting is NAME=OVERRIDE[,OVERRIDE...] (empty: the run's own config). Writes
DIR/<setting>/<run>.jsonl (one `cmbrl eval` line per episode; an existing complete file is kept,
so a stopped study continues where it stopped) and DIR/table.md, one row per setting.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

HEAVY = 20  # violations that make an episode "heavy", as in the reports


def parse_setting(text):
    name, sep, overrides = text.partition("=")
    if not sep or not name:
        sys.exit(f"--setting '{text}': expected NAME=OVERRIDE[,OVERRIDE...] (NAME= for none)")
    return name, [o for o in overrides.split(",") if o]


def evaluate(args, run, name, overrides):
    path = os.path.join(args.out, name, os.path.basename(os.path.normpath(run)) + ".jsonl")
    if os.path.exists(path):
        with open(path) as f:
            lines = [json.loads(line) for line in f if line.strip()]
        if len(lines) == args.episodes:
            return lines
    os.makedirs(os.path.dirname(path), exist_ok=True)
    command = [args.cmbrl, "eval", "--run", run, "--episodes", str(args.episodes),
               "--seed", str(args.seed), "--predictions-every", "0"]
    if args.reseed:
        command.append("--reseed")
    if overrides:
        command += ["--set", *overrides]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"{' '.join(command)} failed: {result.stderr.strip()}")
    with open(path + ".part", "w") as f:
        f.write(result.stdout)
    os.replace(path + ".part", path)
    return [json.loads(line) for line in result.stdout.splitlines() if line.strip()]


def summarise(episodes_by_run):
    per_run = {run: sum(e["cost"] for e in eps) for run, eps in episodes_by_run.items()}
    episodes = [e for eps in episodes_by_run.values() for e in eps]
    steps = sum(e["steps"] for e in episodes)
    return {
        "per_run": per_run,
        "per_100_steps": 100.0 * sum(per_run.values()) / steps,
        "heavy": sum(e["cost"] >= HEAVY for e in episodes),
        "return": statistics.mean(e["return"] for e in episodes),
        "goals": statistics.mean(e.get("goals_met", float("nan")) for e in episodes),
        # Where the steps went: inside hazards, and near the goal (cmbrl eval's steps_near_goal,
        # within 1 m of the goal pursued), and how far from it on average.
        "hazard_share": sum(e.get("hazard_steps", float("nan")) for e in episodes) / steps,
        "near_goal_share": sum(e.get("steps_near_goal", float("nan")) for e in episodes) / steps,
        "goal_distance": statistics.mean(e.get("mean_goal_distance", float("nan"))
                                         for e in episodes),
        "feasible": statistics.mean(e.get("feasible_fraction", float("nan")) for e in episodes),
        "fallback": statistics.mean(e.get("fallback_steps", float("nan")) for e in episodes),
        "ms": statistics.median(e["ms_per_plan"] for e in episodes),
        "episodes": len(episodes),
    }


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cmbrl", required=True)
    parser.add_argument("--runs", nargs="+", required=True)
    parser.add_argument("--setting", action="append", required=True, type=parse_setting)
    parser.add_argument("--episodes", type=int, default=10)
    parser.add_argument("--seed", type=int, default=11)
    parser.add_argument("--out", required=True)
    parser.add_argument("--reseed", action="store_true",
                        help="episode k reset with seed + k: every setting meets the same layouts "
                             "(use one choice per output folder)")
    args = parser.parse_args(argv)

    rows, run_rows = [], []
    for name, overrides in args.setting:
        by_run = {}
        for run in args.runs:
            run_name = os.path.basename(os.path.normpath(run))
            by_run[run_name] = evaluate(args, run, name, overrides)
            run_rows.append((name, run_name, summarise({run_name: by_run[run_name]})))
            print(f"{name}: {run} done", flush=True)
        rows.append((name, overrides, summarise(by_run)))

    with open(os.path.join(args.out, "table.md"), "w") as f:
        f.write(f"Frozen-model planner study: {len(args.runs)} runs x {args.episodes} episodes "
                f"each, environment seed {args.seed} (`python3 -m cmbrl.diagnostics.planner_study`).\n\n")
        f.write("| setting | overrides | violations per run | per 100 steps | episodes >= "
                f"{HEAVY} | return | goals | feasible fraction | fallback steps | ms a plan |\n")
        f.write("|---|---|---|---|---|---|---|---|---|---|\n")
        for name, overrides, s in rows:
            per_run = ", ".join(f"{v:g}" for v in s["per_run"].values())
            named = " ".join(overrides) or "(the run's own)"
            f.write(f"| {name} | {named} | {per_run} | "
                    f"{s['per_100_steps']:.2f} | {s['heavy']} | {s['return']:.2f} | "
                    f"{s['goals']:.2f} | {s['feasible']:.3f} | {s['fallback']:.3f} | "
                    f"{s['ms']:.0f} |\n")
        f.write("\nPer run (whose models) and setting (how they were planned with): where the steps "
                "went.\n\n| setting | run | return | goals | steps in hazards | steps within 1 m of "
                "the goal | mean distance to the goal (m) | feasible fraction | fallback steps |\n")
        f.write("|---|---|---|---|---|---|---|---|---|\n")
        for name, run_name, s in run_rows:
            f.write(f"| {name} | {run_name} | {s['return']:.2f} | {s['goals']:.2f} | "
                    f"{s['hazard_share']:.1%} | {s['near_goal_share']:.1%} | "
                    f"{s['goal_distance']:.2f} | {s['feasible']:.3f} | {s['fallback']:.3f} |\n")
    print(open(os.path.join(args.out, "table.md")).read())


if __name__ == "__main__":
    main()
