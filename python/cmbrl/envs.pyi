# Type stubs of cmbrl.envs.
from typing import Any, Iterable, Mapping, Optional, Self, Sequence, Union

import numpy as np
import numpy.typing as npt

from . import _gymnasium
from ._common import _Bools, _Closable, _Floats, _NotCopyable, _Path
from .spaces import _Box

def tasks() -> list[str]: ...
def variants(task: str) -> list[str]: ...

# Gymnasium's EnvSpec where gymnasium is importable, a look-alike with its fields otherwise.
class EnvSpec(_gymnasium.EnvSpec):
    id: str
    entry_point: Optional[str]
    reward_threshold: Optional[float]
    nondeterministic: bool
    max_episode_steps: Optional[int]
    order_enforce: bool
    disable_env_checker: bool
    kwargs: dict[str, Any]
    additional_wrappers: tuple[Any, ...]
    vector_entry_point: Optional[str]
    namespace: Optional[str]
    name: str
    version: Optional[int]
    def __init__(self, id: str, entry_point: Optional[str] = ...,
                 reward_threshold: Optional[float] = ..., nondeterministic: bool = ...,
                 max_episode_steps: Optional[int] = ..., order_enforce: bool = ...,
                 disable_env_checker: bool = ..., kwargs: Optional[Mapping[str, Any]] = ...,
                 additional_wrappers: Sequence[Any] = ...,
                 vector_entry_point: Optional[str] = ...) -> None: ...
    def make(self, **kwargs: Any) -> Any: ...
    def to_json(self) -> str: ...

# Where gymnasium is installed, a gymnasium.Env whose step gives Safety-Gymnasium's six values.
class Env(_Closable, _gymnasium.Env[_Floats, _Floats]):
    # _Closable's, restated: mypy reads the two bases' Self-typed `with` methods as in conflict.
    def __enter__(self) -> Self: ...
    def __exit__(self, *exc: object) -> bool: ...
    reward_range: tuple[float, float]
    task: str
    variant: str
    spawn: str
    previous_action: bool
    render_mode: Optional[str]
    render_size: int
    observation_names: list[str]
    action_names: list[str]
    observation_space: _Box
    action_space: _Box
    max_episode_steps: int
    agent_step_seconds: float
    metadata: dict[str, Any]
    spec: EnvSpec
    def __init__(self, task: str, variant: Optional[str] = ..., spawn: str = ...,
                 render_mode: Optional[str] = ..., render_size: int = ...,
                 previous_action: bool = ...) -> None: ...
    def reset(self, seed: Optional[int] = ..., options: Optional[Mapping[str, Any]] = ...
              ) -> tuple[_Floats, dict[str, Any]]: ...
    @property
    def np_random(self) -> np.random.Generator: ...
    @np_random.setter
    def np_random(self, generator: np.random.Generator) -> None: ...
    @property
    def np_random_seed(self) -> int: ...
    def close(self) -> None: ...
    # (observation, reward, cost, terminated, truncated, info): Safety-Gymnasium's six values.
    def step(self, action: npt.ArrayLike  # type: ignore[override]
             ) -> tuple[_Floats, float, float, bool, bool, dict[str, Any]]: ...
    def ground_truth(self) -> dict[str, Any]: ...
    def render(self) -> Optional[npt.NDArray[np.uint8]]: ...
    def save_picture(self, path: _Path, caption: str = ...,
                     predictions: Optional[Iterable[Mapping[str, Any]]] = ...) -> None: ...
    @property
    def unwrapped(self) -> Env: ...
    def __getstate__(self) -> dict[str, Any]: ...
    def __setstate__(self, state: dict[str, Any]) -> None: ...
    def __copy__(self, memo: Any = ...) -> Env: ...
    def __deepcopy__(self, memo: Any = ...) -> Env: ...

# Where gymnasium is installed, a gymnasium.vector.VectorEnv whose step gives six values. (Its
# `closed` is _Closable's read-only property, where Gymnasium's is a plain attribute.)
class VectorEnv(_Closable, _NotCopyable,  # type: ignore[misc]
                _gymnasium.VectorEnv[_Floats, _Floats, npt.NDArray[Any]]):
    metadata: dict[str, Any]
    task: str
    variant: str
    num_envs: int
    single_observation_space: _Box
    single_action_space: _Box
    observation_space: _Box
    action_space: _Box
    def __init__(self, task: str, num_envs: int, variant: Optional[str] = ...,
                 spawn: str = ..., threads: Optional[int] = ..., spin_us: int = ...,
                 autoreset_mode: Any = ..., previous_action: bool = ...) -> None: ...
    def close(self, **kwargs: Any) -> None: ...
    def reset(self, seed: Union[int, Sequence[Optional[int]], None] = ...,
              options: Optional[Mapping[str, Any]] = ...) -> tuple[_Floats, dict[str, Any]]: ...
    # (observations, rewards, costs, terminations, truncations, infos), batched.
    def step(self, actions: npt.ArrayLike  # type: ignore[override]
             ) -> tuple[_Floats, _Floats, _Floats, _Bools, _Bools, dict[str, Any]]: ...

def make(task: str, variant: Optional[str] = ..., spawn: str = ...,
         render_mode: Optional[str] = ..., render_size: int = ...,
         previous_action: bool = ...) -> Env: ...
def make_vec(task: str, num_envs: int, variant: Optional[str] = ..., spawn: str = ...,
             threads: Optional[int] = ..., spin_us: int = ...,
             autoreset_mode: Any = ..., previous_action: bool = ...) -> VectorEnv: ...
class _Forwarding:
    env: Any
    def __init__(self, env: Any) -> None: ...
    def __getattr__(self, name: str) -> Any: ...
    @property
    def unwrapped(self) -> Any: ...
    def reset(self, *, seed: Union[int, Sequence[int], None] = ...,
              options: Optional[Mapping[str, Any]] = ...) -> tuple[_Floats, dict[str, Any]]: ...
    def close(self) -> None: ...

# Gymnasium's five-value step, the cost in info["cost"]: a gymnasium.Wrapper where gymnasium is
# importable (then what the wrapped Env lacks is gymnasium's), a _Forwarding otherwise.
class CostInInfo(_gymnasium.Wrapper[_Floats, _Floats, _Floats, _Floats]):
    env: Env
    def __init__(self, env: Env) -> None: ...
    def reset(self, *, seed: Optional[int] = ...,
              options: Optional[dict[str, Any]] = ...) -> tuple[_Floats, dict[str, Any]]: ...
    def step(self, action: npt.ArrayLike
             ) -> tuple[_Floats, float, bool, bool, dict[str, Any]]: ...

class VectorCostInInfo(_gymnasium.VectorWrapper):
    env: VectorEnv
    def __init__(self, env: VectorEnv) -> None: ...
    # Gymnasium's VectorWrapper leaves its types unbound, which its subclasses cannot match.
    def reset(self, *,  # type: ignore[override]
              seed: Union[int, Sequence[Optional[int]], None] = ...,
              options: Optional[dict[str, Any]] = ...) -> tuple[_Floats, dict[str, Any]]: ...
    def step(self, actions: npt.ArrayLike  # type: ignore[override]
             ) -> tuple[_Floats, _Floats, _Bools, _Bools, dict[str, Any]]: ...
    def close(self, **kwargs: Any) -> None: ...
