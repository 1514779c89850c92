"""Python threads sharing one object take turns: hammering one env, one vector of envs or one
agent from several threads neither crashes the interpreter nor garbles a result."""
import threading

import numpy as np

import cmbrl
from conftest import tiny_config

TINY = tiny_config(60)


def hammer(work, threads=4):
    """Runs work(k) in `threads` threads at once; re-raises the first exception of any."""
    errors = []

    def run(k):
        try:
            work(k)
        except Exception as error:  # noqa: BLE001 - reported below
            errors.append(error)

    pool = [threading.Thread(target=run, args=(k,)) for k in range(threads)]
    for thread in pool:
        thread.start()
    for thread in pool:
        thread.join()
    if errors:
        raise errors[0]


def test_threads_stepping_one_env_take_turns():
    env = cmbrl.make("PointGoal2")
    env.reset(seed=0)
    size = env.observation_space.shape[0]

    def work(k):
        rng = np.random.default_rng(k)
        for _ in range(150):
            try:
                obs, reward, cost, terminated, truncated, info = env.step(
                    rng.uniform(-1, 1, size=2))
            except cmbrl.Error as error:
                # Another thread ended the episode between this thread's calls: the env says
                # so clearly and goes on after a reset.
                assert "call Reset first" in str(error)
                env.reset()
                continue
            assert obs.shape == (size,) and np.isfinite(obs).all()
            assert cost in (0.0, 1.0)
            if terminated or truncated:
                env.reset()
            env.ground_truth()

    hammer(work)


def test_threads_stepping_one_vector_env_take_turns():
    envs = cmbrl.make_vec("CarGoal1", num_envs=3)
    envs.reset(seed=0)

    def work(k):
        for _ in range(60):
            obs, rewards, costs, terminated, truncated, info = envs.step(np.zeros((3, 2)))
            assert obs.shape[0] == 3 and np.isfinite(obs).all()

    hammer(work, threads=3)


def test_threads_acting_with_one_agent_take_turns(tmp_path):
    cmbrl.train(config=TINY, out=str(tmp_path / "run"))
    agent = cmbrl.load_run(str(tmp_path / "run"))
    env = agent.make_env()
    obs, _ = env.reset(seed=0)
    agent.begin_episode()

    def work(k):
        for _ in range(10):
            action = agent.act(obs)
            assert action.shape == (2,) and np.isfinite(action).all()
            assert np.all(np.abs(action) <= 1.0)

    hammer(work, threads=3)


def test_distinct_envs_in_threads_match_the_same_envs_stepped_alone():
    def rollout(env, seed):
        env.reset(seed=seed)
        return [env.step(np.full(2, 0.5))[0] for _ in range(50)]

    alone = [rollout(cmbrl.make("PointGoal1"), seed) for seed in (1, 2)]
    together = [None, None]

    def work(k):
        together[k] = rollout(cmbrl.make("PointGoal1"), k + 1)

    hammer(work, threads=2)
    for a, b in zip(alone, together):
        assert all(np.array_equal(x, y) for x, y in zip(a, b))
