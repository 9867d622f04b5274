r"""Wheel kinematics and odometry integration: the Turkish lecture and the Italian CIR report.

Holds wheel odometry, exact arc updates, dead reckoning and the CIR report's matrices.
Does not hold probabilistic motion models (:mod:`probrob.motion`) or noise fits (:mod:`probrob.fitting`).

From the Turkish lecture "Olasılıksal Robotik" (deck ``002``):

* :func:`diff_drive_odometry` — slide *Odometri - Diferansiyel Sürüşlü Robot*: wheel arc
  lengths :math:`(\Delta S_L, \Delta S_R)` to :math:`(\Delta S, \Delta\theta, R)`;
* :func:`tricycle_odometry` — slide *Odometri - Tricycle*: front-wheel travel and steering
  angle to :math:`(\Delta S, \Delta\theta)`;
* :func:`arc_update` — slides *Dış Kinematik*: the exact motion on a circular arc;
* :func:`dead_reckon` — a chain of such steps (exact arcs, or the Euler and midpoint
  approximations whose error the lecture's claim "Δt küçüldükçe toplam hata azalır" is about).

From the Italian report on the centre of instantaneous rotation (deck ``003``):

* :func:`cir_pose_matrix` (eq. 2), :func:`cir_radius_angle` (eq. 4),
  :func:`cir_step_transform` (eqs. 5–7), :func:`cir_state_function` (eqs. 3 and 8) and
  :func:`cir_state_jacobians` (the Jacobians a Kalman filter needs, not in the report).

The odometry deltas :math:`(\delta_{rot1}, \delta_{trans}, \delta_{rot2})` of the lecture's
last kinematics slide are :func:`probrob.motion.odometry_deltas` and
:func:`probrob.motion.apply_odometry_deltas`.

Conventions. Poses are ``(..., 3)`` arrays :math:`(x, y, \theta)`, :math:`\theta`
counter-clockwise from the :math:`x` axis, except in the ``cir_*`` functions, which keep the
report's convention: its eq. 2 puts the *transpose* of the usual rotation matrix in the pose,

.. math::
    T(x, y, \theta) = \begin{pmatrix} \cos\theta & \sin\theta & x \\
                                      -\sin\theta & \cos\theta & y \\ 0 & 0 & 1 \end{pmatrix}
    = \begin{pmatrix} R(-\theta) & p \\ 0 & 1 \end{pmatrix},

so its :math:`\theta` is the heading measured **clockwise** (the robot faces
:math:`(\cos\theta, -\sin\theta)`), and its turn :math:`\alpha = (s_{sx} - s_{dx}) / l` is
positive when the left wheel travels further, a right turn. Under the map
:math:`(x, y, \theta) \mapsto (x, y, -\theta)` the report's state function is exactly the
standard counter-clockwise model :func:`arc_update` (and :func:`probrob.motion.velocity_motion`
with :math:`v\Delta t = \Delta S`, :math:`\omega\Delta t = -\alpha`).

Straight lines are limits, not special cases: every update is evaluated in chord form,
:math:`\Delta S\,\mathrm{sinc}(\Delta\theta / 2)` along the direction
:math:`\theta + \Delta\theta / 2`, exact on the circle and continuous through
:math:`\Delta\theta = 0`.
"""

from __future__ import annotations

import functools

import numpy as np

from . import _validation as check
from .angles import wrap_angle
from .motion import _arc, _sinc, velocity_motion_jacobians

__all__ = [
    "arc_update",
    "cir_pose_matrix",
    "cir_radius_angle",
    "cir_state_function",
    "cir_state_jacobians",
    "cir_step_transform",
    "dead_reckon",
    "diff_drive_odometry",
    "tricycle_odometry",
]

_METHODS = ("arc", "euler", "midpoint")
# The report's heading is clockwise: this flips it to the standard counter-clockwise one.
_FLIP = np.array([1.0, 1.0, -1.0])


