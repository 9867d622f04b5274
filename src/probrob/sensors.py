r"""Measurement models of *Probabilistic Robotics*, chapter 6 (Tables 6.1–6.5).

Holds the measurement models of Tables 6.1–6.5 and :math:`h, H` of Table 7.2, lines 11–13.
Does not hold maps or ray casting (:mod:`probrob.maps`) or the filters (:mod:`probrob.localization`).

Landmark models (Tables 6.4, 6.5; deck ``001`` "Modelo Landmark", "Modelo Sample Landmark"):

* :func:`landmark_measurement` — the noise-free range–bearing–signature measurement
  :math:`h(x, m_j) = (\hat r, \hat\phi, s_j)` of a landmark seen from a pose; the EKF and the
  UKF of chapter 7 use it as their measurement function, so it exists once, here;
* :func:`landmark_measurement_jacobian` — :math:`H = \partial h / \partial x` (Table 7.2,
  line 13);
* :func:`landmark_model_known_correspondence` — :math:`p(f \mid c, x, m)`, Table 6.4;
* :func:`sample_landmark_model_known_correspondence` — poses drawn from one feature,
  Table 6.5.

Conventions: a feature is :math:`f = (r, \phi, s)` (range in m, bearing in rad relative to the
robot's heading, counter-clockwise positive, and a signature); a map ``m`` is an array of
landmark rows :math:`(x, y, s)`; ``sigmas`` are the **standard deviations**
:math:`(\sigma_r, \sigma_\phi, \sigma_s)`. The book's ``prob(a, b^2)`` of Table 5.2 takes a
variance, so these functions pass :math:`\sigma^2` to it (the deck passes :math:`\sigma`:
errata L1). Bearing differences are wrapped to :math:`[-\pi, \pi)`.

Range finder models (Tables 6.1–6.3; deck ``001`` "Modelo Range Beam Finder",
"Modelo Learn Intrinsic Parameters", "Modelo Likelihood Field Range"):

* :class:`BeamModelParams` — the intrinsic parameters :math:`\Theta` of the beam model;
* :func:`beam_model_components`, :func:`beam_mixture` — the four components of
  :math:`p(z \mid z^*)` and their mixture (eqs. 6.4–6.12), for given expected ranges;
* :func:`beam_range_finder_model` — Table 6.1: the product over the beams of a scan,
  with the expected ranges ray cast in an :class:`~probrob.maps.OccupancyGrid`;
* :func:`sample_beam_mixture` — draws ranges from the mixture (synthetic data);
* :func:`learn_intrinsic_parameters` — Table 6.2: EM for :math:`\Theta`, corrected;
* :func:`likelihood_field_range_finder_model` — Table 6.3, with a precomputed
  log-likelihood table (:func:`likelihood_field_table`).

Every range finder model takes ``log=True`` (summed log-likelihoods): the product of 180
beam likelihoods underflows in double precision. Deck departures are errata B1–B5 in
``book/errata.md``: the E-step of Table 6.2 must weigh each component by its mixing
weight; readings at :math:`z_{max}` are a point mass, not a density value; the M-step of
:math:`\lambda_{short}` (and, near the ends of the range, of :math:`\sigma_{hit}`) must
account for the truncation of the components; the likelihood field adds
:math:`z_{rand}/z_{max}`, not :math:`z_{random}/z_{hit}`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numba import njit
from scipy.special import erf, ndtr, ndtri

from . import _validation as check
from .angles import _wrap, _wrap_one, wrap_angle
from .distributions import prob_normal_distribution, sample_normal_distribution
from .maps import _check_grid, _check_inside, ray_cast

__all__ = [
    "BeamModelParams",
    "EMInfo",
    "beam_mixture",
    "beam_model_components",
    "beam_range_finder_model",
    "landmark_measurement",
    "landmark_measurement_jacobian",
    "landmark_model_known_correspondence",
    "learn_intrinsic_parameters",
    "likelihood_field_range_finder_model",
    "likelihood_field_table",
    "sample_beam_mixture",
    "sample_landmark_model_known_correspondence",
]

_TWO_PI = 2.0 * np.pi


# --------------------------------------------------------------------------- landmarks


def _landmark_rows(m, name: str = "m") -> np.ndarray:
    """A finite landmark array whose last axis is (x, y) or (x, y, s)."""
    arr = check.finite(m, name)
    if arr.ndim == 0 or arr.shape[-1] not in (2, 3):
        raise ValueError(
            f"{name} must have shape (..., 2) (x, y) or (..., 3) (x, y, s), got shape {arr.shape}"
        )
    return arr


def _map(m) -> np.ndarray:
    arr = _landmark_rows(m)
    if arr.ndim != 2 or arr.shape[0] == 0:
        raise ValueError(
            f"m must be a non-empty map of landmark rows, shape (L, 3) (x, y, s), got shape "
            f"{arr.shape}"
        )
    return arr


def _correspondences(c, count: int) -> np.ndarray:
    arr = np.asarray(c)
    if arr.dtype.kind not in "iu" and not (
        arr.dtype.kind == "f" and np.all(np.isfinite(arr)) and np.all(arr == np.round(arr))
    ):
        raise ValueError(f"c must hold integer landmark indices, got {c!r}")
    # the range before the cast: an integral 1e300 would wrap the index type
    if np.any(arr < 0) or np.any(arr >= count):
        raise ValueError(f"c must index the map's {count} landmarks (0..{count - 1}), got {c!r}")
    return arr.astype(np.intp, copy=False)


def _feature_rows(f: np.ndarray) -> np.ndarray:
    """Features (..., 2 or 3) whose ranges r are >= 0: no sensor measures a negative range
    (the filters' :func:`probrob._validation.features` refuses it the same way)."""
    if f.size and np.any(f[..., 0] < 0):
        raise ValueError(f"f: ranges r must be >= 0, got min {float(f[..., 0].min())!r}")
    return f


def _relative(x, m):
    dx = m[..., 0] - x[..., 0]
    dy = m[..., 1] - x[..., 1]
    return dx, dy


@njit(cache=True, error_model="numpy")
def _range_bearing_one(dx: float, dy: float, th: float):
    """:func:`_range_bearing` of floats, compiled (for the EKF's per-feature loop)."""
    return math.hypot(dx, dy), _wrap_one(math.atan2(dy, dx) - th)


def _range_bearing(dx, dy, th):
    r"""Range :math:`\sqrt q` and wrapped bearing :math:`\mathrm{atan2}(\delta_y, \delta_x) - \theta`.

    ``dx, dy`` the landmark minus the pose, ``th`` the heading: floats or arrays (unchecked).
    """
    if type(dx) is type(dy) is type(th) is float:
        return _range_bearing_one(dx, dy, th)
    return np.hypot(dx, dy), _wrap(np.arctan2(dy, dx) - th)


_COINCIDES = "x coincides with a landmark of m: the bearing has no Jacobian there"


@njit(cache=True, error_model="numpy")
def _jacobian_entries_one(dx: float, dy: float):
    """:func:`_jacobian_entries` of floats, compiled (for the EKF's per-feature loop)."""
    q = dx * dx + dy * dy
    if q == 0.0:
        raise ValueError(_COINCIDES)
    if q == math.inf:  # q beyond float64 (a landmark 1e154 m away): through r = hypot
        r = math.hypot(dx, dy)
        return -dx / r, -dy / r, dy / r / r, -dx / r / r
    r = math.sqrt(q)
    return -dx / r, -dy / r, dy / q, -dx / q


def _jacobian_entries(dx, dy):
    r"""The entries :math:`H_{11}, H_{12}, H_{21}, H_{22}` of Table 7.2, line 13.

    ``dx, dy`` the landmark minus the pose (floats or arrays, unchecked). Raises
    ``ValueError`` where the pose coincides with its landmark (:math:`q = 0`).
    """
    if type(dx) is type(dy) is float:
        return _jacobian_entries_one(dx, dy)
    with np.errstate(over="ignore"):
        q = dx * dx + dy * dy
    if np.any(q == 0):
        raise ValueError(_COINCIDES)
    if np.any(np.isinf(q)):
        # q beyond float64 (a landmark 1e154 m away): the same entries through r = hypot
        r = np.hypot(dx, dy)
        return -dx / r, -dy / r, dy / r / r, -dx / r / r
    r = np.sqrt(q)
    return -dx / r, -dy / r, dy / q, -dx / q


def _landmark_measurement_core(x: np.ndarray, m: np.ndarray, batch=None) -> np.ndarray:
    """:func:`landmark_measurement` on validated float arrays, unchecked."""
    if batch is None:
        batch = np.broadcast_shapes(x.shape[:-1], m.shape[:-1])
    dx, dy = _relative(x, m)
    out = np.empty((*batch, m.shape[-1]))
    out[..., 0], out[..., 1] = _range_bearing(dx, dy, x[..., 2])
    if m.shape[-1] == 3:
        out[..., 2] = m[..., 2]
    return out


def _landmark_jacobian_core(x: np.ndarray, m: np.ndarray, batch=None) -> np.ndarray:
    """:func:`landmark_measurement_jacobian` on validated float arrays (checks q = 0 only)."""
    if batch is None:
        batch = np.broadcast_shapes(x.shape[:-1], m.shape[:-1])
    dx, dy = _relative(x, m)
    H = np.zeros((*batch, m.shape[-1], 3))
    H[..., 0, 0], H[..., 0, 1], H[..., 1, 0], H[..., 1, 1] = _jacobian_entries(dx, dy)
    H[..., 1, 2] = -1.0
    return H


def landmark_measurement(x, m):
    r"""Return the noise-free measurement :math:`h(x, m_j)` of landmark(s) ``m`` from pose(s) ``x``.

    *Probabilistic Robotics*, Table 6.4, lines 3–4 (and :math:`\hat z` of Table 7.2, line 12):

    .. math::
        \hat r = \sqrt{(m_{j,x} - x)^2 + (m_{j,y} - y)^2}, \qquad
        \hat\phi = \operatorname{atan2}(m_{j,y} - y,\ m_{j,x} - x) - \theta,

    and, if the landmark has a signature, :math:`\hat s = s_j`. The bearing is wrapped to
    :math:`[-\pi, \pi)`. Deck ``001`` omits :math:`-\theta` (errata L2). A pose on the
    landmark (:math:`\hat r = 0`) has bearing :math:`\operatorname{atan2}(0, 0) - \theta =
    -\theta` by numpy's convention.

    Parameters
    ----------
    x : array_like, shape (..., 3)
        Poses :math:`(x, y, \theta)`.
    m : array_like, shape (..., 2) or (..., 3)
        Landmarks :math:`(x, y)` or :math:`(x, y, s)`; broadcast against ``x``'s batch.

    Returns
    -------
    z_hat : ndarray, shape (..., 2) or (..., 3)
        :math:`(\hat r, \hat\phi)` or :math:`(\hat r, \hat\phi, s)`.
    """
    x = check.poses(x, "x")
    m = _landmark_rows(m)
    batch = check.batch_shape(x=x.shape[:-1], m=m.shape[:-1])
    return _measured(x, m, batch)


def _measured(x, m, batch=None):
    """:func:`_landmark_measurement_core`, a range beyond float64 reported against x and m."""
    with np.errstate(over="ignore"):
        z_hat = _landmark_measurement_core(x, m, batch)
    check.no_overflow(z_hat[..., 0], "the range to the landmark", x=x, m=m)
    return z_hat


def landmark_measurement_jacobian(x, m):
    r"""Return :math:`H = \partial h(x, m_j) / \partial x`, the Jacobian of :func:`landmark_measurement`.

    *Probabilistic Robotics*, Table 7.2, line 13, with :math:`q = (m_{j,x}-x)^2 +
    (m_{j,y}-y)^2`:

    .. math::
        H = \begin{pmatrix}
            -\frac{m_{j,x}-x}{\sqrt q} & -\frac{m_{j,y}-y}{\sqrt q} & 0 \\
             \frac{m_{j,y}-y}{q} & -\frac{m_{j,x}-x}{q} & -1 \\
             0 & 0 & 0
        \end{pmatrix}

    (the third row only when ``m`` carries signatures). The range row divides by
    :math:`\sqrt q`, the bearing row by :math:`q`.

    Parameters
    ----------
    x : array_like, shape (..., 3)
        Poses.
    m : array_like, shape (..., 2) or (..., 3)
        Landmarks, broadcast against ``x``'s batch.

    Returns
    -------
    H : ndarray, shape (..., 2, 3) or (..., 3, 3)

    Raises
    ------
    ValueError
        If a pose coincides with its landmark (:math:`q = 0`: the bearing has no derivative).
    """
    x = check.poses(x, "x")
    m = _landmark_rows(m)
    batch = check.batch_shape(x=x.shape[:-1], m=m.shape[:-1])
    with np.errstate(over="ignore"):
        dx, dy = _relative(x, m)
        r = np.hypot(dx, dy)
    check.no_overflow(r, "the distance to the landmark", x=x, m=m)
    return _landmark_jacobian_core(x, m, batch)


def _variances(sig):
    """σ² of standard deviations; one beyond float64 (σ > 1.3e154) reported against sigmas."""
    with np.errstate(over="ignore"):
        sig2 = np.square(sig)
    check.no_overflow(sig2, "the variance sigmas**2", sigmas=sig)
    return sig2


def landmark_model_known_correspondence(f, c, x, m, sigmas, *, log=False):
    r"""Return the likelihood :math:`p(f \mid c, x, m)` of a landmark feature, Table 6.4.

    *Probabilistic Robotics*, Table 6.4:

    .. math::
        q = \mathrm{prob}(r - \hat r, \sigma_r^2)\;
            \mathrm{prob}(\phi - \hat\phi, \sigma_\phi^2)\;
            \mathrm{prob}(s - s_j, \sigma_s^2)

    with :math:`j = c` and :math:`(\hat r, \hat\phi) = h(x, m_j)` of
    :func:`landmark_measurement`; ``prob`` is the normal density of Table 5.2, which takes a
    variance. Corrections to deck ``001``: it passes :math:`\sigma` where the variance
    belongs (errata L1), omits :math:`-\theta` in :math:`\hat\phi` (L2), and does not wrap
    :math:`\phi - \hat\phi` (L3).

    A zero standard deviation makes its factor a point mass (as in :mod:`probrob.distributions`): the likelihood is
    0 (``-inf`` with ``log=True``) where that component differs, ``inf`` where it matches
    exactly.

    Parameters
    ----------
    f : array_like, shape (..., 3)
        Features :math:`(r, \phi, s)`.
    c : array_like of int, shape (...)
        Landmark index of each feature (the correspondence), a row of ``m``.
    x : array_like, shape (..., 3)
        Poses; ``f``, ``c`` and ``x`` broadcast together (e.g. one feature against a
        particle set ``(N, 3)``).
    m : array_like, shape (L, 3)
        The map: landmark rows :math:`(x, y, s)`.
    sigmas : array_like, shape (3,)
        Standard deviations :math:`(\sigma_r, \sigma_\phi, \sigma_s) \ge 0`.
    log : bool, optional
        Return :math:`\log q`, computed in log space (no underflow for far-off poses).

    Returns
    -------
    q : float or ndarray, broadcast batch shape
    """
    log = check.flag(log, "log")
    f = _feature_rows(check.vectors(f, "f", 3, "r, phi, s"))
    x = check.poses(x, "x")
    m = _map(m)
    if m.shape[-1] != 3:
        raise ValueError(f"m must have shape (L, 3) (x, y, s) for signatures, got {m.shape}")
    c = _correspondences(c, m.shape[0])
    sig = check.sigmas(sigmas, "sigmas", (3,), positive=False)
    sig2 = _variances(sig)
    check.batch_shape(f=f.shape[:-1], c=c.shape, x=x.shape[:-1])
    z_hat = _measured(x, m[c])
    errors = (
        f[..., 0] - z_hat[..., 0],
        _wrap(f[..., 1] - z_hat[..., 1]),
        f[..., 2] - z_hat[..., 2],
    )
    terms = [
        np.asarray(prob_normal_distribution(e, s2, log=True))
        for e, s2 in zip(errors, sig2, strict=True)
    ]
    with np.errstate(invalid="ignore"):  # inf + (-inf), resolved on the next line
        logq = terms[0] + terms[1] + terms[2]
    # inf + (-inf): one component a matched point mass, another missed: the likelihood is 0.
    logq = np.where(np.isnan(logq), -np.inf, logq)
    return check.scalar_or_array(logq if log else np.exp(logq))


def sample_landmark_model_known_correspondence(
    f, c, m, sigmas, size=None, rng=None, *, sample: Callable = sample_normal_distribution
):
    r"""Draw poses :math:`x \sim p(x \mid f, c, m)` from one landmark feature, Table 6.5.

    *Probabilistic Robotics*, Table 6.5:

    .. math::
        \hat\gamma = \mathrm{rand}(0, 2\pi),\quad
        \hat r = r + \mathrm{sample}(\sigma_r^2),\quad
        \hat\phi = \phi + \mathrm{sample}(\sigma_\phi^2),

    .. math::
        x = m_{j,x} + \hat r\cos\hat\gamma,\quad
        y = m_{j,y} + \hat r\sin\hat\gamma,\quad
        \theta = \hat\gamma - \pi - \hat\phi .

    The heading is right (deck ``001`` prints it correctly): the landmark is seen from
    :math:`(x, y)` in direction :math:`\hat\gamma + \pi`, and :math:`\phi = \hat\gamma + \pi -
    \theta`. ``sample`` takes a variance (Table 5.4), so :math:`\sigma^2` is passed where
    the deck passes :math:`\sigma` (errata L1). The returned :math:`\theta` is wrapped to
    :math:`[-\pi, \pi)`. The signature plays no part.

    The poses' density is :math:`\frac{1}{2\pi\hat r}\,\mathcal N(\hat r; r, \sigma_r^2)\,
    \mathcal N(\hat\phi; \phi, \sigma_\phi^2)` (the Jacobian of
    :math:`(\hat\gamma, \hat r, \hat\phi) \mapsto (x, y, \theta)` is :math:`\hat r`): exactly
    the range and bearing noise of Table 6.4 around a uniform ring.

    Parameters
    ----------
    f : array_like, shape (..., 2) or (..., 3)
        Features :math:`(r, \phi[, s])`.
    c : array_like of int, shape (...)
        Landmark index of each feature.
    m : array_like, shape (L, 2) or (L, 3)
        The map.
    sigmas : array_like, shape (2,) or (3,)
        Standard deviations :math:`(\sigma_r, \sigma_\phi[, \sigma_s])`; :math:`\sigma_s`
        is not used.
    size : int or tuple of ints, optional
        Shape of the batch of poses; the batch of ``f`` and ``c`` must broadcast to it.
    rng : None, int or numpy.random.Generator, optional
        Source of randomness.
    sample : callable, optional
        ``sample(b2, size=..., rng=...)``, a zero-mean sampler with variance ``b2``;
        default the book's sum of twelve uniforms (Table 5.4).

    Returns
    -------
    x : ndarray, shape size + (3,)
        Sampled poses :math:`(x, y, \theta)`.
    """
    f = check.finite(f, "f")
    if f.ndim == 0 or f.shape[-1] not in (2, 3):
        raise ValueError(f"f must have shape (..., 3) (r, phi, s) or (..., 2), got {f.shape}")
    f = _feature_rows(f)
    m = _map(m)
    c = _correspondences(c, m.shape[0])
    sig = check.sigmas(sigmas, "sigmas", (2, 3), positive=False)
    check.callable_arg(sample, "sample")
    shape = check.output_shape(check.batch_shape(f=f.shape[:-1], c=c.shape), size)
    rng = check.rng(rng)

    sig2 = _variances(sig)
    gamma = rng.uniform(0.0, _TWO_PI, size=shape)
    r_hat = f[..., 0] + check.sample_output(
        sample(sig2[0], size=shape, rng=rng), "sample", shape, sample
    )
    phi_hat = f[..., 1] + check.sample_output(
        sample(sig2[1], size=shape, rng=rng), "sample", shape, sample
    )
    landmark = m[c]
    out = np.empty((*shape, 3))
    out[..., 0] = landmark[..., 0] + r_hat * np.cos(gamma)
    out[..., 1] = landmark[..., 1] + r_hat * np.sin(gamma)
    out[..., 2] = wrap_angle(gamma - np.pi - phi_hat)
    return out


# ---------------------------------------------------------------------- range finders
_LOG_SQRT_2PI = 0.5 * np.log(2.0 * np.pi)
_SQRT2 = math.sqrt(2.0)
_LOG_FLOAT_MAX = math.log(np.finfo(float).max)
_WEIGHT_TOL = 1e-6


@dataclass(frozen=True)
class BeamModelParams:
    r"""Intrinsic parameters :math:`\Theta` of the beam model (Table 6.1, eq. 6.12).

    Parameters
    ----------
    z_hit, z_short, z_max, z_rand : float
        Mixing weights (non-negative, summing to 1 within 1e-6).
    sigma_hit : float
        Standard deviation of the measurement noise of :math:`p_{hit}`, in metres.
    lambda_short : float
        Rate of the exponential :math:`p_{short}`, in 1/m.
    max_range : float
        The sensor's maximum range :math:`z_{max}`, in metres.
    """

    z_hit: float
    z_short: float
    z_max: float
    z_rand: float
    sigma_hit: float
    lambda_short: float
    max_range: float

    def __post_init__(self):
        names = ("z_hit", "z_short", "z_max", "z_rand")
        for name in (*names, "sigma_hit", "lambda_short", "max_range"):
            value = check.finite(getattr(self, name), name)
            if value.ndim != 0:
                raise ValueError(f"{name} must be a scalar, got shape {value.shape}")
            object.__setattr__(self, name, float(value))
        for name in names:
            if getattr(self, name) < 0:
                raise ValueError(f"{name} is a mixing weight and must be >= 0")
        total = sum(getattr(self, n) for n in names)
        if abs(total - 1.0) > _WEIGHT_TOL:
            raise ValueError(
                f"the weights z_hit + z_short + z_max + z_rand must sum to 1, got {total!r}"
            )
        for name in ("sigma_hit", "lambda_short", "max_range"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)!r}")

    @property
    def weights(self) -> np.ndarray:
        """``(z_hit, z_short, z_max, z_rand)`` as an array of shape ``(4,)``."""
        return np.array([self.z_hit, self.z_short, self.z_max, self.z_rand])


