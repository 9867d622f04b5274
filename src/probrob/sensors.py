r"""Measurement models of *Probabilistic Robotics*, chapter 6 (Tables 6.1–6.5).

Landmark models (Tables 6.4, 6.5; deck ``001`` "Modelo Landmark", "Modelo Sample Landmark"):

* :func:`landmark_measurement` — the noise-free range–bearing–signature measurement
  :math:`h(x, m_j) = (\hat r, \hat\phi, s_j)` of a landmark seen from a pose; the EKF and the
  UKF of chapter 7 use it as their measurement function, so it exists once, here;
* :func:`landmark_measurement_jacobian` — :math:`H = \partial h / \partial x` (Table 7.2,
  line 14);
* :func:`landmark_model_known_correspondence` — :math:`p(f \mid c, x, m)`, Table 6.4;
* :func:`sample_landmark_model_known_correspondence` — poses drawn from one feature,
  Table 6.5.

Conventions: a feature is :math:`f = (r, \phi, s)` (range in m, bearing in rad relative to the
robot's heading, counter-clockwise positive, and a signature); a map ``m`` is an array of
landmark rows :math:`(x, y, s)`; ``sigmas`` are the **standard deviations**
:math:`(\sigma_r, \sigma_\phi, \sigma_s)`. The book's ``prob(a, b^2)`` of Table 5.2 takes a
variance, so these functions pass :math:`\sigma^2` to it (the deck passes :math:`\sigma`:
errata L1). Bearing differences are wrapped to :math:`[-\pi, \pi)`.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from . import _validation as check
from .angles import wrap_angle
from .distributions import prob_normal_distribution, sample_normal_distribution

__all__ = [
    "landmark_measurement",
    "landmark_measurement_jacobian",
    "landmark_model_known_correspondence",
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


def _sigmas(sigmas, count: int = 3) -> np.ndarray:
    arr = check.finite(sigmas, "sigmas")
    if arr.shape != (count,):
        raise ValueError(
            f"sigmas must hold {count} standard deviations (σ_r, σ_φ, σ_s), got shape {arr.shape}"
        )
    if np.any(arr < 0):
        raise ValueError(f"sigmas are standard deviations and must be >= 0, got {arr.tolist()}")
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
    if arr.dtype.kind not in "iu":
        if arr.dtype.kind == "f" and np.all(np.isfinite(arr)) and np.all(arr == np.round(arr)):
            arr = arr.astype(np.intp)
        else:
            raise ValueError(f"c must hold integer landmark indices, got {c!r}")
    if np.any(arr < 0) or np.any(arr >= count):
        raise ValueError(f"c must index the map's {count} landmarks (0..{count - 1}), got {c!r}")
    return arr


def _relative(x, m):
    dx = m[..., 0] - x[..., 0]
    dy = m[..., 1] - x[..., 1]
    return dx, dy


def landmark_measurement(x, m):
    r"""Return the noise-free measurement :math:`h(x, m_j)` of landmark(s) ``m`` from pose(s) ``x``.

    *Probabilistic Robotics*, Table 6.4, lines 3–4 (and :math:`\hat z` of Table 7.2, line 13):

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
    dx, dy = _relative(x, m)
    out = np.empty((*batch, m.shape[-1]))
    out[..., 0] = np.hypot(dx, dy)
    out[..., 1] = wrap_angle(np.arctan2(dy, dx) - x[..., 2])
    if m.shape[-1] == 3:
        out[..., 2] = m[..., 2]
    return out


def landmark_measurement_jacobian(x, m):
    r"""Return :math:`H = \partial h(x, m_j) / \partial x`, the Jacobian of :func:`landmark_measurement`.

    *Probabilistic Robotics*, Table 7.2, line 14, with :math:`q = (m_{j,x}-x)^2 +
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
    dx, dy = _relative(x, m)
    q = dx * dx + dy * dy
    if np.any(q == 0):
        raise ValueError("x coincides with a landmark of m: the bearing has no Jacobian there")
    r = np.sqrt(q)
    H = np.zeros((*batch, m.shape[-1], 3))
    H[..., 0, 0] = -dx / r
    H[..., 0, 1] = -dy / r
    H[..., 1, 0] = dy / q
    H[..., 1, 1] = -dx / q
    H[..., 1, 2] = -1.0
    return H


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

    A zero standard deviation makes its factor a point mass (DESIGN.md): the likelihood is
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
    f = check.vectors(f, "f", 3, "r, phi, s")
    x = check.poses(x, "x")
    m = _map(m)
    if m.shape[-1] != 3:
        raise ValueError(f"m must have shape (L, 3) (x, y, s) for signatures, got {m.shape}")
    c = _correspondences(c, m.shape[0])
    sig2 = np.square(_sigmas(sigmas))
    check.batch_shape(f=f.shape[:-1], c=c.shape, x=x.shape[:-1])
    z_hat = landmark_measurement(x, m[c])
    errors = (
        f[..., 0] - z_hat[..., 0],
        wrap_angle(f[..., 1] - z_hat[..., 1]),
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
    m = _map(m)
    c = _correspondences(c, m.shape[0])
    sig = check.finite(sigmas, "sigmas")
    if sig.shape not in ((2,), (3,)):
        raise ValueError(f"sigmas must hold (σ_r, σ_φ) or (σ_r, σ_φ, σ_s), got shape {sig.shape}")
    _sigmas(sig, sig.shape[0])
    check.callable_arg(sample, "sample")
    shape = check.output_shape(check.batch_shape(f=f.shape[:-1], c=c.shape), size)
    rng = check.rng(rng)

    gamma = rng.uniform(0.0, _TWO_PI, size=shape)
    r_hat = f[..., 0] + check.sample_output(
        sample(sig[0] ** 2, size=shape, rng=rng), "sample", shape
    )
    phi_hat = f[..., 1] + check.sample_output(
        sample(sig[1] ** 2, size=shape, rng=rng), "sample", shape
    )
    landmark = m[c]
    out = np.empty((*shape, 3))
    out[..., 0] = landmark[..., 0] + r_hat * np.cos(gamma)
    out[..., 1] = landmark[..., 1] + r_hat * np.sin(gamma)
    out[..., 2] = wrap_angle(gamma - np.pi - phi_hat)
    return out
