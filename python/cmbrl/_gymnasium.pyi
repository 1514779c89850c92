# Type stubs of cmbrl._gymnasium. A type checker sees cmbrl's environments, wrappers and spaces as
# Gymnasium's classes (generic parameters included) where gymnasium is installed. Where it is not,
# these names are Any (the imports below are then unresolved, quietly): cmbrl's classes keep the
# types of the members their stubs declare, and attributes they do not declare are unchecked.
from gymnasium import Env as Env  # type: ignore[import]
from gymnasium import Wrapper as Wrapper  # type: ignore[import]
from gymnasium.envs import registration as registration  # type: ignore[import]
from gymnasium.envs.registration import EnvSpec as EnvSpec  # type: ignore[import]
from gymnasium.spaces import Box as Box  # type: ignore[import]
from gymnasium.vector import AutoresetMode as AutoresetMode  # type: ignore[import]
from gymnasium.vector import VectorEnv as VectorEnv  # type: ignore[import]
from gymnasium.vector import VectorWrapper as VectorWrapper  # type: ignore[import]

AVAILABLE: bool
