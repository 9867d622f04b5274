r"""Probabilistic motion models of *Probabilistic Robotics*, chapter 5.

Holds the motion models of Tables 5.1–5.6 and :math:`g, G, V` of Table 7.2, lines 3–6.
Does not hold the filters (:mod:`probrob.localization`) or wheel kinematics (:mod:`probrob.kinematics`).

* :func:`motion_model_velocity` — Table 5.1, the density :math:`p(x_t \mid u_t, x_{t-1})`
  of the velocity motion model;
* :func:`sample_motion_model_velocity` — Table 5.3, its sampler;
* :func:`motion_model_odometry` — Table 5.5, the odometry motion model's density;
* :func:`sample_motion_model_odometry` — Table 5.6, its sampler;
* :func:`velocity_motion` — the noise-free motion :math:`g(u_t, x_{t-1})` (Table 7.2,
  line 6), exact for :math:`\omega = 0`, and :func:`velocity_motion_jacobians`, its
  Jacobians :math:`G` and :math:`V` (Table 7.2, lines 3–4);
* :func:`odometry_deltas` — :math:`(\delta_{rot1}, \delta_{trans}, \delta_{rot2})` of two
  poses (Table 5.5, lines 2–4, with wrapped angles).

Conventions (see the book's *conventions* page):

* poses are arrays of shape ``(..., 3)`` holding :math:`(x, y, \theta)`; velocity
  controls ``(..., 2)`` holding :math:`(v, \omega)`; odometry controls ``(..., 2, 3)``
  holding :math:`(\bar x_{t-1}, \bar x_t)`. Leading axes broadcast.
* ``alpha`` holds the noise parameters :math:`\alpha_1 \ldots \alpha_6` (velocity) or
  :math:`\alpha_1 \ldots \alpha_4` (odometry).
* ``noise="variance"`` (default, later printings of the book): :math:`\alpha_1 v^2 +
  \alpha_2 \omega^2` is a variance. ``noise="std"`` (first printing, Turkish deck):
  :math:`\alpha_1 |v| + \alpha_2 |\omega|` is a standard deviation.
* ``density="book"``: the tables' value, a density over the noise variables.
  ``density="pose"``: a density over :math:`(x', y', \theta')`, which integrates to one.
* ``log=True`` returns the log density, computed in log space (sums of log factors).
* Degenerate noise: a zero variance makes its factor a point mass (``prob(a, 0)`` is
  ``inf`` at ``a == 0`` and ``0`` elsewhere). A product with a ``0`` factor is ``0`` (the
  hypothesis is off the support of that point mass, whatever the other factors are);
  otherwise a product with an ``inf`` factor is ``inf`` (on the support: a Dirac delta).
  Dividing by a zero Jacobian (the robot stays in place) gives ``inf`` for a positive
  density and ``0`` for a zero one. In log space: ``-inf`` wins over ``+inf``. Never NaN.

The velocity model is written in the robot frame of :math:`x_{t-1}`. With the
displacement :math:`(a, b)` of :math:`x_t` ahead of and to the left of the robot, the
circle through both positions and tangent to the initial heading turns by
:math:`\Delta\theta = 2\arctan(b / a)` (the tangent–chord angle) and has signed radius
:math:`(a^2 + b^2) / (2b)`. This is the book's circle-centre construction (lines 2–6 of
Table 5.1) without its division by zero on straight lines, and with the sign of
:math:`\hat v` right for right turns and reversing.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numba import njit

from . import _validation as check
from .angles import _diff, _wrap
from .distributions import (
    _log_prob,
    _returns_fresh,
    prob_normal_distribution,
    sample_normal_distribution,
)

__all__ = [
    "apply_odometry_deltas",
    "motion_model_odometry",
    "motion_model_velocity",
    "odometry_deltas",
    "sample_motion_model_odometry",
    "sample_motion_model_velocity",
    "velocity_motion",
    "velocity_motion_jacobians",
]

_NOISE_FORMS = ("variance", "std")
_DENSITIES = ("book", "pose", "xy")


# --------------------------------------------------------------------------- helpers


def _unpack(arr: np.ndarray) -> tuple[np.ndarray, ...]:
    """The components along the last axis (views; numpy scalars for a 1-D array)."""
    if arr.ndim == 1:
        return tuple(arr)
    return tuple(arr[..., i] for i in range(arr.shape[-1]))


def _stack(*components) -> np.ndarray:
    return np.stack(np.broadcast_arrays(*components), axis=-1)


def _noise_variance(alpha_a, alpha_b, m_a, m_b, noise: str, alpha_c=None, m_c=None):
    """Variance of one noise term: ``α_a m_a² + α_b m_b² (+ α_c m_c²)`` or its std form."""
    if noise == "variance":
        var = alpha_a * m_a**2 + alpha_b * m_b**2
        if alpha_c is not None:
            var = var + alpha_c * m_c**2
        return var
    std = alpha_a * np.abs(m_a) + alpha_b * np.abs(m_b)
    if alpha_c is not None:
        std = std + alpha_c * np.abs(m_c)
    return std**2


def _trig(a):
    """``(cos, sin)`` for ``a``: :mod:`math`'s for a Python ``float`` (the filters' scalar
    path, where a numpy call on one number costs more than the arithmetic), numpy's else."""
    return (math.cos, math.sin) if type(a) is float else (np.cos, np.sin)


@njit(cache=True, error_model="numpy")
def _sinc_one(h: float) -> float:
    """``sin(h) / h`` of one float, exactly 1 at ``h = 0`` (compiled; ``math.sin`` is the
    C library's, as in Python, so this is Python's arithmetic to the last bit)."""
    return math.sin(h) / h if h != 0.0 else 1.0


def _sinc(h):
    """``sin(h) / h``, exactly 1 at ``h = 0`` (a ``float`` for a Python ``float``)."""
    if type(h) is float:
        return _sinc_one(h)
    h = np.asarray(h, dtype=float)
    return np.divide(np.sin(h), h, out=np.ones_like(h), where=h != 0)


@njit(cache=True, error_model="numpy")
def _arc_one(x: float, y: float, th: float, v: float, w: float, dt: float):
    """:func:`_arc` of one pose and control (floats): the chord form, compiled without
    fast-math (each operation rounds as in IEEE double precision, never fused)."""
    half = w * (0.5 * dt)
    chord = _sinc_one(half) * v * dt
    mid = th + half
    return x + chord * math.cos(mid), y + chord * math.sin(mid), mid + half


