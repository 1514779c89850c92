"""Box spaces: gymnasium.spaces.Box when gymnasium is importable, otherwise a small look-alike
with the same attributes (low, high, shape, dtype) and methods (sample, seed, contains)."""
import numpy as np

from . import _gymnasium


class _Box:
    """A box of real vectors, low <= x <= high elementwise (gymnasium.spaces.Box's look-alike)."""

    def __init__(self, low, high, shape=None, dtype=np.float64, seed=None):
        self.dtype = np.dtype(dtype)
        if self.dtype.kind != "f":
            raise ValueError(f"dtype is {self.dtype}: expected a floating dtype (cmbrl's Box "
                             "holds real vectors)")
        shape = _box_shape(low, high, shape)
        self.low = _bound("low", low, shape, self.dtype)
        self.high = _bound("high", high, shape, self.dtype)
        self.shape = shape
        self.bounded_below, self.bounded_above = np.isfinite(self.low), np.isfinite(self.high)
        self._rng = np.random.default_rng()
        if seed is not None:
            self.seed(seed)

    def seed(self, seed=None):
        """Seeds the space's own generator (sample()) and returns the seed it used, drawn from
        the operating system's entropy when seed is None, as gymnasium's Space.seed does."""
        if seed is None:
            seed = int(np.random.SeedSequence().entropy)
        self._rng = np.random.default_rng(seed)
        return seed

    @property
    def np_random(self):
        """The generator sample() draws from (gymnasium's Space.np_random)."""
        return self._rng

    def is_bounded(self, manner="both"):
        """Whether every entry is bounded: manner 'both', 'below' or 'above' (gymnasium's)."""
        below, above = bool(np.all(self.bounded_below)), bool(np.all(self.bounded_above))
        if manner == "both":
            return below and above
        if manner == "below":
            return below
        if manner == "above":
            return above
        raise ValueError(f"manner is {manner!r}: expected 'both', 'below' or 'above'")

    @property
    def is_np_flattenable(self):
        return True

    def sample(self, mask=None, probability=None):
        """Uniform where bounded on both sides, normal where unbounded, as gymnasium does (which
        takes no mask or probability for a Box either)."""
        if mask is not None or probability is not None:
            raise ValueError("a Box samples without a mask or probability: expected None")
        low, high = self.low, self.high
        bounded = np.isfinite(low) & np.isfinite(high)
        out = self._rng.normal(size=self.shape)
        lo_only = np.isfinite(low) & ~np.isfinite(high)
        hi_only = ~np.isfinite(low) & np.isfinite(high)
        out[lo_only] = low[lo_only] + self._rng.exponential(size=self.shape)[lo_only]
        out[hi_only] = high[hi_only] - self._rng.exponential(size=self.shape)[hi_only]
        out[bounded] = self._rng.uniform(low[bounded], high[bounded])
        return out.astype(self.dtype)

    def contains(self, x):
        """Whether x is an array of this shape, of a dtype that casts to the space's without
        loss, within the bounds (gymnasium's rule: a float64 point is not in a float32 box)."""
        if not isinstance(x, np.ndarray):
            try:
                x = np.asarray(x, dtype=self.dtype)
            except (ValueError, TypeError):
                return False
        return bool(np.can_cast(x.dtype, self.dtype) and x.shape == self.shape
                    and np.all(x >= self.low) and np.all(x <= self.high))

    __contains__ = contains

    def __eq__(self, other):
        return (isinstance(other, _Box) and self.shape == other.shape
                and self.dtype == other.dtype and np.array_equal(self.low, other.low)
                and np.array_equal(self.high, other.high))

    __hash__ = None  # mutable arrays inside, as gymnasium's

    def __repr__(self):
        return f"Box({_short(self.low)}, {_short(self.high)}, {self.shape}, {self.dtype})"


def _box_shape(low, high, shape):
    """The box's shape by gymnasium's rule: `shape` when given, else that of the array bound(s);
    two scalars make a box of shape (1,)."""
    if shape is not None:
        try:
            dims = tuple(shape)
        except TypeError:
            raise TypeError(f"shape is {shape!r}: expected a sequence of integers") from None
        if not all(isinstance(d, (int, np.integer)) and not isinstance(d, bool) and d >= 0
                   for d in dims):
            raise TypeError(f"shape is {shape!r}: expected a sequence of integers >= 0")
        return tuple(int(d) for d in dims)
    low_shape, high_shape = np.shape(low), np.shape(high)
    if low_shape and high_shape and low_shape != high_shape:
        raise ValueError(f"low has shape {low_shape}, high {high_shape}: expected one shape")
    return low_shape or high_shape or (1,)


def _bound(name, value, shape, dtype):
    """A bound as an array of the box's shape: a scalar is repeated, an array must fit."""
    array = np.asarray(value, dtype=dtype)
    if np.isnan(array).any():
        raise ValueError(f"{name} holds NaN: expected numbers or +-inf")
    if array.ndim == 0:
        return np.full(shape, array, dtype=dtype)
    if array.shape != shape:
        raise ValueError(f"{name} has shape {array.shape}: expected {shape}, the box's shape")
    return array.copy()


def _gymnasium_bound(value, dtype):
    """A bound as gymnasium's Box takes it: a scalar stays one (it is repeated over the shape),
    anything else becomes an array."""
    return float(value) if np.ndim(value) == 0 else np.asarray(value, dtype=dtype)


def _short(bound):
    """One number when every entry is equal, else the array (gymnasium's Box repr)."""
    return str(bound.flat[0]) if bound.size and np.all(bound == bound.flat[0]) else str(bound)


def Box(low, high, shape=None, dtype=np.float64, seed=None):  # noqa: N802 (class-like)
    """A box space from low to high: gymnasium.spaces.Box where gymnasium is importable, the
    look-alike otherwise. gymnasium's arguments: a scalar bound is repeated over `shape`; the
    shape is otherwise the bounds' (two scalars: (1,)); `seed` seeds sample(). The default dtype
    is float64 (gymnasium's is float32)."""
    if _gymnasium.Box is not None:
        given = {k: v for k, v in (("shape", shape), ("seed", seed)) if v is not None}
        return _gymnasium.Box(low=_gymnasium_bound(low, dtype), high=_gymnasium_bound(high, dtype),
                              dtype=dtype, **given)
    return _Box(low, high, shape=shape, dtype=dtype, seed=seed)
