"""The environments from Python: Safety-Gymnasium's API, equal to the C++ program bit for bit."""
import copy
import json
import math
import subprocess

import numpy as np
import pytest

import cmbrl


@pytest.mark.parametrize("task", ["PointGoal1", "CarGoal2", "PointButton1", "CarPush2",
                                  "PointCircle2"])
def test_an_episode_from_python_equals_cmbrl_rollout_bit_for_bit(task, cmbrl_binary, tmp_path):
    trace = tmp_path / "trace.jsonl"
    subprocess.run([cmbrl_binary, "rollout", "--task", task, "--seed", "7", "--trace", str(trace)],
                   check=True, stdout=subprocess.DEVNULL)
    lines = [json.loads(line) for line in trace.read_text().splitlines()]
    assert lines[0]["reset"] and lines[0]["seed"] == 7
    env = cmbrl.make(task)
    obs, info = env.reset(seed=7)
    assert np.array_equal(obs, np.array(lines[0]["observation"]))
    for line in lines[1:]:
        obs, reward, cost, terminated, truncated, info = env.step(np.array(line["action"]))
        assert np.array_equal(obs, np.array(line["observation"]))
        assert reward == line["reward"] and cost == line["cost"]
        assert (terminated, truncated) == (line["terminated"], line["truncated"])
    assert terminated or truncated
    assert len(lines) > 50


def test_the_api_is_safety_gymnasiums():
    env = cmbrl.make("PointGoal1", variant="paper")
    assert env.observation_space.shape == (len(env.observation_names),)
    assert env.action_space.shape == (2,)
    assert env.action_space.dtype == np.float64
    assert np.all(env.action_space.low == -1) and np.all(env.action_space.high == 1)
    obs, info = env.reset(seed=0)
    assert isinstance(info, dict)
    assert obs.dtype == np.float64 and obs.shape == env.observation_space.shape
    action = env.action_space.sample()
    assert env.action_space.contains(action)
    obs, reward, cost, terminated, truncated, info = env.step(action)
    assert isinstance(reward, float) and cost in (0.0, 1.0)
    assert isinstance(terminated, bool) and isinstance(truncated, bool)
    assert {"goal_met", "cost_hazards", "env_steps"} <= set(info)
    assert env.max_episode_steps > 0
    # float32 and integer actions are real numbers too.
    env.step(np.zeros(2, dtype=np.float32))
    env.step([0, 1])


def test_reset_with_a_seed_repeats_and_without_continues():
    env = cmbrl.make("CarGoal1")
    first, _ = env.reset(seed=3)
    again, _ = env.reset(seed=3)
    assert np.array_equal(first, again)
    other, _ = env.reset()
    assert not np.array_equal(first, other)


def test_ground_truth_and_render():
    env = cmbrl.make("PointGoal2", render_mode="rgb_array", render_size=256)
    env.reset(seed=1)
    for _ in range(5):
        env.step(np.array([1.0, 0.2]))
    truth = env.ground_truth()
    assert truth["robot_position"].shape == (2,) and truth["goal"].shape == (2,)
    assert truth["hazards"].shape[1] == 2 and len(truth["hazards"]) > 0
    assert truth["vases"].shape[1] == 3
    assert math.isfinite(truth["robot_yaw"])
    assert truth["robot_upright"] == 1.0  # the Point is planar: never tilted
    image = env.render()
    assert image.dtype == np.uint8 and image.ndim == 3 and image.shape[2] == 3
    assert image.shape[1] == 256
    assert (image != 255).any() and (image == 255).any()


@pytest.mark.parametrize("action, words", [
    (np.zeros(3), "shape"),
    (np.zeros((1, 2)), "shape"),
    (np.array(["a", "b"]), "dtype"),
    (np.array([1j, 0]), "dtype"),
    (np.array([np.nan, 0.0]), "finite"),
])
def test_bad_actions_raise_errors_that_name_them(action, words):
    env = cmbrl.make("PointGoal1")
    env.reset(seed=0)
    with pytest.raises(cmbrl.Error, match=words):
        env.step(action)
    env.step(np.zeros(2))  # still usable


