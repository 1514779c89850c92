#!/usr/bin/env python3
"""Does our constraint classifier generalise worse than the original's? (issue 12, cause 3)

Our XGBoost classifier (cmbrl.CostClassifier, 400 trees) against a LightGBM-like one
(scikit-learn's HistGradientBoostingClassifier with the original's LightGBM settings: learning
rate 0.3, 400 trees, 12 leaves, depth 8, 20 samples a leaf or 1), trained on the same
random-policy states of a task (1000 episodes of up to 50 steps, as pre-training collects them;
every unsafe state and 3 n_unsafe + 1 safe ones, as a fit takes them) and scored on fresh states
of other episodes. Needs Debian's python3-sklearn (not a dependency of cmbrl).

Also prints the ceiling of any classifier of the end state: a label is the cost of the whole agent
step (facts B0: 2 or 3 environment steps), but the classifier sees only where the step ended, so
an unsafe step that ended outside every hazard cannot be told apart. The row "state geometry"
calls a state unsafe when a hazard in it lies within the hazard radius (0.2 m, facts A3) of the
robot: the hazards' positions are part of the state (facts B1), so it needs no training.

    PYTHONPATH=build/python python3 scripts/classifier-generalisation.py [TASK] [SEED]
"""
import sys
import time

import numpy as np
from sklearn.ensemble import HistGradientBoostingClassifier

import cmbrl

TASK = sys.argv[1] if len(sys.argv) > 1 else "PointGoal2"
SEED = int(sys.argv[2]) if len(sys.argv) > 2 else 1

def collect(seed, episodes, steps):
    env = cmbrl.make(TASK)
    rng = np.random.default_rng(seed)
    X, y = [], []
    env.reset(seed=seed)
    for ep in range(episodes):
        for t in range(steps):
            o, r, c, te, tr, info = env.step(rng.uniform(-1, 1, 2))
            if info["goal_met"] or te or tr: break
            X.append(o); y.append(c > 0)
        env.reset()
    return np.array(X), np.array(y)

X, y = collect(SEED, 1000, 50)
Xt, yt = collect(SEED + 1000, 300, 100)
print(TASK, "seed", SEED, "train", len(y), "unsafe", y.sum(), "| test", len(yt), "unsafe", yt.sum())

HAZARD_RADIUS = 0.2  # facts A3: hazards_size


def in_hazard(states):
    """Whether a hazard of the state lies within the hazard radius of the robot (facts B1)."""
    names = cmbrl.make(TASK).observation_names
    xs = [i for i, n in enumerate(names) if n.startswith("hazard") and n.endswith("_x")]
    distances = np.hypot(states[:, xs], states[:, [i + 1 for i in xs]])
    return (distances <= HAZARD_RADIUS).any(axis=1)


geometric = in_hazard(Xt)
print(f"state geometry: fresh recall {geometric[yt].mean():.3f}, false alarms "
      f"{geometric[~yt].mean():.3f} (unsafe steps that ended outside every hazard: "
      f"{(~geometric[yt]).mean():.3f})")
# The original's fit: every unsafe state and 3 n_unsafe + 1 safe ones (the newest here).
safe_idx = np.flatnonzero(~y)[-(3 * y.sum() + 1):]
idx = np.concatenate([np.flatnonzero(y), safe_idx])
Xf, yf = X[idx], y[idx]
for name, model in [
    ("xgboost 400 (ours)", None),
    ("lightgbm-like 400, min 20 a leaf", HistGradientBoostingClassifier(learning_rate=0.3, max_iter=400, max_leaf_nodes=12, max_depth=8, min_samples_leaf=20, l2_regularization=0.0, early_stopping=False, random_state=SEED)),
    ("lightgbm-like 400, min 1 a leaf", HistGradientBoostingClassifier(learning_rate=0.3, max_iter=400, max_leaf_nodes=12, max_depth=8, min_samples_leaf=1, l2_regularization=0.0, early_stopping=False, random_state=SEED)),
]:
    t = time.time()
    if model is None:
        c = cmbrl.CostClassifier(X.shape[1], rounds=400, seed=SEED)
        c.fit(Xf, yf)
        p, ptrain = c.predict(Xt), c.predict(Xf)
    else:
        model.fit(Xf, yf)
        p, ptrain = model.predict(Xt).astype(bool), model.predict(Xf).astype(bool)
    print(f"{name}: train recall {ptrain[yf].mean():.3f}; fresh recall {p[yt].mean():.3f}, false alarms {p[~yt].mean():.3f} ({time.time()-t:.1f} s)")