def _check_params(params) -> BeamModelParams:
    if not isinstance(params, BeamModelParams):
        raise ValueError(f"params must be a BeamModelParams, got {type(params).__name__}")
    return params


def _check_ranges(z, name, max_range):
    """Ranges must be finite and >= 0; readings beyond ``max_range`` become ``max_range``."""
    z = check.finite(z, name)
    if np.any(z < 0):
        raise ValueError(f"{name} must be non-negative ranges, got min {float(z.min())!r}")
    return np.minimum(z, max_range)


def _scan_inputs(z, x, beam_angles, log):
    """Check a scan's poses, beam angles and ``log`` flag against its (checked) ranges ``z``."""
    x = check.poses(x, "x")
    log = check.flag(log, "log")
    angles = check.finite(beam_angles, "beam_angles")
    if z.ndim == 0 or angles.ndim != 1 or z.shape[-1] != angles.size:
        raise ValueError(
            f"z must have shape (..., K) with K = len(beam_angles) = {angles.size}, got {z.shape}"
        )
    check.batch_shape(z=z.shape[:-1], x=x.shape[:-1])
    return x, angles, log


def _check_expected(z_star, max_range):
    z_star = check.finite(z_star, "z_star")
    if np.any((z_star < 0) | (z_star > max_range)):
        raise ValueError("z_star must lie in [0, max_range] (expected ranges)")
    return z_star