@njit(cache=True, error_model="numpy")
def _arc_each(x, y, th, v, w, dt, out):
    """:func:`_arc_one` of the 1-D ``x, y, th, v, w`` (one length N) into ``out`` (N, 3)."""
    for i in range(out.shape[0]):
        out[i, 0], out[i, 1], out[i, 2] = _arc_one(x[i], y[i], th[i], v[i], w[i], dt)


def _arc(x, y, th, v, w, dt, out=None):
    r"""Exact motion on a circle for time ``dt`` (Table 5.3 lines 5–7 without γ).

    Uses :math:`\frac{v}{\omega}[\sin(\theta + \omega\Delta t) - \sin\theta] =
    v\Delta t\,\mathrm{sinc}(\omega\Delta t / 2)\cos(\theta + \omega\Delta t / 2)`,
    which is finite and exact at :math:`\omega = 0`. ``x, y, th, v, w`` are floats or
    broadcastable arrays, ``dt`` one number. Six Python floats give a tuple of three floats;
    otherwise writes into ``out`` (a pre-allocated C-contiguous ``(..., 3)`` array) if
    given, else returns the three components (arrays of the broadcast shape).

    One compiled loop over the poses (:func:`_arc_one`): the same arithmetic for one pose
    and for a million, to the last bit, and no temporary arrays (the UKF moves a few sigma
    points a step, where a chain of numpy operations costs more than the arithmetic).
    """
    if out is None and type(x) is type(y) is type(th) is type(v) is type(w) is float:
        return _arc_one(x, y, th, v, w, float(dt))
    arrays = [np.asarray(a, dtype=np.float64) for a in (x, y, th, v, w)]
    shape = arrays[0].shape
    if len(shape) != 1 or any(a.shape != shape for a in arrays):
        shape = np.broadcast_shapes(*(a.shape for a in arrays))
        arrays = [np.broadcast_to(a, shape).ravel() for a in arrays]
    result = np.empty((*shape, 3)) if out is None else out
    if result.shape != (*shape, 3) or not result.flags.c_contiguous:
        raise ValueError(f"out must be a C-contiguous array of shape {(*shape, 3)}")
    _arc_each(*arrays, float(dt), result.reshape(-1, 3))
    return result if out is not None else (result[..., 0], result[..., 1], result[..., 2])


def _velocity_controls(alpha, u_t, noise):
    v, w = _unpack(u_t)
    a1, a2, a3, a4, a5, a6 = alpha
    with np.errstate(over="ignore", invalid="ignore"):
        variances = (
            _noise_variance(a1, a2, v, w, noise),
            _noise_variance(a3, a4, v, w, noise),
            _noise_variance(a5, a6, v, w, noise),
        )
    for k, var in enumerate(variances):
        check.no_overflow(
            var, f"the noise variance of Table 5.1 with alpha{2 * k + 1}", alpha=alpha, u_t=u_t
        )
    return (v, w, *variances)


def _log_product(logs, careful: bool):
    """Sum of log factors; where any factor is ``-inf`` (off a point mass) the sum is ``-inf``.

    ``careful=False`` promises that no factor is ``+inf`` (no zero variance, a library
    density), so no ``-inf + inf`` can arise and the mask is skipped.
    """
    with np.errstate(invalid="ignore"):
        total = np.add(logs[0], logs[1])
        for term in logs[2:]:
            total = np.add(total, term, out=total if isinstance(total, np.ndarray) else None)
    if careful:
        off = np.zeros(np.shape(total), dtype=bool)
        for term in logs:
            off |= np.asarray(term) == -np.inf
        total = np.where(off, -np.inf, total)
    return total


def _minus_log_jacobian(total, log_jac):
    """``total - log_jac``, where a zero Jacobian (``-inf``) of a zero density stays ``-inf``.

    A positive density over a zero Jacobian is ``+inf`` (all the mass of a set of noise
    values lands on one pose).
    """
    with np.errstate(invalid="ignore"):
        out = np.subtract(total, log_jac)
    if np.min(log_jac, initial=0.0) == -np.inf:
        out = np.where(np.asarray(total) == -np.inf, -np.inf, out)
    return out


def _any_zero(*variances) -> bool:
    return any(not np.all(var) for var in variances)


def _finish(total, log: bool):
    """The log density, or its ``exp`` (``inf`` beyond 1.8e308: a near point mass)."""
    if log:
        return check.scalar_or_array(total)
    with np.errstate(over="ignore"):
        return check.scalar_or_array(np.exp(total))


# --------------------------------------------------------------------------- velocity


def velocity_motion(x_prev, u_t, dt):
    r"""Return the noise-free pose after moving with velocities ``u_t`` for ``dt``.

    The function :math:`g(u_t, x_{t-1})` of *Probabilistic Robotics*, Table 7.2,
    line 6 (and Table 5.3, lines 5–7 without noise):

    .. math::
        \begin{pmatrix} x' \\ y' \\ \theta' \end{pmatrix} =
        \begin{pmatrix} x - \frac{v}{\omega}\sin\theta + \frac{v}{\omega}\sin(\theta + \omega\Delta t) \\
                        y + \frac{v}{\omega}\cos\theta - \frac{v}{\omega}\cos(\theta + \omega\Delta t) \\
                        \theta + \omega\Delta t \end{pmatrix}

    evaluated in the equivalent chord form, so that :math:`\omega = 0` gives the
    straight line :math:`(x + v\Delta t\cos\theta,\ y + v\Delta t\sin\theta,\ \theta)`
    exactly, and small :math:`\omega` loses no precision.

    Parameters
    ----------
    x_prev : array_like, shape (..., 3)
        Poses :math:`(x, y, \theta)`.
    u_t : array_like, shape (..., 2)
        Controls :math:`(v, \omega)` in m/s and rad/s.
    dt : float
        Time step :math:`\Delta t > 0` in s.

    Returns
    -------
    x_t : ndarray, shape broadcast(...) + (3,)
        Poses after the motion; :math:`\theta'` is not wrapped.
    """
    x_prev = check.poses(x_prev, "x_prev")
    u_t = check.vectors(u_t, "u_t", 2, "v, omega")
    dt = check.positive_scalar(dt, "dt")
    check.batch_shape(x_prev=x_prev.shape[:-1], u_t=u_t.shape[:-1])
    x_t = _velocity_motion_core(x_prev, u_t, dt)
    check.no_overflow(x_t, "the motion x_prev -> x_t", x_prev=x_prev, u_t=u_t, dt=dt)
    return x_t


