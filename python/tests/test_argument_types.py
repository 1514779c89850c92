"""Every argument of the public API, given a value of the wrong type, is refused with a
cmbrl.Error that names the argument, before any work is done: never pybind11's signature dump
("incompatible function arguments ... Invoked with"), nor a TypeError from deep inside."""
import os

import numpy as np
import pytest

import cmbrl

WRONG = object()  # a value of no type any argument takes


def _calls(tmp):
    """(label, function, keyword arguments, the argument made wrong) for every argument that has
    a type to check. The other arguments are valid, or at least not checked before it."""
    run = os.path.join(tmp, "no-run")
    cases = []

    def each(label, function, base, names, bad=WRONG):
        for name in names:
            cases.append((f"{label}({name})", function, dict(base, **{name: bad}), name))

    each("make", cmbrl.make, {"task": "PointGoal1"},
         ["task", "variant", "spawn", "render_mode", "render_size"])
    each("make_vec", cmbrl.make_vec, {"task": "PointGoal1", "num_envs": 2},
         ["task", "num_envs", "variant", "spawn", "threads", "spin_us", "autoreset_mode"])
    each("train", cmbrl.train, {"config": "quickstart", "out": os.path.join(tmp, "t")},
         ["config", "out", "steps", "seed", "device", "resume", "progress", "checkpoint_seconds",
          "reward", "termination", "env"])
    each("load_run", cmbrl.load_run, {"run_dir": run},
         ["run_dir", "seed", "overrides", "reward", "termination", "env"])
    each("evaluate", cmbrl.evaluate, {"run_dir": run},
         ["run_dir", "episodes", "seed", "reseed_each_episode", "overrides", "reward",
          "termination", "env", "render"])
    each("read_runs", cmbrl.read_runs, {"dirs": [tmp]}, ["dirs"])
    each("report", cmbrl.report, {"dirs": [tmp], "out": os.path.join(tmp, "r")},
         ["dirs", "out", "window", "reference", "complete"])
    each("Ensemble", cmbrl.Ensemble, {"state_dim": 3, "action_dim": 2, "hidden_sizes": [8]},
         ["state_dim", "action_dim", "ensemble_size", "hidden_sizes", "max_epochs", "seed",
          "predict_delta"])
    each("CostClassifier", cmbrl.CostClassifier, {"state_dim": 3},
         ["state_dim", "rounds", "threshold", "seed"])
    each("RewardModel", cmbrl.RewardModel, {"input_dim": 3},
         ["input_dim", "hidden_sizes", "max_epochs", "seed"])
    # The wrong type that looks right: a str for a list or a number, a number for a str or path.
    each("Ensemble", cmbrl.Ensemble, {"state_dim": 3, "action_dim": 2}, ["hidden_sizes"], "64")
    each("CostClassifier", cmbrl.CostClassifier, {"state_dim": 3}, ["threshold", "rounds"], "1")
    each("make", cmbrl.make, {"task": "PointGoal1"}, ["variant", "spawn"], 3)
    each("train", cmbrl.train, {"config": "quickstart", "out": os.path.join(tmp, "t")},
         ["config", "out", "device"], 0)
    each("evaluate", cmbrl.evaluate, {"run_dir": run}, ["reseed_each_episode"], 1)
    each("load_run", cmbrl.load_run, {"run_dir": run}, ["overrides"], "planning.horizon=3")
    return cases


def test_every_argument_of_the_wrong_type_is_refused_by_name(tmp_path):
    faults, cases = [], _calls(str(tmp_path))
    for label, function, kwargs, name in cases:
        try:
            function(**kwargs)
            faults.append(f"{label}: accepted")
        except cmbrl.Error as error:
            if name not in str(error) or "Invoked with" in str(error):
                faults.append(f"{label}: {error}")
        except Exception as error:  # noqa: BLE001 (what the test is looking for)
            faults.append(f"{label}: {type(error).__name__}: {str(error)[:200]}")
    assert not faults, "\n".join(faults)
    assert len(cases) >= 60


def test_methods_refuse_wrong_types_by_name():
    env = cmbrl.make("PointGoal1")
    with pytest.raises(cmbrl.Error, match="seed"):
        env.reset(seed="3")
    with pytest.raises(cmbrl.Error, match="options"):
        env.reset(seed=0, options={"layout": 3})  # a cmbrl.Env takes no reset options
    env.reset(seed=0, options={})
    with pytest.raises(cmbrl.Error, match="action.*dtype"):
        env.step("up")
    vector = cmbrl.make_vec("PointGoal1", 2)
    with pytest.raises(cmbrl.Error, match="options"):
        vector.reset(seed=0, options=5)
    vector.reset(seed=0)
    with pytest.raises(cmbrl.Error, match="actions array has dtype"):
        vector.step(np.array([["a", "b"], ["c", "d"]]))
    vector.close()
