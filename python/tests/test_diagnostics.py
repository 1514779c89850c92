"""The diagnostics package: its pure parts on known inputs, and each module end to end on a tiny
trained run or tiny models."""
import json
import os
import re

import numpy as np
import pytest

import cmbrl
from conftest import tiny_config
from cmbrl.diagnostics import (classifier_learners, classifier_recall, goal_approach,
                               hazard_escape, hidden_state, model_size, open_loop,
                               planner_compare, planner_study, reward_form, runs,
                               violation_anatomy)

TINY = tiny_config(120)


def test_a_diagnostic_refuses_a_model_free_run_naming_what_it_lacks(monkeypatch):
    loaded = []

    class ModelFree:
        is_mpc = False

    def load_run(run, seed=0, overrides=None):
        loaded.append((run, seed, overrides))
        return ModelFree()

    monkeypatch.setattr(cmbrl, "load_run", load_run)
    with pytest.raises(SystemExit, match="^runs/trpo is not an MPC run: it has no classifier$"):
        runs.load_mpc_run("runs/trpo", "classifier", seed=3, overrides=["a.b=1"])
    assert loaded == [("runs/trpo", 3, ["a.b=1"])]
    agents = runs.load_settings("r", [("b", ["x=1"]), ("a", [])], seed=2)
    assert list(agents) == ["b", "a"] and loaded[1:] == [("r", 2, ["x=1"]), ("r", 2, [])]


def test_a_setting_names_its_overrides():
    assert planner_study.parse_setting("preset=") == ("preset", [])
    assert planner_study.parse_setting("t=classifier.threshold=0.3,planning.population=50") == (
        "t", ["classifier.threshold=0.3", "planning.population=50"])
    with pytest.raises(SystemExit):
        planner_study.parse_setting("=planning.population=50")


def test_the_summary_counts_per_run_and_per_100_steps():
    episode = {"cost": 5, "steps": 100, "return": 2.0, "goals_met": 1, "ms_per_plan": 10.0,
               "feasible_fraction": 0.5, "fallback_steps": 0.1, "hazard_steps": 4,
               "steps_near_goal": 10, "mean_goal_distance": 1.5}
    heavy = dict(episode, cost=25, hazard_steps=25, steps_near_goal=0, mean_goal_distance=3.0)
    summary = planner_study.summarise({"a": [episode, heavy], "b": [episode]})
    assert summary["per_run"] == {"a": 30, "b": 5}
    assert summary["per_100_steps"] == pytest.approx(35 / 3)
    assert summary["heavy"] == 1
    assert summary["episodes"] == 3
    assert summary["hazard_share"] == pytest.approx(33 / 300)
    assert summary["near_goal_share"] == pytest.approx(20 / 300)
    assert summary["goal_distance"] == pytest.approx(2.0)


def test_the_violation_anatomy_splits_an_episode_into_its_runs_of_violations():
    kinds = [None, "hole", "hole", None, None, "unforeseen", "hole", None, "hole"]
    assert violation_anatomy.violation_runs(kinds) == [
        ["hole", "hole"], ["unforeseen", "hole"], ["hole"]]
    assert violation_anatomy.violation_runs([None, None]) == []
    assert violation_anatomy.violation_runs(["hole"] * 6) == [["hole"] * 6]


def test_model_size_parses_its_settings_and_fits_tiny_ensembles(capsys):
    assert model_size.parse_setting("d=8,8,delta") == ("d", [8, 8], True)
    assert model_size.parse_setting("a=16") == ("a", [16], False)
    model_size.main(["--task", "PointGoal1", "--transitions", "300", "--ensemble-size", "2",
                     "--max-epochs", "2", "--setting", "a=8", "--setting", "d=8,delta"])
    table = capsys.readouterr().out
    assert "| a | " in table and "| d | " in table


def test_the_planner_study_and_the_violation_anatomy_run_on_a_trained_run(
        tmp_path, cmbrl_binary, capsys):
    run = tmp_path / "run"
    cmbrl.train(config=TINY, out=str(run))
    out = tmp_path / "study"
    planner_study.main(["--cmbrl", cmbrl_binary, "--runs", str(run), "--episodes", "1",
                        "--out", str(out), "--setting", "own=",
                        "--setting", "small=planning.population=12"])
    table = (out / "table.md").read_text()
    assert "| own | (the run's own) |" in table and "| small | planning.population=12 |" in table
    lines = (out / "small" / "run.jsonl").read_text().splitlines()
    assert len(lines) == 1 and "cost" in json.loads(lines[0])
    violation_anatomy.main([str(run), "--episodes", "1"])
    anatomy = capsys.readouterr().out
    assert "| hole |" in anatomy and "1 episodes" in anatomy
    goal_approach.main([str(run), str(run), "--episodes", "1", "--near", "100"])
    table = capsys.readouterr().out
    rows = [line for line in table.splitlines() if line.startswith("| run |")]
    assert len(rows) == 2 and rows[0] == rows[1]  # the same models judged on the same transitions
    assert "nan" in rows[0]  # nothing is farther than 100 m from the goal


