# Type stubs for cmbrl.spaces (PEP 561). Box() returns gymnasium.spaces.Box where gymnasium is
# importable, the look-alike _Box otherwise; for a type checker _Box is a gymnasium Box (where
# gymnasium is installed), with the members the two share, in gymnasium's signatures.
from typing import Any, Literal, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from . import _gymnasium

class _Box(_gymnasium.Box):
    dtype: np.dtype[Any]
    low: npt.NDArray[Any]
    high: npt.NDArray[Any]
    shape: tuple[int, ...]
    def __init__(self, low: npt.ArrayLike, high: npt.ArrayLike,
                 shape: Optional[Sequence[int]] = ..., dtype: npt.DTypeLike = ...,
                 seed: Optional[int] = ...) -> None: ...
    def seed(self, seed: Optional[int] = ...) -> Union[int, list[int], dict[str, int]]: ...
    @property
    def np_random(self) -> np.random.Generator: ...
    bounded_below: npt.NDArray[np.bool_]
    bounded_above: npt.NDArray[np.bool_]
    def is_bounded(self, manner: str = ...) -> bool: ...
    @property
    def is_np_flattenable(self) -> Literal[True]: ...
    def sample(self, mask: None = ..., probability: None = ...) -> npt.NDArray[Any]: ...
    def contains(self, x: Any) -> bool: ...
    def __contains__(self, x: Any) -> bool: ...
    def __eq__(self, other: Any) -> bool: ...
    __hash__: None  # type: ignore[assignment]

def Box(low: npt.ArrayLike, high: npt.ArrayLike, shape: Optional[Sequence[int]] = ...,
        dtype: npt.DTypeLike = ..., seed: Optional[int] = ...) -> _Box: ...
