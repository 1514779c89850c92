"""The Safety Gym Goal environments: one (Env, make), vectors of them stepped in C++ threads
(VectorEnv, make_vec), and Gymnasium's five-value step (CostInInfo, VectorCostInInfo)."""
import json
import math
import os
import re

import numpy as np

from . import _cmbrl, _gymnasium
from ._common import (Error, _as_flag, _as_int, _as_seed, _as_str, _box, _Closable,
                      _copy_through_state, _entropy_seed, _NotCopyable)
from .spaces import Box

def tasks():
    """The registered task names."""
    return list(_cmbrl.env_names())


def variants(task):
    """The variants a task exists in, its default first: the paper's Goal tasks 'paper',
    'standard' and 'paper-lidar'; Button, Push and Circle 'standard' only."""
    if _cmbrl.default_variant(task) == "paper":
        return ["paper", "standard", "paper-lidar"]
    return ["standard"]


class Env(_Closable, _gymnasium.Env):
    """One navigation environment with Safety-Gymnasium's API (reset, step with a separate cost,
    observation_space, action_space, render to an RGB array, close). Where gymnasium is
    importable it is a gymnasium.Env (and its spaces gymnasium's Boxes), as Safety-Gymnasium's
    environments are; step() returns the cost as Safety-Gymnasium's do.

    ground_truth() gives what the agent does not observe: the robot's pose, the goal, hazards
    and vases in world coordinates. render() draws the arena from above with the episode's path.

    pickle, copy.copy and copy.deepcopy give an independent environment in the same state: the
    task, variant and spawn, MuJoCo's whole state, the layout, the episode so far and the
    generators, so that its next step (and reset) equals the original's.

    previous_action=True appends the action the environment last ran (clipped to the action box;
    zeros after a reset) to every observation, as previous_action_0, ...: what a run trained
    with the config key environment.previous_action observes.

    Threads: calls on one object from several threads take turns (one lock per object, taken
    with the GIL released); distinct objects run in parallel.
    """

    reward_range = (-math.inf, math.inf)

    def __init__(self, task, variant=None, spawn="standing", render_mode=None, render_size=400,
                 previous_action=False):
        if render_mode not in (None, "rgb_array", "human"):
            raise Error(f"render_mode '{render_mode}': expected None, 'rgb_array' or 'human'")
        self._window = _HumanWindow.check() if render_mode == "human" else None
        env_id = task
        task, variant = _task_and_variant(task, variant)
        previous_action = _as_flag(previous_action, "previous_action")
        self._env = _cmbrl.Env(task, variant, _as_str(spawn, "spawn", _SPAWNS), previous_action)
        self.task, self.variant, self.spawn = task, variant, spawn
        self.previous_action = previous_action
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
        # "human" where it can open a window (Gymnasium's check_env makes every mode listed).
        self.metadata = {"render_modes": ["rgb_array"] + (["human"] if _HumanWindow.available()
                                                           else []),
                         "render_fps": round(1.0 / self.agent_step_seconds)}
        self.spec = _env_spec(env_id, task, variant, spawn, render_mode, render_size,
                              previous_action)
        self._np_random = None
        self._np_random_seed = None

    def reset(self, seed=None, options=None):
        """Starts an episode: (observation, info). A seed re-seeds the layouts' generator;
        without one the generator continues, and a first reset without one draws its seed from
        the operating system's entropy (Gymnasium's convention). options: None or {} (this
        environment takes none)."""
        if options is not None and options != {}:
            raise Error(f"options {options!r}: a cmbrl.Env takes no reset options (None or {{}})")
        if seed is None and not getattr(self, "_seeded", False):
            seed = _entropy_seed()
        if seed is not None:
            seed = _as_seed(seed)
            self.action_space.seed(seed)
            self._np_random = np.random.default_rng(seed)
            self._np_random_seed = seed
        self._seeded = True
        result = self._env.reset(seed)
        self._show()
        return result

    @property
    def np_random(self):
        """A numpy Generator seeded with the last reset's seed (Gymnasium's env.np_random, for
        wrappers' own draws). The environment's layouts draw from its C++ generator, seeded with
        the same seed, not from this one."""
        if self._np_random is None:
            self._np_random_seed = _entropy_seed()
            self._np_random = np.random.default_rng(self._np_random_seed)
        return self._np_random

    @np_random.setter
    def np_random(self, generator):
        self._np_random = generator
        self._np_random_seed = -1  # Gymnasium's value for a generator set from outside

    @property
    def np_random_seed(self):
        """The seed np_random was seeded with: the last seeded reset's (Gymnasium's
        env.np_random_seed); -1 after np_random was set from outside. Reading it changes
        nothing."""
        if self._np_random is None:
            self.np_random  # noqa: B018 (draws np_random's seed, as Gymnasium does)
        return self._np_random_seed

    def step(self, action):
        """(observation, reward, cost, terminated, truncated, info) for one agent step."""
        result = self._env.step(action)
        self._show()
        return result

    def _show(self):
        """render_mode "human": the arena in a window after every reset and step (Gymnasium's
        convention; render() then returns None)."""
        if self._window is not None:
            self._window.show(self._env.render(self.render_size),
                              f"cmbrl {self.task} ({self.variant})")

    @property
    def spec(self):
        """What made this environment: its id, entry point and kwargs (gymnasium.make sets the
        registered id's spec here, as it does on every gymnasium.Env)."""
        return self._spec

    @spec.setter
    def spec(self, spec):
        self._spec = spec

    def close(self):
        """Frees the environment (and closes its window); later calls raise cmbrl.Error."""
        if getattr(self, "_window", None) is not None:
            self._window.close()
            self._window = None
        super().close()

    def ground_truth(self):
        """What the agent does not observe, in world coordinates: a dict of the robot's position
        and heading, the goal and its radius, and the hazards' and vases' positions."""
        return self._env.ground_truth()

    def render(self):
        """The arena from above as an (H, W, 3) uint8 array; with render_mode "human" it is
        shown in the window instead (after every step already) and None is returned."""
        if not getattr(self, "_seeded", False):
            raise Error("render() before reset(): there is no arena yet; reset the environment "
                        "first")
        if self._window is not None:
            self._show()
            return None
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
        return {"task": self.task, "spec": self.spec, "variant": self.variant,
                "spawn": self.spawn, "previous_action": self.previous_action,
                "render_mode": self.render_mode,
                "render_size": self.render_size, "observation_space": self.observation_space,
                "action_space": self.action_space, "np_random": self._np_random,
                "np_random_seed": self._np_random_seed,
                "seeded": getattr(self, "_seeded", False), "state": self._env.state()}

    def __setstate__(self, state):
        self.__init__(state["task"], state["variant"], state["spawn"], state["render_mode"],
                      state["render_size"], state.get("previous_action", False))
        self._env.set_state(state["state"])
        self.spec = state["spec"]  # the id it was made under (a registered one, say)
        self.observation_space = state["observation_space"]
        self.action_space = state["action_space"]
        self._np_random = state["np_random"]
        self._np_random_seed = state["np_random_seed"]
        self._seeded = state["seeded"]

    __copy__ = __deepcopy__ = _copy_through_state

    def __repr__(self):
        # (also for an Env whose construction failed, which has neither yet)
        return (f"cmbrl.Env({getattr(self, 'task', None)!r}, "
                f"variant={getattr(self, 'variant', None)!r})")


