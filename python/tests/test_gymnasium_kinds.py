"""Where gymnasium is importable, cmbrl's environments are its kinds (gymnasium.Env,
gymnasium.vector.VectorEnv) and its spaces gymnasium's Boxes. gymnasium is not a dependency, so
the test gives a fresh interpreter a stand-in package with the parts of gymnasium 1.x's classes
that a subclass could trip on (np_random and unwrapped properties, a closed attribute that
close() sets, __del__ closing, Generic bases), with the registry and the names cmbrl imports, and
runs a Gymnasium-style loop there. Where the
real gymnasium is installed, it is used instead."""
import os
import subprocess
import sys
import textwrap

FAKE_GYMNASIUM = {
    "gymnasium/__init__.py": """
        from typing import Generic, TypeVar
        from gymnasium import envs, spaces, vector  # noqa: F401
        ObsType, ActType = TypeVar("ObsType"), TypeVar("ActType")
        FAKE = True

        class Env(Generic[ObsType, ActType]):
            metadata = {"render_modes": []}
            render_mode = None
            spec = None
            _np_random = None

            @property
            def np_random(self):
                raise AssertionError("gymnasium.Env.np_random used instead of cmbrl's")

            @property
            def unwrapped(self):
                raise AssertionError("gymnasium.Env.unwrapped used instead of cmbrl's")

            def close(self):
                raise AssertionError("gymnasium.Env.close used instead of cmbrl's")

        class Wrapper(Env):  # gymnasium 1.x: no __getattr__ forwarding
            def __init__(self, env):
                assert isinstance(env, Env)
                self.env = env

            @property
            def action_space(self):
                return self.env.action_space

            @property
            def unwrapped(self):
                return self.env.unwrapped

            def reset(self, *, seed=None, options=None):
                return self.env.reset(seed=seed, options=options)

            def close(self):
                return self.env.close()
    """,
    "gymnasium/envs/__init__.py": """
        from gymnasium.envs import registration  # noqa: F401
    """,
    "gymnasium/envs/registration.py": """
        class EnvSpec:
            def __init__(self, id, entry_point=None, reward_threshold=None,
                         nondeterministic=False, max_episode_steps=None, order_enforce=True,
                         disable_env_checker=False, kwargs=None, additional_wrappers=(),
                         vector_entry_point=None):
                self.id, self.entry_point, self.kwargs = id, entry_point, dict(kwargs or {})
                self.max_episode_steps = max_episode_steps
                self.disable_env_checker = disable_env_checker

        registry = {}

        def register(id, **fields):
            assert id not in registry
            registry[id] = EnvSpec(id, **fields)
    """,
    "gymnasium/spaces.py": """
        import numpy as np

        class Box:
            def __init__(self, low, high, dtype=np.float32):
                self.low, self.high, self.dtype = np.asarray(low), np.asarray(high), dtype
                self.shape = self.low.shape
                self._rng = np.random.default_rng(0)

            def seed(self, seed=None):
                self._rng = np.random.default_rng(seed)

            def sample(self):
                return self._rng.uniform(self.low, self.high).astype(self.dtype)
    """,
    "gymnasium/vector/__init__.py": """
        from enum import Enum
        from typing import Generic, TypeVar
        ObsType, ActType, ArrayType = TypeVar("ObsType"), TypeVar("ActType"), TypeVar("ArrayType")

        class AutoresetMode(Enum):
            NEXT_STEP = "NextStep"
            SAME_STEP = "SameStep"
            DISABLED = "Disabled"

        class VectorEnv(Generic[ObsType, ActType, ArrayType]):
            metadata = {}
            closed = False
            num_envs = 0

            def close(self, **kwargs):
                raise AssertionError("gymnasium's VectorEnv.close used instead of cmbrl's")

            def __del__(self):
                if not getattr(self, "closed", True):
                    self.close()

        class VectorWrapper(VectorEnv):
            def __init__(self, env):
                assert isinstance(env, VectorEnv)
                self.env = env

            @property
            def action_space(self):
                return self.env.action_space

            def reset(self, *, seed=None, options=None):
                return self.env.reset(seed=seed, options=options)

            def close(self, **kwargs):
                return self.env.close()
    """,
}

