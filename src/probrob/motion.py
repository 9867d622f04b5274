r"""Probabilistic motion models of *Probabilistic Robotics*, chapter 5.

* :func:`motion_model_velocity` — Table 5.1, the density :math:`p(x_t \mid u_t, x_{t-1})`
  of the velocity motion model;
* :func:`sample_motion_model_velocity` — Table 5.3, its sampler;
* :func:`motion_model_odometry` — Table 5.5, the odometry motion model's density;
* :func:`sample_motion_model_odometry` — Table 5.6, its sampler;
* :func:`velocity_motion` — the noise-free motion :math:`g(u_t, x_{t-1})` (Table 7.2,
  line 5), exact for :math:`\omega = 0`, and :func:`velocity_motion_jacobians`, its
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

The velocity model is written in the robot frame of :math:`x_{t-1}`. With the
displacement :math:`(a, b)` of :math:`x_t` ahead of and to the left of the robot, the
circle through both positions and tangent to the initial heading turns by
:math:`\Delta\theta = 2\arctan(b / a)` (the tangent–chord angle) and has signed radius
:math:`(a^2 + b^2) / (2b)`. This is the book's circle-centre construction (lines 2–6 of
Table 5.1) without its division by zero on straight lines, and with the sign of
:math:`\hat v` right for right turns and reversing.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from . import _validation as check
from .angles import angle_diff, wrap_angle
from .distributions import prob_normal_distribution, sample_normal_distribution

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
    return tuple(np.moveaxis(arr, -1, 0))


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


def _sinc(h):
    """``sin(h) / h``, exactly 1 at ``h = 0``."""
    h = np.asarray(h, dtype=float)
    return np.divide(np.sin(h), h, out=np.ones_like(h), where=h != 0)


def _arc(x, y, th, v, w, dt, out=None):
    r"""Exact motion on a circle for time ``dt`` (Table 5.3 lines 5–7 without γ).

    Uses :math:`\frac{v}{\omega}[\sin(\theta + \omega\Delta t) - \sin\theta] =
    v\Delta t\,\mathrm{sinc}(\omega\Delta t / 2)\cos(\theta + \omega\Delta t / 2)`,
    which is finite and exact at :math:`\omega = 0`. Writes into ``out`` (a
    pre-allocated ``(..., 3)`` array) if given, else returns the three components.
    """
    half = np.multiply(w, 0.5 * dt)
    chord = _sinc(half)
    chord *= v
    chord *= dt
    mid = np.add(th, half)
    if out is None:
        return x + chord * np.cos(mid), y + chord * np.sin(mid), mid + half
    np.multiply(chord, np.cos(mid), out=out[..., 0])
    out[..., 0] += x
    np.multiply(chord, np.sin(mid), out=out[..., 1])
    out[..., 1] += y
    np.add(mid, half, out=out[..., 2])
    return out


def _velocity_controls(alpha, u_t, noise):
    v, w = _unpack(u_t)
    a1, a2, a3, a4, a5, a6 = alpha
    return (
        v,
        w,
        _noise_variance(a1, a2, v, w, noise),
        _noise_variance(a3, a4, v, w, noise),
        _noise_variance(a5, a6, v, w, noise),
    )


# --------------------------------------------------------------------------- velocity


def velocity_motion(x_prev, u_t, dt):
    r"""Return the noise-free pose after moving with velocities ``u_t`` for ``dt``.

    The function :math:`g(u_t, x_{t-1})` of *Probabilistic Robotics*, Table 7.2,
    line 5 (and Table 5.3, lines 5–7 without noise):

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
    x, y, th = _unpack(x_prev)
    v, w = _unpack(u_t)
    return _stack(*_arc(x, y, th, v, w, dt))


def _sinc_derivative(h):
    r"""``d/dh [sin(h) / h] = (h cos h - sin h) / h²``, without cancellation near 0.

    For :math:`|h| < 0.1` the Taylor series :math:`-h/3 + h^3/30 - h^5/840 + h^7/45360 -
    h^9/3991680` (next term below :math:`10^{-18}` relative); elsewhere the closed form,
    which loses at most two digits there.
    """
    h = np.asarray(h, dtype=float)
    small = np.abs(h) < 0.1
    h2 = h * h
    series = h * (-1 / 3 + h2 * (1 / 30 + h2 * (-1 / 840 + h2 * (1 / 45360 - h2 / 3991680))))
    safe = np.where(small, 1.0, h)
    closed = (safe * np.cos(safe) - np.sin(safe)) / (safe * safe)
    return np.where(small, series, closed)


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
    th = _unpack(x_prev)[2]
    v, w = _unpack(u_t)
    h = w * (0.5 * dt)
    sinc, dsinc = _sinc(h), _sinc_derivative(h)
    mid = th + h
    c, s = np.cos(mid), np.sin(mid)
    batch = np.broadcast_shapes(th.shape, v.shape)
    G = np.zeros((*batch, 3, 3))
    G[..., 0, 0] = G[..., 1, 1] = G[..., 2, 2] = 1.0
    G[..., 0, 2] = -v * dt * sinc * s
    G[..., 1, 2] = v * dt * sinc * c
    V = np.zeros((*batch, 3, 2))
    V[..., 0, 0] = dt * sinc * c
    V[..., 1, 0] = dt * sinc * s
    V[..., 0, 1] = 0.5 * v * dt**2 * (dsinc * c - sinc * s)
    V[..., 1, 1] = 0.5 * v * dt**2 * (dsinc * s + sinc * c)
    V[..., 2, 1] = dt
    return G, V


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
        half = np.where(moved, half, 0.5 * np.asarray(angle_diff(thn, th)))
        ratio = np.where(moved, ratio, 0.0)
    v_hat = rho * ratio
    v_hat /= dt
    w_hat = half * (2.0 / dt)
    turn = np.subtract(thn, th)
    turn -= 2.0 * half
    gamma_hat = np.asarray(wrap_angle(turn)) / dt
    return v_hat, w_hat, gamma_hat, half