def _velocity_motion_core(x_prev: np.ndarray, u_t: np.ndarray, dt: float) -> np.ndarray:
    """:func:`velocity_motion` on validated float arrays, unchecked (the filters' inner loops).

    Overflow gives ``inf``/``NaN`` silently; the caller checks the result.
    """
    x, y, th = _unpack(x_prev)
    v, w = _unpack(u_t)
    with np.errstate(over="ignore", invalid="ignore"):
        return _stack(*_arc(x, y, th, v, w, dt))


def _sinc_derivative(h):
    r"""``d/dh [sin(h) / h] = (h cos h - sin h) / h²``, without cancellation near 0.

    For :math:`|h| < 0.1` the Taylor series :math:`-h/3 + h^3/30 - h^5/840 + h^7/45360 -
    h^9/3991680` (next term below :math:`10^{-18}` relative); elsewhere the closed form,
    whose cancellation costs at most 2.5 digits, at :math:`|h| = 0.1` (relative error
    below :math:`5 \cdot 10^{-14}`).
    """
    if type(h) is float:
        return _sinc_derivative_series(h) if abs(h) < 0.1 else _sinc_derivative_closed(h)
    h = np.asarray(h, dtype=float)
    small = np.abs(h) < 0.1
    series = _sinc_derivative_series(h)
    closed = _sinc_derivative_closed(np.where(small, 1.0, h))
    return np.where(small, series, closed)


def _sinc_derivative_series(h):
    h2 = h * h
    return h * (-1 / 3 + h2 * (1 / 30 + h2 * (-1 / 840 + h2 * (1 / 45360 - h2 / 3991680))))


def _sinc_derivative_closed(h):
    cos, sin = _trig(h)
    return (h * cos(h) - sin(h)) / (h * h)


def velocity_motion_jacobians(x_prev, u_t, dt):
    r"""Return the Jacobians :math:`G = \partial g / \partial x_{t-1}` and :math:`V = \partial g / \partial u_t`.

    *Probabilistic Robotics*, Table 7.2, lines 3 and 4, for the noise-free motion
    :math:`g` of :func:`velocity_motion`. With :math:`h = \omega\Delta t / 2`,
    :math:`S = \sin h / h` and :math:`m = \theta + h` (the chord form of :math:`g`):

    .. math::
        G = \begin{pmatrix} 1 & 0 & -v\Delta t\, S \sin m \\
                            0 & 1 & v\Delta t\, S \cos m \\
                            0 & 0 & 1 \end{pmatrix},\qquad
        V = \begin{pmatrix} \Delta t\, S \cos m &
                              \tfrac12 v\Delta t^2 (S' \cos m - S \sin m) \\
                            \Delta t\, S \sin m &
                              \tfrac12 v\Delta t^2 (S' \sin m + S \cos m) \\
                            0 & \Delta t \end{pmatrix}.

    These equal the book's entries, e.g. :math:`-\frac{v}{\omega}\cos\theta +
    \frac{v}{\omega}\cos(\theta + \omega\Delta t)` for :math:`G_{13}`, but stay finite
    and exact at :math:`\omega = 0` (where the book's :math:`V` divides by
    :math:`\omega^2`): there :math:`S = 1`, :math:`S' = 0`.

    Parameters
    ----------
    x_prev : array_like, shape (..., 3)
        Poses :math:`(x, y, \theta)`.
    u_t : array_like, shape (..., 2)
        Controls :math:`(v, \omega)`.
    dt : float
        Time step, > 0.

    Returns
    -------
    G : ndarray, shape broadcast(...) + (3, 3)
    V : ndarray, shape broadcast(...) + (3, 2)
    """
    x_prev = check.poses(x_prev, "x_prev")
    u_t = check.vectors(u_t, "u_t", 2, "v, omega")
    dt = check.positive_scalar(dt, "dt")
    batch = check.batch_shape(x_prev=x_prev.shape[:-1], u_t=u_t.shape[:-1])
    G, V = _velocity_jacobians_core(x_prev, u_t, dt, batch)
    for name, value in (("G", G), ("V", V)):
        check.no_overflow(value, f"the Jacobian {name}", x_prev=x_prev, u_t=u_t, dt=dt)
    return G, V


def _velocity_jacobians_core(x_prev: np.ndarray, u_t: np.ndarray, dt: float, batch=None):
    """:func:`velocity_motion_jacobians` on validated float arrays, unchecked.

    ``batch`` is the broadcast batch shape (computed here if not given). Overflow gives
    ``inf``/``NaN`` silently; the caller checks the result.
    """
    if batch is None:
        batch = np.broadcast_shapes(x_prev.shape[:-1], u_t.shape[:-1])
    th = _unpack(x_prev)[2]
    v, w = _unpack(u_t)
    with np.errstate(over="ignore", invalid="ignore"):
        g02, g12, v00, v10, v01, v11 = _velocity_jacobian_entries(th, v, w, dt)
        G = np.zeros((*batch, 3, 3))
        G[..., 0, 0] = G[..., 1, 1] = G[..., 2, 2] = 1.0
        G[..., 0, 2] = g02
        G[..., 1, 2] = g12
        V = np.zeros((*batch, 3, 2))
        V[..., 0, 0] = v00
        V[..., 1, 0] = v10
        V[..., 0, 1] = v01
        V[..., 1, 1] = v11
        V[..., 2, 1] = dt
    return G, V


def _velocity_jacobian_entries(th, v, w, dt):
    r"""The entries :math:`G_{13}, G_{23}, V_{11}, V_{21}, V_{12}, V_{22}` of
    :func:`velocity_motion_jacobians` (the others are 0, 1 or :math:`\Delta t`).

    Floats or arrays, unchecked: the one place of these formulas, used by the public
    function (arrays) and by the EKF's scalar step (floats).
    """
    h = w * (0.5 * dt)
    sinc, dsinc = _sinc(h), _sinc_derivative(h)
    mid = th + h
    cos, sin = _trig(mid)
    c, s = cos(mid), sin(mid)
    return (
        -v * dt * sinc * s,
        v * dt * sinc * c,
        dt * sinc * c,
        dt * sinc * s,
        0.5 * v * (dt * dt) * (dsinc * c - sinc * s),
        0.5 * v * (dt * dt) * (dsinc * s + sinc * c),
    )


