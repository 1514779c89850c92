#!/usr/bin/env python3
"""One Markdown table of the level-2 ablations from their `cmbrl report` outputs.

Usage: scripts/ablation-table.py REPORTS_DIR

REPORTS_DIR/<task>-<method>/<variant>/table-1.csv as `cmbrl report` writes them; prints, per
task and method, one row per variant: violations over the window (mean and per seed), the
original's over the same window, episodes with >= 20 violations, FeasibleFraction and the return
of the last 10 episodes.
"""
import csv
import os
import sys

ORDER = ["grid", "faithful", "bonus", "labels", "population", "classifier", "min-child-weight",
         "dynamics", "combined", "threshold", "spawn"]


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    root = sys.argv[1]
    for cell in sorted(os.listdir(root)):
        folder = os.path.join(root, cell)
        if not os.path.isdir(folder):
            continue
        variants = [v for v in ORDER if os.path.exists(os.path.join(folder, v, "table-1.csv"))]
        variants += sorted(v for v in os.listdir(folder)
                           if v not in ORDER and os.path.exists(os.path.join(folder, v, "table-1.csv")))
        if not variants:
            continue
        print(f"\n### {cell}\n")
        print("| variant | seeds | violations: mean (per seed) | original (per seed) | episodes >= 20 "
              "| original's | feasible fraction | return | original's return |")
        print("|---|---|---|---|---|---|---|---|---|")
        for variant in variants:
            with open(os.path.join(folder, variant, "table-1.csv")) as f:
                for row in csv.DictReader(f):
                    heavy = row.get("heavy_per_seed", "").split()
                    print("| {} | {} | {:.1f} ({}) | {} ({}) | {} ({}) | {} | {} | {:.2f} | {} |".format(
                        variant, row["seeds"], float(row["mean"]), row["per_seed"].replace(" ", ", "),
                        "{:.1f}".format(float(row["original_mean"])) if row["original_mean"] else "-",
                        row["original_per_seed"].replace(" ", ", "),
                        sum(int(h) for h in heavy), ", ".join(heavy),
                        row["original_heavy_per_seed"].replace(" ", ", ") or "-",
                        "{:.3f}".format(float(row["feasible_fraction"]))
                        if row["feasible_fraction"] not in ("", "nan") else "-",
                        float(row["return_mean"]),
                        "{:.2f}".format(float(row["original_return_mean"]))
                        if row["original_return_mean"] else "-"))


if __name__ == "__main__":
    main()
