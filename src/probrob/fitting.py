r"""Noise parameters fitted to recorded data: the motion and measurement noise of the models.

Holds noise parameters fitted to recorded data: ML fits (Tables 5.1, 5.5) and moment fits (7.2, 6.4).
Does not hold the models (:mod:`probrob.motion`, :mod:`probrob.sensors`) or the filters.

The noise parameters :math:`\alpha` of the velocity model (*Probabilistic Robotics*,
Table 5.1, :math:`\alpha_1 \ldots \alpha_6`) and of the odometry model (Table 5.5,
:math:`\alpha_1 \ldots \alpha_4`) are usually guessed. Given pose pairs
:math:`(x_{t-1}, x_t)` measured by an external reference (e.g. a motion-capture system)
and the controls :math:`u_t` recorded between them, this module maximises

.. math::
    \ell(\alpha) = \sum_k \log p(x_t^{(k)} \mid u_t^{(k)}, x_{t-1}^{(k)}, \alpha)

over :math:`\alpha \ge 0`, with the densities of :mod:`probrob.motion` (never a second
copy of a model), for either noise form (``noise="variance"`` or ``"std"``) and either
density mode (``density="book"`` or ``"pose"``). The search runs in
:math:`\log\alpha` (L-BFGS-B within bounds), so every :math:`\alpha_i` stays positive
and parameters of very different sizes are handled alike.

It also turns a recording into such pose pairs:

* :func:`interpolate_poses` — ground-truth poses at arbitrary times (linear in
  :math:`x, y` and the unwrapped heading);
* :func:`integrate_commands` — dead reckoning: integrates recorded :math:`(v, \omega)`
  commands, held constant between their time stamps, with the exact arc update;
* :func:`motion_windows` — cuts a recording into windows of a fixed length: the
  ground-truth poses at both ends, the mean commands over the window (for the velocity
  model) and the dead-reckoned poses at both ends (the "odometry" of the odometry model);
* :func:`frame_errors` — poses seen from reference poses (along-track, cross-track and
  heading errors).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field, replace
from typing import NamedTuple

import numpy as np
from scipy.optimize import minimize

from . import _validation as check
from .angles import angle_diff
from .evaluation import nees
from .kinematics import _interpolate_track, arc_update, dead_reckon
from .localization import _NonFinite, _predict_segment
from .motion import motion_model_odometry, motion_model_velocity
from .sensors import _landmark_measurement_core

__all__ = [
    "AlphaFit",
    "MeasurementNoiseFit",
    "MotionNoiseFit",
    "MotionWindows",
    "fit_measurement_noise",
    "fit_motion_noise",
    "fit_odometry_alpha",
    "fit_velocity_alpha",
    "frame_errors",
    "integrate_commands",
    "interpolate_poses",
    "motion_windows",
    "odometry_log_likelihood",
    "velocity_log_likelihood",
]

_NOISE_FORMS = ("variance", "std")
_FIT_DENSITIES = ("book", "pose")
_ALPHA_BOUNDS = (1e-12, 1e4)
# Common scales tried as starting points: the best one on the data starts the search.
_START_SCALES = 10.0 ** np.arange(-8, 3)


# --------------------------------------------------------------------------- input checks


def _times(t, name: str) -> np.ndarray:
    t = check.finite(t, name)
    if t.ndim != 1 or t.size < 2:
        raise ValueError(f"{name} must be a 1-d array of at least 2 times, got shape {t.shape}")
    if np.any(np.diff(t) <= 0):
        raise ValueError(f"{name} must be strictly increasing")
    return t


def _rows(value, name: str, n: int, width: int, what: str) -> np.ndarray:
    arr = check.vectors(value, name, width, what)
    if arr.shape != (n, width):
        raise ValueError(f"{name} must have shape ({n}, {width}) ({what}), got {arr.shape}")
    return arr


def _within(t_out, t, name: str, span_name: str) -> np.ndarray:
    t_out = check.finite(t_out, name)
    if np.any(t_out < t[0]) or np.any(t_out > t[-1]):
        raise ValueError(
            f"{name} must lie within {span_name} [{float(t[0])!r}, {float(t[-1])!r}], "
            f"got [{float(t_out.min())!r}, {float(t_out.max())!r}]"
        )
    return t_out


# --------------------------------------------------------------------------- recordings


def interpolate_poses(t, poses, t_out):
    r"""Return poses at the times ``t_out``, linearly interpolated between recorded poses.

    :math:`x` and :math:`y` are interpolated linearly; the heading is unwrapped
    (:func:`numpy.unwrap`), interpolated linearly and wrapped back to
    :math:`[-\pi, \pi)`, so a heading crossing :math:`\pm\pi` between two samples is not
    swept through zero.

    Parameters
    ----------
    t : array_like, shape (M,)
        Strictly increasing time stamps in s.
    poses : array_like, shape (M, 3)
        Poses :math:`(x, y, \theta)` at ``t``.
    t_out : array_like, shape (...)
        Times within ``[t[0], t[-1]]``.

    Returns
    -------
    poses_out : ndarray, shape (..., 3)
        Interpolated poses, heading wrapped to :math:`[-\pi, \pi)`.
    """
    t = _times(t, "t")
    poses = _rows(poses, "poses", t.size, 3, "x, y, theta")
    t_out = _within(t_out, t, "t_out", "the recording")
    return _interpolate_track(t, poses, t_out)


def integrate_commands(t, u, x0, t_out=None):
    r"""Return the poses reached by integrating recorded :math:`(v, \omega)` commands.

    The command ``u[i]`` is held from ``t[i]`` to ``t[i + 1]`` (zero-order hold), over
    which the robot drives the arc of length :math:`\Delta s = v\,\Delta t` turning by
    :math:`\Delta\theta = \omega\,\Delta t` (the exact arc update, "Dış Kinematik" of
    the Turkish deck; the noise-free motion of *Probabilistic Robotics*, Table 5.3).
    The stamped poses come from :func:`probrob.kinematics.dead_reckon` (cumulative sums,
    no Python loop), a time between two stamps gets the partial arc of
    :func:`probrob.kinematics.arc_update`. The last command ``u[-1]`` is not used (it
    has no end time).

    Parameters
    ----------
    t : array_like, shape (N,)
        Strictly increasing command time stamps in s.
    u : array_like, shape (N, 2)
        Commands :math:`(v, \omega)` in m/s and rad/s.
    x0 : array_like, shape (3,)
        Pose at ``t[0]``.
    t_out : array_like, shape (...), optional
        Times within ``[t[0], t[-1]]`` at which to return the pose (a time between two
        stamps gets the partial arc). Default: ``t``.

    Returns
    -------
    poses : ndarray, shape (N, 3) or t_out.shape + (3,)
        Dead-reckoned poses; the heading is not wrapped.
    """
    t = _times(t, "t")
    u = _rows(u, "u", t.size, 2, "v, omega")
    x0 = check.single_pose(x0, "x0")
    dt = np.diff(t)
    knots = dead_reckon(x0, u[:-1, 0] * dt, u[:-1, 1] * dt, method="arc")
    if t_out is None:
        return knots
    t_out = _within(t_out, t, "t_out", "the command times")
    i = np.clip(np.searchsorted(t, t_out, side="right") - 1, 0, t.size - 2)
    held = t_out - t[i]
    return arc_update(knots[i], u[i, 0] * held, u[i, 1] * held)


def frame_errors(reference, poses):
    r"""Return ``poses`` expressed in the frames of ``reference`` poses.

    With :math:`(x_r, y_r, \theta_r)` a reference pose (e.g. a predicted end pose) and
    :math:`(x, y, \theta)` a pose (e.g. the measured one), the along-track error
    :math:`e_a`, cross-track error :math:`e_c` (positive to the left) and heading error
    :math:`e_\theta` are

    .. math::
        e_a = \cos\theta_r (x - x_r) + \sin\theta_r (y - y_r),\quad
        e_c = -\sin\theta_r (x - x_r) + \cos\theta_r (y - y_r),\quad
        e_\theta = \mathrm{wrap}(\theta - \theta_r).

    Parameters
    ----------
    reference, poses : array_like, shape (..., 3)
        Reference poses and poses; leading axes broadcast.

    Returns
    -------
    errors : ndarray, shape broadcast(...) + (3,)
        :math:`(e_a, e_c, e_\theta)` in m, m and rad (wrapped to :math:`[-\pi, \pi)`).

    Raises
    ------
    ValueError
        If the batch shapes do not broadcast (naming both), or an error overflows float64
        (naming the most extreme argument).
    """
    reference = check.poses(reference, "reference")
    poses = check.poses(poses, "poses")
    check.batch_shape(reference=reference.shape[:-1], poses=poses.shape[:-1])
    xr, yr, thr = np.moveaxis(reference, -1, 0)
    x, y, th = np.moveaxis(poses, -1, 0)
    c, s = np.cos(thr), np.sin(thr)
    with np.errstate(over="ignore", invalid="ignore"):
        dx, dy = x - xr, y - yr
        errors = np.stack(
            np.broadcast_arrays(c * dx + s * dy, c * dy - s * dx, np.asarray(angle_diff(th, thr))),
            axis=-1,
        )
    per_pose = np.where(np.all(np.isfinite(errors), axis=-1), 0.0, np.inf)
    check.no_overflow(per_pose, "the frame error", reference=reference, poses=poses)
    return errors


@dataclass(frozen=True)
class MotionWindows:
    r"""Pose pairs cut from a recording: one row per window of length ``dt``.

    Attributes
    ----------
    t0 : ndarray, shape (K,)
        Start time of each window in s (the window is ``[t0, t0 + dt]``).
    dt : float
        Window length in s.
    u : ndarray, shape (K, 2)
        Mean commands :math:`(\bar v, \bar\omega)` over each window (the exact time
        average of the held commands): the velocity model's control.
    u_min, u_max : ndarray, shape (K, 2)
        Smallest and largest held command over each window (e.g. ``u_min[:, 0] > 0``:
        the robot was commanded forwards throughout).
    x_prev, x_t : ndarray, shape (K, 3)
        Ground-truth poses at the start and end of each window.
    odometry : ndarray, shape (K, 2, 3)
        Dead-reckoned poses :math:`(\bar x_{t-1}, \bar x_t)` at the start and end of
        each window: the odometry model's control.
    """

    t0: np.ndarray
    dt: float
    u: np.ndarray
    u_min: np.ndarray = field(repr=False)
    u_max: np.ndarray = field(repr=False)
    x_prev: np.ndarray = field(repr=False)
    x_t: np.ndarray = field(repr=False)
    odometry: np.ndarray = field(repr=False)

    def __len__(self) -> int:
        return self.t0.size

    def select(self, mask) -> MotionWindows:
        """Return the windows picked by a boolean mask or an index array over ``K``."""
        return replace(
            self,
            t0=self.t0[mask],
            u=self.u[mask],
            u_min=self.u_min[mask],
            u_max=self.u_max[mask],
            x_prev=self.x_prev[mask],
            x_t=self.x_t[mask],
            odometry=self.odometry[mask],
        )


_MAX_WINDOWS = 1e8  # windows of one recording: 16 GB of arrays


def motion_windows(command_t, commands, truth_t, truth, dt, *, stride=None):
    r"""Cut a recording into windows of length ``dt`` with their controls and true poses.

    Windows start at :math:`t_0 + k \cdot \mathrm{stride}` from the later of the two
    first time stamps and end before the earlier of the two last ones. For each window
    the ground truth is interpolated (:func:`interpolate_poses`) at both ends; the
    commands, held between their stamps, are averaged over the window exactly (for the
    velocity model, which assumes one constant command per step); and the commands are
    dead-reckoned once over the whole recording (:func:`integrate_commands`, starting from
    the true pose at the first command) and read at both ends (the odometry model's
    :math:`(\bar x_{t-1}, \bar x_t)`; only their relative motion enters the model, so
    the drift accumulated before the window does not matter).

    Parameters
    ----------
    command_t : array_like, shape (N,)
        Strictly increasing command time stamps in s.
    commands : array_like, shape (N, 2)
        Commands :math:`(v, \omega)`.
    truth_t : array_like, shape (M,)
        Strictly increasing ground-truth time stamps in s.
    truth : array_like, shape (M, 3)
        Ground-truth poses.
    dt : float
        Window length in s, > 0.
    stride : float, optional
        Time between window starts, > 0; default ``dt`` (adjacent windows).

    Returns
    -------
    MotionWindows
    """
    command_t = _times(command_t, "command_t")
    commands = _rows(commands, "commands", command_t.size, 2, "v, omega")
    truth_t = _times(truth_t, "truth_t")
    truth = _rows(truth, "truth", truth_t.size, 3, "x, y, theta")
    dt = check.positive_scalar(dt, "dt")
    stride = dt if stride is None else check.positive_scalar(stride, "stride")
    start = max(command_t[0], truth_t[0])
    stop = min(command_t[-1], truth_t[-1])
    with np.errstate(over="ignore"):  # a stride near the smallest float: too many, below
        windows = np.floor((stop - start - dt) / stride) + 1
    if stop - start < dt or windows < 1:
        raise ValueError(
            f"dt = {dt!r} s is longer than the time covered by both recordings "
            f"({max(stop - start, 0.0):.3f} s)"
        )
    if not windows <= _MAX_WINDOWS:
        raise ValueError(
            f"{'stride' if stride != dt else 'dt'} = {stride!r} s cuts the "
            f"{stop - start:.6g} s of the recordings into {windows:.3g} windows, more than "
            f"{_MAX_WINDOWS:.0e}: use a longer {'stride' if stride != dt else 'dt or a stride'}"
        )
    count = int(windows)
    t0 = start + stride * np.arange(count)
    t1 = np.minimum(t0 + dt, stop)  # guards the last window against rounding past stop
    # The integral of the held commands at any time: exact at the stamps, linear between.
    with np.errstate(over="ignore", invalid="ignore"):
        integral = np.concatenate(
            [np.zeros((1, 2)), np.cumsum(commands[:-1] * np.diff(command_t)[:, None], axis=0)]
        )
    check.no_overflow(
        integral, "the integral of the commands", commands=commands, command_t=command_t
    )
    mean_u = np.stack(
        [
            (np.interp(t1, command_t, integral[:, j]) - np.interp(t0, command_t, integral[:, j]))
            / dt
            for j in range(2)
        ],
        axis=-1,
    )
    # The commands held during [t0, t1): from the one in force at t0 to the last one
    # stamped before t1 (reduceat over the pairs of bounds; the odd slots are unused).
    first = np.searchsorted(command_t, t0, side="right") - 1
    last = np.maximum(np.searchsorted(command_t, t1, side="left") - 1, first)
    bounds = np.stack([first, last + 1], axis=-1).ravel()
    u_min = np.minimum.reduceat(commands, bounds, axis=0)[::2]
    u_max = np.maximum.reduceat(commands, bounds, axis=0)[::2]
    # Dead reckoning starts from the true pose at the first command (or the first truth).
    x_start = interpolate_poses(truth_t, truth, np.clip(command_t[0], truth_t[0], truth_t[-1]))
    odo = integrate_commands(command_t, commands, x_start, np.stack([t0, t1], axis=-1))
    return MotionWindows(
        t0=t0,
        dt=dt,
        u=mean_u,
        u_min=u_min,
        u_max=u_max,
        x_prev=interpolate_poses(truth_t, truth, t0),
        x_t=interpolate_poses(truth_t, truth, t1),
        odometry=odo,
    )


# --------------------------------------------------------------------------- likelihoods


def _log_density(density_fn, *args, **kwargs):
    # log=True: computed in log space, so far tails do not underflow to -inf.
    return np.asarray(density_fn(*args, log=True, **kwargs), dtype=float)


def velocity_log_likelihood(x_t, u_t, x_prev, dt, alpha, *, noise="variance", density="book"):
    r"""Return :math:`\log p(x_t \mid u_t, x_{t-1})` of the velocity model, per pose pair.

    The logarithm of :func:`probrob.motion.motion_model_velocity` (*Probabilistic
    Robotics*, Table 5.1) with the normal noise density, one value per pair.

    Parameters
    ----------
    x_t, x_prev : array_like, shape (..., 3)
        End and start poses.
    u_t : array_like, shape (..., 2)
        Commands :math:`(v, \omega)` held over the step.
    dt : float
        Step length in s.
    alpha : array_like, shape (6,)
        :math:`\alpha_1 \ldots \alpha_6 \ge 0`.
    noise : {"variance", "std"}, optional
        Noise form (see :func:`~probrob.motion.motion_model_velocity`).
    density : {"book", "pose"}, optional
        Density mode (see :func:`~probrob.motion.motion_model_velocity`).

    Returns
    -------
    log_p : float or ndarray, shape broadcast(...)
        ``-inf`` where the density is zero.
    """
    check.choice(density, "density", _FIT_DENSITIES)
    return check.scalar_or_array(
        _log_density(
            motion_model_velocity, x_t, u_t, x_prev, dt, alpha, noise=noise, density=density
        )
    )


def odometry_log_likelihood(x_t, u_t, x_prev, alpha, *, noise="variance", density="book"):
    r"""Return :math:`\log p(x_t \mid u_t, x_{t-1})` of the odometry model, per pose pair.

    The logarithm of :func:`probrob.motion.motion_model_odometry` (*Probabilistic
    Robotics*, Table 5.5) with the normal noise density, one value per pair.

    Parameters
    ----------
    x_t, x_prev : array_like, shape (..., 3)
        End and start poses.
    u_t : array_like, shape (..., 2, 3)
        Odometry poses :math:`(\bar x_{t-1}, \bar x_t)`.
    alpha : array_like, shape (4,)
        :math:`\alpha_1 \ldots \alpha_4 \ge 0`.
    noise : {"variance", "std"}, optional
        Noise form (see :func:`~probrob.motion.motion_model_odometry`).
    density : {"book", "pose"}, optional
        ``"book"``: Table 5.5 as printed (variances at the hypothesis, not normalised);
        ``"pose"``: the normalised density of the sampler, Table 5.6 (errata O3).

    Returns
    -------
    log_p : float or ndarray, shape broadcast(...)
        ``-inf`` where the density is zero.
    """
    check.choice(density, "density", _FIT_DENSITIES)
    return check.scalar_or_array(
        _log_density(motion_model_odometry, x_t, u_t, x_prev, alpha, noise=noise, density=density)
    )


# --------------------------------------------------------------------------- fits


@dataclass(frozen=True)
class AlphaFit:
    r"""The result of a maximum-likelihood fit of motion-noise parameters.

    Attributes
    ----------
    alpha : ndarray, shape (6,) or (4,)
        The maximiser :math:`\hat\alpha`.
    stderr : ndarray, same shape
        Asymptotic standard errors of :math:`\hat\alpha` from the observed information
        (the inverse Hessian of :math:`-\ell` in :math:`\log\alpha`, by central
        differences, mapped to :math:`\alpha` by the delta method). NaN for a parameter
        that sits at a bound, where the asymptotic theory does not apply.
    at_bound : ndarray of bool, same shape
        Whether :math:`\hat\alpha_i` sits at the lower bound (read: zero) or the upper.
    log_likelihood : float
        :math:`\ell(\hat\alpha)`, the summed log density of the fitted mode.
    n_pairs : int
        Number of pose pairs.
    nit, nfev : int
        Iterations and objective evaluations of L-BFGS-B (``nfev`` includes the
        finite-difference gradients, not the start search or the Hessian).
    success : bool
        Whether the optimiser reported convergence.
    message : str
        The optimiser's message.
    model, noise, density : str
        ``"velocity"`` or ``"odometry"``, and the noise form and density mode fitted.
    """

    alpha: np.ndarray
    stderr: np.ndarray
    at_bound: np.ndarray
    log_likelihood: float
    n_pairs: int
    nit: int
    nfev: int
    success: bool
    message: str
    model: str
    noise: str
    density: str

    @property
    def mean_log_likelihood(self) -> float:
        """:math:`\\ell(\\hat\\alpha)` per pose pair."""
        return self.log_likelihood / self.n_pairs


def _bounds(alpha_bounds) -> tuple[float, float]:
    bounds = check.finite(alpha_bounds, "alpha_bounds")
    if bounds.shape != (2,) or not 0 < bounds[0] < bounds[1]:
        raise ValueError(
            f"alpha_bounds must be (low, high) with 0 < low < high, got {alpha_bounds!r}"
        )
    return float(bounds[0]), float(bounds[1])


def _hessian(f, x, step=1e-3):
    """Central-difference Hessian of a scalar function of a vector."""
    k = x.size
    hess = np.empty((k, k))
    eye = np.eye(k) * step
    f0 = f(x)
    for i in range(k):
        hess[i, i] = (f(x + eye[i]) - 2.0 * f0 + f(x - eye[i])) / step**2
        for j in range(i):
            hess[i, j] = hess[j, i] = (
                f(x + eye[i] + eye[j])
                - f(x + eye[i] - eye[j])
                - f(x - eye[i] + eye[j])
                + f(x - eye[i] - eye[j])
            ) / (4.0 * step**2)
    return hess


def _fit(loglik, count, n_pairs, model, noise, density, alpha0, alpha_bounds):
    lo, hi = _bounds(alpha_bounds)
    log_lo, log_hi = np.log(lo), np.log(hi)
    # Every pair must have a finite log density for positive α (else no α explains it:
    # e.g. a command of zero predicts a point mass that a measured jitter never hits).
    # Positive α all give the same support, so one probe checks them all.
    probe = loglik(np.full(count, hi))
    bad = np.flatnonzero(~np.isfinite(probe))
    if bad.size:
        raise ValueError(
            f"x_t, u_t, x_prev: {bad.size} of {n_pairs} pose pairs have a log density of "
            f"{probe[bad[0]]} for every alpha > 0 (first at index {bad[0]}): the model puts "
            "a point mass there (e.g. a zero command) or the pair did not move; drop them"
        )

    def objective(beta):
        return -float(np.sum(loglik(np.exp(beta)))) / n_pairs

    if alpha0 is None:
        scores = [objective(np.full(count, np.log(c))) for c in _START_SCALES]
        beta0 = np.full(count, np.log(_START_SCALES[int(np.nanargmin(scores))]))
    else:
        alpha0 = check.alphas(alpha0, "alpha0", count)
        beta0 = np.log(np.clip(alpha0, lo, hi))
    beta0 = np.clip(beta0, log_lo, log_hi)
    res = minimize(
        objective,
        beta0,
        method="L-BFGS-B",
        bounds=[(log_lo, log_hi)] * count,
        options={"ftol": 1e-12, "gtol": 1e-8},
    )
    beta = np.clip(res.x, log_lo, log_hi)
    at_bound = (beta <= log_lo + 1e-6) | (beta >= log_hi - 1e-6)
    free = np.flatnonzero(~at_bound)
    stderr = np.full(count, np.nan)
    if free.size:

        def free_objective(b):
            full = beta.copy()
            full[free] = b
            return objective(full) * n_pairs

        hess = _hessian(free_objective, beta[free])
        with np.errstate(invalid="ignore"):
            cov = np.linalg.pinv(hess)
            stderr[free] = np.exp(beta[free]) * np.sqrt(np.diag(cov))
    alpha = np.exp(beta)
    return AlphaFit(
        alpha=alpha,
        stderr=stderr,
        at_bound=at_bound,
        log_likelihood=float(np.sum(loglik(alpha))),
        n_pairs=n_pairs,
        nit=int(res.nit),
        nfev=int(res.nfev),
        success=bool(res.success),
        message=str(res.message),
        model=model,
        noise=noise,
        density=density,
    )


def _fit_model(model_fn, model, count, data, noise, density, alpha0, alpha_bounds):
    """Check the options, then fit ``count`` α of ``model_fn`` to ``data`` (see :func:`_fit`).

    ``data`` are the model's arguments before ``alpha``: ``(x_t, u_t, x_prev[, dt])``.
    """
    check.choice(noise, "noise", _NOISE_FORMS)
    check.choice(density, "density", _FIT_DENSITIES)

    def loglik(alpha):
        return _log_density(model_fn, *data, alpha, noise=noise, density=density)

    return _fit(loglik, count, data[0].shape[0], model, noise, density, alpha0, alpha_bounds)


def _pairs(x_t, x_prev):
    x_t = check.poses(x_t, "x_t")
    x_prev = check.poses(x_prev, "x_prev")
    if x_t.ndim != 2 or x_t.shape != x_prev.shape or x_t.shape[0] < 1:
        raise ValueError(
            "x_t and x_prev must both have shape (K, 3) with K >= 1, "
            f"got {x_t.shape} and {x_prev.shape}"
        )
    return x_t, x_prev


def fit_velocity_alpha(
    x_t,
    u_t,
    x_prev,
    dt,
    *,
    noise="variance",
    density="book",
    alpha0=None,
    alpha_bounds=_ALPHA_BOUNDS,
):
    r"""Fit the velocity model's :math:`\alpha_1 \ldots \alpha_6` by maximum likelihood.

    Maximises :math:`\sum_k \log p(x_t^{(k)} \mid u_t^{(k)}, x_{t-1}^{(k)}, \alpha)` of
    *Probabilistic Robotics*, Table 5.1 (:func:`probrob.motion.motion_model_velocity`,
    normal noise) over :math:`\log\alpha` with L-BFGS-B. ``density="pose"`` divides the
    book's value by a Jacobian that depends on the pose pair but not on :math:`\alpha`,
    so both modes have the same maximiser; they differ only in :math:`\ell`.

    Parameters
    ----------
    x_t, x_prev : array_like, shape (K, 3)
        Measured end and start poses of ``K`` steps.
    u_t : array_like, shape (K, 2)
        Commands :math:`(v, \omega)` of each step. A step with :math:`v = \omega = 0`
        has a point-mass model and raises ``ValueError`` (drop such steps).
    dt : float
        Step length in s, > 0, the same for every pair.
    noise : {"variance", "std"}, optional
        Noise form.
    density : {"book", "pose"}, optional
        Density mode.
    alpha0 : array_like, shape (6,), optional
        Starting point. Default: the best of :math:`\alpha = c(1, \ldots, 1)` for
        :math:`c = 10^{-8} \ldots 10^2`.
    alpha_bounds : (float, float), optional
        Search bounds for every :math:`\alpha_i`, default ``(1e-12, 1e4)``.

    Returns
    -------
    AlphaFit
    """
    x_t, x_prev = _pairs(x_t, x_prev)
    u_t = _rows(u_t, "u_t", x_t.shape[0], 2, "v, omega")
    dt = check.positive_scalar(dt, "dt")
    return _fit_model(
        motion_model_velocity, "velocity", 6, (x_t, u_t, x_prev, dt), noise, density, alpha0,
        alpha_bounds,
    )  # fmt: skip


def fit_odometry_alpha(
    x_t,
    u_t,
    x_prev,
    *,
    noise="variance",
    density="book",
    alpha0=None,
    alpha_bounds=_ALPHA_BOUNDS,
):
    r"""Fit the odometry model's :math:`\alpha_1 \ldots \alpha_4` by maximum likelihood.

    Maximises :math:`\sum_k \log p(x_t^{(k)} \mid u_t^{(k)}, x_{t-1}^{(k)}, \alpha)` of
    *Probabilistic Robotics*, Table 5.5 (:func:`probrob.motion.motion_model_odometry`,
    normal noise) over :math:`\log\alpha` with L-BFGS-B. ``density="pose"`` (the
    sampler's normalised density, variances at the odometry) is the proper likelihood;
    ``density="book"`` maximises the printed table, whose variances move with the
    hypothesis, and lands elsewhere (errata O3).

    Parameters
    ----------
    x_t, x_prev : array_like, shape (K, 3)
        Measured end and start poses of ``K`` steps.
    u_t : array_like, shape (K, 2, 3)
        Odometry poses :math:`(\bar x_{t-1}, \bar x_t)` of each step. A step whose
        odometry does not translate has a point-mass :math:`\delta_{rot1}` under
        ``density="pose"`` and raises ``ValueError`` (drop such steps).
    noise : {"variance", "std"}, optional
        Noise form.
    density : {"book", "pose"}, optional
        Density mode.
    alpha0 : array_like, shape (4,), optional
        Starting point (default: see :func:`fit_velocity_alpha`).
    alpha_bounds : (float, float), optional
        Search bounds for every :math:`\alpha_i`, default ``(1e-12, 1e4)``.

    Returns
    -------
    AlphaFit
    """
    x_t, x_prev = _pairs(x_t, x_prev)
    u_t = check.finite(u_t, "u_t")
    if u_t.shape != (x_t.shape[0], 2, 3):
        raise ValueError(
            f"u_t must have shape ({x_t.shape[0]}, 2, 3) (odometry poses), got {u_t.shape}"
        )
    return _fit_model(
        motion_model_odometry, "odometry", 4, (x_t, u_t, x_prev), noise, density, alpha0,
        alpha_bounds,
    )  # fmt: skip


# --------------------------------------------------------------------------- moment fits


class MeasurementNoiseFit(NamedTuple):
    r"""Result of :func:`fit_measurement_noise` (a tuple: ``bias, sigma, robust = fit``).

    Attributes
    ----------
    bias : ndarray, shape (2,)
        Mean residual of range [m] and bearing [rad].
    sigma : ndarray, shape (2,)
        Their standard deviations (Gaussian ML fit).
    robust_sigma : ndarray, shape (2,)
        1.4826 × the median absolute deviation from the median.
    """

    bias: np.ndarray
    sigma: np.ndarray
    robust_sigma: np.ndarray


def fit_measurement_noise(z, c, poses, m):
    r"""Return the bias and standard deviation of range and bearing, fitted to true poses.

    The residuals :math:`r - \hat r` and :math:`\mathrm{wrap}(\phi - \hat\phi)` of
    measurements ``z`` of landmarks ``c`` taken at known poses, with :math:`(\hat r,
    \hat\phi) = h(x, m_c)` (the measurement function of Table 6.4), and their Gaussian
    maximum-likelihood fit: the mean (bias) and the standard deviation (``ddof=0``). Also
    returns the robust standard deviation :math:`1.4826\cdot\mathrm{MAD}`, which
    describes the core of a heavy-tailed residual distribution.

    Parameters
    ----------
    z : array_like, shape (K, 2) or (K, 3)
        Measurements :math:`(r, \phi[, s])`.
    c : array_like of int, shape (K,)
        Landmark rows.
    poses : array_like, shape (K, 3)
        True poses at the measurement times (e.g. motion capture).
    m : array_like, shape (L, 3)

    Returns
    -------
    MeasurementNoiseFit
        ``(bias, sigma, robust_sigma)``, each of shape (2,) (range [m], bearing [rad]).
    """
    m = check.landmark_map(m, "m")
    z = check.features(z, "z")
    c = check.landmark_indices(c, "c", z.shape[0], m.shape[0])
    poses = check.poses(poses, "poses")
    if poses.shape != (z.shape[0], 3):
        raise ValueError(f"poses must have shape ({z.shape[0]}, 3), got {poses.shape}")
    if z.shape[0] < 2:
        raise ValueError("z: at least two measurements are needed to fit a noise")
    with np.errstate(over="ignore", invalid="ignore"):  # reported below, naming the inputs
        z_hat = _landmark_measurement_core(poses, m[c, :2])
        res = np.stack([z[:, 0] - z_hat[:, 0], angle_diff(z[:, 1], z_hat[:, 1])], axis=-1)
        med = np.median(res, axis=0)
        fit = MeasurementNoiseFit(
            bias=res.mean(axis=0),
            sigma=res.std(axis=0),
            robust_sigma=1.4826 * np.median(np.abs(res - med), axis=0),
        )
    check.no_overflow(np.concatenate(fit), "the residuals' statistics", z=z, poses=poses, m=m)
    return fit


@dataclass(frozen=True)
class MotionNoiseFit:
    r"""Result of :func:`fit_motion_noise`.

    Attributes
    ----------
    alpha : ndarray, shape (4,)
        Fitted :math:`\alpha_1 \ldots \alpha_4`.
    windows : int
        Number of windows.
    errors : ndarray, shape (windows, 3)
        Each window's end-pose error in the robot frame: along the direction of travel,
        across it (left), and in heading.
    nees : ndarray, shape (windows,)
        :math:`e^T \bar\Sigma^{-1} e` of each window's end pose under the fitted
        :math:`\alpha` (windows without motion left out: NaN).
    """

    alpha: np.ndarray
    windows: int
    errors: np.ndarray
    nees: np.ndarray


def _nonnegative_lstsq(X: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Least squares ``X a ≈ y`` with ``a >= 0`` for two columns (exact active-set)."""
    best, best_cost = np.zeros(2), float(y @ y)
    candidates = [np.linalg.lstsq(X, y, rcond=None)[0]]
    for j in range(2):
        col = X[:, j]
        den = float(col @ col)
        a = np.zeros(2)
        if den > 0:
            a[j] = float(col @ y) / den
        candidates.append(a)
    for a in candidates:
        if np.all(a >= 0):
            cost = float(np.sum((X @ a - y) ** 2))
            if cost < best_cost:
                best, best_cost = a, cost
    return best


def _predicted(x0, Sigma0, u_w, dt_w, alpha, u, dt, poses):
    """One window's prediction (Table 7.2), an overflow reported against the fit's arguments."""
    try:
        with np.errstate(over="ignore", invalid="ignore"):
            mus, Sig = _predict_segment(x0, Sigma0, u_w, dt_w, alpha)
    except _NonFinite:
        mus = Sig = np.array([np.inf])
    check.no_overflow(
        np.concatenate([mus.ravel(), Sig.ravel()]),
        "a window's prediction",
        u=u,
        dt=dt,
        poses=poses,
    )
    return mus, Sig


def fit_motion_noise(u, dt, poses, *, window):
    r"""Fit :math:`\alpha_1 \ldots \alpha_4` of the EKF's motion noise to a true trajectory.

    The steps are cut into consecutive windows of about ``window`` seconds. In each
    window the noise-free motion :math:`g` (Table 7.2, line 6) runs from the true pose
    over the window's commands; the error :math:`e_w` between the true end pose and that
    prediction is split into its component along the direction of travel, across it,
    and in heading. In the model of Table 7.2 the heading error is exactly
    :math:`\sum_k \Delta t_k\, \delta\omega_k` and the along-track error is, to first
    order, :math:`\sum_k \Delta t_k\, \delta v_k`, so (method of moments)

    .. math::
        E[e_{w,\parallel}^2] = \alpha_1 \sum_k \Delta t_k^2 v_k^2 + \alpha_2 \sum_k \Delta t_k^2 \omega_k^2,
        \qquad
        E[e_{w,\theta}^2] = \alpha_3 \sum_k \Delta t_k^2 v_k^2 + \alpha_4 \sum_k \Delta t_k^2 \omega_k^2,

    two linear regressions of the squared errors on the windows' sums, solved by
    non-negative least squares. The cross-track error is not used: the model has no
    noise term that moves the robot sideways (only a heading error does, slowly), so
    what the data show there is reported (``errors[:, 1]``) rather than fitted.

    The book's model draws independent noise at every step, so the fitted values
    depend on the step length and on ``window``: fit at the horizon the filter
    predicts over between measurements.

    Parameters
    ----------
    u : array_like, shape (N, 2)
        Commands of the steps.
    dt : array_like, shape (N,)
        Step lengths, > 0.
    poses : array_like, shape (N + 1, 3)
        True poses at the step boundaries (the start of step 0, then each step's end).
    window : float
        Window length, s.

    Returns
    -------
    MotionNoiseFit
    """
    u = check.vectors(u, "u", 2, "v, omega")
    if u.ndim != 2:
        raise ValueError(f"u must have shape (N, 2), got {u.shape}")
    n = u.shape[0]
    dt = check.step_lengths(dt, "dt", n)
    poses = check.poses(poses, "poses")
    if poses.shape != (n + 1, 3):
        raise ValueError(f"poses must have shape ({n + 1}, 3), got {poses.shape}")
    window = check.positive_scalar(window, "window")
    with np.errstate(over="ignore"):
        begins = np.concatenate([[0.0], np.cumsum(dt[:-1])])
    check.no_overflow(begins, "the time sum(dt)", dt=dt)
    # A step belongs to the window its start falls in (tolerant of summed rounding).
    with np.errstate(over="ignore"):
        label = np.floor(begins / window + 1e-9)
    if np.all(np.isfinite(label)):
        cuts = np.concatenate([[0], np.flatnonzero(np.diff(label) != 0) + 1, [n]])
    else:  # a window below every step's length divided by 1.8e308: one step each
        cuts = np.arange(n + 1)
    zero3 = np.zeros((3, 3))
    errors, design, starts = [], [], []
    for a, b in itertools.pairwise(cuts.tolist()):
        mus, _ = _predicted(poses[a], zero3, u[a:b], dt[a:b], np.zeros(4), u, dt, poses)
        e = poses[b] - mus[-1]
        e[2] = angle_diff(poses[b, 2], mus[-1, 2])
        move = mus[-1, :2] - poses[a, :2]
        heading = math.atan2(move[1], move[0]) if np.hypot(*move) > 0 else float(poses[a, 2])
        c, s_ = math.cos(heading), math.sin(heading)
        errors.append([c * e[0] + s_ * e[1], -s_ * e[0] + c * e[1], e[2]])
        with np.errstate(over="ignore", invalid="ignore"):
            w2 = dt[a:b] ** 2
            design.append([w2 @ u[a:b, 0] ** 2, w2 @ u[a:b, 1] ** 2])
        starts.append((a, b))
    errors = np.array(errors)
    X = np.array(design)
    check.no_overflow(X, "the sums of dt² v² and dt² ω²", u=u, dt=dt)
    with np.errstate(over="ignore"):
        squared = errors[:, [0, 2]] ** 2
    check.no_overflow(squared, "the squared window errors", poses=poses, u=u, dt=dt)
    if np.count_nonzero(np.any(X > 0, axis=1)) < 2:
        raise ValueError(
            f"u, dt and window = {window!r} s give fewer than two windows with motion "
            "(sum of dt² v² or dt² ω² above 0 in float64): cannot fit the noise"
        )
    alpha = np.concatenate(
        [_nonnegative_lstsq(X, squared[:, 0]), _nonnegative_lstsq(X, squared[:, 1])]
    )
    nees_w = np.full(len(errors), np.nan)
    for w, (a, b) in enumerate(starts):
        mus, Sig = _predicted(poses[a], zero3, u[a:b], dt[a:b], alpha, u, dt, poses)
        eig = np.linalg.eigvalsh(Sig[-1])
        if eig[0] > 1e-9 * eig[-1]:
            nees_w[w] = nees(poses[b], mus[-1], Sig[-1])
    return MotionNoiseFit(alpha=alpha, windows=len(errors), errors=errors, nees=nees_w)