def _interpolate_track(t, poses, t_out):
    """Poses of a recorded track ``(t (M,), poses (M, 3))`` at times ``t_out`` (unchecked).

    x and y linearly; the heading unwrapped (:func:`numpy.unwrap`), interpolated linearly
    and wrapped back to [-π, π), so a turn across ±π between two samples takes the short
    way. The one implementation behind :func:`probrob.fitting.interpolate_poses` and
    :meth:`probrob.datasets.MRCLAM.ground_truth_at`, which check their inputs first.
    """
    heading = poses[:, 2]
    if heading.size and np.max(np.abs(heading)) > 2.0**52:
        # beyond 2**52 rad a float angle has lost its place in the turn (and the differences
        # that unwrap sums may overflow): unwrap the wrapped headings, the same directions
        heading = wrap_angle(heading)
    heading = np.unwrap(heading)
    return np.stack(
        [
            np.interp(t_out, t, poses[:, 0]),
            np.interp(t_out, t, poses[:, 1]),
            np.asarray(wrap_angle(np.interp(t_out, t, heading)), dtype=float),
        ],
        axis=-1,
    )


def _quiet(function):
    """Compute without numpy's floating-point warnings; overflow is reported by
    :func:`probrob._validation.no_overflow` as a ``ValueError`` naming the arguments."""

    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        with np.errstate(over="ignore", invalid="ignore"):
            return function(*args, **kwargs)

    return wrapper


def _positive(value, name: str) -> np.ndarray:
    """A finite array of strictly positive values (a length such as the wheel base)."""
    arr = check.finite(value, name)
    if np.any(arr <= 0):
        raise ValueError(f"{name} must be > 0, got {value!r}")
    return arr


def _broadcast(name_values: dict) -> list[np.ndarray]:
    """Broadcast named arrays, or raise ``ValueError`` naming each of them and its shape."""
    check.batch_shape(**{k: np.shape(v) for k, v in name_values.items()})
    return list(np.broadcast_arrays(*name_values.values()))


def _signed_infinity(sign_of):
    """``+inf`` where ``sign_of >= 0``, ``-inf`` where it is negative."""
    return np.where(np.asarray(sign_of) < 0, -np.inf, np.inf)


# --------------------------------------------------------------------------- deck 002


@_quiet
def diff_drive_odometry(ds_left, ds_right, wheelbase):
    r"""Return the body's travel, turn and turning radius from the two wheels' arc lengths.

    Deck ``002``, slide *Odometri - Diferansiyel Sürüşlü Robot* (Siegwart & Nourbakhsh,
    *Introduction to Autonomous Mobile Robots*, §5.2.4). The wheels run on concentric arcs
    about the centre of rotation, :math:`\Delta S_L = (R - d/2)\Delta\theta` and
    :math:`\Delta S_R = (R + d/2)\Delta\theta`, so

    .. math::
        \Delta S = \frac{\Delta S_R + \Delta S_L}{2},\qquad
        \Delta\theta = \frac{\Delta S_R - \Delta S_L}{d},\qquad
        R = \frac{\Delta S}{\Delta\theta}
          = \frac{d\,(\Delta S_R + \Delta S_L)}{2\,(\Delta S_R - \Delta S_L)}.

    On a straight line (:math:`\Delta S_R = \Delta S_L`) the radius is infinite:
    ``R = +inf`` driving forwards or standing still, ``-inf`` reversing, never a division
    by zero. :math:`R > 0` means the centre of rotation is on the robot's left
    (:math:`\Delta\theta > 0`, counter-clockwise, for forward motion).

    Parameters
    ----------
    ds_left, ds_right : array_like, broadcastable
        Arc lengths travelled by the left and right wheel, m (negative when reversing).
    wheelbase : array_like, broadcastable
        Distance :math:`d > 0` between the wheels, m.

    Returns
    -------
    ds : float or ndarray
        Arc length travelled by the midpoint of the axle, m.
    dtheta : float or ndarray
        Change of heading, rad, counter-clockwise positive.
    radius : float or ndarray
        Signed radius of the midpoint's arc, m (``±inf`` on a straight line).
    """
    left = check.finite(ds_left, "ds_left")
    right = check.finite(ds_right, "ds_right")
    d = _positive(wheelbase, "wheelbase")
    left, right, d = _broadcast({"ds_left": left, "ds_right": right, "wheelbase": d})
    ds = 0.5 * (left + right)
    dtheta = (right - left) / d
    check.no_overflow(
        ds + dtheta, "diff_drive_odometry", ds_left=left, ds_right=right, wheelbase=d
    )
    turning = dtheta != 0
    # a tiny but nonzero turn may overflow to the infinite radius (warnings are off)
    radius = np.divide(ds, dtheta, out=_signed_infinity(ds), where=turning)
    return tuple(check.scalar_or_array(a) for a in (ds, dtheta, radius))