def _invert_velocity(x_t, x_prev, dt):
    r"""Recover :math:`(\hat v, \hat\omega, \hat\gamma)` that move ``x_prev`` to ``x_t``.

    Also returns the half turn :math:`\hat\omega\Delta t / 2` for the Jacobian.
    """
    x, y, th = _unpack(x_prev)
    xn, yn, thn = _unpack(x_t)
    dx, dy = np.subtract(xn, x), np.subtract(yn, y)
    c, s = np.cos(th), np.sin(th)
    # The displacement ahead of the initial heading and to its left (in place: fewer
    # temporaries make this markedly faster for a million poses).
    ahead = c * dx
    ahead += s * dy
    left = c * dy
    left -= s * dx
    # Half the turn, arctan(left / ahead) in [-π/2, π/2]: reversing (ahead < 0) is the
    # short arc backwards, not a turn of nearly 2π. atan2 needs no normalisation.
    sign = np.where(ahead < 0, -1.0, 1.0)
    half = np.arctan2(sign * left, np.abs(ahead))
    # Arc length v̂ Δt = ρ² · half / left = ρ · half / cl with ρ the distance and
    # cl = left / ρ; at cl = 0 the limit is ±ρ (straight ahead or back), and
    # |half / cl| lies in [1, π/2], so nothing overflows.
    rho = np.sqrt(np.square(ahead) + np.square(left))
    moved = rho > 0
    all_moved = bool(np.all(moved))
    if all_moved:
        cl = left / rho
    else:
        cl = np.where(moved, left / np.where(moved, rho, 1.0), 0.0)
    nonzero = cl != 0
    if np.all(nonzero):
        ratio = half / cl
    else:
        ratio = np.where(nonzero, half / np.where(nonzero, cl, 1.0), sign)
    if not all_moved:
        # Rotation in place (x', y' = x, y): every ω̂ reaches the position. Take the
        # limit of arcs with v̂ → 0, on which the whole turn is ω̂ Δt and γ̂ = 0.
        half = np.where(moved, half, 0.5 * _diff(thn, th))
        ratio = np.where(moved, ratio, 0.0)
    v_hat = rho * ratio
    v_hat /= dt
    w_hat = half * (2.0 / dt)
    turn = np.subtract(thn, th)
    if not check.all_finite(turn):  # headings 1e308 apart: reduce each first
        turn = _diff(thn, th)
    turn -= 2.0 * half
    gamma_hat = _wrap(turn) / dt
    return v_hat, w_hat, gamma_hat, half


def _velocity_log_jacobian(v_hat, half, dt, power: int = 4):
    r"""``log |det ∂(x', y', θ') / ∂(v̂, ω̂, γ̂)|`` for the velocity model.

    :math:`\Delta t \cdot |\hat v| \Delta t^3 (1 - \cos\hat\omega\Delta t) /
    (\hat\omega\Delta t)^2 = \tfrac12 |\hat v| \Delta t^4\,
    \mathrm{sinc}^2(\hat\omega\Delta t / 2)`, in log space (no overflow for any
    :math:`\Delta t`; ``-inf`` where :math:`\hat v = 0`). ``power=3`` drops one factor
    :math:`\Delta t` (the ``"xy"`` density). :math:`|\hat\omega\Delta t / 2| \le \pi/2`,
    so the sinc is at least :math:`2/\pi`.
    """
    core = np.square(_sinc(half))  # in [4/π², 1]
    core *= np.abs(v_hat)
    with np.errstate(divide="ignore"):
        out = np.log(core)
    if np.min(core, initial=1.0) == 0:  # v̂ = 0, or |v̂| sinc² below the smallest double
        with np.errstate(divide="ignore"):
            exact = np.log(np.abs(v_hat)) + 2.0 * np.log(_sinc(half))
        out = np.where(core == 0, exact, out)
    out += np.log(0.5) + power * np.log(dt)
    return out


def _check_hypotheses(x_t, density: str) -> np.ndarray:
    """Check ``x_t``: poses ``(..., 3)``, or for ``density="xy"`` also positions ``(..., 2)``."""
    if density != "xy":
        return check.poses(x_t, "x_t")
    x_t = check.finite(x_t, "x_t")
    if x_t.ndim == 0 or x_t.shape[-1] not in (2, 3):
        raise ValueError(
            f"x_t must have shape (..., 3) or, for density='xy', (..., 2); got {x_t.shape}"
        )
    return x_t


def _hypotheses(x_t, x_prev) -> np.ndarray:
    """Positions ``(..., 2)`` get the heading of ``x_prev`` (ignored by ``density="xy"``)."""
    if x_t.shape[-1] == 3:
        return x_t
    x, y = _unpack(x_t)
    return _stack(x, y, _unpack(x_prev)[2])


