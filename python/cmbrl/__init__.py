"""cmbrl from Python: the Safety Gym Goal environments, vectors of them, training and trained runs.

    import cmbrl
    env = cmbrl.make("PointGoal1")                 # the paper's variant
    obs, info = env.reset(seed=0)
    obs, reward, cost, terminated, truncated, info = env.step(env.action_space.sample())

    envs = cmbrl.make_vec("PointGoal1", num_envs=4)  # stepped in C++ threads, auto-reset
    cmbrl.train(config=["configs/pointgoal1-rce.yaml", "configs/quickstart.yaml"], out="runs/q",
                steps=200)
    agent = cmbrl.load_run("runs/q")
    action = agent.act(obs)

Errors from the C++ core are raised as cmbrl.Error (a ValueError) with its message.
"""
import copy
import json
import math
import os
import re
import tempfile

import numpy as np

from . import _cmbrl
from .spaces import Box

try:  # gymnasium is optional: where it is importable, the environments are of its own kinds
    import gymnasium as _gymnasium
    import gymnasium.vector  # noqa: F401 (makes _gymnasium.vector available)
    _EnvBase, _VectorEnvBase = _gymnasium.Env, _gymnasium.vector.VectorEnv
    _WrapperBase, _VectorWrapperBase = _gymnasium.Wrapper, _gymnasium.vector.VectorWrapper
except ImportError:  # pragma: no cover - depends on the machine
    _EnvBase = _VectorEnvBase = object
    _WrapperBase = _VectorWrapperBase = None

Error = _cmbrl.Error
# The version of the C++ core this module was built from, and its source commit ("744c47e1a2b3",
# with "+dirty" for uncommitted changes): what a run's sessions.jsonl records as "cmbrl".
__version__ = _cmbrl.__version__
__commit__ = _cmbrl.__commit__

__all__ = ["Error", "Box", "Env", "EnvSpec", "VectorEnv", "Agent", "Ensemble", "CostClassifier", "make",
           "make_vec", "tasks", "train", "load_run", "read_runs", "report", "CostInInfo",
           "VectorCostInInfo"]


def tasks():
    """The registered task names."""
    return list(_cmbrl.env_names())


def _box(spec, dtype=np.float64):
    return Box(low=spec["low"], high=spec["high"], dtype=dtype)


class _NotCopyable:
    """Objects that hold a running simulation or a loaded run: copying one would share its C++
    object (copy.copy did), and pickling cannot carry a simulation mid-episode. Both are refused
    by name, saying what to do instead."""

    _instead = "make another one"

    def _refuse(self, what):
        raise Error(f"a cmbrl.{type(self).__name__} cannot be {what}: it holds a running C++ "
                    f"object; {self._instead}")

    def __copy__(self):
        self._refuse("copied")

    def __deepcopy__(self, memo):
        self._refuse("copied")

    def __reduce_ex__(self, protocol):
        self._refuse("pickled")


def _copy_through_state(obj, memo=None):
    """__copy__ and __deepcopy__ of the objects that hold a C++ object and carry its state through
    __getstate__/__setstate__ (Env, the standalone models): both give an independent object in the
    same state, where a shallow copy would share the C++ one."""
    clone = type(obj).__new__(type(obj))
    clone.__setstate__(copy.deepcopy(obj.__getstate__()))
    return clone


class _Closable:
    """What Env and VectorEnv share: the C++ object in self._env, close() and `with`."""

    def close(self):
        self._env.close()

    @property
    def closed(self):
        return self._env.closed

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _json_number(value):
    """numpy scalars in a config dict, as JSON numbers (json.dumps knows only Python's)."""
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating):
        return float(value)
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"a config value of type {type(value).__name__} is not a number or a list")


def _entropy_seed():
    """A seed from the operating system's entropy, for a first reset without one (Gymnasium's
    convention: unseeded environments differ from process to process)."""
    return int.from_bytes(os.urandom(8), "little") >> 1


_INT_MAX = 2**31 - 1  # the C++ side's int


