r"""Gaussian filter localization of *Probabilistic Robotics*, chapter 7.

* :func:`ekf_localization_known_correspondences` — Table 7.2, the EKF with known
  correspondences, returning :math:`\mu_t, \Sigma_t` and the measurement likelihood
  :math:`p(z_t)`;
* :func:`ekf_localization` — Table 7.3, the EKF with maximum-likelihood data
  association (unknown correspondences), returning the chosen landmark per feature, with
  an optional χ² gate;
* :func:`ukf_localization` — Table 7.4, the UKF with the augmented state (pose, control
  noise, measurement noise); several features of one step are stacked into one update;
* :func:`nees` — the normalised estimation error squared of a pose estimate;
* :func:`run_filter` — one of the filters over a sequence of steps (a simulation or a
  dataset's ``stream()``), collecting the estimates.

All three use the noise-free velocity motion :math:`g` and its Jacobians from
:mod:`probrob.motion` (exact at :math:`\omega = 0`) and the range–bearing–signature
measurement function :math:`h` and its Jacobian from :mod:`probrob.sensors`, so each
model exists once. The public functions validate their input once and then call those
modules' unchecked cores (the public model functions are the same cores behind their
checks); Table 7.2's sequential correction and the UKF's sigma-point motion run on Python
floats, which for 3×3 algebra is several times faster than numpy calls on tiny arrays
(``benchmarks/bench_filters.py``; equal to the per-call public functions to 1e-12,
``tests/test_localization_fastpath.py``). Every bearing innovation, and every bearing and heading residual of
the UKF, is wrapped with :mod:`probrob.angles`; the returned mean heading is wrapped to
:math:`[-\pi, \pi)`.

Conventions: a pose is ``(3,)`` :math:`(x, y, \theta)`, a control ``(2,)``
:math:`(v, \omega)`, a step's features ``z`` are rows :math:`(r, \phi, s)` (shape
``(K, 3)``) or :math:`(r, \phi)` (shape ``(K, 2)``: no signatures, association on range
and bearing only), the map ``m`` rows :math:`(x, y, s)` (shape ``(L, 3)``), ``c`` the
landmark row of each feature (shape ``(K,)``), ``alpha`` the four motion-noise parameters
:math:`\alpha_1 \ldots \alpha_4` of :math:`M_t` (variances: :math:`\alpha_1 v^2 +
\alpha_2 \omega^2`), ``sigmas`` the standard deviations :math:`(\sigma_r, \sigma_\phi,
\sigma_s)`.
"""

from __future__ import annotations

import functools
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from . import _validation as check
from .angles import _wrap
from .motion import (
    _arc,
    _velocity_jacobian_entries,
    _velocity_jacobians_core,
    _velocity_motion_core,
)
from .sensors import (
    _jacobian_entries,
    _landmark_jacobian_core,
    _landmark_measurement_core,
    _range_bearing,
)

__all__ = [
    "FilterRun",
    "MotionNoiseFit",
    "chi2_quantile",
    "covariance_ellipse",
    "ekf_localization",
    "ekf_localization_known_correspondences",
    "ekf_predict_segment",
    "fit_measurement_noise",
    "fit_motion_noise",
    "nees",
    "run_filter",
    "ukf_localization",
    "ukf_localization_ml",
    "ukf_weights",
]

_LOG_2PI = math.log(2.0 * math.pi)


# --------------------------------------------------------------------------- validation


def _covariance(Sigma, name: str = "Sigma") -> np.ndarray:
    """A finite, symmetric, positive-definite 3×3 covariance."""
    S = _finite(Sigma, name)
    if S.shape != (3, 3):
        raise ValueError(f"{name} must have shape (3, 3), got {S.shape}")
    # np.allclose(S, S.T, rtol=1e-9, atol=1e-12), on the three pairs (floats: faster).
    a = S.tolist()
    for i, j in ((0, 1), (0, 2), (1, 2)):
        if not abs(a[i][j] - a[j][i]) <= 1e-12 + 1e-9 * abs(a[j][i]):
            raise ValueError(f"{name} must be symmetric")
    # Singular but positive semi-definite is legal (Σ = 0 is a known pose).
    _psd(S, name)
    return S


def _chol3(S: np.ndarray):
    """Lower Cholesky factor of a symmetric 3×3 ``S`` in scalar arithmetic, or ``None``.

    The Cholesky–Banachiewicz recurrence (LAPACK's ``potrf`` criterion: every pivot must
    be > 0); a numpy/LAPACK call on a 3×3 matrix costs ten times the arithmetic.
    """
    (a00, _, _), (a10, a11, _), (a20, a21, a22) = S.tolist()
    if not a00 > 0.0:
        return None
    l00 = math.sqrt(a00)
    l10, l20 = a10 / l00, a20 / l00
    d1 = a11 - l10 * l10
    if not d1 > 0.0:
        return None
    l11 = math.sqrt(d1)
    l21 = (a21 - l20 * l10) / l11
    d2 = a22 - l20 * l20 - l21 * l21
    if not d2 > 0.0:
        return None
    return [[l00, 0.0, 0.0], [l10, l11, 0.0], [l20, l21, math.sqrt(d2)]]


def _psd(S: np.ndarray, name: str) -> None:
    """Raise ``ValueError`` unless the symmetric ``S`` is positive semi-definite."""
    if S.shape == (3, 3) and _chol3(S) is not None:
        return
    try:
        np.linalg.cholesky(S)
    except np.linalg.LinAlgError:
        eig = np.linalg.eigvalsh(S)
        if eig[0] < -1e-12 * max(1.0, eig[-1]):
            raise ValueError(
                f"{name} is not positive semi-definite (smallest eigenvalue {eig[0]:.3g})"
            ) from None


def _sqrt_psd(S: np.ndarray) -> np.ndarray:
    """A square root ``R`` with ``R @ R.T == S``: the lower Cholesky factor if ``S`` is
    positive definite, else the symmetric root (``S`` positive semi-definite)."""
    if S.shape == (3, 3):
        L = _chol3(S)
        if L is not None:
            return np.array(L)
    try:
        return np.linalg.cholesky(S)
    except np.linalg.LinAlgError:
        w, U = np.linalg.eigh(S)
        return U * np.sqrt(np.clip(w, 0.0, None))


_S_NAME = "S (the innovation covariance, from Sigma and sigmas)"


def _cholesky(S: np.ndarray, name: str) -> np.ndarray:
    """Lower Cholesky factor of ``S`` (..., n, n), or ``ValueError`` naming ``name``."""
    try:
        L = np.linalg.cholesky(S)
    except np.linalg.LinAlgError:
        L = None
    if L is None or not np.all(np.isfinite(L)):
        raise ValueError(
            f"{name} is not positive definite (a covariance must be symmetric with "
            "positive eigenvalues)"
        )
    return L


def _finite(value, name: str) -> np.ndarray:
    """``check.finite`` with a fast accept for small arrays (a filter step's arguments).

    Anything that is not plainly finite goes through ``check.finite`` itself, so the
    errors and their messages are the canonical ones.
    """
    arr = check.as_float_array(value, name)
    if arr.size <= 64 and all(map(math.isfinite, arr.ravel().tolist())):
        return arr
    return check.finite(arr, name)


def _dt(dt) -> float:
    if type(dt) is float and math.isfinite(dt) and dt > 0.0:
        return dt
    return check.positive_scalar(dt, "dt")


def _pose(mu, name: str = "mu") -> np.ndarray:
    mu = _finite(mu, name)
    if mu.shape != (3,):
        check.poses(mu, name)
        raise ValueError(f"{name} must have shape (3,), got {mu.shape}")
    return mu


def _control(u) -> np.ndarray:
    u = _finite(u, "u")
    if u.shape != (2,):
        check.vectors(u, "u", 2, "v, omega")
        raise ValueError(f"u must have shape (2,), got {u.shape}")
    return u


def _landmark_map(m) -> np.ndarray:
    m = _finite(m, "m")
    if m.ndim != 2 or m.shape[1] != 3:
        raise ValueError(f"m must have shape (L, 3) (landmark x, y, s), got {m.shape}")
    if m.shape[0] == 0:
        raise ValueError("m is an empty map: it needs at least one landmark")
    return m


