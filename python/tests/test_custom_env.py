"""Training on an environment given from Python (cmbrl.train(env=...)): the adapter's protocol,
its errors, checkpoints and resume, loading, and that the path itself changes no row."""
import csv
import functools
import importlib.util
import json
import pickle
import shutil

import numpy as np
import pytest

import cmbrl
from conftest import tiny_config


def rows(run_dir):
    """progress.csv without its clock columns."""
    with open(run_dir / "progress.csv") as f:
        return [{k: v for k, v in row.items() if k not in ("Time", "MsPerPlan", "CpuTime")}
                for row in csv.DictReader(f)]


def custom_env_module(source_dir):
    spec = importlib.util.spec_from_file_location("custom_env", source_dir / "examples" /
                                                  "custom_env.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def tiny(total_steps=200, **changes):
    """The tests' tiny MPC run, without a task (the env given is the task)."""
    config = tiny_config(total_steps)
    del config["task"]
    config.update(changes)
    return config


class Line:
    """A 1-D walk to x = 1 with a wall at x < -0.5 (cost 2.5 there: not 0/1), Gymnasium's
    five-value step with info["cost"], an action box of [0, 2] (mapped from cmbrl's [-1, 1])."""

    def __init__(self, length=20, fail_at=None, bad=None, wall=-0.5):
        self.observation_space = cmbrl.Box(np.array([-5.0]), np.array([5.0]))
        self.action_space = cmbrl.Box(np.array([0.0]), np.array([2.0]))
        self.length, self.fail_at, self.bad, self.wall = length, fail_at, bad, wall
        self.x, self.t, self.steps = 0.0, 0, 0
        self.actions = []

    def reset(self, seed=None, options=None):
        self.x, self.t = 0.0, 0
        return np.array([self.x]), {}

    def step(self, action):
        self.actions.append(float(action[0]))
        self.steps += 1
        if self.fail_at is not None and self.steps >= self.fail_at:
            if self.bad == "raise":
                raise RuntimeError("the simulator broke")
            if self.bad == "nan":
                return np.array([np.nan]), 0.0, False, False, {"cost": 0.0}
            if self.bad == "shape":
                return np.zeros(3), 0.0, False, False, {"cost": 0.0}
            if self.bad == "no cost":
                return np.array([self.x]), 0.0, False, False, {}
        self.x += 0.1 * (float(action[0]) - 1.0)
        self.t += 1
        cost = 2.5 if self.x < self.wall else 0.0
        return np.array([self.x]), -abs(self.x - 1.0), False, self.t >= self.length, {"cost": cost}


def line_reward(states, actions, next_states):
    return -np.abs(next_states[:, 0] - 1.0)


def stop_after_30_steps(summary):
    """Ctrl-C's path without the signal: a progress callback that raises once 30 steps are done
    (with a checkpoint after every step, the stop lands inside an episode)."""
    if summary["steps"] >= 30:
        raise KeyboardInterrupt


def test_the_example_trains_rce_on_its_own_env_then_loads_acts_and_evaluates(tmp_path,
                                                                               source_dir):
    module = custom_env_module(source_dir)
    config = tiny(200)
    cmbrl.train(env=module.DoubleIntegrator, reward=module.reward, config=config,
                out=tmp_path / "run")
    table = rows(tmp_path / "run")
    assert len(table) == 2 and int(table[-1]["TotalEnvInteracts"]) == 200
    with open(tmp_path / "run" / "config.yaml") as f:
        text = f.read()
    assert "task: python:custom_env.DoubleIntegrator()" in text
    assert "observation_size: 4" in text and "action_size: 2" in text
    with open(tmp_path / "run" / "sessions.jsonl") as f:
        session = json.loads(f.readline())
    assert session["python_functions"] == ("env=custom_env.DoubleIntegrator(), "
                                           "reward=custom_env.reward")

    agent = cmbrl.load_run(tmp_path / "run", env=module.DoubleIntegrator, reward=module.reward)
    assert agent.task == "python:custom_env.DoubleIntegrator()"
    env = agent.make_env()
    observation, _ = env.reset(seed=3)
    agent.begin_episode()
    for _ in range(5):
        action = agent.act(observation)
        assert action.shape == (2,) and np.all(np.abs(action) <= 1.0)
        observation, *_ = env.step(action)

    # Evaluated as `cmbrl eval` would: episodes of the agent in the env given.
    episodes = cmbrl.evaluate(tmp_path / "run", episodes=2, seed=5, env=module.DoubleIntegrator,
                              reward=module.reward)
    assert [e["steps"] for e in episodes] == [100, 100]
    assert all(0 <= e["cost"] <= 100 and 0 < e["feasible_fraction"] <= 1 for e in episodes)
    again = cmbrl.evaluate(tmp_path / "run", episodes=2, seed=5, env=module.DoubleIntegrator,
                           reward=module.reward)
    assert [e["return"] for e in again] == [e["return"] for e in episodes]

    # Without the env, or with another, the run is not loaded.
    with pytest.raises(cmbrl.Error, match=r"environment given from Python: give it again"):
        cmbrl.load_run(tmp_path / "run", reward=module.reward)
    with pytest.raises(cmbrl.Error, match=r"trained on task 'python:custom_env.DoubleIntegrator"):
        cmbrl.load_run(tmp_path / "run", env=Line, reward=module.reward)


def test_an_env_declared_by_name_trains_as_the_one_given_and_loads_without_it(tmp_path,
                                                                             source_dir):
    module = custom_env_module(source_dir)
    cmbrl.train(env=module.DoubleIntegrator, reward=module.reward, config=tiny(200),
                out=tmp_path / "given")
    declared = tiny(200, python={"env": "custom_env:DoubleIntegrator",
                                 "reward": "custom_env:reward",
                                 "path": [str(source_dir / "examples")]})
    cmbrl.train(config=declared, out=tmp_path / "declared")
    assert rows(tmp_path / "declared") == rows(tmp_path / "given")
    with open(tmp_path / "declared" / "config.yaml") as f:
        text = f.read()
    assert "task: python:custom_env.DoubleIntegrator()" in text
    assert "observation_size: 4" in text and "action_size: 2" in text
    # Loaded, evaluated and resumed with nothing given: the config says what makes them.
    def sums(episodes):
        return [(e["return"], e["cost"], e["steps"]) for e in episodes]
    assert sums(cmbrl.evaluate(tmp_path / "declared", episodes=1, seed=5)) == sums(
        cmbrl.evaluate(tmp_path / "given", episodes=1, seed=5, env=module.DoubleIntegrator,
                       reward=module.reward))
    assert cmbrl.load_run(tmp_path / "declared").act(np.zeros(4)).shape == (2,)
    # Drawn from the env's own pictures: its class takes render_mode.
    drawn = cmbrl.evaluate(tmp_path / "declared", episodes=1, seed=5, render=tmp_path / "pics")
    assert drawn[0]["picture"] == str(tmp_path / "pics" / "episode-0.png")
    assert (tmp_path / "pics" / "episode-0.png").stat().st_size > 0
    cmbrl.train(env=Line, reward=line_reward, config=tiny(40), out=tmp_path / "line")
    with pytest.raises(cmbrl.Error, match=r"draws no pictures"):  # Line takes no render_mode
        cmbrl.evaluate(tmp_path / "line", env=Line, reward=line_reward, render=tmp_path / "none")
    assert not (tmp_path / "none").exists()
    assert cmbrl.train(resume=tmp_path / "declared", steps=300)["steps"] == 300
    # Another env than the one declared is refused.
    with pytest.raises(cmbrl.Error, match=r"declares python.env 'custom_env:DoubleIntegrator' "
                                          r"\(python:custom_env.DoubleIntegrator\(\)\), and "
                                          r"another environment is given"):
        cmbrl.train(config=declared, env=Line, out=tmp_path / "both")
    assert not (tmp_path / "both").exists()


def test_a_built_in_task_through_the_python_path_writes_the_built_in_runs_rows(tmp_path):
    # The adapter changes nothing: the same task and seed give the same rows.
    config = tiny(200, objective={"analytic_form": "goal-distance"})
    cmbrl.train(env=functools.partial(cmbrl.make, "PointGoal1"), config=config,
                out=tmp_path / "python")
    cmbrl.train(config=tiny_config(200), out=tmp_path / "built-in")
    through_python = rows(tmp_path / "python")
    # A Python env's rows add the raw costs, here the 0/1 costs themselves.
    assert all(row.pop("EpRawCost") == row["EpCost"] for row in through_python)
    assert through_python == rows(tmp_path / "built-in")
    with open(tmp_path / "python" / "config.yaml") as f:
        assert "task: python:cmbrl.envs.make('PointGoal1')" in f.read()


def test_costs_that_are_not_0_or_1_count_where_above_0_and_actions_map_onto_the_box(tmp_path):
    made = []

    def make():
        made.append(Line(wall=0.5))  # costs until it has walked half way
        return made[-1]

    cmbrl.train(env=make, reward=line_reward, config=tiny(60), out=tmp_path / "run")
    env = made[0]
    assert min(env.actions) >= 0.0 and max(env.actions) <= 2.0
    assert max(env.actions) > 1.5 and min(env.actions) < 0.5  # the whole box is used
    costs = [(float(row["EpCost"]), float(row["EpRawCost"])) for row in rows(tmp_path / "run")]
    assert any(cost > 0 for cost, _ in costs)
    for cost, raw in costs:  # EpCost counts steps; EpRawCost sums the env's 2.5s
        assert cost == int(cost) and raw == 2.5 * cost
    agent = cmbrl.load_run(tmp_path / "run", env=make, reward=line_reward)
    assert np.array_equal(agent.action_space.low, [0.0]) and np.array_equal(
        agent.action_space.high, [2.0])
    action = agent.act(np.array([0.0]))
    assert 0.0 <= action[0] <= 2.0


# How SwitchableLine misbehaves, read at each step (a pickled one restored by a resume reads it
# too): from step SWITCH["fail_at"] on, as SWITCH["bad"] says; empty: never.
SWITCH = {}


class SwitchableLine(Line):
    def step(self, action):
        self.fail_at, self.bad = SWITCH.get("fail_at"), SWITCH.get("bad")
        return super().step(action)


@pytest.mark.parametrize("bad, message", [
    ("raise", r"episode \d+, step \d+: step\(\) raised RuntimeError: the simulator broke"),
    ("nan", r"episode \d+, step \d+: step\(\): the observation holds nan at component 0"),
    ("shape", r"episode \d+, step \d+: step\(\): the observation has shape \(3,\): expected "
              r"\(1,\)"),
    ("no cost", r"step\(\) returned five values and its info has no 'cost'"),
])
def test_an_env_that_misbehaves_stops_the_run_naming_the_step_and_loses_no_checkpoint(
        tmp_path, bad, message):
    SWITCH.update(fail_at=130, bad=bad)  # after the pre-training's 120 steps and its checkpoint
    try:
        with pytest.raises(cmbrl.Error, match=message):
            cmbrl.train(env=SwitchableLine, reward=line_reward, config=tiny(200),
                        out=tmp_path / "run")
    finally:
        SWITCH.clear()
    # The checkpoint taken before it is whole: with the env mended, the run resumes to the rows
    # of a run that never failed.
    cmbrl.train(resume=tmp_path / "run", env=SwitchableLine, reward=line_reward)
    cmbrl.train(env=SwitchableLine, reward=line_reward, config=tiny(200), out=tmp_path / "whole")
    assert rows(tmp_path / "run") == rows(tmp_path / "whole")


@pytest.mark.parametrize("space, name", [
    ("discrete", r"observation_space is .*: cmbrl learns and plans on a 1-D Box"),
    ("2-d", r"observation_space is .*: expected a 1-D Box"),
    ("unbounded action", r"action_space bounds component 0 to \[-inf, inf\]"),
])
def test_spaces_other_than_a_1d_box_are_refused_by_name_before_anything_is_written(
        tmp_path, space, name):
    class Discrete:
        n = 3

    def make():
        env = Line()
        if space == "discrete":
            env.observation_space = Discrete()
        elif space == "2-d":
            env.observation_space = cmbrl.Box(np.zeros((2, 2)), np.ones((2, 2)))
        else:
            env.action_space = cmbrl.Box(np.array([-np.inf]), np.array([np.inf]))
        return env

    with pytest.raises(cmbrl.Error, match=name):
        cmbrl.train(env=make, reward=line_reward, config=tiny(60), out=tmp_path / "run")
    assert not (tmp_path / "run").exists()


def test_a_python_env_needs_a_reward_for_its_planner(tmp_path):
    with pytest.raises(cmbrl.Error, match=r"has no analytic reward of its own: give a reward"):
        cmbrl.train(env=Line, config=tiny(60), out=tmp_path / "run")
    assert not (tmp_path / "run").exists()


def test_a_run_stopped_mid_episode_resumes_through_pickle_to_the_same_rows(tmp_path):
    with pytest.raises(KeyboardInterrupt):
        cmbrl.train(env=Line, reward=line_reward, config=tiny(80), out=tmp_path / "run",
                    progress=stop_after_30_steps, checkpoint_seconds=0)
    cmbrl.train(resume=tmp_path / "run", env=Line, reward=line_reward)
    cmbrl.train(env=Line, reward=line_reward, config=tiny(80), out=tmp_path / "whole")
    assert rows(tmp_path / "run") == rows(tmp_path / "whole")
    with pytest.raises(cmbrl.Error, match=r"trained on task 'python:.*Line\(\)'"):
        cmbrl.train(resume=tmp_path / "run", env=functools.partial(Line, 30),
                    reward=line_reward, steps=100)


class Unpicklable(Line):
    def __reduce__(self):
        raise TypeError("this simulator cannot be pickled")


def test_an_env_that_does_not_pickle_restarts_the_episode_and_the_session_says_so(tmp_path):
    with pytest.raises(TypeError):
        pickle.dumps(Unpicklable())

    with pytest.raises(KeyboardInterrupt):
        cmbrl.train(env=Unpicklable, reward=line_reward, config=tiny(80), out=tmp_path / "run",
                    progress=stop_after_30_steps, checkpoint_seconds=0)
    summary = cmbrl.train(resume=tmp_path / "run", env=Unpicklable, reward=line_reward)
    assert summary["steps"] >= 80
    with open(tmp_path / "run" / "sessions.jsonl") as f:
        sessions = [json.loads(line) for line in f]
    assert "started again" in sessions[-1]["note"] and "does not pickle" in sessions[-1]["note"]


def test_an_env_instance_is_accepted_and_named_by_its_class(tmp_path):
    cmbrl.train(env=Line(), reward=line_reward, config=tiny(60), out=tmp_path / "run")
    with open(tmp_path / "run" / "config.yaml") as f:
        assert "task: python:test_custom_env.Line()" in f.read()
    # An env with a spec id names it; only one that gymnasium made is named by the id alone.
    config = tiny(60, objective={"analytic_form": "goal-distance"})
    cmbrl.train(env=cmbrl.make("PointGoal1"), config=config, out=tmp_path / "goal")
    with open(tmp_path / "goal" / "config.yaml") as f:
        assert "task: python:cmbrl.envs.Env('PointGoal1')" in f.read()


def test_a_learned_reward_plans_without_a_function_resumes_exactly_and_loads(tmp_path):
    config = tiny(80, objective={"reward": "learned"}, reward_model={"hidden_sizes": [16],
                                                                      "max_epochs": 5})

    with pytest.raises(KeyboardInterrupt):
        cmbrl.train(env=Line, config=config, out=tmp_path / "run",
                    progress=stop_after_30_steps, checkpoint_seconds=0)
    assert (tmp_path / "run" / "checkpoint" / "reward_model.pt").exists()
    cmbrl.train(resume=tmp_path / "run", env=Line)
    cmbrl.train(env=Line, config=config, out=tmp_path / "whole")
    assert rows(tmp_path / "run") == rows(tmp_path / "whole")
    agent = cmbrl.load_run(tmp_path / "run", env=Line)
    assert 0.0 <= agent.act(np.array([0.2]))[0] <= 2.0
    # A function given where the config asks for a learned reward is refused, not obeyed.
    with pytest.raises(cmbrl.Error, match=r"asks for objective.reward 'learned': give no "
                                          r"reward function"):
        cmbrl.train(env=Line, reward=line_reward, config=config, out=tmp_path / "both")
    assert not (tmp_path / "both").exists()


class Cliff:
    """A walk along x, rewarded x per step, whose episode ends by itself (terminated) once x
    passes the cliff at 1; 30 steps otherwise. A planner that knows the cliff stays near its
    edge for the whole episode; one that does not walks off it."""

    def __init__(self):
        self.observation_space = cmbrl.Box(np.array([-5.0]), np.array([5.0]))
        self.action_space = cmbrl.Box(-np.ones(1), np.ones(1))
        self.x, self.t = 0.0, 0

    def reset(self, seed=None, options=None):
        self.x, self.t = 0.0, 0
        return np.array([self.x]), {}

    def step(self, action):
        self.x += 0.2 * float(action[0])
        self.t += 1
        return np.array([self.x]), self.x, 0.0, self.x > 1.0, self.t >= 30, {}


def cliff_reward(states, actions, next_states):
    return next_states[:, 0]


def cliff_config(termination, total_steps=600):
    config = tiny(total_steps, planner="cem", objective={"termination": termination},
                  termination_model={"hidden_sizes": [32, 32], "max_epochs": 50})
    config["training"].update({"pretrain_episodes": 20, "pretrain_steps": 30})
    config["planning"].update({"horizon": 8, "population": 100, "elites": 10,
                               "max_iterations": 4})
    return config


def test_a_learned_termination_keeps_the_planner_off_the_cliff_and_resumes_exactly(tmp_path):
    for termination in ("none", "learned"):
        cmbrl.train(env=Cliff, reward=cliff_reward, config=cliff_config(termination),
                    out=tmp_path / termination)
    late = {termination: [int(row["Steps"]) for row in rows(tmp_path / termination)[-10:]]
            for termination in ("none", "learned")}
    # Without it every episode ends at the cliff within 10 steps; with it most last all 30.
    assert max(late["none"]) < 10, late
    assert np.mean(late["learned"]) > 2 * np.mean(late["none"]), late
    assert (tmp_path / "learned" / "checkpoint" / "termination_model.pt").exists()
    assert not (tmp_path / "none" / "checkpoint" / "termination_model.pt").exists()

    # Stopped mid-episode and resumed, it writes the uninterrupted run's rows.
    with pytest.raises(KeyboardInterrupt):
        cmbrl.train(env=Cliff, reward=cliff_reward, config=cliff_config("learned", 120),
                    out=tmp_path / "stopped", progress=stop_after_30_steps, checkpoint_seconds=0)
    cmbrl.train(resume=tmp_path / "stopped", env=Cliff, reward=cliff_reward)
    cmbrl.train(env=Cliff, reward=cliff_reward, config=cliff_config("learned", 120),
                out=tmp_path / "whole")
    assert rows(tmp_path / "stopped") == rows(tmp_path / "whole")
    agent = cmbrl.load_run(tmp_path / "stopped", env=Cliff, reward=cliff_reward)
    assert -1.0 <= agent.act(np.array([0.5]))[0] <= 1.0
    with pytest.raises(cmbrl.Error, match=r"plans with objective.termination 'learned': give "
                                          r"no termination function"):
        cmbrl.load_run(tmp_path / "stopped", env=Cliff, reward=cliff_reward,
                       termination=lambda s, a, n: n[:, 0] > 1.0)
    with pytest.raises(cmbrl.Error, match=r"asks for objective.termination 'learned': give no "
                                          r"termination function"):
        cmbrl.train(env=Cliff, reward=cliff_reward, config=cliff_config("learned"),
                    termination=lambda s, a, n: n[:, 0] > 1.0, out=tmp_path / "both")
    assert not (tmp_path / "both").exists()


def test_the_reward_model_stands_alone_on_numpy_arrays(tmp_path):
    rng = np.random.default_rng(0)
    inputs = rng.normal(size=(1500, 3))
    rewards = -np.abs(inputs[:, 2] - 1.0)
    model = cmbrl.RewardModel(3, hidden_sizes=[32, 32], max_epochs=60, seed=1)
    report = model.fit(inputs, rewards)
    assert report["validation_mse"] < 0.1 * rewards.var()
    model.save(tmp_path / "model")
    again = cmbrl.RewardModel.load(tmp_path / "model")
    assert np.array_equal(again.predict(inputs[:10]), model.predict(inputs[:10]))
    copied = pickle.loads(pickle.dumps(model))
    assert np.array_equal(copied.predict(inputs[:10]), model.predict(inputs[:10]))


def test_a_model_free_learner_trains_on_copies_of_a_python_env_and_resumes(tmp_path):
    made = []

    def make():
        made.append(Line(wall=0.0))  # 2.5 a step below 0
        return made[-1]

    config = {"algorithm": "cpo", "seed": 2, "training": {"total_steps": 600},
              "policy_optimisation": {"steps_per_epoch": 300, "envs": 2, "policy_hidden": [16],
                                      "value_hidden": [16], "value_iterations": 5}}
    seen = []
    first = cmbrl.train(env=make, config=config, out=tmp_path / "run", steps=300,
                        progress=seen.append)
    assert len(made) == 2  # one per rollout env
    # A model-free unit is an epoch of many episodes: the call counts the episodes its epoch
    # ended (7 of 20 steps in each env's 150) and their violations (not those of the episodes
    # the epoch's end cut), and splits its time by the learner's parts.
    epoch = rows(tmp_path / "run")[0]
    assert first["episodes_this_session"] == int(epoch["Episodes"]) == 2 * (150 // 20)
    assert [d["episodes"] for d in seen] == [int(epoch["Episodes"])]
    assert first["cost_this_session"] == round(
        float(epoch["AverageEpCost"]) * int(epoch["Episodes"]))
    assert 0 < first["cost_this_session"] <= float(epoch["CumulativeCost"])
    assert list(first["seconds_this_session"]) == ["rollout", "policy_updates", "value_fits",
                                                   "checkpoints", "other"]
    cmbrl.train(resume=tmp_path / "run", env=make, steps=600)
    cmbrl.train(env=functools.partial(Line, wall=0.0), config=config, out=tmp_path / "whole")
    assert rows(tmp_path / "run") == rows(tmp_path / "whole")
    # The rows sum the env's raw costs beside the violations they count.
    last = rows(tmp_path / "run")[-1]
    assert float(last["CumulativeCost"]) > 0
    assert float(last["CumulativeRawCost"]) == 2.5 * float(last["CumulativeCost"])
    episodes = cmbrl.evaluate(tmp_path / "run", env=make, episodes=2)
    assert [e["steps"] for e in episodes] == [20, 20]
    assert not any("goal" in key or "hazard" in key for key in episodes[0])  # no such world


def test_the_custom_tasks_report_is_made_again_from_its_committed_logs(tmp_path, source_dir):
    spec = importlib.util.spec_from_file_location(
        "custom_tasks_run", source_dir / "experiments" / "custom-tasks" / "run.py")
    run = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(run)
    committed = source_dir / "experiments" / "custom-tasks" / "report"
    shutil.copytree(committed, tmp_path / "report")
    summary = run.report(tmp_path / "report", runs_dir=tmp_path / "no-runs")
    assert summary == (committed / "summary.md").read_text()
    for name in ("table-1.md", "table-1.csv"):
        assert (tmp_path / "report" / name).read_text() == (committed / name).read_text(), name


def test_an_env_given_from_python_can_observe_its_previous_action(tmp_path):
    made = []

    def make():
        made.append(Line())
        return made[-1]

    config = tiny(60, environment={"previous_action": True})
    cmbrl.train(env=make, reward=line_reward, config=config, out=tmp_path / "run")
    agent = cmbrl.load_run(tmp_path / "run", env=make, reward=line_reward)
    assert agent.previous_action and agent.observation_space.shape == (2,)
    # The previous action is observed in the planner's units, [-1, 1] mapped onto the env's box.
    assert np.array_equal(agent.observation_space.low, [-5.0, -1.0])
    assert 0.0 <= agent.act(np.array([0.0, 0.5]))[0] <= 2.0
    # make_env appends it as the run observed it: the env's action 1.5 is 0.5 in [-1, 1].
    env = agent.make_env()
    assert env.observation_space.shape == (2,)
    obs, _ = env.reset(seed=0)
    assert np.array_equal(obs, [0.0, 0.0])
    obs = env.step(np.array([1.5]))[0]
    assert obs[0] == pytest.approx(0.05) and obs[1] == pytest.approx(0.5)
    obs = env.step(np.array([7.0]))[0]
    assert obs[1] == 1.0  # clipped, as the planner's actions are
    agent.begin_episode()
    for _ in range(3):
        obs, _, terminated, truncated, _ = env.step(agent.act(obs))
    assert env.env.actions[-1] == pytest.approx(2.0 * (obs[1] + 1.0) / 2.0)
