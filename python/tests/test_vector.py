"""Vectors of environments: batched arrays, C++ threads, same-step automatic resets."""
import numpy as np
import pytest

import cmbrl


@pytest.mark.parametrize("spin_us", [2000, 0])
def test_a_vector_steps_as_its_environments_do_one_by_one_with_auto_reset(spin_us):
    n = 3
    envs = cmbrl.make_vec("PointGoal1", num_envs=n, threads=2, spin_us=spin_us,
                          autoreset_mode="same-step")
    singles = [cmbrl.make("PointGoal1") for _ in range(n)]
    obs, _ = envs.reset(seed=10)
    assert obs.shape == (n, envs.single_observation_space.shape[0])
    for k, env in enumerate(singles):
        assert np.array_equal(obs[k], env.reset(seed=10 + k)[0])
    rng = np.random.default_rng(0)
    ended = np.zeros(n, dtype=bool)
    steps = singles[0].max_episode_steps + 5
    for _ in range(steps):
        actions = rng.uniform(-1, 1, size=(n, 2))
        obs, rewards, costs, terminated, truncated, info = envs.step(actions)
        assert obs.shape[0] == rewards.shape[0] == costs.shape[0] == n
        assert terminated.dtype == bool and truncated.dtype == bool
        for k, env in enumerate(singles):
            o, r, c, te, tr, _ = env.step(actions[k])
            assert rewards[k] == r and costs[k] == c
            assert (terminated[k], truncated[k]) == (te, tr)
            if te or tr:
                assert info["_final_obs"][k] and info["_final_info"][k]
                assert np.array_equal(info["final_obs"][k], o)
                assert info["final_info"]["goal_met"][k] == info["goal_met"][k]
                o, _ = env.reset()
                ended[k] = True
            else:
                assert not info["_final_obs"][k] and not info["_final_info"][k]
            assert np.array_equal(obs[k], o)
    assert ended.all()


def test_bad_actions_for_a_vector_are_named():
    envs = cmbrl.make_vec("CarGoal1", num_envs=2)
    envs.reset(seed=0)
    with pytest.raises(cmbrl.Error, match="shape"):
        envs.step(np.zeros(2))
    bad = np.zeros((2, 2))
    bad[1, 0] = np.inf
    with pytest.raises(cmbrl.Error, match="environment 1"):
        envs.step(bad)
    envs.close()
    with pytest.raises(cmbrl.Error, match="closed"):
        envs.step(np.zeros((2, 2)))
    with pytest.raises(cmbrl.Error, match="num_envs"):
        cmbrl.make_vec("CarGoal1", num_envs=0)
    with pytest.raises(cmbrl.Error, match="spin_us is -1: expected an integer from 0"):
        cmbrl.make_vec("CarGoal1", num_envs=2, spin_us=-1)


def test_disabled_autoreset_waits_for_a_masked_reset():
    n = 2
    envs = cmbrl.make_vec("PointGoal1", num_envs=n, threads=2, autoreset_mode="disabled")
    assert getattr(envs.metadata["autoreset_mode"], "value", "disabled") in ("Disabled",
                                                                             "disabled")
    singles = [cmbrl.make("PointGoal1") for _ in range(n)]
    with pytest.raises(cmbrl.Error, match="first reset must reset every environment"):
        envs.reset(seed=3, options={"reset_mask": np.array([True, False])})
    obs, info = envs.reset(seed=3, options={"reset_mask": np.array([True, True])})
    assert info == {}
    for k, env in enumerate(singles):
        assert np.array_equal(obs[k], env.reset(seed=3 + k)[0])
    ended = np.zeros(n, dtype=bool)
    for _ in range(singles[0].max_episode_steps):
        obs, _, _, terminated, truncated, info = envs.step(np.full((n, 2), 0.3))
        assert "final_obs" not in info and "final_info" not in info
        for k, env in enumerate(singles):
            o, _, _, te, tr, _ = env.step(np.full(2, 0.3))
            assert np.array_equal(obs[k], o)  # the last observation itself, not reset
        ended = terminated | truncated
        if ended.any():
            break
    assert ended.any() and not ended.all()  # the goal ends one episode before the time limit
    k = int(np.argmax(ended))
    with pytest.raises(cmbrl.Error, match=f"environment {k} is stepped before a reset"):
        envs.step(np.zeros((n, 2)))
    kept = obs[~ended].copy()
    obs, _ = envs.reset(options={"reset_mask": ended})
    assert np.array_equal(obs[k], singles[k].reset()[0])  # continues its generator
    assert np.array_equal(obs[~ended], kept)               # untouched, as Gymnasium keeps them
    obs, *_ = envs.step(np.full((n, 2), 0.1))
    for j, env in enumerate(singles):
        assert np.array_equal(obs[j], env.step(np.full(2, 0.1))[0])
    with pytest.raises(cmbrl.Error, match="reset_mask has shape"):
        envs.reset(options={"reset_mask": [True]})
    with pytest.raises(cmbrl.Error, match="only 'reset_mask'"):
        envs.reset(options={"mask": [True, True]})
    with pytest.raises(cmbrl.Error, match="autoreset_mode is 'never'"):
        cmbrl.make_vec("PointGoal1", num_envs=1, autoreset_mode="never")
    # A masked reset works in every mode, as Gymnasium's (the environment then steps on).
    same_step = cmbrl.make_vec("PointGoal1", num_envs=2, autoreset_mode="same-step")
    same_step.reset(seed=0)
    obs, _ = same_step.reset(seed=[None, 8], options={"reset_mask": np.array([False, True])})
    assert np.array_equal(obs[1], cmbrl.make("PointGoal1").reset(seed=8)[0])


def test_a_vector_too_large_for_the_memory_is_refused_by_name():
    # The first environment is made and measured; 100 million of them are not attempted.
    with pytest.raises(cmbrl.Error, match=r"num_envs 100000000: .* MiB each\) would need"):
        cmbrl.make_vec("PointGoal1", num_envs=100_000_000)


def test_a_vector_of_envs_observing_the_previous_action_matches_single_ones():
    vec = cmbrl.make_vec("CarGoal2", 3, previous_action=True, threads=2)
    singles = [cmbrl.make("CarGoal2", previous_action=True) for _ in range(3)]
    assert vec.single_observation_space.shape == singles[0].observation_space.shape
    obs, _ = vec.reset(seed=5)
    assert np.array_equal(obs, [env.reset(seed=5 + k)[0] for k, env in enumerate(singles)])
    rng = np.random.default_rng(0)
    for _ in range(5):
        actions = rng.uniform(-1.5, 1.5, (3, 2))
        obs = vec.step(actions)[0]
        assert np.array_equal(obs, [env.step(a)[0] for env, a in zip(singles, actions)])
    assert np.array_equal(obs[:, -2:], np.clip(actions, -1, 1))
    vec.close()
