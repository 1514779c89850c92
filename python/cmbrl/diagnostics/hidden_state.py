"""Whether a robot's observation holds its motion state: how much of one agent step's motion the
observed motion and the action explain, and how much the previous action adds.

A robot whose observation holds its whole motion state (the paper's Point: its velocity and yaw
rate are its velocity state) moves, in its own frame, as a function of what it observes and the
action it is given; nothing from before adds to that. If the motion depends on a state the
observation lacks (a steering angle, a wheel's speed, a bounce), the previous action and the
previous observation carry some of it, and adding them explains more of the next step.

Data: episodes of uniform random actions, one per agent step (the pre-training's, facts B5), so
the previous action is independent of the current one and can matter only through the robot's
state. Inputs (each start state t): the observed motion m_t = (velocimeter_x, velocimeter_y,
gyro_z), the action a_t, and a pair of extra features: the previous action a_(t-1), or, as the
control, an unrelated action (the previous actions shuffled across steps: the same number of
inputs, of the same spread, carrying nothing). Targets: one agent step's motion in the robot's
frame at t: the displacement (forward, left) and the heading change, from the pose that the
hazards' ego-frame coordinates fix (open_loop.pose_from_ego), and the next observed motion
m_(t+1). Regression: the dynamics ensemble's own fit (cmbrl.Ensemble, ENSEMBLE members of
HIDDEN, their mean), on the first 80% of episodes, judged on the rest; the measure is the
held-out unexplained fraction, mean squared error over the target's variance. Steps that met a
goal or ended are left out.

Reading: the robot's observation lacks a motion state when the previous action leaves the
displacement's or the heading change's unexplained fraction a quarter or more below the
unrelated action's, and by at least FLOOR (half a percent of the target's variance: below it
the fit's own noise decides). The paper's Point, whose observation is its velocity state, is the
robot-level control. (A first version regressed with nearest neighbours; there the previous
action, being partly redundant with m_t, costs the neighbour search less than an unrelated
input does, and it "explained" 22-30% of the Point's motion too. The reading above was fixed
before the ensemble's first run.)

Usage:
  PYTHONPATH=build/python python3 -m cmbrl.diagnostics.hidden_state --task CarGoal2 \\
      --task PointGoal2 [--episodes 300] [--seed 0] [--variant paper]
Prints a Markdown table, one row per task and feature set.
"""
import argparse

import numpy as np

import cmbrl
from cmbrl.diagnostics.open_loop import hazard_slots, pose_from_ego, wrap

TARGETS = ("forward move", "left move", "heading change", "next velocimeter_x",
           "next velocimeter_y", "next gyro_z")
FEATURE_SETS = {
    "+ an unrelated action (control)": "unrelated_action",
    "+ previous action": "previous_action",
}
ENSEMBLE = 2
HIDDEN = (200, 200)
EPOCHS = 50
LACKS = 0.25
FLOOR = 0.005  # a relative drop of this much in the unexplained fraction: a state is missing


def collect(task, variant, episodes, seed):
    """Per usable step: features and targets (dict of arrays), and each step's episode index."""
    env = cmbrl.make(task, variant=variant)
    names = env.observation_names
    slots = hazard_slots(names)
    motion_index = [names.index(n) for n in ("velocimeter_x", "velocimeter_y", "gyro_z")]
    rng = np.random.default_rng(seed)
    rows = {key: [] for key in ("motion", "action", "previous_action", "previous_motion",
                                "target", "episode")}
    for k in range(episodes):
        obs, _ = env.reset(seed=seed + k)
        hazards = env.ground_truth()["hazards"]
        previous_obs, previous_action, done = None, None, False
        while not done:
            action = rng.uniform(-1.0, 1.0, size=env.action_space.shape[0])
            nxt, _, _, terminated, truncated, info = env.step(action)
            done = terminated or truncated
            if previous_obs is not None and not (info.get("goal_met") or done):
                (start, end), (yaw0, yaw1), _ = pose_from_ego(np.stack([obs[slots], nxt[slots]]),
                                                              hazards)
                c, s = np.cos(yaw0), np.sin(yaw0)
                offset = end - start
                rows["motion"].append(obs[motion_index])
                rows["action"].append(action)
                rows["previous_action"].append(previous_action)
                rows["previous_motion"].append(previous_obs[motion_index])
                rows["target"].append([c * offset[0] + s * offset[1],
                                       -s * offset[0] + c * offset[1], wrap(yaw1 - yaw0),
                                       *nxt[motion_index]])
                rows["episode"].append(k)
            previous_obs, previous_action, obs = obs, action, nxt
    env.close()
    data = {key: np.array(value, dtype=float) for key, value in rows.items()}
    data["unrelated_action"] = data["previous_action"][rng.permutation(len(data["target"]))]
    return data