def _features(z) -> np.ndarray:
    z = _finite(z, "z")
    if z.size == 0:
        return np.zeros((0, 3))
    if z.ndim == 1:
        z = z[None, :]
    if z.ndim != 2 or z.shape[1] not in (2, 3):
        raise ValueError(f"z must have shape (K, 3) (r, phi, s) or (K, 2) (r, phi), got {z.shape}")
    if min(z[:, 0].tolist()) < 0:
        raise ValueError("z: ranges must be >= 0")
    return z


def _correspondences(c, k: int, n_landmarks: int) -> np.ndarray:
    arr = np.asarray(c)
    if arr.size == 0 and k == 0:
        return np.zeros(0, dtype=int)
    arr = np.atleast_1d(arr)
    if arr.dtype.kind not in "iu":
        if arr.dtype.kind != "f" or not np.all(np.isfinite(arr)) or np.any(arr != np.round(arr)):
            raise ValueError(f"c must hold integer landmark indices, got {c!r}")
        arr = arr.astype(int)
    if arr.shape != (k,):
        raise ValueError(
            f"c must have shape ({k},), one landmark index per feature, got {arr.shape}"
        )
    listed = arr.tolist()
    if min(listed) < 0 or max(listed) >= n_landmarks:
        raise ValueError(f"c must index the map's {n_landmarks} landmarks, got {listed}")
    return arr.astype(int)


def _alpha4(alpha) -> np.ndarray:
    arr = _finite(alpha, "alpha")
    if arr.shape == (4,) and min(arr.tolist()) >= 0.0:
        return arr
    return check.alphas(arr, "alpha", 4)


def _sigmas(sigmas, count: int = 3) -> np.ndarray:
    s = _finite(sigmas, "sigmas")
    if s.shape not in ((2,), (3,)) or s.shape[0] < count:
        need = "(sigma_r, sigma_phi, sigma_s)" if count == 3 else "(sigma_r, sigma_phi[, sigma_s])"
        raise ValueError(f"sigmas must hold {need}, got shape {s.shape}")
    if min(s.tolist()) <= 0:
        raise ValueError(f"sigmas are standard deviations and must be > 0, got {s.tolist()}")
    return s


# --------------------------------------------------------------------------- shared pieces


def _motion_noise(alpha: np.ndarray, u: np.ndarray) -> np.ndarray:
    r"""Diagonal of :math:`M_t` (Table 7.2, line 5): control-noise variances."""
    v2, w2 = u[0] ** 2, u[1] ** 2
    return np.array([alpha[0] * v2 + alpha[1] * w2, alpha[2] * v2 + alpha[3] * w2])


def _ekf_predict(mu, Sigma, u, dt, alpha):
    """Lines 2–7 of Tables 7.2 and 7.3 (validated input), as arrays."""
    mu_bar, P = _ekf_predict_floats(mu, Sigma, u, dt, alpha)
    (p00, p01, p02, p11, p12, p22) = P
    return np.array(mu_bar), np.array([[p00, p01, p02], [p01, p11, p12], [p02, p12, p22]])


def _ekf_predict_floats(mu, Sigma, u, dt, alpha):
    r"""Lines 2–7 of Tables 7.2 and 7.3 in scalar arithmetic.

    :math:`g` and the entries of :math:`G_t, V_t` come from the model code of
    :mod:`probrob.motion` (``_arc``, ``_velocity_jacobian_entries``) evaluated on floats.
    With :math:`G = I + g e_3^T`, :math:`g = (G_{13}, G_{23}, 0)`:
    :math:`(G\Sigma G^T)_{ij} = \Sigma_{ij} + g_i\Sigma_{3j} + \Sigma_{i3} g_j +
    g_i g_j \Sigma_{33}` and :math:`(V M V^T)_{ij} = \sum_k M_k V_{ik} V_{jk}`.
    Returns :math:`ar\mu` as a tuple and the upper triangle
    :math:`(ar\Sigma_{11}, ar\Sigma_{12}, ar\Sigma_{13}, ar\Sigma_{22},
    ar\Sigma_{23}, ar\Sigma_{33})`. ``Sigma`` is symmetrised first (it is validated
    symmetric to 1e-9 relative).
    """
    x, y, th = mu.tolist()
    v, w = u.tolist()
    dt = float(dt)  # a Python float: the scalar path of the model code
    a1, a2, a3, a4 = alpha.tolist()
    try:
        mu_bar = _arc(x, y, th, v, w, dt)
        g0, g1, v00, v10, v01, v11 = _velocity_jacobian_entries(th, v, w, dt)
    except ValueError:  # math.sin(inf): an overflowing control
        raise ValueError(
            "the filter produced a non-finite estimate; check the inputs' scales"
        ) from None
    m0 = a1 * v * v + a2 * w * w
    m1 = a3 * v * v + a4 * w * w
    (s00, s01, s02), (s10, s11, s12), (s20, s21, s22) = Sigma.tolist()
    s01 = 0.5 * (s01 + s10)
    s02 = 0.5 * (s02 + s20)
    s12 = 0.5 * (s12 + s21)
    # G Σ G^T (g_2 = 0), then + V M V^T (V_31 = 0, V_32 = Δt).
    p00 = s00 + 2.0 * g0 * s02 + g0 * g0 * s22 + m0 * v00 * v00 + m1 * v01 * v01
    p01 = s01 + g0 * s12 + s02 * g1 + g0 * g1 * s22 + m0 * v00 * v10 + m1 * v01 * v11
    p11 = s11 + 2.0 * g1 * s12 + g1 * g1 * s22 + m0 * v10 * v10 + m1 * v11 * v11
    p02 = s02 + g0 * s22 + m1 * v01 * dt
    p12 = s12 + g1 * s22 + m1 * v11 * dt
    p22 = s22 + m1 * dt * dt
    return mu_bar, (p00, p01, p02, p11, p12, p22)


def ekf_predict_segment(mu, Sigma, u, dt, alpha):
    r"""Return the EKF predictions of ``n`` consecutive steps without features, all at once.

        The composition of ``n`` prediction steps of Table 7.2 (lines 2–7),
        :math:`ar\mu_k = g(u_k, ar\mu_{k-1})`,
        :math:`ar\Sigma_k = G_k ar\Sigma_{k-1} G_k^T + V_k M_k V_k^T`, evaluated without
        a loop over time. Two facts make this exact:

        * :math:`g` moves the heading by :math:`\omega_k\Delta t_k` whatever the position, so
          the headings are a cumulative sum and the position increments follow from them;
        * every :math:`G_k = I + p_k e_3^T` with :math:`p_k = (G_{k,13}, G_{k,23}, 0)`, and
          :math:`e_3^T p_j = 0`, so :math:`G_k \cdots G_{j+1} = I + (P_k - P_j) e_3^T` with
          :math:`P_k = \sum_{i \le k} p_i`. With :math:`Q_j = V_j M_j V_j^T`,
          :math:`r_j` its third column and :math:`q_j` its (3, 3) entry,

          .. math::
              ar\Sigma_k = \Phi_k \Sigma_0 \Phi_k^T + \sum_{j \le k} \left[Q_j + D r_j^T
              + r_j D^T + q_j D D^T
    ight]_{D = P_k - P_j},

          and each sum over :math:`j` is a cumulative sum.

        The result equals the step-by-step predictions to rounding (tested to 1e-10
        relative). :func:`run_filter` uses it for the stretches between measurements.

        Parameters
        ----------
        mu : array_like, shape (3,)
        Sigma : array_like, shape (3, 3)
        u : array_like, shape (n, 2)
            Controls of the ``n`` steps.
        dt : array_like, shape (n,) or float
            Their lengths, > 0.
        alpha : array_like, shape (4,)

        Returns
        -------
        mu : ndarray, shape (n, 3)
            :math:`ar\mu_1 \ldots ar\mu_n` (headings not wrapped).
        Sigma : ndarray, shape (n, 3, 3)
    """
    mu, Sigma = _pose(mu), _covariance(Sigma)
    u = check.vectors(u, "u", 2, "v, omega")
    if u.ndim != 2:
        raise ValueError(f"u must have shape (n, 2), got {u.shape}")
    dt = _step_lengths(dt, u.shape[0])
    return _predict_segment(mu, Sigma, u, dt, _alpha4(alpha))