def _as_int(value, what, low=1, high=_INT_MAX):
    """value as an int from low to high; refuses floats (2.5 is not silently 2), bools, strings
    and out-of-range values with cmbrl.Error naming the argument."""
    upper = "2**64 - 1" if high == 2**64 - 1 else ("2**31 - 1" if high == _INT_MAX else high)
    expected = f"expected an integer from {low} to {upper}"
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise Error(f"{what} is {value!r}: {expected}")
    value = int(value)
    if not low <= value <= high:
        raise Error(f"{what} is {value}: {expected}")
    return value


def _as_seed(seed, what="seed"):
    """seed as an int from 0 to 2**64 - 1; refuses floats, bools and anything else by name."""
    return _as_int(seed, what, 0, 2**64 - 1)


class Env(_Closable, _EnvBase):
    """One Goal environment with Safety-Gymnasium's API (reset, step with a separate cost,
    observation_space, action_space, render to an RGB array, close). Where gymnasium is
    importable it is a gymnasium.Env (and its spaces gymnasium's Boxes), as Safety-Gymnasium's
    environments are; step() returns the cost as Safety-Gymnasium's do.

    ground_truth() gives what the agent does not observe: the robot's pose, the goal, hazards
    and vases in world coordinates. render() draws the arena from above with the episode's path.

    pickle, copy.copy and copy.deepcopy give an independent environment in the same state: the
    task, variant and spawn, MuJoCo's whole state, the layout, the episode so far and the
    generators, so that its next step (and reset) equals the original's.

    Threads: calls on one object from several threads take turns (one lock per object, taken
    with the GIL released); distinct objects run in parallel.
    """

    reward_range = (-math.inf, math.inf)

    def __init__(self, task, variant=None, spawn="standing", render_mode=None, render_size=400):
        if render_mode not in (None, "rgb_array"):
            raise Error(f"render_mode '{render_mode}': expected None or 'rgb_array'")
        env_id = task
        task, variant = _task_and_variant(task, variant)
        self._env = _cmbrl.Env(task, variant, spawn)
        self.task, self.variant, self.spawn = task, variant, spawn
        self.render_mode = render_mode
        self.render_size = _as_int(render_size, "render_size", 1, 16384)
        obs_spec, act_spec = self._env.observation_spec(), self._env.action_spec()
        self.observation_names = list(obs_spec["names"])
        self.action_names = list(act_spec["names"])
        self.observation_space = _box(obs_spec)
        self.action_space = _box(act_spec)
        self.max_episode_steps = self._env.max_episode_steps
        self.agent_step_seconds = self._env.agent_step_seconds
        # Per instance: Gymnasium's wrappers read render_fps, and it follows the agent's step.
        self.metadata = {"render_modes": ["rgb_array"],
                         "render_fps": round(1.0 / self.agent_step_seconds)}
        self.spec = EnvSpec(env_id, self.max_episode_steps,
                            {"variant": variant, "spawn": spawn})
        self._np_random = None

    def reset(self, seed=None, options=None):
        """Starts an episode: (observation, info). A seed re-seeds the layouts' generator;
        without one the generator continues, and a first reset without one draws its seed from
        the operating system's entropy (Gymnasium's convention)."""
        if seed is None and not getattr(self, "_seeded", False):
            seed = _entropy_seed()
        if seed is not None:
            seed = _as_seed(seed)
            self.action_space.seed(seed)
            self._np_random = np.random.default_rng(seed)
        self._seeded = True
        return self._env.reset(seed)

    @property
    def np_random(self):
        """A numpy Generator seeded with the last reset's seed (Gymnasium's env.np_random, for
        wrappers' own draws). The environment's layouts draw from its C++ generator, seeded with
        the same seed, not from this one."""
        if self._np_random is None:
            self._np_random = np.random.default_rng(_entropy_seed())
        return self._np_random

    @np_random.setter
    def np_random(self, generator):
        self._np_random = generator

    def step(self, action):
        """(observation, reward, cost, terminated, truncated, info) for one agent step."""
        return self._env.step(action)

    def ground_truth(self):
        """What the agent does not observe, in world coordinates: a dict of the robot's position
        and heading, the goal and its radius, and the hazards' and vases' positions."""
        return self._env.ground_truth()

    def render(self):
        """The arena from above as an (H, W, 3) uint8 array."""
        return self._env.render(self.render_size)

    def save_picture(self, path, caption="", predictions=None):
        """Writes render()'s picture as PNG, with a caption and, optionally, the planner's
        predicted paths (Agent.predictions)."""
        self._env.save_picture(os.fspath(path), self.render_size, caption, list(predictions or []))

    @property
    def unwrapped(self):
        """The environment itself (no wrappers inside): Gymnasium's convention."""
        return self

    def __getstate__(self):
        if self.closed:
            raise Error(f"a closed cmbrl.Env ({self.task}) cannot be pickled or copied: "
                        "it has no state left")
        return {"id": self.spec.id, "variant": self.variant, "spawn": self.spawn,
                "render_mode": self.render_mode, "render_size": self.render_size,
                "observation_space": self.observation_space, "action_space": self.action_space,
                "np_random": self._np_random, "seeded": getattr(self, "_seeded", False),
                "state": self._env.state()}

    def __setstate__(self, state):
        self.__init__(state["id"], state["variant"], state["spawn"], state["render_mode"],
                      state["render_size"])
        self._env.set_state(state["state"])
        self.observation_space = state["observation_space"]
        self.action_space = state["action_space"]
        self._np_random = state["np_random"]
        self._seeded = state["seeded"]

    __copy__ = __deepcopy__ = _copy_through_state

    def __repr__(self):
        return f"cmbrl.Env({self.task!r}, variant={self.variant!r})"


