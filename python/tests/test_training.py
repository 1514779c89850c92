"""Training from Python, resuming, and acting with a trained run's agent and models."""
import csv
import os

import numpy as np
import pytest

import cmbrl
from conftest import tiny_config

TINY = tiny_config(300)


def rows(run_dir):
    """progress.csv without its clock columns."""
    with open(run_dir / "progress.csv") as f:
        return [{k: v for k, v in row.items() if k not in ("Time", "MsPerPlan", "CpuTime")}
                for row in csv.DictReader(f)]


def test_train_resume_and_act(tmp_path, source_dir):
    seen = []
    summary = cmbrl.train(config=TINY, out=tmp_path / "run", steps=200, progress=seen.append)
    assert summary["steps"] >= 200 and summary["budget"] == 200
    # Where the call's time went, as `cmbrl train`'s last line says: parts of its wall seconds,
    # and its CPU seconds, which its cores bound.
    split = summary["seconds_this_session"]
    assert list(split) == ["planning", "environment", "dynamics_fits", "classifier_fits",
                           "checkpoints", "other"]
    assert all(seconds >= 0 for seconds in split.values()) and split["planning"] > 0
    assert 0 < summary["cpu_seconds_this_session"] <= sum(split.values()) * os.cpu_count() + 0.01
    assert seen and seen[-1]["steps"] == summary["steps"]
    # An MPC unit is an episode: the call ended one per progress call, and their cost is the
    # progress rows' EpCost.
    assert summary["episodes_this_session"] == len(seen)
    assert all(d["episodes"] == 1 for d in seen)
    assert summary["cost_this_session"] == sum(d["episode_cost"] for d in seen)
    assert summary["cost_this_session"] == sum(float(r["EpCost"]) for r in rows(tmp_path / "run"))
    assert {"epoch", "episode_return", "episode_cost", "seconds"} <= set(seen[0])
    # Continued to 300 steps, the rows are those of a run made with 300 from the start (the
    # YAML file of the same settings).
    cmbrl.train(resume=tmp_path / "run", steps=300)
    cmbrl.train(config=source_dir / "tests" / "cli" / "tiny-rce.yaml", out=tmp_path / "whole")
    assert rows(tmp_path / "run") == rows(tmp_path / "whole")

    agent = cmbrl.load_run(tmp_path / "run", seed=1)
    assert agent.is_mpc and "planner: rce" in agent.config()
    assert (agent.task, agent.variant, agent.spawn) == ("PointGoal1", "paper", "standing")
    env = agent.make_env()
    obs, _ = env.reset(seed=2)
    agent.begin_episode()
    for call in (agent.last_plan, lambda: agent.predictions(env)):  # no plan yet: named
        with pytest.raises(cmbrl.Error, match=r"before act\(\): the agent has made no plan yet"):
            call()
    action = agent.act(obs)
    assert action.shape == (2,) and np.all(np.abs(action) <= 1)
    plan = agent.last_plan()
    assert plan["actions"].shape == (3, 2)
    paths = agent.predictions(env, samples=4)
    members = 1 + max(p["member"] for p in paths)
    assert len(paths) == (4 + 1) * members  # 4 samples and the executed plan, every member
    assert [p["chosen"] for p in paths] == [False] * 4 * members + [True] * members
    assert all(p["points"].shape == (4, 2) for p in paths)
    # Asked again about the same plan, with more samples than its population (24): the same
    # plan every time, not the executed plan's re-evaluation (36 paths, then 8, before v0.7).
    again = agent.predictions(env, samples=4)
    assert all(np.array_equal(a["points"], b["points"]) for a, b in zip(paths, again))
    assert len(agent.predictions(env, samples=1000)) == (24 + 1) * members
    states = np.repeat(obs[None, :], 5, axis=0)
    nxt = agent.predict_next(states, np.zeros((5, 2)))
    assert nxt.shape[1:] == (5, obs.shape[0]) and np.isfinite(nxt).all()
    verdict = agent.predict_violation(states)
    assert verdict.dtype == bool and verdict.shape == (5,)
    with pytest.raises(cmbrl.Error, match="observation"):
        agent.act(np.zeros(3))

    # Overrides change the planner, not the models: a threshold no probability reaches leaves
    # every sample feasible; one every probability exceeds leaves none.
    for threshold, feasible in ((0.999999, 1.0), (0.000001, 0.0)):
        changed = cmbrl.load_run(tmp_path / "run", seed=1,
                                 overrides={"classifier.threshold": threshold,
                                            "planning.population": 12})
        assert "population: 12" in changed.config()
        changed.begin_episode()
        changed.act(obs)
        assert changed.last_plan()["feasible_fraction"] == feasible
        assert np.array_equal(changed.predict_next(states, np.zeros((5, 2))), nxt)
    with pytest.raises(cmbrl.Error, match="shape its models"):
        cmbrl.load_run(tmp_path / "run", overrides=["ensemble.max_epochs=1"])
    # Another planner on the same models.
    cem = cmbrl.load_run(tmp_path / "run", seed=1, overrides={"planner": "cem"})
    assert "planner: cem" in cem.config()
    cem.begin_episode()
    assert cem.act(obs).shape == (2,)

    # Scores: the same models and objective judge any planner's plans from one state.
    plan = cem.last_plan()["actions"]
    scores = agent.score(obs, np.stack([plan, np.zeros_like(plan)]))
    assert scores["reward_cost"].shape == (2,) and scores["feasible"].dtype == bool
    assert np.array_equal(scores["feasible"], scores["constraint_cost"] == 0)
    again = agent.score(obs, plan[None])  # a sequence's score does not depend on its company
    assert again["reward_cost"][0] == pytest.approx(scores["reward_cost"][0], rel=1e-5)
    strict = cmbrl.load_run(tmp_path / "run", overrides={"classifier.threshold": 0.000001})
    assert not strict.score(obs, plan[None])["feasible"][0]  # every state called unsafe
    with pytest.raises(cmbrl.Error, match=r"expected \(N, 3, 2\)|shape"):
        agent.score(obs, np.zeros((2, 5, 2)))
    with pytest.raises(cmbrl.Error, match="action bounds"):
        agent.score(obs, np.full((1, 3, 2), 1.5))
    with pytest.raises(cmbrl.Error, match="observation"):
        agent.score(np.zeros(3), plan[None])
    agent.act(obs)
    agent.score(obs, plan[None])
    with pytest.raises(cmbrl.Error, match="after score"):
        agent.predictions(env, samples=2)