@_quiet
def tricycle_odometry(d_front, steering_angle, wheelbase):
    r"""Return the body's travel and turn from the steered front wheel's travel and angle.

    Deck ``002``, slide *Odometri - Tricycle*. The body's reference point is the middle of
    the rear axle; the front wheel, a distance :math:`d` ahead of it, is steered by
    :math:`\alpha`. The centre of rotation lies on the rear axle's line at
    :math:`R = d / \tan\alpha`, and the front wheel runs on a circle of radius
    :math:`d / \sin\alpha` about it, so

    .. math::
        \Delta\theta = \frac{\Delta F \sin\alpha}{d},\qquad
        \Delta S = R\,\Delta\theta = \Delta F \cos\alpha.

    :math:`\alpha = 0` drives straight; :math:`\alpha = \pm\pi/2` turns in place about the
    rear axle's midpoint. The deck's formulas are right; these are they.

    Parameters
    ----------
    d_front : array_like, broadcastable
        Arc length travelled by the front wheel, m.
    steering_angle : array_like, broadcastable
        Steering angle :math:`\alpha` of the front wheel, rad, positive to the left.
    wheelbase : array_like, broadcastable
        Distance :math:`d > 0` from the rear axle to the front wheel, m.

    Returns
    -------
    ds : float or ndarray
        Arc length travelled by the middle of the rear axle, m.
    dtheta : float or ndarray
        Change of heading, rad, counter-clockwise positive.
    """
    front = check.finite(d_front, "d_front")
    steer = check.finite(steering_angle, "steering_angle")
    d = _positive(wheelbase, "wheelbase")
    front, steer, d = _broadcast({"d_front": front, "steering_angle": steer, "wheelbase": d})
    ds, dtheta = front * np.cos(steer), front * np.sin(steer) / d
    check.no_overflow(dtheta, "tricycle_odometry", d_front=front, wheelbase=d)
    return check.scalar_or_array(ds), check.scalar_or_array(dtheta)


@_quiet
def arc_update(x_prev, ds, dtheta):
    r"""Return the pose after travelling ``ds`` along a circular arc that turns ``dtheta``.

    Deck ``002``, slides *Dış Kinematik* (exterior kinematics). The deck puts the centre of
    rotation at :math:`C = (x - R\sin\theta,\ y + R\cos\theta)` with :math:`R = \Delta S /
    \Delta\theta` and rotates the robot about it by :math:`\Delta\theta`:

    .. math::
        \begin{pmatrix} x' - C_x \\ y' - C_y \end{pmatrix} =
        \begin{pmatrix} \cos\Delta\theta & -\sin\Delta\theta \\
                        \sin\Delta\theta & \cos\Delta\theta \end{pmatrix}
        \begin{pmatrix} x - C_x \\ y - C_y \end{pmatrix},\qquad
        \theta' = \theta + \Delta\theta.

    Eliminating :math:`C` gives the chord form used here,

    .. math::
        x' = x + \Delta S\,\mathrm{sinc}\tfrac{\Delta\theta}{2}\cos\left(\theta +
        \tfrac{\Delta\theta}{2}\right),\quad
        y' = y + \Delta S\,\mathrm{sinc}\tfrac{\Delta\theta}{2}\sin\left(\theta +
        \tfrac{\Delta\theta}{2}\right),

    with :math:`\mathrm{sinc}\,h = \sin h / h`: the same numbers where :math:`\Delta\theta
    \ne 0`, the straight line at :math:`\Delta\theta = 0` (where the deck divides by zero),
    and no cancellation between the huge :math:`C` and :math:`R` of a nearly straight arc.
    It is :func:`probrob.motion.velocity_motion` with :math:`v\Delta t = \Delta S` and
    :math:`\omega\Delta t = \Delta\theta`.

    Parameters
    ----------
    x_prev : array_like, shape (..., 3)
        Poses :math:`(x, y, \theta)`.
    ds : array_like, broadcastable with ``x_prev[..., 0]``
        Arc length, m (negative: reversing).
    dtheta : array_like, broadcastable with ``x_prev[..., 0]``
        Change of heading, rad.

    Returns
    -------
    x_t : ndarray, shape broadcast(...) + (3,)
        The poses at the end of the arcs; :math:`\theta'` is not wrapped.
    """
    x_prev = check.poses(x_prev, "x_prev")
    ds = check.finite(ds, "ds")
    dtheta = check.finite(dtheta, "dtheta")
    x, y, th = np.moveaxis(x_prev, -1, 0)
    check.batch_shape(x_prev=x_prev.shape[:-1], ds=ds.shape, dtheta=dtheta.shape)
    out = np.stack(_arc(x, y, th, ds, dtheta, 1.0), axis=-1)
    check.no_overflow(out, "arc_update", x_prev=x_prev, ds=ds, dtheta=dtheta)
    return out


