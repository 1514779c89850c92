"""The paper's learned models on numpy arrays, standalone: the dynamics ensemble (Ensemble) and
the constraint classifier (CostClassifier), with saving, loading, pickling and copying; and the
learned reward of objective.reward: learned (RewardModel)."""
import json
import os
import tempfile

import numpy as np

from . import _cmbrl
from ._common import (Error, _as_flag, _as_int, _as_number, _as_seed, _as_sizes,
                      _copy_through_state, _json_number)


class _StandaloneModel:
    """Saving, loading, pickling and copying the standalone models (Ensemble, CostClassifier):
    a folder of the constructor's arguments (settings.json) and the C++ model's own files.
    Pickles carry that folder's files as bytes; copy.copy and copy.deepcopy give an independent
    model (a shallow copy would share the C++ one)."""

    _kind = ""  # "ensemble", "classifier" or "reward_model"
    _SETTINGS = "settings.json"
    _FILES = {"classifier": "classifier.json", "reward_model": "reward_model.pt"}

    def _write_files(self, folder):
        with open(os.path.join(folder, self._SETTINGS), "w") as out:
            json.dump({"kind": self._kind, "args": self._args}, out, default=_json_number)
        if self._kind == "ensemble":
            self._model.save(folder)
        else:
            self._model.save(os.path.join(folder, self._FILES[self._kind]))

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
            model._model.load(os.path.join(os.fspath(path), cls._FILES[cls._kind]))
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
        hidden_sizes = _as_sizes(hidden_sizes, "hidden_sizes")
        self._args = {"state_dim": state_dim, "action_dim": action_dim,
                      "ensemble_size": ensemble_size, "hidden_sizes": list(hidden_sizes),
                      "max_epochs": max_epochs, "seed": seed, "predict_delta": predict_delta}
        self._model = _cmbrl.Ensemble(
            _as_int(state_dim, "state_dim"), _as_int(action_dim, "action_dim"),
            _as_int(ensemble_size, "ensemble_size"),
            hidden_sizes, _as_int(max_epochs, "max_epochs"),
            _as_flag(predict_delta, "predict_delta"), _as_seed(seed))

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
                                            _as_int(rounds, "rounds"),
                                            _as_number(threshold, "threshold", 0.0, 1.0),
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

    def fit_set(self, states, unsafe):
        """The states a run's fit would take from these labelled ones (N, S) and (N), stored in
        order in a buffer of the run's capacities (50,000 safe, 10,000 unsafe): every unsafe
        state and the newest 3 n_unsafe + 1 safe ones (facts B4). Returns (states, unsafe) of
        those rows, the safe first, as the fit orders them. The run's own rule, not a copy."""
        states = np.asarray(states)
        unsafe = np.asarray(unsafe)
        flags = unsafe.astype(np.float64) if unsafe.dtype == bool else unsafe
        rows = self._model.fit_set_rows(states, flags)
        return states[rows], unsafe[rows]

    def predict(self, states):
        """states (N, S) -> (N) bool: True where the classifier says a constraint is violated."""
        return self._model.predict(states)


class RewardModel(_StandaloneModel):
    """The learned reward of `objective.reward: learned` on numpy arrays: an MLP (ReLU,
    hidden_sizes) from a step's inputs (training feeds it state, action and next state side by
    side) to its reward, refitted from fresh weights at every fit with a held-out split and the
    epoch of least validation error kept."""

    _kind = "reward_model"

    def __init__(self, input_dim, hidden_sizes=(200, 200), max_epochs=50, seed=0):
        hidden_sizes = _as_sizes(hidden_sizes, "hidden_sizes")
        self._args = {"input_dim": input_dim, "hidden_sizes": list(hidden_sizes),
                      "max_epochs": max_epochs, "seed": seed}
        self._model = _cmbrl.RewardModel(
            _as_int(input_dim, "input_dim"),
            hidden_sizes, _as_int(max_epochs, "max_epochs"),
            _as_seed(seed))

    def fit(self, inputs, rewards):
        """inputs (N, input_dim), rewards (N) -> a dict: epochs, train and validation MSE (in
        the reward's units squared), seconds."""
        return self._model.fit(inputs, rewards)

    def predict(self, inputs):
        """inputs (N, input_dim) -> (N) rewards."""
        return self._model.predict(inputs)
