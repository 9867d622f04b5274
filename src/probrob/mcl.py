r"""Monte Carlo localization: particle filters over an occupancy grid (*Probabilistic Robotics*, ch. 8).

Holds MCL (Table 8.2), augmented MCL (Table 8.3), KLD-sampling MCL (Table 8.4), the low-variance
sampler (Table 4.4), uniform initial particles, a pose estimate for multimodal particle sets, the
effective sample size and a runner that collects a whole run. Does not hold the models it uses:
the odometry motion model is :mod:`probrob.motion` (Table 5.6), the range-finder models are
:mod:`probrob.sensors` (Tables 6.1, 6.3), the map and ray casting are :mod:`probrob.maps`.

Conventions: particles have shape ``(N, 3)``; ``u`` is an odometry pair ``(2, 3)`` =
:math:`(\bar x_{t-1}, \bar x_t)` in the odometry's own frame (only its relative motion is used);
``z`` holds the ranges ``(K,)`` of the beams at ``beam_angles`` ``(K,)``; ``alpha`` the four
odometry noise parameters in the variance form; ``params`` a
:class:`~probrob.sensors.BeamModelParams`. Weights are computed as log-likelihoods and normalised
by log-sum-exp, so that a scan of many beams never underflows. A particle that leaves the map has
weight zero (log-likelihood :math:`-\infty`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from scipy.special import logsumexp
from scipy.stats import norm

from . import _validation as check
from .angles import _diff as _angle_diff
from .angles import wrap_angle
from .distributions import sample_normal_distribution
from .maps import _check_grid
from .motion import sample_motion_model_odometry
from .sensors import (
    BeamModelParams,
    beam_range_finder_model,
    likelihood_field_range_finder_model,
)

__all__ = [
    "MCLRun",
    "PoseEstimate",
    "augmented_mcl",
    "effective_sample_size",
    "estimate_pose",
    "kld_sample_size",
    "kld_sampling_mcl",
    "low_variance_sampler",
    "mcl",
    "measurement_log_weights",
    "occupied_bins",
    "run_mcl",
    "selective_mcl",
    "uniform_particles",
]

_SENSORS = ("likelihood_field", "beam")
_LOG_FLOAT_MAX = math.log(np.finfo(float).max)
_MAX_PARTICLES = 10**9


# ---------------------------------------------------------------------- argument checks
def _particles(value, name: str = "particles") -> np.ndarray:
    p = check.poses(value, name)
    if p.ndim != 2 or p.shape[0] == 0:
        raise ValueError(f"{name} must have shape (N, 3) with N >= 1, got {p.shape}")
    return p


def _odometry_pair(u) -> np.ndarray:
    u = check.finite(u, "u")
    if u.shape != (2, 3):
        raise ValueError(
            f"u must be an odometry pair (x̄_{{t-1}}, x̄_t) of shape (2, 3), got {u.shape}"
        )
    return u


def _scan(z, beam_angles) -> tuple[np.ndarray, np.ndarray]:
    z = check.finite(z, "z")
    angles = check.finite(beam_angles, "beam_angles")
    if angles.ndim != 1 or angles.size == 0:
        raise ValueError(f"beam_angles must have shape (K,) with K >= 1, got {angles.shape}")
    if z.shape != angles.shape:
        raise ValueError(
            f"z must hold one range per beam: shape {angles.shape}, got {z.shape} "
            "(beam_angles has the shape (K,))"
        )
    if np.any(z < 0):
        raise ValueError(f"z must be non-negative ranges, got min {z.min()!r}")
    return z, angles


def _sensor(sensor) -> str:
    return check.choice(sensor, "sensor", _SENSORS)


def _params(params) -> BeamModelParams:
    if not isinstance(params, BeamModelParams):
        raise ValueError(f"params must be a BeamModelParams, got {type(params).__name__}")
    return params


def _exponent(exponent) -> float:
    value = check.in_range(exponent, "exponent", 0.0, 1.0)
    if value == 0.0:
        raise ValueError("exponent must lie in (0, 1]: an exponent of 0 ignores the scan")
    return value


def _weights(weights, name: str = "weights") -> np.ndarray:
    """Normalised weights, shape (N,): finite, non-negative, not all zero."""
    w = check.as_float_array(weights, name)
    if w.ndim != 1 or w.size == 0:
        raise ValueError(f"{name} must have shape (N,) with N >= 1, got {w.shape}")
    if np.any(np.isnan(w)):
        raise ValueError(f"{name} contains NaN")
    if np.any(w < 0):
        raise ValueError(f"{name} must be non-negative, got min {w.min()!r}")
    if np.any(np.isinf(w)):
        raise ValueError(f"{name} must be finite (an infinite weight cannot be normalised)")
    with np.errstate(over="ignore"):  # finite weights whose sum overflows: handled below
        total = w.sum()
    if not total > 0:
        raise ValueError(f"{name} are all zero: there is no particle to resample from")
    if not np.isfinite(total):
        w = w / w.max()  # the sum overflowed; the ratios are what matter
        total = w.sum()
    return w / total


def _normalise_log(log_w: np.ndarray) -> np.ndarray:
    """exp(log_w) / sum, shape (N,). When every weight is zero (log -inf) the scan says
    nothing about the particles: equal weights, the prior kept (as amcl does). An infinite
    density (+inf: the beam model's short-reading point mass, a reading of 0 where the map's
    range is 0) is the limit of a weight that outweighs every finite one: such particles
    share all the weight."""
    top = log_w == np.inf
    if top.any():
        return top / np.count_nonzero(top)
    if not np.any(np.isfinite(log_w)):
        return np.full(log_w.shape, 1.0 / log_w.size)
    return np.exp(log_w - logsumexp(log_w))


def _unit_draws(value, name: str, shape: tuple) -> np.ndarray:
    """Given uniform draws in [0, 1) of ``shape`` (a float for ``()``), or a ValueError."""
    u = check.finite(value, name)
    if u.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got {u.shape}")
    if np.any(u < 0) or np.any(u >= 1):
        raise ValueError(f"{name} must lie in [0, 1), got min {u.min()!r}, max {u.max()!r}")
    return float(u) if shape == () else u


# ---------------------------------------------------------------------- resampling
def low_variance_sampler(weights, size=None, rng=None, *, offset=None) -> np.ndarray:
    r"""Return the indices drawn by the low-variance sampler (*Probabilistic Robotics*, Table 4.4).

    One random number :math:`r \sim U(0, M^{-1})` (line 3) and the :math:`M` equally spaced
    pointers :math:`U = r + (m - 1) M^{-1}` (line 7); pointer :math:`m` selects the particle
    :math:`i` whose stretch of the cumulative weights holds it,
    :math:`c_{i-1} \le U < c_i` with :math:`c_i = \sum_{j \le i} w^{[j]}` (lines 4–5 and
    8–11). Every stretch is half-open and as long as its weight, so particle :math:`i` is drawn
    :math:`\lfloor M w^{[i]} \rfloor` or :math:`\lceil M w^{[i]} \rceil` times for every
    :math:`r` in :math:`[0, M^{-1})`, the end points included, and a particle of weight zero
    never. (The book's loop, ``while U > c``, takes the closed stretch
    :math:`c_{i-1} < U \le c_i`; the two differ only when a pointer falls exactly on a
    :math:`c_i`, which for a drawn :math:`r` has probability zero, but at :math:`r = 0` the
    closed stretch would draw a particle of weight zero first.)

    Parameters
    ----------
    weights : array_like, shape (N,)
        Importance weights, finite and non-negative, not all zero (normalised here).
    size : int, optional
        :math:`M`, the number of indices to draw (default ``N``).
    rng : None, int, numpy.random.SeedSequence or numpy.random.Generator, optional
    offset : float in [0, 1), optional
        A uniform draw to use for line 3 instead of one from ``rng``: :math:`r = offset / M`
        (``rng`` is then not used). For replaying given random numbers, e.g. those the
        live particle filter of :func:`probrob.widgets.particle_filter_live` embeds.

    Returns
    -------
    indices : ndarray of int, shape (M,)
        Sorted indices into ``weights``.
    """
    w = _weights(weights)
    m = w.size if size is None else check.count(size, "size", 1)
    if m > 2**52:  # the pointer counts m * c are exact integers only below 2**53
        raise ValueError(f"size must be at most 2**52 indices, got {m}")
    if offset is None:
        offset = check.rng(rng).uniform(0.0, 1.0)  # line 3: r = offset / M ~ U(0, 1/M)
    else:
        offset = _unit_draws(offset, "offset", ())  # line 3, r = offset / M given
    # Lines 4-11 for every pointer at once, in units of 1/M: pointer k = 0 .. M-1 sits at
    # k + offset, and M c_i = M sum_{j<=i} w^[j] ends the stretch of particle i. The pointers
    # below x number floor(x) + [offset < x - floor(x)], computed exactly (no r + k/M is
    # formed, whose round-off can move a pointer onto the next stretch).
    c = np.cumsum(w)
    c[np.flatnonzero(w)[-1] :] = 1.0  # the last pointer is < M: round-off must not lose it
    x = m * c
    whole = np.floor(x)
    below = np.minimum(whole + (offset < x - whole), m).astype(np.intp)
    return np.repeat(np.arange(w.size), np.diff(below, prepend=0))  # the i with c_{i-1} <= U < c_i


def effective_sample_size(weights, *, log=False) -> float:
    r"""Return :math:`N_{eff} = 1 / \sum_i \tilde w_i^2` of normalised weights :math:`\tilde w`.

    *Probabilistic Robotics*, Sec. 4.3.4 (the variance of the weights); ``N`` for equal
    weights, ``1`` when one particle carries all the weight, and always in :math:`[1, N]`.
    Computed as :math:`(\sum_i a_i)^2 / \sum_i a_i^2` of the weights divided by the largest
    (:math:`a_i = w_i / \max_j w_j`, or :math:`e^{\ell_i - \max_j \ell_j}` of log-weights
    :math:`\ell`): nothing overflows or underflows away, whatever the weights' scale.

    Parameters
    ----------
    weights : array_like, shape (N,)
        Weights (or log-weights with ``log=True``; ``-inf`` allowed there).
    log : bool
        ``weights`` are log-weights.

    Returns
    -------
    float
    """
    if check.flag(log, "log"):
        lw = check.as_float_array(weights, "weights")
        if lw.ndim != 1 or lw.size == 0 or np.any(np.isnan(lw)) or np.any(lw == np.inf):
            raise ValueError("weights (log) must have shape (N,) with no NaN and no +inf")
        if not np.isfinite(lw).any():
            raise ValueError("weights are all zero (log -inf): N_eff is undefined")
        a = np.exp(lw - lw.max())  # exact 1 at the largest: log-sum-exp loses no log 2 here
    else:
        w = _weights(weights)
        a = w / w.max()
    n_eff = float(np.sum(a) ** 2 / np.sum(a * a))
    return min(max(n_eff, 1.0), float(a.size))  # rounding never takes it out of [1, N]


# ---------------------------------------------------------------------- initial particles
def uniform_particles(grid, n, rng=None, *, free=None, uniforms=None) -> np.ndarray:
    r"""Draw ``n`` poses uniformly over the free space of a map, headings uniform in :math:`[-\pi, \pi)`.

    The prior of global localization (*Probabilistic Robotics*, Sec. 8.3). A free cell is drawn
    uniformly (all cells have the same area), then a point uniformly inside it.

    Parameters
    ----------
    grid : OccupancyGrid
    n : int
        Number of particles (>= 1).
    rng : None, int, numpy.random.SeedSequence or numpy.random.Generator, optional
    free : array_like of bool, shape (H, W), optional
        The cells to draw from (default: the grid's :attr:`~probrob.maps.OccupancyGrid.free`
        cells; for a map built from scans, those its beams saw, so that no particle starts
        in unexplored space).
    uniforms : array_like, shape (n, 4), optional
        Uniform draws in [0, 1) to use instead of ``rng`` (which is then not used): per
        particle, the free cell ``floor(u0 * count)`` in row-major order of the free cells,
        the point ``(j + u1, i + u2)`` cells from the origin inside it, and the heading
        :math:`-\pi + 2\pi u_3`. For replaying given random numbers (the live particle
        filter of :func:`probrob.widgets.particle_filter_live`).

    Returns
    -------
    particles : ndarray, shape (n, 3)
    """
    grid = _check_grid(grid)
    n = check.count(n, "n", 1)
    gen = check.rng(rng)
    if free is None:
        mask = grid.free
    else:
        mask = np.asarray(free)
        if mask.dtype != bool or mask.shape != grid.shape:
            raise ValueError(
                f"free must be a boolean array of the grid's shape {grid.shape}, "
                f"got {mask.dtype} {mask.shape}"
            )
    cells = np.flatnonzero(mask)
    if cells.size == 0:
        raise ValueError("the map has no free cell to draw particles from")
    if n > _MAX_PARTICLES:  # numpy's "Maximum allowed dimension exceeded", or MemoryError
        raise ValueError(f"n = {n} particles is more than {_MAX_PARTICLES:.0e}, 24 GB of poses")
    if uniforms is None:
        pick = cells[gen.integers(cells.size, size=n)]
        inside = gen.random((n, 2))
        theta = gen.uniform(-np.pi, np.pi, size=n)
    else:
        u = _unit_draws(uniforms, "uniforms", (n, 4))
        pick = cells[np.floor(u[:, 0] * cells.size).astype(np.intp)]
        inside = u[:, 1:3]
        theta = -np.pi + (2.0 * np.pi) * u[:, 3]  # as Generator.uniform(-π, π)
    i, j = np.divmod(pick, grid.shape[1])
    xy = grid.origin + (np.stack([j, i], axis=-1) + inside) * grid.resolution
    return np.column_stack([xy, theta])


# ---------------------------------------------------------------------- the measurement step
def measurement_log_weights(
    particles, z, grid, beam_angles, params, *, sensor="likelihood_field", exponent=1.0
) -> np.ndarray:
    r"""Return :math:`\log p(z_t \mid x_t^{[m]}, m)` for every particle (Table 8.2, line 5).

    The range-finder model is the likelihood field (Table 6.3) or the beam model (Table 6.1),
    with the beams taken as independent; ``exponent`` :math:`< 1` tempers the product
    (:math:`p^{\,exponent}`), the book's remedy for the overconfidence of independent beams
    (Sec. 6.3.4). Particles outside the map get :math:`-\infty`.

    Parameters
    ----------
    particles : array_like, shape (N, 3)
    z : array_like, shape (K,)
        Ranges (m); readings at ``params.max_range`` are max-range readings.
    grid : OccupancyGrid
    beam_angles : array_like, shape (K,)
    params : BeamModelParams
    sensor : {"likelihood_field", "beam"}
    exponent : float in (0, 1]

    Returns
    -------
    log_w : ndarray, shape (N,)
    """
    x = _particles(particles)
    z, angles = _scan(z, beam_angles)
    grid = _check_grid(grid)
    p = _params(params)
    sensor = _sensor(sensor)
    exponent = _exponent(exponent)
    return _log_weights(x, z, grid, angles, p, sensor, exponent)


# Particles are weighted in blocks: an (N, K) array of end points for 10,000 particles does not
# fit in the cache, one of 512 does (the results are the same to the bit).
_BLOCK = 512


def _log_weights(x, z, grid, angles, params, sensor, exponent):
    inside = np.flatnonzero(grid.contains(x[:, :2]))
    log_w = np.full(x.shape[0], -np.inf)
    model = (
        likelihood_field_range_finder_model
        if sensor == "likelihood_field"
        else beam_range_finder_model
    )
    for start in range(0, inside.size, _BLOCK):
        rows = inside[start : start + _BLOCK]
        log_w[rows] = exponent * np.asarray(
            model(z, x[rows], grid, angles, params, log=True)
        ).reshape(-1)
    return log_w


def _predict(x, u, alpha, gen, sample=sample_normal_distribution):
    """Table 8.2, line 4: x_t^[m] ~ p(x_t | u_t, x_{t-1}^[m]), the odometry model (Table 5.6)."""
    return sample_motion_model_odometry(u, x, alpha, sample=sample, rng=gen)


def _checked(particles, u, z, grid, beam_angles, alpha, params, sensor, exponent, rng):
    return (
        _particles(particles),
        _odometry_pair(u),
        *_scan(z, beam_angles),
        _check_grid(grid),
        check.alphas(alpha, "alpha", 4),
        _params(params),
        _sensor(sensor),
        _exponent(exponent),
        check.rng(rng),
    )


# ---------------------------------------------------------------------- Table 8.2
def mcl(
    particles,
    u,
    z,
    grid,
    beam_angles,
    alpha,
    params,
    *,
    sensor="likelihood_field",
    exponent=1.0,
    rng=None,
    sample=sample_normal_distribution,
    resample_offset=None,
) -> np.ndarray:
    r"""One step of Monte Carlo localization (*Probabilistic Robotics*, Table 8.2).

    For every particle: a motion sample from the odometry model (line 4), its weight
    :math:`p(z_t \mid x_t^{[m]}, m)` (line 5); then :math:`M` particles drawn with probability
    proportional to their weights (lines 8–11), by the low-variance sampler (Table 4.4) rather
    than independent draws.

    Parameters
    ----------
    particles : array_like, shape (N, 3)
        :math:`\mathcal X_{t-1}`, equally weighted.
    u : array_like, shape (2, 3)
        Odometry pair :math:`(\bar x_{t-1}, \bar x_t)`.
    z : array_like, shape (K,)
        Ranges of the scan (m).
    grid : OccupancyGrid
    beam_angles : array_like, shape (K,)
    alpha : array_like, shape (4,)
        Odometry noise :math:`\alpha_1 \ldots \alpha_4` (variance form).
    params : BeamModelParams
    sensor : {"likelihood_field", "beam"}
    exponent : float in (0, 1], optional
        Tempering of the beam product (see :func:`measurement_log_weights`); 1 is the book's.
    rng : None, int, numpy.random.SeedSequence or numpy.random.Generator, optional
    sample : callable, optional
        The zero-mean sampler of the motion model, ``sample(b2, size=..., rng=...)``, as
        :func:`~probrob.motion.sample_motion_model_odometry` takes it (default the book's
        :func:`~probrob.distributions.sample_normal_distribution`). Called three times, for
        :math:`\hat\delta_{rot1}`, :math:`\hat\delta_{trans}`, :math:`\hat\delta_{rot2}`, with
        ``size=(N,)``.
    resample_offset : float in [0, 1), optional
        The low-variance sampler's random number as a uniform draw (``offset`` of
        :func:`low_variance_sampler`); default drawn from ``rng``. With ``sample`` it replays
        given random numbers (the live particle filter's test does).

    Returns
    -------
    particles : ndarray, shape (N, 3)
        :math:`\mathcal X_t`, equally weighted.

    Notes
    -----
    When every particle has weight zero (each left the map, or the scan has probability
    zero at each of them, as under a mixture without ``z_rand``), the weights carry no
    information: the moved particles are kept with equal weights, as amcl does. A filter
    in that state is lost; :func:`augmented_mcl` is the one that recovers.
    """
    x, u, z, angles, grid, alpha, p, sensor, exponent, gen = _checked(
        particles, u, z, grid, beam_angles, alpha, params, sensor, exponent, rng
    )
    x_bar = _predict(x, u, alpha, gen, sample)  # line 4
    w = _normalise_log(_log_weights(x_bar, z, grid, angles, p, sensor, exponent))  # line 5
    return x_bar[low_variance_sampler(w, rng=gen, offset=resample_offset)]  # lines 8-11


def selective_mcl(
    particles,
    weights,
    u,
    z,
    grid,
    beam_angles,
    alpha,
    params,
    *,
    threshold=0.5,
    sensor="likelihood_field",
    exponent=1.0,
    rng=None,
) -> tuple[np.ndarray, np.ndarray]:
    r"""One step of MCL that resamples only when the weights have degenerated (Sec. 4.3.4).

    Table 8.2 with its weights carried over: every particle is moved (line 4) and its weight
    multiplied by :math:`p(z_t \mid x_t^{[m]}, m)` (line 5); lines 8–11, the low-variance
    resampling, run only when the effective sample size
    :math:`N_{eff} = 1 / \sum_m \tilde w_m^2` has fallen below ``threshold`` :math:`\cdot M`
    (*Probabilistic Robotics*, Sec. 4.3.4, "resampling frequency"). Resampling less often loses
    fewer particles to the sampler's variance; resampling too seldom lets the weights
    degenerate.

    Parameters
    ----------
    particles : array_like, shape (M, 3)
    weights : array_like, shape (M,) or None
        Their weights (normalised here; ``None``: equal).
    u, z, grid, beam_angles, alpha, params, sensor, exponent, rng
        As :func:`mcl`.
    threshold : float in [0, 1]
        Resample when :math:`N_{eff} < threshold \cdot M`: 1 resamples at every step whose
        weights are not all equal (as :func:`mcl` does at every step), 0 never.

    Returns
    -------
    particles : ndarray, shape (M, 3)
    weights : ndarray, shape (M,)
        Normalised; equal after a resampling.
    """
    x, u, z, angles, grid, alpha, p, sensor, exponent, gen = _checked(
        particles, u, z, grid, beam_angles, alpha, params, sensor, exponent, rng
    )
    n = x.shape[0]
    w_prev = np.full(n, 1.0 / n) if weights is None else _weights(weights)
    if w_prev.size != n:
        raise ValueError(f"weights must have shape ({n},), got {w_prev.shape}")
    threshold = check.in_range(threshold, "threshold", 0.0, 1.0)
    x_bar = _predict(x, u, alpha, gen)  # line 4
    with np.errstate(divide="ignore"):
        log_w = np.log(w_prev) + _log_weights(x_bar, z, grid, angles, p, sensor, exponent)
    w = _normalise_log(log_w)  # line 5, times the weight carried over
    if 1.0 / np.sum(w * w) < threshold * n:
        return x_bar[low_variance_sampler(w, rng=gen)], np.full(n, 1.0 / n)  # lines 8-11
    return x_bar, w


# ---------------------------------------------------------------------- Table 8.3
def augmented_mcl(
    particles,
    u,
    z,
    grid,
    beam_angles,
    alpha,
    params,
    w_slow,
    w_fast,
    *,
    alpha_slow=0.001,
    alpha_fast=0.1,
    sensor="likelihood_field",
    exponent=1.0,
    free=None,
    rng=None,
    sample=sample_normal_distribution,
) -> tuple[np.ndarray, float, float]:
    r"""One step of augmented MCL, with random particles for recovery (*Probabilistic Robotics*, Table 8.3).

    As :func:`mcl`, and the running averages of the mean measurement likelihood
    :math:`w_{avg} = M^{-1}\sum_m w_t^{[m]}` (line 9):
    :math:`w_{slow} \mathrel{+}= \alpha_{slow}(w_{avg} - w_{slow})`,
    :math:`w_{fast} \mathrel{+}= \alpha_{fast}(w_{avg} - w_{fast})` (lines 11–12). Each new
    particle is, with probability :math:`\max(0, 1 - w_{fast}/w_{slow})`, a pose drawn
    uniformly over the free space, and otherwise drawn by weight (lines 14–18). The number of
    random particles is drawn once (binomial); the others come from the low-variance sampler.
    When every particle has weight zero, the whole set is drawn anew uniformly (the book's
    ratio :math:`w_{fast}/w_{slow}` is then undefined; a lost filter re-localizes). ROS amcl
    also resets both averages to zero after each injection; this function follows the book.

    Parameters
    ----------
    particles, u, z, grid, beam_angles, alpha, params
        As :func:`mcl`.
    w_slow, w_fast : float
        The averages returned by the previous call (``0.0`` at the start), on the likelihood's
        linear scale (a 60-beam likelihood is of order :math:`10^{\pm 40}`; both must be finite).
    alpha_slow, alpha_fast : float
        Decay rates, :math:`0 \le \alpha_{slow} \ll \alpha_{fast} \le 1`.
    sensor, exponent, rng
        As :func:`mcl`.
    free : array_like of bool, shape (H, W), optional
        Where random particles are drawn (see :func:`uniform_particles`).
    sample : callable, optional
        The motion model's zero-mean sampler (line 6), as :func:`mcl` takes it.

    Returns
    -------
    particles : ndarray, shape (N, 3)
    w_slow, w_fast : float
    """
    x, u, z, angles, grid, alpha, p, sensor, exponent, gen = _checked(
        particles, u, z, grid, beam_angles, alpha, params, sensor, exponent, rng
    )
    w_slow = check.finite(w_slow, "w_slow")
    w_fast = check.finite(w_fast, "w_fast")
    if w_slow.ndim or w_fast.ndim or w_slow < 0 or w_fast < 0:
        raise ValueError(f"w_slow and w_fast must be scalars >= 0, got {w_slow!r}, {w_fast!r}")
    a_slow = check.in_range(alpha_slow, "alpha_slow", 0.0, 1.0)
    a_fast = check.in_range(alpha_fast, "alpha_fast", 0.0, 1.0)
    if not a_slow < a_fast:
        raise ValueError(f"need alpha_slow < alpha_fast, got {a_slow!r} and {a_fast!r}")
    n = x.shape[0]
    x_bar = _predict(x, u, alpha, gen, sample)  # line 6
    log_w = _log_weights(x_bar, z, grid, angles, p, sensor, exponent)  # line 7
    log_avg = logsumexp(log_w) - math.log(n) if np.isfinite(log_w).any() else -math.inf
    if log_avg > _LOG_FLOAT_MAX:  # math.exp would raise OverflowError
        raise check.overflow_error(
            f"the mean measurement likelihood w_avg of Table 8.3 (log w_avg = {log_avg:.6g}; "
            "too many beams on a linear scale: use fewer beams or exponent < 1)",
            z=z,
            exponent=exponent,
            **{"params.sigma_hit": p.sigma_hit, "params.max_range": p.max_range},
        )
    w_avg = math.exp(log_avg)
    w_slow = float(w_slow) + a_slow * (w_avg - float(w_slow))  # line 11
    w_fast = float(w_fast) + a_fast * (w_avg - float(w_fast))  # line 12
    p_random = max(0.0, 1.0 - w_fast / w_slow) if w_slow > 0 else 0.0  # line 14
    n_random = int(gen.binomial(n, p_random)) if p_random > 0 else 0
    if n_random == n or not np.isfinite(log_w).any():
        return uniform_particles(grid, n, gen, free=free), w_slow, w_fast
    w = _normalise_log(log_w)
    drawn = x_bar[low_variance_sampler(w, size=n - n_random, rng=gen)]  # lines 17-18
    if n_random:
        drawn = np.concatenate([drawn, uniform_particles(grid, n_random, gen, free=free)])
    return drawn, w_slow, w_fast


# ---------------------------------------------------------------------- Table 8.4
def kld_sample_size(k, epsilon=0.05, delta=0.01) -> int:
    r"""Return the KLD bound :math:`M_\chi` on the number of particles (*Probabilistic Robotics*, Table 8.4).

    .. math::
        M_\chi = \frac{k-1}{2\varepsilon}\left\{1 - \frac{2}{9(k-1)}
                 + \sqrt{\frac{2}{9(k-1)}}\, z_{1-\delta}\right\}^3

    (Fox 2003): with probability :math:`1 - \delta`, the Kullback–Leibler divergence between
    the sample-based maximum-likelihood estimate and the true posterior over :math:`k` occupied
    bins stays below :math:`\varepsilon`. :math:`z_{1-\delta}` is the upper
    :math:`1 - \delta` quantile of the standard normal (2.326 for :math:`\delta = 0.01`), not the
    probability itself.

    Parameters
    ----------
    k : int
        Number of occupied bins, ``k >= 2``.
    epsilon : float
        Error bound :math:`\varepsilon > 0`.
    delta : float
        :math:`\delta \in (0, 1/2)`: a bound that holds with probability :math:`1 - \delta`
        of at most one half promises nothing (and the formula, with :math:`z_{1-\delta} \le 0`,
        can fall below one particle).

    Returns
    -------
    m : int
        :math:`\lceil M_\chi \rceil`, at least 1.
    """
    k = check.count(k, "k", 2)
    epsilon, z = _kld_constants(epsilon, delta)
    return int(_kld_bound(np.array([k]), epsilon, z)[0])


def _kld_constants(epsilon, delta) -> tuple[float, float]:
    """(ε, z_{1-δ}) checked, or a ValueError naming the argument."""
    epsilon = check.positive_scalar(epsilon, "epsilon")
    delta = check.in_range(delta, "delta", 0.0, 0.5)
    if not 0.0 < delta < 0.5:
        raise ValueError(
            f"delta must lie strictly between 0 and 0.5 (the bound holds with probability "
            f"1 - delta), got {delta!r}"
        )
    return epsilon, float(norm.isf(delta))  # z_{1-delta}


# The largest bound returned: far above any particle count a machine can hold.
_KLD_MAX = 2.0**53


def _kld_bound(k: np.ndarray, epsilon: float, z: float) -> np.ndarray:
    """⌈M_χ(k)⌉ for an int array k >= 2 (Table 8.4, line 15), at least 1; a ValueError
    when it exceeds 2**53 (an ε too small for a count of particles)."""
    km1 = k.astype(float) - 1.0
    a = 2.0 / (9.0 * km1)
    with np.errstate(over="ignore"):
        m = km1 / (2.0 * epsilon) * (1.0 - a + np.sqrt(a) * z) ** 3
    if np.any(~(m <= _KLD_MAX)):
        raise ValueError(
            f"the KLD bound exceeds 2**53 particles (epsilon = {epsilon!r} is too small)"
        )
    return np.maximum(np.ceil(m), 1.0).astype(np.int64)


# Histogram bins are labelled by integer cells; beyond 2**52 cells from the origin a float
# pose no longer separates neighbouring cells (and int64 codes could wrap).
_BIN_LIMIT = 2.0**52


def _bin_cells(x: np.ndarray, bin_size: np.ndarray, name: str = "particles") -> np.ndarray:
    """The (x, y, θ) histogram cell of each particle, int64 (N, 3); θ wrapped first."""
    pose = np.column_stack([x[:, :2], wrap_angle(x[:, 2])])
    with np.errstate(over="ignore", invalid="ignore"):
        scaled = np.floor(pose / bin_size)
    if not np.all(np.abs(scaled) < _BIN_LIMIT):
        raise ValueError(
            f"{name} lie more than 2**52 bins from the origin at bin_size {tuple(bin_size)}: "
            "they cannot be binned exactly (is bin_size too small, or a pose too far?)"
        )
    return scaled.astype(np.int64)


def _bin_sizes(bin_size) -> np.ndarray:
    bins = check.finite(bin_size, "bin_size")
    if bins.shape != (3,) or np.any(bins <= 0):
        raise ValueError(f"bin_size must be 3 positive sizes (x, y, θ), got {bin_size!r}")
    return bins


def occupied_bins(particles, bin_size=(0.5, 0.5, np.pi / 18)) -> int:
    r"""Return :math:`k`, the number of histogram bins that a particle set occupies (Table 8.4).

    Parameters
    ----------
    particles : array_like, shape (N, 3)
    bin_size : array_like, shape (3,)
        Bin sides in x (m), y (m) and θ (rad); θ is wrapped to :math:`[-\pi, \pi)` first.

    Returns
    -------
    k : int
    """
    x = _particles(particles)
    return int(np.unique(_row_labels(_bin_cells(x, _bin_sizes(bin_size)))).size)


def _row_labels(cells: np.ndarray) -> np.ndarray:
    """One int64 per row of ``cells`` (N, 3), equal exactly for equal rows: each column's rank
    among its distinct values, combined (np.unique over rows sorts 3-column records, ~20
    times slower)."""
    label, size = np.zeros(cells.shape[0], dtype=np.int64), 1
    for column in cells.T:
        values, rank = np.unique(column, return_inverse=True)
        size *= values.size
        if size >= 2**62:  # cannot happen below 2**20 rows; kept exact beyond
            return np.unique(cells, axis=0, return_inverse=True)[1].reshape(-1)
        label = label * values.size + rank.reshape(-1)
    return label


def _new_bins(cells: np.ndarray, seen: int) -> np.ndarray:
    """For the rows ``cells[seen:]``: whether each is the first of its bin among all rows."""
    _, first = np.unique(_row_labels(cells), return_index=True)
    flag = np.zeros(cells.shape[0], dtype=bool)
    flag[first] = True
    return flag[seen:]


def kld_sampling_mcl(
    particles,
    u,
    z,
    grid,
    beam_angles,
    alpha,
    params,
    *,
    weights=None,
    epsilon=0.05,
    delta=0.01,
    bin_size=(0.5, 0.5, np.pi / 18),
    n_min=100,
    n_max=100_000,
    sensor="likelihood_field",
    exponent=1.0,
    rng=None,
    sample=sample_normal_distribution,
) -> tuple[np.ndarray, np.ndarray]:
    r"""One step of KLD-sampling MCL (*Probabilistic Robotics*, Table 8.4).

    Each new particle is made as Table 8.4 makes it: an index :math:`j` drawn from the previous
    set with probability :math:`w_{t-1}^{[j]}` (line 8), a fresh motion sample from
    :math:`x_{t-1}^{[j]}` (line 9), its weight (line 10); if it falls into an empty histogram
    bin, :math:`k` grows and with it the bound :math:`M_\chi` of :func:`kld_sample_size`
    (lines 12–16); particles are made until :math:`M \ge M_\chi` and
    :math:`M \ge M_{\chi_{min}}` (line 18). The set returned is weighted, as the table's is:
    the next step draws from its weights.

    The table's loop runs here in rounds, each vectorised: a round draws the missing
    :math:`M_\chi - M` indices at once by the low-variance sampler (Table 4.4, put in random
    order), samples their motion and weights them; the first particle of the round after
    which the table's loop would stop (:math:`M \ge M_\chi(k)`, with :math:`k` counted over
    every particle made so far, in order) ends the set. A round costs :math:`O(N)` for the
    draw plus :math:`O(M \log M)` for the bins, against amcl's :math:`O(NM)` linear searches of
    the cumulative weights; from a spread-out set a step takes a few rounds.

    Parameters
    ----------
    particles, u, z, grid, beam_angles, alpha, params, sensor, exponent, rng
        As :func:`mcl`.
    weights : array_like, shape (N,), optional
        :math:`w_{t-1}`, the weights of ``particles`` (as this function returned them;
        default: equal weights).
    epsilon, delta : float
        The KLD bound's :math:`\varepsilon` and :math:`\delta`.
    bin_size : array_like, shape (3,)
        Bin sides in x (m), y (m) and θ (rad).
    n_min, n_max : int
        Bounds on the number of particles made (:math:`M_{\chi_{min}}` and a cap).
    sample : callable, optional
        The motion model's zero-mean sampler (line 9), as :func:`mcl` takes it; called three
        times per round, with ``size=(L,)`` for the round's ``L`` new particles.

    Returns
    -------
    particles : ndarray, shape (M, 3)
        :math:`\mathcal X_t`, ``n_min <= M <= n_max``.
    weights : ndarray, shape (M,)
        :math:`w_t`, normalised (equal when every particle has weight zero, as in :func:`mcl`).
    """
    x, u, z, angles, grid, alpha, p, sensor, exponent, gen = _checked(
        particles, u, z, grid, beam_angles, alpha, params, sensor, exponent, rng
    )
    w_prev = None if weights is None else _weights(weights)
    if w_prev is not None and w_prev.size != x.shape[0]:
        raise ValueError(f"weights must have shape ({x.shape[0]},), got {w_prev.shape}")
    if w_prev is None:
        w_prev = np.full(x.shape[0], 1.0 / x.shape[0])
    epsilon, z_delta = _kld_constants(epsilon, delta)
    bins = _bin_sizes(bin_size)
    n_min = check.count(n_min, "n_min", 1)
    n_max = check.count(n_max, "n_max", 1)
    if n_min > n_max:
        raise ValueError(f"need n_min <= n_max, got {n_min} and {n_max}")
    made, log_w, cells = [], [], np.empty((0, 3), dtype=np.int64)
    m, k, target = 0, 0, n_min  # line 3: M = 0, k = 0 (and M_chi_min)
    while m < target:  # line 18
        j = gen.permutation(low_variance_sampler(w_prev, size=target - m, rng=gen))  # line 8
        x_new = _predict(x[j], u, alpha, gen, sample)  # line 9
        lw_new = _log_weights(x_new, z, grid, angles, p, sensor, exponent)  # line 10
        cells = np.concatenate([cells, _bin_cells(x_new, bins)])
        k_after = k + np.cumsum(_new_bins(cells, m))  # lines 12-14, after each new particle
        m_after = m + 1 + np.arange(x_new.shape[0])  # line 17
        m_chi = np.where(k_after > 1, _kld_bound(np.maximum(k_after, 2), epsilon, z_delta), 0)
        stop = (m_after >= np.maximum(m_chi, n_min)) | (m_after >= n_max)
        keep = int(np.argmax(stop)) + 1 if stop.any() else x_new.shape[0]
        made.append(x_new[:keep])  # line 11
        log_w.append(lw_new[:keep])
        m, k = m + keep, int(k_after[keep - 1])
        target = m if stop.any() else min(n_max, max(n_min, int(m_chi[-1])))
    return np.concatenate(made), _normalise_log(np.concatenate(log_w))


# ---------------------------------------------------------------------- estimates
class PoseEstimate(NamedTuple):
    """The pose of the heaviest cluster of a particle set (:func:`estimate_pose`)."""

    pose: np.ndarray
    """Weighted mean (x, y, θ) of the cluster, shape (3,); θ by circular mean."""
    fraction: float
    """The share of the total weight inside the cluster (1 for a unimodal, converged set)."""


def _dense_ranks(column: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct values of ``column - 1``, ``column``, ``column + 1`` (int64, sorted) and
    the rank of each entry of ``column`` among them: neighbouring cells keep neighbouring
    labels, and a label never exceeds 3 N, however far the cells are from the origin."""
    values = np.unique(np.concatenate([column - 1, column, column + 1]))
    return values, np.searchsorted(values, column)