class VectorEnv(_Closable, _NotCopyable, _VectorEnvBase):
    """num_envs environments stepped together in C++ threads, in Gymnasium's vector API:
    batched (num_envs, ...) arrays in and out. Resets follow Gymnasium 1.x's autoreset modes:
    "same-step" (the default: an environment whose episode ended returns its next episode's first
    observation; the last one is info["final_obs"][k] and its step's info info["final_info"],
    with info["_final_obs"][k] and info["_final_info"][k] True, Gymnasium 1.x's names) or "disabled" (an ended environment returns its last observation and must be reset with
    reset(options={"reset_mask": mask}) before it steps again).

    Threads: calls on one object from several threads take turns (one lock per object, taken
    with the GIL released); distinct objects run in parallel.
    """

    _instead = "make another with cmbrl.make_vec(...)"

    def __init__(self, task, num_envs, variant=None, spawn="standing", threads=None,
                 spin_us=2000, autoreset_mode="same-step"):
        mode = _autoreset_mode(autoreset_mode)
        task, variant = _task_and_variant(task, variant)
        # 0: one thread per core this process may use (its affinity mask), at most one per env.
        num_envs = _as_int(num_envs, "num_envs")
        threads = 0 if threads is None else _as_int(threads, "threads", 1, 4096)
        self._env = _cmbrl.VectorEnv(task, num_envs, variant, spawn, threads,
                                     _as_int(spin_us, "spin_us", 0, 10**9), mode)
        self.metadata = {"autoreset_mode": mode}
        self._observations = None
        self.task, self.variant, self.num_envs = task, variant, num_envs
        obs_spec, act_spec = self._env.observation_spec(), self._env.action_spec()
        self.single_observation_space = _box(obs_spec)
        self.single_action_space = _box(act_spec)
        self.observation_space = Box(
            low=np.tile(obs_spec["low"], (self.num_envs, 1)),
            high=np.tile(obs_spec["high"], (self.num_envs, 1)), dtype=np.float64)
        self.action_space = Box(
            low=np.tile(act_spec["low"], (self.num_envs, 1)),
            high=np.tile(act_spec["high"], (self.num_envs, 1)), dtype=np.float64)

    def reset(self, seed=None, options=None):
        """Resets all; with a seed, environment k gets seed + k, and a list of seeds may give
        them as [s, s + 1, ...]. A first reset without a seed draws one from the operating
        system's entropy, so unseeded environments differ from each other and from run to run.
        With autoreset "disabled", options={"reset_mask": mask} (num_envs booleans) resets only
        the environments marked True (with seed + k, or seeds[k], when a seed is given); the
        others keep their current observation."""
        options = {} if options is None else options
        if not isinstance(options, dict) or set(options) - {"reset_mask"}:
            raise Error(f"options {options!r}: expected None or a dict with only 'reset_mask'")
        if "reset_mask" in options:
            return self._reset_where(options["reset_mask"], seed)
        if isinstance(seed, (list, tuple, np.ndarray)):
            seeds = [_as_seed(item, "a seed of the list") for item in seed]
            if len(seeds) != self.num_envs:
                raise Error(f"{len(seeds)} seeds for {self.num_envs} environments: expected one "
                            "each")
            if any(later != seeds[0] + k for k, later in enumerate(seeds)):
                raise Error(f"seeds {seeds}: this vector seeds environment k with seed + k, so "
                            "a list must be consecutive; give one seed for other layouts")
            seed = seeds[0]
        if seed is None and not getattr(self, "_seeded", False):
            seed = max(0, _entropy_seed() - self.num_envs)  # room for seed + k
        if seed is not None:
            seed = _as_seed(seed)
            self.action_space.seed(seed)
        self._seeded = True
        observations, info = self._env.reset(seed)
        self._observations = observations.copy()
        return observations, info

    def _reset_where(self, mask, seed):
        if self.metadata["autoreset_mode"] != "disabled":
            raise Error("options['reset_mask'] needs autoreset_mode 'disabled': with 'same-step' "
                        "the environments reset themselves")
        mask = np.asarray(mask)
        if mask.shape != (self.num_envs,) or mask.dtype != np.bool_:
            raise Error(f"reset_mask has shape {mask.shape} and dtype {mask.dtype}: expected "
                        f"({self.num_envs},) booleans")
        if self._observations is None and not mask.all():
            raise Error("the first reset must reset every environment: reset_mask has False")
        if isinstance(seed, (list, tuple, np.ndarray)):
            seeds = [_as_seed(item, "a seed of the list") for item in seed]
            if len(seeds) != self.num_envs:
                raise Error(f"{len(seeds)} seeds for {self.num_envs} environments: expected one "
                            "each")
        elif seed is not None:
            first = _as_seed(seed)
            seeds = [first + k for k in range(self.num_envs)]
        else:
            seeds = []
        first_observations = self._env.reset_where(mask.tolist(), seeds)
        if self._observations is None:
            self._observations = first_observations
        else:
            self._observations[mask] = first_observations[mask]
        self._seeded = True
        return self._observations.copy(), {}

    def step(self, actions):
        """(num_envs, A) actions -> (observations, rewards, costs, terminations, truncations,
        infos), each batched over the environments; ended ones reset as the autoreset mode says."""
        result = self._env.step(actions)
        self._observations = result[0].copy()
        return result