# ---------------------------------------------------------------------- components
def _hit_mass(z_star, sigma, max_range):
    """The N(z*, σ²) mass on [0, z_max] (the normaliser of p_hit, eq. 6.6):
    Φ(b) − Φ(a) with a = −z*/σ ≤ 0 ≤ b = (z_max − z*)/σ.

    Where both ends lie within a fraction of σ of z* (σ far above z_max) the difference of
    two Φ near 1/2 cancels to nothing; the sum of the two half masses, erf(b/√2)/2 +
    erf(−a/√2)/2, does not (it is used where the mass is below 1/4, the same number to
    rounding elsewhere). A subnormal σ makes a and b infinite: Φ is exact there.
    """
    with np.errstate(over="ignore", divide="ignore"):
        a, b = -z_star / sigma, (max_range - z_star) / sigma
    mass = ndtr(b) - ndtr(a)
    small = mass < 0.25
    if np.any(small):
        halves = 0.5 * (erf(b / _SQRT2) + erf(-a / _SQRT2))
        mass = np.where(small, halves, mass)
    return mass


def _hit_log_mass(z_star, sigma, max_range):
    """log of the N(z*, σ²) mass on [0, z_max] (:func:`_hit_mass`)."""
    return np.log(_hit_mass(z_star, sigma, max_range))