def test_the_reward_form_study_measures_both_forms_on_the_same_steps(source_dir):
    row = reward_form.study("DoubleIntegrator",
                            lambda: reward_form.double_integrator(source_dir / "examples"),
                            train_episodes=4, test_episodes=2, seed=0, hidden=[16],
                            max_epochs=3, rows=100)
    assert row["train_steps"] == 4 * 99 and row["test_steps"] == 2 * 99
    for key in ("extra_output_mse", "own_model_mse_true_next", "own_model_mse_predicted_next",
                "state_nmse_widened", "state_nmse_plain", "own_model_ms_per_iteration"):
        assert row[key] >= 0.0 and row[key] == row[key], key  # measured, not NaN


def test_the_pose_fit_recovers_a_known_pose_and_reports_a_non_rigid_one():
    rng = np.random.default_rng(4)
    world = rng.uniform(-2, 2, size=(7, 2))
    position, yaw = np.array([0.3, -1.1]), 2.5
    c, s = np.cos(yaw), np.sin(yaw)
    ego = (world - position) @ np.array([[c, -s], [s, c]])  # R(yaw)^T (world - position)
    fitted, fitted_yaw, residual = open_loop.pose_from_ego(ego, world)
    assert np.allclose(fitted, position) and fitted_yaw == pytest.approx(yaw)
    assert residual == pytest.approx(0.0, abs=1e-12)
    batch = np.stack([ego, ego + rng.normal(0, 0.1, ego.shape)])  # leading axes are kept
    _, _, residuals = open_loop.pose_from_ego(batch, world)
    assert residuals.shape == (2,) and residuals[1] > 0.01
    assert open_loop.wrap(3 * np.pi / 2) == pytest.approx(-np.pi / 2)


@pytest.mark.parametrize("task", ["PointGoal1", "CarGoal2"])
def test_the_pose_fit_of_a_real_observation_is_the_simulators_pose(task):
    env = cmbrl.make(task, variant="paper")
    slots = open_loop.hazard_slots(env.observation_names)
    obs, _ = env.reset(seed=3)
    for step in range(12):
        obs, *_ = env.step(np.array([0.8, 0.6 if step < 6 else -0.6]))
        truth = env.ground_truth()
        position, yaw, residual = open_loop.pose_from_ego(obs[slots], truth["hazards"])
        # The observation's float32 and the robot's site beside its body: a millimetre.
        assert np.linalg.norm(position - truth["robot_position"]) < 2e-3, step
        assert abs(open_loop.wrap(yaw - truth["robot_yaw"])) < 2e-3, step
        assert residual < 1e-3
    with pytest.raises(SystemExit, match="two or more hazards"):
        open_loop.hazard_slots(["goal_x", "goal_y", "hazard0_x", "hazard0_y"])


def test_the_open_loop_study_rolls_each_member_on_its_own_and_writes_its_tables(tmp_path):
    run = tmp_path / "run"
    cmbrl.train(config=dict(TINY, ensemble={"hidden_sizes": [16], "max_epochs": 5,
                                            "ensemble_size": 3}), out=str(run))
    agent = cmbrl.load_run(str(run))
    rng = np.random.default_rng(0)
    states = rng.normal(size=(4, agent.observation_space.shape[0]))
    actions = rng.uniform(-1, 1, size=(4, 3, 2))
    paths = open_loop.roll_out(agent, states, actions)  # (E, N, H, S)
    assert paths.shape == (3, 4, 3, states.shape[1])
    assert np.array_equal(paths[:, :, 0], agent.predict_next(states, actions[:, 0]))
    for member in range(3):  # step 2 of member e: member e's prediction from its own step 1
        own = agent.predict_next(paths[member, :, 0], actions[:, 1])[member]
        assert np.allclose(paths[member, :, 1], own, atol=1e-6)
    out = tmp_path / "out"
    open_loop.main([str(run), "--episodes", "1", "--seed", "5", "--out", str(out)])
    text = (out / "table.md").read_text()
    for k in open_loop.HORIZONS:
        assert f"| Point | {k} | all | " in text and f"| Point | {k} | not turning | " in text
    summary = json.loads((out / "summary.json").read_text())
    assert summary["Point"]["episodes"] == 1 and summary["Point"]["steps"] > 8
    everything = summary["Point"]["by_k"]["1"][0]
    assert everything[0] == "all" and everything[1]["samples"] == summary["Point"]["steps"] - 7