class EnvSpec:
    """What made an environment, as gymnasium.envs.registration.EnvSpec names it: id (the name
    given to make), max_episode_steps and kwargs (variant, spawn)."""

    def __init__(self, id, max_episode_steps, kwargs):  # noqa: A002 (Gymnasium's name)
        self.id, self.max_episode_steps, self.kwargs = id, max_episode_steps, dict(kwargs)

    def __repr__(self):
        return f"EnvSpec(id={self.id!r}, max_episode_steps={self.max_episode_steps})"


_SAFETY_GYMNASIUM_ID = re.compile(r"Safety((?:Point|Car)Goal[12])-v0")


def _task_and_variant(task, variant):
    """A task name or a Safety-Gymnasium id ("SafetyPointGoal1-v0": that task's stock variant,
    'standard'), and the variant: the one given, else 'standard' for such an id and 'paper'."""
    if not isinstance(task, str):
        raise Error(f"task is {task!r}: expected a task name ({', '.join(tasks())}) or a "
                    "Safety-Gymnasium id such as 'SafetyPointGoal1-v0'")
    match = _SAFETY_GYMNASIUM_ID.fullmatch(task)
    if match:
        return match.group(1), "standard" if variant is None else variant
    return task, "paper" if variant is None else variant


def make(task, variant=None, spawn="standing", render_mode=None, render_size=400):
    """An environment: task is one of tasks() or a Safety-Gymnasium id ('SafetyPointGoal1-v0',
    which gives that task's stock variant); variant 'paper' (the default for a task name: the
    paper's modified suite), 'standard' (Safety-Gymnasium's stock tasks) or 'paper-lidar' (the
    paper's world as its model-free baselines observed it); spawn 'standing' or
    'model-origin'."""
    return Env(task, variant=variant, spawn=spawn, render_mode=render_mode,
               render_size=render_size)


