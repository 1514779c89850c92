"""Box spaces: gymnasium.spaces.Box when gymnasium is importable, otherwise a small look-alike
with the same attributes (low, high, shape, dtype) and methods (sample, seed, contains)."""
import numpy as np

try:  # gymnasium is optional
    from gymnasium.spaces import Box as _GymBox
except ImportError:  # pragma: no cover - depends on the machine
    _GymBox = None


class _Box:
    """A box of real vectors, low <= x <= high elementwise (gymnasium.spaces.Box's look-alike)."""

    def __init__(self, low, high, dtype=np.float64):
        self.dtype = np.dtype(dtype)
        self.low = np.asarray(low, dtype=self.dtype)
        self.high = np.asarray(high, dtype=self.dtype)
        if self.low.shape != self.high.shape:
            raise ValueError(f"low has shape {self.low.shape}, high {self.high.shape}: expected one")
        self.shape = self.low.shape
        self._rng = np.random.default_rng()

    def seed(self, seed=None):
        self._rng = np.random.default_rng(seed)
        return [seed]

    def sample(self):
        """Uniform where bounded on both sides, normal where unbounded, as gymnasium does."""
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
        x = np.asarray(x)
        return x.shape == self.shape and bool(np.all(x >= self.low) and np.all(x <= self.high))

    __contains__ = contains

    def __repr__(self):
        return f"Box({self.low.min()}, {self.high.max()}, {self.shape}, {self.dtype})"


def Box(low, high, dtype=np.float64):  # noqa: N802 (a class-like factory)
    """A box space from low to high: gymnasium.spaces.Box where gymnasium is importable, the
    look-alike otherwise."""
    if _GymBox is not None:
        return _GymBox(low=np.asarray(low, dtype=dtype), high=np.asarray(high, dtype=dtype),
                       dtype=dtype)
    return _Box(low, high, dtype)