class _SlidingAgent:
    """Two members that move the robot (yaw 0) along world x by 0.1 x the action's first component
    a step; the objective calls a sequence feasible when it never drives forward, and its reward
    cost is the sum of the action's second component."""

    def predict_next(self, states, actions):
        moved = np.array(states, dtype=float)
        moved[:, 0:4:2] -= 0.1 * np.asarray(actions)[:, :1]  # the two hazards' ego x
        return np.stack([moved, moved])

    def score(self, obs, sequences):
        sequences = np.asarray(sequences)
        return {"feasible": (sequences[:, :, 0] <= 0).all(axis=1),
                "reward_cost": sequences[:, :, 1].sum(axis=1)}


def test_a_hazard_is_a_trap_when_only_staying_is_feasible():
    world = np.array([[0.0, 0.0], [3.0, 1.0]])  # the robot at the first hazard's centre
    obs = np.concatenate([(world - world[0]).ravel(), [0.0]])  # hazard0 x, y, hazard1 x, y
    slots = np.array([[0, 1], [2, 3]])
    forward = np.zeros((3, 4, 2)); forward[:, :, 0] = [[1.0], [0.5], [0.2]]   # 0.4, 0.2, 0.08 m
    backward = np.zeros((2, 4, 2)); backward[:, :, 0] = -1.0                  # 0.4 m back
    backward[1, :, 1] = 0.25                                                   # reward cost 1
    sequences = np.concatenate([forward, backward])
    feasible, leaves, reward_cost = hazard_escape.escape_at(
        _SlidingAgent(), obs, world[0], 0.3, slots, world, sequences)
    assert feasible.tolist() == [False, False, False, True, True]
    assert leaves.tolist() == [True, False, False, True, True]
    assert reward_cost.tolist() == [0.0, 0.0, 0.0, 0.0, 1.0]
    judged = hazard_escape.judge_state(feasible, leaves, reward_cost)
    assert np.isnan(judged.pop("leave_scores_better"))  # no feasible staying sequence
    assert judged == {"leave_feasible": pytest.approx(2 / 3), "stay_feasible": 0.0,
                      "leaving": pytest.approx(0.6), "trapped": False, "best_way_out": 0.0}
    # Only forward: the ways out are infeasible, staying is not: trapped.
    trapped = hazard_escape.judge_state(np.array([False, True, True]),
                                        np.array([True, False, False]), np.zeros(3))
    assert trapped["trapped"] and trapped["leave_feasible"] == 0.0
    assert trapped["best_way_out"] == np.inf and np.isnan(trapped["leave_scores_better"])
    only_staying = hazard_escape.judge_state(np.array([True]), np.array([False]), np.zeros(1))
    assert np.isnan(only_staying["leave_feasible"])
    # Two feasible ways out (costs 1, 3) against three feasible stays (2, 3, 9): 1 beats all
    # three, 3 ties one and beats one: (3 + 1.5) / 6.
    mixed = hazard_escape.judge_state(np.ones(5, bool), np.array([1, 1, 0, 0, 0], bool),
                                      np.array([1.0, 3.0, 2.0, 3.0, 9.0]))
    assert mixed["leave_scores_better"] == pytest.approx(4.5 / 6)
    assert mixed["best_way_out"] == 1.0


def test_a_cold_plan_forgets_the_warm_start_and_searches_are_summarised_per_state_kind(tmp_path):
    run = tmp_path / "run"
    cmbrl.train(config=TINY, out=str(run))
    # Two agents alike, warm-starting (same seed, same states planned from), but the last plan
    # of one is cold: it differs from the warm-started one's.
    plans = []
    for cold in (True, False):
        agent = cmbrl.load_run(str(run), seed=4, overrides={"planning.warm_start": True})
        env = agent.make_env()
        first, _ = env.reset(seed=1)
        agent.begin_episode()
        obs = first
        for _ in range(3):
            obs = env.step(agent.act(obs))[0]
        if cold:
            plans.append(hazard_escape.cold_plan(agent, obs))
        else:
            agent.act(obs)
            plans.append(np.asarray(agent.last_plan()["actions"]))
        env.close()
    assert plans[0].shape == (3, 2) and not np.allclose(plans[0], plans[1])
    record = {"feasible": np.array([True, False, True]), "leaves": np.array([True, True, False]),
              "reward_cost": np.array([1.0, 5.0, 3.0])}
    assert hazard_escape.summarise_search(record, np.ones(3, bool)) == {
        "states": 3, "feasible": pytest.approx(2 / 3), "leaves": pytest.approx(2 / 3),
        "feasible_and_leaves": pytest.approx(1 / 3), "reward_cost": 3.0}
    assert hazard_escape.summarise_search(record, np.zeros(3, bool)) == {"states": 0}