def _autoreset_mode(mode):
    """'same-step' or 'disabled', also from Gymnasium's AutoresetMode (SAME_STEP, DISABLED)."""
    value = getattr(mode, "value", mode)
    names = {"same-step": "same-step", "SameStep": "same-step", "disabled": "disabled",
             "Disabled": "disabled"}
    if not isinstance(value, str) or value not in names:
        raise Error(f"autoreset_mode is {mode!r}: expected 'same-step' or 'disabled' "
                    "(NEXT_STEP is not offered)")
    return names[value]


def make_vec(task, num_envs, variant=None, spawn="standing", threads=None, spin_us=2000,
             autoreset_mode="same-step"):
    """A VectorEnv of num_envs environments on `threads` threads (default: one per core this
    process may use, at most one per environment). Between steps the threads spin for up to
    spin_us microseconds before they sleep: the default suits a loop that steps at once again;
    0 spares the cores of a loop that does much else between steps."""
    return VectorEnv(task, num_envs, variant=variant, spawn=spawn, threads=threads,
                     spin_us=spin_us, autoreset_mode=autoreset_mode)


class _Forwarding:
    """Without gymnasium, what its wrappers give: the wrapped environment as .env, and every
    attribute and method this wrapper does not define taken from it."""

    def __init__(self, env):
        self.env = env

    def __getattr__(self, name):
        if name == "env":  # not set yet (unpickling, say): do not recurse
            raise AttributeError(name)
        return getattr(self.env, name)

    @property
    def unwrapped(self):
        return self.env.unwrapped

    def reset(self, *, seed=None, options=None):
        return self.env.reset(seed=seed, options=options)

    def close(self):
        self.env.close()


def _with_cost(info, cost):
    info = dict(info)
    info["cost"] = cost
    return info


class CostInInfo(_WrapperBase or _Forwarding):
    """An Env with Gymnasium's five-value step: (observation, reward, terminated, truncated, info),
    the cost moved into info["cost"], for Gymnasium's own wrappers and the libraries built on
    them (Safety-Gymnasium's SafetyGymnasium2Gymnasium does the same). Where gymnasium is
    importable it is a gymnasium.Wrapper. Threads: as the Env it wraps."""

    def step(self, action):
        """(observation, reward, terminated, truncated, info), the cost in info["cost"]."""
        observation, reward, cost, terminated, truncated, info = self.env.step(action)
        return observation, reward, terminated, truncated, _with_cost(info, cost)


class VectorCostInInfo(_VectorWrapperBase or _Forwarding):
    """A VectorEnv with Gymnasium's five-value step, the (num_envs) costs in info["cost"]. Where
    gymnasium is importable it is a gymnasium.vector.VectorWrapper. Threads: as the VectorEnv it
    wraps."""

    def step(self, actions):
        """(observations, rewards, terminations, truncations, infos), the costs in
        infos["cost"]."""
        observations, rewards, costs, terminations, truncations, infos = self.env.step(actions)
        return observations, rewards, terminations, truncations, _with_cost(infos, costs)


def train(config=None, out=None, steps=None, seed=None, device=None, resume=None, progress=None,
          checkpoint_seconds=300.0):
    """Trains a run as `cmbrl train` does, into the run directory `out`.

    config: a YAML file (path), a list of them composed in order (a task's paper preset, then a
    preset family: ["configs/pointgoal1-rce.yaml", "configs/quickstart.yaml"]), or a dict of
    the same keys. steps, seed and device override the config's. resume=RUN_DIR continues a stopped run instead (steps then gives a new budget).
    progress(summary) is called after each unit of work (an MPC episode or a model-free epoch)
    with a dict of epoch, steps, budget, episode_return, episode_cost and seconds. An exception
    it raises, or Ctrl-C (seen after the agent step or fit epoch under way in an MPC run, the
    rollout round or value-fit iteration in a model-free one), stops training at a checkpoint;
    the run resumes later from there.
    checkpoint_seconds: an MPC episode, model fit or model-free epoch still going this long
    after the last checkpoint is checkpointed after its agent step, fit epoch, rollout round or
    value-fit iteration under way (0: after every one); it changes no result.
    Returns {"run", "steps", "budget"}.
    """
    if (isinstance(checkpoint_seconds, (bool, np.bool_))
            or not isinstance(checkpoint_seconds, (int, float, np.integer, np.floating))
            or not math.isfinite(checkpoint_seconds) or checkpoint_seconds < 0):
        raise Error(f"checkpoint_seconds is {checkpoint_seconds!r}: expected a finite number of "
                    "seconds >= 0")
    config_path = config_text = None
    if isinstance(config, dict):
        if "task" not in config:
            raise Error("the config dict names no task, so the run would be the defaults' full "
                        "paper-size PointGoal1 run: name one ({'task': 'PointGoal1', ...})")
        config_text = json.dumps(config, default=_json_number)  # JSON is YAML
    elif isinstance(config, (list, tuple)):
        config_path = [os.fspath(path) for path in config]
    elif config is not None:
        config_path = [os.fspath(config)]
    out = os.fspath(out) if out is not None else None
    resume = os.fspath(resume) if resume is not None else None
    return _cmbrl.train(config_path, config_text, out, resume,
                        None if steps is None else _as_int(steps, "steps", 1, 10**10),
                        None if seed is None else _as_seed(seed), device, progress,
                        float(checkpoint_seconds))


