"""Shared test configuration: a derandomised hypothesis profile and grid integration."""

from __future__ import annotations

import contextlib
import os
import signal

import matplotlib
import numpy as np
import pytest
from hypothesis import settings

matplotlib.use("Agg")  # no display in CI

# Property tests must give the same verdict run after run (CI re-runs them).
settings.register_profile(
    "probrob", derandomize=True, database=None, deadline=None, max_examples=200
)
# A slower, more thorough run: PROBROB_HYPOTHESIS_PROFILE=thorough make pytest (ten times the
# examples; tests/test_api_properties.py scales its per-function counts by the same factor).
settings.register_profile("thorough", parent=settings.get_profile("probrob"), max_examples=2000)
settings.load_profile(os.environ.get("PROBROB_HYPOTHESIS_PROFILE", "probrob"))


class Grid3:
    """A regular midpoint grid over a box in (x', y', θ'), for integrating pose densities."""

    def __init__(self, lo, hi, n):
        self.lo = np.asarray(lo, float)
        self.hi = np.asarray(hi, float)
        self.n = n
        self.step = (self.hi - self.lo) / n
        axes = [self.lo[k] + (np.arange(n) + 0.5) * self.step[k] for k in range(3)]
        self.points = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)  # (n, n, n, 3)
        self.cell = float(np.prod(self.step))

    @classmethod
    def around(cls, samples, n, pad=0.15):
        """The bounding box of ``samples`` (N, 3), padded by ``pad`` of its size per side."""
        lo, hi = samples.min(axis=0), samples.max(axis=0)
        margin = pad * (hi - lo)
        return cls(lo - margin, hi + margin, n)

    def integrate(self, values):
        return float(values.sum() * self.cell)

    def bin_masses(self, values, k):
        """Masses of a coarse k×k×k partition of the box (n must be a multiple of k)."""
        m = self.n // k
        return values.reshape(k, m, k, m, k, m).sum(axis=(1, 3, 5)) * self.cell

    def bin_counts(self, samples, k):
        """Counts of ``samples`` in the same k×k×k partition, and the count outside it."""
        edges = [np.linspace(self.lo[d], self.hi[d], k + 1) for d in range(3)]
        counts, _ = np.histogramdd(samples, bins=edges)
        return counts, len(samples) - int(counts.sum())


@pytest.fixture
def grid3():
    return Grid3


def chi_square_pvalue(samples, density_values, grid, k=6, min_expected=5.0):
    """χ² goodness of fit of ``samples`` to the density tabulated on ``grid``.

    Bins are a k×k×k partition of the grid's box plus one bin for everything outside
    it; bins expected to hold fewer than ``min_expected`` samples are pooled.
    """
    from scipy import stats

    n = len(samples)
    expected = grid.bin_masses(density_values, k).ravel() * n
    observed, outside = grid.bin_counts(samples, k)
    observed = observed.ravel()
    small = expected < min_expected
    exp = np.append(expected[~small], expected[small].sum() + max(0.0, n - expected.sum()))
    obs = np.append(observed[~small], observed[small].sum() + outside)
    # Rescale the expectation to the sample size; the grid's quadrature error is far
    # below the sampling noise of the bins, so the test measures the sampler.
    exp *= n / exp.sum()
    return stats.chisquare(obs, exp).pvalue


@pytest.fixture
def sampler_for():
    """The exact sampler of each density of Table 5.2: normal -> numpy's exact normal."""
    from functools import partial

    from probrob.distributions import (
        prob_normal_distribution,
        prob_triangular_distribution,
        sample_normal_distribution,
        sample_triangular_distribution,
    )

    return {
        prob_normal_distribution: partial(sample_normal_distribution, method="exact"),
        prob_triangular_distribution: sample_triangular_distribution,
    }.__getitem__


@pytest.fixture
def chi_square():
    return chi_square_pvalue


# --------------------------------------------------------------------------- time limits
class TimeLimitExceeded(AssertionError):
    """A block given to ``time_limit`` ran longer than allowed (a loop that never ends?)."""


@contextlib.contextmanager
def _time_limit(seconds: float):
    """Fail (``TimeLimitExceeded``) instead of hanging if the block runs longer than ``seconds``.

    SIGALRM-based (POSIX, main thread): the handler raises between two Python bytecodes,
    which interrupts any loop written in Python, such as the library's vectorised traversals.
    """

    def on_alarm(signum, frame):
        raise TimeLimitExceeded(f"did not finish within {seconds} s (a loop that never ends?)")

    previous = signal.signal(signal.SIGALRM, on_alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


@pytest.fixture
def time_limit():
    """``with time_limit(seconds): ...`` fails the test if the block does not finish in time."""
    return _time_limit