def test_bad_training_input_is_named(tmp_path):
    bad = dict(TINY, planner="sideways")
    with pytest.raises(cmbrl.Error, match="sideways"):
        cmbrl.train(config=bad, out=tmp_path / "bad")
    assert not (tmp_path / "bad").exists()
    with pytest.raises(cmbrl.Error, match="no run"):
        cmbrl.load_run(tmp_path)
    with pytest.raises(cmbrl.Error, match="resume"):
        cmbrl.train(resume=tmp_path, seed=3)


def test_a_progress_callback_that_raises_stops_training_and_the_run_resumes(tmp_path):
    def stop(summary):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        cmbrl.train(config=TINY, out=tmp_path / "run", steps=200, progress=stop)
    summary = cmbrl.train(resume=tmp_path / "run")
    assert summary["steps"] >= 200
    cmbrl.train(config=TINY, out=tmp_path / "whole", steps=200)
    assert rows(tmp_path / "run") == rows(tmp_path / "whole")


def test_ctrl_c_in_the_middle_of_an_episode_stops_at_a_checkpoint_and_the_run_resumes(tmp_path):
    import os
    import signal
    import threading

    timers = []

    def interrupt_soon(summary):  # after the first episode: Ctrl-C lands in a later one
        if not timers:
            timers.append(threading.Timer(0.1, os.kill, (os.getpid(), signal.SIGINT)))
            timers[0].start()

    try:
        with pytest.raises(KeyboardInterrupt):
            cmbrl.train(config=TINY, out=tmp_path / "run", steps=400, progress=interrupt_soon,
                        checkpoint_seconds=1e9)
    finally:
        timers[0].join()
    # The run stopped short of its budget, at a checkpoint of the step it had reached.
    assert len(rows(tmp_path / "run")) < 4
    summary = cmbrl.train(resume=tmp_path / "run")
    assert summary["steps"] >= 400
    cmbrl.train(config=TINY, out=tmp_path / "whole", steps=400)
    assert rows(tmp_path / "run") == rows(tmp_path / "whole")