def test_bad_use_raises_python_exceptions():
    with pytest.raises(cmbrl.Error, match="NoSuchTask"):
        cmbrl.make("NoSuchTask")
    with pytest.raises(ValueError, match="variant"):
        cmbrl.make("PointGoal1", variant="sideways")
    env = cmbrl.make("PointGoal1")
    with pytest.raises(cmbrl.Error, match="reset"):
        env.step(np.zeros(2))
    env.reset(seed=0)
    env.close()
    assert env.closed
    with pytest.raises(cmbrl.Error, match="closed"):
        env.step(np.zeros(2))
    with pytest.raises(cmbrl.Error, match="closed"):
        env.reset()
    assert issubclass(cmbrl.Error, ValueError)
    assert set(cmbrl.tasks()) >= {"PointGoal1", "PointGoal2", "CarGoal1", "CarGoal2"}


def test_spaces_are_gymnasiums_boxes_when_gymnasium_is_importable(monkeypatch):
    import cmbrl._gymnasium

    class FakeBox:
        def __init__(self, low, high, dtype, shape=None, seed=None):
            self.low, self.high, self.shape, self.dtype, self.seed = low, high, shape, dtype, seed

    with monkeypatch.context() as patch:  # gymnasium's Box, as cmbrl._gymnasium finds it
        patch.setattr(cmbrl._gymnasium, "Box", FakeBox)
        box = cmbrl.spaces.Box(low=[-1, -1], high=[1, 1])
        assert isinstance(box, FakeBox) and box.dtype == np.float64
        box = cmbrl.spaces.Box(low=-1, high=1, shape=(3,), seed=4)  # passed on as given
        assert (box.low, box.shape, box.seed) == (-1.0, (3,), 4)
    with monkeypatch.context() as patch:  # no gymnasium: the look-alike
        patch.setattr(cmbrl._gymnasium, "Box", None)
        assert isinstance(cmbrl.spaces.Box(low=[0], high=[1]), cmbrl.spaces._Box)


def test_an_unseeded_first_reset_draws_from_entropy_and_seeds_must_be_integers():
    first = [cmbrl.make("PointGoal1").reset()[0] for _ in range(3)]
    # Three layouts drawn from OS entropy: equal only by a collision of 63-bit seeds.
    assert not np.array_equal(first[0], first[1]) or not np.array_equal(first[1], first[2])
    env = cmbrl.make("PointGoal1")
    seeded = env.reset(seed=np.int64(5))[0]
    assert np.array_equal(seeded, cmbrl.make("PointGoal1").reset(seed=5)[0])
    for bad in (1.7, True, -1, 2**64, "3"):
        with pytest.raises(cmbrl.Error, match="expected an integer"):
            env.reset(seed=bad)


def test_unseeded_vector_envs_differ_and_any_list_of_seeds_seeds_each():
    envs = cmbrl.make_vec("PointGoal1", num_envs=3)
    obs, _ = envs.reset()
    assert not np.array_equal(obs[0], obs[1]) and not np.array_equal(obs[1], obs[2])
    by_list, _ = envs.reset(seed=[7, 8, 9])
    by_base, _ = cmbrl.make_vec("PointGoal1", num_envs=3).reset(seed=7)
    assert np.array_equal(by_list, by_base)
    # Any list (Gymnasium's SyncVectorEnv): each its own seed, None where it continues.
    spread, _ = envs.reset(seed=[11, 3, None])
    single = [cmbrl.make("PointGoal1").reset(seed=s)[0] for s in (11, 3)]
    assert np.array_equal(spread[0], single[0]) and np.array_equal(spread[1], single[1])
    fresh, _ = cmbrl.make_vec("PointGoal1", num_envs=2).reset(seed=[None, None])
    assert not np.array_equal(fresh[0], fresh[1])  # a first reset's None draws from entropy
    with pytest.raises(cmbrl.Error, match="2 seeds for 3 environments"):
        envs.reset(seed=[7, 8])
    with pytest.raises(cmbrl.Error, match="expected an integer"):
        envs.reset(seed=2.5)


