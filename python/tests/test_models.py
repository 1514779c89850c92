"""The learned models on numpy arrays, without a run."""
import numpy as np
import pytest

import cmbrl


def test_the_ensemble_learns_a_linear_system():
    rng = np.random.default_rng(0)
    states = rng.uniform(-1, 1, size=(3000, 4))
    actions = rng.uniform(-1, 1, size=(3000, 2))
    next_states = states + 0.2 * np.concatenate([actions, -actions], axis=1)
    model = cmbrl.Ensemble(4, 2, ensemble_size=3, hidden_sizes=[64, 64], max_epochs=40, seed=1)
    report = model.fit(states, actions, next_states)
    assert model.transitions == 3000 and report["epochs"] > 0
    assert report["backend"] in ("onednn", "libtorch")
    assert report["training_backend"] == report["backend"]  # 64 wide: trained where it predicts
    test_s, test_a = rng.uniform(-0.8, 0.8, size=(200, 4)), rng.uniform(-0.8, 0.8, size=(200, 2))
    predicted = model.predict(test_s, test_a)
    assert predicted.shape == (3, 200, 4)
    truth = test_s + 0.2 * np.concatenate([test_a, -test_a], axis=1)
    assert np.mean((predicted - truth) ** 2) < 0.05 * np.var(truth)
    with pytest.raises(cmbrl.Error, match="actions"):
        model.predict(test_s, test_a[:, :1])


def _cpu_has_avx512():
    # The flags cmbrl's CpuHasAvx512 asks for (cmbrl/core/cpu_features.h).
    try:
        with open("/proc/cpuinfo") as cpuinfo:
            flags = next((line.split() for line in cpuinfo if line.startswith("flags")), [])
    except OSError:
        return False
    return all(f in flags for f in ("avx512f", "avx512bw", "avx512vl", "avx512dq"))


def test_wide_ensembles_train_on_onednn_only_with_avx512():
    # Wider than 256: oneDNN trains where it predicts on a CPU with AVX-512, LibTorch elsewhere.
    rng = np.random.default_rng(1)
    states, actions = rng.uniform(-1, 1, size=(20, 3)), rng.uniform(-1, 1, size=(20, 1))
    model = cmbrl.Ensemble(3, 1, ensemble_size=2, hidden_sizes=[8, 600], max_epochs=1, seed=1)
    report = model.fit(states, actions, states)
    assert report["backend"] in ("onednn", "libtorch")
    wide_on_onednn = report["backend"] == "onednn" and _cpu_has_avx512()
    assert report["training_backend"] == ("onednn" if wide_on_onednn else "libtorch")


def test_predicting_the_change_helps_where_states_dwarf_their_change():
    # States spread over +-20 with a change of at most 0.2 from the action: an absolute-state
    # network must learn the identity map first, a change-predicting one only the change.
    rng = np.random.default_rng(3)
    states = rng.uniform(-20, 20, size=(3000, 4))
    actions = rng.uniform(-1, 1, size=(3000, 2))
    change = 0.2 * np.concatenate([actions, -actions], axis=1)
    test_s, test_a = rng.uniform(-16, 16, size=(300, 4)), rng.uniform(-0.8, 0.8, size=(300, 2))
    truth = test_s + 0.2 * np.concatenate([test_a, -test_a], axis=1)
    errors = {}
    for delta in (False, True):
        model = cmbrl.Ensemble(4, 2, ensemble_size=2, hidden_sizes=[32, 32], max_epochs=20,
                               seed=1, predict_delta=delta)
        model.fit(states, actions, states + change)
        errors[delta] = np.mean((model.predict(test_s, test_a) - truth) ** 2)
    assert errors[True] < 0.2 * errors[False], errors


def test_the_classifier_learns_a_hazard():
    rng = np.random.default_rng(2)
    states = rng.uniform(-1, 1, size=(4000, 3))
    unsafe = np.hypot(states[:, 0], states[:, 1]) < 0.4
    classifier = cmbrl.CostClassifier(3, rounds=100, seed=0)
    report = classifier.fit(states, unsafe)
    assert report["trained"] and report["unsafe_used"] == unsafe.sum()
    test = rng.uniform(-1, 1, size=(1000, 3))
    verdict = classifier.predict(test)
    assert verdict.dtype == bool and verdict.shape == (1000,)
    assert np.mean(verdict == (np.hypot(test[:, 0], test[:, 1]) < 0.4)) > 0.95
    with pytest.raises(cmbrl.Error, match="unsafe"):
        classifier.fit(states, np.full(4000, 2.0))