def test_the_executed_plan_is_outscored_only_where_it_was_feasible_and_stayed():
    rows = {"leaving": np.full(4, 0.5), "leave_feasible": np.full(4, 0.5),
            "stay_feasible": np.full(4, 0.5), "trapped": np.zeros(4, bool),
            "leave_scores_better": np.array([0.2, np.nan, 0.6, 0.4]),
            "plan_feasible": np.array([True, True, False, True]),
            "plan_leaves": np.array([False, False, False, True]),
            "plan_outscored": np.array([True, False, True, True]),
            "plan_beaten": np.array([0.5, 0.1, 0.9, np.nan])}
    summary = hazard_escape.summarise(rows, np.ones(4, bool))
    assert summary["staying_plans"] == 2 and summary["plan_outscored"] == 0.5
    assert summary["staying_plan_beaten"] == pytest.approx(0.3)  # the two staying plans
    assert summary["leave_scores_better"] == pytest.approx(0.4)
    none = hazard_escape.summarise(rows, np.array([False, False, True, True]))
    assert none["staying_plans"] == 0 and none["plan_outscored"] is None
    # The rank among the feasible sequences: of the feasible 1, 2, 5 (the infeasible 0 left
    # out), one beats a plan of 1.5.
    assert hazard_escape.beaten(np.array([True, True, False, True]),
                                np.array([1.0, 2.0, 0.0, 5.0]), 1.5) == pytest.approx(1 / 3)
    assert np.isnan(hazard_escape.beaten(np.zeros(2, bool), np.zeros(2), 1.0))
    outside = {"plan_feasible": np.array([True, False, True]),
               "plan_beaten": np.array([0.2, 0.9, np.nan]),
               "dwelling": np.array([True, True, False])}
    control = hazard_escape.summarise_outside(outside, outside["dwelling"])
    assert control == {"states": 2, "plan_feasible": 0.5, "feasible_plans": 1,
                       "plan_beaten": pytest.approx(0.2)}
    assert hazard_escape.summarise_outside(outside, ~outside["dwelling"])["plan_beaten"] is None
    # A run that never entered a hazard: empty, typed arrays still mask.
    empty = {key: np.array([], dtype=bool if key in hazard_escape.FLAGS else float)
             for key in rows}
    assert hazard_escape.summarise(empty, ~np.array([], dtype=bool)) == {"states": 0}


def test_the_hazard_escape_study_writes_a_row_per_run_and_episode_kind(tmp_path):
    run = tmp_path / "run"
    cmbrl.train(config=TINY, out=str(run))
    out = tmp_path / "out"
    hazard_escape.main([str(run), "--episodes", "2", "--samples", "6", "--out", str(out),
                        "--search", "own=", "--search", "big=planning.population=12"])
    text = (out / "table.md").read_text()
    kinds = dict(re.findall(r"\| run \| (dwelling|other) \((\d+)\) \|", text))
    assert set(kinds) == {"dwelling", "other"} and sum(map(int, kinds.values())) == 2
    summary = json.loads((out / "summary.json").read_text())
    assert len(summary["run"]["violations"]) == 2
    for kind in ("dwelling", "other"):
        part = summary["run"][kind]
        assert part["states"] == 0 or (0.0 <= part["leaving"] <= 1.0
                                       and 0.0 <= part["plan_feasible"] <= 1.0
                                       and 0 <= part["staying_plans"] <= part["states"])
        control = summary["run"]["outside"][kind]
        assert control["states"] == 0 or 0.0 <= control["plan_feasible"] <= 1.0
    # Each search setting judged at the same states inside hazards as the uniform sequences.
    for name in ("own", "big"):
        assert f"| run | dwelling | {name} | " in text and f"| run | other | {name} | " in text
        for kind in ("dwelling", "other"):
            assert summary["run"]["searches"][name][kind]["states"] == \
                summary["run"][kind]["states"]
    with pytest.raises(SystemExit):
        hazard_escape.main([str(run), "--search", "a=", "--search", "a=planning.population=12"])
    # The control scored the states outside hazards: most of two episodes' steps.
    assert sum(summary["run"]["outside"][kind]["states"] for kind in kinds) > 10
    assert "| run | dwelling | " in text and "| run | other | " in text
    # The executed plans recorded beside the episode: each step's action is its plan's first.
    agent = cmbrl.load_run(str(run), seed=3)
    env = agent.make_env()
    episode = open_loop.collect(agent, env, 7, plans=True)
    steps = len(episode["actions"])
    assert episode["plans"].shape == (steps, 3, 2)
    assert np.allclose(episode["plans"][:, 0], episode["actions"], atol=1e-6)
    assert "plans" not in open_loop.collect(agent, env, 7)
    with pytest.raises(SystemExit):
        hazard_escape.main([str(run), "--samples", "0"])