class VectorEnv(_Closable, _NotCopyable, _gymnasium.VectorEnv):
    """num_envs environments stepped together in C++ threads, in Gymnasium's vector API:
    batched (num_envs, ...) arrays in and out, each info key with its mask info["_key"].
    Resets follow Gymnasium 1.x's autoreset modes (metadata["autoreset_mode"], Gymnasium's
    AutoresetMode where importable): "next-step" (the default, as Gymnasium's: the step after an
    episode ended resets that environment instead, its action unread, returning the next
    episode's first observation with reward and cost 0; its info keys' masks are False),
    "same-step" (an environment whose episode ended returns its next episode's first
    observation; the last one is info["final_obs"][k] and its step's info info["final_info"],
    with info["_final_obs"][k] and info["_final_info"][k] True) or "disabled" (an ended
    environment returns its last observation and must be reset with
    reset(options={"reset_mask": mask}) before it steps again).

    Threads: calls on one object from several threads take turns (one lock per object, taken
    with the GIL released); distinct objects run in parallel.
    """

    _instead = "make another with cmbrl.make_vec(...)"

    def __init__(self, task, num_envs, variant=None, spawn="standing", threads=None,
                 spin_us=0, autoreset_mode="next-step", previous_action=False):
        mode = _autoreset_mode(autoreset_mode)
        task, variant = _task_and_variant(task, variant)
        # 0: one thread per core this process may use (its affinity mask), at most one per env.
        num_envs = _as_int(num_envs, "num_envs")
        threads = 0 if threads is None else _as_int(threads, "threads", 1, 4096)
        self._env = _cmbrl.VectorEnv(task, num_envs, variant, _as_str(spawn, "spawn", _SPAWNS),
                                     threads, _as_int(spin_us, "spin_us", 0, 10**9), mode,
                                     _as_flag(previous_action, "previous_action"))
        self._mode = mode
        self.metadata = {"autoreset_mode": _gymnasium_autoreset_mode(mode)}
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

    def close(self, **kwargs):
        """Frees the environments and stops their threads. kwargs: what Gymnasium's vector
        close passes on (an async vector's timeout, say), which, as its sync vector does, this
        one has no use for."""
        self._env.close()

    def reset(self, seed=None, options=None):
        """Resets all; with a seed, environment k gets seed + k; a list gives each its own seed
        (None: its generator continues, or, at a first reset, a seed from the operating system's
        entropy). A first reset without a seed draws one from the entropy, so unseeded
        environments differ from each other and from run to run. options={"reset_mask": mask}
        (num_envs booleans) resets only the environments marked True (with seed + k, or
        seeds[k], when a seed is given); the others keep their current observation."""
        options = {} if options is None else options
        if not isinstance(options, dict) or set(options) - {"reset_mask"}:
            raise Error(f"options {options!r}: expected None or a dict with only 'reset_mask'")
        if "reset_mask" in options:
            return self._reset_where(options["reset_mask"], seed)
        if isinstance(seed, (list, tuple, np.ndarray)):
            return self._reset_where(np.ones(self.num_envs, dtype=bool), seed)
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
        mask = np.asarray(mask)
        if mask.shape != (self.num_envs,) or mask.dtype != np.bool_:
            raise Error(f"reset_mask has shape {mask.shape} and dtype {mask.dtype}: expected "
                        f"({self.num_envs},) booleans")
        if self._observations is None and not mask.all():
            raise Error("the first reset must reset every environment: reset_mask has False")
        if isinstance(seed, (list, tuple, np.ndarray)):
            if len(seed) != self.num_envs:
                raise Error(f"{len(seed)} seeds for {self.num_envs} environments: expected one "
                            "each")
            # None: the environment's generator continues (a first reset draws from entropy).
            first_time = not getattr(self, "_seeded", False)
            seeds = [None if item is None else _as_seed(item, "a seed of the list")
                     for item in seed]
            seeds = [_entropy_seed() if item is None and first_time else item for item in seeds]
            if seeds and seeds[0] is not None:
                self.action_space.seed(seeds[0])
        elif seed is not None:
            first = _as_seed(seed)
            seeds = [first + k for k in range(self.num_envs)]
            self.action_space.seed(first)
        else:
            seeds = [None] * self.num_envs
        seeded = [item is not None for item in seeds]
        first_observations = np.zeros((self.num_envs, self.single_observation_space.shape[0]))
        for with_seed in (True, False):  # the seeded ones, then those whose generator continues
            part = mask & (np.asarray(seeded) == with_seed)
            if part.any():
                rows = self._env.reset_where(
                    part.tolist(), [item or 0 for item in seeds] if with_seed else [])
                first_observations[part] = rows[part]
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