def _paths(dirs, what):
    if isinstance(dirs, (str, bytes, os.PathLike)):
        dirs = [dirs]
    paths = [os.fspath(d) for d in dirs]
    if not paths:
        raise Error(f"{what} is empty: expected at least one sweep or report folder")
    return paths


def read_runs(dirs):
    """The runs of sweep folders (their runs/) and report folders (their run-logs/), as `cmbrl
    report` reads them: only what each run's last checkpoint covers, each run once.

    dirs: one folder or several. Returns a list of dicts, in name order: name, task, method,
    seed, setting (an experiment's axis values, "" for none), epoch_log (True for a model-free
    run, whose points are epochs), source, and numpy arrays with one entry per episode (or
    epoch): end_step, steps, episode_return, episode_cost, cumulative_violations,
    feasible_fraction and elapsed_seconds (the run's wall seconds over all its sessions), each
    NaN where not logged.
    """
    return _cmbrl.read_runs(_paths(dirs, "dirs"))


def report(dirs, out, window=None, reference=None, complete=False):
    """Writes the report of sweep or report folders into `out`, as `cmbrl report --out` does:
    report.md, Table I as Markdown and CSV, the curves as PNG and SVG, and run-logs/.

    window: agent steps counted (default: the smallest run budget, at most 10,000);
    reference: the original's logs (default: the source tree's data/reference); complete: leave
    out runs that have not reached the window. Returns {"report", "runs", "window", "cells",
    "left_out"}.
    """
    return _cmbrl.report(_paths(dirs, "dirs"), os.fspath(out),
                         None if window is None else _as_int(window, "window", 1, 10**10),
                         None if reference is None else os.fspath(reference), bool(complete))


class Agent(_NotCopyable):
    """A trained run's agent (load_run): act(observation) gives its action. An MPC run also
    offers its planner's last plan and predictions and its learned models on numpy arrays.
    Not copyable or picklable: load the run again (cmbrl.load_run) where another is needed.

    Threads: calls on one object from several threads take turns (one lock per object, taken
    with the GIL released); distinct objects run in parallel.
    """

    _instead = "load the run again with cmbrl.load_run(run_dir)"

    def __init__(self, run_dir, seed=0, overrides=()):
        self._agent = _cmbrl.Agent(os.fspath(run_dir), _as_seed(seed), list(overrides))
        self.run_dir = os.fspath(run_dir)
        self.observation_space = _box(self._agent.observation_spec())
        self.action_space = _box(self._agent.action_spec())
        self.is_mpc = self._agent.is_mpc
        environment = self._agent.environment()
        self.task = environment["task"]
        self.variant = environment["variant"]
        self.spawn = environment["spawn"]

    def make_env(self, render_mode=None, render_size=400):
        """A new environment of the run's task, variant and spawn (what it was trained in)."""
        return Env(self.task, self.variant, self.spawn, render_mode=render_mode,
                   render_size=render_size)

    def config(self):
        """The run's resolved config, as YAML text."""
        return self._agent.config_yaml()

    def begin_episode(self):
        """Call at each episode's start (the MPC planner forgets its warm start)."""
        self._agent.begin_episode()

    def act(self, observation):
        """The trained agent's action for one observation: the MPC plan's first action, or the
        model-free policy's mean action."""
        return self._agent.act(observation)

    def last_plan(self):
        """MPC only: the executed plan's action sequence (H, A), its planning time, iterations,
        the feasible fraction of the last population and the share of infeasible elites (RCE's
        fallback when fewer than its minimum of elites are feasible)."""
        return self._agent.last_plan()

    def predictions(self, env, samples=8):
        """MPC only: the last plan's predicted robot paths in world coordinates, for plotting:
        dicts of points (H + 1, 2), feasible, chosen (the executed plan) and member (the
        ensemble member that predicted it). `samples` sampled sequences spread over the plan's
        last population, each as every member predicted it, then the executed plan's: (samples
        + 1) x members paths (fewer samples when the population is smaller). `env` is the
        environment the plan was made in (its ground truth places the paths); calls between two
        act()s give the same plan."""
        return self._agent.predictions(env.ground_truth(), _as_int(samples, "samples"))

    def predict_next(self, states, actions):
        """MPC only: every ensemble member's next state, (E, N, S) for (N, S) and (N, A)."""
        return self._agent.predict_next(states, actions)

    def predict_violation(self, states):
        """MPC only: the constraint classifier's verdict per state, (N) bool."""
        return self._agent.predict_violation(states)