def _log_components(z, z_star, p: BeamModelParams):
    """log p_hit, log p_short, log p_max, log p_rand; shape broadcast(z, z_star) + (4,)."""
    z, z_star = np.broadcast_arrays(z, z_star)
    zmax, sigma, lam = p.max_range, p.sigma_hit, p.lambda_short
    with np.errstate(over="ignore"):  # a tiny σ: u² is inf far from z*, log p_hit -inf
        u = (z - z_star) / sigma
        log_hit = -0.5 * u * u - np.log(sigma) - _LOG_SQRT_2PI - _hit_log_mass(z_star, sigma, zmax)
    positive = z_star > 0
    zs = np.where(positive, z_star, 1.0)
    with np.errstate(divide="ignore"):
        log_short = np.where(
            positive,
            np.log(lam) - lam * z - np.log(-np.expm1(-lam * zs)),
            np.where(z == 0, np.inf, -np.inf),  # z* = 0: a point mass at 0
        )
    log_short = np.where(z <= z_star, log_short, -np.inf)
    at_max = z >= zmax
    log_max = np.where(at_max, 0.0, -np.inf)
    log_rand = np.where(at_max, -np.inf, -np.log(zmax))
    return np.stack([log_hit, log_short, log_max, log_rand], axis=-1)


def beam_model_components(z, z_star, params, *, log=False):
    r"""Return :math:`p_{hit}, p_{short}, p_{max}, p_{rand}` of the beam model.

    *Probabilistic Robotics*, eqs. 6.4–6.10 (the components of Table 6.1, line 5):

    .. math::
        p_{hit}(z) &= \eta\,\mathcal N(z; z^*, \sigma_{hit}^2), \quad
            \eta = \Big(\int_0^{z_{max}} \mathcal N(z; z^*, \sigma_{hit}^2)\,dz\Big)^{-1}
            \quad (0 \le z \le z_{max}) \\
        p_{short}(z) &= \frac{\lambda_{short}\, e^{-\lambda_{short} z}}
            {1 - e^{-\lambda_{short} z^*}} \quad (0 \le z \le z^*) \\
        p_{max}(z) &= I(z = z_{max}), \qquad
        p_{rand}(z) = \frac{1}{z_{max}} \quad (0 \le z < z_{max})

    and 0 elsewhere. :math:`p_{max}` is a point mass: its value 1 at :math:`z_{max}` is
    a probability, the others are densities. Where :math:`z^* = 0`, :math:`p_{short}`
    is its limit, a point mass at 0 (``inf`` at ``z == 0``, 0 elsewhere).

    Parameters
    ----------
    z : array_like
        Measured ranges in metres (>= 0); readings beyond ``max_range`` count as
        ``max_range``.
    z_star : array_like, broadcastable with ``z``
        Expected ranges in :math:`[0, z_{max}]`.
    params : BeamModelParams
    log : bool
        Return the logarithms (``-inf`` off the support).

    Returns
    -------
    p : ndarray, shape broadcast(z, z_star) + (4,)
        The four components along the last axis.
    """
    p = _check_params(params)
    log = check.flag(log, "log")
    z = _check_ranges(z, "z", p.max_range)
    z_star = _check_expected(z_star, p.max_range)
    check.batch_shape(z=z.shape, z_star=z_star.shape)
    out = _log_components(z, z_star, p)
    if log:
        return out
    with np.errstate(over="ignore"):
        linear = np.exp(out)
    _no_hit_overflow(out[..., 0], z, z_star, p)
    return linear