class _HumanWindow:
    """render_mode "human": a Tk window showing the latest picture. check() refuses, naming the
    cause, where there is no display or no tkinter."""

    @staticmethod
    def available():
        """Whether a window can be opened here."""
        try:
            _HumanWindow.check()
        except Error:
            return False
        return True

    @staticmethod
    def check():
        if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
            raise Error("render_mode 'human' needs a display: neither DISPLAY nor "
                        "WAYLAND_DISPLAY is set; use render_mode 'rgb_array' (render() gives "
                        "the picture) or save_picture(path)")
        try:
            import tkinter  # noqa: F401
        except ImportError as error:
            raise Error("render_mode 'human' draws with tkinter (Debian's python3-tk), which is "
                        f"not importable here ({error}); use render_mode 'rgb_array'") from None
        return _HumanWindow()

    def __init__(self):
        self._root = self._label = self._image = None

    def show(self, rgb, title):
        import tkinter
        if self._root is None:
            self._root = tkinter.Tk()
            self._label = tkinter.Label(self._root)
            self._label.pack()
        self._root.title(title)
        height, width, _ = rgb.shape
        ppm = b"P6 %d %d 255\n" % (width, height) + np.ascontiguousarray(rgb).tobytes()
        self._image = tkinter.PhotoImage(data=ppm, format="PPM")
        self._label.configure(image=self._image)
        self._root.update()

    def close(self):
        if self._root is not None:
            self._root.destroy()
            self._root = None


