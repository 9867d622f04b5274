r"""Zero-mean densities and samplers of *Probabilistic Robotics*, Table 5.2.

Holds the zero-mean densities and samplers of Table 5.2.
Does not hold motion or measurement models (:mod:`probrob.motion`, :mod:`probrob.sensors`).

Every function takes the **variance** :math:`b^2` (not the standard deviation), as the
book's tables do. The samplers are the book's: the normal one sums twelve uniforms
(an Irwin–Hall approximation, exact in mean and variance, bounded at :math:`\pm 6b`);
``method="exact"`` swaps in numpy's exact normal generator, which is also faster.

A variance of zero is legal (a robot at rest has no motion noise): it is a point mass at
0, so the density is ``0`` (log: ``-inf``) off its support, ``a != 0``, and ``inf`` (log:
``+inf``, a Dirac delta) on it, ``a == 0``; the samplers return zeros there. Never NaN.

Every density takes ``log=True`` and then returns the natural log of the density, computed
in log space: a variance as small as ``1e-320`` (whose density at 0 is about ``4e159``) or
an argument far in the tail gives the exact value, ``-inf`` off the support, and never an
overflow. The linear density is ``exp`` of the log density.
"""

from __future__ import annotations

import functools
import inspect

import numpy as np

from . import _validation as check

__all__ = [
    "prob_normal_distribution",
    "prob_triangular_distribution",
    "sample_normal_distribution",
    "sample_triangular_distribution",
]

_SQRT6 = np.sqrt(6.0)
_HALF_LOG_2PI = 0.5 * np.log(2.0 * np.pi)


def _log_normal_kernel(a, b2):
    """``log N(a; 0, b2)`` for arrays with ``b2 > 0`` (unchecked): ``-(a/b)²/2 - log b - ½log 2π``.

    Written with ``a / b`` rather than ``a² / b2``, so that nothing overflows before it must
    (``(a/b)²`` overflowing means the log density is ``-inf``, which is then exact).
    """
    b = np.sqrt(b2)
    with np.errstate(over="ignore"):
        z = np.divide(a, b)
        z = np.square(z, out=z) if isinstance(z, np.ndarray) else np.square(z)
    z *= -0.5
    z -= np.log(b) + _HALF_LOG_2PI
    return z


def _log_triangular_kernel(a, b2):
    """Log of ``max(0, 1/(√6 b) - |a|/(6 b²)) = (1 - |a|/(√6 b)) / (√6 b)`` for ``b2 > 0``."""
    width = _SQRT6 * np.sqrt(b2)  # half-width of the triangle
    with np.errstate(over="ignore"):
        t = np.divide(np.abs(a), width)
    t = np.minimum(t, 1.0)
    with np.errstate(divide="ignore"):
        out = np.log1p(-t)  # -inf at and beyond the edge
    out -= np.log(width)
    return out


def _point_mass_log(a):
    """Log density of the point mass at 0: ``+inf`` at ``a == 0``, ``-inf`` elsewhere."""
    return np.where(a == 0, np.inf, -np.inf)


def _log_density(a, b2, kernel):
    """``kernel`` where ``b2 > 0``, the point mass where ``b2 == 0`` (checked arrays)."""
    if b2.ndim == 0:  # the common case: one variance for many points
        return kernel(a, b2) if b2 > 0 else _point_mass_log(a)
    positive = b2 > 0
    if positive.all():
        return kernel(a, b2)
    values = kernel(a, np.where(positive, b2, 1.0))
    return np.where(positive, values, _point_mass_log(a))


def _zero_mean_density(a, b2, kernel, log):
    """Check the inputs, evaluate the log density, return it or its ``exp``."""
    a = check.finite(a, "a")
    b2 = check.variance(b2, "b2")
    check.batch_shape(a=a.shape, b2=b2.shape)
    check.flag(log, "log")
    out = _log_density(a, b2, kernel)
    if not log:
        with np.errstate(over="ignore"):  # (cannot overflow: the peak is at most 2e161)
            out = np.exp(out)
    return check.scalar_or_array(out)


