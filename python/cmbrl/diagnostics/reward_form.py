"""Which form a learned reward should take: an extra output of each dynamics member, or a model of
its own. Offline, on the same transitions for both, per task and seed.

Collects transitions of uniform random actions (as training's pre-training does, leaving out
steps that reached a goal or ended an episode), then fits on them:
  - extra output: a dynamics ensemble (cmbrl.Ensemble, the training's fit) whose state is
    widened by one component, 0 in the input and the step's reward in the target: each member
    then predicts the reward beside the next state from (state, action);
  - own model: cmbrl.RewardModel on (state, action, next state), the form objective.reward:
    learned trains, with a plain dynamics ensemble beside it.
It measures, on held-out episodes of other seeds:
  - the reward's mean squared error: the extra output's member mean; the own model's on the
    true next state and on the ensemble's predicted one (what the planner gives it);
  - the next state's normalised MSE of both ensembles (does the extra output cost the dynamics
    anything?), over the components that vary;
  - the seconds of each fit, and the milliseconds the own model adds to one planner iteration
    of `--rows` predicted steps.

Usage (Debian's python3, with python3-numpy), from the source tree:
  PYTHONPATH=build/python python3 -m cmbrl.diagnostics.reward_form --seeds 0 1 2
Prints a Markdown table; --json also writes its rows.
"""
import argparse
import importlib.util
import json
import pathlib
import statistics
import time

import numpy as np

import cmbrl

def double_integrator(examples):
    """examples/custom_env.py's environment (the source tree's examples folder)."""
    spec = importlib.util.spec_from_file_location("custom_env",
                                                  pathlib.Path(examples) / "custom_env.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.DoubleIntegrator()


def collect(env, episodes, first_seed, rng):
    rows = {"s": [], "a": [], "n": [], "r": []}
    for k in range(episodes):
        obs, _ = env.reset(seed=first_seed + k)
        done = False
        while not done:
            action = rng.uniform(env.action_space.low, env.action_space.high)
            nxt, reward, _, terminated, truncated, info = env.step(action)
            done = terminated or truncated
            if not (info.get("goal_met") or done):
                for key, value in zip("sanr", (obs, action, nxt, reward)):
                    rows[key].append(value)
            obs = nxt
    return {key: np.array(value, dtype=np.float64) for key, value in rows.items()}


def study(task, make, train_episodes, test_episodes, seed, hidden, max_epochs, rows):
    rng = np.random.default_rng(seed)
    env = make()
    train = collect(env, train_episodes, 1000 * seed, rng)
    test = collect(env, test_episodes, 1000 * seed + 500, rng)
    s_dim, a_dim = train["s"].shape[1], train["a"].shape[1]
    state_var = test["n"].var(axis=0)
    varying = state_var > 1e-8  # components that never move (a sensor of nothing) are left out

    def state_nmse(predicted):  # (N, S) against the held-out next states
        error = (predicted - test["n"])[:, varying] ** 2 / state_var[varying]
        return float(np.mean(error))

    widened = cmbrl.Ensemble(s_dim + 1, a_dim, hidden_sizes=hidden, max_epochs=max_epochs,
                             seed=seed)
    zeros = np.zeros((len(train["s"]), 1))
    start = time.perf_counter()
    widened.fit(np.hstack([train["s"], zeros]), train["a"],
                np.hstack([train["n"], train["r"][:, None]]))
    widened_seconds = time.perf_counter() - start
    out = widened.predict(np.hstack([test["s"], np.zeros((len(test["s"]), 1))]), test["a"])
    extra_mse = float(np.mean((out[:, :, -1].mean(axis=0) - test["r"]) ** 2))
    widened_nmse = state_nmse(out[:, :, :-1].mean(axis=0))

    plain = cmbrl.Ensemble(s_dim, a_dim, hidden_sizes=hidden, max_epochs=max_epochs, seed=seed)
    start = time.perf_counter()
    plain.fit(train["s"], train["a"], train["n"])
    plain_seconds = time.perf_counter() - start
    predicted_next = plain.predict(test["s"], test["a"]).mean(axis=0)
    own = cmbrl.RewardModel(2 * s_dim + a_dim, seed=seed)
    start = time.perf_counter()
    own.fit(np.hstack([train["s"], train["a"], train["n"]]), train["r"])
    own_seconds = time.perf_counter() - start
    own_true = own.predict(np.hstack([test["s"], test["a"], test["n"]]))
    own_predicted = own.predict(np.hstack([test["s"], test["a"], predicted_next]))
    big = np.random.default_rng(seed).normal(size=(rows, 2 * s_dim + a_dim))
    own.predict(big)  # the first call allocates
    start = time.perf_counter()
    own.predict(big)
    own_ms = 1e3 * (time.perf_counter() - start)
    return {
        "task": task, "seed": seed, "train_steps": len(train["s"]), "test_steps": len(test["s"]),
        "reward_var": float(test["r"].var()),
        "extra_output_mse": extra_mse,
        "own_model_mse_true_next": float(np.mean((own_true - test["r"]) ** 2)),
        "own_model_mse_predicted_next": float(np.mean((own_predicted - test["r"]) ** 2)),
        "state_nmse_widened": widened_nmse,
        "state_nmse_plain": state_nmse(predicted_next),
        "fit_seconds_widened_ensemble": widened_seconds,
        "fit_seconds_plain_ensemble": plain_seconds,
        "fit_seconds_own_model": own_seconds,
        "own_model_ms_per_iteration": own_ms,
    }


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--hidden", type=int, nargs="+", default=[200, 200],
                        help="the dynamics ensembles' hidden sizes (the quickstart family's)")
    parser.add_argument("--max-epochs", type=int, default=30)
    parser.add_argument("--rows", type=int, default=16000,
                        help="predicted steps of one planner iteration (RCE: 8 x 4 x 500)")
    parser.add_argument("--examples", default="examples",
                        help="the source tree's examples folder (custom_env.py)")
    parser.add_argument("--json", help="also write the rows to this file")
    args = parser.parse_args(argv)
    tasks = [("DoubleIntegrator", lambda: double_integrator(args.examples), 100, 30),
             ("PointGoal1", lambda: cmbrl.make("PointGoal1"), 100, 30)]
    results = [study(task, make, train_eps, test_eps, seed, args.hidden, args.max_epochs,
                     args.rows)
               for task, make, train_eps, test_eps in tasks for seed in args.seeds]
    if args.json:
        with open(args.json, "w") as out:
            json.dump(results, out, indent=1)
    keys = ["reward_var", "extra_output_mse", "own_model_mse_true_next",
            "own_model_mse_predicted_next", "state_nmse_widened", "state_nmse_plain",
            "fit_seconds_widened_ensemble", "fit_seconds_plain_ensemble", "fit_seconds_own_model",
            "own_model_ms_per_iteration"]
    print("| task | " + " | ".join(keys) + " |")
    print("|---|" + "---|" * len(keys))
    for task, *_ in tasks:
        mine = [r for r in results if r["task"] == task]
        cells = []
        for key in keys:
            values = [r[key] for r in mine]
            cells.append(f"{statistics.median(values):.4g} [{min(values):.3g}, {max(values):.3g}]")
        print(f"| {task} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
