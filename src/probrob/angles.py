r"""Angles: wrapping, differences and circular means.

Every angular difference in probrob (an innovation, a heading change, an odometry
rotation) goes through this module, so that :math:`\theta = \pi - 0.01` and
:math:`\theta = -\pi + 0.01` are 0.02 rad apart, not :math:`2\pi - 0.02`.

All functions preserve the shape of their input and return a Python ``float`` for a
scalar input.
"""

from __future__ import annotations

import numpy as np

from ._validation import scalar_or_array

__all__ = ["angle_diff", "circular_mean", "wrap_angle"]

_TWO_PI = 2.0 * np.pi


def wrap_angle(theta):
    r"""Return ``theta`` wrapped to the half-open interval :math:`[-\pi, \pi)`.

    Parameters
    ----------
    theta : array_like, any shape
        Angles in radians.

    Returns
    -------
    wrapped : float or ndarray, same shape as ``theta``
        ``theta + 2πk`` for the integer ``k`` that puts it in ``[-π, π)``.
        ``π`` itself maps to ``-π``.
    """
    theta = np.asarray(theta, dtype=float)
    # θ - 2π·round(θ / 2π) is θ itself for |θ| < π (no rounding error in range) and
    # lands in [-π, π]; the closed end π is then moved to -π.
    turns = np.round(theta * (1.0 / _TWO_PI))
    turns *= _TWO_PI
    wrapped = np.atleast_1d(np.subtract(theta, turns))
    wrapped[wrapped >= np.pi] -= _TWO_PI
    wrapped = wrapped.reshape(theta.shape)
    return scalar_or_array(wrapped)


def angle_diff(a, b):
    r"""Return the wrapped difference :math:`a - b` in :math:`[-\pi, \pi)`.

    Parameters
    ----------
    a, b : array_like, broadcastable
        Angles in radians.

    Returns
    -------
    diff : float or ndarray, broadcast shape of ``a`` and ``b``
        The signed rotation that takes ``b`` to ``a`` by the shorter way.
    """
    return wrap_angle(np.subtract(np.asarray(a, dtype=float), np.asarray(b, dtype=float)))


def circular_mean(theta, weights=None, axis=None):
    r"""Return the (weighted) circular mean of angles, in :math:`[-\pi, \pi)`.

    The mean of the unit vectors :math:`(\cos\theta_i, \sin\theta_i)`, turned back
    into an angle. Used for the mean heading of particle sets and sigma points,
    where an arithmetic mean of :math:`\pi - \epsilon` and :math:`-\pi + \epsilon`
    would point the wrong way.

    Parameters
    ----------
    theta : array_like
        Angles in radians.
    weights : array_like, optional
        Non-negative weights, broadcastable to ``theta``; default equal weights.
    axis : int, optional
        Axis to average over; default all.

    Returns
    -------
    mean : float or ndarray
        ``theta`` reduced over ``axis``. When the resultant vector is exactly zero
        (e.g. two opposite angles) the mean is undefined and 0 is returned, which
        is ``atan2(0, 0)``.
    """
    theta = np.asarray(theta, dtype=float)
    if weights is None:
        weights = np.ones_like(theta)
    else:
        weights = np.broadcast_to(np.asarray(weights, dtype=float), theta.shape)
        if np.any(weights < 0) or not np.all(np.isfinite(weights)):
            raise ValueError("weights must be finite and non-negative")
    s = np.sum(weights * np.sin(theta), axis=axis)
    c = np.sum(weights * np.cos(theta), axis=axis)
    return wrap_angle(np.arctan2(s, c))