def prob_normal_distribution(a, b2, *, log=False):
    r"""Return the zero-mean normal density :math:`\mathcal N(a; 0, b^2)`.

    *Probabilistic Robotics*, Table 5.2, line 2:

    .. math:: \varepsilon_{b^2}(a) = \frac{1}{\sqrt{2\pi b^2}}
              \exp\left(-\frac{1}{2}\frac{a^2}{b^2}\right)

    Parameters
    ----------
    a : array_like
        Points at which to evaluate the density.
    b2 : array_like, broadcastable with ``a``
        Variance :math:`b^2 \ge 0`.
    log : bool, optional
        Return :math:`\log p` instead, computed in log space.

    Returns
    -------
    p : float or ndarray, broadcast shape of ``a`` and ``b2``
        Density values (or their logs). Where ``b2 == 0``, a point mass at 0: ``inf``
        at ``a == 0`` and ``0`` elsewhere (log: ``+inf`` and ``-inf``).
    """
    return _zero_mean_density(a, b2, _log_normal_kernel, log)


def prob_triangular_distribution(a, b2, *, log=False):
    r"""Return the zero-mean triangular density with variance :math:`b^2`.

    *Probabilistic Robotics*, Table 5.2, line 4:

    .. math:: \max\left\{0,\ \frac{1}{\sqrt6\,b} - \frac{|a|}{6b^2}\right\}
              = \frac{1}{\sqrt6\,b}\max\left\{0,\ 1 - \frac{|a|}{\sqrt6\,b}\right\}

    The triangle has half-width :math:`\sqrt6\,b` and peak :math:`1/(\sqrt6\,b)`, so
    it integrates to one and has variance :math:`b^2`. It is evaluated in the second
    form, which neither overflows for tiny :math:`b^2` nor cancels near the edges.

    Parameters
    ----------
    a : array_like
        Points at which to evaluate the density.
    b2 : array_like, broadcastable with ``a``
        Variance :math:`b^2 \ge 0`.
    log : bool, optional
        Return :math:`\log p` instead (``-inf`` outside the triangle).

    Returns
    -------
    p : float or ndarray, broadcast shape of ``a`` and ``b2``
        Density values (or their logs). Where ``b2 == 0``, a point mass at 0: ``inf``
        at ``a == 0`` and ``0`` elsewhere (log: ``+inf`` and ``-inf``).
    """
    return _zero_mean_density(a, b2, _log_triangular_kernel, log)


# The library's own densities, by their unchecked log kernels: the motion models call these
# directly on inputs they have already checked (a user's ``prob`` goes through _log_prob).
_LOG_KERNELS = {
    prob_normal_distribution: _log_normal_kernel,
    prob_triangular_distribution: _log_triangular_kernel,
}


def _accepts_log(func) -> bool:
    try:
        parameters = inspect.signature(func).parameters.values()
    except (TypeError, ValueError):  # builtins without a signature
        return False
    return any(
        (p.name == "log" and p.kind is not p.POSITIONAL_ONLY) or p.kind is p.VAR_KEYWORD
        for p in parameters
    )


def _log_prob(prob, name: str = "prob"):
    """``(log_density(a, b2), exact)`` for a ``prob(a, b2)`` callable.

    ``log_density`` takes checked float arrays (``b2 >= 0``, finite) and returns the log
    density. The library's densities map to their kernels (with the point mass for
    ``b2 == 0``); a user's callable is called as ``prob(a, b2, log=True)`` if it takes
    ``log``, else as ``log(prob(a, b2))``; its result must be real, not NaN and (linear) not
    negative, and is never modified. ``exact`` is True for the library's own kernels, whose
    only ``+inf`` is the point mass.
    """
    kernel = _LOG_KERNELS.get(prob)
    if kernel is not None:
        return functools.partial(_log_density, kernel=kernel), True
    takes_log = _accepts_log(prob)

    def call(a, b2):
        shape = np.broadcast_shapes(np.shape(a), np.shape(b2))
        if takes_log:
            return check.callable_result(prob(a, b2, log=True), name, shape, prob)
        p = check.callable_result(prob(a, b2), name, shape, prob)
        if np.any(p < 0):
            raise ValueError(f"{name} returned a negative density")
        with np.errstate(divide="ignore"):
            return np.log(p)

    return call, False


_BLOCK = 1 << 14  # columns of uniforms per block: 12 × 16384 doubles = 1.5 MB, cache-sized


def _irwin_hall_12(rng: np.random.Generator, shape: tuple[int, ...]) -> np.ndarray:
    """Σ of twelve U(0, 1), minus 6, of the given shape: ½ Σ rand(-1, 1) (Table 5.4).

    Drawn block by block into one reused buffer, which avoids a temporary of twelve
    times the output's size (96 MB for a million samples) and is faster.
    """
    n = int(np.prod(shape))
    out = np.empty(n)
    buffer = np.empty(12 * min(n, _BLOCK))
    for start in range(0, n, _BLOCK):
        m = min(n - start, _BLOCK)
        uniforms = buffer[: 12 * m].reshape(12, m)
        rng.random(out=uniforms)
        np.sum(uniforms, axis=0, out=out[start : start + m])
    out -= 6.0
    return out.reshape(shape)


