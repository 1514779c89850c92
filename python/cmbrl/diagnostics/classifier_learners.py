"""Whether the constraint classifier's holes come from its learner rather than its data: the same
labelled states fitted by cmbrl's classifier and by a LightGBM-style learner, judged on layouts
none of them saw.

The original's classifier is LightGBM's LGBMClassifier with every parameter but five at its
default (facts B4); among the defaults is min_data_in_leaf 20: no leaf holds fewer than 20
training states. cmbrl's classifier is XGBoost set up as that LightGBM (leaf-wise growth, 12
leaves, depth 8, learning rate 0.3, 400 rounds, no L2 term, min hessian 1e-3), but XGBoost has no
floor on a leaf's state count: a leaf may hold one state. A leaf of a few states fits one
layout's hazard where it was, which on another layout is a false alarm far from any hazard, and
takes its share of the tree's 12 leaves from the boundaries that carry over.

The LightGBM-style learner is scikit-learn's HistGradientBoostingClassifier, modelled on
LightGBM (histograms of 255 bins, leaf-wise growth, min_samples_leaf = LightGBM's
min_data_in_leaf, min_hessian_to_split = its min_sum_hessian_in_leaf 1e-3), set to the original's
five parameters, with no early stopping and no L2 term, at 20 states a leaf (LightGBM's default)
and at 1 (the control: the same learner without the floor). If the floor of 20 raises the
recall inside hazards and lowers the false alarms far from them against the floor of 1, the
leaf floor, which cmbrl lacks, is a difference that matters. The reading, fixed before the
first run: the floor matters for a task when, on every seed, the floor of 20 calls a larger share
of the hazards' insides unsafe than the floor of 1 does, by 0.05 or more on the seeds' mean, and
calls no larger share of the states far from hazards and vases unsafe.

Data, as the pre-training's (facts B4, B6): EPISODES episodes of uniform random actions on
layouts seed + k, each stopped after STEPS stored agent steps; each stored step's next state is
labelled unsafe when the step paid a cost; steps that met the goal or ended are not stored. A
fit takes every unsafe state and the last 3 n_unsafe + 1 safe ones, as the original's. Judged
on classifier_recall's states (random-action episodes on layouts eval_seed + k), split by the
distance to the nearest hazard.

Usage:
  PYTHONPATH=build/python python3 -m cmbrl.diagnostics.classifier_learners --task CarGoal2 \\
      [--task PointGoal2 ...] [--seeds 0 1 2] [--episodes 1000] [--steps 50] \\
      [--eval-episodes 150] [--eval-seed 5000] [--variant paper]
Prints a Markdown table, one row per task, seed and learner; with --labels-only, instead, what
the unsafe labels are made of (the share each cost term paid), one row per task and seed. Needs
scikit-learn for the LightGBM-style rows (Debian: python3-sklearn); without it only cmbrl's rows
are made.
"""
import argparse
import time

import numpy as np

import cmbrl
from cmbrl.diagnostics.classifier_recall import NEAR, called_unsafe, states_by_distance
from cmbrl.models import CostClassifier

LIGHTGBM = dict(learning_rate=0.3, max_iter=400, max_leaf_nodes=12, max_depth=8,
                l2_regularization=0.0, early_stopping=False)  # the original's five, facts B4


TERMS = ("cost_hazards", "cost_vases_contact", "cost_vases_velocity")


def label_term(info):
    """Which cost made a step unsafe, the first of TERMS that paid (hazards before a vase's
    contact before a vase's speed), "other" for any other term."""
    for term in TERMS:
        if info.get(term, 0.0) > 0.0:
            return term
    return "other"


def labelled_states(task, variant, episodes, steps, seed, terms=None):
    """The pre-training's labelled next states: (states (N, S), unsafe (N) bool), in storage
    order. `terms`, a list, receives label_term of each unsafe state, in order."""
    env = cmbrl.make(task, variant=variant)
    rng = np.random.default_rng(seed)
    states, unsafe = [], []
    for k in range(episodes):
        env.reset(seed=seed + k)
        stored = 0
        while stored < steps:
            obs, _, cost, terminated, truncated, info = env.step(
                rng.uniform(-1.0, 1.0, size=env.action_space.shape[0]))
            end = terminated or truncated
            if not (info.get("goal_met") or end):
                states.append(obs)
                unsafe.append(cost > 0.0)
                if cost > 0.0 and terms is not None:
                    terms.append(label_term(info))
                stored += 1
            if end:
                break
    env.close()
    return np.array(states, dtype=float), np.array(unsafe, dtype=bool)


def fit_set(states, unsafe):
    """The fit set a run takes (the original's): every unsafe state and the newest 3 n_unsafe + 1
    safe ones, by cmbrl's own selection (CostClassifier.fit_set)."""
    return CostClassifier(states.shape[1]).fit_set(states, unsafe)