@_quiet
def dead_reckon(x0, ds, dtheta, *, method="arc"):
    r"""Return the trajectory obtained by chaining odometry steps from ``x0``.

    The lecture's *Odometri* slides: the wheels' travel is read every :math:`\Delta t`, and
    each reading :math:`(\Delta S_k, \Delta\theta_k)` moves the pose estimate on. Step
    :math:`k` goes from :math:`\theta_{k-1}` to :math:`\theta_k = \theta_{k-1} +
    \Delta\theta_k` and moves the position by :math:`\Delta S_k` along

    * ``method="arc"``: the exact arc of :func:`arc_update` (chord
      :math:`\Delta S_k\,\mathrm{sinc}(\Delta\theta_k / 2)` at :math:`\theta_{k-1} +
      \Delta\theta_k / 2`);
    * ``method="midpoint"``: a straight segment at :math:`\theta_{k-1} + \Delta\theta_k / 2`
      (second order; Siegwart & Nourbakhsh, eq. 5.7);
    * ``method="euler"``: a straight segment at :math:`\theta_{k-1}` (first order).

    All steps are evaluated at once (cumulative sums over the last axis), with no Python loop.

    Parameters
    ----------
    x0 : array_like, shape (..., 3)
        Start poses.
    ds, dtheta : array_like, shape (..., K)
        Arc lengths (m) and heading changes (rad) of the K steps; leading axes broadcast
        with ``x0[..., 0]``.
    method : {"arc", "midpoint", "euler"}
        How one step moves the position (above).

    Returns
    -------
    trajectory : ndarray, shape broadcast(...) + (K + 1, 3)
        The poses before the first step and after each step; headings are not wrapped.
    """
    x0 = check.poses(x0, "x0")
    ds = check.finite(ds, "ds")
    dtheta = check.finite(dtheta, "dtheta")
    method = check.choice(method, "method", _METHODS)
    if ds.ndim == 0 or dtheta.ndim == 0:
        raise ValueError("ds and dtheta must have a last axis of steps, shape (..., K)")
    if ds.shape[-1] != dtheta.shape[-1]:
        raise ValueError(
            f"ds and dtheta must have the same number of steps K (last axis), got shapes "
            f"{ds.shape} and {dtheta.shape}"
        )
    batch = check.batch_shape(x0=x0.shape[:-1], ds=ds.shape[:-1], dtheta=dtheta.shape[:-1])
    steps = ds.shape[-1]
    x0 = np.broadcast_to(x0, (*batch, 3))
    ds = np.broadcast_to(ds, (*batch, steps))
    dtheta = np.broadcast_to(dtheta, (*batch, steps))
    heading = x0[..., 2:3] + np.cumsum(dtheta, axis=-1)
    before = np.concatenate([x0[..., 2:3], heading[..., :-1]], axis=-1)
    if method == "euler":
        direction, chord = before, ds
    else:
        direction = before + 0.5 * dtheta
        chord = ds * _sinc(0.5 * dtheta) if method == "arc" else ds
    out = np.empty((*batch, steps + 1, 3))
    out[..., 0, :] = x0
    out[..., 1:, 0] = x0[..., 0:1] + np.cumsum(chord * np.cos(direction), axis=-1)
    out[..., 1:, 1] = x0[..., 1:2] + np.cumsum(chord * np.sin(direction), axis=-1)
    out[..., 1:, 2] = heading
    check.no_overflow(out, "dead_reckon's trajectory", x0=x0, ds=ds, dtheta=dtheta)
    return out