class _EnvSpec:
    """What made an environment, with gymnasium.envs.registration.EnvSpec's fields, where gymnasium
    is not importable (where it is, EnvSpec is Gymnasium's own): id (the name
    given to make), entry_point, kwargs (task, variant, spawn), max_episode_steps (None: the
    environment truncates its own episodes, and Gymnasium's TimeLimit expects five values),
    disable_env_checker (True: the six-value step is Safety-Gymnasium's, not Gymnasium's) and the
    rest at Gymnasium's defaults. make() makes the environment again; to_json() writes it."""

    def __init__(self, id, entry_point=None, reward_threshold=None,  # noqa: A002 (Gymnasium's)
                 nondeterministic=False, max_episode_steps=None, order_enforce=True,
                 disable_env_checker=False, kwargs=None, additional_wrappers=(),
                 vector_entry_point=None):
        self.id, self.entry_point = id, entry_point
        self.reward_threshold, self.nondeterministic = reward_threshold, nondeterministic
        self.max_episode_steps, self.order_enforce = max_episode_steps, order_enforce
        self.disable_env_checker = disable_env_checker
        self.kwargs = dict(kwargs or {})
        self.additional_wrappers, self.vector_entry_point = tuple(additional_wrappers), \
            vector_entry_point
        match = re.fullmatch(r"(?:(?P<namespace>[\w:.-]+)/)?(?P<name>[\w:.-]+?)(?:-v(?P<version>\d+))?",
                             id)
        self.namespace = match.group("namespace") if match else None
        self.name = match.group("name") if match else id
        self.version = int(match.group("version")) if match and match.group("version") else None

    def make(self, **kwargs):
        """The environment this spec describes, its kwargs updated with `kwargs`."""
        module, _, attribute = self.entry_point.partition(":")
        import importlib
        creator = getattr(importlib.import_module(module), attribute)
        return creator(**{**self.kwargs, **kwargs})

    def to_json(self):
        """The spec as a JSON string (Gymnasium's field names)."""
        return json.dumps({"id": self.id, "entry_point": self.entry_point,
                           "reward_threshold": self.reward_threshold,
                           "nondeterministic": self.nondeterministic,
                           "max_episode_steps": self.max_episode_steps,
                           "order_enforce": self.order_enforce,
                           "disable_env_checker": self.disable_env_checker,
                           "kwargs": self.kwargs, "additional_wrappers": [],
                           "vector_entry_point": self.vector_entry_point})

    def __repr__(self):
        return f"EnvSpec(id={self.id!r}, entry_point={self.entry_point!r}, kwargs={self.kwargs!r})"