def learners(seed):
    """(name, make) pairs: each make() gives an object with fit(x, y) and predict(x) -> bool."""
    found = [("cmbrl (XGBoost, no leaf floor)", lambda width: _Cmbrl(width, seed))]
    try:
        from sklearn.ensemble import HistGradientBoostingClassifier  # type: ignore[import]
    except ImportError:
        return found
    for floor in (20, 1):
        found.append((f"LightGBM-style, {floor} a leaf",
                      lambda width, floor=floor: _Sklearn(HistGradientBoostingClassifier(
                          min_samples_leaf=floor, random_state=seed, **LIGHTGBM))))
    return found


class _Cmbrl:
    def __init__(self, width, seed):
        self.model = CostClassifier(width, seed=seed)

    def fit(self, x, y):
        self.model.fit(x, y)

    def predict(self, x):
        return np.asarray(self.model.predict(x), dtype=bool)


class _Sklearn:
    """One OpenMP thread: on a machine busy with other work, scikit-learn's threads wait on
    each other (a fit that takes 7 s alone took 300 s beside two training runs), and the
    comparison is of learners, not of their threading."""

    def __init__(self, model):
        self.model = model

    def fit(self, x, y):
        from threadpoolctl import threadpool_limits  # type: ignore[import]  # sklearn's
        with threadpool_limits(limits=1):
            self.model.fit(x, y.astype(int))

    def predict(self, x):
        from threadpoolctl import threadpool_limits  # type: ignore[import]
        with threadpool_limits(limits=1):
            return self.model.predict(x).astype(bool)


def print_label_terms(args):
    """The share of the unsafe labels each cost term made, per task and seed."""
    print(f"What the pre-training's unsafe labels are made of ({args.episodes} random-action "
          f"episodes of {args.steps} stored steps): the share of unsafe states whose step paid "
          f"each cost (the first that paid, in the order of the columns).\n")
    print("| task | seed | stored | unsafe | " + " | ".join(TERMS) + " | other |")
    print("|---|---|---|---|" + "---|" * (len(TERMS) + 1))
    for task in args.task:
        for seed in args.seeds:
            terms = []
            _, unsafe = labelled_states(task, args.variant, args.episodes, args.steps, seed,
                                        terms)
            shares = [terms.count(t) / max(len(terms), 1) for t in TERMS + ("other",)]
            print(f"| {task} | {seed} | {len(unsafe)} | {int(unsafe.sum())} | "
                  + " | ".join(f"{x:.3f}" for x in shares) + " |", flush=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--task", action="append", required=True)
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--episodes", type=int, default=1000)
    parser.add_argument("--steps", type=int, default=50)
    parser.add_argument("--eval-episodes", type=int, default=150)
    parser.add_argument("--eval-seed", type=int, default=5000)
    parser.add_argument("--variant", default="paper")
    parser.add_argument("--labels-only", action="store_true",
                        help="print only what the unsafe labels are made of, and fit nothing")
    args = parser.parse_args(argv)
    for key in ("episodes", "steps", "eval_episodes"):
        if getattr(args, key) < 1:
            parser.error(f"--{key.replace('_', '-')} {getattr(args, key)}: expected at least 1")
    if args.labels_only:
        print_label_terms(args)
        return
    print(f"Classifiers fitted on the pre-training's labelled states ({args.episodes} "
          f"random-action episodes of {args.steps} stored steps, layouts of seed + k), judged on "
          f"{args.eval_episodes} random-action episodes of layouts {args.eval_seed} + k: the "
          f"share of states called unsafe.\n")
    print(f"| task | seed | learner | unsafe / safe fitted | inside a hazard (recall) | "
          f"within {NEAR:g} m | farther, a vase within {NEAR:g} m | farther, no vase | "
          f"fit s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for task in args.task:
        env = cmbrl.make(task, variant=args.variant)
        groups = states_by_distance(env, args.eval_episodes, args.eval_seed)
        env.close()
        for seed in args.seeds:
            states, unsafe = labelled_states(task, args.variant, args.episodes, args.steps, seed)
            x, y = fit_set(states, unsafe)
            for name, make in learners(seed):
                model = make(x.shape[1])
                start = time.perf_counter()
                model.fit(x, y)
                seconds = time.perf_counter() - start
                shares = called_unsafe(model.predict, groups)
                print(f"| {task} | {seed} | {name} | {int(y.sum())} / {int((~y).sum())} | "
                      + " | ".join(f"{s:.3f}" for s in shares) + f" | {seconds:.1f} |",
                      flush=True)


if __name__ == "__main__":
    main()