@pytest.mark.parametrize("seconds", [-1, float("nan"), float("inf"), "60", True, None])
def test_a_bad_checkpoint_interval_is_named(tmp_path, seconds):
    with pytest.raises(cmbrl.Error, match=r"checkpoint_seconds is .*: expected a finite number"):
        cmbrl.train(config=TINY, out=tmp_path / "run", checkpoint_seconds=seconds)
    assert not (tmp_path / "run").exists()


def test_checkpoints_after_every_step_change_no_row(tmp_path):
    cmbrl.train(config=TINY, out=tmp_path / "every", steps=200, checkpoint_seconds=0)
    cmbrl.train(config=TINY, out=tmp_path / "whole", steps=200)
    assert rows(tmp_path / "every") == rows(tmp_path / "whole")


def test_a_model_free_run_acts_with_its_policy_mean(tmp_path):
    config = {"task": "PointGoal1", "variant": "paper-lidar", "algorithm": "trpo-lagrangian",
              "training": {"total_steps": 600},
              "policy_optimisation": {"steps_per_epoch": 300, "envs": 2, "value_iterations": 2,
                                      "policy_hidden": [8], "value_hidden": [8]}}
    cmbrl.train(config=config, out=tmp_path / "mf")
    agent = cmbrl.load_run(tmp_path / "mf")
    assert not agent.is_mpc
    env = agent.make_env()
    assert (env.task, env.variant) == ("PointGoal1", "paper-lidar")
    obs, _ = env.reset(seed=0)
    assert agent.act(obs).shape == (2,)
    with pytest.raises(cmbrl.Error, match="not an MPC run"):
        agent.predict_violation(obs[None, :])


def test_the_example_trains_evaluates_and_draws(tmp_path, source_dir):
    import os
    import subprocess
    import sys

    out = tmp_path / "example"
    subprocess.run([sys.executable, str(source_dir / "examples" / "train_quickstart.py"),
                    "--config", str(source_dir / "tests" / "cli" / "tiny-rce.yaml"), "--out", str(out),
                    "--steps", "100"], check=True, env=dict(os.environ), stdout=subprocess.PIPE)
    assert (out / "python-evaluation.png").stat().st_size > 10_000


def test_a_config_dict_must_name_its_task_and_may_hold_numpy_numbers(tmp_path):
    with pytest.raises(cmbrl.Error, match="names no task"):
        cmbrl.train(config={}, out=str(tmp_path / "none"))
    config = tiny_config(40)
    config["planning"]["population"] = np.int64(24)
    config["objective"] = {"gamma": np.float32(0.98)}
    result = cmbrl.train(config=config, out=str(tmp_path / "numpy"))
    assert result["steps"] >= 40


def test_evaluate_gives_what_cmbrl_eval_gives(tmp_path, cmbrl_binary):
    import json
    import subprocess

    cmbrl.train(config=tiny_config(100), out=tmp_path / "run")
    [ours] = cmbrl.evaluate(tmp_path / "run", episodes=1, seed=1)
    line = subprocess.run([cmbrl_binary, "eval", "--run", str(tmp_path / "run"), "--episodes", "1",
                           "--seed", "1"], check=True, stdout=subprocess.PIPE, text=True).stdout
    theirs = json.loads(line)
    # The navigation world's counts beside the sums; the same episode (the clock aside).
    counts = ["goals_met", "hazard_steps", "vase_steps", "mean_goal_distance", "steps_near_goal"]
    shared = ["return", "cost", "steps", "feasible_fraction", "fallback_steps"] + counts
    assert {key: ours[key] for key in shared} == {key: theirs[key] for key in shared}
    assert ours["steps_near_goal"] >= ours["goals_met"]
    assert ours["hazard_steps"] + ours["vase_steps"] >= ours["cost"]  # a violation is one or both


def test_the_gymnasium_loop_example_runs(source_dir):
    import os
    import subprocess
    import sys

    done = subprocess.run([sys.executable, str(source_dir / "examples" / "gymnasium_loop.py"),
                           "--num-envs", "2", "--steps", "1001"], check=True,
                          env=dict(os.environ), stdout=subprocess.PIPE, text=True)
    assert "(PointGoal1, standard): 2 episodes ended in 1001 steps" in done.stdout