def test_the_package_says_its_version_and_documents_its_public_api():
    import inspect
    import re

    assert re.fullmatch(r"\d+\.\d+\.\d+", cmbrl.__version__)
    assert cmbrl.__commit__
    undocumented = []
    for name in cmbrl.__all__:
        obj = getattr(cmbrl, name)
        if not (obj.__doc__ or "").strip():
            undocumented.append(name)
        if inspect.isclass(obj):
            for attr, member in vars(obj).items():
                if attr.startswith("_"):
                    continue
                target = member.fget if isinstance(member, property) else member
                if callable(target) and not (getattr(target, "__doc__", "") or "").strip():
                    undocumented.append(f"{name}.{attr}")
    assert undocumented == []
    for cls in (cmbrl.Env, cmbrl.VectorEnv, cmbrl.Agent, cmbrl.Ensemble, cmbrl.CostClassifier):
        assert "take turns" in cls.__doc__, f"{cls.__name__} does not say its thread rule"


def test_gymnasium_attributes_and_safety_gymnasium_ids():
    env = cmbrl.make("SafetyPointGoal1-v0")
    assert (env.task, env.variant) == ("PointGoal1", "standard")
    assert env.spec.id == "SafetyPointGoal1-v0"
    assert env.spec.max_episode_steps is None  # it truncates itself (no TimeLimit)
    assert env.spec.kwargs["variant"] == "standard"
    assert env.spec.disable_env_checker  # the six-value step is Safety-Gymnasium's
    again = env.spec.make().unwrapped  # gymnasium.make(spec) wraps it, where importable
    assert (again.task, again.variant) == ("PointGoal1", "standard")
    assert json.loads(env.spec.to_json())["kwargs"]["task"] == "PointGoal1"
    assert cmbrl.make("SafetyCarGoal2-v0", variant="paper").variant == "paper"
    assert cmbrl.make("PointGoal1").variant == "paper"
    assert env.reward_range == (-math.inf, math.inf)
    assert env.metadata["render_fps"] == round(1 / env.agent_step_seconds)
    env.reset(seed=5)
    first = env.np_random.integers(1 << 30)
    env.reset(seed=5)
    assert env.np_random.integers(1 << 30) == first
    vec = cmbrl.make_vec("SafetyCarGoal1-v0", num_envs=2)
    assert (vec.task, vec.variant) == ("CarGoal1", "standard")
    with pytest.raises(cmbrl.Error, match="SafetyPointGoal3-v0"):
        cmbrl.make("SafetyPointGoal3-v0")
    with pytest.raises(cmbrl.Error, match=r"unknown task 'SafetyPointGaol1-v0' \(did you mean "
                                          r"'SafetyPointGoal1-v0'\?\): expected a Safety-Gym"):
        cmbrl.make("SafetyPointGaol1-v0")
    with pytest.raises(cmbrl.Error, match=r"unknown task 'SafetyCarPush2-v1' \(did you mean "
                                          r"'SafetyCarPush2-v0'\?\)"):
        cmbrl.make("SafetyCarPush2-v1")
    with pytest.raises(cmbrl.Error, match=r"unknown task 'PointGaol2' \(did you mean 'PointGoal2'"):
        cmbrl.make("PointGaol2")
    with pytest.raises(cmbrl.Error, match="task is 3"):
        cmbrl.make(3)