def _no_hit_overflow(log_hit, z, z_star, p):
    """p_hit beyond float64 (at z* for a σ_hit near the smallest float, 1.8e308 per metre;
    finite in logs) is reported against the arguments. Not p_short's 1/z* for a subnormal
    z*, which is the point mass at 0 that z* = 0 has (inf, as documented)."""
    check.no_overflow(
        np.where(np.isfinite(log_hit) & (log_hit > _LOG_FLOAT_MAX), np.inf, 0.0),
        "the beam model's density (finite with log=True)",
        z=z,
        z_star=z_star,
        **{"params.sigma_hit": p.sigma_hit},
    )


def _mixture(z, z_star, p: BeamModelParams, log):
    """Beam mixture without input checks; see :func:`beam_mixture`."""
    zmax, sigma, lam = p.max_range, p.sigma_hit, p.lambda_short
    z, z_star = np.broadcast_arrays(z, z_star)
    with np.errstate(over="ignore", invalid="ignore"):  # extreme σ: redone in logs below
        u = (z - z_star) / sigma
        q = (p.z_hit / (sigma * np.sqrt(2.0 * np.pi))) * np.exp(-0.5 * u * u)
        # p_hit's normaliser differs from 1 (in double precision) only within 9σ of 0 or z_max.
        near = (z_star < 9.0 * sigma) | (z_star > zmax - 9.0 * sigma)
    if near.any():
        zn = z_star[near]
        q = np.array(q, dtype=float)  # writable, also for 0-d input
        q[near] /= _hit_mass(zn, sigma, zmax)
    lost = ~np.isfinite(q)  # σ near the smallest float: inf · 0 far from z*, inf at it
    if np.any(lost):
        q = np.array(q, dtype=float)
        with np.errstate(over="ignore"):
            q[lost] = np.exp(_log_components(z[lost], z_star[lost], p)[..., 0] + np.log(p.z_hit))
    at_max = z >= zmax
    if p.z_short > 0:
        positive = z_star > 0
        zs = np.where(positive, z_star, 1.0)
        with np.errstate(divide="ignore", over="ignore"):  # z* subnormal: 1/z* is inf
            short = lam * np.exp(-lam * z) / -np.expm1(-lam * zs)
        short = np.where(positive, short, np.where(z == 0, np.inf, 0.0))
        q += p.z_short * np.where(z <= z_star, short, 0.0)
    q += np.where(at_max, p.z_max, p.z_rand / zmax)
    if not log:
        return q
    with np.errstate(divide="ignore"):
        out = np.asarray(np.log(q))
    # the hit term underflowed and nothing else is left, or it overflowed: redo in logs
    under = (q == 0) | (np.isposinf(q) & ~(z_star == 0))
    if np.any(under):
        lc = _log_components(z[under], z_star[under], p)
        with np.errstate(divide="ignore", invalid="ignore"):  # 0-weight terms: inf + -inf
            terms = np.where(p.weights > 0, lc + np.log(p.weights), -np.inf)
        out[under] = _logsumexp(terms, axis=-1)
    return out


def _logsumexp(a, axis):
    m = np.max(a, axis=axis, keepdims=True)
    finite_m = np.where(np.isfinite(m), m, 0.0)
    with np.errstate(divide="ignore"):
        s = np.log(np.sum(np.exp(a - finite_m), axis=axis, keepdims=True)) + finite_m
    s = np.where(np.isposinf(m), np.inf, s)
    return np.squeeze(s, axis=axis)


def beam_mixture(z, z_star, params, *, log=False):
    r"""Return the beam model's :math:`p(z \mid z^*)` for one beam (Table 6.1, lines 5-6).

    .. math:: p = z_{hit} p_{hit} + z_{short} p_{short} + z_{max} p_{max}
              + z_{rand} p_{rand}

    with the components of :func:`beam_model_components`. Over :math:`[0, z_{max}]` the
    density part integrates to :math:`1 - z_{max}` and the point mass at
    :math:`z_{max}` holds :math:`z_{max}` (the weight).

    Parameters
    ----------
    z : array_like
        Measured ranges (m, >= 0); readings beyond ``max_range`` count as ``max_range``.
    z_star : array_like, broadcastable with ``z``
        Expected ranges in :math:`[0, z_{max}]`.
    params : BeamModelParams
    log : bool
        Return :math:`\log p` (computed without underflow).

    Returns
    -------
    p : float or ndarray, shape broadcast(z, z_star)
    """
    p = _check_params(params)
    log = check.flag(log, "log")
    z = _check_ranges(z, "z", p.max_range)
    z_star = _check_expected(z_star, p.max_range)
    check.batch_shape(z=z.shape, z_star=z_star.shape)
    q = _mixture(z, z_star, p, log)
    if not log and np.any(np.isposinf(q)):  # p_hit's overflow, or p_short's point mass?
        z_b, zs_b = np.broadcast_arrays(z, z_star)
        inf = np.isposinf(q)
        log_hit = np.full(q.shape, -np.inf)
        log_hit[inf] = _log_components(z_b[inf], zs_b[inf], p)[..., 0] + math.log(p.z_hit or 1.0)
        _no_hit_overflow(log_hit, z, z_star, p)
    return check.scalar_or_array(q)


def beam_range_finder_model(z, x, grid, beam_angles, params, *, log=False, method="hybrid"):
    r"""Return :math:`p(z_t \mid x_t, m)` of the beam model (*Probabilistic Robotics*, Table 6.1).

    .. math:: p(z_t \mid x_t, m) = \prod_{k=1}^K p(z_t^k \mid z_t^{k*})

    with :math:`z_t^{k*}` ray cast in ``grid`` (:func:`~probrob.maps.ray_cast`) and
    :math:`p(z \mid z^*)` the mixture of :func:`beam_mixture`.

    Parameters
    ----------
    z : array_like, shape (..., K)
        Measured ranges of a scan (m); readings beyond ``params.max_range`` count as
        max-range readings.
    x : array_like, shape (..., 3)
        Sensor poses (x, y, θ) inside the map, e.g. particles ``(N, 3)``.
    grid : OccupancyGrid
    beam_angles : array_like, shape (K,)
        Beam directions relative to the heading (rad).
    params : BeamModelParams
    log : bool
        Return :math:`\sum_k \log p(z^k \mid z^{k*})`; use it for more than a few
        beams (the product of 180 likelihoods underflows).
    method : {"hybrid", "dda", "march"}
        Ray-casting method (:func:`~probrob.maps.ray_cast`).

    Returns
    -------
    q : float or ndarray, shape broadcast(z.shape[:-1], x.shape[:-1])
    """
    p = _check_params(params)
    z = _check_ranges(z, "z", p.max_range)
    x, angles, log = _scan_inputs(z, x, beam_angles, log)
    grid = _check_grid(grid)
    _check_inside(grid, x[..., :2], "x")  # here, so that the message names x, not "poses"
    z_star = ray_cast(grid, x, angles, p.max_range, method=method)
    lp = _mixture(z, z_star, p, log=True).sum(axis=-1)
    return check.scalar_or_array(lp if log else _likelihood(lp, p, z=z, x=x))


