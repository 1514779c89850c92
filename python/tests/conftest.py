"""Shared fixtures: the cmbrl program and the source tree (CTest sets both)."""
import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("CMBRL_SOURCE_DIR",
                                         pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture
def cmbrl_binary():
    binary = os.environ.get("CMBRL_BINARY", str(SOURCE_DIR / "build" / "bin" / "cmbrl"))
    if not os.path.exists(binary):
        pytest.fail(f"no cmbrl program at {binary}: set CMBRL_BINARY")
    return binary


@pytest.fixture
def source_dir():
    return SOURCE_DIR


def tiny_config(total_steps=300):
    """The tests' tiny MPC run of PointGoal1 (seconds to train), as a config dict."""
    return {
        "task": "PointGoal1", "planner": "rce", "seed": 0,
        "training": {"pretrain_episodes": 6, "pretrain_steps": 20, "episodes_per_epoch": 2,
                     "total_steps": total_steps},
        "ensemble": {"hidden_sizes": [16], "max_epochs": 5},
        "classifier": {"rounds": 10},
        "planning": {"horizon": 3, "population": 24, "elites": 6, "min_feasible_elites": 3,
                     "max_iterations": 2, "random_samples": 50},
    }