def load_run(run_dir, seed=0, overrides=None):
    """The agent of a trained run directory (its last checkpoint); seed seeds the planner.

    overrides: a dict {"section.key": value} or a list of "section.key=value" that changes how
    the trained models are used, as `cmbrl eval --set` does: planning.*, objective.* and
    classifier.threshold, e.g. {"classifier.threshold": 0.3}."""
    if overrides is None:
        overrides = []
    elif isinstance(overrides, dict):
        overrides = [f"{key}={_yaml_value(value)}" for key, value in overrides.items()]
    return Agent(run_dir, seed=seed, overrides=[str(item) for item in overrides])


def _yaml_value(value):
    """A Python value as YAML flow text (bools lower-case, lists in brackets)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_yaml_value(v) for v in value) + "]"
    return repr(value) if isinstance(value, float) else str(value)


class _StandaloneModel:
    """Saving, loading, pickling and copying the standalone models (Ensemble, CostClassifier):
    a folder of the constructor's arguments (settings.json) and the C++ model's own files.
    Pickles carry that folder's files as bytes; copy.copy and copy.deepcopy give an independent
    model (a shallow copy would share the C++ one)."""

    _kind = ""  # "ensemble" or "classifier"
    _SETTINGS = "settings.json"

    def _write_files(self, folder):
        with open(os.path.join(folder, self._SETTINGS), "w") as out:
            json.dump({"kind": self._kind, "args": self._args}, out, default=_json_number)
        if self._kind == "ensemble":
            self._model.save(folder)
        else:
            self._model.save(os.path.join(folder, "classifier.json"))

    def save(self, path):
        """Writes the model to the folder `path` (made if missing): its settings and its state
        (an Ensemble: networks, optimiser, generator and the transitions it holds, so that a
        loaded copy predicts the same and a later fit continues as this one's would; a
        CostClassifier: its trees)."""
        folder = os.fspath(path)
        os.makedirs(folder, exist_ok=True)
        self._write_files(folder)

    @classmethod
    def load(cls, path):
        """The model as save() wrote it to the folder `path`."""
        settings_path = os.path.join(os.fspath(path), cls._SETTINGS)
        try:
            with open(settings_path) as inp:
                settings = json.load(inp)
        except (OSError, ValueError) as error:
            raise Error(f"'{settings_path}': cannot read it ({error}): expected a folder "
                        f"written by {cls.__name__}.save") from None
        kind = settings.get("kind") if isinstance(settings, dict) else None
        if kind != cls._kind:
            raise Error(f"'{settings_path}' is not a saved {cls.__name__}: its kind is {kind!r}")
        model = cls(**settings["args"])
        if cls._kind == "ensemble":
            model._model.load(os.fspath(path))
        else:
            model._model.load(os.path.join(os.fspath(path), "classifier.json"))
        return model

    def __getstate__(self):
        with tempfile.TemporaryDirectory() as folder:
            self._write_files(folder)
            files = {}
            for name in sorted(os.listdir(folder)):
                with open(os.path.join(folder, name), "rb") as inp:
                    files[name] = inp.read()
        return {"files": files}

    def __setstate__(self, state):
        with tempfile.TemporaryDirectory() as folder:
            for name, data in state["files"].items():
                with open(os.path.join(folder, name), "wb") as out:
                    out.write(data)
            self.__dict__.update(type(self).load(folder).__dict__)

    __copy__ = __deepcopy__ = _copy_through_state


class Ensemble(_StandaloneModel):
    """The paper's dynamics model on numpy arrays: ensemble_size MLPs (ReLU, hidden_sizes) that
    each predict the absolute next state (or, with predict_delta, the change of state: not the
    paper's way), trained by MSE with the paper's settings (facts B3). fit() adds the
    transitions to a ring of 500,000 and trains on all of it, warm-started after the first fit,
    as training does; predict() gives every member's next state.

    Threads: calls on one object from several threads take turns (one lock per object, taken
    with the GIL released); distinct objects run in parallel.
    """

    _kind = "ensemble"

    def __init__(self, state_dim, action_dim, ensemble_size=4, hidden_sizes=(1024, 1024, 1024),
                 max_epochs=70, seed=0, predict_delta=False):
        self._args = {"state_dim": state_dim, "action_dim": action_dim,
                      "ensemble_size": ensemble_size, "hidden_sizes": list(hidden_sizes),
                      "max_epochs": max_epochs, "seed": seed, "predict_delta": predict_delta}
        self._model = _cmbrl.Ensemble(
            _as_int(state_dim, "state_dim"), _as_int(action_dim, "action_dim"),
            _as_int(ensemble_size, "ensemble_size"),
            [_as_int(h, f"hidden_sizes[{i}]") for i, h in enumerate(hidden_sizes)],
            _as_int(max_epochs, "max_epochs"), bool(predict_delta), _as_seed(seed))

    def fit(self, states, actions, next_states):
        """(N, S), (N, A), (N, S) -> a dict: epochs, train and validation MSE, seconds, and
        whose products ran: backend (the predictions') and training_backend, each "onednn" or
        "libtorch" (with backend "auto", oneDNN trains at any width on a CPU with AVX-512, and
        elsewhere only where every hidden layer is at most 256 wide).
        Ctrl-C (or another signal handler's exception) stops the fit after the epoch in
        progress: the epochs done are kept, and the exception is raised."""
        return self._model.fit(states, actions, next_states)

    def predict(self, states, actions):
        """(N, S), (N, A) -> (E, N, S)."""
        return self._model.predict(states, actions)

    @property
    def transitions(self):
        """How many transitions the ensemble holds (at most 500,000; the oldest go first)."""
        return self._model.transitions


class CostClassifier(_StandaloneModel):
    """The paper's constraint classifier on numpy arrays: gradient-boosted trees (XGBoost, set
    up as the original's LightGBM) that learn from 0/1 labels where states violate a
    constraint. fit() trains from scratch on every given state; predict() gives (N) bool.

    Threads: calls on one object from several threads take turns (one lock per object, taken
    with the GIL released); distinct objects run in parallel.
    """

    _kind = "classifier"

    def __init__(self, state_dim, rounds=400, threshold=0.5, seed=0):
        self._args = {"state_dim": state_dim, "rounds": rounds, "threshold": threshold,
                      "seed": seed}
        self._model = _cmbrl.CostClassifier(_as_int(state_dim, "state_dim"),
                                            _as_int(rounds, "rounds"), float(threshold),
                                            _as_seed(seed))

    def fit(self, states, unsafe):
        """states (N, S), unsafe (N) of 0/1 or bool -> a dict: trees, accuracies, seconds.
        Ctrl-C (or another signal handler's exception) abandons the fit after the boosting round
        in progress, leaving the classifier as it was before (each fit starts from scratch), and
        the exception is raised."""
        unsafe = np.asarray(unsafe)
        if unsafe.dtype == bool:
            unsafe = unsafe.astype(np.float64)
        return self._model.fit(states, unsafe)

    def predict(self, states):
        """states (N, S) -> (N) bool: True where the classifier says a constraint is violated."""
        return self._model.predict(states)