def test_the_hidden_state_study_measures_motion_in_the_robots_frame(capsys):
    data = hidden_state.collect("PointGoal1", "paper", episodes=3, seed=0)
    steps = len(data["target"])
    assert steps > 250 and data["motion"].shape == (steps, 3) and data["action"].shape == (steps, 2)
    # The heading change over a step follows the gyro; the forward move, the velocimeter's x.
    forward, heading = data["target"][:, 0], data["target"][:, 2]
    assert np.corrcoef(heading, data["target"][:, 5])[0, 1] > 0.9
    assert np.corrcoef(forward, data["target"][:, 3])[0, 1] > 0.9
    # The control is the previous actions, shuffled: the same values in another order.
    assert np.allclose(np.sort(data["unrelated_action"], axis=0),
                       np.sort(data["previous_action"], axis=0))
    hidden_state.main(["--task", "PointGoal1", "--episodes", "5"])
    out = capsys.readouterr().out
    assert "| PointGoal1 | " in out and "+ previous action" in out and "PointGoal1: against" in out


def test_the_planner_comparison_scores_every_plan_by_one_objective(tmp_path):
    run = tmp_path / "run"
    cmbrl.train(config=TINY, out=str(run))
    out = tmp_path / "out"
    planner_compare.main([str(run), "--setting", "own=", "--setting", "same=",
                          "--setting", "cem=planner=cem,planning.population=12",
                          "--driver", "cem", "--episodes", "1", "--seed", "3", "--out", str(out)])
    rows = [line for line in (out / "table.md").read_text().splitlines()
            if line.startswith("| own |") or line.startswith("| same |")]
    # The same planner, seed and models on the same states: the same plans, no worse everywhere.
    assert len(rows) == 2 and rows[0].split("|")[2:7] == rows[1].split("|")[2:7]
    assert "| 100.0% | +0.000 | +0.000 |" in rows[1]
    records = {"ref": {"reward_cost": np.array([1.0, 1.0, 2.0]),
                       "constraint_cost": np.array([0.0, 0.0, 0.5]),
                       "feasible": np.array([True, True, False]), "ms": [1.0]},
               "other": {"reward_cost": np.array([0.5, 3.0, 9.0]),
                         "constraint_cost": np.array([0.0, 0.0, 0.0]),
                         "feasible": np.array([True, True, True]), "ms": [2.0]}}
    other = planner_compare.summarise(records, "ref")[1]
    assert other["no_worse"] == pytest.approx(2 / 3)  # better, worse, feasible where ref is not
    assert other["gap_mean"] == pytest.approx(0.75) and other["feasible"] == 1.0
    with pytest.raises(SystemExit):
        planner_compare.main([str(run), "--setting", "a=", "--driver", "b"])


def test_the_open_loop_breakdowns_split_the_samples_they_name():
    samples = {"inside": np.array([True, False, False, False]),
               "speed": np.array([0.05, 0.2, 0.3, 1.0]),
               "turning": np.array([False, True, False, False]),
               "position_error": np.array([1.0, 2.0, 3.0, 4.0]),
               "mean_position_error": np.array([0.5, 1.0, 1.5, 2.0]),
               "heading_error": np.zeros(4), "real_move": np.array([0.1, 0.1, 0.1, 0.1]),
               "predicted_move": np.array([0.2, 0.2, 0.2, 0.2]), "spread": np.ones(4),
               "residual": np.zeros(4)}
    subsets = dict(open_loop.subsets(samples))
    counts = {name: int(mask.sum()) for name, mask in subsets.items()}
    assert counts == {"all": 4, "inside a hazard": 1, "outside hazards": 3,
                      "speed 0-0.1 m/s": 1, "speed 0.1-0.3 m/s": 1, "speed >= 0.3 m/s": 2,
                      "turning": 1, "not turning": 3}
    outside = open_loop.summarise(samples, subsets["outside hazards"])
    assert outside["samples"] == 3 and outside["position_error"] == pytest.approx(3.0)
    assert outside["move_ratio"] == pytest.approx(2.0)
    assert open_loop.summarise(samples, np.zeros(4, dtype=bool)) == {"samples": 0}