def _step_lengths(dt, n: int) -> np.ndarray:
    """``dt`` as ``n`` step lengths > 0 (one value or one per step)."""
    dt = check.finite(dt, "dt")
    if dt.shape not in ((), (n,)):
        raise ValueError(f"dt must be a scalar or have shape ({n},), got shape {dt.shape}")
    if np.any(dt <= 0):
        raise ValueError("dt must be > 0")
    return np.broadcast_to(dt, (n,))


def _predict_segment(mu, Sigma, u, dt, alpha):
    n = u.shape[0]
    if n == 0:
        return np.zeros((0, 3)), np.zeros((0, 3, 3))
    # g(x, (v, ω), Δt) = g(x, (vΔt, ωΔt), 1) and V(x, u, Δt) = Δt·V(x, uΔt, 1).
    ud = u * dt[:, None]
    starts = np.zeros((n, 3))
    starts[0, 2] = mu[2]
    starts[1:, 2] = mu[2] + np.cumsum(ud[:-1, 1])
    steps = _velocity_motion_core(starts, ud, 1.0)  # position increments, new headings
    mus = np.empty((n, 3))
    mus[:, 0] = mu[0] + np.cumsum(steps[:, 0])
    mus[:, 1] = mu[1] + np.cumsum(steps[:, 1])
    mus[:, 2] = steps[:, 2]
    G, V = _velocity_jacobians_core(starts, ud, 1.0)
    V *= dt[:, None, None]
    var = np.stack(
        [
            alpha[0] * u[:, 0] ** 2 + alpha[1] * u[:, 1] ** 2,
            alpha[2] * u[:, 0] ** 2 + alpha[3] * u[:, 1] ** 2,
        ],
        axis=-1,
    )
    Q = (V * var[:, None, :]) @ np.swapaxes(V, -1, -2)  # (n, 3, 3)
    P = np.zeros((n, 3))
    P[:, 0] = np.cumsum(G[:, 0, 2])
    P[:, 1] = np.cumsum(G[:, 1, 2])
    r = Q[:, :, 2]
    q = Q[:, 2, 2]
    cum_Q = np.cumsum(Q, axis=0)
    R = np.cumsum(r, axis=0)
    C = np.cumsum(P[:, :, None] * r[:, None, :], axis=0)
    W = np.cumsum(q)
    E = np.cumsum(q[:, None] * P, axis=0)
    F = np.cumsum(q[:, None, None] * P[:, :, None] * P[:, None, :], axis=0)
    X = P[:, :, None] * R[:, None, :] - C
    PP = P[:, :, None] * P[:, None, :]
    PE = P[:, :, None] * E[:, None, :]
    noise = (
        cum_Q
        + X
        + np.swapaxes(X, -1, -2)
        + W[:, None, None] * PP
        - PE
        - np.swapaxes(PE, -1, -2)
        + F
    )
    Phi = np.broadcast_to(np.eye(3), (n, 3, 3)).copy()
    Phi[:, :, 2] += P
    Sigmas = Phi @ Sigma @ np.swapaxes(Phi, -1, -2) + noise
    return mus, 0.5 * (Sigmas + np.swapaxes(Sigmas, -1, -2))


def _innovation(z: np.ndarray, zhat: np.ndarray) -> np.ndarray:
    """``z - zhat`` with the bearing (second component) wrapped to [-π, π)."""
    nu = z - zhat
    nu[..., 1] = _wrap(nu[..., 1])
    return nu


def _gaussian_terms(nu: np.ndarray, S: np.ndarray, name: str = _S_NAME):
    """Mahalanobis distances² and log-densities of innovations ``nu`` (..., d) under S."""
    L = _cholesky(S, name)
    w = np.linalg.solve(L, nu[..., None])[..., 0]
    d2 = np.sum(w * w, axis=-1)
    logdet = 2.0 * np.sum(np.log(np.diagonal(L, axis1=-2, axis2=-1)), axis=-1)
    d = nu.shape[-1]
    return d2, -0.5 * (d2 + logdet + d * _LOG_2PI)


def _correct(mu_bar, Sigma_bar, nu, H, S):
    r"""One EKF correction (Table 7.2, lines 15–17) and the feature's log-likelihood.

    Returns the new μ̄, Σ̄ and :math:`\log N(\nu; 0, S)` (line 21's factor). ``S`` is
    positive definite by construction (:math:`Q_t` is); its determinant and diagonal are
    checked anyway, against rounding with badly scaled inputs.
    """
    sign, logdet = np.linalg.slogdet(S)
    if not sign > 0 or not S[0, 0] > 0 or not S[1, 1] > 0:
        raise ValueError("S is not positive definite; check the scales of Sigma and sigmas")
    S_inv = np.linalg.inv(S)
    PHt = Sigma_bar @ H.T
    K = PHt @ S_inv
    mu_bar = mu_bar + K @ nu
    Sigma_bar = Sigma_bar - K @ PHt.T
    d2 = float(nu @ S_inv @ nu)
    logp = -0.5 * (d2 + float(logdet) + nu.shape[0] * _LOG_2PI)
    return mu_bar, 0.5 * (Sigma_bar + Sigma_bar.T), logp


def _finish(mu: np.ndarray, Sigma: np.ndarray):
    mu = mu.copy()
    mu[2] = _wrap(float(mu[2]))
    if not all(map(math.isfinite, mu.tolist() + Sigma.ravel().tolist())):
        raise ValueError("the filter produced a non-finite estimate; check the inputs' scales")
    return mu, Sigma