def test_the_look_alike_box_has_gymnasiums_attributes_and_rules():
    from cmbrl.spaces import _Box

    box = _Box(low=[-1.0, 0.0], high=[1.0, np.inf], dtype=np.float32)
    assert box.is_bounded("below") and not box.is_bounded("above") and not box.is_bounded()
    assert list(box.bounded_above) == [True, False]
    assert box.seed(4) == 4  # the seed used, as gymnasium's Space.seed returns it
    first = box.sample()
    assert box.np_random is box._rng
    drawn = box.seed()
    assert isinstance(drawn, int) and drawn >= 0  # None: one drawn from the system's entropy
    box.seed(4)
    assert np.array_equal(box.sample(), first) and first.dtype == np.float32
    assert box.contains(np.array([0.5, 3.0], dtype=np.float32))
    assert not box.contains(np.array([0.5, 3.0], dtype=np.float64))  # float64 is not float32
    assert not box.contains(np.array([0.5, -1.0], dtype=np.float32))  # below the bound
    assert not box.contains(np.array([0.5], dtype=np.float32))  # shape
    assert not box.contains("a")
    assert box == _Box(low=[-1.0, 0.0], high=[1.0, np.inf], dtype=np.float32)
    assert box != _Box(low=[-1.0, 0.0], high=[1.0, np.inf], dtype=np.float64)
    assert box != _Box(low=[-1.0, 0.0], high=[2.0, np.inf], dtype=np.float32)
    with pytest.raises(ValueError, match="manner"):
        box.is_bounded("sideways")
    with pytest.raises(ValueError, match="mask"):
        box.sample(mask=np.ones(2, dtype=np.int8))


BOX_ARGUMENTS = [  # gymnasium.spaces.Box's forms: (low, high, keyword arguments)
    (-1.0, 2.0, {"shape": (3, 2)}),
    (np.zeros(2), np.ones(2), {}),
    (0, 1, {}),  # two scalars: shape (1,)
    (-np.inf, np.inf, {"shape": [4]}),
    (np.array([-1.0, -2.0]), 2.0, {}),  # the scalar repeated over the array's shape
    (0, 1, {"shape": (2,), "dtype": np.float32}),
]
BAD_BOX_ARGUMENTS = [
    (np.zeros(2), np.ones(3), {}, ValueError, r"low has shape \(2,\), high \(3,\)"),
    (np.zeros(2), 1.0, {"shape": (3,)}, ValueError, r"low has shape \(2,\): expected \(3,\)"),
    (float("nan"), 1.0, {"shape": (2,)}, ValueError, "low holds NaN"),
    (0.0, 1.0, {"shape": "ab"}, TypeError, "shape is 'ab'"),
    (0.0, 1.0, {"shape": 3}, TypeError, "shape is 3"),
]


@pytest.mark.parametrize("low,high,kwargs", BOX_ARGUMENTS)
def test_the_look_alike_box_takes_gymnasiums_arguments(low, high, kwargs):
    from cmbrl.spaces import _Box

    box = _Box(low, high, **kwargs)
    shape = tuple(kwargs.get("shape", np.shape(low) or np.shape(high) or (1,)))
    assert box.shape == shape and box.low.shape == shape and box.high.shape == shape
    assert box.low.dtype == box.dtype == np.dtype(kwargs.get("dtype", np.float64))
    assert np.all(box.low == low) and np.all(box.high == high)
    assert box.sample().shape == shape and box.contains(box.sample())
    seeded = [_Box(low, high, seed=7, **kwargs).sample() for _ in range(2)]
    assert np.array_equal(*seeded)  # seed= seeds sample(), as gymnasium's Box(seed=) does


@pytest.mark.parametrize("low,high,kwargs,error,message", BAD_BOX_ARGUMENTS)
def test_the_look_alike_box_refuses_what_gymnasium_refuses(low, high, kwargs, error, message):
    from cmbrl.spaces import _Box

    with pytest.raises(error, match=message):
        _Box(low, high, **kwargs)
    with pytest.raises(ValueError, match="dtype is int64: expected a floating dtype"):
        _Box(0, 1, dtype=np.int64)