def _goal_reward(calls):
    """A Python planning reward: minus the goal distance of the predicted state (the Goal tasks'
    analytic term without its bonuses), recording each call's array shapes."""
    def reward(states, actions, next_states):
        calls.append((states.shape, actions.shape, next_states.shape, states.dtype))
        return -np.linalg.norm(next_states[:, 6:8], axis=1)
    return reward


def test_a_python_reward_is_called_once_per_planner_iteration_on_every_predicted_step(tmp_path):
    config = tiny_config(60)
    config["ensemble"]["ensemble_size"] = 3
    calls = []
    summary = cmbrl.train(config=config, out=tmp_path / "run", reward=_goal_reward(calls))
    # RCE (2 iterations a plan, none skipped) rolls every member: horizon 3 x 3 members x 24.
    assert len(calls) == 2 * summary["steps"]
    assert set(calls) == {((216, 24), (216, 2), (216, 24), np.dtype(np.float64))}  # PointGoal1: S 24
    with open(tmp_path / "run" / "config.yaml") as f:
        assert "reward: python" in f.read()
    # Each session names the function it planned with.
    with open(tmp_path / "run" / "sessions.jsonl") as f:
        assert ('"python_functions":"reward=test_training._goal_reward.<locals>.reward"'
                in f.read())
    # The run needs its function again to go on or to act, and the command line has none.
    with pytest.raises(cmbrl.Error, match="objective.reward is 'python': the run plans with a "
                                          "reward function given from Python"):
        cmbrl.train(resume=tmp_path / "run", steps=summary["steps"] + 50)
    with pytest.raises(cmbrl.Error, match="objective.reward is 'python'"):
        cmbrl.load_run(tmp_path / "run")
    cmbrl.train(resume=tmp_path / "run", steps=summary["steps"] + 50, reward=_goal_reward(calls))
    agent = cmbrl.load_run(tmp_path / "run", reward=_goal_reward(calls))
    before = len(calls)
    agent.begin_episode()
    action = agent.act(agent.make_env().reset(seed=0)[0])
    assert action.shape == (2,) and len(calls) == before + 2
    # A run with its task's analytic reward takes none.
    cmbrl.train(config=tiny_config(20), out=tmp_path / "analytic")
    with pytest.raises(cmbrl.Error, match="plans with objective.reward 'analytic': give no "
                                          "reward function"):
        cmbrl.load_run(tmp_path / "analytic", reward=_goal_reward([]))


def test_a_bad_python_reward_is_named(tmp_path):
    with pytest.raises(cmbrl.Error, match="reward is 3: expected a function"):
        cmbrl.train(config=tiny_config(20), out=tmp_path / "number", reward=3)

    def wrong_shape(states, actions, next_states):
        return np.zeros((2, 2))

    with pytest.raises(cmbrl.Error, match=r"the reward function .*wrong_shape: the result has "
                                          r"shape \(2, 2\): expected \(\d+,\)"):
        cmbrl.train(config=tiny_config(20), out=tmp_path / "shape", reward=wrong_shape)

    def raises(states, actions, next_states):
        raise RuntimeError("no reward here")

    with pytest.raises(cmbrl.Error, match="the reward function .*raises raised RuntimeError: no "
                                          "reward here"):
        cmbrl.train(config=tiny_config(20), out=tmp_path / "raises", reward=raises)

    def two_arguments(states, actions):  # the form it is called in is named
        return np.zeros(len(states))

    with pytest.raises(cmbrl.Error, match=r"raised TypeError: .* \(it is called as "
                                          r"reward\(states, actions, next_states\), arrays of "
                                          r"(\d+) rows, and returns \1 values\)"):
        cmbrl.train(config=tiny_config(20), out=tmp_path / "two", reward=two_arguments)

    def not_finite(states, actions, next_states):
        return np.full(len(states), np.nan)

    with pytest.raises(cmbrl.Error, match="returned nan: expected finite rewards"):
        cmbrl.train(config=tiny_config(20), out=tmp_path / "nan", reward=not_finite)


