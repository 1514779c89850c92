"""cmbrl's tasks in Gymnasium's registry, under Safety-Gymnasium's ids (its
safety_gymnasium/__init__.py and utils/registration.py), registered when cmbrl is imported where
gymnasium is importable:

- ``Safety<Robot><Task><Level>Gymnasium-v0``: the stock task in Gymnasium's five-value form, the
  cost in ``info["cost"]`` (Safety-Gymnasium's SafetyGymnasium2Gymnasium), for Gymnasium's own
  tooling: ``gymnasium.make``, ``check_env``, ``make_vec``, its wrappers;
- ``Safety<Robot><Task><Level>-v0``: the stock task in Safety-Gymnasium's six-value form, as
  ``safety_gymnasium.make`` gives it (Gymnasium's environment checker, which expects five
  values, is off for it);
- ``cmbrl/<Robot>Goal<Level>-v0``: the paper's modified Goal tasks (variant ``paper``) in the
  five-value form.

``gymnasium.make("cmbrl:SafetyPointGoal1Gymnasium-v0")`` imports cmbrl first (Gymnasium's
``module:id``)."""
from . import _cmbrl, _gymnasium
from .envs import CostInInfo, Env, VectorCostInInfo, make_vec, tasks



def make_gymnasium_env(task, variant="standard", spawn="standing", render_mode=None,
                       render_size=400):
    """The five-value environment of a registered id: Env wrapped in CostInInfo."""
    return CostInInfo(Env(task, variant=variant, spawn=spawn, render_mode=render_mode,
                          render_size=render_size))


def make_gymnasium_vector_env(num_envs, task, variant="standard", spawn="standing",
                              max_episode_steps=None, **kwargs):
    """The vector_entry_point of the five-value ids (gymnasium.make_vec(...,
    vectorization_mode="vector_entry_point")): cmbrl's C++ VectorEnv in VectorCostInInfo.
    max_episode_steps, which Gymnasium passes from the spec, must be the task's own: the
    environments truncate their episodes themselves. Other kwargs go to make_vec (threads,
    spin_us, autoreset_mode)."""
    if max_episode_steps is not None and max_episode_steps != _cmbrl.episode_steps(task,
                                                                                  variant):
        raise _cmbrl.Error(f"max_episode_steps {max_episode_steps}: {task} ({variant}) episodes "
                           f"are {_cmbrl.episode_steps(task, variant)} steps, and the vector "
                           "cannot cut them shorter; use vectorization_mode 'sync' with a "
                           "TimeLimit")
    kwargs.pop("render_mode", None)  # a vector does not render
    return VectorCostInInfo(make_vec(task, num_envs, variant=variant, spawn=spawn, **kwargs))


def make_safety_gymnasium_env(task, variant="standard", spawn="standing", render_mode=None,
                              render_size=400, previous_action=False):
    """The six-value environment of a registered id (Safety-Gymnasium's form)."""
    return Env(task, variant=variant, spawn=spawn, render_mode=render_mode,
               render_size=render_size, previous_action=previous_action)


def registered_ids():
    """Every id this module registers, with its entry point and kwargs:
    [(id, entry_point, kwargs, five_value)]."""
    ids = []
    for task in tasks():
        stock = {"task": task, "variant": "standard"}
        ids.append((f"Safety{task}Gymnasium-v0", "cmbrl.registration:make_gymnasium_env",
                    stock, True))
        ids.append((f"Safety{task}-v0", "cmbrl.registration:make_safety_gymnasium_env", stock,
                    False))
        if _cmbrl.default_variant(task) == "paper":
            ids.append((f"cmbrl/{task}-v0", "cmbrl.registration:make_gymnasium_env",
                        {"task": task, "variant": "paper"}, True))
    return ids


def register_envs():
    """Registers registered_ids() in Gymnasium's registry (once; ids already there are left as
    they are). Nothing happens where gymnasium is not importable."""
    if _gymnasium.registration is None:
        return
    registry = _gymnasium.registration.registry
    for env_id, entry_point, kwargs, five_value in registered_ids():
        if env_id in registry:
            continue
        _gymnasium.registration.register(
            id=env_id, entry_point=entry_point, kwargs=dict(kwargs),
            # The environment truncates its own episodes at this step; Gymnasium's TimeLimit
            # (five values only) repeats that at the same step.
            max_episode_steps=(_cmbrl.episode_steps(kwargs["task"], kwargs["variant"])
                               if five_value else None),
            disable_env_checker=not five_value,
            vector_entry_point=("cmbrl.registration:make_gymnasium_vector_env" if five_value
                                else None))


register_envs()  # at import: `import cmbrl` registers, as `import safety_gymnasium` does
