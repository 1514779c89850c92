"""How well dynamics ensembles of several sizes predict one agent step of a task, offline.

Collects transitions of uniform random actions (the pre-training data of facts B5), fits one
ensemble per setting on the same transitions (cmbrl.Ensemble: the training's fit, 85/15 split,
early stopping), and measures on held-out episodes from other seeds:
  - the one-step error of the goal's position in the robot frame (state indices 6 and 7,
    facts B1), in metres: median over steps, per member and for the ensemble mean;
  - the same over the steps where the robot is nearly still (speed below 0.1 m/s), where a
    member's bias shows undiluted by motion;
  - the normalised mean squared error over the whole state, per member.

Usage (Debian's python3, with python3-numpy):
  PYTHONPATH=build/python python3 -m cmbrl.diagnostics.model_size --task CarGoal2 --transitions 20000 \\
      --setting 256=256,256,256 --setting 512=512,512,512 --setting delta-256=256,256,256,delta
Each --setting is NAME=H1,H2,...[,delta]. Prints a Markdown table.
"""
import argparse
import time

import numpy as np

import cmbrl


def collect(env, episodes, first_seed, rng):
    states, actions, next_states = [], [], []
    for k in range(episodes):
        obs, _ = env.reset(seed=first_seed + k)
        done = False
        while not done:
            action = rng.uniform(-1.0, 1.0, size=2)
            nxt, _, _, terminated, truncated, info = env.step(action)
            done = terminated or truncated
            # As training stores them: no transition that reached a goal or ended (facts B3).
            if not (info.get("goal_met") or done):
                states.append(obs)
                actions.append(action)
                next_states.append(nxt)
            obs = nxt
    return np.array(states), np.array(actions), np.array(next_states)


def parse_setting(text):
    name, _, spec = text.partition("=")
    parts = spec.split(",")
    delta = parts[-1] == "delta"
    hidden = [int(p) for p in (parts[:-1] if delta else parts)]
    return name, hidden, delta


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--task", required=True)
    parser.add_argument("--transitions", type=int, default=20000,
                        help="at least this many training transitions")
    parser.add_argument("--ensemble-size", type=int, default=5)
    parser.add_argument("--max-epochs", type=int, default=70)
    parser.add_argument("--setting", action="append", required=True)
    args = parser.parse_args(argv)

    env = cmbrl.make(args.task)
    rng = np.random.default_rng(0)
    batches, collected, seed = [], 0, 10_000
    while collected < args.transitions:
        batches.append(collect(env, 20, seed, rng))
        collected += len(batches[-1][0])
        seed += 20
    train = [np.concatenate([batch[i] for batch in batches]) for i in range(3)]
    test_s, test_a, test_n = collect(env, 30, 1, rng)
    scale = test_n.std(axis=0)
    scale[scale < 1e-3] = 1.0
    still = np.hypot(test_s[:, 0], test_s[:, 1]) < 0.1

    print(f"{args.task}: {len(train[0])} training transitions of uniform random actions, "
          f"{len(test_s)} held-out ones ({still.sum()} with the robot nearly still); true move of "
          f"the goal in the robot frame, median {np.median(np.hypot(*(test_n[:, 6:8] - test_s[:, 6:8]).T)):.3f} m")
    print("| setting | epochs | fit (s) | goal error per member (m) | ensemble mean (m) | "
          "nearly still: per member (m) | normalised MSE per member |")
    print("|---|---|---|---|---|---|---|")
    for text in args.setting:
        name, hidden, delta = parse_setting(text)
        model = cmbrl.Ensemble(train[0].shape[1], 2, ensemble_size=args.ensemble_size,
                               hidden_sizes=hidden, max_epochs=args.max_epochs, seed=0,
                               predict_delta=delta)
        start = time.perf_counter()
        report = model.fit(*train)
        seconds = time.perf_counter() - start
        predicted = model.predict(test_s, test_a)  # (E, N, S)
        goal_error = np.hypot(*(predicted[:, :, 6:8] - test_n[:, 6:8]).transpose(2, 0, 1))
        mean_error = np.hypot(*(predicted[:, :, 6:8].mean(0) - test_n[:, 6:8]).T)
        nmse = (((predicted - test_n) / scale) ** 2).mean(axis=(1, 2))
        fmt = lambda values: ", ".join(f"{v:.3f}" for v in values)  # noqa: E731
        still_text = fmt(np.median(goal_error[:, still], axis=1)) if still.any() else "-"
        print(f"| {name} | {report['epochs']} | {seconds:.0f} | {fmt(np.median(goal_error, axis=1))} "
              f"| {np.median(mean_error):.3f} | {still_text} | "
              f"{', '.join(f'{v:.4f}' for v in nmse)} |", flush=True)


if __name__ == "__main__":
    main()