def test_the_classifier_recall_sorts_states_by_their_distance_to_hazards(tmp_path, capsys):
    env = cmbrl.make("PointGoal1", variant="paper")
    inside, near, by_vase, farther = classifier_recall.states_by_distance(env, episodes=3, seed=7)
    assert len(inside) + len(near) + len(by_vase) + len(farther) == 300
    slots = open_loop.hazard_slots(env.observation_names)
    vase = [env.observation_names.index(n) for n in ("vase0_x", "vase0_y")]
    assert np.all(np.hypot(*by_vase[:, vase].T) <= 0.5 + 2e-3)
    assert np.all(np.hypot(*farther[:, vase].T) > 0.5 - 2e-3)
    for group, low, high in ((inside, 0.0, 0.2), (near, 0.2, 0.5), (by_vase, 0.5, 99.0),
                             (farther, 0.5, 99.0)):
        # The nearest hazard's centre in the robot's frame, from the observation itself.
        gaps = np.hypot(group[:, slots[:, 0]], group[:, slots[:, 1]]).min(axis=1)
        assert np.all(gaps >= low - 2e-3) and np.all(gaps <= high + 2e-3)
    run = tmp_path / "run"
    cmbrl.train(config=TINY, out=str(run))
    classifier_recall.main([str(run), "--episodes", "2"])
    assert "| run | PointGoal1 | " in capsys.readouterr().out


def test_the_learner_comparison_fits_the_originals_set_on_the_pretrainings_labels(capsys):
    terms = []
    states, unsafe = classifier_learners.labelled_states("PointGoal1", "paper", episodes=20,
                                                         steps=50, seed=3, terms=terms)
    # Every unsafe label is named by the cost that paid it; the Point's are its hazards'.
    assert len(terms) == unsafe.sum() and "cost_hazards" in terms
    assert set(terms) <= set(classifier_learners.TERMS)
    assert states.shape == (1000, 24) and unsafe.dtype == bool and unsafe.shape == (1000,)
    # A label is the step's cost: a state that ends inside a hazard (radius 0.2) paid it.
    names = cmbrl.make("PointGoal1", variant="paper").observation_names
    slots = open_loop.hazard_slots(names)
    gaps = np.hypot(states[:, slots[:, 0]], states[:, slots[:, 1]]).min(axis=1)
    assert (gaps < 0.2 - 2e-3).sum() > 0 and np.all(unsafe[gaps < 0.2 - 2e-3])
    # The fit set is a run's own selection (test_models tests the rule): every unsafe state.
    x, y = classifier_learners.fit_set(states, unsafe)
    same_x, same_y = cmbrl.CostClassifier(24).fit_set(states, unsafe)
    assert np.array_equal(x, same_x) and np.array_equal(y, same_y) and y.sum() == unsafe.sum()
    classifier_learners.main(["--task", "PointGoal1", "--seeds", "0", "--episodes", "20",
                              "--steps", "20", "--eval-episodes", "1"])
    out = capsys.readouterr().out
    assert "| PointGoal1 | 0 | cmbrl (XGBoost, no leaf floor) | " in out
    classifier_learners.main(["--task", "PointGoal1", "--seeds", "3", "--episodes", "20",
                              "--steps", "50", "--labels-only"])
    row = [r for r in capsys.readouterr().out.splitlines() if r.startswith("| PointGoal1 |")][0]
    cells = row.strip("| ").split(" | ")
    assert cells[2:4] == ["1000", str(unsafe.sum())]
    assert abs(sum(float(x) for x in cells[4:]) - 1.0) < 2e-3
    try:
        import sklearn  # noqa: F401
    except ImportError:
        return
    assert "| PointGoal1 | 0 | LightGBM-style, 20 a leaf | " in out
    assert "| PointGoal1 | 0 | LightGBM-style, 1 a leaf | " in out