def _likelihood(lp, p, **arguments):
    """exp of a scan's log-likelihood; one that overflows float64 (finite in logs: a tiny
    σ_hit or z_max, many beams) is reported against the arguments, a point mass (+inf) not."""
    with np.errstate(over="ignore"):
        q = np.exp(lp)
    check.no_overflow(
        np.where(np.isposinf(lp), 0.0, q),
        "the scan's likelihood (finite with log=True)",
        **arguments,
        **{"params.sigma_hit": p.sigma_hit, "params.max_range": p.max_range},
    )
    return q


def sample_beam_mixture(z_star, params, size=None, rng=None):
    r"""Draw ranges from the beam model :math:`p(z \mid z^*)` (for synthetic data).

    A component is drawn with probabilities :math:`(z_{hit}, z_{short}, z_{max},
    z_{rand})`, then a range from it by inversion: the truncated normal of
    :math:`p_{hit}` on :math:`[0, z_{max}]`, the truncated exponential of
    :math:`p_{short}` on :math:`[0, z^*]`, :math:`z_{max}`, or a uniform on
    :math:`[0, z_{max})`.

    Parameters
    ----------
    z_star : array_like
        Expected ranges in :math:`[0, z_{max}]`.
    params : BeamModelParams
    size : int or tuple of ints, optional
        Output shape (``z_star`` must broadcast to it); default ``z_star.shape``.
    rng : None, int or numpy.random.Generator

    Returns
    -------
    z : ndarray
        Sampled ranges.
    """
    p = _check_params(params)
    z_star = _check_expected(z_star, p.max_range)
    shape = check.output_shape(z_star.shape, size)
    rng = check.rng(rng)
    zs = np.broadcast_to(z_star, shape)
    comp = rng.choice(4, size=shape, p=p.weights / p.weights.sum())
    u = rng.random(shape)
    zmax, sigma, lam = p.max_range, p.sigma_hit, p.lambda_short
    with np.errstate(over="ignore", divide="ignore"):  # a subnormal σ: ±inf, Φ exact there
        lo, hi = ndtr(-zs / sigma), ndtr((zmax - zs) / sigma)
    hit = np.clip(zs + sigma * ndtri(lo + u * (hi - lo)), 0.0, zmax)
    short = -np.log1p(u * np.expm1(-lam * zs)) / lam
    z = np.select([comp == 0, comp == 1, comp == 2], [hit, short, np.full(shape, zmax)], u * zmax)
    return z


# ---------------------------------------------------------------------- EM (Table 6.2)
@dataclass(frozen=True)
class EMInfo:
    """Diagnostics of :func:`learn_intrinsic_parameters`.

    Attributes
    ----------
    n_iter : int
        Iterations run.
    converged : bool
        Whether the stopping criterion was met before ``max_iter``.
    log_likelihood : ndarray, shape (n_iter + 1,)
        Mean log-likelihood per reading (nats) before the first and after every
        iteration; non-decreasing for the correct EM.
    responsibilities : ndarray, shape (n, 4)
        Final E-step :math:`e_{i,hit}, e_{i,short}, e_{i,max}, e_{i,rand}`.
    """

    n_iter: int
    converged: bool
    log_likelihood: np.ndarray = field(repr=False)
    responsibilities: np.ndarray = field(repr=False)


def _weighted(lc, lw):
    """``lc + lw`` with a zero weight's term -inf also where ``lc`` is +inf (0 · ∞ = 0)."""
    with np.errstate(invalid="ignore"):
        return np.where(np.isneginf(lw), -np.inf, lc + lw)


def _mean_log_likelihood(lc, lw, at_max):
    """Mean log-likelihood per reading: the log density below z_max, log z_max at it."""
    with np.errstate(divide="ignore"):
        ll = np.where(at_max, lw[2], _logsumexp(_weighted(lc, lw), axis=-1))
    return float(np.mean(ll)) if not np.isneginf(ll).any() else -np.inf


def _responsibilities(lc, lw, at_max, e_step):
    """E-step. ``lc``: log components (n, 4); ``lw``: log weights (4,)."""
    if e_step == "deck":
        # Table 6.2 as printed: η = [p_hit + p_short + p_max + p_rand]^{-1}, no weights,
        # the point mass p_max = 1 added to densities.
        a = lc
    else:
        a = _weighted(lc, lw)
        # A reading at z_max is the point mass: only p_max has mass there.
        a = np.where(at_max[:, None], np.array([-np.inf, -np.inf, 0.0, -np.inf]), a)
    norm = _logsumexp(a, axis=-1)
    ok = np.isfinite(norm)
    e = np.zeros_like(a)
    e[ok] = np.exp(a[ok] - norm[ok, None])
    # A reading at z = z* = 0 is p_short's point mass (+inf): it explains the reading alone.
    point = np.isposinf(norm)
    if point.any():
        mass = np.isposinf(a[point])
        e[point] = mass / mass.sum(axis=-1, keepdims=True)
    return e


def _fit_sigma(e, d2, z_star, sigma_closed, max_range, m_step):
    """M-step for σ_hit: the weighted RMS (the book), or the truncated-normal MLE."""
    if m_step == "book":
        return sigma_closed
    w = e > 1e-12
    margin = np.minimum(z_star[w], max_range - z_star[w]).min() if w.any() else np.inf
    if margin > 9.0 * sigma_closed:  # truncation mass < 1e-18: the closed form is exact
        return sigma_closed
    from scipy.optimize import minimize_scalar

    # Only readings within reach of a boundary feel the truncation; the rest enter
    # through two sums.
    c = np.log(sigma_closed)
    near = w & (np.minimum(z_star, max_range - z_star) < 12.0 * np.e * sigma_closed)
    s_e, s_ed2 = float(e[w].sum()), float(np.sum(e[w] * d2[w]))
    en, zn = e[near], z_star[near]

    def neg(log_s):
        s = np.exp(log_s)
        trunc = np.sum(en * _hit_log_mass(zn, s, max_range)) if en.size else 0.0
        return 0.5 * s_ed2 / s**2 + s_e * log_s + trunc

    res = minimize_scalar(
        neg, bounds=(c - 1.0, c + 1.0), method="bounded", options={"xatol": 1e-10}
    )
    return float(np.exp(res.x))