# --------------------------------------------------------------------------- deck 003


def _wheels(u, wheelbase):
    u = check.vectors(u, "u", 2, "s_sx, s_dx: left and right wheel arc lengths")
    ell = _positive(wheelbase, "wheelbase")
    check.batch_shape(u=u.shape[:-1], wheelbase=ell.shape)
    s_sx, s_dx = np.moveaxis(u, -1, 0)
    return np.broadcast_arrays(s_sx, s_dx, ell)


def _translation(tx, ty):
    t = np.zeros((*np.shape(tx), 3, 3))
    t[..., 0, 0] = t[..., 1, 1] = t[..., 2, 2] = 1.0
    t[..., 0, 2] = tx
    t[..., 1, 2] = ty
    return t


def _deck_rotation(angle):
    """The report's rotation block: the transpose of the usual R(angle)."""
    c, s = np.cos(angle), np.sin(angle)
    t = np.zeros((*np.shape(angle), 3, 3))
    t[..., 0, 0] = t[..., 1, 1] = c
    t[..., 0, 1] = s
    t[..., 1, 0] = -s
    t[..., 2, 2] = 1.0
    return t


@_quiet
def cir_pose_matrix(x):
    r"""Return the report's homogeneous matrix :math:`T^w_{R}` of poses ``x``.

    Deck ``003``, eq. 2:

    .. math::
        T^w_{R_t} = \begin{pmatrix} \cos\theta_t & \sin\theta_t & x_t \\
                                    -\sin\theta_t & \cos\theta_t & y_t \\
                                    0 & 0 & 1 \end{pmatrix}.

    Its rotation block is the transpose of the usual :math:`R(\theta)`, i.e.
    :math:`R(-\theta)`: this is the usual homogeneous matrix of the pose
    :math:`(x, y, -\theta)`. The report's :math:`\theta` is the heading measured clockwise
    (see the module notes).

    Parameters
    ----------
    x : array_like, shape (..., 3)
        Poses :math:`(x, y, \theta)` in the report's convention.

    Returns
    -------
    T : ndarray, shape (..., 3, 3)
    """
    x = check.poses(x, "x")
    px, py, th = np.moveaxis(x, -1, 0)
    t = _deck_rotation(th)
    t[..., 0, 2] = px
    t[..., 1, 2] = py
    return t


@_quiet
def cir_radius_angle(u, wheelbase):
    r"""Return the report's radius :math:`r` and turn :math:`\alpha` of one step.

    Deck ``003``, eq. 4:

    .. math::
        r = \frac{l\, s_{dx}}{s_{sx} - s_{dx}},\qquad \alpha = \frac{s_{sx} - s_{dx}}{l},

    with :math:`s_{sx}, s_{dx}` the arc lengths of the left (*sinistra*) and right
    (*destra*) wheel and :math:`l` the distance between them. :math:`r` is the signed
    distance from the right wheel to the centre of instantaneous rotation (CIR), which lies
    at :math:`-(r + l/2)` along the robot's :math:`y` axis; :math:`\alpha > 0` is a right
    (clockwise) turn. On a straight line (:math:`s_{sx} = s_{dx}`) ``r`` is ``+inf``
    (``-inf`` if :math:`s_{dx} < 0`) and ``alpha`` is 0.

    Parameters
    ----------
    u : array_like, shape (..., 2)
        Wheel arc lengths :math:`(s_{sx}, s_{dx})`, m.
    wheelbase : array_like, broadcastable
        :math:`l > 0`, m.

    Returns
    -------
    r, alpha : float or ndarray
    """
    s_sx, s_dx, ell = _wheels(u, wheelbase)
    diff = s_sx - s_dx
    # a tiny but nonzero difference may overflow to the infinite radius (warnings are off)
    r = np.divide(ell * s_dx, diff, out=_signed_infinity(s_dx), where=diff != 0)
    alpha = diff / ell
    check.no_overflow(alpha, "the turn alpha", u=np.stack([s_sx, s_dx], -1), wheelbase=ell)
    return check.scalar_or_array(r), check.scalar_or_array(alpha)