def chi2_quantile(p: float, dof: int) -> float:
    r"""Return the ``p``-quantile of the χ² distribution with ``dof`` degrees of freedom.

    Bisection on the closed-form CDF (regularised lower incomplete gamma function,
    summed in closed form for integer ``dof``), accurate to ~1e-12. Used for the χ²
    gate of :func:`ekf_localization` and the NEES bounds, without a SciPy dependency.

    Parameters
    ----------
    p : float
        Probability in (0, 1).
    dof : int
        Degrees of freedom, >= 1.

    Returns
    -------
    q : float
        The value with :math:`P(\chi^2_{dof} \le q) = p`.
    """
    p = check.as_float_array(p, "p")
    if p.ndim != 0 or not 0.0 < p < 1.0:
        raise ValueError(f"p must lie in (0, 1), got {check._short(p)}")
    p = float(p)
    dof = check.count(dof, "dof", 1)

    def cdf(x: float) -> float:
        h = 0.5 * x
        if dof % 2 == 0:
            # 1 - e^{-h} Σ_{k < dof/2} h^k / k!
            term, total = 1.0, 1.0
            for k in range(1, dof // 2):
                term *= h / k
                total += term
            return 1.0 - math.exp(-h) * total
        # erf(√h) - e^{-h} Σ_{k=1}^{(dof-1)/2} h^{k-1/2} / Γ(k + 1/2)
        total = 0.0
        term = math.sqrt(h) / math.gamma(1.5) if h > 0 else 0.0
        for k in range(1, (dof + 1) // 2):
            total += term
            term *= h / (k + 0.5)
        return math.erf(math.sqrt(h)) - math.exp(-h) * total

    lo, hi = 0.0, float(dof)
    while cdf(hi) < p:
        hi *= 2.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if cdf(mid) < p:
            lo = mid
        else:
            hi = mid
        if hi - lo <= 1e-13 * max(1.0, hi):
            break
    return 0.5 * (lo + hi)


# --------------------------------------------------------------------------- Table 7.2


def ekf_localization_known_correspondences(mu, Sigma, u, z, c, m, dt, alpha, sigmas, *, log=False):
    r"""Return :math:`\mu_t, \Sigma_t, p(z_t)` of one EKF step with known correspondences.

    *Probabilistic Robotics*, Table 7.2. Prediction with the velocity motion model
    (lines 2–7):

    .. math::
        \bar\mu_t = g(u_t, \mu_{t-1}),\qquad
        \bar\Sigma_t = G_t \Sigma_{t-1} G_t^T + V_t M_t V_t^T,\qquad
        M_t = \mathrm{diag}(\alpha_1 v_t^2 + \alpha_2 \omega_t^2,\ \alpha_3 v_t^2 + \alpha_4 \omega_t^2),

    then, for each feature :math:`z_t^i` in turn with :math:`j = c_t^i` (lines 9–18),
    the predicted measurement :math:`\hat z = h(\bar\mu_t, m_j) = (\sqrt q,\
    \mathrm{atan2}(\delta_y, \delta_x) - \bar\mu_\theta,\ m_{j,s})` with
    :math:`\delta = m_j - \bar\mu`, :math:`q = \delta^T\delta`, its Jacobian

    .. math::
        H = \begin{pmatrix} -\delta_x/\sqrt q & -\delta_y/\sqrt q & 0 \\
                             \delta_y/q & -\delta_x/q & -1 \\ 0 & 0 & 0 \end{pmatrix},

    :math:`S = H\bar\Sigma H^T + Q_t`, :math:`K = \bar\Sigma H^T S^{-1}`,
    :math:`\bar\mu \mathrel{+}= K(z^i - \hat z)` with the bearing innovation wrapped,
    :math:`\bar\Sigma = (I - KH)\bar\Sigma`. The deck's :math:`V_{11}`, :math:`H_{11}`,
    :math:`H_{22}` and third component of :math:`\hat z` are misprinted (errata, deck 004).

    Parameters
    ----------
    mu : array_like, shape (3,)
        :math:`\mu_{t-1}`.
    Sigma : array_like, shape (3, 3)
        :math:`\Sigma_{t-1}`, symmetric positive semi-definite (``0``: the pose is known).
    u : array_like, shape (2,)
        Control :math:`(v, \omega)`.
    z : array_like, shape (K, 3) or (K, 2)
        Features :math:`(r, \phi, s)`, or :math:`(r, \phi)` (then :math:`Q_t` is 2×2 and
        signatures are not used). ``K = 0`` (an empty array): prediction only.
    c : array_like of int, shape (K,)
        Landmark row of each feature.
    m : array_like, shape (L, 3)
        Map: landmark :math:`(x, y, s)`.
    dt : float
        Time step, > 0.
    alpha : array_like, shape (4,)
        :math:`\alpha_1 \ldots \alpha_4 \ge 0`.
    sigmas : array_like, shape (3,)
        :math:`(\sigma_r, \sigma_\phi, \sigma_s) > 0`, standard deviations.
    log : bool, optional
        Return :math:`\log p(z_t)` instead of :math:`p(z_t)`.

    Returns
    -------
    mu : ndarray, shape (3,)
        :math:`\mu_t`, heading wrapped to :math:`[-\pi, \pi)`.
    Sigma : ndarray, shape (3, 3)
        :math:`\Sigma_t` (symmetrised).
    p_z : float
        :math:`\prod_i \det(2\pi S^i)^{-1/2} \exp(-\frac12 \nu_i^T [S^i]^{-1} \nu_i)`
        (line 21), 1 (log: 0) for a step without features.

    Raises
    ------
    ValueError
        On bad input, a non-positive-definite ``Sigma`` or innovation covariance ``S``.
    """
    mu, Sigma, u = _pose(mu), _covariance(Sigma), _control(u)
    m = _landmark_map(m)
    z = _features(z)
    c = _correspondences(c, z.shape[0], m.shape[0])
    dt = _dt(dt)
    alpha, sigmas = _alpha4(alpha), _sigmas(sigmas, 3)

    mu_t, Sigma_t, log_pz = _ekf_known(mu, Sigma, u, z, c, m, dt, alpha, sigmas)
    return mu_t, Sigma_t, (log_pz if log else math.exp(log_pz))


def _ekf_known(mu, Sigma, u, z, c, m, dt, alpha, sigmas):
    """Table 7.2 on validated input; returns μ, Σ and log p(z)."""
    mu_bar, P = _ekf_predict_floats(mu, Sigma, u, dt, alpha)
    return _ekf_known_correct(mu_bar, P, z, c, m, sigmas)


def _ekf_known_correct(mu_bar, P, z, c, m, sigmas):
    r"""Lines 8–21 of Table 7.2: the features in sequence, in scalar arithmetic.

        The same algebra as :func:`_correct` (:math:`S = Har\Sigma H^T + Q_t`,
        :math:`K = ar\Sigma H^T S^{-1}`, :math:`ar\mu \mathrel{+}= K
    u`,
        :math:`ar\Sigma \mathrel{-}= K (ar\Sigma H^T)^T`, :math:`\log N(
    u; 0, S)`) written
        out on Python floats, because a step is a few 3×3 products per feature and a numpy call
        on such tiny arrays costs more than the arithmetic. :math:`\hat z` and :math:`H` come
        from the same model code as :func:`probrob.sensors.landmark_measurement` and
        :func:`probrob.sensors.landmark_measurement_jacobian` (``_range_bearing``,
        ``_jacobian_entries``). The third row of :math:`H` (signature) is zero, so :math:`S`
        is block-diagonal, :math:`\mathrm{diag}(S_{2	imes2}, \sigma_s^2)`, and the signature
        enters only :math:`p(z_t)`. ``mu_bar`` and ``P`` as returned by
        :func:`_ekf_predict_floats`.
    """
    d = z.shape[1]
    s_r2, s_p2 = float(sigmas[0]) ** 2, float(sigmas[1]) ** 2
    s_s2 = float(sigmas[2]) ** 2 if d == 3 else 1.0
    const = d * _LOG_2PI + (math.log(s_s2) if d == 3 else 0.0)
    x, y, th = mu_bar
    p00, p01, p02, p11, p12, p22 = P
    p10, p20, p21 = p01, p02, p12
    feats = z.tolist()
    lms = m[c].tolist()
    log_pz = 0.0
    for f, lm in zip(feats, lms, strict=True):
        dx, dy = lm[0] - x, lm[1] - y
        r_hat, phi_hat = _range_bearing(dx, dy, th)
        h00, h01, h10, h11 = _jacobian_entries(dx, dy)
        # P H^T (third column zero): rows a = x, y, θ.
        a0, a1 = p00 * h00 + p01 * h01, p00 * h10 + p01 * h11 - p02
        b0, b1 = p10 * h00 + p11 * h01, p10 * h10 + p11 * h11 - p12
        c0, c1 = p20 * h00 + p21 * h01, p20 * h10 + p21 * h11 - p22
        s00 = h00 * a0 + h01 * b0 + s_r2
        s01 = h00 * a1 + h01 * b1
        s10 = h10 * a0 + h11 * b0 - c0
        s11 = h10 * a1 + h11 * b1 - c1 + s_p2
        s01 = s10 = 0.5 * (s01 + s10)
        det = s00 * s11 - s01 * s10
        if not (det > 0.0 and s00 > 0.0 and s11 > 0.0):
            raise ValueError("S is not positive definite; check the scales of Sigma and sigmas")
        i00, i01, i11 = s11 / det, -s01 / det, s00 / det
        n0 = f[0] - r_hat
        n1 = _wrap(f[1] - phi_hat)
        # K = P H^T S^{-1} (first two columns; the third is zero).
        k00, k01 = a0 * i00 + a1 * i01, a0 * i01 + a1 * i11
        k10, k11 = b0 * i00 + b1 * i01, b0 * i01 + b1 * i11
        k20, k21 = c0 * i00 + c1 * i01, c0 * i01 + c1 * i11
        x += k00 * n0 + k01 * n1
        y += k10 * n0 + k11 * n1
        th += k20 * n0 + k21 * n1
        # Σ -= K (P H^T)^T, symmetrised.
        p00 -= k00 * a0 + k01 * a1
        p11 -= k10 * b0 + k11 * b1
        p22 -= k20 * c0 + k21 * c1
        p01 = p10 = p01 - 0.5 * ((k00 * b0 + k01 * b1) + (k10 * a0 + k11 * a1))
        p02 = p20 = p02 - 0.5 * ((k00 * c0 + k01 * c1) + (k20 * a0 + k21 * a1))
        p12 = p21 = p12 - 0.5 * ((k10 * c0 + k11 * c1) + (k20 * b0 + k21 * b1))
        d2 = n0 * (i00 * n0 + i01 * n1) + n1 * (i01 * n0 + i11 * n1)
        if d == 3:
            n2 = f[2] - lm[2]
            d2 += n2 * n2 / s_s2
        log_pz += -0.5 * (d2 + math.log(det) + const)
    mu_t = np.array([x, y, th])
    Sigma_t = np.array([[p00, p01, p02], [p10, p11, p12], [p20, p21, p22]])
    mu_t, Sigma_t = _finish(mu_t, Sigma_t)
    return mu_t, Sigma_t, log_pz


# --------------------------------------------------------------------------- Table 7.3


def ekf_localization(mu, Sigma, u, z, m, dt, alpha, sigmas, *, gate=None):
    r"""Return :math:`\mu_t, \Sigma_t` and the maximum-likelihood landmark of each feature.

    *Probabilistic Robotics*, Table 7.3 (EKF localization with unknown
    correspondences). Prediction as in :func:`ekf_localization_known_correspondences`;
    then, for each feature :math:`z_t^i` in turn, :math:`\hat z^k`, :math:`H^k` and
    :math:`S^k = H^k \bar\Sigma H^{kT} + Q_t` for every landmark :math:`k` (at the
    current :math:`\bar\mu`, already corrected by the earlier features), the choice

    .. math::
        j(i) = \operatorname{argmax}_k\ \det(2\pi S^k)^{-1/2}
               \exp\!\left(-\tfrac12 (z^i - \hat z^k)^T [S^k]^{-1} (z^i - \hat z^k)\right)

    (bearing innovations wrapped) and the Kalman correction with landmark :math:`j(i)`.
    With ``z`` of shape ``(K, 3)`` the signature takes part in the likelihood (it never
    moves the pose: the third row of :math:`H` is zero); with ``(K, 2)`` association
    uses range and bearing only (a map whose signatures are unknown).

    Parameters
    ----------
    mu, Sigma, u, z, m, dt, alpha, sigmas
        As in :func:`ekf_localization_known_correspondences` (no ``c``).
    gate : float, optional
        Off by default (``None``): the book's algorithm, every feature is associated.
        A probability such as 0.99: a feature whose most likely landmark lies outside
        the χ² gate :math:`(z - \hat z)^T S^{-1} (z - \hat z) >` ``chi2_quantile(gate,
        d)`` (``d`` = 2 or 3 components) is rejected (index -1) and not used.

    Returns
    -------
    mu : ndarray, shape (3,)
    Sigma : ndarray, shape (3, 3)
    c : ndarray of int, shape (K,)
        The chosen landmark row :math:`j(i)` of each feature; -1 where the gate rejected it.
    """
    mu, Sigma, u = _pose(mu), _covariance(Sigma), _control(u)
    m = _landmark_map(m)
    z = _features(z)
    dt = _dt(dt)
    alpha, sigmas = _alpha4(alpha), _sigmas(sigmas, 3)
    threshold = _gate_threshold(gate, z.shape[1])

    mu_bar, Sigma_bar = _ekf_predict(mu, Sigma, u, dt, alpha)
    return _ekf_ml_correct(mu_bar, Sigma_bar, z, m, sigmas, threshold)


def _ekf_ml_correct(mu_bar, Sigma_bar, z, m, sigmas, threshold):
    """Lines 8–22 of Table 7.3: every landmark scored at once, features in sequence."""
    d = z.shape[1]
    Q = np.diag(sigmas[:d] ** 2)
    landmarks = m[:, :d]
    chosen = np.full(z.shape[0], -1, dtype=int)
    for i in range(z.shape[0]):
        zhat = _landmark_measurement_core(mu_bar, landmarks)  # (L, d)
        H = _landmark_jacobian_core(mu_bar, landmarks)  # (L, d, 3)
        S = H @ Sigma_bar @ np.swapaxes(H, -1, -2) + Q
        nu = _innovation(z[i], zhat)
        d2, logp = _gaussian_terms(nu, S)
        j = int(np.argmax(logp))
        if threshold is not None and d2[j] > threshold:
            continue
        chosen[i] = j
        mu_bar, Sigma_bar, _ = _correct(mu_bar, Sigma_bar, nu[j], H[j], S[j])
    mu_t, Sigma_t = _finish(mu_bar, Sigma_bar)
    return mu_t, Sigma_t, chosen


# --------------------------------------------------------------------------- Table 7.4


def ukf_weights(n: int, ukf_alpha: float = 1.0, beta: float = 2.0, kappa: float = 0.0):
    r"""Return :math:`\gamma` and the weights :math:`w^{(m)}, w^{(c)}` of the scaled unscented transform.

    *Probabilistic Robotics*, Table 3.4 (used by Table 7.4), the scaled sigma points of
    Wan and van der Merwe: with :math:`\lambda = \alpha^2 (n + \kappa) - n`,

    .. math::
        \gamma = \sqrt{n + \lambda},\quad
        w_0^{(m)} = \frac{\lambda}{n + \lambda},\quad
        w_0^{(c)} = \frac{\lambda}{n + \lambda} + (1 - \alpha^2 + \beta),\quad
        w_i^{(m)} = w_i^{(c)} = \frac{1}{2(n + \lambda)}\ (i = 1 \ldots 2n).

    Parameters
    ----------
    n : int
        Dimension :math:`L` of the (augmented) state.
    ukf_alpha, beta, kappa : float
        Spread :math:`\alpha > 0`, prior-knowledge :math:`\beta` (2 is optimal for a
        Gaussian) and secondary scaling :math:`\kappa` (with :math:`n + \kappa > 0`).

    Returns
    -------
    gamma : float
    wm, wc : ndarray, shape (2n + 1,)
    """
    n = check.count(n, "n", 1)
    a = check.positive_scalar(ukf_alpha, "ukf_alpha")
    beta = float(check.finite(beta, "beta"))
    kappa = float(check.finite(kappa, "kappa"))
    if n + kappa <= 0:
        raise ValueError(f"kappa must satisfy n + kappa > 0 (n = {n}), got {kappa!r}")
    lam = a * a * (n + kappa) - n
    wm = np.full(2 * n + 1, 0.5 / (n + lam))
    wc = wm.copy()
    wm[0] = lam / (n + lam)
    wc[0] = lam / (n + lam) + (1.0 - a * a + beta)
    return math.sqrt(n + lam), wm, wc


def ukf_localization(
    mu,
    Sigma,
    u,
    z,
    c,
    m,
    dt,
    alpha,
    sigmas,
    *,
    ukf_alpha=1.0,
    beta=2.0,
    kappa=0.0,
    log=False,
):
    r"""Return :math:`\mu_t, \Sigma_t, p(z_t)` of one UKF localization step.

    *Probabilistic Robotics*, Table 7.4, with the augmented state
    :math:`x^a = (x, \epsilon_u, \epsilon_z)` of dimension :math:`n = 5 + 2K` for
    :math:`K` features, :math:`\mu^a = (\mu_{t-1}, 0, 0)` and
    :math:`\Sigma^a = \mathrm{diag}(\Sigma_{t-1}, M_t, Q_t, \ldots, Q_t)` with the
    2×2 :math:`Q_t = \mathrm{diag}(\sigma_r^2, \sigma_\phi^2)` (the signature is not
    used). One feature is exactly the book's table with :math:`L = 7`; several features
    are stacked into one update (their noises are independent blocks of
    :math:`\Sigma^a`).

    Sigma points :math:`\chi_0 = \mu^a`, :math:`\chi_{i} = \mu^a \pm \gamma\, [\sqrt{\Sigma^a}]_i`
    with the lower Cholesky factor (columns :math:`1 \ldots n` then :math:`n+1 \ldots 2n`),
    :math:`\lambda = \alpha^2(n + \kappa) - n`, :math:`\gamma = \sqrt{n + \lambda}` and
    weights (see :func:`ukf_weights`)

    .. math::
        w_0^{(m)} = \tfrac{\lambda}{n+\lambda},\quad
        w_0^{(c)} = \tfrac{\lambda}{n+\lambda} + 1 - \alpha^2 + \beta,\quad
        w_i^{(m)} = w_i^{(c)} = \tfrac{1}{2(n+\lambda)}.

    Each sigma point moves with its own control noise,
    :math:`\bar\chi^x_i = g(u_t + \chi^u_{i,t-1}, \chi^x_{i,t-1})` (line 7; the
    :math:`\chi^u` and :math:`\chi^z` are the noise blocks of the same
    :math:`\chi^a_{t-1}`), and is measured with its own measurement noise,
    :math:`\bar Z_i = h(\bar\chi^x_i) + \chi^z_i` (line 10). Means of headings and
    bearings are taken on the circle (about the central point), and every heading and
    bearing residual is wrapped. The measurement sigma points are the predicted ones,
    not redrawn (as in the table).

    Parameters
    ----------
    mu, Sigma, u, m, dt, alpha
        As in :func:`ekf_localization_known_correspondences`.
    z : array_like, shape (K, 2) or (K, 3)
        Features :math:`(r, \phi)` or :math:`(r, \phi, s)`; :math:`s` is ignored.
    c : array_like of int, shape (K,)
        Landmark row of each feature (the table assumes known correspondences).
    sigmas : array_like, shape (2,) or (3,)
        :math:`(\sigma_r, \sigma_\phi[, \sigma_s])`; :math:`\sigma_s` is ignored.
    ukf_alpha, beta, kappa : float, optional
        Unscented-transform parameters :math:`\alpha, \beta, \kappa` (book defaults of
        the deck's exercises: 1, 2, 0, which make :math:`\lambda = 0`).
    log : bool, optional
        Return :math:`\log p(z_t)`.

    Returns
    -------
    mu : ndarray, shape (3,)
        Heading wrapped to :math:`[-\pi, \pi)`.
    Sigma : ndarray, shape (3, 3)
    p_z : float
        :math:`\det(2\pi S_t)^{-1/2}\exp(-\frac12 \nu^T S_t^{-1} \nu)` over the stacked
        :math:`2K` innovation (line 17); 1 (log: 0) without features.

    Raises
    ------
    ValueError
        On bad input, a non-positive-definite ``Sigma``, predicted covariance or ``S``
        (a very small ``ukf_alpha`` makes :math:`w_0^{(c)}` so negative that the
        predicted covariance can lose definiteness).
    """
    mu, Sigma, u = _pose(mu), _covariance(Sigma), _control(u)
    m = _landmark_map(m)
    z = _features(z)
    c = _correspondences(c, z.shape[0], m.shape[0])
    dt = _dt(dt)
    alpha, sigmas = _alpha4(alpha), _sigmas(sigmas, 2)
    params = _ukf_params(ukf_alpha, beta, kappa)
    mu_t, Sigma_t, logp = _ukf(mu, Sigma, u, z, c, m, dt, alpha, sigmas, params)
    return mu_t, Sigma_t, (logp if log else math.exp(logp))


def _ukf_params(ukf_alpha, beta, kappa):
    a = check.positive_scalar(ukf_alpha, "ukf_alpha")
    beta = float(check.finite(beta, "beta"))
    kappa = float(check.finite(kappa, "kappa"))
    if 5 + kappa <= 0:
        raise ValueError(f"kappa must satisfy n + kappa > 0 (n >= 5), got {kappa!r}")
    return a, beta, kappa


@functools.lru_cache(maxsize=64)
def _weights_cached(n, a, beta, kappa):
    gamma, wm, wc = ukf_weights(n, a, beta, kappa)
    wm.setflags(write=False)
    wc.setflags(write=False)
    return gamma, wm, wc


def _ukf(mu, Sigma, u, z, c, m, dt, alpha, sigmas, params):
    """Table 7.4 on validated input; returns μ, Σ and log p(z)."""
    k = z.shape[0]
    n = 5 + 2 * k
    gamma, wm, wc = _weights_cached(n, *params)

    # Lines 2-6: augmented mean and the square root of the block-diagonal covariance
    # (block by block: M_t is zero for a robot at rest, which a Cholesky of the whole
    # matrix would reject; for a positive-definite Σ^a this is its Cholesky factor).
    # The root is block-diagonal, so a sigma point along a measurement-noise axis has the
    # pose and control of χ_0: only 1 + 2·5 distinct poses move (lines 7-9), evaluated on
    # floats with the model code of probrob.motion (``_arc``); the 4K points along the
    # measurement noise share χ_0's motion and weight, and are added to its weight.
    R = _chol3(Sigma)
    if R is None:
        R = _sqrt_psd(Sigma).tolist()
    x0, y0, th0 = mu.tolist()
    v0, w0 = u.tolist()
    dt = float(dt)  # a Python float: the scalar path of the model code
    m0, m1 = _motion_noise(alpha, u).tolist()
    wi = float(wm[1])
    center = _arc(x0, y0, th0, v0, w0, dt)
    moved = []
    for sign in (gamma, -gamma):
        for j in range(3):
            moved.append(
                _arc(x0 + sign * R[0][j], y0 + sign * R[1][j], th0 + sign * R[2][j], v0, w0, dt)
            )
        moved.append(_arc(x0, y0, th0, v0 + sign * math.sqrt(m0), w0, dt))
        moved.append(_arc(x0, y0, th0, v0, w0 + sign * math.sqrt(m1), dt))
    shared = 4 * k * wi  # the measurement-noise points: χ_0's motion
    wm0, wc0 = float(wm[0]) + shared, float(wc[0]) + shared
    cx, cy, cth = center
    mx = wm0 * cx + wi * math.fsum(p[0] for p in moved)
    my = wm0 * cy + wi * math.fsum(p[1] for p in moved)
    # The heading mean on the circle: θ_0 + Σ_i w_i wrap(θ_i - θ_0) about the central point,
    # the weighted mean of the headings unwrapped next to θ_0, right across ±π and with a
    # negative w_0 (where a mean of unit vectors would not be).
    mth = cth + wi * math.fsum(_wrap(p[2] - cth) for p in moved)
    dx = np.empty((2 * n + 1, 3))
    dx[:] = (cx - mx, cy - my, _wrap(cth - mth))
    rows = np.array([(p[0] - mx, p[1] - my, _wrap(p[2] - mth)) for p in moved])
    dx[1:6] = rows[:5]
    dx[n + 1 : n + 6] = rows[5:]
    d0 = dx[0]
    Sigma_bar = wc0 * np.outer(d0, d0) + wi * (rows.T @ rows)
    Sigma_bar = 0.5 * (Sigma_bar + Sigma_bar.T)
    mu_bar = np.array([mx, my, mth])
    _psd(Sigma_bar, "the predicted covariance (check ukf_alpha, beta, kappa)")
    if k == 0:
        mu_t, Sigma_t = _finish(mu_bar, Sigma_bar)
        return mu_t, Sigma_t, 0.0
    xbar = np.empty((2 * n + 1, 3))
    xbar[:] = center
    xbar[1:6] = np.array(moved[:5])
    xbar[n + 1 : n + 6] = np.array(moved[5:])
    # The measurement-noise part of the sigma points: ±γ√(σ²) on axis 5 + j.
    noise = np.zeros((2 * n + 1, 2 * k))
    spread = gamma * np.sqrt(np.tile(sigmas[:2] ** 2, k))
    idx = np.arange(2 * k)
    noise[6 + idx, idx] = spread
    noise[n + 6 + idx, idx] = -spread

    # Lines 10-13: predicted measurements of every sigma point, stacked over features.
    Z = _landmark_measurement_core(xbar[:, None, :], m[c][None, :, :2])  # (2n+1, K, 2)
    Z += noise.reshape(2 * n + 1, k, 2)
    zhat = np.einsum("i,ikd->kd", wm, Z)
    ref = Z[0, :, 1]  # the bearing means on the circle (as the heading's), all features at once
    zhat[:, 1] = ref + wm @ _wrap(Z[:, :, 1] - ref)
    dz = _innovation(Z, zhat).reshape(2 * n + 1, 2 * k)
    S = (wc[:, None] * dz).T @ dz
    S = 0.5 * (S + S.T)
    Pxz = (wc[:, None] * dx).T @ dz

    # Lines 14-17.
    nu = _innovation(z[:, :2], zhat).reshape(2 * k)
    L = _cholesky(S, _S_NAME)
    S_inv = np.linalg.inv(S)
    K = Pxz @ S_inv
    mu_t = mu_bar + K @ nu
    Sigma_t = Sigma_bar - K @ S @ K.T
    Sigma_t = 0.5 * (Sigma_t + Sigma_t.T)
    logdet = 2.0 * float(np.sum(np.log(np.diagonal(L))))
    logp = -0.5 * (float(nu @ S_inv @ nu) + logdet + 2 * k * _LOG_2PI)
    mu_t, Sigma_t = _finish(mu_t, Sigma_t)
    return mu_t, Sigma_t, logp


def ukf_localization_ml(
    mu,
    Sigma,
    u,
    z,
    m,
    dt,
    alpha,
    sigmas,
    *,
    gate=None,
    ukf_alpha=1.0,
    beta=2.0,
    kappa=0.0,
):
    r"""Return :math:`\mu_t, \Sigma_t` and the maximum-likelihood landmark of each feature (UKF).

    Not a table of the book: Table 7.4 with the association of Table 7.3. Every
    landmark :math:`k` is scored as if it were the only feature, with exactly the
    one-feature Table 7.4 (:math:`L = 7`): the predicted measurement :math:`\hat z^k`
    and its covariance :math:`S^k` from the same 15 sigma points; each feature takes
    the landmark of highest :math:`N(z^i; \hat z^k, S^k)` (all features against the same
    prediction, so two features may pick the same landmark). The features are then
    used together in one update by :func:`ukf_localization` with these correspondences.

    Parameters
    ----------
    mu, Sigma, u, z, m, dt, alpha, sigmas, ukf_alpha, beta, kappa
        As in :func:`ukf_localization` (no ``c``); ``z`` rows :math:`(r, \phi)` or
        :math:`(r, \phi, s)` — the signature is not used.
    gate : float, optional
        As in :func:`ekf_localization`: a feature whose best landmark lies outside the
        χ² gate of 2 degrees of freedom is rejected (index -1). Off by default.

    Returns
    -------
    mu : ndarray, shape (3,)
    Sigma : ndarray, shape (3, 3)
    c : ndarray of int, shape (K,)
    """
    mu, Sigma, u = _pose(mu), _covariance(Sigma), _control(u)
    m = _landmark_map(m)
    z = _features(z)
    dt = _dt(dt)
    alpha, sigmas = _alpha4(alpha), _sigmas(sigmas, 2)
    params = _ukf_params(ukf_alpha, beta, kappa)
    threshold = _gate_threshold(gate, 2)
    return _ukf_ml(mu, Sigma, u, z, m, dt, alpha, sigmas, params, threshold)


def _gate_threshold(gate, dof):
    if gate is None:
        return None
    g = check.finite(gate, "gate")
    if g.ndim != 0 or not 0.0 < float(g) < 1.0:
        raise ValueError(f"gate must be None or a probability in (0, 1), got {gate!r}")
    return chi2_quantile(float(g), dof)


def _ukf_ml(mu, Sigma, u, z, m, dt, alpha, sigmas, params, threshold):
    k = z.shape[0]
    if k == 0:
        mu_t, Sigma_t, _ = _ukf(
            mu, Sigma, u, z, np.zeros(0, dtype=int), m, dt, alpha, sigmas, params
        )
        return mu_t, Sigma_t, np.zeros(0, dtype=int)
    # One-feature Table 7.4 (n = 7) for every landmark at once.
    n = 7
    gamma, wm, wc = _weights_cached(n, *params)
    root = np.zeros((n, n))
    root[:3, :3] = _sqrt_psd(Sigma)
    root[3:, 3:] = np.diag(np.sqrt(np.concatenate([_motion_noise(alpha, u), sigmas[:2] ** 2])))
    chi = np.zeros((2 * n + 1, n))
    chi[:, :3] = mu
    chi[1 : n + 1] += gamma * root.T
    chi[n + 1 :] -= gamma * root.T
    xbar = _velocity_motion_core(chi[:, :3], u + chi[:, 3:5], dt)
    Z = _landmark_measurement_core(xbar[:, None, :], m[None, :, :2])  # (15, L, 2)
    Z = Z + chi[:, None, 5:7]
    zhat = np.einsum("i,ild->ld", wm, Z)
    ref = Z[0, :, 1]
    zhat[:, 1] = ref + wm @ _wrap(Z[:, :, 1] - ref)
    dz = _innovation(Z, zhat)  # (15, L, 2)
    S = np.einsum("i,ila,ilb->lab", wc, dz, dz)
    chosen = np.full(k, -1, dtype=int)
    for i in range(k):
        nu = _innovation(z[i, :2], zhat)
        d2, logp = _gaussian_terms(nu, S)
        j = int(np.argmax(logp))
        if threshold is None or d2[j] <= threshold:
            chosen[i] = j
    keep = chosen >= 0
    mu_t, Sigma_t, _ = _ukf(mu, Sigma, u, z[keep], chosen[keep], m, dt, alpha, sigmas, params)
    return mu_t, Sigma_t, chosen


# --------------------------------------------------------------------------- evaluation


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
    bias : ndarray, shape (2,)
        Mean residual of range [m] and bearing [rad].
    sigma : ndarray, shape (2,)
        Their standard deviations (Gaussian ML fit).
    robust_sigma : ndarray, shape (2,)
        1.4826 × the median absolute deviation from the median.
    """
    m = _landmark_map(m)
    z = _features(z)
    c = _correspondences(c, z.shape[0], m.shape[0])
    poses = check.poses(poses, "poses")
    if poses.shape != (z.shape[0], 3):
        raise ValueError(f"poses must have shape ({z.shape[0]}, 3), got {poses.shape}")
    if z.shape[0] < 2:
        raise ValueError("z: at least two measurements are needed to fit a noise")
    res = _innovation(z[:, :2], _landmark_measurement_core(poses, m[c, :2]))
    bias = res.mean(axis=0)
    sigma = res.std(axis=0)
    med = np.median(res, axis=0)
    robust = 1.4826 * np.median(np.abs(res - med), axis=0)
    return bias, sigma, robust


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
    dt = _step_lengths(dt, n)
    poses = check.poses(poses, "poses")
    if poses.shape != (n + 1, 3):
        raise ValueError(f"poses must have shape ({n + 1}, 3), got {poses.shape}")
    window = check.positive_scalar(window, "window")
    begins = np.concatenate([[0.0], np.cumsum(dt[:-1])])
    # A step belongs to the window its start falls in (tolerant of summed rounding).
    label = np.floor(begins / window + 1e-9).astype(int)
    cuts = np.concatenate([[0], np.flatnonzero(np.diff(label)) + 1, [n]])
    zero3 = np.zeros((3, 3))
    errors, design, starts = [], [], []
    for a, b in itertools.pairwise(cuts.tolist()):
        mus, _ = _predict_segment(poses[a], zero3, u[a:b], dt[a:b], np.zeros(4))
        e = _innovation_pose(poses[b], mus[-1])
        move = mus[-1, :2] - poses[a, :2]
        heading = math.atan2(move[1], move[0]) if np.hypot(*move) > 0 else float(poses[a, 2])
        c, s_ = math.cos(heading), math.sin(heading)
        errors.append([c * e[0] + s_ * e[1], -s_ * e[0] + c * e[1], e[2]])
        w2 = dt[a:b] ** 2
        design.append([w2 @ u[a:b, 0] ** 2, w2 @ u[a:b, 1] ** 2])
        starts.append((a, b))
    errors = np.array(errors)
    X = np.array(design)
    if np.count_nonzero(np.any(X > 0, axis=1)) < 2:
        raise ValueError("fewer than two windows with motion: cannot fit the noise")
    alpha = np.concatenate(
        [_nonnegative_lstsq(X, errors[:, 0] ** 2), _nonnegative_lstsq(X, errors[:, 2] ** 2)]
    )
    nees_w = np.full(len(errors), np.nan)
    for w, (a, b) in enumerate(starts):
        mus, Sig = _predict_segment(poses[a], zero3, u[a:b], dt[a:b], alpha)
        eig = np.linalg.eigvalsh(Sig[-1])
        if eig[0] > 1e-9 * eig[-1]:
            e = _innovation_pose(poses[b], mus[-1])
            nees_w[w] = float(e @ np.linalg.solve(Sig[-1], e))
    return MotionNoiseFit(alpha=alpha, windows=len(errors), errors=errors, nees=nees_w)


def covariance_ellipse(mu, Sigma, p=0.95, n=60):
    r"""Return ``n`` points on the ``p``-probability ellipse of the position of ``(mu, Sigma)``.

    The boundary of :math:`\{x : (x - \mu_{xy})^T \Sigma_{xy}^{-1} (x - \mu_{xy}) \le
    \chi^2_2(p)\}` for the 2×2 position block :math:`\Sigma_{xy}`: the region that
    holds the true position with probability ``p`` if the estimate is right.

    Parameters
    ----------
    mu : array_like, shape (3,) or (2,)
    Sigma : array_like, shape (3, 3) or (2, 2)
        Positive semi-definite.
    p : float
        Probability in (0, 1).
    n : int
        Number of points (the first is repeated at the end: ``n + 1`` rows).

    Returns
    -------
    xy : ndarray, shape (n + 1, 2)
    """
    mu = check.finite(mu, "mu")
    if mu.shape not in ((2,), (3,)):
        raise ValueError(f"mu must have shape (3,) or (2,), got {mu.shape}")
    mu = mu[:2]
    S = check.finite(Sigma, "Sigma")
    if S.ndim != 2 or S.shape[0] != S.shape[1] or S.shape[0] not in (2, 3):
        raise ValueError(f"Sigma must have shape (3, 3) or (2, 2), got {S.shape}")
    S = S[:2, :2]
    w, U = np.linalg.eigh(0.5 * (S + S.T))
    if w[0] < -1e-12 * max(1.0, w[-1]):
        raise ValueError("Sigma is not positive semi-definite")
    radius = math.sqrt(chi2_quantile(p, 2))
    t = np.linspace(0.0, 2.0 * np.pi, check.count(n, "n", 1) + 1)
    circle = np.stack([np.cos(t), np.sin(t)], axis=-1)
    return mu + radius * (circle * np.sqrt(np.clip(w, 0.0, None))) @ U.T


def nees(x_true, mu, Sigma):
    r"""Return the normalised estimation error squared :math:`e^T \Sigma^{-1} e`.

    :math:`e = x - \mu` with the heading error wrapped. For a consistent filter it is
    :math:`\chi^2_3`-distributed: mean 3 (Bar-Shalom, Li & Kirubarajan, *Estimation
    with Applications to Tracking and Navigation*, §5.4).

    Parameters
    ----------
    x_true, mu : array_like, shape (..., 3)
        True poses and estimates.
    Sigma : array_like, shape (..., 3, 3)
        Estimate covariances (positive definite).

    Returns
    -------
    nees : float or ndarray, shape (...)
    """
    x_true = check.poses(x_true, "x_true")
    mu = check.poses(mu, "mu")
    Sigma = check.finite(Sigma, "Sigma")
    if Sigma.ndim < 2 or Sigma.shape[-2:] != (3, 3):
        raise ValueError(f"Sigma must have shape (..., 3, 3), got {Sigma.shape}")
    e = _innovation_pose(x_true, mu)
    d2, _ = _gaussian_terms(e, Sigma, "Sigma")
    return check.scalar_or_array(d2)


def _innovation_pose(x_true, mu):
    e = np.subtract(x_true, mu)
    e[..., 2] = _wrap(e[..., 2])
    return e


@dataclass(frozen=True)
class FilterRun:
    r"""The estimates of :func:`run_filter`, one row per step (after its correction).

    Attributes
    ----------
    t : ndarray, shape (T,)
        Step times.
    mu : ndarray, shape (T, 3)
    Sigma : ndarray, shape (T, 3, 3)
    c : list of ndarray of int
        Per step, the landmark used for each feature (given or chosen; -1 = gated out).
    log_pz : ndarray, shape (T,)
        :math:`\log p(z_t)` (NaN for the ML filters, which return none).
    """

    t: np.ndarray
    mu: np.ndarray
    Sigma: np.ndarray
    c: list
    log_pz: np.ndarray


_METHODS = ("ekf", "ekf_ml", "ukf", "ukf_ml")


def run_filter(
    steps: Sequence,
    mu0,
    Sigma0,
    m,
    alpha,
    sigmas,
    *,
    method="ekf",
    signatures=True,
    gate=None,
    ukf_alpha=1.0,
    beta=2.0,
    kappa=0.0,
):
    r"""Run a filter over ``steps`` and return a :class:`FilterRun`.

    Parameters
    ----------
    steps : sequence
        Items with attributes ``t``, ``dt``, ``u`` (2,), ``z`` (k, 3) and ``c`` (k,),
        e.g. :attr:`probrob.simulation.SimRun.steps` or a dataset's ``stream()``.
    mu0 : array_like, shape (3,)
    Sigma0 : array_like, shape (3, 3)
    m, alpha, sigmas
        As in :func:`ekf_localization_known_correspondences`.
    method : {"ekf", "ekf_ml", "ukf", "ukf_ml"}
        Table 7.2 (``c`` from the steps), Table 7.3 (``c`` chosen by maximum
        likelihood), Table 7.4 (``c`` from the steps) or :func:`ukf_localization_ml`.
        Steps without features of the two EKFs are predicted together by
        :func:`ekf_predict_segment` (exact).
    signatures : bool
        ``False`` drops the signature column of every ``z`` (association and update on
        range and bearing only).
    gate : float, optional
        The χ² gate of :func:`ekf_localization` (``"ekf_ml"`` and ``"ukf_ml"`` only).
    ukf_alpha, beta, kappa : float
        The UKF's parameters (``"ukf"`` and ``"ukf_ml"``).
    """
    check.choice(method, "method", _METHODS)
    mu, Sigma = _pose(mu0, "mu0"), _covariance(Sigma0, "Sigma0")
    signatures = check.flag(signatures, "signatures")
    if not (hasattr(steps, "__len__") and hasattr(steps, "__iter__")):
        raise ValueError(f"steps must be a sequence of steps, got {check._short(steps)}")
    m = _landmark_map(m)
    alpha = _alpha4(alpha)
    sigmas = _sigmas(sigmas, 3 if method.startswith("ekf") else 2)
    if gate is not None and method not in ("ekf_ml", "ukf_ml"):
        raise ValueError("gate applies to method='ekf_ml' or 'ukf_ml' only")
    threshold = _gate_threshold(gate, 3 if signatures and method == "ekf_ml" else 2)
    params = _ukf_params(ukf_alpha, beta, kappa)

    T = len(steps)
    t = np.empty(T)
    dts = np.empty(T)
    us = np.empty((T, 2))
    zs, cs_true = [], []
    known = method in ("ekf", "ukf")
    no_z = np.zeros((0, 3 if signatures else 2))
    no_c = np.zeros(0, dtype=int)
    for i, step in enumerate(steps):
        t[i] = step.t
        dts[i] = step.dt
        us[i] = step.u
        if len(step.z) == 0:  # most steps of a real run: nothing to check
            zs.append(no_z)
            cs_true.append(no_c)
            continue
        z = _features(step.z)
        if not signatures:
            z = z[:, :2]
        zs.append(z)
        cs_true.append(_correspondences(step.c, z.shape[0], m.shape[0]) if known else None)
    if not np.all(np.isfinite(us)):
        raise ValueError("steps: every u must be finite")
    if not np.all(dts > 0):
        raise ValueError("steps: every dt must be > 0")

    mus = np.empty((T, 3))
    Sigmas = np.empty((T, 3, 3))
    cs = [None] * T
    log_pz = np.full(T, np.nan)
    i = 0
    while i < T:
        if method.startswith("ekf") and zs[i].shape[0] == 0:
            # A stretch without features: the exact vectorised composition of predictions.
            j = i
            while j < T and zs[j].shape[0] == 0:
                j += 1
            seg_mu, seg_Sigma = _predict_segment(mu, Sigma, us[i:j], dts[i:j], alpha)
            seg_mu[:, 2] = _wrap(seg_mu[:, 2])
            mus[i:j], Sigmas[i:j] = seg_mu, seg_Sigma
            for k in range(i, j):
                cs[k] = np.zeros(0, dtype=int)
            log_pz[i:j] = 0.0 if method == "ekf" else np.nan
            mu, Sigma = seg_mu[-1], seg_Sigma[-1]
            i = j
            continue
        if method == "ekf":
            mu, Sigma, log_pz[i] = _ekf_known(
                mu, Sigma, us[i], zs[i], cs_true[i], m, dts[i], alpha, sigmas
            )
            cs[i] = cs_true[i]
        elif method == "ekf_ml":
            mu_bar, Sigma_bar = _ekf_predict(mu, Sigma, us[i], dts[i], alpha)
            mu, Sigma, cs[i] = _ekf_ml_correct(mu_bar, Sigma_bar, zs[i], m, sigmas, threshold)
        elif method == "ukf_ml":
            mu, Sigma, cs[i] = _ukf_ml(
                mu, Sigma, us[i], zs[i], m, dts[i], alpha, sigmas, params, threshold
            )
        else:
            mu, Sigma, log_pz[i] = _ukf(
                mu, Sigma, us[i], zs[i], cs_true[i], m, dts[i], alpha, sigmas, params
            )
            cs[i] = cs_true[i]
        mus[i] = mu
        Sigmas[i] = Sigma
        i += 1
    return FilterRun(t=t, mu=mus, Sigma=Sigmas, c=cs, log_pz=log_pz)
