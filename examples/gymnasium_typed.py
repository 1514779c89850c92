#!/usr/bin/env python3
"""cmbrl's environments as Gymnasium's own classes, for code typed against Gymnasium (it passes
mypy --strict: python/tests/test_typing.py). Needs gymnasium:

    PYTHONPATH=build/python:<gymnasium's folder> python3 examples/gymnasium_typed.py

A cmbrl.Env is a gymnasium.Env whose step gives Safety-Gymnasium's six values; cmbrl.CostInInfo
makes it Gymnasium's five, the cost in info["cost"], for Gymnasium's wrappers; a cmbrl.VectorEnv
is a gymnasium.vector.VectorEnv.
"""
from typing import Any

import gymnasium
import numpy as np
import numpy.typing as npt
from gymnasium.wrappers import RecordEpisodeStatistics
from gymnasium.wrappers.vector import RecordEpisodeStatistics as VectorEpisodeStatistics

import cmbrl

Array = npt.NDArray[np.float64]


def episode_cost(env: gymnasium.Env[Array, Array], seed: int) -> tuple[float, float]:
    """(return, violations) of one random episode of a five-value environment."""
    env.action_space.seed(seed)
    env.reset(seed=seed)
    episode_return, violations, done = 0.0, 0.0, False
    while not done:
        _, reward, terminated, truncated, info = env.step(env.action_space.sample())
        episode_return += float(reward)
        violations += float(info["cost"])
        done = terminated or truncated
    return episode_return, violations


def vector_steps(envs: gymnasium.vector.VectorEnv[Array, Array, npt.NDArray[Any]],
                 steps: int) -> int:
    """How many episodes end in `steps` random steps of a vector."""
    envs.action_space.seed(0)
    envs.reset(seed=0)
    ended = 0
    for _ in range(steps):
        _, _, terminations, truncations, _ = envs.step(envs.action_space.sample())
        ended += int(np.sum(terminations | truncations))
    return ended


def main() -> None:
    env = cmbrl.make("SafetyPointGoal1-v0")  # six values
    as_gymnasium: gymnasium.Env[Array, Array] = env
    space: gymnasium.spaces.Box = env.observation_space
    spec: gymnasium.envs.registration.EnvSpec = env.spec
    print(f"{spec.id}: observation {space.shape}, six-value step, render mode "
          f"{as_gymnasium.render_mode}")
    env.close()

    wrapped = RecordEpisodeStatistics(cmbrl.CostInInfo(cmbrl.make("SafetyPointGoal1-v0")))
    episode_return, violations = episode_cost(wrapped, seed=0)
    print(f"one episode under RecordEpisodeStatistics: return {episode_return:.2f}, "
          f"violations {violations:.0f}")
    wrapped.close()

    registered = gymnasium.make("SafetyCarGoal1Gymnasium-v0")
    print(f"gymnasium.make: {registered.spec.id if registered.spec else '?'}, "
          f"return and violations {episode_cost(registered, seed=1)}")
    registered.close()

    vector = VectorEpisodeStatistics(cmbrl.VectorCostInInfo(cmbrl.make_vec("PointGoal1", 2)))
    print(f"a vector of 2 under Gymnasium's vector statistics: {vector_steps(vector, 1000)} "
          "episodes ended in 1000 steps")
    vector.close()


if __name__ == "__main__":
    main()
