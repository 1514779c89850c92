#!/usr/bin/env python3
"""Prints the JSON lines of `cmbrl bench` as one Markdown table (standard library only)."""
import json
import sys


def row(line):
    what = line.get("what", "")
    name = " ".join(
        str(part) for part in (line.get("task"), what, line.get("planner"), line.get("precision"))
        if part)
    if line.get("bench") == "env":
        return name + " env", f'{line["agent_steps_per_second"]:.0f} steps/s', \
            f'{line["ceiling_agent_steps_per_second"]:.0f} steps/s', f'{line["ratio_to_ceiling"]:.2f}'
    if "median_ms" not in line:
        return None
    floor = f'{line["floor_ms"]:.2f} ms' if "floor_ms" in line else ""
    ratio = f'{line["ratio_to_ceiling"]:.2f}' if "ratio_to_ceiling" in line else ""
    return name, f'{line["median_ms"]:.2f} ms', floor, ratio


def main():
    lines = [json.loads(text) for text in open(sys.argv[1]) if text.strip().startswith("{")]
    for line in lines:
        if line.get("bench") == "ceiling":
            rates = ", ".join(f"{key} {value:.0f}" for key, value in line.items()
                              if key.endswith("_gflops"))
            print(f'ceiling on {line["device"]}: GEMM GFLOP/s {rates}')
    print("| what | median | floor (or ceiling) | ratio |")
    print("|---|---|---|---|")
    for line in lines:
        cells = row(line)
        if cells:
            print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