def motion_model_velocity(
    x_t,
    u_t,
    x_prev,
    dt,
    alpha,
    *,
    prob: Callable = prob_normal_distribution,
    noise: str = "variance",
    density: str = "book",
    log: bool = False,
):
    r"""Return :math:`p(x_t \mid u_t, x_{t-1})` of the velocity motion model.

    *Probabilistic Robotics*, Table 5.1. The table recovers the noisy velocities
    :math:`(\hat v, \hat\omega)` of the circular arc from :math:`x_{t-1}` to
    :math:`x_t` and the final rotation :math:`\hat\gamma`, and returns

    .. math::
        \mathrm{prob}(v - \hat v,\ \alpha_1 v^2 + \alpha_2\omega^2)\,
        \mathrm{prob}(\omega - \hat\omega,\ \alpha_3 v^2 + \alpha_4\omega^2)\,
        \mathrm{prob}(\hat\gamma,\ \alpha_5 v^2 + \alpha_6\omega^2).

    Corrections to the deck ``000`` and the Turkish deck (see the errata page):
    :math:`\Delta\theta` and :math:`\hat\gamma` use wrapped angle differences; the
    radius is signed, so :math:`\hat v` is right for right turns and reversing (the
    unsigned :math:`r^*` flips it); straight-line motion, where :math:`\mu` divides by
    zero, gives its finite limit; :math:`\hat\gamma` subtracts :math:`\hat\omega`, not
    :math:`\omega`. A rotation in place (:math:`x', y' = x, y`, where every
    :math:`\hat\omega` fits) is read as the limit of arcs with :math:`\hat v \to 0`:
    the whole turn is :math:`\hat\omega\Delta t` and :math:`\hat\gamma = 0`.

    Parameters
    ----------
    x_t : array_like, shape (..., 3)
        Hypothesised poses :math:`(x', y', \theta')`.
    u_t : array_like, shape (..., 2)
        Commanded :math:`(v, \omega)` in m/s and rad/s.
    x_prev : array_like, shape (..., 3)
        Previous poses :math:`(x, y, \theta)`.
    dt : float
        Time step in s, > 0.
    alpha : array_like, shape (6,)
        Noise parameters :math:`\alpha_1 \ldots \alpha_6 \ge 0`.
    prob : callable, optional
        ``prob(a, b2)``, a zero-mean density with variance ``b2`` (Table 5.2), e.g.
        :func:`~probrob.distributions.prob_triangular_distribution`. If it takes a
        ``log`` keyword it is called with ``log=True`` and the factors are summed in log
        space; otherwise the log of its value is taken. Its result is never modified.
    noise : {"variance", "std"}, optional
        Whether :math:`\alpha_1 v^2 + \alpha_2\omega^2` is a variance (default) or
        :math:`\alpha_1|v| + \alpha_2|\omega|` a standard deviation.
    density : {"book", "pose", "xy"}, optional
        ``"book"`` returns the table's value, a density over
        :math:`(\hat v, \hat\omega, \hat\gamma)`. ``"pose"`` divides it by
        :math:`|\partial(x', y', \theta') / \partial(\hat v, \hat\omega, \hat\gamma)| =
        \tfrac12 |\hat v| \Delta t^4 \mathrm{sinc}^2(\hat\omega\Delta t / 2)`, giving a
        density over poses (units 1/(m² rad)) that integrates to one (up to the mass of
        turns beyond :math:`\pm\pi` per step, which the table folds back). It is
        infinite where :math:`x', y' = x, y` and the book value is positive.
        ``"xy"``: the pose density integrated over :math:`\theta'` (the book's
        Fig. 5.3 "projected into x-y space"), in 1/m²; the heading of ``x_t`` is
        ignored and ``x_t`` may be positions of shape ``(..., 2)``. The factor of
        :math:`\hat\gamma` integrates to one over :math:`\theta'`, leaving
        :math:`\mathrm{prob}(v - \hat v)\,\mathrm{prob}(\omega - \hat\omega) /
        (\tfrac12 |\hat v| \Delta t^3 \mathrm{sinc}^2(\hat\omega\Delta t / 2))`.
    log : bool, optional
        Return the log density, computed as a sum of log factors (``prob`` is called
        with ``log=True`` if it takes that keyword).

    Returns
    -------
    p : float or ndarray, shape broadcast(...)
        Density values (or their logs).

    Notes
    -----
    Degenerate noise (a zero variance, e.g. :math:`v = \omega = 0` or some
    :math:`\alpha_i = 0`) makes a factor a point mass: the density is ``0`` where the
    hypothesis needs noise in a direction that has none, and ``inf`` (a Dirac delta) where
    it needs none, e.g. at :math:`x_t = x_{t-1}` for a robot at rest. For ``"pose"`` and
    ``"xy"`` a zero Jacobian (:math:`\hat v = 0`) gives ``inf`` where the book value is
    positive and ``0`` where it is ``0``. Never NaN; see the module docstring.
    """
    x_prev = check.poses(x_prev, "x_prev")
    check.choice(density, "density", _DENSITIES)
    x_t = _check_hypotheses(x_t, density)
    u_t = check.vectors(u_t, "u_t", 2, "v, omega")
    dt = check.positive_scalar(dt, "dt")
    alpha = check.alphas(alpha, "alpha", 6)
    check.callable_arg(prob, "prob")
    check.choice(noise, "noise", _NOISE_FORMS)
    log = check.flag(log, "log")
    check.batch_shape(x_t=x_t.shape[:-1], u_t=u_t.shape[:-1], x_prev=x_prev.shape[:-1])
    x_t = _hypotheses(x_t, x_prev)
    log_prob, exact = _log_prob(prob)

    v, w, var_v, var_w, var_g = _velocity_controls(alpha, u_t, noise)
    with np.errstate(over="ignore", invalid="ignore"):
        v_hat, w_hat, gamma_hat, half = _invert_velocity(x_t, x_prev, dt)
    for hat in (v_hat, w_hat, gamma_hat):
        check.no_overflow(
            hat, "the velocities that move x_prev to x_t", x_t=x_t, x_prev=x_prev, dt=dt
        )
    with np.errstate(over="ignore"):  # an overflowing difference is a density of 0, exactly
        a_v, a_w = v - v_hat, w - w_hat
    if not exact:  # a user's prob gets finite arguments only
        for a in (a_v, a_w):
            check.no_overflow(a, "u_t - (v̂, ω̂)", u_t=u_t, x_t=x_t, x_prev=x_prev, dt=dt)
    logs = [log_prob(a_v, var_v), log_prob(a_w, var_w)]
    if density != "xy":  # "xy": ∫ prob(γ̂) dθ' = Δt, one factor Δt of the Jacobian
        logs.append(log_prob(gamma_hat, var_g))
    total = _log_product(logs, careful=not exact or _any_zero(var_v, var_w, var_g))
    if density != "book":
        power = 3 if density == "xy" else 4
        total = _minus_log_jacobian(total, _velocity_log_jacobian(v_hat, half, dt, power))
    return _finish(total, log)


