"""With the real Gymnasium importable: every registered id makes, and its five-value form passes
Gymnasium's check_env. Checked against Farama-Foundation/Gymnasium v1.3.0, and on 2026-12-03
against v1.4.0 (commit 3f0476a; this module with python/tests' other Gymnasium-importing ones:
243 passed). Skipped where gymnasium is not importable (Debian 12 has none)."""
import warnings

import numpy as np
import pytest

import cmbrl

gymnasium = pytest.importorskip("gymnasium")
env_checker = pytest.importorskip("gymnasium.utils.env_checker")
if not hasattr(gymnasium, "make"):  # the suite's stand-in, not the library
    pytest.skip("the real gymnasium is not importable", allow_module_level=True)

FIVE_VALUE = [env_id for env_id, _, _, five in cmbrl.registration.registered_ids() if five]

# What check_env says of every environment gymnasium.make wraps, and of Safety-Gymnasium's
# sensors' unbounded Box (its observation spaces are Box(-inf, inf) too).
EXPECTED = ("is different from the unwrapped version", "minimum value is -infinity",
            "maximum value is infinity")


@pytest.mark.parametrize("env_id", FIVE_VALUE)
def test_every_five_value_id_passes_check_env(env_id):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        env = gymnasium.make(env_id)
        env_checker.check_env(env)
    unexpected = [str(w.message) for w in caught
                  if not any(text in str(w.message) for text in EXPECTED)]
    assert unexpected == []
    assert env.spec.id == env_id and isinstance(env.spec, gymnasium.envs.registration.EnvSpec)
    env.close()


def test_the_six_value_id_and_the_module_prefix():
    env = gymnasium.make("SafetyPointButton1-v0")
    env.reset(seed=0)
    assert len(env.step(env.action_space.sample())) == 6
    made = gymnasium.make("cmbrl:SafetyCarGoal2Gymnasium-v0")
    assert made.unwrapped.task == "CarGoal2" and made.unwrapped.variant == "standard"
    paper = gymnasium.make("cmbrl/PointGoal2-v0")
    assert paper.unwrapped.variant == "paper"
    paper.reset(seed=1)
    _, _, _, _, info = paper.step(np.zeros(2))
    assert "cost" in info


def _vector_wrappers():
    from gymnasium.wrappers import vector as vw
    return [("RecordEpisodeStatistics", vw.RecordEpisodeStatistics),
            ("NormalizeObservation", vw.NormalizeObservation),
            ("FlattenObservation", vw.FlattenObservation),
            ("TransformObservation", lambda e: vw.TransformObservation(e, lambda o: 2 * o,
                                                                       e.observation_space)),
            ("DtypeObservation", lambda e: vw.DtypeObservation(e, np.float32)),
            ("NormalizeReward", vw.NormalizeReward), ("ClipAction", vw.ClipAction),
            ("RescaleAction", lambda e: vw.RescaleAction(e, -2.0, 2.0)),
            ("DictInfoToList", vw.DictInfoToList)]


@pytest.mark.parametrize("mode", ["sync", "async", "vector_entry_point"])
def test_make_vec_in_every_mode_under_every_vector_wrapper(mode):
    vec = gymnasium.make_vec("SafetyCarGoal2Gymnasium-v0", num_envs=4, vectorization_mode=mode)
    assert vec.metadata["autoreset_mode"] in list(gymnasium.vector.AutoresetMode)
    vec.close()
    for name, wrap in _vector_wrappers():
        # The paper's CarGoal2: 75-step episodes, so that autoresets happen.
        env = wrap(gymnasium.make_vec("cmbrl/CarGoal2-v0", num_envs=4, vectorization_mode=mode))
        env.reset(seed=[1, None, 5, 9])
        for _ in range(160):
            out = env.step(env.action_space.sample())
        assert len(out) == 5, name
        env.close()
