"""Training a run (train, as `cmbrl train` does) and the agent of a trained run (load_run,
Agent)."""
import copy
import functools
import json
import os

from . import _cmbrl
from ._common import (Error, _as_flag, _as_int, _as_number, _as_overrides, _as_path, _as_seed,
                      _as_str, _box, _json_number, _NotCopyable)
from .envs import Env, _PlannerUnitsPreviousAction


def _step_function(function, name, returns):
    """A planning function as the bindings take it: None, or a callable (refused by name)."""
    if function is not None and not callable(function):
        raise Error(f"{name} is {function!r}: expected a function {name}(states, actions, "
                    f"next_states) -> (N,) {returns}, or None")
    return function


def _callable_name(function):
    """"module.qualname(args)": what a factory is called, with a functools.partial's arguments."""
    if isinstance(function, functools.partial):
        args = [repr(a) for a in function.args] + [f"{k}={v!r}" for k, v in function.keywords.items()]
        inner = _callable_name(function.func)
        return inner[:-2] + "(" + ", ".join(args) + ")" if inner.endswith("()") else inner
    module = getattr(function, "__module__", None)
    name = getattr(function, "__qualname__", None) or type(function).__qualname__
    return (f"{module}." if module else "") + f"{name}()"


def _env_source(env):
    """(factory, name) of an environment given to train or load_run: a zero-argument factory
    (a function or class), or an environment (its copies, where a learner needs several, are
    deep copies). The name is what a run's task records: "python:" + name."""
    if env is None:
        return None, None
    if not isinstance(env, type) and hasattr(env, "step") and hasattr(env, "reset"):
        spec = getattr(env, "spec", None)
        env_id = getattr(spec, "id", None) if spec is not None else None
        kind = type(env)
        if env_id and kind.__module__.split(".")[0] == "gymnasium":  # made by gymnasium.make
            name = f"gymnasium:{env_id}"
        else:
            name = f"{kind.__module__}.{kind.__qualname__}({repr(env_id) if env_id else ''})"
        given = [env]

        def factory():
            return given.pop() if given else copy.deepcopy(env)
        return factory, name
    if callable(env):
        return env, _callable_name(env)
    raise Error(f"env is {env!r}: expected a Gymnasium-style environment (reset and step) or a "
                "zero-argument function that makes one")


_PRESETS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "presets")


def presets():
    """The presets the package ships (configs/ of the source: each task's paper preset per
    method, the families "cpu" and "quickstart", the PPO ones), by the name train() takes."""
    names = []
    for folder in (_PRESETS, os.path.join(_PRESETS, "ppo")):
        if os.path.isdir(folder):
            names += [name[:-5] for name in os.listdir(folder) if name.endswith(".yaml")]
    return sorted(names)


def _preset_or_path(config):
    """A config file's path: a path as given, or a preset's name ("pointgoal1-rce",
    "quickstart": no folder, no .yaml, no such file here) in the package's presets."""
    if not isinstance(config, (str, os.PathLike)):
        raise Error(f"config is {config!r}: expected a preset's name (cmbrl.presets()), a YAML "
                    "file's path, a list of them, or a dict of config keys")
    path = _as_path(config, "config")
    if (os.sep in path or path.endswith((".yaml", ".yml"))
            or os.path.exists(path)):
        return path
    for folder in (_PRESETS, os.path.join(_PRESETS, "ppo")):
        candidate = os.path.join(folder, path + ".yaml")
        if os.path.isfile(candidate):
            return candidate
    raise Error(f"config '{path}' is neither a file nor a preset"
                f"{_cmbrl.did_you_mean(path, presets())}: expected a YAML file's path or one of "
                f"cmbrl.presets() ({', '.join(presets()[:6])}, ...)")