# What made an environment: Gymnasium's EnvSpec where gymnasium is importable, the look-alike
# otherwise.
EnvSpec = _gymnasium.EnvSpec or _EnvSpec


def _env_spec(env_id, task, variant, spawn, render_mode=None, render_size=400,
              previous_action=False):
    """The spec of an Env made by make(): Gymnasium's EnvSpec where gymnasium is importable,
    whose make() (gymnasium.make) gives the same six-value environment again."""
    kwargs = {"task": task, "variant": variant, "spawn": spawn, "render_mode": render_mode,
              "render_size": render_size}
    if previous_action:
        kwargs["previous_action"] = True
    fields = dict(id=env_id, entry_point="cmbrl.registration:make_safety_gymnasium_env",
                  max_episode_steps=None, disable_env_checker=True, kwargs=kwargs)
    return EnvSpec(**fields)


_SPAWNS = "'standing' or 'model-origin'"

# Safety-Gymnasium's id of a task: "Safety" + its name + a version ("SafetyPointGoal1-v0").
_SAFETY_GYMNASIUM_ID = re.compile(r"Safety(\w+)-v0")


def _task_and_variant(task, variant):
    """A task name or a Safety-Gymnasium id ("SafetyPointGoal1-v0": that task's stock variant,
    'standard'), and the variant: the one given, else 'standard' for such an id and the task's
    default: 'paper' for the paper's Goal tasks, 'standard' for the others (Button, Push,
    Circle)."""
    if not isinstance(task, str):
        raise Error(f"task is {task!r}: expected a task name ({', '.join(tasks())}) or a "
                    "Safety-Gymnasium id such as 'SafetyPointGoal1-v0'")
    match = _SAFETY_GYMNASIUM_ID.fullmatch(task)
    if match and match.group(1) in tasks():  # the task list is the C++ core's, named once
        return match.group(1), "standard" if variant is None else _as_str(
            variant, "variant", "'paper', 'standard' or 'paper-lidar'")
    if task.startswith("Safety") and task not in tasks():
        ids = [f"Safety{name}-v0" for name in tasks()]
        raise Error(f"unknown task '{task}'{_cmbrl.did_you_mean(task, ids)}: expected a "
                    f"Safety-Gymnasium id of a task cmbrl has ({ids[0]}, ..., {ids[-1]}) or one "
                    f"of {', '.join(tasks())}")
    if variant is None:
        variant = _cmbrl.default_variant(task) if task in tasks() else "paper"
    return task, _as_str(variant, "variant", "'paper', 'standard' or 'paper-lidar'")


def make(task, variant=None, spawn="standing", render_mode=None, render_size=400,
         previous_action=False):
    """An environment: task is one of tasks() or a Safety-Gymnasium id ('SafetyPointGoal1-v0',
    which gives that task's stock variant); variant 'paper' (the default for the paper's Goal
    tasks: the paper's modified suite), 'standard' (Safety-Gymnasium's stock tasks; the default
    and only variant of Button, Push and Circle) or 'paper-lidar' (the
    paper's world as its model-free baselines observed it); spawn 'standing' or
    'model-origin'; previous_action True appends the last action to the observation (Env)."""
    return Env(task, variant=variant, spawn=spawn, render_mode=render_mode,
               render_size=render_size, previous_action=previous_action)


def _autoreset_mode(mode):
    """'next-step', 'same-step' or 'disabled', also from Gymnasium's AutoresetMode (NEXT_STEP,
    SAME_STEP, DISABLED)."""
    value = getattr(mode, "value", mode)
    names = {"next-step": "next-step", "NextStep": "next-step", "same-step": "same-step",
             "SameStep": "same-step", "disabled": "disabled", "Disabled": "disabled"}
    if not isinstance(value, str) or value not in names:
        raise Error(f"autoreset_mode is {mode!r}: expected 'next-step', 'same-step' or "
                    "'disabled' (or Gymnasium's AutoresetMode)")
    return names[value]


def _gymnasium_autoreset_mode(mode):
    """Gymnasium's AutoresetMode member of a mode's name, where gymnasium is importable; the
    name otherwise."""
    modes = _gymnasium.AutoresetMode
    if modes is None:
        return mode
    return {"next-step": modes.NEXT_STEP, "same-step": modes.SAME_STEP,
            "disabled": modes.DISABLED}[mode]


