#!/usr/bin/env python3
"""Converts the per-episode and per-epoch logs that the paper's authors published (liuzuxin/
safe-mbrl, folder data/) into the CSV files under data/reference/ that `cmbrl report` reads.

Usage: data/reference/import_logs.py LOGS_DIR [OUT_DIR]

LOGS_DIR holds {pg1,pg2,cg1,cg2}/... as published. Only numbers are carried over: every column
of every row, tab-separated values rewritten as CSV, one file per run:

  mbrl/<Task>-<planner>-s<seed>.csv   one row per MPC episode (Epoch, Episode, EpRet, EpCost,
                                      TotalEnvInteracts, Time); agent steps, pre-training not
                                      counted
  model-free/<Task>-<algo>-limit<L>.csv  one row per epoch of 30,000 environment steps
"""
import json
import os
import sys

TASKS = {"pg1": "PointGoal1", "pg2": "PointGoal2", "cg1": "CarGoal1", "cg2": "CarGoal2"}
MODEL_FREE = {"trpo": "trpo", "trpo-lagrangian": "trpo-lagrangian",
              "trpo_lagrangian": "trpo-lagrangian", "cpo": "cpo"}


def convert(src, dst):
    with open(src) as f:
        rows = [line.rstrip("\n").split("\t") for line in f if line.strip()]
    width = len(rows[0])
    for i, row in enumerate(rows):
        if len(row) != width:
            sys.exit(f"{src}: line {i + 1} has {len(row)} fields, the header {width}")
    os.makedirs(os.path.dirname(dst), exist_ok=True)
    with open(dst, "w") as f:
        for row in rows:
            f.write(",".join(field.strip() for field in row) + "\n")


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    logs = sys.argv[1]
    # By default beside this script: data/reference.
    out = sys.argv[2] if len(sys.argv) == 3 else os.path.dirname(os.path.abspath(__file__))
    count = 0
    for short, task in TASKS.items():
        for root, _, files in os.walk(os.path.join(logs, short)):
            if "progress.txt" not in files:
                continue
            parts = os.path.relpath(root, os.path.join(logs, short)).split(os.sep)
            family = parts[0].lower()
            src = os.path.join(root, "progress.txt")
            if family.startswith("ensemble-"):
                planner = family[len("ensemble-"):]
                seed = parts[-1].rsplit("_s", 1)[1]
                dst = os.path.join(out, "mbrl", f"{task}-{planner}-s{seed}.csv")
            elif family in MODEL_FREE:
                with open(os.path.join(root, "config.json")) as f:
                    limit = json.load(f)["cost_lim"]
                dst = os.path.join(out, "model-free", f"{task}-{MODEL_FREE[family]}-limit{limit:g}.csv")
            else:
                sys.exit(f"{root}: unknown run family '{parts[0]}'")
            convert(src, dst)
            count += 1
    print(f"wrote {count} files under {out}")


if __name__ == "__main__":
    main()
