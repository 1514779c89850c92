"""The diagnostics package: its pure parts on known inputs, and each module end to end on a tiny
trained run or tiny models."""
import json
import os

import pytest

import cmbrl
from conftest import tiny_config
from cmbrl.diagnostics import (goal_approach, model_size, planner_study, reward_form,
                               violation_anatomy)

TINY = tiny_config(120)


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
    assert capsys.readouterr().out.strip()
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
