r"""Zero-mean densities and samplers of *Probabilistic Robotics*, Table 5.2.

Every function takes the **variance** :math:`b^2` (not the standard deviation), as the
book's tables do. The samplers are the book's: the normal one sums twelve uniforms
(an Irwin–Hall approximation, exact in mean and variance, bounded at :math:`\pm 6b`);
``method="exact"`` swaps in numpy's exact normal generator, which is also faster.

A variance of zero is legal (a robot at rest has no motion noise): the densities
then return the limit of a point mass (``inf`` at ``a == 0``, ``0`` elsewhere) and the
samplers return zeros.
"""

from __future__ import annotations

import numpy as np

from ._validation import choice, finite, output_shape, scalar_or_array, variance

__all__ = [
    "prob_normal_distribution",
    "prob_triangular_distribution",
    "sample_normal_distribution",
    "sample_triangular_distribution",
]

_SQRT6 = np.sqrt(6.0)


def _zero_mean_density(a, b2, formula):
    """Check the inputs and evaluate ``formula(a, b2)`` where ``b2 > 0``.

    Where ``b2 == 0`` the density is the limit of a point mass: ``inf`` at ``a == 0``,
    ``0`` elsewhere. A single positive variance (the common case: one variance for many
    points) skips the masking.
    """
    a = finite(a, "a")
    b2 = variance(b2, "b2")
    if b2.ndim == 0 and b2 > 0:
        return scalar_or_array(formula(a, b2))
    positive = b2 > 0
    p = formula(a, np.where(positive, b2, 1.0))
    return scalar_or_array(np.where(positive, p, np.where(a == 0, np.inf, 0.0)))


def _normal(a, b2):
    return np.exp(np.square(a) * (-0.5 / b2)) / np.sqrt(2.0 * np.pi * b2)


def _triangular(a, b2):
    return np.maximum(1.0 / (_SQRT6 * np.sqrt(b2)) - np.abs(a) * (1.0 / (6.0 * b2)), 0.0)


def prob_normal_distribution(a, b2):
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

    Returns
    -------
    p : float or ndarray, broadcast shape of ``a`` and ``b2``
        Density values. Where ``b2 == 0`` the limit of a point mass.
    """
    return _zero_mean_density(a, b2, _normal)


def prob_triangular_distribution(a, b2):
    r"""Return the zero-mean triangular density with variance :math:`b^2`.

    *Probabilistic Robotics*, Table 5.2, line 4:

    .. math:: \max\left\{0,\ \frac{1}{\sqrt6\,b} - \frac{|a|}{6b^2}\right\}

    The triangle has half-width :math:`\sqrt6\,b` and peak :math:`1/(\sqrt6\,b)`, so
    it integrates to one and has variance :math:`b^2`.

    Parameters
    ----------
    a : array_like
        Points at which to evaluate the density.
    b2 : array_like, broadcastable with ``a``
        Variance :math:`b^2 \ge 0`.

    Returns
    -------
    p : float or ndarray, broadcast shape of ``a`` and ``b2``
        Density values. Where ``b2 == 0`` the limit of a point mass.
    """
    return _zero_mean_density(a, b2, _triangular)


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
    b = np.sqrt(variance(b2, "b2"))
    return b, output_shape(b.shape, size)


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
    rng : None, int or numpy.random.Generator, optional
        Source of randomness, normalised with :func:`numpy.random.default_rng`.
    method : {"sum12", "exact"}, optional
        ``"sum12"`` (default) is the book's sum of twelve uniforms, whose tails are
        cut at :math:`\pm 6b`; ``"exact"`` uses :meth:`numpy.random.Generator.normal`.

    Returns
    -------
    samples : float or ndarray of shape ``size``
    """
    choice(method, "method", ("sum12", "exact"))
    b, shape = _std_and_shape(b2, size)
    rng = np.random.default_rng(rng)
    if method == "exact":
        z = rng.standard_normal(shape)
    else:
        z = _irwin_hall_12(rng, shape)
    return scalar_or_array(b * z)


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
    rng : None, int or numpy.random.Generator, optional
        Source of randomness, normalised with :func:`numpy.random.default_rng`.

    Returns
    -------
    samples : float or ndarray of shape ``size``
    """
    b, shape = _std_and_shape(b2, size)
    rng = np.random.default_rng(rng)
    # √6/2 · (rand(-b, b) + rand(-b, b)) = √6 · b · (U1 + U2 − 1).
    u = rng.random((2, *shape))
    return scalar_or_array(_SQRT6 * b * (u[0] + u[1] - 1.0))