def _velocity_jacobian_abs(v_hat, half, dt):
    r"""``|det ∂(x', y', θ') / ∂(v̂, ω̂, γ̂)|`` for the velocity model.

    :math:`\Delta t \cdot |\hat v| \Delta t^3 (1 - \cos\hat\omega\Delta t) /
    (\hat\omega\Delta t)^2 = \tfrac12 |\hat v| \Delta t^4\,
    \mathrm{sinc}^2(\hat\omega\Delta t / 2)`.
    """
    return 0.5 * np.abs(v_hat) * dt**4 * _sinc(half) ** 2


def _hypotheses(x_t, x_prev, density: str) -> np.ndarray:
    """Check ``x_t``; for ``density="xy"`` positions ``(..., 2)`` get a dummy heading."""
    if density != "xy":
        return check.poses(x_t, "x_t")
    x_t = check.finite(x_t, "x_t")
    if x_t.ndim == 0 or x_t.shape[-1] not in (2, 3):
        raise ValueError(
            f"x_t must have shape (..., 3) or, for density='xy', (..., 2); got {x_t.shape}"
        )
    if x_t.shape[-1] == 3:
        return x_t
    x, y = _unpack(x_t)
    return _stack(x, y, _unpack(x_prev)[2])


def _divide_by_jacobian(p, jac):
    safe = np.where(jac > 0, jac, 1.0)
    return np.where(jac > 0, p / safe, np.where(p > 0, np.inf, 0.0))


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
        :func:`~probrob.distributions.prob_triangular_distribution`.
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

    Returns
    -------
    p : float or ndarray, shape broadcast(...)
        Density values.
    """
    x_prev = check.poses(x_prev, "x_prev")
    check.choice(density, "density", _DENSITIES)
    x_t = _hypotheses(x_t, x_prev, density)
    u_t = check.vectors(u_t, "u_t", 2, "v, omega")
    dt = check.positive_scalar(dt, "dt")
    alpha = check.alphas(alpha, "alpha", 6)
    check.callable_arg(prob, "prob")
    check.choice(noise, "noise", _NOISE_FORMS)

    v, w, var_v, var_w, var_g = _velocity_controls(alpha, u_t, noise)
    v_hat, w_hat, gamma_hat, half = _invert_velocity(x_t, x_prev, dt)
    p = prob(v - v_hat, var_v) * prob(w - w_hat, var_w)
    if density == "xy":  # ∫ prob(γ̂) dθ' = Δt, one factor Δt of the Jacobian
        p = _divide_by_jacobian(p, _velocity_jacobian_abs(v_hat, half, dt) / dt)
    else:
        p = p * prob(gamma_hat, var_g)
    if density == "pose":
        p = _divide_by_jacobian(p, _velocity_jacobian_abs(v_hat, half, dt))
    return check.scalar_or_array(p)


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
        (Table 5.4); default the book's sum of twelve uniforms. Pass
        ``functools.partial(sample_normal_distribution, method="exact")`` for exact
        normal noise.
    noise : {"variance", "std"}, optional
        See :func:`motion_model_velocity`.
    size : int or tuple of ints, optional
        Shape of the batch of samples; the batch shape of ``u_t`` and ``x_prev`` must
        broadcast to it. Default: that batch shape (one sample per particle).
    rng : None, int or numpy.random.Generator, optional
        Source of randomness.

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
    shape = check.output_shape(np.broadcast_shapes(u_t.shape[:-1], x_prev.shape[:-1]), size)
    rng = np.random.default_rng(rng)

    v, w, var_v, var_w, var_g = _velocity_controls(alpha, u_t, noise)
    # The variances broadcast to ``size`` inside the sampler (numpy's convention), so a
    # single command costs one scalar, not an array of a million equal variances.
    v_hat = v + sample(var_v, size=shape, rng=rng)
    w_hat = w + sample(var_w, size=shape, rng=rng)
    gamma_hat = sample(var_g, size=shape, rng=rng)
    out = np.empty((*shape, 3))
    _arc(*_unpack(x_prev), v_hat, w_hat, dt, out=out)
    gamma_hat *= dt
    out[..., 2] += gamma_hat
    return out


# --------------------------------------------------------------------------- odometry


def _deltas(prev: np.ndarray, new: np.ndarray):
    x, y, th = _unpack(prev)
    xn, yn, thn = _unpack(new)
    dx, dy = xn - x, yn - y
    trans = np.hypot(dx, dy)
    # With no translation the direction of travel is undefined; the whole turn is
    # then δrot2 (δrot1 = 0), the exact limit of a pure rotation in place.
    rot1 = np.where(trans > 0, angle_diff(np.arctan2(dy, dx), th), 0.0)
    rot2 = angle_diff(thn - th, rot1)
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
    return tuple(check.scalar_or_array(d) for d in _deltas(xbar_prev, xbar_t))


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
                heta' = \theta + \delta_{rot1} + \delta_{rot2}.

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
    x, y, th = _unpack(check.poses(x_prev, "x_prev"))
    rot1 = check.finite(rot1, "rot1")
    trans = check.finite(trans, "trans")
    rot2 = check.finite(rot2, "rot2")
    return _stack(*_apply_deltas(x, y, th, rot1, trans, rot2))


def _odometry_control(u_t) -> tuple[np.ndarray, ...]:
    u_t = check.finite(u_t, "u_t")
    if u_t.ndim < 2 or u_t.shape[-2:] != (2, 3):
        raise ValueError(
            "u_t must have shape (..., 2, 3): the odometry poses (xbar_{t-1}, xbar_t), "
            f"got shape {u_t.shape}"
        )
    return _deltas(u_t[..., 0, :], u_t[..., 1, :])


def _odometry_variances(alpha, rot1, trans, rot2, noise):
    a1, a2, a3, a4 = alpha
    return (
        _noise_variance(a1, a2, rot1, trans, noise),
        _noise_variance(a3, a4, trans, rot1, noise, a4, rot2),
        _noise_variance(a1, a2, rot2, trans, noise),
    )


def motion_model_odometry(
    x_t,
    u_t,
    x_prev,
    alpha,
    *,
    prob: Callable = prob_normal_distribution,
    noise: str = "variance",
    density: str = "book",
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
        ``prob(a, b2)``, a zero-mean density with variance ``b2`` (Table 5.2).
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

    Returns
    -------
    p : float or ndarray, shape broadcast(...)
        Density values.
    """
    x_prev = check.poses(x_prev, "x_prev")
    check.choice(density, "density", _DENSITIES)
    x_t = _hypotheses(x_t, x_prev, density)
    rot1, trans, rot2 = _odometry_control(u_t)
    alpha = check.alphas(alpha, "alpha", 4)
    check.callable_arg(prob, "prob")
    check.choice(noise, "noise", _NOISE_FORMS)

    rot1_hat, trans_hat, rot2_hat = _deltas(x_prev, x_t)
    if density == "book":
        var1, var_t, var2 = _odometry_variances(alpha, rot1_hat, trans_hat, rot2_hat, noise)
    else:
        var1, var_t, var2 = _odometry_variances(alpha, rot1, trans, rot2, noise)
    p = prob(angle_diff(rot1, rot1_hat), var1) * prob(trans - trans_hat, var_t)
    if density != "xy":
        p = p * prob(angle_diff(rot2, rot2_hat), var2)
    if density != "book":
        p = _divide_by_jacobian(p, trans_hat)
    return check.scalar_or_array(p)


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
    rng : None, int or numpy.random.Generator, optional
        Source of randomness.

    Returns
    -------
    x_t : ndarray, shape size + (3,)
        Sampled poses; :math:`\theta'` is not wrapped.
    """
    rot1, trans, rot2 = _odometry_control(u_t)
    x_prev = check.poses(x_prev, "x_prev")
    alpha = check.alphas(alpha, "alpha", 4)
    check.callable_arg(sample, "sample")
    check.choice(noise, "noise", _NOISE_FORMS)
    shape = check.output_shape(np.broadcast_shapes(rot1.shape, x_prev.shape[:-1]), size)
    rng = np.random.default_rng(rng)

    var1, var_t, var2 = _odometry_variances(alpha, rot1, trans, rot2, noise)
    rot1_hat = rot1 - sample(var1, size=shape, rng=rng)
    trans_hat = trans - sample(var_t, size=shape, rng=rng)
    rot2_hat = rot2 - sample(var2, size=shape, rng=rng)
    out = np.empty((*shape, 3))
    out[..., 0], out[..., 1], out[..., 2] = _apply_deltas(
        *_unpack(x_prev), rot1_hat, trans_hat, rot2_hat
    )
    return out