def test_the_classifier_fit_set_is_the_runs_own_selection():
    # Every unsafe state and the newest 3 n + 1 safe ones, the safe first, in storage order.
    classifier = cmbrl.CostClassifier(1)
    rows = np.arange(20, dtype=float).reshape(20, 1)
    labels = np.zeros(20, dtype=bool)
    labels[[2, 5]] = True
    x, y = classifier.fit_set(rows, labels)
    assert list(x[:, 0]) == [13, 14, 15, 16, 17, 18, 19, 2, 5]
    assert list(y) == [False] * 7 + [True] * 2
    # A run's buffer keeps the newest 10,000 unsafe states: so does the fit set.
    n = 10_005
    x, y = classifier.fit_set(np.arange(n, dtype=float).reshape(n, 1), np.ones(n, dtype=bool))
    assert len(x) == 10_000 and y.all() and list(x[[0, -1], 0]) == [5, n - 1]
    with pytest.raises(cmbrl.Error, match=r"unsafe\[1\] is 2: expected 0 or 1"):
        classifier.fit_set(rows[:2], [0, 2])


def test_sizes_too_large_for_the_machine_are_refused_by_name():
    # Before anything is allocated: these ended in LibTorch's allocator stack trace.
    with pytest.raises(cmbrl.Error, match=r"an ensemble of 4 members with hidden layers "
                                          r"\[65536, 65536, 65536\].*more than 80%"):
        cmbrl.Ensemble(state_dim=4, action_dim=2, hidden_sizes=[65536] * 3)
    # A view of a billion rows that takes no memory itself: the copies a fit makes would.
    huge = np.broadcast_to(np.zeros(8), (10**9, 8))
    with pytest.raises(cmbrl.Error, match="fitting the classifier on 1000000000 states"):
        cmbrl.CostClassifier(state_dim=8, rounds=5).fit(huge, np.broadcast_to(np.zeros(1), (10**9,)))
    model = cmbrl.Ensemble(state_dim=8, action_dim=2, hidden_sizes=[8], max_epochs=1)
    with pytest.raises(cmbrl.Error, match="fitting the ensemble on 1000000000 more transitions"):
        model.fit(huge, np.broadcast_to(np.zeros(2), (10**9, 2)), huge)


@pytest.mark.parametrize("bad", [2.5, "3", True, -1, 2**40])
def test_integer_arguments_refuse_floats_and_out_of_range_values(bad):
    with pytest.raises(cmbrl.Error, match="state_dim is"):
        cmbrl.Ensemble(state_dim=bad, action_dim=2)
    with pytest.raises(cmbrl.Error, match=r"hidden_sizes\[1\] is"):
        cmbrl.Ensemble(state_dim=4, action_dim=2, hidden_sizes=[8, bad])
    with pytest.raises(cmbrl.Error, match="rounds is"):
        cmbrl.CostClassifier(state_dim=4, rounds=bad)
    with pytest.raises(cmbrl.Error, match="num_envs is"):
        cmbrl.make_vec("PointGoal1", num_envs=bad)


def _pendulum_data(seed, n=600):
    rng = np.random.default_rng(seed)
    states = rng.uniform(-1, 1, size=(n, 4))
    actions = rng.uniform(-1, 1, size=(n, 2))
    return states, actions, states + 0.1 * np.concatenate([actions, -actions], axis=1)


def test_an_ensemble_saved_loaded_pickled_or_deep_copied_predicts_and_continues_the_same(tmp_path):
    import copy
    import pickle

    model = cmbrl.Ensemble(state_dim=4, action_dim=2, ensemble_size=2, hidden_sizes=[16],
                           max_epochs=3, seed=5)
    model.fit(*_pendulum_data(0))
    model.save(tmp_path / "saved")
    copies = [cmbrl.Ensemble.load(tmp_path / "saved"), pickle.loads(pickle.dumps(model)),
              copy.deepcopy(model), copy.copy(model)]
    s, a, _ = _pendulum_data(1, 50)
    for other in copies:
        assert other.transitions == model.transitions
        assert np.array_equal(other.predict(s, a), model.predict(s, a))
    more = _pendulum_data(2)
    model.fit(*more)
    for other in copies:  # each is its own model: fitting one leaves the others alone
        assert not np.array_equal(other.predict(s, a), model.predict(s, a))
        other.fit(*more)
        assert np.array_equal(other.predict(s, a), model.predict(s, a))
    with pytest.raises(cmbrl.Error, match="settings.json"):
        cmbrl.Ensemble.load(tmp_path / "nothing")