def sample_motion_model_velocity(
    u_t,
    x_prev,
    dt,
    alpha,
    *,
    sample: Callable = sample_normal_distribution,
    noise: str = "variance",
    size=None,
    rng=None,
):
    r"""Draw poses :math:`x_t \sim p(x_t \mid u_t, x_{t-1})` of the velocity motion model.

    *Probabilistic Robotics*, Table 5.3:

    .. math::
        \hat v = v + \mathrm{sample}(\alpha_1 v^2 + \alpha_2\omega^2),\quad
        \hat\omega = \omega + \mathrm{sample}(\alpha_3 v^2 + \alpha_4\omega^2),\quad
        \hat\gamma = \mathrm{sample}(\alpha_5 v^2 + \alpha_6\omega^2),

    then the arc of :func:`velocity_motion` with :math:`(\hat v, \hat\omega)` and a
    final turn :math:`\theta' \mathrel{+}= \hat\gamma\Delta t`. The arc is evaluated in
    chord form, exact when a sampled :math:`\hat\omega` is zero (the printed
    :math:`\hat v / \hat\omega` divides by zero there).

    Parameters
    ----------
    u_t : array_like, shape (..., 2)
        Commanded :math:`(v, \omega)` in m/s and rad/s.
    x_prev : array_like, shape (..., 3)
        Previous poses, e.g. a particle set of shape ``(N, 3)``.
    dt : float
        Time step in s, > 0.
    alpha : array_like, shape (6,)
        Noise parameters :math:`\alpha_1 \ldots \alpha_6 \ge 0`.
    sample : callable, optional
        ``sample(b2, size=..., rng=...)``, a zero-mean sampler with variance ``b2``
        (Table 5.4); default the book's sum of twelve uniforms. It may return any real
        dtype, of a shape that broadcasts to ``size``; its result is never modified. Pass
        ``functools.partial(sample_normal_distribution, method="exact")`` for exact
        normal noise.
    noise : {"variance", "std"}, optional
        See :func:`motion_model_velocity`.
    size : int or tuple of ints, optional
        Shape of the batch of samples; the batch shape of ``u_t`` and ``x_prev`` must
        broadcast to it. Default: that batch shape (one sample per particle).
    rng : None, int, numpy.random.SeedSequence or numpy.random.Generator, optional
        Source of randomness (a non-negative seed; a generator is used as is).

    Returns
    -------
    x_t : ndarray, shape size + (3,)
        Sampled poses; :math:`\theta'` is not wrapped.
    """
    u_t = check.vectors(u_t, "u_t", 2, "v, omega")
    x_prev = check.poses(x_prev, "x_prev")
    dt = check.positive_scalar(dt, "dt")
    alpha = check.alphas(alpha, "alpha", 6)
    check.callable_arg(sample, "sample")
    check.choice(noise, "noise", _NOISE_FORMS)
    batch = check.batch_shape(u_t=u_t.shape[:-1], x_prev=x_prev.shape[:-1])
    shape = check.output_shape(batch, size)
    rng = check.rng(rng)

    v, w, var_v, var_w, var_g = _velocity_controls(alpha, u_t, noise)

    # The variances broadcast to ``size`` inside the sampler (numpy's convention), so a
    # single command costs one scalar, not an array of a million equal variances.
    def draw(var):
        return check.sample_output(sample(var, size=shape, rng=rng), "sample", shape, sample)

    # One draw at a time, each used at once: no more million-element arrays alive than needed.
    with np.errstate(over="ignore", invalid="ignore"):
        v_hat = v + draw(var_v)
        w_hat = w + draw(var_w)
        gamma_hat = draw(var_g)
        out = np.empty((*shape, 3))
        _arc(*_unpack(x_prev), v_hat, w_hat, dt, out=out)
        if _returns_fresh(sample) and gamma_hat.shape == shape and gamma_hat.base is None:
            gamma_hat *= dt  # our own sampler's fresh array: scale it in place
        else:  # never modify what a user's callable returned
            gamma_hat = gamma_hat * dt
        out[..., 2] += gamma_hat
    check.no_overflow(out, "the sampled motion", u_t=u_t, x_prev=x_prev, dt=dt, alpha=alpha)
    return out


# --------------------------------------------------------------------------- odometry


def _deltas(prev: np.ndarray, new: np.ndarray, **names):
    """``(rot1, trans, rot2)`` from ``prev`` to ``new`` (checked arrays).

    ``names`` are the caller's arguments the poses came from, for the message if the
    translation overflows (poses more than 1.8e308 apart).
    """
    x, y, th = _unpack(prev)
    xn, yn, thn = _unpack(new)
    with np.errstate(over="ignore"):
        dx, dy = xn - x, yn - y
        turn = thn - th
    trans = np.hypot(dx, dy)
    check.no_overflow(trans, "the translation between the two poses", **names)
    # With no translation the direction of travel is undefined; the whole turn is
    # then δrot2 (δrot1 = 0), the exact limit of a pure rotation in place.
    rot1 = np.where(trans > 0, _diff(np.arctan2(dy, dx), th), 0.0)
    if not check.all_finite(turn):  # headings more than 1.8e308 apart
        turn = _diff(thn, th)
    rot2 = _diff(turn, rot1)
    return np.asarray(rot1), trans, np.asarray(rot2)


def odometry_deltas(xbar_prev, xbar_t):
    r"""Return :math:`(\delta_{rot1}, \delta_{trans}, \delta_{rot2})` between two poses.

    *Probabilistic Robotics*, Table 5.5, lines 2–4 (and Table 5.6, lines 2–4):

    .. math::
        \delta_{rot1} = \mathrm{atan2}(\bar y' - \bar y, \bar x' - \bar x) - \bar\theta,\quad
        \delta_{trans} = \sqrt{(\bar x' - \bar x)^2 + (\bar y' - \bar y)^2},\quad
        \delta_{rot2} = \bar\theta' - \bar\theta - \delta_{rot1},

    with both rotations wrapped to :math:`[-\pi, \pi)` (the decks leave them unwrapped,
    so a heading near :math:`\pm\pi` can yield a rotation near :math:`2\pi`). With
    zero translation, :math:`\delta_{rot1} = 0` and the turn is all :math:`\delta_{rot2}`.

    Parameters
    ----------
    xbar_prev, xbar_t : array_like, shape (..., 3)
        Consecutive poses (e.g. odometry readings) :math:`\bar x_{t-1}, \bar x_t`.

    Returns
    -------
    rot1, trans, rot2 : float or ndarray, shape broadcast(...)
        Rotations in rad, translation :math:`\ge 0` in the poses' length unit.
    """
    xbar_prev = check.poses(xbar_prev, "xbar_prev")
    xbar_t = check.poses(xbar_t, "xbar_t")
    check.batch_shape(xbar_prev=xbar_prev.shape[:-1], xbar_t=xbar_t.shape[:-1])
    deltas = _deltas(xbar_prev, xbar_t, xbar_prev=xbar_prev, xbar_t=xbar_t)
    return tuple(check.scalar_or_array(d) for d in deltas)