@pytest.mark.parametrize("low,high,kwargs", BOX_ARGUMENTS)
def test_the_look_alike_box_is_gymnasiums_box_where_gymnasium_is_installed(low, high, kwargs):
    gymnasium = pytest.importorskip("gymnasium")
    if getattr(gymnasium, "FAKE", False):
        pytest.skip("a stand-in gymnasium")
    from cmbrl.spaces import _Box

    kwargs = {"dtype": np.float64, **kwargs}  # gymnasium's default dtype is float32, cmbrl's 64
    ours, theirs = _Box(low, high, **kwargs), gymnasium.spaces.Box(low, high, **kwargs)
    assert isinstance(cmbrl.Box(low, high, **kwargs), gymnasium.spaces.Box)
    assert (ours.shape, ours.dtype, repr(ours)) == (theirs.shape, theirs.dtype, repr(theirs))
    assert np.array_equal(ours.low, theirs.low) and np.array_equal(ours.high, theirs.high)
    for bad_low, bad_high, bad, error, _ in BAD_BOX_ARGUMENTS:
        with pytest.raises(error):
            gymnasium.spaces.Box(bad_low, bad_high, **{"dtype": np.float64, **bad})


@pytest.mark.parametrize("task,variant", [("PointGoal1", "paper"), ("CarGoal2", "standard"),
                                          ("SafetyPointGoal2-v0", None)])
def test_an_env_pickled_or_copied_mid_episode_continues_exactly(task, variant):
    import copy
    import pickle

    env = cmbrl.make(task, variant=variant, render_size=64)
    obs, _ = env.reset(seed=11)
    for _ in range(env.max_episode_steps - 20):  # the episode ends after the copies are made
        obs, _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        assert not (terminated or truncated)
    copies = [pickle.loads(pickle.dumps(env)), copy.deepcopy(env), copy.copy(env)]
    for other in copies:
        assert other is not env and other._env is not env._env
        assert (other.task, other.variant, other.spawn, other.spec.id) == \
            (env.task, env.variant, env.spawn, env.spec.id)
        assert np.array_equal(other.render(), env.render())  # the episode's path came along
    for step in range(60):
        action = env.action_space.sample()
        for other in copies:
            assert np.array_equal(other.action_space.sample(), action)  # its generator too
        result = env.step(action)
        for other in copies:
            theirs = other.step(action)
            assert np.array_equal(theirs[0], result[0]), f"step {step}"
            assert theirs[1:5] == result[1:5]
        if result[3] or result[4]:
            first = env.reset()[0]  # unseeded: the generator continues, in the copies too
            for other in copies:
                assert np.array_equal(other.reset()[0], first)
    # The copies are independent: stepping one leaves the others where they were.
    before = copies[1]._env.state()
    copies[0].step(env.action_space.sample())
    assert copies[1]._env.state() == before


def test_a_pickled_env_refuses_another_environments_state_and_a_closed_one_refuses_copies():
    import pickle

    point, car = cmbrl.make("PointGoal1"), cmbrl.make("CarGoal1")
    point.reset(seed=1)
    car.reset(seed=1)
    with pytest.raises(cmbrl.Error, match="pickled CarGoal1 environment|another environment"):
        car._env.set_state(point._env.state())
    with pytest.raises(cmbrl.Error, match="damaged"):
        car._env.set_state(b"not a state")
    point.close()
    with pytest.raises(cmbrl.Error, match=r"a closed cmbrl\.Env \(PointGoal1\) cannot be pickled"):
        pickle.dumps(point)


