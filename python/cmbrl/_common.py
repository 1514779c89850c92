"""What the modules of cmbrl share: its error, argument checks that name the bad value, and the
copying and closing rules of the objects that hold a C++ object."""
import copy
import math
import os

import numpy as np

from . import _cmbrl
from .spaces import Box

Error = _cmbrl.Error


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
        return False  # an exception raised inside `with` goes on (gymnasium's Env: the same)


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


def _as_path(value, what):
    """value (a str or os.PathLike) as a str; anything else refused with cmbrl.Error naming the
    argument (where os.fspath's TypeError would not)."""
    if isinstance(value, (str, os.PathLike)):
        path = os.fspath(value)
        if isinstance(path, str):
            return path
    raise Error(f"{what} is {value!r}: expected a path (a str or os.PathLike)")


def _as_str(value, what, expected="a str"):
    """value if it is a str; anything else refused with cmbrl.Error naming the argument."""
    if not isinstance(value, str):
        raise Error(f"{what} is {value!r}: expected {expected}")
    return value


def _as_flag(value, what):
    """value if it is a bool (numpy's too); 1, "yes" and the like refused by name."""
    if not isinstance(value, (bool, np.bool_)):
        raise Error(f"{what} is {value!r}: expected True or False")
    return bool(value)


def _as_number(value, what, low=-math.inf, high=math.inf):
    """value as a finite float from low to high; bools, strings and NaN refused by name."""
    if (isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer,
                                                                     np.floating))
            or not math.isfinite(value) or not low <= value <= high):
        raise Error(f"{what} is {value!r}: expected a finite number from {low} to {high}")
    return float(value)


def _as_sizes(value, what):
    """A list or tuple of layer widths as ints, each from 1 to 2**31 - 1; a str ("64") or a
    number refused as a whole, by name."""
    if not isinstance(value, (list, tuple)):
        raise Error(f"{what} is {value!r}: expected a list of integers")
    return [_as_int(size, f"{what}[{i}]") for i, size in enumerate(value)]


def _as_overrides(overrides, what="overrides"):
    """overrides as "section.key=value" strings: from None, a dict {"section.key": value} or a
    list of such strings; anything else refused by name."""
    if overrides is None:
        return []
    if isinstance(overrides, dict):
        return [f"{_as_str(key, f'{what} key', 'a str section.key')}={_yaml_value(value)}"
                for key, value in overrides.items()]
    if not isinstance(overrides, (list, tuple)):
        raise Error(f"{what} is {overrides!r}: expected a dict {{'section.key': value}} or a "
                    "list of 'section.key=value' strings")
    return [_as_str(item, f"{what}[{i}]", "a 'section.key=value' str")
            for i, item in enumerate(overrides)]


def _as_seed(seed, what="seed"):
    """seed as an int from 0 to 2**64 - 1; refuses floats, bools and anything else by name."""
    return _as_int(seed, what, 0, 2**64 - 1)



def _yaml_value(value):
    """A Python value as YAML flow text (bools lower-case, lists in brackets)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_yaml_value(v) for v in value) + "]"
    return repr(value) if isinstance(value, float) else str(value)