def train(config=None, out=None, steps=None, seed=None, device=None, resume=None, progress=None,
          checkpoint_seconds=300.0, reward=None, termination=None, env=None):
    """Trains a run as `cmbrl train` does, into the run directory `out`.

    config: a YAML file (path) or a preset's name (cmbrl.presets(): "pointgoal1-rce"), a list of
    them composed in order (a task's paper preset, then a preset family: ["pointgoal1-rce",
    "quickstart"]), or a dict of
    the same keys. steps, seed and device override the config's. resume=RUN_DIR continues a stopped run instead (steps then gives a new budget).
    progress(summary) is called after each unit of work (an MPC episode or a model-free epoch)
    with a dict of epoch, steps, budget, episode_return, episode_cost, episodes (those the unit
    ended: a model-free epoch's return and cost are their means) and seconds. An exception
    it raises, or Ctrl-C (seen after the agent step or fit epoch under way in an MPC run, the
    rollout round or value-fit iteration in a model-free one), stops training at a checkpoint;
    the run resumes later from there.
    checkpoint_seconds: an MPC episode, model fit or model-free epoch still going this long
    after the last checkpoint is checkpointed after its agent step, fit epoch, rollout round or
    value-fit iteration under way (0: after every one); it changes no result.
    reward: an MPC run's planning reward as a vectorised function reward(states, actions,
    next_states) -> rewards, in place of its task's analytic one (the run's config then says
    objective.reward: python). It is called once per planner iteration with every predicted step
    at once: N rows of float64 states (N, S), actions (N, A) and next states (N, S), N = horizon
    x rolled trajectories x samples; it returns N finite rewards (higher is better). A run
    planned so is resumed and loaded with the same function given again (resume=..., reward=f;
    load_run(..., reward=f)); the command line cannot.
    termination: likewise termination(states, actions, next_states) -> N booleans, True where a
    predicted step ends the episode (objective.termination: python): the planning objective
    counts no step after it. Without a function, objective.termination: learned fits a model
    of the probability that a step ends the episode on the steps that ended the run's episodes
    by themselves (terminated, not truncated), refitted with the dynamics; the objective then
    weighs each predicted step by the probability that the episode is still going.
    env: train on your own environment instead of a built-in task (the config then names no
    task): a Gymnasium-style environment, or a zero-argument function or class that makes one
    (the model-free learners step several copies: deep copies of an environment given, or new
    ones from a factory). reset(seed=...) returns (observation, info); step(action) returns
    Safety-Gymnasium's (observation, reward, cost, terminated, truncated, info) or Gymnasium's
    five values with the cost in info["cost"]. A cost above 0 counts as a violation (0/1 is what
    the classifier learns); the raw cost is kept in the step's info. Observation and action
    spaces are 1-D Boxes, the action box finite: cmbrl plans in [-1, 1] per action component and
    maps it linearly onto the box. The run's task records what made it ("python:" +
    "module.make_env()", "python:gymnasium:<id>", or an env object's class and spec id); resume
    and load_run take the same env
    again. Its state is saved through pickle where it pickles (otherwise an episode under way at
    a checkpoint starts again on resume, and the run's sessions.jsonl says so).
    Returns {"run", "steps", "budget", "episodes_this_session", "cost_this_session",
    "seconds_this_session", "cpu_seconds_this_session"}: the run directory, the steps its last
    checkpoint covers, its budget, the episodes this call ended and their summed cost (steps
    with a violation), and this call's wall seconds by part (an MPC run's planning, environment,
    fits; a model-free run's rollout, policy updates, value fits; then checkpoints and other)
    and CPU seconds, as the last line of `cmbrl train` gives them.
    """
    checkpoint_seconds = _as_number(checkpoint_seconds, "checkpoint_seconds", 0.0)
    config_path = config_text = None
    env_factory, env_name = _env_source(env)
    if isinstance(config, dict):
        if "task" not in config and env is None and not (config.get("python") or {}).get("env"):
            raise Error("the config dict names no task, so the run would be the defaults' full "
                        "paper-size PointGoal1 run: name one ({'task': 'PointGoal1', ...})")
        config_text = json.dumps(config, default=_json_number)  # JSON is YAML
    elif isinstance(config, (list, tuple)):
        config_path = [_preset_or_path(path) for path in config]
    elif config is not None:
        config_path = [_preset_or_path(config)]
    out = _as_path(out, "out") if out is not None else None
    resume = _as_path(resume, "resume") if resume is not None else None
    if device is not None:
        _as_str(device, "device", "'cpu', 'cuda' or 'cuda:<index>'")
    if progress is not None and not callable(progress):
        raise Error(f"progress is {progress!r}: expected a function progress(summary) or None")
    return _cmbrl.train(config_path, config_text, out, resume,
                        None if steps is None else _as_int(steps, "steps", 1, 10**10),
                        None if seed is None else _as_seed(seed), device, progress,
                        checkpoint_seconds, _step_function(reward, "reward", "rewards"),
                        _step_function(termination, "termination", "booleans"), env_factory,
                        env_name)