def _fit_lambda(e, z, z_star, max_range, m_step):
    """M-step for λ_short: Σe/Σez (the book), or the truncated-exponential MLE.

    The MLE solves Σ e_i (1/λ − z_i − z*_i / (exp(λ z*_i) − 1)) = 0, whose left side
    decreases in λ; if it is negative already as λ → 0 (the short readings are not
    biased towards 0) the MLE is the boundary and λ = 1e-6/z_max is returned; if it is
    still positive at λ = 1e9/z_max (the short readings all at 0, where the MLE is
    infinite: a point mass at 0) that bound is returned. The bracket search therefore
    takes at most 18 doublings of log λ's step.
    """
    w = (e > 1e-12) & (z_star > 0)
    ew, zw, zsw = e[w], z[w], z_star[w]
    total = ew.sum()
    if total == 0:
        return None
    lam_book = total / max(float(np.sum(ew * zw)), 1e-12 * max_range)
    if m_step == "book":
        return lam_book
    from scipy.optimize import brentq

    def g(log_lam):
        lam = np.exp(log_lam)
        with np.errstate(over="ignore", invalid="ignore"):  # exp(λ z*) beyond float64: 0
            value = total / lam - np.sum(ew * zw) - np.sum(ew * zsw / np.expm1(lam * zsw))
        if np.isfinite(value):
            return value
        # λ so small (z_max near the largest float) that 1/λ overflows: the 1/λ terms
        # cancel; Σ e z* (1/x - 1/(e^x - 1)) - Σ e z with x = λ z*, 1/x - 1/(e^x - 1) =
        # 1/2 - x/12 + x³/720 - ... for small x
        x = lam * zsw
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):  # unused branch
            h = np.where(x < 1e-4, 0.5 - x / 12 + x**3 / 720, 1 / x - 1 / np.expm1(x))
        return float(np.sum(ew * zsw * h) - np.sum(ew * zw))

    lo, top = np.log(1e-6 / max_range), np.log(1e9 / max_range)
    if g(lo) <= 0:
        return float(np.exp(lo))
    hi = min(max(np.log(lam_book), lo) + 1.0, top)
    while g(hi) > 0:  # at most (top - lo) / 2 + 1 = 18 steps
        if hi == top:
            return float(np.exp(top))
        hi = min(hi + 2.0, top)
    return float(np.exp(brentq(g, lo, hi, xtol=1e-12)))


def learn_intrinsic_parameters(
    z,
    z_star,
    max_range,
    *,
    init=None,
    e_step="weighted",
    m_step="exact",
    tol=1e-8,
    max_iter=500,
    full_output=False,
):
    r"""Fit the beam model's intrinsic parameters by EM (*Probabilistic Robotics*, Table 6.2).

    E-step: the responsibility of component :math:`c` for reading :math:`i` is

    .. math:: e_{i,c} = \frac{z_c\, p_c(z_i \mid z_i^*)}{\sum_{c'} z_{c'}\, p_{c'}(z_i \mid z_i^*)}

    weighted by the current mixing weights :math:`z_c` (the book's and the deck's
    Table 6.2 leave the weights out: ``e_step="deck"`` runs that version, which is not
    EM and does not recover the weights). A reading at :math:`z_{max}` is explained by
    the point mass alone (:math:`e_{i,max} = 1`): the other components are densities
    and put no mass on a single point.

    M-step: :math:`z_c = |Z|^{-1}\sum_i e_{i,c}`; :math:`\sigma_{hit}` and
    :math:`\lambda_{short}` maximise the expected log-likelihood of the *truncated*
    components of :func:`beam_model_components` (``m_step="exact"``). The book's closed
    forms :math:`\sigma_{hit}^2 = \sum e_{i,hit}(z_i - z_i^*)^2 / \sum e_{i,hit}` and
    :math:`\lambda_{short} = \sum e_{i,short} / \sum e_{i,short} z_i`
    (``m_step="book"``) ignore the truncation: exact for :math:`\sigma_{hit}` when every
    :math:`z^*` is many :math:`\sigma` inside :math:`[0, z_{max}]` (then the exact step
    uses it too), biased for :math:`\lambda_{short}`, whose truncation at :math:`z^*`
    is never negligible.

    Convergence: stop when the mean log-likelihood per reading (nats; densities for
    readings below :math:`z_{max}`, the probability :math:`z_{max}` for readings at
    it) changes by less than ``tol`` between iterations, or after ``max_iter``.

    Parameters
    ----------
    z : array_like, shape (n,) or any shape
        Measured ranges (m); readings at or beyond ``max_range`` are max-range readings.
    z_star : array_like, broadcastable with ``z``
        Expected (ray-cast) ranges in :math:`[0, z_{max}]`.
    max_range : float
        The sensor's maximum range :math:`z_{max}` (m).
    init : BeamModelParams, optional
        Starting point; default: equal weights, :math:`\sigma_{hit}` from the median
        absolute deviation of :math:`z - z^*`, :math:`\lambda_{short} = 1/\bar z`.
    e_step : {"weighted", "deck"}
        The correct E-step, or the deck's (no mixing weights) for comparison.
    m_step : {"exact", "book"}
        Truncated-component maximisation, or the book's closed forms.
    tol : float
        Convergence threshold on the change of the mean log-likelihood (nats).
    max_iter : int
    full_output : bool
        Also return an :class:`EMInfo`.

    Returns
    -------
    params : BeamModelParams
    info : EMInfo
        Only if ``full_output``.
    """
    max_range = check.positive_scalar(max_range, "max_range")
    z = _check_ranges(z, "z", max_range)
    z_star = _check_expected(z_star, max_range)
    check.batch_shape(z=z.shape, z_star=z_star.shape)
    z, z_star = (a.ravel() for a in np.broadcast_arrays(z, z_star))
    if z.size == 0:
        raise ValueError("z must hold at least one reading")
    e_step = check.choice(e_step, "e_step", ("weighted", "deck"))
    m_step = check.choice(m_step, "m_step", ("exact", "book"))
    tol = check.positive_scalar(tol, "tol")
    max_iter = check.count(max_iter, "max_iter", minimum=1)
    full_output = check.flag(full_output, "full_output")
    at_max = z >= max_range
    if init is None:
        dev = np.abs(z - z_star)[~at_max]
        sigma0 = 1.4826 * np.median(dev) if dev.size else 0.01 * max_range
        sigma0 = max(float(sigma0), 1e-4 * max_range)
        lam0 = 1.0 / max(float(np.mean(z[~at_max])) if dev.size else 1.0, 1e-3 * max_range)
        init = BeamModelParams(0.25, 0.25, 0.25, 0.25, sigma0, lam0, max_range)
    p = _check_params(init)
    if p.max_range != max_range:
        raise ValueError("init.max_range must equal max_range")
    with np.errstate(over="ignore"):
        d2 = (z - z_star) ** 2
    check.no_overflow(d2, "the squared error (z - z_star)**2", z=z, z_star=z_star)
    history = []
    converged = False
    n_iter = 0
    e = None
    while True:
        lc = _log_components(z, z_star, p)
        with np.errstate(divide="ignore"):
            lw = np.log(p.weights)
        history.append(_mean_log_likelihood(lc, lw, at_max))
        if n_iter and np.isfinite(history[-1]) and abs(history[-1] - history[-2]) < tol:
            converged = True
            break
        if n_iter == max_iter:
            break
        n_iter += 1
        e = _responsibilities(lc, lw, at_max, e_step)
        s = e.sum(axis=0)
        w = s / s.sum()
        sigma, lam = p.sigma_hit, p.lambda_short
        if s[0] > 0:
            sigma_closed = float(np.sqrt(np.sum(e[:, 0] * d2) / s[0]))
            if sigma_closed > 0:
                sigma = _fit_sigma(e[:, 0], d2, z_star, sigma_closed, max_range, m_step)
        if s[1] > 0:
            lam_new = _fit_lambda(e[:, 1], z, z_star, max_range, m_step)
            lam = lam if lam_new is None else lam_new
        p = BeamModelParams(*w, sigma, lam, max_range)
    if not full_output:
        return p
    return p, EMInfo(n_iter, converged, np.array(history), e)


