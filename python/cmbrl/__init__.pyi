# Type stubs for the cmbrl package (PEP 561; py.typed ships beside them), one per module as the
# runtime is laid out: cmbrl/__init__.py re-exports the public names of envs, models, agents and
# results over the compiled cmbrl._cmbrl. python/tests/test_typing.py checks these stubs against
# it with mypy's stubtest and type-checks the examples with them.
from ._common import Error as Error
from .agents import Agent as Agent
from .agents import evaluate as evaluate
from .agents import load_run as load_run
from .agents import train as train
from .agents import presets as presets
from .envs import CostInInfo as CostInInfo
from .envs import Env as Env
from .envs import EnvSpec as EnvSpec
from .envs import VectorCostInInfo as VectorCostInInfo
from .envs import VectorEnv as VectorEnv
from .envs import make as make
from .envs import make_vec as make_vec
from .envs import tasks as tasks
from .envs import variants as variants
from . import registration as registration
from .models import CostClassifier as CostClassifier
from .models import Ensemble as Ensemble
from .models import RewardModel as RewardModel
from .results import read_runs as read_runs
from .results import report as report
from .spaces import Box as Box

__version__: str
__commit__: str
__all__ = ["Error", "Box", "Env", "EnvSpec", "VectorEnv", "Agent", "Ensemble", "CostClassifier",
           "RewardModel", "make", "make_vec", "tasks", "variants", "presets", "train", "load_run", "evaluate",
           "read_runs", "report", "CostInInfo", "VectorCostInInfo"]
