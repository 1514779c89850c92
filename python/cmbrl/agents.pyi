# Type stubs of cmbrl.agents.
from typing import Any, Callable, Iterable, Mapping, Optional, Sequence, Union

import numpy.typing as npt

from ._common import _Bools, _Floats, _NotCopyable, _Path

# f(states (N, S), actions (N, A), next_states (N, S)) -> (N,): rewards, or terminal booleans.
_StepFunction = Callable[[_Floats, _Floats, _Floats], npt.ArrayLike]

def _step_function(function: Optional[_StepFunction], name: str,
                   returns: str) -> Optional[_StepFunction]: ...
from .envs import Env
from .spaces import _Box

# A Gymnasium-style environment (reset, step, observation_space, action_space), or a
# zero-argument function or class that makes one.
_EnvSource = Union[Any, Callable[[], Any]]

def presets() -> list[str]: ...
def train(config: Union[_Path, Sequence[_Path], Mapping[str, Any], None] = ...,
          out: Optional[_Path] = ..., steps: Optional[int] = ..., seed: Optional[int] = ...,
          device: Optional[str] = ..., resume: Optional[_Path] = ...,
          progress: Optional[Callable[[dict[str, Any]], object]] = ...,
          checkpoint_seconds: float = ..., reward: Optional[_StepFunction] = ...,
          termination: Optional[_StepFunction] = ...,
          env: Optional[_EnvSource] = ...) -> dict[str, Any]: ...

class Agent(_NotCopyable):
    run_dir: str
    observation_space: _Box
    action_space: _Box
    is_mpc: bool
    task: str
    variant: str
    spawn: str
    previous_action: bool
    def __init__(self, run_dir: _Path, seed: int = ..., overrides: Iterable[str] = ...,
                 reward: Optional[_StepFunction] = ...,
                 termination: Optional[_StepFunction] = ...,
                 env: Optional[_EnvSource] = ...) -> None: ...
    def make_env(self, render_mode: Optional[str] = ..., render_size: int = ...) -> Any: ...
    def config(self) -> str: ...
    def begin_episode(self) -> None: ...
    def act(self, observation: npt.ArrayLike) -> _Floats: ...
    def last_plan(self) -> dict[str, Any]: ...
    def predictions(self, env: Env, samples: int = ...) -> list[dict[str, Any]]: ...
    def predict_next(self, states: npt.ArrayLike, actions: npt.ArrayLike) -> _Floats: ...
    def score(self, observation: npt.ArrayLike, sequences: npt.ArrayLike) -> dict[str, Any]: ...
    def predict_violation(self, states: npt.ArrayLike) -> _Bools: ...

def evaluate(run_dir: _Path, episodes: int = ..., seed: int = ...,
             reseed_each_episode: bool = ..., overrides: Optional[Mapping[str, Any]] = ...,
             reward: Optional[_StepFunction] = ..., termination: Optional[_StepFunction] = ...,
             env: Optional[_EnvSource] = ...,
             render: Optional[_Path] = ...) -> list[dict[str, Any]]: ...

def load_run(run_dir: _Path, seed: int = ..., overrides: Optional[Mapping[str, Any]] = ...,
             reward: Optional[_StepFunction] = ...,
             termination: Optional[_StepFunction] = ...,
             env: Optional[_EnvSource] = ...) -> Agent: ...