def unexplained(data, extra, held_out=0.2, seed=0):
    """Held-out unexplained fraction per target of an MLP ensemble given the observed motion, the
    action and one extra pair of features.

    The fit is the training's own (cmbrl.Ensemble: 85/15 split, early stopping, inputs
    standardised), as a map from "state" (m_t, extra, 0) to "next state" (the six targets)."""
    state = np.concatenate([data["motion"], data[extra], np.zeros((len(data["motion"]), 1))],
                           axis=1)
    y = data["target"]
    episodes = data["episode"]
    split = np.quantile(np.unique(episodes), 1.0 - held_out)
    train, test = episodes < split, episodes >= split
    model = cmbrl.Ensemble(state.shape[1], data["action"].shape[1], ensemble_size=ENSEMBLE,
                           hidden_sizes=HIDDEN, max_epochs=EPOCHS, seed=seed)
    model.fit(state[train], data["action"][train], y[train])
    predicted = model.predict(state[test], data["action"][test]).mean(axis=0)
    return np.mean((predicted - y[test]) ** 2, axis=0) / y[test].var(axis=0)


def study(task, variant, episodes, seed):
    data = collect(task, variant, episodes, seed)
    fractions = {name: unexplained(data, extra, seed=seed) for name, extra in FEATURE_SETS.items()}
    control = fractions["+ an unrelated action (control)"]
    with_action = fractions["+ previous action"]
    drops = 1.0 - with_action[:3] / control[:3]  # the displacement and the heading change
    lacks = (drops >= LACKS) & (control[:3] - with_action[:3] >= FLOOR)
    return {"task": task, "steps": len(data["target"]), "fractions": fractions,
            "drop": drops, "lacks_state": bool(np.any(lacks))}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--task", action="append", required=True)
    parser.add_argument("--variant", default="paper")
    parser.add_argument("--episodes", type=int, default=300)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    if args.episodes < 5:
        parser.error(f"--episodes {args.episodes}: expected at least 5 (a fifth are held out)")
    print(f"Held-out unexplained fraction (MSE / variance) of one agent step's motion, an "
          f"ensemble of {ENSEMBLE} x {HIDDEN}, {args.episodes} episodes of uniform random "
          "actions a task "
          f"(seeds {args.seed} + k), variant {args.variant}.\n")
    print("| task | steps | features | " + " | ".join(TARGETS) + " |")
    print("|---|---|---|" + "---|" * len(TARGETS))
    verdicts = []
    for task in args.task:
        result = study(task, args.variant, args.episodes, args.seed)
        for name, fraction in result["fractions"].items():
            print(f"| {task} | {result['steps']} | {name} | "
                  + " | ".join(f"{v:.4f}" for v in fraction) + " |")
        verdicts.append(f"{task}: against the unrelated action, the previous action lowers the "
                        "unexplained fraction of the "
                        "forward move, left move and heading change by "
                        + ", ".join(f"{d:.0%}" for d in result["drop"])
                        + (": the observation lacks a motion state" if result["lacks_state"]
                           else ": no missing motion state shows"))
    print("\n" + "\n".join(verdicts))


if __name__ == "__main__":
    main()
