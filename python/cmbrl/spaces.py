"""Box spaces: gymnasium.spaces.Box when gymnasium is importable, otherwise a small look-alike
with the same attributes (low, high, shape, dtype) and methods (sample, seed, contains)."""
import numpy as np

from . import _gymnasium


class _Box:
    """A box of real vectors, low <= x <= high elementwise (gymnasium.spaces.Box's look-alike)."""

    def __init__(self, low, high, dtype=np.float64):
        self.dtype = np.dtype(dtype)
        self.low = np.asarray(low, dtype=self.dtype)
        self.high = np.asarray(high, dtype=self.dtype)
        if self.low.shape != self.high.shape:
            raise ValueError(f"low has shape {self.low.shape}, high {self.high.shape}: expected one")
        self.shape = self.low.shape
        self.bounded_below, self.bounded_above = np.isfinite(self.low), np.isfinite(self.high)
        self._rng = np.random.default_rng()

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
        return f"Box({self.low.min()}, {self.high.max()}, {self.shape}, {self.dtype})"


def Box(low, high, dtype=np.float64):  # noqa: N802 (a class-like factory)
    """A box space from low to high: gymnasium.spaces.Box where gymnasium is importable, the
    look-alike otherwise."""
    if _gymnasium.Box is not None:
        return _gymnasium.Box(low=np.asarray(low, dtype=dtype),
                              high=np.asarray(high, dtype=dtype), dtype=dtype)
    return _Box(low, high, dtype)
