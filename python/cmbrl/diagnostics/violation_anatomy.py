"""Where an MPC run's violations come from: each violating step of a trained run's agent, sorted
by what its models knew.

For every step whose agent step had a cost, with the run's final models (cmbrl.load_run):
  - hole: the classifier calls the true next state safe, so no plan could have avoided it;
  - unforeseen: the classifier knows that state is unsafe, but every ensemble member predicted a
    safe next state for the executed action (a dynamics error);
  - foreseen, fallback: a member predicted the violation and RCE had too few feasible samples
    (its plan came from the least-violating, infeasible elites);
  - foreseen, feasible: a member predicted the violation although the plan had enough feasible
    samples (the executed mean of the elites differs from each elite).
Also: how long violations last once they start (consecutive violating steps), what kinds the
steps of long runs (5 or more: a robot staying in a hazard) are, and the robot's speed at
violating steps and at the others.

Usage (Debian's python3, with python3-numpy):
       PYTHONPATH=build/python python3 -m cmbrl.diagnostics.violation_anatomy RUN_DIR [--episodes 8] [--seed 5]
       [--set planning.population=500 ...]
Episode k is episode k of `cmbrl eval --run RUN_DIR --seed 5` with the same --set (and
--reseed).
"""
import argparse
import collections
import statistics

import numpy as np

from cmbrl.diagnostics.runs import load_mpc_run

COST_TERMS = ("cost_hazards", "cost_vases_contact", "cost_vases_velocity")  # facts A3
KINDS = ("hole", "unforeseen", "foreseen, fallback", "foreseen, feasible")
LONG_RUN = 5  # consecutive violating steps from which a run counts as a stay


def violation_runs(step_kinds):
    """The runs of consecutive violating steps in one episode: [kind, or None for a step without a
    cost, per step] -> [[kind of each step of the run], ...] in order."""
    runs, current = [], []
    for kind in step_kinds:
        if kind is None:
            if current:
                runs.append(current)
            current = []
        else:
            current.append(kind)
    if current:
        runs.append(current)
    return runs


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("run")
    parser.add_argument("--episodes", type=int, default=8)
    parser.add_argument("--seed", type=int, default=5)
    parser.add_argument("--set", nargs="*", default=[], help="overrides, as cmbrl eval --set")
    parser.add_argument("--reseed", action="store_true",
                        help="episode k reset with seed + k, as cmbrl eval --reseed")
    args = parser.parse_args(argv)

    agent = load_mpc_run(args.run, "models to sort its violations by", seed=args.seed,
                         overrides=args.set)
    env = agent.make_env()

    kinds = collections.Counter()
    long_kinds = collections.Counter()  # kinds of the steps in runs of LONG_RUN or more
    terms = collections.Counter()  # which cost terms made the violating steps (facts A3)
    steps = violations = 0
    dwell = []          # lengths of runs of consecutive violating steps
    speeds_in, speeds_out = [], []
    episode_costs, episode_returns = [], []
    for k in range(args.episodes):
        # As `cmbrl eval --seed S`: the first reset seeded, the others continuing its generator,
        # so episode k here is eval's episode k (the same planner seed too).
        if args.reseed:
            obs, _ = env.reset(seed=args.seed + k)
        else:
            obs, _ = env.reset(seed=args.seed) if k == 0 else env.reset()
        agent.begin_episode()
        step_kinds = []
        cost_sum = 0
        episode_return = 0.0
        done = False
        while not done:
            action = agent.act(obs)
            plan = agent.last_plan()
            predicted = agent.predict_next(obs[None, :], action[None, :])[:, 0, :]
            foreseen = bool(agent.predict_violation(predicted).any())
            speed = float(np.hypot(obs[0], obs[1]))  # velocimeter x, y (facts B1)
            nxt, reward, cost, terminated, truncated, info = env.step(action)
            episode_return += reward
            steps += 1
            done = terminated or truncated
            if cost > 0:
                violations += 1
                cost_sum += 1
                speeds_in.append(speed)
                for term in COST_TERMS:
                    if info.get(term, 0.0) > 0:
                        terms[term] += 1
                if info.get("cost_hazards", 0.0) > 0:
                    # An agent step repeats its action over several environment steps (facts
                    # B0); the cost counts each of them, the models see only the last state.
                    truth = env.ground_truth()
                    gap = np.hypot(*(truth["hazards"] - truth["robot_position"]).T).min()
                    if gap > truth["hazard_radius"]:
                        terms["hazard crossed between samples"] += 1
                known = bool(agent.predict_violation(nxt[None, :])[0])
                if not known:
                    step_kinds.append("hole")
                elif not foreseen:
                    step_kinds.append("unforeseen")
                elif plan["infeasible_elite_fraction"] > 0:
                    step_kinds.append("foreseen, fallback")
                else:
                    step_kinds.append("foreseen, feasible")
            else:
                speeds_out.append(speed)
                step_kinds.append(None)
            obs = nxt
        for run in violation_runs(step_kinds):
            kinds.update(run)
            dwell.append(len(run))
            if len(run) >= LONG_RUN:
                long_kinds.update(run)
        episode_costs.append(cost_sum)
        episode_returns.append(round(episode_return, 3))

    print(f"{args.run}: {args.episodes} episodes, {steps} steps, {violations} violating "
          f"(per episode: {episode_costs}; returns {episode_returns})"
          + (f", overrides {args.set}" if args.set else ""))
    print("| kind | steps | share |\n|---|---|---|")
    for kind in KINDS:
        share = kinds[kind] / violations if violations else 0.0
        print(f"| {kind} | {kinds[kind]} | {share:.2f} |")
    print("cost terms at violating steps (a step may have several): "
          + ", ".join(f"{term[5:]} {terms[term]}" for term in COST_TERMS)
          + f"; hazard steps that end outside every hazard (crossed within the agent step): "
          f"{terms['hazard crossed between samples']}")
    if dwell:
        print(f"runs of consecutive violations: {len(dwell)}, median length "
              f"{statistics.median(dwell)}, longest {max(dwell)}, share of violating steps in "
              f"runs of {LONG_RUN} or more {sum(long_kinds.values()) / violations:.2f}")
        print(f"kinds of the steps in runs of {LONG_RUN} or more: "
              + ", ".join(f"{kind} {long_kinds[kind]}" for kind in KINDS))
        print(f"robot speed (m/s): median {statistics.median(speeds_in):.3f} at violating steps, "
              f"{statistics.median(speeds_out):.3f} at the others")


if __name__ == "__main__":
    main()