def test_cost_in_info_gives_gymnasiums_five_values():
    plain, wrapped = cmbrl.make("PointGoal2"), cmbrl.CostInInfo(cmbrl.make("PointGoal2"))
    assert wrapped.action_space == plain.action_space and wrapped.spec.id == "PointGoal2"
    assert wrapped.unwrapped is wrapped.env
    a, _ = plain.reset(seed=4)
    b, _ = wrapped.reset(seed=4)
    assert np.array_equal(a, b)
    costs = 0.0
    for _ in range(80):
        action = plain.action_space.sample()
        obs, reward, cost, terminated, truncated, info = plain.step(action)
        five = wrapped.step(action)
        assert len(five) == 5
        assert np.array_equal(five[0], obs) and five[1:4] == (reward, terminated, truncated)
        assert five[4]["cost"] == cost and five[4]["goal_met"] == info["goal_met"]
        costs += cost
    wrapped.close()
    assert wrapped.env.closed

    plain_vec = cmbrl.make_vec("CarGoal2", num_envs=3)
    vec = cmbrl.VectorCostInInfo(cmbrl.make_vec("CarGoal2", num_envs=3))
    assert vec.num_envs == 3
    plain_vec.reset(seed=[1, 2, 3])
    vec.reset(seed=[1, 2, 3])
    for _ in range(30):
        actions = plain_vec.action_space.sample()
        obs, rewards, step_costs, terminations, truncations, _ = plain_vec.step(actions)
        five = vec.step(actions)
        assert np.array_equal(five[0], obs) and np.array_equal(five[1], rewards)
        assert np.array_equal(five[4]["cost"], step_costs)


def test_button_push_and_circle_are_stock_tasks_with_their_cost_terms():
    assert {"PointButton0", "CarPush2", "PointCircle1"} <= set(cmbrl.tasks())
    env = cmbrl.make("PointButton1")  # its only variant, the stock one, by default
    assert env.observation_names[12:14] == ["buttons_lidar_0", "buttons_lidar_1"]
    env.reset(seed=0)
    _, _, _, _, _, info = env.step(np.zeros(2))
    for term in ("cost_hazards", "cost_buttons", "cost_gremlins", "cost_pillars",
                 "cost_out_of_boundary"):
        assert info[term] == 0.0
    same = cmbrl.make("SafetyPointButton1-v0")
    assert same.observation_names == env.observation_names
    with pytest.raises(cmbrl.Error, match="has no variant 'paper'"):
        cmbrl.make("PointCircle1", variant="paper")
    vec = cmbrl.make_vec("PointPush1", num_envs=2)
    vec.reset(seed=0)
    _, _, _, _, _, info = vec.step(np.zeros((2, 2)))
    assert info["cost_pillars"].shape == (2,)
    vec.close()


def test_registered_ids_follow_safety_gymnasiums_conventions():
    ids = {env_id: (entry, kwargs, five) for env_id, entry, kwargs, five in
           cmbrl.registration.registered_ids()}
    for task in cmbrl.tasks():
        assert ids[f"Safety{task}Gymnasium-v0"][1:] == ({"task": task, "variant": "standard"}, True)
        assert ids[f"Safety{task}-v0"][1:] == ({"task": task, "variant": "standard"}, False)
        assert (f"cmbrl/{task}-v0" in ids) == ("paper" in cmbrl.variants(task))
    five = cmbrl.registration.make_gymnasium_env("PointCircle1")
    five.reset(seed=1)
    assert len(five.step(np.zeros(2))) == 5
    env = cmbrl.make("CarButton1")  # copied and pickled before its first reset
    import copy
    import pickle
    for twin in (copy.deepcopy(env), pickle.loads(pickle.dumps(env))):
        a, _ = env.reset(seed=3)
        b, _ = twin.reset(seed=3)
        assert np.array_equal(a, b)
    env.reset(seed=9)
    assert env.np_random_seed == 9
    generator = env.np_random
    assert env.np_random_seed == 9 and env.np_random is generator
    env.np_random = np.random.default_rng(1)
    assert env.np_random_seed == -1


