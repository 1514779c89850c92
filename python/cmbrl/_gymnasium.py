"""Gymnasium, where it is importable: the one place cmbrl imports it. cmbrl's environments,
wrappers and spaces are then of Gymnasium's own classes (as Safety-Gymnasium's are); without it
they stand alone, and AVAILABLE is False. Type checkers see the same through _gymnasium.pyi."""
try:  # gymnasium is optional
    import gymnasium as _gymnasium
    import gymnasium.envs.registration as registration
    import gymnasium.spaces
    import gymnasium.vector
except ImportError:  # pragma: no cover - depends on the machine
    AVAILABLE = False
    Env = VectorEnv = object  # what cmbrl's Env and VectorEnv derive from
    Wrapper = VectorWrapper = EnvSpec = Box = AutoresetMode = registration = None
else:
    AVAILABLE = True
    Env, Wrapper = _gymnasium.Env, _gymnasium.Wrapper
    VectorEnv, VectorWrapper = _gymnasium.vector.VectorEnv, _gymnasium.vector.VectorWrapper
    AutoresetMode = _gymnasium.vector.AutoresetMode
    EnvSpec = registration.EnvSpec
    Box = _gymnasium.spaces.Box
