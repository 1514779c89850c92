"""cmbrl from Python: the Safety Gym Goal environments, vectors of them, training and trained runs.

    import cmbrl
    env = cmbrl.make("PointGoal1")                 # the paper's variant
    obs, info = env.reset(seed=0)
    obs, reward, cost, terminated, truncated, info = env.step(env.action_space.sample())

    envs = cmbrl.make_vec("PointGoal1", num_envs=4)  # stepped in C++ threads, auto-reset
    cmbrl.train(config=["configs/pointgoal1-rce.yaml", "configs/quickstart.yaml"], out="runs/q",
                steps=200)
    agent = cmbrl.load_run("runs/q")
    action = agent.act(obs)

Errors from the C++ core are raised as cmbrl.Error (a ValueError) with its message.

This file re-exports the public names of the package's modules, one per concept: envs
(environments and vectors of them), models (the standalone learned models), agents (training
and trained runs' agents) and results (runs as reports read them, and reports); _common holds
what they share.
"""
from . import _cmbrl
from ._common import Error
from .agents import Agent, evaluate, load_run, presets, train
from .envs import (CostInInfo, Env, EnvSpec, VectorCostInInfo, VectorEnv, make, make_vec,
                   tasks, variants)
from .models import CostClassifier, Ensemble, RewardModel
from .results import read_runs, report
from .spaces import Box
from . import registration  # registers every task in Gymnasium's registry (where importable)

# The version of the C++ core this module was built from, and its source commit ("744c47e1a2b3",
# with "+dirty" for uncommitted changes): what a run's sessions.jsonl records as "cmbrl".
__version__ = _cmbrl.__version__
__commit__ = _cmbrl.__commit__

__all__ = ["Error", "Box", "Env", "EnvSpec", "VectorEnv", "Agent", "Ensemble", "CostClassifier",
           "RewardModel", "make", "make_vec", "tasks", "variants", "presets", "train", "load_run", "evaluate",
           "read_runs", "report", "CostInInfo", "VectorCostInInfo"]