def test_a_python_termination_is_called_beside_the_reward_and_checked(tmp_path):
    calls = []

    def never(states, actions, next_states):
        calls.append(len(states))
        return np.zeros(len(states), dtype=bool)

    summary = cmbrl.train(config=tiny_config(20), out=tmp_path / "run", termination=never)
    assert len(calls) == 2 * summary["steps"]  # once per planner iteration, as the reward
    with open(tmp_path / "run" / "config.yaml") as f:
        text = f.read()
    assert "termination: python" in text and "reward: analytic" in text
    with pytest.raises(cmbrl.Error, match="objective.termination is 'python'"):
        cmbrl.load_run(tmp_path / "run")
    cmbrl.load_run(tmp_path / "run", termination=never).act(np.zeros(24))

    def two(states, actions, next_states):
        return np.full(len(states), 2.0)

    with pytest.raises(cmbrl.Error, match=r"the termination function .*two returned 2: expected "
                                          r"booleans \(or 0 and 1\)"):
        cmbrl.train(config=tiny_config(20), out=tmp_path / "two", termination=two)


def test_presets_ship_in_the_package_and_are_named_not_pathed(tmp_path):
    names = cmbrl.presets()
    for name in ("pointgoal1-rce", "quickstart", "cpu", "pointbutton1-cem",
                 "pointgoal1-ppo-lagrangian"):
        assert name in names
    with pytest.raises(cmbrl.Error, match="'pointgoal9-rce' is neither a file nor a preset"):
        cmbrl.train(config=["pointgoal9-rce", "quickstart"], out=str(tmp_path / "r"))
    with pytest.raises(cmbrl.Error, match=r"'quickstrat' is neither a file nor a preset \(did "
                                          r"you mean 'quickstart'\?\)"):
        cmbrl.train(config=["pointgoal1-rce", "quickstrat"], out=str(tmp_path / "r"))


def test_rce_icem_trains_resumes_and_acts_from_python(tmp_path):
    # The sample-economy planner by name, its own keys in the planning section; 2 iterations of
    # 24 then 19 new samples, one elite kept (floor(0.3 * 6)).
    config = tiny_config(120)
    config["planner"] = "rce-icem"
    config["planning"].update({"population_decay": 1.25, "keep_elites": 0.3,
                               "noise_exponent": 2.5})
    cmbrl.train(config=config, out=tmp_path / "run", steps=80)
    cmbrl.train(resume=tmp_path / "run", steps=120)
    cmbrl.train(config=config, out=tmp_path / "whole")
    assert rows(tmp_path / "run") == rows(tmp_path / "whole")
    agent = cmbrl.load_run(tmp_path / "run", seed=1)
    assert "planner: rce-icem" in agent.config() and "noise_exponent: 2.5" in agent.config()
    env = agent.make_env()
    obs, _ = env.reset(seed=2)
    agent.begin_episode()
    for _ in range(3):
        action = agent.act(obs)
        assert action.shape == (2,) and np.all(np.abs(action) <= 1)
        obs, *_ = env.step(action)
    plan = agent.last_plan()
    assert plan["actions"].shape == (3, 2) and plan["iterations"] == 2
    # The executed plan is the best sample, so it starts with the executed action.
    assert np.allclose(plan["actions"][0], action)
    with pytest.raises(cmbrl.Error, match="noise_exponent is -1"):
        cmbrl.train(config={**config, "planning": {**config["planning"], "noise_exponent": -1}},
                    out=tmp_path / "bad")


def test_a_run_that_observes_the_previous_action_makes_its_env_so(tmp_path):
    config = tiny_config(150)
    config["task"] = "CarGoal1"
    config["environment"] = {"previous_action": True}
    cmbrl.train(config=config, out=tmp_path / "run")
    agent = cmbrl.load_run(tmp_path / "run")
    assert agent.previous_action
    env = agent.make_env()
    assert env.previous_action
    assert env.observation_space.shape == agent.observation_space.shape
    assert cmbrl.make("CarGoal1").observation_space.shape[0] + 2 == env.observation_space.shape[0]
    obs, _ = env.reset(seed=0)
    agent.begin_episode()
    for _ in range(3):
        obs = env.step(agent.act(obs))[0]
    # The planner's predictions carry the action taken in the previous action's components.
    states = np.repeat(obs[None, :], 4, axis=0)
    actions = np.random.default_rng(0).uniform(-1, 1, (4, 2))
    predicted = agent.predict_next(states, actions)  # (E, N, S)
    assert predicted.shape[-1] == obs.shape[0]
    np.testing.assert_allclose(predicted[..., -2:], np.broadcast_to(actions, predicted[..., -2:]
                                                                    .shape), rtol=1e-6)
