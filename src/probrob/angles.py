r"""Angles: wrapping, differences and circular means.

Holds angle wrapping, differences and circular means: every angle of the library goes here.
Does not hold poses or motion (:mod:`probrob.motion`, :mod:`probrob.kinematics`).

Every angular difference in probrob (an innovation, a heading change, an odometry
rotation) goes through this module, so that :math:`\theta = \pi - 0.01` and
:math:`\theta = -\pi + 0.01` are 0.02 rad apart, not :math:`2\pi - 0.02`.

All functions preserve the shape of their input and return a Python ``float`` for a
scalar input. They accept every finite float: the wrap is an exact floating-point
remainder by :math:`2\pi` (the double nearest to it), so the result lies in
:math:`[-\pi, \pi)` however large the input, and an angle already in that range is
returned unchanged, bit for bit. NaN and :math:`\pm\infty` have no direction and raise
``ValueError``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from . import _validation as check

__all__ = ["angle_diff", "circular_mean", "wrap_angle"]

_TWO_PI = 2.0 * np.pi


# Below this magnitude the fast wrap θ - 2π·round(θ / 2π) is exact: 2π has a 50-bit
# mantissa, so k·2π is exact for |k| <= 7, and θ - k·2π is exact by Sterbenz's lemma (both
# within a factor of two). Larger angles take the (slower) exact remainder ``fmod``.
_FAST_LIMIT = 40.0


@njit(cache=True, error_model="numpy")
def _wrap_one(theta: float) -> float:
    """:func:`_wrap` of one float, compiled (no fast-math: each operation rounds as in IEEE
    double precision, so this is the Python float path's algorithm to the last bit)."""
    if -_FAST_LIMIT < theta < _FAST_LIMIT:
        r = theta - np.rint(theta * (1.0 / _TWO_PI)) * _TWO_PI  # rint: half to even
    elif np.isinf(theta):  # no direction
        return np.nan
    else:
        r = np.fmod(theta, _TWO_PI)  # exact, in (-2π, 2π), sign of θ
    if r >= np.pi:  # exact (Sterbenz)
        r -= _TWO_PI
    if r < -np.pi:  # round() one turn too far (θ / 2π just below k + ½)
        r += _TWO_PI
    return r


@njit(cache=True, error_model="numpy")
def _wrap_each(theta: np.ndarray, out: np.ndarray) -> None:
    """:func:`_wrap_one` of every entry of the 1-D ``theta``, into ``out``: a first loop
    without branches for the common case (which the compiler vectorizes), then the
    others."""
    rare = False
    for i in range(theta.size):
        t = theta[i]
        r = t - np.rint(t * (1.0 / _TWO_PI)) * _TWO_PI
        r = r - _TWO_PI if r >= np.pi else r
        out[i] = r + _TWO_PI if r < -np.pi else r
        rare |= not abs(t) < _FAST_LIMIT
    if rare:
        for i in range(theta.size):
            if not abs(theta[i]) < _FAST_LIMIT:
                out[i] = _wrap_one(theta[i])


def _wrap(theta: np.ndarray) -> np.ndarray:
    """``wrap_angle`` of a finite float array, unchecked (for the library's inner loops).

    The result is the exact remainder of θ by the double ``2π`` moved into ``[-π, π)``
    (``fmod`` is exact, and moving its result by one turn is exact by Sterbenz's lemma), so
    it never leaves the range and θ in range comes back unchanged. Angles below
    ``_FAST_LIMIT`` in magnitude take a faster route to the same bits.

    One compiled loop over the entries (the filters wrap arrays of a few sigma points at a
    time, where a chain of numpy operations costs more than the arithmetic). A Python
    ``float`` (exactly that type) takes the same steps in Python's arithmetic and returns a
    ``float``, bit for bit the array result (``round`` and ``np.rint`` both round half to
    even): the filters' per-feature loops wrap one bearing at a time.
    """
    if type(theta) is float:
        if -_FAST_LIMIT < theta < _FAST_LIMIT:
            r = theta - round(theta * (1.0 / _TWO_PI)) * _TWO_PI
        elif math.isinf(theta):  # no direction (the array path gives NaN too)
            return math.nan
        else:
            r = math.fmod(theta, _TWO_PI)
        if r >= math.pi:
            r -= _TWO_PI
        if r < -math.pi:
            r += _TWO_PI
        return r
    theta = np.asarray(theta, dtype=np.float64)
    out = np.empty(theta.shape)
    _wrap_each(theta.ravel(), out.reshape(-1))
    return out


def _diff(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``angle_diff`` of finite float arrays, unchecked; exact when ``a - b`` overflows too."""
    with np.errstate(over="ignore"):
        d = np.subtract(a, b)
    if not check.all_finite(d):  # |a - b| beyond 1.8e308: reduce each first
        d = np.subtract(_wrap(np.asarray(a)), _wrap(np.asarray(b)))
    return _wrap(d)


def wrap_angle(theta):
    r"""Return ``theta`` wrapped to the half-open interval :math:`[-\pi, \pi)`.

    Parameters
    ----------
    theta : array_like, any shape
        Angles in radians, finite (any magnitude).

    Returns
    -------
    wrapped : float or ndarray, same shape as ``theta``
        ``theta - 2πk`` for the integer ``k`` that puts it in ``[-π, π)``, with ``2π``
        the float64 nearest to it and the subtraction exact. ``π`` itself maps to
        ``-π``; angles already in range are returned unchanged.

    Raises
    ------
    ValueError
        If ``theta`` is NaN, infinite or not numeric (``TypeError`` if complex).
    """
    theta = check.finite(theta, "theta")
    return check.scalar_or_array(_wrap(theta))


def angle_diff(a, b):
    r"""Return the wrapped difference :math:`a - b` in :math:`[-\pi, \pi)`.

    Parameters
    ----------
    a, b : array_like, broadcastable
        Angles in radians, finite.

    Returns
    -------
    diff : float or ndarray, broadcast shape of ``a`` and ``b``
        The signed rotation that takes ``b`` to ``a`` by the shorter way.
    """
    a = check.finite(a, "a")
    b = check.finite(b, "b")
    check.batch_shape(a=a.shape, b=b.shape)
    return check.scalar_or_array(_diff(a, b))


def circular_mean(theta, weights=None, axis=None):
    r"""Return the (weighted) circular mean of angles, in :math:`[-\pi, \pi)`.

    The mean of the unit vectors :math:`(\cos\theta_i, \sin\theta_i)`, turned back
    into an angle. Used for the mean heading of particle sets and sigma points,
    where an arithmetic mean of :math:`\pi - \epsilon` and :math:`-\pi + \epsilon`
    would point the wrong way.

    Parameters
    ----------
    theta : array_like
        Angles in radians, finite; at least one along ``axis``.
    weights : array_like, optional
        Non-negative weights, broadcastable to ``theta``; default equal weights. Along
        ``axis`` they must not all be zero.
    axis : int, optional
        Axis to average over; default all.

    Returns
    -------
    mean : float or ndarray
        ``theta`` reduced over ``axis``, the direction of the resultant
        :math:`\sum_i w_i (\cos\theta_i, \sin\theta_i)`. Two float angles are never exactly
        opposite (π is irrational): ``np.pi`` lies 1.2e-16 below a half turn, so the mean of
        0 and ``np.pi`` is their bisector, π/2, and the mean of ±``np.pi / 2`` is 0. The
        weights are scaled by their largest first, so that neither 1e308 nor 5e-324 changes
        the mean.

    Raises
    ------
    ValueError
        If there is nothing to average (``theta`` empty along ``axis``), the weights are
        negative, not finite or sum to zero, ``axis`` is not an axis of ``theta``, or the
        resultant vector is exactly zero in floating point (no direction: the mean is
        undefined).
    """
    theta = check.finite(theta, "theta")
    if axis is not None:
        if isinstance(axis, bool) or not isinstance(axis, int | np.integer):
            raise ValueError(f"axis must be None or an int, got {axis!r}")
        if not -theta.ndim <= axis < theta.ndim:
            raise ValueError(f"axis {axis} is out of range for theta of shape {theta.shape}")
    if theta.size == 0 or (axis is not None and theta.shape[axis] == 0):
        raise ValueError(f"theta must hold at least one angle to average, got shape {theta.shape}")
    if weights is None:
        weights = np.ones_like(theta)
    else:
        weights = check.finite(weights, "weights")
        try:
            weights = np.broadcast_to(weights, theta.shape)
        except ValueError:
            raise ValueError(
                f"weights of shape {weights.shape} do not broadcast to theta's shape {theta.shape}"
            ) from None
        if np.any(weights < 0):
            raise ValueError("weights must be finite and non-negative")
        top = np.max(weights, axis=axis, keepdims=True)
        if np.any(top == 0):
            raise ValueError("weights sum to zero: the mean of nothing is undefined")
        weights = weights / top  # in [0, 1], the largest 1: no overflow, no underflow to 0
    s = np.sum(weights * np.sin(theta), axis=axis)
    c = np.sum(weights * np.cos(theta), axis=axis)
    if np.any((s == 0) & (c == 0)):
        raise ValueError(
            "the weighted unit vectors of theta sum to exactly zero: their mean direction is "
            "undefined"
        )
    return check.scalar_or_array(_wrap(np.arctan2(s, c)))