def estimate_pose(particles, weights=None, *, radius=0.5, heading_bins=12) -> PoseEstimate:
    r"""Return the pose of the heaviest cluster of particles, right for a multimodal set.

    The mean of a multimodal particle set lies between its modes, often inside a wall, and
    the mean heading of two headings half a turn apart is one that neither has. Here the
    particles are binned in :math:`(x, y, \theta)`: squares of side ``radius`` and
    ``heading_bins`` equal sectors of heading that wrap at :math:`\pm\pi` (as amcl's k-d
    tree bins in :math:`(x, y, \theta)`). The block of 3 × 3 × 3 bins that holds the most
    weight seeds the cluster (a block, so that a mode split by bin edges is not outweighed
    by a smaller one that fits in one bin; ties go to the first block in (x, y, θ) order);
    the cluster holds every particle within ``2·radius`` of the block's weighted mean in x
    and y and within two sectors of its circular mean heading; the estimate is the cluster's
    weighted mean (circular in θ). The cluster spans at most four sectors of heading, less
    than half a turn, so its mean heading lies among its particles' headings. Compare amcl,
    which reports the mean of its heaviest k-d-tree cluster.

    Parameters
    ----------
    particles : array_like, shape (N, 3)
    weights : array_like, shape (N,), optional
        Default: equal weights.
    radius : float
        Cluster scale in x and y (m), > 0.
    heading_bins : int
        Number of heading sectors, 9 (so that a cluster spans less than half a turn) to
        2**20; the default 12 makes them 30° wide.

    Returns
    -------
    PoseEstimate

    Raises
    ------
    ValueError
        Naming the argument, for a bad one; naming ``particles`` and ``radius`` when a
        particle lies 2**52 or more bins of side ``radius`` from the origin, where
        floating-point positions no longer separate neighbouring bins.
    """
    x = _particles(particles)
    w = np.full(x.shape[0], 1.0 / x.shape[0]) if weights is None else _weights(weights)
    if w.size != x.shape[0]:
        raise ValueError(f"weights must have shape ({x.shape[0]},), got {w.shape}")
    radius = check.positive_scalar(radius, "radius")
    n_theta = check.count(heading_bins, "heading_bins", minimum=9)
    if n_theta > 2**20:  # sectors below a microradian: the int64 bin labels would not hold
        raise ValueError(f"heading_bins must be at most 2**20, got {n_theta}")
    with np.errstate(over="ignore", invalid="ignore"):
        scaled = np.floor(x[:, :2] / radius)
    if not np.all(np.abs(scaled) < _BIN_LIMIT):
        far = float(np.max(np.abs(x[:, :2])))
        raise ValueError(
            f"particles lie {far:.3g} m from the origin, 2**52 or more bins of radius "
            f"{radius!r} m: they cannot be binned exactly (is radius too small, or a "
            "particle too far?)"
        )
    cells = scaled.astype(np.int64)
    theta = wrap_angle(x[:, 2])
    sector = 2.0 * np.pi / n_theta
    k_theta = np.minimum(np.floor((theta + np.pi) / sector), n_theta - 1).astype(np.int64)
    # dense labels: x and y by rank (neighbours included), θ by sector; at most 9 N² n_theta
    values_x, rank_x = _dense_ranks(cells[:, 0])
    values_y, rank_y = _dense_ranks(cells[:, 1])
    span_y = values_y.size
    if (values_x.size * span_y) * n_theta >= 2**62:
        raise ValueError(
            f"too many particles ({x.shape[0]}) for the int64 bin labels at heading_bins {n_theta}"
        )
    label = (rank_x * span_y + rank_y) * n_theta + k_theta
    keys, first, inverse = np.unique(label, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    # equal weights: whole counts, so that ties between blocks are exact (and broken by order)
    mass = np.bincount(inverse, weights=None if weights is None else w, minlength=len(keys))
    key_x, key_y, key_t = cells[first, 0], cells[first, 1], k_theta[first]
    block = np.zeros(len(keys))
    for di in (-1, 0, 1):
        rx = np.searchsorted(values_x, key_x + di)
        for dj in (-1, 0, 1):
            ry = np.searchsorted(values_y, key_y + dj)
            for dk in (-1, 0, 1):
                target = (rx * span_y + ry) * n_theta + (key_t + dk) % n_theta
                pos = np.minimum(np.searchsorted(keys, target), len(keys) - 1)
                block += np.where(keys[pos] == target, mass[pos], 0.0)
    best = int(np.argmax(block))
    seed = np.all(np.abs(cells - cells[first[best]]) <= 1, axis=1) & (
        np.abs((k_theta - key_t[best] + 1) % n_theta) <= 2
    )
    ws = w[seed]
    centre = np.average(x[seed, :2], axis=0, weights=ws)
    heading = math.atan2(
        float(np.sum(ws * np.sin(theta[seed]))), float(np.sum(ws * np.cos(theta[seed])))
    )
    near = np.all(np.abs(x[:, :2] - centre) <= 2.0 * radius, axis=1) & (
        np.abs(_angle_diff(theta, heading)) <= 2.0 * sector
    )
    wc = w[near]
    xy = np.average(x[near, :2], axis=0, weights=wc)
    theta_c = math.atan2(
        float(np.sum(wc * np.sin(theta[near]))), float(np.sum(wc * np.cos(theta[near])))
    )
    return PoseEstimate(np.array([xy[0], xy[1], theta_c]), float(wc.sum()))


# ---------------------------------------------------------------------- a whole run
@dataclass(frozen=True, eq=False)
class MCLRun:
    """What :func:`run_mcl` collects over a run of T steps (all arrays read-only)."""

    estimates: np.ndarray
    """(T + 1, 3): :func:`estimate_pose` of the initial set, then after each step."""
    fraction: np.ndarray
    """(T + 1,): the weight share of the estimate's cluster."""
    n_particles: np.ndarray
    """(T + 1,): particles in each set."""
    w_slow: np.ndarray
    """(T + 1,): augmented MCL's slow average (zeros for the other methods)."""
    w_fast: np.ndarray
    """(T + 1,): augmented MCL's fast average (zeros for the other methods)."""
    seconds: np.ndarray
    """(T,): wall-clock time of each step."""
    snapshots: dict
    """Step index -> particles (n, 3) kept at the steps asked for."""
    snapshot_weights: dict
    """Step index -> their weights (n,), normalised (equal but for KLD-sampling's and selective
    resampling's sets)."""
    resampled: np.ndarray
    """(T,) bool: whether each step's set came out equally weighted, i.e. resampled (always
    but for :func:`selective_mcl`, and for it also when a scan weighted every particle alike,
    as when all have left the map)."""


def run_mcl(
    particles,
    odometry,
    scans,
    grid,
    beam_angles,
    alpha,
    params,
    *,
    method="mcl",
    keep=(),
    rng=None,
    on_step: Callable | None = None,
    **options,
) -> MCLRun:
    r"""Run a particle filter over a log and collect its estimates.

    Parameters
    ----------
    particles : array_like, shape (N, 3)
        The initial set (e.g. :func:`uniform_particles`, or a cloud around a known start).
    odometry : array_like, shape (T, 2, 3)
        One odometry pair per step.
    scans : array_like, shape (T, K)
        The scan at the end of each step.
    grid, beam_angles, alpha, params
        As :func:`mcl`.
    method : {"mcl", "augmented", "kld", "selective"}
        :func:`mcl`, :func:`augmented_mcl`, :func:`kld_sampling_mcl` or :func:`selective_mcl`.
    keep : iterable of int
        Steps whose particle sets are kept in :attr:`MCLRun.snapshots` (0 = the initial set),
        their weights in :attr:`MCLRun.snapshot_weights`.
    rng : None, int, numpy.random.SeedSequence or numpy.random.Generator, optional
    on_step : callable, optional
        ``on_step(t, particles)`` after step ``t`` (1-based) returns the particles to go on
        with (e.g. to teleport the robot for a kidnapping test), or ``None`` to keep them.
    **options
        Passed to the step function (``sensor``, ``exponent``, ``alpha_slow``, ``epsilon``, …).

    Returns
    -------
    MCLRun

    Notes
    -----
    KLD-sampling's and selective resampling's sets are weighted (Table 8.4 returns :math:`w_t`
    with :math:`\mathcal X_t`): the run passes each step's weights to the next and estimates the
    pose with them.
    """
    x = _particles(particles)
    u_all = check.finite(odometry, "odometry")
    z_all = check.finite(scans, "scans")
    if u_all.ndim != 3 or u_all.shape[1:] != (2, 3):
        raise ValueError(f"odometry must have shape (T, 2, 3), got {u_all.shape}")
    if z_all.ndim != 2 or z_all.shape[0] != u_all.shape[0]:
        raise ValueError(
            f"scans must have shape (T, K) with T = {u_all.shape[0]} (odometry's), got {z_all.shape}"
        )
    method = check.choice(method, "method", ("mcl", "augmented", "kld", "selective"))
    gen = check.rng(rng)
    n_steps = u_all.shape[0]
    if isinstance(keep, str) or not hasattr(keep, "__iter__"):
        raise ValueError(f"keep must be an iterable of step indices, got {keep!r}")
    keep = {check.count(k, "keep", 0) for k in keep}
    if any(k > n_steps for k in keep):
        raise ValueError(f"keep holds steps after the last one ({n_steps}): {sorted(keep)}")
    est = np.empty((n_steps + 1, 3))
    frac = np.empty(n_steps + 1)
    count = np.empty(n_steps + 1, dtype=np.int64)
    w_slow_t = np.zeros(n_steps + 1)
    w_fast_t = np.zeros(n_steps + 1)
    seconds = np.empty(n_steps)
    resampled = np.ones(n_steps, dtype=bool)
    snapshots, snapshot_weights = {}, {}
    w_slow = w_fast = 0.0
    w = None  # equal weights, but for KLD-sampling's sets

    def record(t, x):
        e = estimate_pose(x, w)
        est[t], frac[t], count[t] = e.pose, e.fraction, x.shape[0]
        w_slow_t[t], w_fast_t[t] = w_slow, w_fast
        if t in keep:
            snapshots[t] = x.copy()
            n = x.shape[0]
            snapshot_weights[t] = np.full(n, 1.0 / n) if w is None else w.copy()

    record(0, x)
    for t in range(n_steps):
        start = time.perf_counter()
        args = (x, u_all[t], z_all[t], grid, beam_angles, alpha, params)
        if method == "mcl":
            x = mcl(*args, rng=gen, **options)
        elif method == "augmented":
            x, w_slow, w_fast = augmented_mcl(*args, w_slow, w_fast, rng=gen, **options)
        elif method == "kld":
            x, w = kld_sampling_mcl(*args, weights=w, rng=gen, **options)
        else:
            x, w = selective_mcl(x, w, *args[1:], rng=gen, **options)
            resampled[t] = bool(np.all(w == w[0]))
        seconds[t] = time.perf_counter() - start
        if on_step is not None:
            replaced = on_step(t + 1, x)
            if replaced is not None:
                x = _particles(replaced)
                if w is not None and w.size != x.shape[0]:
                    w = None  # a new set of another size: equal weights
        record(t + 1, x)
    for arr in (est, frac, count, w_slow_t, w_fast_t, seconds, resampled):
        arr.flags.writeable = False
    return MCLRun(
        est, frac, count, w_slow_t, w_fast_t, seconds, snapshots, snapshot_weights, resampled
    )