def _std_and_shape(b2, size) -> tuple[np.ndarray, tuple[int, ...]]:
    b = np.sqrt(check.variance(b2, "b2"))
    return b, check.output_shape(b.shape, size)


def sample_normal_distribution(b2, size=None, rng=None, *, method="sum12"):
    r"""Draw zero-mean samples that approximate :math:`\mathcal N(0, b^2)`.

    *Probabilistic Robotics*, Table 5.4, line 2 (the book's sampler for Table 5.2):

    .. math:: \frac12 \sum_{i=1}^{12} \mathrm{rand}(-b, b)

    Each uniform on :math:`(-b, b)` has variance :math:`b^2/3`, so the sum of twelve,
    halved, has variance :math:`\tfrac14 \cdot 12 \cdot b^2/3 = b^2`. The deck ``000``
    omits the upper limit 12 of the sum (see the errata page).

    Parameters
    ----------
    b2 : array_like
        Variance :math:`b^2 \ge 0` (broadcast to ``size``).
    size : int or tuple of ints, optional
        Output shape; default the shape of ``b2``.
    rng : None, int, numpy.random.SeedSequence or numpy.random.Generator, optional
        Source of randomness: ``None`` (fresh entropy), a non-negative seed, a seed
        sequence, or a generator (used as is, continuing its stream).
    method : {"sum12", "exact"}, optional
        ``"sum12"`` (default) is the book's sum of twelve uniforms, whose tails are
        cut at :math:`\pm 6b`; ``"exact"`` uses :meth:`numpy.random.Generator.normal`.

    Returns
    -------
    samples : float or ndarray of shape ``size``
    """
    check.choice(method, "method", ("sum12", "exact"))
    b, shape = _std_and_shape(b2, size)
    rng = check.rng(rng)
    if method == "exact":
        z = rng.standard_normal(shape)
    else:
        z = _irwin_hall_12(rng, shape)
    return check.scalar_or_array(b * z)


def sample_triangular_distribution(b2, size=None, rng=None):
    r"""Draw zero-mean samples from the triangular distribution with variance :math:`b^2`.

    *Probabilistic Robotics*, Table 5.4, line 4:

    .. math:: \frac{\sqrt6}{2}\,\left[\mathrm{rand}(-b, b) + \mathrm{rand}(-b, b)\right]

    The sum of two uniforms is exactly triangular on :math:`(-2b, 2b)` with variance
    :math:`2b^2/3`; the factor :math:`\sqrt6/2` stretches it to half-width
    :math:`\sqrt6\,b` and variance :math:`b^2`, the density of
    :func:`prob_triangular_distribution`.

    Parameters
    ----------
    b2 : array_like
        Variance :math:`b^2 \ge 0` (broadcast to ``size``).
    size : int or tuple of ints, optional
        Output shape; default the shape of ``b2``.
    rng : None, int, numpy.random.SeedSequence or numpy.random.Generator, optional
        Source of randomness: ``None`` (fresh entropy), a non-negative seed, a seed
        sequence, or a generator (used as is, continuing its stream).

    Returns
    -------
    samples : float or ndarray of shape ``size``
    """
    b, shape = _std_and_shape(b2, size)
    rng = check.rng(rng)
    # √6/2 · (rand(-b, b) + rand(-b, b)) = √6 · b · (U1 + U2 − 1).
    u = rng.random((2, *shape))
    return check.scalar_or_array(_SQRT6 * b * (u[0] + u[1] - 1.0))


def _sample_exact_normal(b2, size=None, rng=None):
    """``sample_normal_distribution(b2, size, rng, method="exact")`` as a ``sample`` callable.

    The one exact-normal sampler of the library (the simulator's motion noise, the plots'
    "normal (exact)" choice).
    """
    return sample_normal_distribution(b2, size=size, rng=rng, method="exact")


# Samplers whose result is a fresh array the motion models may scale in place.
_FRESH_SAMPLERS = (
    sample_normal_distribution,
    sample_triangular_distribution,
    _sample_exact_normal,
)


def _returns_fresh(sample) -> bool:
    """Whether ``sample`` is one of the library's samplers (or a partial of one)."""
    while isinstance(sample, functools.partial):
        sample = sample.func
    return sample in _FRESH_SAMPLERS