@_quiet
def cir_step_transform(u, wheelbase):
    r"""Return the roto-translation :math:`T^{R_{t-1}}_{R_t}` of one step, as the report builds it.

    Deck ``003``, eqs. 5–7: translate to the CIR, rotate about it by :math:`\alpha`,
    translate back,

    .. math::
        T^{R_{t-1}}_{R_t} = T^{R_{t-1}}_{CIR}\,T^{CIR_{t-1}}_{CIR_t}\,T^{CIR_t}_{R_t}
        = \begin{pmatrix} 1 & 0 & 0 \\ 0 & 1 & -r - l/2 \\ 0 & 0 & 1 \end{pmatrix}
          \begin{pmatrix} \cos\alpha & \sin\alpha & 0 \\ -\sin\alpha & \cos\alpha & 0 \\
                          0 & 0 & 1 \end{pmatrix}
          \begin{pmatrix} 1 & 0 & 0 \\ 0 & 1 & r + l/2 \\ 0 & 0 & 1 \end{pmatrix},

    and, where :math:`s_{sx} = s_{dx}` (eq. 7), the translation by :math:`s_{sx}` along the
    robot's :math:`x` axis. The product is evaluated literally (three matrices per step);
    :func:`cir_state_function` composes it with the pose.

    Parameters
    ----------
    u : array_like, shape (..., 2)
        Wheel arc lengths :math:`(s_{sx}, s_{dx})`, m.
    wheelbase : array_like, broadcastable
        :math:`l > 0`, m.

    Returns
    -------
    T : ndarray, shape (..., 3, 3)
    """
    s_sx, s_dx, ell = _wheels(u, wheelbase)
    r, alpha = cir_radius_angle(np.stack([s_sx, s_dx], axis=-1), ell)
    straight = np.isinf(r)
    rho = np.where(straight, 0.0, r + 0.5 * ell)  # distance from the CIR to the axle's middle
    zero = np.zeros_like(rho)
    turning = _translation(zero, -rho) @ _deck_rotation(alpha) @ _translation(zero, rho)
    return np.where(straight[..., None, None], _translation(s_sx, zero), turning)


@_quiet
def cir_state_function(x_prev, u, wheelbase):
    r"""Return the report's state function :math:`f(x_{t-1}, u)`: the pose after one step.

    Deck ``003``, eqs. 3 and 8: :math:`T^w_{R_t} = T^w_{R_{t-1}} T^{R_{t-1}}_{R_t}` (from
    :func:`cir_pose_matrix` and :func:`cir_step_transform`), and

    .. math::
        f(x_{t-1}, u) = \bigl(T^w_{R_t}(1, 3),\ T^w_{R_t}(2, 3),\ \theta_{t-1} + \alpha\bigr).

    Turning, this is the report's closed form

    .. math::
        f = \begin{pmatrix}
        x - \sin\theta\,\rho(1 - \cos\alpha) + \cos\theta\sin\alpha\,\rho \\
        y - \cos\theta\,\rho(1 - \cos\alpha) - \sin\theta\sin\alpha\,\rho \\
        \theta + \alpha \end{pmatrix},\qquad \rho = r + \frac l2,

    and straight, :math:`(x + s_{sx}\cos\theta,\ y - s_{sx}\sin\theta,\ \theta)`. Its
    :math:`\theta` is clockwise: :math:`f(x, u) = M\,\mathrm{arc\_update}(Mx, \Delta S,
    -\alpha)` with :math:`M = \mathrm{diag}(1, 1, -1)` and :math:`\Delta S = (s_{sx} +
    s_{dx}) / 2` (see the module notes).

    Parameters
    ----------
    x_prev : array_like, shape (..., 3)
        Poses in the report's convention (clockwise :math:`\theta`).
    u : array_like, shape (..., 2)
        Wheel arc lengths :math:`(s_{sx}, s_{dx})`, m.
    wheelbase : array_like, broadcastable
        :math:`l > 0`, m.

    Returns
    -------
    x_t : ndarray, shape broadcast(...) + (3,)
    """
    x_prev = check.poses(x_prev, "x_prev")
    s_sx, s_dx, ell = _wheels(u, wheelbase)
    check.batch_shape(x_prev=x_prev.shape[:-1], u=s_sx.shape)
    u = np.stack([s_sx, s_dx], axis=-1)
    world = cir_pose_matrix(x_prev) @ cir_step_transform(u, ell)
    alpha = (s_sx - s_dx) / ell
    out = np.stack(
        np.broadcast_arrays(world[..., 0, 2], world[..., 1, 2], x_prev[..., 2] + alpha), axis=-1
    )
    check.no_overflow(out, "cir_state_function", x_prev=x_prev, u=u, wheelbase=ell)
    return out