# ---------------------------------------------------------------------- likelihood field
def likelihood_field_table(grid, params):
    r"""Return the per-cell log-likelihood of the likelihood field (Table 6.3, line 8).

    .. math:: \log\big(z_{hit}\,\varepsilon_{\sigma_{hit}^2}(d_{ij})
              + z_{rand}/z_{max}\big)

    with :math:`d_{ij}` the distance from the centre of cell :math:`(i, j)` to the
    nearest occupied cell centre (:attr:`~probrob.maps.OccupancyGrid.distance_field`)
    and :math:`\varepsilon_{\sigma^2}` the zero-mean normal density. Cached on the grid
    per parameter set.

    Parameters
    ----------
    grid : OccupancyGrid
        Must have at least one occupied cell.
    params : BeamModelParams
        Uses ``z_hit``, ``z_rand``, ``sigma_hit``, ``max_range``.

    Returns
    -------
    table : ndarray, shape (H + 2, W + 2), read-only
        Padded by one cell on each side holding the value far from any obstacle,
        :math:`\log(z_{rand}/z_{max})` (used for end points outside the map).
    """
    grid = _check_grid(grid)
    p = _check_params(params)
    if not grid.occupied.any():
        raise ValueError("grid has no occupied cell: the likelihood field is undefined")
    key = (p.z_hit, p.z_rand, p.sigma_hit, p.max_range)
    cached = grid._likelihood_tables.get(key)
    if cached is not None:
        return cached
    d = grid.distance_field
    with np.errstate(divide="ignore", over="ignore"):  # σ near the smallest float: -inf
        log_hit = (
            np.log(p.z_hit) - 0.5 * (d / p.sigma_hit) ** 2 - np.log(p.sigma_hit) - _LOG_SQRT_2PI
        )
        floor = np.log(p.z_rand / p.max_range)
    table = np.pad(np.logaddexp(log_hit, floor), 1, constant_values=floor)
    table.flags.writeable = False
    if len(grid._likelihood_tables) >= 8:
        grid._likelihood_tables.clear()
    grid._likelihood_tables[key] = table
    return table


def likelihood_field_range_finder_model(
    z, x, grid, beam_angles, params, *, log=False, sensor_offset=(0.0, 0.0)
):
    r"""Return :math:`p(z_t \mid x_t, m)` of the likelihood field (*Probabilistic Robotics*, Table 6.3).

    For every beam :math:`k` with :math:`z_t^k < z_{max}` (max-range readings are
    skipped), its end point in the world

    .. math::
        x_{z} &= x + x_{k,sens}\cos\theta - y_{k,sens}\sin\theta
                 + z_t^k \cos(\theta + \theta_{k,sens}) \\
        y_{z} &= y + y_{k,sens}\cos\theta + x_{k,sens}\sin\theta
                 + z_t^k \sin(\theta + \theta_{k,sens})

    contributes the factor :math:`z_{hit}\,\varepsilon_{\sigma_{hit}^2}(dist) +
    z_{rand}/z_{max}` (the deck prints :math:`z_{random}/z_{hit}`: errata B5), with
    :math:`dist` the distance from the centre of the end point's cell to the nearest
    occupied cell centre, looked up in :func:`likelihood_field_table`. End points
    outside the map get :math:`z_{rand}/z_{max}`.

    Parameters
    ----------
    z : array_like, shape (..., K)
        Measured ranges (m).
    x : array_like, shape (..., 3)
        Robot poses inside the map.
    grid : OccupancyGrid
    beam_angles : array_like, shape (K,)
        :math:`\theta_{k,sens}`, beam directions relative to the heading (rad).
    params : BeamModelParams
        Uses ``z_hit``, ``z_rand``, ``sigma_hit``, ``max_range``.
    log : bool
        Return the summed log-likelihood.
    sensor_offset : array_like, shape (2,) or (K, 2)
        :math:`(x_{k,sens}, y_{k,sens})`, the sensor position in the robot frame (m).

    Returns
    -------
    q : float or ndarray, shape broadcast(z.shape[:-1], x.shape[:-1])
    """
    grid = _check_grid(grid)
    p = _check_params(params)
    z = check.finite(z, "z")
    if np.any(z < 0):
        raise ValueError("z must be non-negative ranges")
    x, angles, log = _scan_inputs(z, x, beam_angles, log)
    offset = check.finite(sensor_offset, "sensor_offset")
    if offset.shape not in ((2,), (angles.size, 2)):
        raise ValueError(f"sensor_offset must have shape (2,) or (K, 2), got {offset.shape}")
    _check_inside(grid, x[..., :2], "x")
    table = likelihood_field_table(grid, p)
    res = grid.resolution
    ox, oy = grid.origin
    th = x[..., 2:3]
    ct, st = np.cos(th), np.sin(th)
    ca, sa = np.cos(angles), np.sin(angles)
    xs, ys = offset[..., 0], offset[..., 1]
    # Sensor position in grid units (shape (..., 1) or (..., K)), then the end points.
    gx = (x[..., 0:1] + xs * ct - ys * st - ox) / res
    gy = (x[..., 1:2] + ys * ct + xs * st - oy) / res
    zr = np.minimum(z, p.max_range) / res  # readings at max range are skipped: no overflow
    # ex = gx + zr (ct ca - st sa), ey = gy + zr (st ca + ct sa), computed into two buffers of
    # the batch's shape (the same operations in the same order: the same numbers, fewer
    # temporaries; an MCL step evaluates this for 10,000 particles x 60 beams).
    shape = np.broadcast_shapes(gx.shape, zr.shape, ct.shape[:-1] + ca.shape)
    ex, ey, tmp = np.empty(shape), np.empty(shape), np.empty(shape)
    np.multiply(ct, ca, out=ex)
    ex -= np.multiply(st, sa, out=tmp)
    ex *= zr
    ex += gx
    np.multiply(st, ca, out=ey)
    ey += np.multiply(ct, sa, out=tmp)
    ey *= zr
    ey += gy
    h, w = grid.shape
    # Padded table: indices clipped into [-1, W] x [-1, H] land on the border value.
    j = np.floor(np.clip(ex, -1.0, w, out=ex), out=ex).astype(np.intp)
    i = np.floor(np.clip(ey, -1.0, h, out=ey), out=ey).astype(np.intp)
    i += 1
    i *= w + 2
    i += j + 1
    lp = table.ravel().take(i)
    hit = z < p.max_range
    lp = (lp if hit.all() else np.where(hit, lp, 0.0)).sum(axis=-1)
    return check.scalar_or_array(lp if log else _likelihood(lp, p, z=z, x=x))
