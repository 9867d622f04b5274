r"""Simulated landmark worlds for the localization chapters.

Holds simulated landmark maps, control sequences and runs (true path, odometry, features).
Does not hold the filters (:mod:`probrob.localization`) or real recordings (:mod:`probrob.datasets`).

* :func:`grid_landmarks`, :func:`random_landmarks` — maps of landmarks with signatures,
  rows :math:`(x, y, s)`;
* :func:`loop_controls` — a commanded velocity sequence that drives a closed loop;
* :func:`simulate_run` — the true path executed with noisy controls (the velocity
  sampler of *Probabilistic Robotics*, Table 5.3), and range–bearing–signature
  measurements of the landmarks in a field of view with Gaussian noise (the landmark
  model of Table 6.4), as a list of filter steps :class:`Step` — the same fields as a
  dataset's ``stream()``, so one loop runs either.

Everything is seeded through ``rng`` and vectorised over time steps and landmarks.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _validation as check
from .angles import wrap_angle
from .distributions import _sample_exact_normal
from .motion import sample_motion_model_velocity, velocity_motion
from .sensors import landmark_measurement

__all__ = [
    "SimRun",
    "Step",
    "grid_landmarks",
    "loop_controls",
    "random_landmarks",
    "simulate_run",
]


@dataclass(frozen=True)
class Step:
    """One filter step: control over ``dt`` ending at ``t``, then the features seen at ``t``.

    Attributes
    ----------
    t : float
        Time at the end of the step, s.
    dt : float
        Step length, s.
    u : ndarray, shape (2,)
        Commanded :math:`(v, \\omega)`.
    z : ndarray, shape (k, 3)
        Features :math:`(r, \\phi, s)` seen at ``t``.
    c : ndarray of int, shape (k,)
        True landmark row of each feature.
    """

    t: float
    dt: float
    u: np.ndarray
    z: np.ndarray
    c: np.ndarray


@dataclass(frozen=True)
class SimRun:
    """A simulated run (its arrays are its own, and read-only).

    Attributes
    ----------
    t : ndarray, shape (T + 1,)
        Times of the poses (0 first).
    poses : ndarray, shape (T + 1, 3)
        True poses, the first one the start pose.
    commanded : ndarray, shape (T, 2)
        Commanded controls.
    odometry : ndarray, shape (T + 1, 3)
        Noise-free dead reckoning of the commands from the start pose.
    steps : list of Step
        Filter input: the command and the features seen after each motion.
    landmarks : ndarray, shape (L, 3)
    """

    t: np.ndarray
    poses: np.ndarray
    commanded: np.ndarray
    odometry: np.ndarray
    steps: list
    landmarks: np.ndarray


def _signatures(signatures, n):
    if signatures is None:
        return np.arange(n, dtype=float)
    s = check.finite(signatures, "signatures")
    if s.shape != (n,):
        raise ValueError(f"signatures must have shape ({n},), got {s.shape}")
    return s


def grid_landmarks(nx, ny, spacing, origin=(0.0, 0.0), signatures=None):
    """Return ``nx·ny`` landmarks on a regular grid, rows ``(x, y, s)``.

    Parameters
    ----------
    nx, ny : int
        Landmarks along x and y (>= 1).
    spacing : float or (float, float)
        Distance between neighbours in m (> 0), one value or (along x, along y).
    origin : (float, float)
        Position of the first landmark.
    signatures : array_like, shape (nx·ny,), optional
        Default ``0, 1, 2, …`` in row-major order.

    Returns
    -------
    m : ndarray, shape (nx·ny, 3)
    """
    nx, ny = check.count(nx, "nx", 1), check.count(ny, "ny", 1)
    sp = check.finite(spacing, "spacing")
    if sp.shape not in ((), (1,), (2,)):
        raise ValueError(f"spacing must be one value or (along x, along y), got shape {sp.shape}")
    sp = np.broadcast_to(sp, (2,))
    if np.any(sp <= 0):
        raise ValueError(f"spacing must be > 0, got {spacing!r}")
    ox, oy = check.vectors(origin, "origin", 2, "x, y")
    with np.errstate(over="ignore"):
        xs, ys = ox + sp[0] * np.arange(nx), oy + sp[1] * np.arange(ny)
    check.no_overflow(xs, "the landmarks' x", nx=nx, spacing=sp, origin=(ox, oy))
    check.no_overflow(ys, "the landmarks' y", ny=ny, spacing=sp, origin=(ox, oy))
    given = None if signatures is None else _signatures(signatures, nx * ny)
    # written in place, row by row of the grid: no (ny, nx) temporaries beside the result
    m = np.empty((nx * ny, 3))
    grid = m.reshape(ny, nx, 3)
    grid[:, :, 0] = xs
    grid[:, :, 1] = ys[:, None]
    if given is None:
        grid[:, :, 2] = np.arange(nx, dtype=float)
        grid[:, :, 2] += (nx * np.arange(ny, dtype=float))[:, None]
    else:
        m[:, 2] = given
    return m


def random_landmarks(n, bounds, *, min_distance=0.0, rng=None, signatures=None):
    """Return ``n`` landmarks drawn uniformly in a rectangle, rows ``(x, y, s)``.

    Parameters
    ----------
    n : int
        Number of landmarks (>= 1).
    bounds : (xmin, xmax, ymin, ymax)
        The rectangle, m.
    min_distance : float, optional
        Redraw a landmark that falls closer than this to an earlier one (rejection;
        gives up with ``ValueError`` if the rectangle cannot hold them).
    rng : None, int or numpy.random.Generator
    signatures : array_like, shape (n,), optional
        Default ``0, 1, …, n-1``.

    Returns
    -------
    m : ndarray, shape (n, 3)
    """
    n = check.count(n, "n", 1)
    xmin, xmax, ymin, ymax = check.vectors(bounds, "bounds", 4, "xmin, xmax, ymin, ymax")
    if not (xmax > xmin and ymax > ymin):
        raise ValueError(f"bounds must satisfy xmin < xmax and ymin < ymax, got {bounds!r}")
    min_distance = check.in_range(min_distance, "min_distance", 0.0, np.inf)
    rng = check.rng(rng)
    pts = np.empty((0, 2))
    for _ in range(1000):
        need = n - len(pts)
        if need == 0:
            break
        cand = rng.uniform((xmin, ymin), (xmax, ymax), size=(need, 2))
        for p in cand:
            if len(pts) == 0 or np.min(np.hypot(*(pts - p).T)) >= min_distance:
                pts = np.vstack([pts, p])
    if len(pts) < n:
        raise ValueError(f"cannot place {n} landmarks at min_distance {min_distance} in {bounds}")
    return np.column_stack([pts, _signatures(signatures, n)])


def _scalar(arr: np.ndarray, name: str) -> float:
    if arr.ndim != 0:
        raise ValueError(f"{name} must be a scalar, got shape {arr.shape}")
    return float(arr)


def loop_controls(T, dt, v=0.5, radius=4.0, *, wiggle=0.0, period=None):
    r"""Return ``(T, 2)`` commands :math:`(v, \omega)` that drive a circle, optionally wavy.

    :math:`\omega = v / \mathrm{radius} + \mathrm{wiggle}\cdot\sin(2\pi t / \mathrm{period})`.
    ``radius = inf`` drives straight (:math:`\omega = 0` exactly).
    """
    T = check.count(T, "T")
    dt = check.positive_scalar(dt, "dt")
    v, wiggle = (
        _scalar(check.finite(v, "v"), "v"),
        _scalar(check.finite(wiggle, "wiggle"), "wiggle"),
    )
    radius = _scalar(check.as_float_array(radius, "radius"), "radius")
    if np.isnan(radius) or radius == 0:
        raise ValueError(f"radius must be a non-zero number (inf: straight), got {radius!r}")
    if period is not None:
        period = check.positive_scalar(period, "period")
    with np.errstate(over="ignore"):
        t = dt * np.arange(T)
        turn = 0.0 if np.isinf(radius) else v / radius
    check.no_overflow(t, "the time dt * T", dt=dt, T=T)
    check.no_overflow(turn, "the turn rate v / radius", v=v, radius=radius)
    w = np.full(T, turn)
    if wiggle and T > 0:
        period = period if period is not None else dt * (T / 4)
        with np.errstate(over="ignore"):
            phase = 2 * np.pi * t / period
        if not np.all(phase < 2.0**52):  # the phase would be lost: its exact remainder
            phase = 2 * np.pi * (np.fmod(t, period) / period)
        with np.errstate(over="ignore"):
            w = w + wiggle * np.sin(phase)
        check.no_overflow(w, "the turn rate", v=v, radius=radius, wiggle=wiggle)
    return np.column_stack([np.full(T, float(v)), w])


def simulate_run(
    x0,
    controls,
    dt,
    m,
    alpha,
    sigmas,
    *,
    max_range=np.inf,
    fov=np.pi,
    rng=None,
):
    r"""Return a :class:`SimRun`: true path, noisy measurements and filter steps.

    The robot starts at ``x0`` and executes each command with noise from the velocity
    sampler (Table 5.3, exact normal draws) with :math:`\alpha_1 \ldots \alpha_4` and
    no final rotation (:math:`\alpha_5 = \alpha_6 = 0`, the motion model the EKF and UKF
    of chapter 7 assume). After each motion it measures every landmark within
    ``max_range`` and within ``±fov`` of its heading: :math:`z = h(x_t, m_j) +
    \epsilon`, :math:`\epsilon \sim N(0, \mathrm{diag}(\sigma_r^2, \sigma_\phi^2,
    \sigma_s^2))`, the bearing wrapped (the landmark model of Table 6.4).

    Parameters
    ----------
    x0 : array_like, shape (3,)
        Start pose.
    controls : array_like, shape (T, 2)
        Commanded :math:`(v, \omega)` per step.
    dt : float
        Step length, s.
    m : array_like, shape (L, 3)
        Landmarks :math:`(x, y, s)`.
    alpha : array_like, shape (4,)
        :math:`\alpha_1 \ldots \alpha_4` (variances :math:`\alpha_1 v^2 + \alpha_2\omega^2`).
    sigmas : array_like, shape (3,)
        :math:`(\sigma_r, \sigma_\phi, \sigma_s) \ge 0`.
    max_range : float, optional
        Sensor range, m.
    fov : float, optional
        Half field of view, rad (π: all around).
    rng : None, int or numpy.random.Generator

    Returns
    -------
    SimRun
    """
    x0 = check.poses(x0, "x0")
    if x0.shape != (3,):
        raise ValueError(f"x0 must have shape (3,), got {x0.shape}")
    controls = check.vectors(controls, "controls", 2, "v, omega")
    if controls.ndim != 2:
        raise ValueError(f"controls must have shape (T, 2), got {controls.shape}")
    dt = check.positive_scalar(dt, "dt")
    m = check.finite(m, "m")
    if m.ndim != 2 or m.shape[1] != 3 or m.shape[0] == 0:
        raise ValueError(f"m must have shape (L, 3) with L >= 1, got {m.shape}")
    alpha = check.alphas(alpha, "alpha", 4)
    sig = check.finite(sigmas, "sigmas")
    if sig.shape != (3,) or np.any(sig < 0):
        raise ValueError(f"sigmas must be three standard deviations >= 0, got {sigmas!r}")
    max_range = _scalar(check.as_float_array(max_range, "max_range"), "max_range")
    if not max_range > 0:  # inf (the default: no limit) is allowed, NaN is not
        raise ValueError(f"max_range must be > 0 (inf: no limit), got {max_range!r}")
    fov = check.in_range(fov, "fov", 0.0, np.pi)
    if fov == 0:
        raise ValueError(f"fov must lie in (0, π], got {fov!r}")
    rng = check.rng(rng)

    T = controls.shape[0]
    alpha6 = np.concatenate([alpha, [0.0, 0.0]])
    # Every step drawn at once from the robot's own frame (the sampler at the origin,
    # heading 0), then chained: the motion is rotation- and translation-equivariant and,
    # with γ = 0, turns the heading by ω̂Δt whatever the start pose.
    with np.errstate(over="ignore"):
        t = dt * np.arange(T + 1)
    check.no_overflow(t, "the time dt * T", dt=dt, controls=controls)
    local = sample_motion_model_velocity(
        controls, np.zeros(3), dt, alpha6, sample=_sample_exact_normal, rng=rng
    )
    with np.errstate(over="ignore", invalid="ignore"):
        poses = _chain(x0, local)
        odo = _chain(x0, velocity_motion(np.zeros(3), controls, dt))
    check.no_overflow(poses, "the true path", x0=x0, controls=controls, dt=dt)
    check.no_overflow(odo, "the dead-reckoned path", x0=x0, controls=controls, dt=dt)

    truth = landmark_measurement(poses[1:, None, :], m[None, :, :])  # (T, L, 3)
    visible = (truth[..., 0] <= max_range) & (np.abs(truth[..., 1]) <= fov)
    with np.errstate(over="ignore"):
        noise = rng.standard_normal(truth.shape) * sig
        z = truth + noise
    check.no_overflow(z, "the noisy measurements", sigmas=sig, m=m, x0=x0)
    z[..., 1] = wrap_angle(z[..., 1])
    z[..., 0] = np.abs(z[..., 0])
    steps = []
    for k in range(T):
        idx = np.flatnonzero(visible[k])
        steps.append(Step(t=float(t[k + 1]), dt=dt, u=controls[k].copy(), z=z[k, idx], c=idx))
    # the run's own arrays: not the caller's controls and m, and read-only like a recording's
    fields = dict(t=t, poses=poses, commanded=controls.copy(), odometry=odo, landmarks=m.copy())
    for arr in fields.values():
        arr.flags.writeable = False
    return SimRun(**fields, steps=steps)


def _chain(x0: np.ndarray, local: np.ndarray) -> np.ndarray:
    """Poses ``(T + 1, 3)`` from ``x0`` and per-step motions expressed in the robot frame."""
    T = local.shape[0]
    out = np.empty((T + 1, 3))
    out[0] = x0
    heading = x0[2] + np.concatenate([[0.0], np.cumsum(local[:, 2])])
    c, s = np.cos(heading[:-1]), np.sin(heading[:-1])
    out[1:, 0] = x0[0] + np.cumsum(c * local[:, 0] - s * local[:, 1])
    out[1:, 1] = x0[1] + np.cumsum(s * local[:, 0] + c * local[:, 1])
    out[1:, 2] = heading[1:]
    return out