class Agent(_NotCopyable):
    """A trained run's agent (load_run): act(observation) gives its action. An MPC run also
    offers its planner's last plan and predictions and its learned models on numpy arrays.
    Not copyable or picklable: load the run again (cmbrl.load_run) where another is needed.

    Threads: calls on one object from several threads take turns (one lock per object, taken
    with the GIL released); distinct objects run in parallel.
    """

    _instead = "load the run again with cmbrl.load_run(run_dir)"

    def __init__(self, run_dir, seed=0, overrides=(), reward=None, termination=None, env=None):
        self._env_factory, env_name = _env_source(env)
        run_dir = _as_path(run_dir, "run_dir")
        self._agent = _cmbrl.Agent(run_dir, _as_seed(seed), _as_overrides(overrides),
                                   _step_function(reward, "reward", "rewards"),
                                   _step_function(termination, "termination", "booleans"),
                                   self._env_factory, env_name)
        self.run_dir = run_dir
        self.observation_space = _box(self._agent.observation_spec())
        self.action_space = _box(self._agent.action_spec())
        self.is_mpc = self._agent.is_mpc
        environment = self._agent.environment()
        self.task = environment["task"]
        self.variant = environment["variant"]
        self.spawn = environment["spawn"]
        self.previous_action = environment["previous_action"]

    def make_env(self, render_mode=None, render_size=400):
        """A new environment of the run's task, variant and spawn, observing the previous action
        where the run did (what it was trained in); for a run on an environment given from
        Python, one more from what was given (load_run's env; render_mode and render_size are
        then the env's own business), with the previous action appended in the planner's units
        (the action box mapped onto [-1, 1]) where the run observed it."""
        if self._env_factory is not None:
            if self.previous_action:  # as the run observed it, in the planner's units
                return _PlannerUnitsPreviousAction(self._env_factory(), self.observation_space)
            return self._env_factory()
        return Env(self.task, self.variant, self.spawn, render_mode=render_mode,
                   render_size=render_size, previous_action=self.previous_action)

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

    def score(self, observation, sequences):
        """MPC only: the planning objective's scores of action sequences (N, H, A), each within
        the action bounds, from one observation, with this agent's models: a dict of
        reward_cost (N, to minimise), constraint_cost (N, >= 0) and feasible (N bool: no member
        predicts a violation). Plans of other agents or planners, scored alike, compare on the
        same models and state (cmbrl.diagnostics.planner_compare). Call predictions() for a plan
        before scoring: scoring replaces the paths it draws on, until the next act()."""
        return self._agent.score(observation, sequences)

    def predict_violation(self, states):
        """MPC only: the constraint classifier's verdict per state, (N) bool."""
        return self._agent.predict_violation(states)


def load_run(run_dir, seed=0, overrides=None, reward=None, termination=None, env=None):
    """The agent of a trained run directory (its last checkpoint); seed seeds the planner.

    overrides: a dict {"section.key": value} or a list of "section.key=value" that changes how
    the trained models are used, as `cmbrl eval --set` does: planning.*, objective.* and
    classifier.threshold, e.g. {"classifier.threshold": 0.3}.
    reward, termination: the planning functions of a run trained with them (train(...,
    reward=f, termination=g)).
    env: the environment of a run trained on one given from Python (train(env=...)): the same
    kind of factory or environment again; act() then returns actions in its action box."""
    return Agent(run_dir, seed=seed, overrides=_as_overrides(overrides), reward=reward,
                 termination=termination, env=env)


def evaluate(run_dir, episodes=1, seed=0, reseed_each_episode=False, overrides=None, reward=None,
             termination=None, env=None, render=None):
    """Episodes of a trained run's agent, as `cmbrl eval` runs them: a list of dicts of return,
    cost (violating steps), steps, terminated, truncated, ms_per_plan and, for MPC, the plans'
    mean feasible fraction and the share of steps on RCE's fallback; in the navigation world
    (not a declared or Python task) also goals_met, hazard_steps, vase_steps (violating steps
    in a hazard, at a vase), mean_goal_distance and steps_near_goal (within 1 m of the goal).
    seed seeds the environment and the planner; reseed_each_episode resets episode k with
    seed + k. overrides, reward, termination and env as load_run takes them (a run on a Python
    environment needs its env, unless its config names it). render=DIR draws each episode into
    DIR/episode-<k>.png as `cmbrl eval --render` does (the Goal world's arena with the plans,
    or a Python environment's own rgb_array pictures: its factory is called with
    render_mode="rgb_array" where it takes one), and each dict names its "picture"."""
    env_factory, env_name = _env_source(env)
    return _cmbrl.evaluate(_as_path(run_dir, "run_dir"), _as_int(episodes, "episodes", 1, 10**6),
                           _as_seed(seed), _as_flag(reseed_each_episode, "reseed_each_episode"),
                           _as_overrides(overrides),
                           _step_function(reward, "reward", "rewards"),
                           _step_function(termination, "termination", "booleans"),
                           env_factory, env_name,
                           None if render is None else _as_path(render, "render"))
