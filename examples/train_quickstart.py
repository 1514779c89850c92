#!/usr/bin/env python3
"""Trains the quickstart preset from Python, evaluates its agent for one episode and saves a
picture of it with the planner's predictions.

    PYTHONPATH=build/python python3 examples/train_quickstart.py --out runs/py-quickstart
    PYTHONPATH=build/python python3 examples/train_quickstart.py --out /tmp/q --steps 300  # a taste

Run again with the same --out, it resumes the run where it stopped (Ctrl-C is safe).
"""
import argparse
import os
import pathlib

import numpy as np

import cmbrl

ROOT = pathlib.Path(__file__).resolve().parents[1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--config", nargs="+",
                        default=[ROOT / "configs" / "pointgoal1-rce.yaml",
                                 ROOT / "configs" / "quickstart.yaml"],
                        help="config files, composed in order (a preset, then a family)")
    parser.add_argument("--out", required=True, help="run directory")
    parser.add_argument("--steps", type=int, help="agent steps (default: the config's)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    def report(unit):
        print(f"epoch {unit['epoch']}: steps {unit['steps']}/{unit['budget']}, "
              f"return {unit['episode_return']:.2f}, cost {unit['episode_cost']:.0f}", flush=True)

    if os.path.exists(os.path.join(args.out, "config.yaml")):
        cmbrl.train(resume=args.out, progress=report)
    else:
        cmbrl.train(config=args.config, out=args.out, steps=args.steps, seed=args.seed,
                    progress=report)

    # One evaluation episode with the trained agent.
    agent = cmbrl.load_run(args.out, seed=args.seed)
    task = next(line.split(":", 1)[1].strip() for line in agent.config().splitlines()
                if line.startswith("task:"))
    env = cmbrl.make(task, render_size=600)
    obs, _ = env.reset(seed=args.seed)
    agent.begin_episode()
    episode_return = episode_cost = 0.0
    predictions = []
    for step in range(env.max_episode_steps * 2):
        action = agent.act(obs)
        if agent.is_mpc and step % 25 == 0:
            predictions += agent.predictions(env, samples=4)
        obs, reward, cost, terminated, truncated, _ = env.step(action)
        episode_return += reward
        episode_cost += cost
        if terminated or truncated:
            break
    picture = pathlib.Path(args.out) / "python-evaluation.png"
    env.save_picture(picture, caption=f"{task}: return {episode_return:.2f}, "
                     f"cost {episode_cost:.0f} (from Python)", predictions=predictions)
    print(f"evaluation: return {episode_return:.2f}, cost {episode_cost:.0f}, "
          f"steps {step + 1}; picture {picture}")
    assert np.isfinite(episode_return)


if __name__ == "__main__":
    main()