def test_next_step_autoreset_is_the_default_with_gymnasiums_masks():
    vec = cmbrl.make_vec("PointGoal1", num_envs=2)
    assert str(getattr(vec.metadata["autoreset_mode"], "value", vec.metadata["autoreset_mode"])) \
        in ("NextStep", "next-step")
    single = cmbrl.make("PointGoal1")
    vec.reset(seed=[4, 5])
    first, _ = single.reset(seed=4)
    actions = np.zeros((2, 2))
    for step in range(single.max_episode_steps):
        obs, rewards, costs, terminated, truncated, info = vec.step(actions)
        out = single.step(actions[0])
        assert np.array_equal(obs[0], out[0]) and rewards[0] == out[1]
        assert info["_cost_hazards"].all() and info["cost_sum"].shape == (2,)
        if truncated[0]:
            break
    assert truncated.all() and step + 1 == single.max_episode_steps
    # The next step resets both, their actions unread: first observations, zeros, masks False.
    obs, rewards, costs, terminated, truncated, info = vec.step(np.full((2, 2), np.nan))
    again, _ = single.reset()
    assert np.array_equal(obs[0], again)
    assert not rewards.any() and not costs.any() and not (terminated | truncated).any()
    assert not info["_cost_hazards"].any()
    obs, *_ , info = vec.step(actions)
    assert info["_cost_hazards"].all()
    with pytest.raises(cmbrl.Error, match="expected 'next-step', 'same-step' or 'disabled'"):
        cmbrl.make_vec("PointGoal1", num_envs=2, autoreset_mode="sometimes")


def test_human_rendering_names_what_it_lacks(monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    with pytest.raises(cmbrl.Error, match="render_mode 'human' needs a display: neither DISPLAY"):
        cmbrl.make("PointGoal1", render_mode="human")
    monkeypatch.setenv("DISPLAY", ":99")
    try:
        import tkinter  # noqa: F401
    except ImportError:
        with pytest.raises(cmbrl.Error, match="draws with tkinter"):
            cmbrl.make("PointGoal1", render_mode="human")
        # Listed only where it works: Gymnasium's check_env makes every listed mode.
        assert "human" not in cmbrl.make("PointGoal1").metadata["render_modes"]


def test_the_paper_car_runs_the_originals_action_path():
    """Issue 58's second candidate, as the original's wrapper and engine (facts B0): an agent step
    is 2 env steps of 0.2 s, an episode 75 agent steps, the action box [-1, 1], and the engine
    clips each entry to its actuator's range, so steering saturates at 0.6."""
    env = cmbrl.make("CarGoal2", variant="paper")
    assert env.agent_step_seconds == pytest.approx(0.4) and env.max_episode_steps == 75
    assert np.array_equal(env.action_space.low, [-1, -1])
    assert np.array_equal(env.action_space.high, [1, 1])
    env.reset(seed=1)
    for _ in range(3):
        env.step(np.array([0.2, 0.8]))
    after = {steer: copy.deepcopy(env).step(np.array([steer, 0.7]))[0] for steer in (0.5, 0.6, 1.0)}
    assert np.array_equal(after[0.6], after[1.0])  # beyond the servo's range: the same command
    assert np.abs(after[0.5] - after[0.6]).max() > 0.01


def test_previous_action_is_appended_clipped_and_survives_copies():
    import copy
    import pickle

    env = cmbrl.make("CarGoal1", previous_action=True)
    plain = cmbrl.make("CarGoal1")
    assert env.previous_action and not plain.previous_action
    size = plain.observation_space.shape[0]
    assert env.observation_space.shape == (size + 2,)
    assert env.observation_names[size:] == ["previous_action_0", "previous_action_1"]
    assert env.spec.kwargs["previous_action"] is True and "previous_action" not in plain.spec.kwargs
    obs, _ = env.reset(seed=4)
    assert np.array_equal(obs[:size], plain.reset(seed=4)[0]) and not obs[size:].any()
    for action in ([0.25, -0.5], [3.0, -2.0]):
        obs = env.step(np.array(action))[0]
        assert np.array_equal(obs[:size], plain.step(np.array(action))[0])
    assert np.array_equal(obs[size:], [1.0, -1.0])  # clipped to the action box
    for other in (pickle.loads(pickle.dumps(env)), copy.deepcopy(env)):
        assert other.previous_action
        assert np.array_equal(other.step(np.array([0.1, 0.2]))[0],
                              copy.deepcopy(env).step(np.array([0.1, 0.2]))[0])
    with pytest.raises(cmbrl.Error, match="previous_action is 1: expected True or False"):
        cmbrl.make("CarGoal1", previous_action=1)
