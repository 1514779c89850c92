"""Results in Python: read_runs gives the numbers `cmbrl report` counts, and report writes the
same files as `cmbrl report --out`."""
import csv
import os

import numpy as np
import pytest

import cmbrl
from conftest import tiny_config


def test_read_runs_gives_the_counts_of_the_committed_table(source_dir):
    report_dir = source_dir / "experiments" / "cpu-grid" / "report"
    runs = cmbrl.read_runs(report_dir)
    with open(report_dir / "table-1.csv", newline="") as table:
        cells = list(csv.DictReader(table))
    assert len(runs) == sum(int(cell["seeds"]) for cell in cells)
    for cell in cells:
        window = int(cell["window"])
        ours = sorted((run for run in runs
                       if run["task"] == cell["task"] and run["method"] == cell["planner"]),
                      key=lambda run: run["seed"])
        counts = [float(run["episode_cost"][run["end_step"] <= window].sum()) for run in ours]
        assert counts == [float(v) for v in cell["per_seed"].split()], cell["task"]
    run = runs[0]
    assert run["setting"] == "" and run["epoch_log"] is False
    assert run["end_step"].dtype == np.int64 and np.all(np.diff(run["end_step"]) > 0)
    assert np.array_equal(np.cumsum(run["episode_cost"]), run["cumulative_violations"])
    # The run's wall seconds over its sessions: never falling, and within the grid's hour.
    assert np.all(np.diff(run["elapsed_seconds"]) >= 0) and 0 < run["elapsed_seconds"][-1] < 3600
    assert np.all(np.isnan(run["cpu_seconds"]))  # logged before CpuTime was kept


def test_read_runs_gives_the_cpu_seconds_of_a_run_that_logs_them(tmp_path):
    cmbrl.train(config=tiny_config(200), out=tmp_path / "sweep" / "runs" / "tiny")
    (run,) = cmbrl.read_runs(tmp_path / "sweep")
    cpu, wall = run["cpu_seconds"], run["elapsed_seconds"]
    assert len(cpu) == len(run["end_step"]) >= 2
    assert np.all(cpu > 0) and np.all(np.diff(cpu) >= 0)
    assert np.all(cpu <= wall * os.cpu_count() + 0.01)  # no more than its cores could give


def model_free_report(source_dir):
    """The committed model-free report, and the names of the runs it holds (it grows run by run)."""
    report_dir = source_dir / "experiments" / "model-free" / "report"
    return report_dir, sorted(path.name for path in (report_dir / "run-logs").iterdir())


def test_read_runs_of_a_model_free_run_gives_its_epochs(source_dir):
    report_dir, names = model_free_report(source_dir)
    runs = cmbrl.read_runs([report_dir])
    assert len(runs) == len(names) and "pointgoal2-trpo-lagrangian-s0" in names
    (run,) = [run for run in runs
              if run["task"] == "PointGoal2" and run["method"] == "trpo-lagrangian"]
    assert run["seed"] == 0 and run["epoch_log"] is True
    assert run["end_step"][-1] == 3_000_000
    assert np.all(np.diff(run["cumulative_violations"]) >= 0)
    assert np.all(np.diff(run["elapsed_seconds"]) > 0)


def test_report_writes_the_files_of_cmbrl_report(source_dir, tmp_path):
    report_dir, names = model_free_report(source_dir)
    summary = cmbrl.report(report_dir, tmp_path / "out", window=3_000_000)
    # One seed a cell: as many cells as runs.
    assert summary["runs"] == len(names) and summary["window"] == 3_000_000
    assert summary["cells"] == len(names)
    for name in ("report.md", "table-1.csv", "curves-model-free-epcost.png"):
        assert (tmp_path / "out" / name).is_file(), name
    assert sorted(path.name for path in (tmp_path / "out" / "run-logs").iterdir()) == names


def test_bad_folders_are_named(tmp_path):
    with pytest.raises(cmbrl.Error, match="dirs is empty"):
        cmbrl.read_runs([])
    with pytest.raises(cmbrl.Error, match="holds neither runs/ nor run-logs/"):
        cmbrl.read_runs(tmp_path)
    with pytest.raises(cmbrl.Error, match="window is 0"):
        cmbrl.report(tmp_path, tmp_path / "out", window=0)