def _apply_deltas(x, y, th, rot1, trans, rot2):
    heading = th + rot1
    return x + trans * np.cos(heading), y + trans * np.sin(heading), heading + rot2


def apply_odometry_deltas(x_prev, rot1, trans, rot2):
    r"""Return the pose reached by turning ``rot1``, driving ``trans``, turning ``rot2``.

    *Probabilistic Robotics*, Table 5.6, lines 8–10 (the inverse of
    :func:`odometry_deltas`):

    .. math::
        x' = x + \delta_{trans}\cos(\theta + \delta_{rot1}),\quad
        y' = y + \delta_{trans}\sin(\theta + \delta_{rot1}),\quad
                \theta' = \theta + \delta_{rot1} + \delta_{rot2}.

    Parameters
    ----------
    x_prev : array_like, shape (..., 3)
        Start poses.
    rot1, trans, rot2 : array_like, broadcastable with ``x_prev[..., 0]``
        Rotations in rad and translation in m.

    Returns
    -------
    x_t : ndarray, shape broadcast(...) + (3,)
        End poses; :math:`\theta'` is not wrapped.
    """
    x_prev = check.poses(x_prev, "x_prev")
    rot1 = check.finite(rot1, "rot1")
    trans = check.finite(trans, "trans")
    rot2 = check.finite(rot2, "rot2")
    check.batch_shape(
        x_prev=x_prev.shape[:-1], rot1=rot1.shape, trans=trans.shape, rot2=rot2.shape
    )
    with np.errstate(over="ignore", invalid="ignore"):
        x_t = _stack(*_apply_deltas(*_unpack(x_prev), rot1, trans, rot2))
    check.no_overflow(
        x_t, "the motion x_prev -> x_t", x_prev=x_prev, rot1=rot1, trans=trans, rot2=rot2
    )
    return x_t


def _odometry_control(u_t) -> np.ndarray:
    u_t = check.finite(u_t, "u_t")
    if u_t.ndim < 2 or u_t.shape[-2:] != (2, 3):
        raise ValueError(
            "u_t must have shape (..., 2, 3): the odometry poses (xbar_{t-1}, xbar_t), "
            f"got shape {u_t.shape}"
        )
    return u_t


def _odometry_deltas_of(u_t):
    return _deltas(u_t[..., 0, :], u_t[..., 1, :], u_t=u_t)


def _odometry_variances(alpha, rot1, trans, rot2, noise, **names):
    a1, a2, a3, a4 = alpha
    with np.errstate(over="ignore", invalid="ignore"):
        variances = (
            _noise_variance(a1, a2, rot1, trans, noise),
            _noise_variance(a3, a4, trans, rot1, noise, a4, rot2),
            _noise_variance(a1, a2, rot2, trans, noise),
        )
    for var in variances:
        check.no_overflow(var, "the noise variance of Table 5.5", alpha=alpha, **names)
    return variances


def motion_model_odometry(
    x_t,
    u_t,
    x_prev,
    alpha,
    *,
    prob: Callable = prob_normal_distribution,
    noise: str = "variance",
    density: str = "book",
    log: bool = False,
):
    r"""Return :math:`p(x_t \mid u_t, x_{t-1})` of the odometry motion model.

    *Probabilistic Robotics*, Table 5.5. With :math:`\delta` the rotations and
    translation of the odometry :math:`u_t = (\bar x_{t-1}, \bar x_t)` and
    :math:`\hat\delta` those from :math:`x_{t-1}` to :math:`x_t`
    (:func:`odometry_deltas`), the table returns

    .. math::
        \mathrm{prob}(\delta_{rot1} - \hat\delta_{rot1},\ \alpha_1\hat\delta_{rot1}^2 + \alpha_2\hat\delta_{trans}^2)\,
        \mathrm{prob}(\delta_{trans} - \hat\delta_{trans},\ \alpha_3\hat\delta_{trans}^2 + \alpha_4(\hat\delta_{rot1}^2 + \hat\delta_{rot2}^2))\,
        \mathrm{prob}(\delta_{rot2} - \hat\delta_{rot2},\ \alpha_1\hat\delta_{rot2}^2 + \alpha_2\hat\delta_{trans}^2)

    with the rotation differences wrapped to :math:`[-\pi, \pi)` (the decks do not
    wrap them).

    Parameters
    ----------
    x_t : array_like, shape (..., 3)
        Hypothesised poses :math:`(x', y', \theta')`.
    u_t : array_like, shape (..., 2, 3)
        Odometry readings :math:`(\bar x_{t-1}, \bar x_t)`.
    x_prev : array_like, shape (..., 3)
        Previous poses :math:`(x, y, \theta)`.
    alpha : array_like, shape (4,)
        Noise parameters :math:`\alpha_1 \ldots \alpha_4 \ge 0`.
    prob : callable, optional
        ``prob(a, b2)``, a zero-mean density with variance ``b2`` (Table 5.2); see
        :func:`motion_model_velocity`.
    noise : {"variance", "std"}, optional
        Whether :math:`\alpha_1\delta_{rot1}^2 + \alpha_2\delta_{trans}^2` is a variance
        (default) or :math:`\alpha_1|\delta_{rot1}| + \alpha_2\delta_{trans}` a standard
        deviation.
    density : {"book", "pose", "xy"}, optional
        ``"book"``: Table 5.5 as printed; its variances are evaluated at the
        hypothesis :math:`\hat\delta`. ``"pose"``: the density over
        :math:`(x', y', \theta')` of the sampler, Table 5.6, whose variances are
        evaluated at the odometry :math:`\delta`, divided by the Jacobian
        :math:`|\partial(x', y', \theta') / \partial(\hat\delta_{rot1}, \hat\delta_{trans},
        \hat\delta_{rot2})| = \hat\delta_{trans}`. It integrates to one (up to the mass
        of negative sampled translations); the book's value does not, because its
        variances move with the hypothesis (see the errata page). Units 1/(m² rad);
        infinite where :math:`x', y' = x, y` and the density is positive.
        ``"xy"``: the ``"pose"`` density integrated over :math:`\theta'` (the book's
        Fig. 5.7), in 1/m²: :math:`p_1 p_2 / \hat\delta_{trans}`, since :math:`p_3`
        integrates to one over :math:`\theta'`. ``x_t`` may be positions
        ``(..., 2)``.
    log : bool, optional
        Return the log density, computed as a sum of log factors.

    Returns
    -------
    p : float or ndarray, shape broadcast(...)
        Density values (or their logs).

    Notes
    -----
    Degenerate noise (a zero variance, e.g. an odometry that reports no motion, or
    :math:`\delta_{rot1} = \delta_{trans} = 0` for a rotation in place) makes a factor a
    point mass: the density is ``0`` where the hypothesis needs noise in a direction that
    has none and ``inf`` where it needs none. For ``"pose"`` and ``"xy"`` a zero Jacobian
    (:math:`\hat\delta_{trans} = 0`) gives ``inf`` for a positive density and ``0`` for a
    zero one. Never NaN; see the module docstring.
    """
    x_prev = check.poses(x_prev, "x_prev")
    check.choice(density, "density", _DENSITIES)
    x_t = _check_hypotheses(x_t, density)
    u_t = _odometry_control(u_t)
    alpha = check.alphas(alpha, "alpha", 4)
    check.callable_arg(prob, "prob")
    check.choice(noise, "noise", _NOISE_FORMS)
    log = check.flag(log, "log")
    check.batch_shape(x_t=x_t.shape[:-1], u_t=u_t.shape[:-2], x_prev=x_prev.shape[:-1])
    x_t = _hypotheses(x_t, x_prev)
    log_prob, exact = _log_prob(prob)

    rot1, trans, rot2 = _odometry_deltas_of(u_t)
    rot1_hat, trans_hat, rot2_hat = _deltas(x_prev, x_t, x_t=x_t, x_prev=x_prev)
    if density == "book":
        var1, var_t, var2 = _odometry_variances(
            alpha, rot1_hat, trans_hat, rot2_hat, noise, x_t=x_t, x_prev=x_prev
        )
    else:
        var1, var_t, var2 = _odometry_variances(alpha, rot1, trans, rot2, noise, u_t=u_t)
    logs = [log_prob(_diff(rot1, rot1_hat), var1), log_prob(trans - trans_hat, var_t)]
    if density != "xy":
        logs.append(log_prob(_diff(rot2, rot2_hat), var2))
    total = _log_product(logs, careful=not exact or _any_zero(var1, var_t, var2))
    if density != "book":
        with np.errstate(divide="ignore"):
            log_jac = np.log(trans_hat)
        total = _minus_log_jacobian(total, log_jac)
    return _finish(total, log)