LOOP = """
    import copy, pickle
    import gymnasium, numpy as np
    import cmbrl
    assert getattr(gymnasium, "FAKE", False) == {fake}
    assert issubclass(cmbrl.Env, gymnasium.Env)
    assert issubclass(cmbrl.VectorEnv, gymnasium.vector.VectorEnv)
    env = cmbrl.make("PointGoal1")
    assert isinstance(env, gymnasium.Env) and env.unwrapped is env
    assert isinstance(env.action_space, gymnasium.spaces.Box)
    obs, info = env.reset(seed=3)
    assert isinstance(env.np_random, np.random.Generator)
    twin = copy.deepcopy(env)
    for _ in range(20):
        action = env.action_space.sample()
        assert np.array_equal(env.step(action)[0], twin.step(action)[0])
    assert pickle.loads(pickle.dumps(env)).spec.id == "PointGoal1"
    assert isinstance(env.spec, gymnasium.envs.registration.EnvSpec) and cmbrl.EnvSpec is type(
        env.spec)
    assert "SafetyPointGoal1Gymnasium-v0" in gymnasium.envs.registration.registry
    five = cmbrl.CostInInfo(copy.deepcopy(env))
    assert isinstance(five, gymnasium.Wrapper) and five.unwrapped is five.env
    five.reset(seed=5)
    assert len(five.step(five.action_space.sample())) == 5 and "cost" in five.step(
        five.action_space.sample())[4]
    with env:
        pass
    assert env.closed
    vec = cmbrl.make_vec("CarGoal1", num_envs=3)
    assert isinstance(vec, gymnasium.vector.VectorEnv) and vec.num_envs == 3
    assert vec.metadata["autoreset_mode"] is gymnasium.vector.AutoresetMode.NEXT_STEP
    obs, info = vec.reset(seed=[1, 2, 3])
    obs, reward, cost, terminated, truncated, info = vec.step(vec.action_space.sample())
    assert obs.shape[0] == 3 and not vec.closed
    wrapped = cmbrl.VectorCostInInfo(vec)
    assert isinstance(wrapped, gymnasium.vector.VectorWrapper)
    assert wrapped.step(wrapped.action_space.sample())[4]["cost"].shape == (3,)
    vec.close()
    assert vec.closed
    del vec
    print("gymnasium kinds: ok")
"""


def _run(code, extra_path):
    environment = dict(os.environ)
    environment["PYTHONPATH"] = os.pathsep.join(
        [p for p in [extra_path, environment.get("PYTHONPATH")] if p])
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], env=environment,
                          capture_output=True, text=True, timeout=300)


def test_with_gymnasium_the_envs_are_its_kinds(tmp_path):
    try:
        import gymnasium  # noqa: F401
        real = True
    except ImportError:
        real = False
    if not real:
        for name, text in FAKE_GYMNASIUM.items():
            path = tmp_path / name
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(textwrap.dedent(text))
    result = _run(LOOP.format(fake=not real), None if real else str(tmp_path))
    assert result.returncode == 0, result.stderr
    assert "gymnasium kinds: ok" in result.stdout


def test_without_gymnasium_the_look_alikes_stand_in(tmp_path):
    # A gymnasium that cannot be imported (as on a machine without it).
    (tmp_path / "gymnasium").mkdir()
    (tmp_path / "gymnasium" / "__init__.py").write_text("raise ImportError('no gymnasium here')\n")
    result = _run("""
        import cmbrl, cmbrl.spaces
        assert cmbrl.Env.__mro__[-1] is object and len(cmbrl.Env.__mro__) == 3
        env = cmbrl.make("PointGoal1")
        assert isinstance(env.action_space, cmbrl.spaces._Box)
        print("look-alikes: ok")
    """, str(tmp_path))
    assert result.returncode == 0, result.stderr
    assert "look-alikes: ok" in result.stdout