def test_a_classifier_saved_loaded_or_pickled_predicts_the_same(tmp_path):
    import pickle

    rng = np.random.default_rng(0)
    states = rng.uniform(-1, 1, size=(800, 3))
    unsafe = states[:, 0] > 0.3
    model = cmbrl.CostClassifier(state_dim=3, rounds=10, seed=2)
    model.fit(states, unsafe)
    model.save(tmp_path / "saved")
    for other in (cmbrl.CostClassifier.load(tmp_path / "saved"), pickle.loads(pickle.dumps(model))):
        assert np.array_equal(other.predict(states), model.predict(states))
    ensemble_dir = tmp_path / "ensemble"
    cmbrl.Ensemble(state_dim=3, action_dim=1, hidden_sizes=[4]).save(ensemble_dir)
    with pytest.raises(cmbrl.Error, match="not a saved CostClassifier: its kind is 'ensemble'"):
        cmbrl.CostClassifier.load(ensemble_dir)


def test_live_objects_refuse_copies_and_pickles_by_name():
    import copy
    import pickle

    vec = cmbrl.make_vec("PointGoal1", num_envs=2)
    for obj, instead in ((vec, r"cmbrl\.make_vec"),):
        name = type(obj).__name__
        for attempt, what in ((copy.copy, "copied"), (copy.deepcopy, "copied"),
                              (pickle.dumps, "pickled")):
            with pytest.raises(cmbrl.Error, match=rf"a cmbrl\.{name} cannot be {what}.*{instead}"):
                attempt(obj)


def test_ctrl_c_stops_a_fit_after_its_epoch_and_keeps_what_was_learned():
    import os
    import signal
    import threading

    # A fit of many seconds (its early stop comes after about 1400 epochs of 20,000 rows).
    states, actions, next_states = _pendulum_data(0, 20000)
    model = cmbrl.Ensemble(state_dim=4, action_dim=2, ensemble_size=2, hidden_sizes=[32],
                           max_epochs=100000, seed=1)
    with pytest.raises(cmbrl.Error, match="Ensemble.predict before fit"):
        model.predict(states[:20], actions[:20])  # untrained networks are not an answer
    # What one epoch learns, from an identical model: the interrupted fit must keep more.
    one_epoch = cmbrl.Ensemble(state_dim=4, action_dim=2, ensemble_size=2, hidden_sizes=[32],
                               max_epochs=1, seed=1)
    one_epoch.fit(states, actions, next_states)
    untrained = one_epoch.predict(states[:20], actions[:20])
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        model.fit(states, actions, next_states)
    timer.join()
    assert model.transitions == 20000
    trained = model.predict(states[:20], actions[:20])
    assert not np.array_equal(trained, untrained)  # the epochs done are kept
    assert np.mean((trained - next_states[:20]) ** 2) < np.mean((untrained - next_states[:20]) ** 2)


def test_ctrl_c_abandons_a_classifier_fit_and_leaves_the_classifier_as_it_was(tmp_path):
    import os
    import signal
    import threading

    rng = np.random.default_rng(0)
    states = rng.uniform(-1, 1, size=(4000, 3))
    unsafe = np.linalg.norm(states[:, :2], axis=1) < 0.5
    model = cmbrl.CostClassifier(state_dim=3, rounds=20, seed=0)
    model.fit(states, unsafe)
    before = model.predict(states)
    assert (before == unsafe).mean() > 0.9
    # A fit of very many rounds on other labels, stopped after half a second.
    slow = cmbrl.CostClassifier(state_dim=3, rounds=100000, seed=0)
    model.save(tmp_path / "fast")
    slow._model.load(str(tmp_path / "fast" / "classifier.json"))  # the trees, not the settings
    assert np.array_equal(slow.predict(states), before)
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        slow.fit(states, ~unsafe)
    timer.join()
    assert np.array_equal(slow.predict(states), before)


def test_models_refuse_to_predict_before_they_are_fitted():
    with pytest.raises(cmbrl.Error, match="CostClassifier.predict before fit"):
        cmbrl.CostClassifier(state_dim=3).predict(np.zeros((2, 3)))
    with pytest.raises(cmbrl.Error, match="RewardModel.predict before fit"):
        cmbrl.RewardModel(input_dim=3).predict(np.zeros((2, 3)))
    with pytest.raises(cmbrl.Error, match="render\\(\\) before reset\\(\\)"):
        cmbrl.make("PointGoal1", render_mode="rgb_array").render()
    classifier = cmbrl.CostClassifier(state_dim=1, rounds=5)
    classifier.fit(np.array([[0.0], [1.0]] * 20), np.array([0, 1] * 20))
    assert classifier.predict(np.array([[1.0]])).tolist() == [True]
