#!/usr/bin/env python3
"""Your own environment, planned by RCE with a constraint it learns from 0/1 signals.

A point mass on a plane (a 2-D double integrator, no MuJoCo) must reach a target while staying
out of a keep-out disc that lies between it and the target. The env says only whether a step
ended inside the disc (cost 1) or not (0); RCE's classifier learns where that happens, and the
planner avoids it. The planner scores plans with `reward` below, a vectorised function of
predicted steps.

    PYTHONPATH=build/python python3 examples/custom_env.py --out runs/custom-env
    PYTHONPATH=build/python python3 examples/custom_env.py --out /tmp/di --steps 400  # a taste
"""
import argparse

import numpy as np

import cmbrl

TARGET = np.array([1.0, 1.0])
KEEP_OUT_CENTRE, KEEP_OUT_RADIUS = np.array([0.0, 0.0]), 0.5


class DoubleIntegrator:
    """Gymnasium-style: observation (x, y, vx, vy), action (ax, ay) in [-1, 1]; 100 steps of
    0.1 s. reward: minus the distance to the target; cost: 1 inside the keep-out disc."""

    dt = 0.1
    max_steps = 100
    metadata = {"render_modes": ["rgb_array"]}

    def __init__(self, render_mode=None):
        self.render_mode = render_mode  # "rgb_array": render() draws the plane (cmbrl eval --render)
        self.observation_space = cmbrl.Box(np.full(4, -np.inf), np.full(4, np.inf))
        self.action_space = cmbrl.Box(-np.ones(2), np.ones(2))
        self._rng = np.random.default_rng()
        self._state = np.zeros(4)
        self._t = 0

    def reset(self, seed=None, options=None):
        if seed is not None:
            self._rng = np.random.default_rng(seed)
        self._state = np.concatenate([[-1.0, -1.0] + self._rng.uniform(-0.2, 0.2, 2), [0.0, 0.0]])
        self._t = 0
        return self._state.copy(), {}

    def step(self, action):
        a = np.clip(np.asarray(action, dtype=float), -1.0, 1.0)
        velocity = 0.95 * self._state[2:] + a * self.dt
        position = self._state[:2] + velocity * self.dt
        self._state = np.concatenate([position, velocity])
        self._t += 1
        reward = -float(np.linalg.norm(position - TARGET))
        cost = float(np.linalg.norm(position - KEEP_OUT_CENTRE) < KEEP_OUT_RADIUS)
        truncated = self._t >= self.max_steps
        return self._state.copy(), reward, cost, False, truncated, {}

    def render(self, size=160):
        """The plane from -1.5 to 1.5 m: the keep-out disc red, the target green, the mass blue."""
        if self.render_mode != "rgb_array":
            return None
        ys, xs = np.mgrid[0:size, 0:size]
        x, y = xs * 3.0 / size - 1.5, 1.5 - ys * 3.0 / size
        image = np.full((size, size, 3), 255, dtype=np.uint8)
        image[np.hypot(x - KEEP_OUT_CENTRE[0], y - KEEP_OUT_CENTRE[1]) < KEEP_OUT_RADIUS] = (240, 160, 160)
        image[np.hypot(x - TARGET[0], y - TARGET[1]) < 0.08] = (40, 170, 60)
        image[np.hypot(x - self._state[0], y - self._state[1]) < 0.06] = (30, 60, 200)
        return image


def reward(states, actions, next_states):
    """The planner's reward of N predicted steps at once: minus the distance to the target."""
    return -np.linalg.norm(next_states[:, :2] - TARGET, axis=1)


# A small run: a few minutes on one core (the paper's network sizes are for the Goal tasks).
SMALL = {"planner": "rce",
         "training": {"pretrain_episodes": 20, "pretrain_steps": 100, "episodes_per_epoch": 2},
         "ensemble": {"ensemble_size": 4, "hidden_sizes": [64, 64], "max_epochs": 30},
         "classifier": {"rounds": 50},
         "planning": {"horizon": 10, "population": 200, "elites": 10, "max_iterations": 5}}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", required=True, help="run directory")
    parser.add_argument("--steps", type=int, default=2000, help="agent steps")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    # The whole of what cmbrl asks: train on the env, then evaluate or load the agent and act.
    cmbrl.train(env=DoubleIntegrator, reward=reward, config=SMALL, out=args.out,
                steps=args.steps, seed=args.seed)
    for episode in cmbrl.evaluate(args.out, episodes=3, seed=1000, env=DoubleIntegrator,
                                  reward=reward):
        print(f"an episode of the trained agent: return {episode['return']:.1f}, "
              f"violations {episode['cost']:.0f}")
    # Or act yourself: agent.act(observation) gives the action in the env's own box.
    agent = cmbrl.load_run(args.out, env=DoubleIntegrator, reward=reward)
    print("its first action from the start:", agent.act(DoubleIntegrator().reset(seed=0)[0]))


if __name__ == "__main__":
    main()