def make_vec(task, num_envs, variant=None, spawn="standing", threads=None, spin_us=0,
             autoreset_mode="next-step", previous_action=False):
    """A VectorEnv of num_envs environments on `threads` threads (default: one per core this
    process may use, at most one per environment). Between steps the threads spin for up to
    spin_us microseconds before they sleep: the default, 0, spares the cores for the rest of the
    program (on a busy machine spinning threads compete with it: docs/PERFORMANCE.md); a loop
    that does nothing but step may gain from a few thousand. previous_action: as make()'s."""
    return VectorEnv(task, num_envs, variant=variant, spawn=spawn, threads=threads,
                     spin_us=spin_us, autoreset_mode=autoreset_mode,
                     previous_action=previous_action)


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

    def close(self, **kwargs):
        self.env.close(**kwargs)


def _with_cost(info, cost):
    info = dict(info)
    info["cost"] = cost
    return info


class CostInInfo(_gymnasium.Wrapper or _Forwarding):
    """An Env with Gymnasium's five-value step: (observation, reward, terminated, truncated, info),
    the cost moved into info["cost"], for Gymnasium's own wrappers and the libraries built on
    them (Safety-Gymnasium's SafetyGymnasium2Gymnasium does the same). Where gymnasium is
    importable it is a gymnasium.Wrapper. Threads: as the Env it wraps."""

    def step(self, action):
        """(observation, reward, terminated, truncated, info), the cost in info["cost"]."""
        observation, reward, cost, terminated, truncated, info = self.env.step(action)
        return observation, reward, terminated, truncated, _with_cost(info, cost)


class _PlannerUnitsPreviousAction(_Forwarding):
    """An environment given from Python, as a run with environment.previous_action observed it:
    its observation followed by the action it last ran in the planner's units (its action box,
    finite, mapped onto [-1, 1]; zeros after a reset). A loaded run's make_env() gives it. Not
    a gymnasium.Wrapper, which would refuse environments that are not gymnasium.Envs."""

    def __init__(self, env, observation_space):
        super().__init__(env)
        self.observation_space = observation_space  # the run's: the env's, then [-1, 1] each
        self._low = np.asarray(env.action_space.low, dtype=np.float64).reshape(-1)
        self._high = np.asarray(env.action_space.high, dtype=np.float64).reshape(-1)
        # A box of [-1, 1] is not mapped (the adapter passes such actions on as they are).
        self._identity = bool(np.all(self._low == -1.0) and np.all(self._high == 1.0))
        self._previous = np.zeros(self._low.shape[0])

    def _observed(self, observation):
        return np.concatenate([np.asarray(observation, dtype=np.float64).reshape(-1),
                               self._previous])

    def reset(self, *, seed=None, options=None):
        observation, info = (self.env.reset(seed=seed) if options is None else
                             self.env.reset(seed=seed, options=options))
        self._previous = np.zeros(self._low.shape[0])
        return self._observed(observation), info

    def step(self, action):
        result = self.env.step(action)
        action = np.asarray(action, dtype=np.float64).reshape(-1)
        if self._identity:
            planner = action
        else:
            planner = 2.0 * (action - self._low) / (self._high - self._low) - 1.0
        self._previous = np.clip(planner, -1.0, 1.0)
        return (self._observed(result[0]),) + tuple(result[1:])


class VectorCostInInfo(_gymnasium.VectorWrapper or _Forwarding):
    """A VectorEnv with Gymnasium's five-value step, the (num_envs) costs in info["cost"]. Where
    gymnasium is importable it is a gymnasium.vector.VectorWrapper. Threads: as the VectorEnv it
    wraps."""

    def step(self, actions):
        """(observations, rewards, terminations, truncations, infos), the costs in
        infos["cost"]."""
        observations, rewards, costs, terminations, truncations, infos = self.env.step(actions)
        return observations, rewards, terminations, truncations, _with_cost(infos, costs)