@_quiet
def cir_state_jacobians(x_prev, u, wheelbase):
    r"""Return the Jacobians :math:`F = \partial f / \partial x_{t-1}` and :math:`W = \partial f / \partial u`.

    For the report's state function :math:`f` (:func:`cir_state_function`, deck ``003``
    eq. 8), as a Kalman filter needs them (the report stops before them). With
    :math:`\Delta S = (s_{sx} + s_{dx}) / 2`, :math:`S = \mathrm{sinc}(\alpha / 2)` and
    :math:`m = \theta + \alpha / 2`, :math:`f = (x + \Delta S\,S\cos m,\ y - \Delta S\,S
    \sin m,\ \theta + \alpha)`, so

    .. math::
        F = \begin{pmatrix} 1 & 0 & -\Delta S\,S\sin m \\ 0 & 1 & -\Delta S\,S\cos m \\
                            0 & 0 & 1 \end{pmatrix},\qquad
        W = \frac{\partial f}{\partial(\Delta S, \alpha)}
            \begin{pmatrix} 1/2 & 1/2 \\ 1/l & -1/l \end{pmatrix}.

    They are computed as :math:`F = M G M` and :math:`W = M V J` from the Jacobians
    :math:`G, V` of :func:`probrob.motion.velocity_motion_jacobians` (Table 7.2, with
    :math:`\Delta t = 1`, :math:`v = \Delta S`, :math:`\omega = -\alpha`), :math:`M =
    \mathrm{diag}(1, 1, -1)` and :math:`J = \partial(v, \omega) / \partial(s_{sx},
    s_{dx})`: exact and finite on straight lines, where differentiating the report's turning
    case would divide by :math:`(s_{sx} - s_{dx})^2`.

    Parameters
    ----------
    x_prev : array_like, shape (..., 3)
        Poses in the report's convention.
    u : array_like, shape (..., 2)
        Wheel arc lengths :math:`(s_{sx}, s_{dx})`, m.
    wheelbase : array_like, broadcastable
        :math:`l > 0`, m.

    Returns
    -------
    F : ndarray, shape broadcast(...) + (3, 3)
    W : ndarray, shape broadcast(...) + (3, 2)
    """
    x_prev = check.poses(x_prev, "x_prev")
    s_sx, s_dx, ell = _wheels(u, wheelbase)
    check.batch_shape(x_prev=x_prev.shape[:-1], u=s_sx.shape)
    controls = np.stack([0.5 * (s_sx + s_dx), (s_dx - s_sx) / ell], axis=-1)
    check.no_overflow(controls, "the step's (ds, dθ)", u=u, wheelbase=ell)
    G, V = velocity_motion_jacobians(x_prev * _FLIP, controls, 1.0)
    J = np.zeros((*ell.shape, 2, 2))
    J[..., 0, :] = 0.5
    J[..., 1, 0] = -1.0 / ell
    J[..., 1, 1] = 1.0 / ell
    F = _FLIP[:, None] * G * _FLIP
    W = _FLIP[:, None] * (V @ J)
    check.no_overflow(W, "cir_state_jacobians", x_prev=x_prev, u=u, wheelbase=ell)
    return F, W