def sample_motion_model_odometry(
    u_t,
    x_prev,
    alpha,
    *,
    sample: Callable = sample_normal_distribution,
    noise: str = "variance",
    size=None,
    rng=None,
):
    r"""Draw poses :math:`x_t \sim p(x_t \mid u_t, x_{t-1})` of the odometry motion model.

    *Probabilistic Robotics*, Table 5.6:

    .. math::
        \hat\delta_{rot1} = \delta_{rot1} - \mathrm{sample}(\alpha_1\delta_{rot1}^2 + \alpha_2\delta_{trans}^2),\\
        \hat\delta_{trans} = \delta_{trans} - \mathrm{sample}(\alpha_3\delta_{trans}^2 + \alpha_4(\delta_{rot1}^2 + \delta_{rot2}^2)),\\
        \hat\delta_{rot2} = \delta_{rot2} - \mathrm{sample}(\alpha_1\delta_{rot2}^2 + \alpha_2\delta_{trans}^2),\\
        x' = x + \hat\delta_{trans}\cos(\theta + \hat\delta_{rot1}),\quad
        y' = y + \hat\delta_{trans}\sin(\theta + \hat\delta_{rot1}),\quad
        \theta' = \theta + \hat\delta_{rot1} + \hat\delta_{rot2}.

    The motion is applied from the robot's own heading :math:`\theta`, not the
    odometry frame's :math:`\bar\theta` (the Turkish deck uses :math:`\bar\theta`),
    and the :math:`\delta` come from :func:`odometry_deltas` (wrapped rotations).

    Parameters
    ----------
    u_t : array_like, shape (..., 2, 3)
        Odometry readings :math:`(\bar x_{t-1}, \bar x_t)`.
    x_prev : array_like, shape (..., 3)
        Previous poses, e.g. a particle set of shape ``(N, 3)``.
    alpha : array_like, shape (4,)
        Noise parameters :math:`\alpha_1 \ldots \alpha_4 \ge 0`.
    sample : callable, optional
        ``sample(b2, size=..., rng=...)``, a zero-mean sampler with variance ``b2``.
    noise : {"variance", "std"}, optional
        See :func:`motion_model_odometry`.
    size : int or tuple of ints, optional
        Shape of the batch of samples (see :func:`sample_motion_model_velocity`).
    rng : None, int, numpy.random.SeedSequence or numpy.random.Generator, optional
        Source of randomness (a non-negative seed; a generator is used as is).

    Returns
    -------
    x_t : ndarray, shape size + (3,)
        Sampled poses; :math:`\theta'` is not wrapped.
    """
    u_t = _odometry_control(u_t)
    x_prev = check.poses(x_prev, "x_prev")
    alpha = check.alphas(alpha, "alpha", 4)
    check.callable_arg(sample, "sample")
    check.choice(noise, "noise", _NOISE_FORMS)
    batch = check.batch_shape(u_t=u_t.shape[:-2], x_prev=x_prev.shape[:-1])
    shape = check.output_shape(batch, size)
    rng = check.rng(rng)

    rot1, trans, rot2 = _odometry_deltas_of(u_t)
    variances = _odometry_variances(alpha, rot1, trans, rot2, noise, u_t=u_t)

    def draw(var):
        return check.sample_output(sample(var, size=shape, rng=rng), "sample", shape, sample)

    with np.errstate(over="ignore", invalid="ignore"):
        rot1_hat = rot1 - draw(variances[0])
        trans_hat = trans - draw(variances[1])
        rot2_hat = rot2 - draw(variances[2])
        out = np.empty((*shape, 3))
        out[..., 0], out[..., 1], out[..., 2] = _apply_deltas(
            *_unpack(x_prev), rot1_hat, trans_hat, rot2_hat
        )
    check.no_overflow(out, "the sampled motion", u_t=u_t, x_prev=x_prev, alpha=alpha)
    return out
