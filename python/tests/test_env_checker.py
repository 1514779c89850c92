"""The essential checks of Gymnasium's env_checker and check_env, written out here (gymnasium is
optional, and Debian 12 has none), run on every task and variant. Where Safety-Gymnasium's API
differs from Gymnasium's (step returns the cost as its own sixth value), Safety-Gymnasium's is
checked."""
import numpy as np
import pytest

import cmbrl

CASES = [(task, variant) for task in cmbrl.tasks() for variant in cmbrl.variants(task)]


def _in_space(space, x):
    return space.contains(np.asarray(x, dtype=space.dtype)) and np.asarray(x).dtype == space.dtype


@pytest.mark.parametrize("task,variant", CASES)
def test_reset_and_step_return_what_the_api_promises(task, variant):
    env = cmbrl.make(task, variant=variant)
    assert env.observation_space.shape == (len(env.observation_names),)
    assert env.action_space.shape == (len(env.action_names),)
    # The environment truncates itself; its spec names no TimeLimit (which expects five values).
    assert env.spec.max_episode_steps is None and env.max_episode_steps > 0
    assert env.metadata["render_fps"] > 0 and env.unwrapped is env
    # reset: (observation in the space, info dict); the seed keyword and options are accepted.
    result = env.reset(seed=11, options=None)
    assert isinstance(result, tuple) and len(result) == 2
    obs, info = result
    assert isinstance(info, dict)
    assert _in_space(env.observation_space, obs), "the first observation is outside its space"
    for _ in range(25):
        action = env.action_space.sample()
        assert env.action_space.contains(action)
        result = env.step(action)
        assert isinstance(result, tuple) and len(result) == 6
        obs, reward, cost, terminated, truncated, info = result
        assert _in_space(env.observation_space, obs)
        assert isinstance(reward, float) and np.isfinite(reward)
        assert isinstance(cost, float) and cost >= 0
        assert isinstance(terminated, bool) and isinstance(truncated, bool)
        assert isinstance(info, dict)
        if terminated or truncated:
            env.reset()


@pytest.mark.parametrize("task,variant", CASES)
def test_seeding_is_deterministic_as_gymnasium_requires(task, variant):
    # check_env's reset checks: the same seed gives the same first observation and the same
    # np_random; a reset without a seed after a seeded one continues (does not repeat it).
    env = cmbrl.make(task, variant=variant)
    first, _ = env.reset(seed=123)
    draw = env.np_random.random()
    again, _ = env.reset(seed=123)
    assert np.array_equal(first, again)
    assert env.np_random.random() == draw
    other, _ = env.reset()
    assert not np.array_equal(first, other)
    # The same seed and the same actions give the same trajectory in another instance.
    twin = cmbrl.make(task, variant=variant)
    env.reset(seed=7)
    twin.reset(seed=7)
    actions = np.random.default_rng(0).uniform(-1, 1, size=(40, env.action_space.shape[0]))
    for action in actions:
        a, b = env.step(action), twin.step(action)
        assert np.array_equal(a[0], b[0]) and a[1:5] == b[1:5]


@pytest.mark.parametrize("task,variant", CASES)
def test_render_and_close(task, variant):
    env = cmbrl.make(task, variant=variant, render_mode="rgb_array", render_size=64)
    env.reset(seed=0)
    frame = env.render()
    # render_size is the picture's width; its height adds the caption's band.
    assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[1:] == (64, 3)
    env.close()
    env.close()  # closing twice is allowed, as in Gymnasium
    assert env.closed
    with pytest.raises(cmbrl.Error, match="closed"):
        env.step(np.zeros(env.action_space.shape))


@pytest.mark.parametrize("task", cmbrl.tasks())
def test_the_vector_env_follows_the_single_env_spaces(task):
    envs = cmbrl.make_vec(task, num_envs=3, threads=1)
    single = cmbrl.make(task)
    assert envs.single_observation_space.shape == single.observation_space.shape
    assert envs.single_action_space.shape == single.action_space.shape
    assert envs.observation_space.shape == (3,) + single.observation_space.shape
    obs, info = envs.reset(seed=[1, 2, 3])
    assert obs.shape == envs.observation_space.shape and isinstance(info, dict)
    obs, rewards, costs, terminated, truncated, info = envs.step(envs.action_space.sample())
    assert obs.shape == (3,) + single.observation_space.shape
    assert rewards.shape == costs.shape == terminated.shape == truncated.shape == (3,)
    assert terminated.dtype == truncated.dtype == bool
    envs.close()
