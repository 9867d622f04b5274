r"""Gaussian filter localization of *Probabilistic Robotics*, chapter 7 (Tables 7.2–7.4).

Holds the EKF (Tables 7.2, 7.3), the UKF (Table 7.4) and :func:`run_filter`, which runs one
of them along a sequence of steps. Does not hold the models :math:`g, h` (:mod:`probrob.motion`,
:mod:`probrob.sensors`), noise fits (:mod:`probrob.fitting`) or the NEES, its χ² bounds and
the covariance ellipse (:mod:`probrob.evaluation`).

* :func:`ekf_localization_known_correspondences` — Table 7.2, the EKF with known
  correspondences, returning :math:`\mu_t, \Sigma_t` and the measurement likelihood
  :math:`p(z_t)`;
* :func:`ekf_localization` — Table 7.3, the EKF with maximum-likelihood data
  association (unknown correspondences), with an optional χ² gate;
* :func:`ukf_localization` — Table 7.4, the UKF with the augmented state (pose, control
  noise, measurement noise); several features of one step are stacked into one update;
  :func:`ukf_weights` its weights, :func:`ukf_localization_ml` Table 7.4 with the
  association of Table 7.3;
* :func:`ekf_predict_segment` — the predictions of Table 7.2 over many steps at once;
* :func:`run_filter` — one of the filters over a sequence of steps (a simulation or a
  dataset's ``stream()``), collecting the estimates in a :class:`FilterRun`.

Each table is written once, with the book's names (``G``, ``V``, ``M``, ``H``, ``S``,
``K``, ``mu_bar``, ``Sigma_bar``) in the order of its lines. :math:`g` and its Jacobians
come from :mod:`probrob.motion` (exact at :math:`\omega = 0`), :math:`h` and its Jacobian
from :mod:`probrob.sensors`, so each model exists once. The public functions check their
input once (:mod:`probrob._validation`) and then call the unchecked cores under one
``np.errstate`` (:func:`run_filter`: one for the whole run). On the tables' 2×2 and 3×3
matrices numpy's per-call cost exceeds the arithmetic: the EKF's per-feature loop (Table
7.2, lines 9–18) is compiled by numba (the same matrix lines, ``@`` and ``np.linalg``; the
models' scalar code compiled with it), and elsewhere the lines are spelled as filterpy
spells them, products with ``ndarray.dot``, and :math:`S^{-1}` with its Cholesky factor
from one LAPACK call (``dposv``), not from ``np.linalg`` calls that each check their input
again. Every
bearing innovation, and every bearing and heading residual of the UKF, is wrapped with
:mod:`probrob.angles`; the returned mean heading is wrapped to :math:`[-\pi, \pi)`.

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
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numba import njit
from scipy.linalg.lapack import dposv as _dposv
from scipy.linalg.lapack import dpotrf as _dpotrf

from . import _validation as check
from .angles import _wrap, _wrap_one
from .evaluation import chi2_quantile
from .motion import (
    _arc,
    _velocity_jacobian_entries,
    _velocity_jacobians_core,
    _velocity_motion_core,
)
from .sensors import (
    _jacobian_entries_one,
    _landmark_jacobian_core,
    _landmark_measurement_core,
    _range_bearing_one,
)

__all__ = [
    "FilterRun",
    "ekf_localization",
    "ekf_localization_known_correspondences",
    "ekf_predict_segment",
    "run_filter",
    "ukf_localization",
    "ukf_localization_ml",
    "ukf_weights",
]

_LOG_2PI = math.log(2.0 * math.pi)
_S_NAME = "S (the innovation covariance, from Sigma and sigmas)"


class _NonFinite(ValueError):
    """A filter's arithmetic left float64 (inf or NaN from finite input).

    Raised by the cores; each public function turns it into
    :func:`probrob._validation.overflow_error` naming its own most extreme argument.
    """


def _finite_or_raise(what: str, *arrays) -> None:
    if not all(map(check.all_finite, arrays)):
        raise _NonFinite(what)


def _checked(core, what: str, arguments):
    """Call ``core()``; a :class:`_NonFinite` becomes an overflow error naming ``arguments``.

    ``arguments`` is a dict of the caller's arguments, or a function returning it (built
    only for the error).
    """
    try:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            return core()
    except _NonFinite as exc:
        named = arguments() if callable(arguments) else arguments
        raise check.overflow_error(f"{what} ({exc})", **named) from None


# --------------------------------------------------------------------------- shared pieces


def _motion_noise(alpha: np.ndarray, u: np.ndarray) -> np.ndarray:
    r"""Diagonal of :math:`M_t` (Table 7.2, line 5): the control-noise variances.

    :math:`(\alpha_1 v^2 + \alpha_2 \omega^2,\ \alpha_3 v^2 + \alpha_4 \omega^2)` for
    ``u`` of shape (..., 2).
    """
    return (u * u).dot(alpha.reshape(2, 2).T)


def _innovation(z: np.ndarray, z_hat: np.ndarray) -> np.ndarray:
    """``z - z_hat`` with the bearing (second component) wrapped to [-π, π)."""
    nu = z - z_hat
    nu[..., 1] = _wrap(nu[..., 1] if nu.ndim > 1 else float(nu[1]))
    return nu


def _cholesky(S: np.ndarray, name: str = _S_NAME) -> np.ndarray:
    """Lower Cholesky factor of ``S`` (..., n, n), or ``ValueError`` naming ``name``."""
    try:
        L = np.linalg.cholesky(S)
    except np.linalg.LinAlgError:
        L = None
    if L is None or not np.all(np.isfinite(L)):
        raise _not_positive_definite(name)
    return L


def _not_positive_definite(name: str) -> ValueError:
    return ValueError(
        f"{name} is not positive definite (a covariance must be symmetric with "
        "positive eigenvalues); check the scales of Sigma and sigmas"
    )


@functools.cache
def _identity(n: int) -> np.ndarray:
    eye = np.eye(n)
    eye.setflags(write=False)
    return eye


def _diag(v: np.ndarray) -> np.ndarray:
    """``np.diag(v)`` of a vector ``v`` (n,): ``v`` times the identity (one multiplication,
    where ``np.diag`` costs more in its checks than in the arithmetic on a 2×2 or 3×3)."""
    return v * _identity(v.shape[0])


def _inverse(S: np.ndarray, name: str = _S_NAME):
    r""":math:`S^{-1}` and the Cholesky factor :math:`L` of one positive-definite ``S`` (n, n).

    One factorisation :math:`S = LL^T` and the solution of :math:`SX = I` with it (LAPACK
    ``dposv``, one call: ``np.linalg`` on a 2×2 or 3×3 matrix costs more in its checks than
    in the arithmetic), or ``ValueError`` naming ``name``. ``L`` is the lower triangle of the
    array returned (its upper triangle is left as ``S``'s): for :func:`_log_normal_one`.
    """
    if not check.all_finite(S):  # LAPACK would factor an infinite diagonal entry
        raise _not_positive_definite(name)
    L, S_inv, info = _dposv(S, _identity(S.shape[0]), lower=1)
    if info != 0 or not check.all_finite(S_inv):
        raise _not_positive_definite(name)
    return S_inv, L


def _log_normal(nu: np.ndarray, L: np.ndarray):
    r"""Mahalanobis distances² and :math:`\log N(\nu; 0, S)` with ``L`` the Cholesky factor of S."""
    w = np.linalg.solve(L, nu[..., None])[..., 0]
    d2 = np.sum(w * w, axis=-1)
    log_det = 2.0 * np.sum(np.log(np.diagonal(L, axis1=-2, axis2=-1)), axis=-1)
    return d2, -0.5 * (d2 + log_det + nu.shape[-1] * _LOG_2PI)


def _sqrt_psd(S: np.ndarray) -> np.ndarray:
    """A square root ``R`` with ``R @ R.T == S``: the lower Cholesky factor if ``S`` is
    positive definite, else the symmetric root (``S`` positive semi-definite)."""
    L, info = _dpotrf(S, lower=1)  # LAPACK's Cholesky (its other triangle zeroed)
    if info == 0:
        return L
    w, U = np.linalg.eigh(S)
    return U * np.sqrt(np.clip(w, 0.0, None))


def _finish(mu: np.ndarray, Sigma: np.ndarray):
    """Lines 19–20 (Tables 7.2, 7.3) and 15–16 (7.4): the heading wrapped, Σ symmetrised."""
    _finite_or_raise("the estimate", mu, Sigma)
    mu[2] = _wrap(mu.item(2))  # in place: every caller passes an array of its own
    return mu, 0.5 * (Sigma + Sigma.T)


def _filter_arguments(mu, Sigma, u, z, m, dt, alpha, sigmas, sigma_lengths):
    """The checks shared by the one-step filters; returns the validated arrays."""
    return (
        check.single_pose(mu, "mu"),
        check.covariance(Sigma, "Sigma"),
        check.vector(u, "u", 2, "v, omega"),
        check.features(z, "z"),
        check.landmark_map(m, "m"),
        check.positive_scalar(dt, "dt"),
        check.alphas(alpha, "alpha", 4),
        check.sigmas(sigmas, "sigmas", sigma_lengths, positive=True),
    )


# --------------------------------------------------------------------------- Table 7.2


def _model_at(function, *args):
    """A model function of :mod:`probrob.motion` or :mod:`probrob.sensors` at one point (floats).

    Float arithmetic overflows to ``inf`` silently, but ``math.sin(inf)`` raises: both are
    reported as :class:`_NonFinite`.
    """
    try:
        values = function(*args)
    except (ValueError, OverflowError):
        raise _NonFinite("the motion model") from None
    if not all(map(math.isfinite, values)):
        raise _NonFinite("the motion model")
    return values


def _ekf_predict(mu, Sigma, u, dt, alpha):
    """Table 7.2, lines 2–7 (the prediction, shared by Table 7.3), on validated input.

    :math:`g` and the entries of :math:`G_t, V_t` are the model code of
    :mod:`probrob.motion` evaluated at the one pose; the matrices are the table's.
    """
    x, y, theta = mu.tolist()  # line 2
    v, w = u.tolist()
    g13, g23, v11, v21, v12, v22 = _model_at(_velocity_jacobian_entries, theta, v, w, dt)
    G = np.array([[1.0, 0.0, g13], [0.0, 1.0, g23], [0.0, 0.0, 1.0]])  # line 3
    V = np.array([[v11, v12], [v21, v22], [0.0, dt]])  # line 4
    M = _diag(_motion_noise(alpha, u))  # line 5
    mu_bar = np.array(_model_at(_arc, x, y, theta, v, w, dt))  # line 6
    Sigma_bar = G.dot(Sigma).dot(G.T) + V.dot(M).dot(V.T)  # line 7
    _finite_or_raise("the prediction", Sigma_bar)
    return mu_bar, Sigma_bar


@njit(cache=True, error_model="numpy")
def _landmark_at(mu_bar, landmark, d):
    r"""Table 7.2, lines 11–13, for one landmark: :math:`\hat z` and :math:`H` (``d`` rows).

    :math:`h` and the entries of :math:`H` are the model code of :mod:`probrob.sensors`
    evaluated at the one pose; the matrix is the table's.
    """
    x, y, theta = mu_bar[0], mu_bar[1], mu_bar[2]
    m_x, m_y, m_s = landmark[0], landmark[1], landmark[2]
    delta_x, delta_y = m_x - x, m_y - y  # line 11: q = δ_x² + δ_y²
    r_hat, phi_hat = _range_bearing_one(delta_x, delta_y, theta)
    z_hat = np.array([r_hat, phi_hat, m_s])[:d]  # line 12
    h11, h12, h21, h22 = _jacobian_entries_one(delta_x, delta_y)
    H = np.array([[h11, h12, 0.0], [h21, h22, -1.0], [0.0, 0.0, 0.0]])[:d]  # line 13
    return z_hat, H


@njit(cache=True, error_model="numpy")
def _forward_solve(L, v):
    """:math:`L^{-1} v` for the lower triangle of ``L`` (n, n) (its upper triangle unread)."""
    w = np.empty(v.shape[0])
    for i in range(v.shape[0]):
        s = v[i]
        for j in range(i):
            s -= L[i, j] * w[j]
        w[i] = s / L[i, i]
    return w


@njit(cache=True, error_model="numpy")
def _log_normal_one(nu, L):
    r""":math:`\log N(\nu; 0, S)` of one ``nu`` (n,), ``L`` (n, n) holding the lower Cholesky
    factor of ``S`` in its lower triangle (its upper triangle is not read).

    The Mahalanobis distance² as :math:`|L^{-1}\nu|^2`; where that overflows (the solve
    may give ``inf - inf``), as :math:`s^2 |L^{-1}(\nu / s)|^2` with :math:`s = \max|\nu_i|`:
    +inf, never NaN. The log-determinant from the diagonal of ``L``. Compiled.
    """
    w = _forward_solve(L, nu)
    d2 = w.dot(w)
    if not d2 < math.inf:
        scale = np.abs(nu).max()
        w = _forward_solve(L, nu / scale)
        d2 = scale * scale * w.dot(w)
    log_det = 2.0 * np.log(np.diag(L)).sum()
    return -0.5 * (d2 + log_det + nu.shape[0] * _LOG_2PI)


@njit(cache=True, error_model="numpy")
def _ekf_updates(mu_bar, Sigma_bar, z, landmarks, Q):
    r"""Table 7.2, lines 9–18 and the factors of line 21, compiled: the features ``z``
    (K, d) of the landmarks ``landmarks`` (K, 3) (rows ``m[c]``) in turn; returns
    :math:`\bar\mu, \bar\Sigma` after the last and :math:`\log p(z_t)`.

    Raises ``np.linalg.LinAlgError`` where an ``S`` is not positive definite (or not finite).
    """
    I = np.eye(3)  # noqa: E741 (the table's I)
    log_p = 0.0
    for i in range(z.shape[0]):  # lines 9-10
        z_hat, H = _landmark_at(mu_bar, landmarks[i], z.shape[1])  # lines 11-13
        S = H @ Sigma_bar @ H.T + Q  # line 14
        L = np.linalg.cholesky(S)
        S_inv = np.linalg.inv(S)
        if not np.all(np.isfinite(S_inv)):
            raise np.linalg.LinAlgError("S has no finite inverse")
        K = Sigma_bar @ H.T @ S_inv  # line 15
        nu = z[i] - z_hat
        nu[1] = _wrap_one(nu[1])
        mu_bar = mu_bar + K @ nu  # line 16
        Sigma_bar = (I - K @ H) @ Sigma_bar  # line 17
        log_p += _log_normal_one(nu, L)  # line 21, one factor
    return mu_bar, Sigma_bar, log_p


def _ekf_known(mu, Sigma, u, z, c, m, dt, alpha, sigmas):
    """Table 7.2 on validated input; returns μ_t, Σ_t and log p(z_t)."""
    mu_bar, Sigma_bar = _ekf_predict(mu, Sigma, u, dt, alpha)  # lines 2-7
    d = z.shape[1]
    Q = _diag(sigmas[:d] ** 2)  # line 8
    try:
        mu_bar, Sigma_bar, log_p = _ekf_updates(mu_bar, Sigma_bar, z, m[c], Q)  # lines 9-18
    except np.linalg.LinAlgError:
        raise _not_positive_definite(_S_NAME) from None
    mu_t, Sigma_t = _finish(mu_bar, Sigma_bar)  # lines 19-20
    return mu_t, Sigma_t, log_p


def ekf_localization_known_correspondences(mu, Sigma, u, z, c, m, dt, alpha, sigmas, *, log=False):
    r"""Table 7.2, lines 1–22: return :math:`\mu_t, \Sigma_t, p(z_t)` of one EKF step.

    *Probabilistic Robotics*, Table 7.2 (EKF localization with known correspondences).
    Prediction with the velocity motion model (lines 2–7):

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
        On bad input, a non-positive-definite ``Sigma`` or innovation covariance ``S``, or
        an estimate that overflows float64 (naming the most extreme argument).
    """
    args = _filter_arguments(mu, Sigma, u, z, m, dt, alpha, sigmas, (3,))
    mu, Sigma, u, z, m, dt, alpha, sigmas = args
    c = check.landmark_indices(c, "c", z.shape[0], m.shape[0])
    log = check.flag(log, "log")
    mu_t, Sigma_t, log_p = _checked(
        lambda: _ekf_known(mu, Sigma, u, z, c, m, dt, alpha, sigmas),
        "Table 7.2's step",
        lambda: dict(mu=mu, Sigma=Sigma, u=u, z=z, dt=dt, alpha=alpha, sigmas=sigmas),
    )
    return mu_t, Sigma_t, (log_p if log else math.exp(log_p))


# --------------------------------------------------------------------------- segments


def ekf_predict_segment(mu, Sigma, u, dt, alpha):
    r"""Table 7.2, lines 2–7, over ``n`` steps without features: all predictions at once.

    The composition of ``n`` prediction steps of Table 7.2,
    :math:`\bar\mu_k = g(u_k, \bar\mu_{k-1})`,
    :math:`\bar\Sigma_k = G_k \bar\Sigma_{k-1} G_k^T + V_k M_k V_k^T`, evaluated without
    a loop over time. Two facts make this exact:

    * :math:`g` moves the heading by :math:`\omega_k\Delta t_k` whatever the position, so
      the headings are a cumulative sum and the position increments follow from them;
    * every :math:`G_k = I + p_k e_3^T` with :math:`p_k = (G_{k,13}, G_{k,23}, 0)`, and
      :math:`e_3^T p_j = 0`, so :math:`G_k \cdots G_{j+1} = I + (P_k - P_j) e_3^T` with
      :math:`P_k = \sum_{i \le k} p_i`. With :math:`Q_j = V_j M_j V_j^T`,
      :math:`r_j` its third column and :math:`q_j` its (3, 3) entry,

      .. math::
          \bar\Sigma_k = \Phi_k \Sigma_0 \Phi_k^T + \sum_{j \le k} \left[Q_j + D r_j^T
          + r_j D^T + q_j D D^T\right]_{D = P_k - P_j},

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
        :math:`\bar\mu_1 \ldots \bar\mu_n` (headings not wrapped).
    Sigma : ndarray, shape (n, 3, 3)

    Raises
    ------
    ValueError
        On bad input, or predictions that overflow float64 (naming the most extreme
        argument).
    """
    mu, Sigma = check.single_pose(mu, "mu"), check.covariance(Sigma, "Sigma")
    u = check.vectors(u, "u", 2, "v, omega")
    if u.ndim != 2:
        raise ValueError(f"u must have shape (n, 2), got {u.shape}")
    dt = check.step_lengths(dt, "dt", u.shape[0])
    alpha = check.alphas(alpha, "alpha", 4)
    return _checked(
        lambda: _predict_segment(mu, Sigma, u, dt, alpha),
        "the predictions",
        dict(mu=mu, Sigma=Sigma, u=u, dt=dt, alpha=alpha),
    )


def _predict_segment(mu, Sigma, u, dt, alpha):
    """:func:`ekf_predict_segment` on validated input (under ``np.errstate``)."""
    n = u.shape[0]
    if n == 0:
        return np.zeros((0, 3)), np.zeros((0, 3, 3))
    # g(x, (v, ω), Δt) = g(x, (vΔt, ωΔt), 1) and V(x, u, Δt) = Δt·V(x, uΔt, 1).
    ud = u * dt[:, None]
    starts = np.zeros((n, 3))
    starts[0, 2] = mu[2]
    starts[1:, 2] = mu[2] + np.cumsum(ud[:-1, 1])
    steps = _velocity_motion_core(starts, ud, 1.0)  # position increments, new headings
    mu_bar = np.empty((n, 3))
    mu_bar[:, 0] = mu[0] + np.cumsum(steps[:, 0])
    mu_bar[:, 1] = mu[1] + np.cumsum(steps[:, 1])
    mu_bar[:, 2] = steps[:, 2]
    G, V = _velocity_jacobians_core(starts, ud, 1.0)
    V *= dt[:, None, None]
    M = _motion_noise(alpha, u)  # (n, 2), the diagonals of M_k
    Q = (V * M[:, None, :]) @ np.swapaxes(V, -1, -2)  # V_k M_k V_k^T, (n, 3, 3)
    P = np.zeros((n, 3))
    P[:, 0] = np.cumsum(G[:, 0, 2])
    P[:, 1] = np.cumsum(G[:, 1, 2])
    r = Q[:, :, 2]
    q = Q[:, 2, 2]
    R = np.cumsum(r, axis=0)
    C = np.cumsum(P[:, :, None] * r[:, None, :], axis=0)
    W = np.cumsum(q)
    E = np.cumsum(q[:, None] * P, axis=0)
    F = np.cumsum(q[:, None, None] * P[:, :, None] * P[:, None, :], axis=0)
    X = P[:, :, None] * R[:, None, :] - C
    PP = P[:, :, None] * P[:, None, :]
    PE = P[:, :, None] * E[:, None, :]
    noise = np.cumsum(Q, axis=0) + X + np.swapaxes(X, -1, -2) + W[:, None, None] * PP
    noise += F - PE - np.swapaxes(PE, -1, -2)
    Phi = np.broadcast_to(np.eye(3), (n, 3, 3)).copy()
    Phi[:, :, 2] += P
    Sigma_bar = Phi @ Sigma @ np.swapaxes(Phi, -1, -2) + noise
    _finite_or_raise("the predictions", mu_bar, Sigma_bar)
    return mu_bar, 0.5 * (Sigma_bar + np.swapaxes(Sigma_bar, -1, -2))


# --------------------------------------------------------------------------- Table 7.3


def _ekf_ml(mu, Sigma, u, z, m, dt, alpha, sigmas, threshold):
    """Table 7.3 on validated input: every landmark scored at once, features in sequence."""
    mu_bar, Sigma_bar = _ekf_predict(mu, Sigma, u, dt, alpha)  # lines 2-7
    d = z.shape[1]
    Q = _diag(sigmas[:d] ** 2)  # line 8
    I = _identity(3)  # noqa: E741 (the table's I)
    landmarks = m[:, :d]
    j = np.full(z.shape[0], -1, dtype=int)
    for i in range(z.shape[0]):  # line 9; lines 10-15 for all landmarks k at once
        z_hat = _landmark_measurement_core(mu_bar, landmarks)  # lines 11-12, (L, d)
        H = _landmark_jacobian_core(mu_bar, landmarks)  # line 13, (L, d, 3)
        S = H @ Sigma_bar @ np.swapaxes(H, -1, -2) + Q  # line 14, (L, d, d)
        nu = _innovation(z[i], z_hat)
        d2, log_p = _log_normal(nu, _cholesky(S))
        k = int(np.argmax(log_p))  # line 16: j(i) = argmax_k N(z_i; z_hat_k, S_k)
        if threshold is not None and d2[k] > threshold:
            continue
        j[i] = k
        K = Sigma_bar.dot(H[k].T).dot(_inverse(S[k])[0])  # line 17
        mu_bar = mu_bar + K.dot(nu[k])  # line 18
        Sigma_bar = (I - K.dot(H[k])).dot(Sigma_bar)  # line 19
    mu_t, Sigma_t = _finish(mu_bar, Sigma_bar)  # lines 21-22
    return mu_t, Sigma_t, j


def _gate_threshold(gate, dof):
    if gate is None:
        return None
    return chi2_quantile(check.open_probability(gate, "gate"), dof)


def ekf_localization(mu, Sigma, u, z, m, dt, alpha, sigmas, *, gate=None):
    r"""Table 7.3, lines 1–23: return :math:`\mu_t, \Sigma_t` and the most likely landmark of each feature.

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
        the χ² gate :math:`(z - \hat z)^T S^{-1} (z - \hat z) >`
        :func:`~probrob.evaluation.chi2_quantile` ``(gate, d)`` (``d`` = 2 or 3
        components) is rejected (index -1) and not used.

    Returns
    -------
    mu : ndarray, shape (3,)
    Sigma : ndarray, shape (3, 3)
    c : ndarray of int, shape (K,)
        The chosen landmark row :math:`j(i)` of each feature; -1 where the gate rejected it.
    """
    args = _filter_arguments(mu, Sigma, u, z, m, dt, alpha, sigmas, (3,))
    mu, Sigma, u, z, m, dt, alpha, sigmas = args
    threshold = _gate_threshold(gate, z.shape[1])
    return _checked(
        lambda: _ekf_ml(mu, Sigma, u, z, m, dt, alpha, sigmas, threshold),
        "Table 7.3's step",
        lambda: dict(mu=mu, Sigma=Sigma, u=u, z=z, dt=dt, alpha=alpha, sigmas=sigmas),
    )


# --------------------------------------------------------------------------- Table 7.4


def ukf_weights(n: int, ukf_alpha: float = 1.0, beta: float = 2.0, kappa: float = 0.0):
    r"""The weights of Table 7.4, lines 6–13: return :math:`\gamma, w^{(m)}, w^{(c)}`.

    *Probabilistic Robotics*, Sec. 3.4.2 (the unscented Kalman filter, Table 3.4), the
    scaled sigma points of Wan and van der Merwe: with :math:`\lambda = \alpha^2 (n + \kappa) - n`,

    .. math::
        \gamma = \sqrt{n + \lambda},\quad
        w_0^{(m)} = \frac{\lambda}{n + \lambda},\quad
        w_0^{(c)} = \frac{\lambda}{n + \lambda} + (1 - \alpha^2 + \beta),\quad
        w_i^{(m)} = w_i^{(c)} = \frac{1}{2(n + \lambda)}\ (i = 1 \ldots 2n).

    :math:`n + \lambda = \alpha^2 (n + \kappa)` is computed as that product (not as
    :math:`n + \lambda` after rounding :math:`\lambda`). Parameters for which it is not a
    positive float64, or for which the weights are not finite or cancel to rounding (the
    weighted mean of equal points must return the point to 1e-6; about
    :math:`\alpha < 2\cdot10^{-5}`), raise ``ValueError`` naming them.

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
    beta = check.real_scalar(beta, "beta")
    kappa = check.real_scalar(kappa, "kappa")
    return _ukf_weights(n, a, beta, kappa)


def _ukf_weights(n, a, beta, kappa):
    if not n + kappa > 0:
        raise ValueError(f"kappa must satisfy n + kappa > 0 (n = {n}), got {kappa!r}")
    spread = a * a * (n + kappa)  # n + λ
    lam = spread - n
    given = f"ukf_alpha = {a!r}, beta = {beta!r}, kappa = {kappa!r}, n = {n}"
    if not (math.isfinite(spread) and spread > 0):
        raise ValueError(
            f"ukf_alpha and kappa give n + lambda = ukf_alpha**2 (n + kappa) = {spread!r}, "
            f"which must be a positive float64; got {given}"
        )
    with np.errstate(over="ignore", invalid="ignore"):
        wm = np.full(2 * n + 1, 0.5 / spread)
        wc = wm.copy()
        wm[0] = lam / spread
        wc[0] = lam / spread + (1.0 - a * a + beta)
        rounding = np.finfo(float).eps * float(np.sum(np.abs(wm)))
    if not (np.all(np.isfinite(wm)) and np.all(np.isfinite(wc))):
        raise ValueError(f"ukf_alpha, beta and kappa give non-finite weights; got {given}")
    if not (rounding <= 1e-6 and abs(float(np.sum(wm)) - 1.0) <= 1e-6):
        raise ValueError(
            f"ukf_alpha is too small: the weights (w0 = {wm[0]:.3g}) cancel to rounding "
            f"(their sum is {float(np.sum(wm))!r}, not 1); got {given}"
        )
    return math.sqrt(spread), wm, wc


@functools.lru_cache(maxsize=64)
def _weights_cached(n, a, beta, kappa):
    gamma, wm, wc = _ukf_weights(n, a, beta, kappa)
    wm.setflags(write=False)
    wc.setflags(write=False)
    return gamma, wm, wc


def _ukf_params(ukf_alpha, beta, kappa):
    a = check.positive_scalar(ukf_alpha, "ukf_alpha")
    beta = check.real_scalar(beta, "beta")
    kappa = check.real_scalar(kappa, "kappa")
    _weights_cached(5, a, beta, kappa)  # the smallest state: a step without features
    return a, beta, kappa


def _circular_mean(w, angles):
    r"""Weighted mean of ``angles`` (sigma points along axis 0) about the central point.

    :math:`\theta_0 + \sum_i w_i \mathrm{wrap}(\theta_i - \theta_0)`: the mean of the
    angles unwrapped next to :math:`\theta_0`, right across ±π and with a negative
    :math:`w_0` (where a mean of unit vectors would not be).
    """
    return angles[0] + w.dot(_wrap(angles - angles[0]))


def _ukf_predict(mu, Sigma, u, dt, alpha, sigmas, k, params):
    r"""Table 7.4, lines 2–9, with ``k`` features: the predicted sigma points and moments.

    Returns :math:`\bar\chi^x` (2n+1, 3), :math:`\chi^z` (2n+1, 2k), the weights,
    :math:`\bar\mu`, :math:`\bar\Sigma` and the pose residuals :math:`\bar\chi^x_i -
    \bar\mu` (2n+1, 3, heading wrapped).
    """
    n = 5 + 2 * k
    gamma, wm, wc = _weights_cached(n, *params)
    M = _motion_noise(alpha, u)  # line 2, the diagonal of M_t
    Q = sigmas[:2] ** 2  # line 3, the diagonal of Q_t
    mu_a = np.zeros(n)  # line 4: (mu, 0, 0)
    mu_a[:3] = mu
    # Line 5: Σ^a = diag(Σ, M_t, Q_t, ..., Q_t) (one Q_t a feature), and its square root
    # block by block (M_t is zero for a robot at rest, which a Cholesky of the whole matrix
    # would reject; for a positive-definite Σ^a this is its Cholesky factor).
    root = np.zeros((n, n))
    root[:3, :3] = _sqrt_psd(Sigma)
    root.ravel()[3 * (n + 1) :: n + 1] = np.sqrt(np.concatenate([M, *[Q] * k]))  # diagonal
    spread = gamma * root.T
    chi_a = np.concatenate([mu_a[None], mu_a + spread, mu_a - spread])  # line 6
    chi_x, chi_u, chi_z = chi_a[:, :3], chi_a[:, 3:5], chi_a[:, 5:]
    chi_x_bar = np.empty((2 * n + 1, 3))  # line 7: g(u + χ^u, χ^x), the motion model's _arc
    u_a = u + chi_u
    _arc(chi_x[:, 0], chi_x[:, 1], chi_x[:, 2], u_a[:, 0], u_a[:, 1], dt, out=chi_x_bar)
    _finite_or_raise("the predicted sigma points", chi_x_bar)
    mu_bar = wm.dot(chi_x_bar)  # line 8
    mu_bar[2] = _circular_mean(wm, chi_x_bar[:, 2])
    dx = chi_x_bar - mu_bar
    dx[:, 2] = _wrap(dx[:, 2])
    Sigma_bar = (wc[:, None] * dx).T.dot(dx)  # line 9 (symmetrised with Σ_t, by _finish)
    # A sum of outer products with weights >= 0 is positive semi-definite; only a negative
    # w_0^(c) (a small ukf_alpha) can break it.
    if wc[0] < 0 and not check.is_positive_semidefinite(Sigma_bar):
        raise ValueError(
            "the predicted covariance is not positive semi-definite (check ukf_alpha, beta, kappa)"
        )
    return chi_x_bar, chi_z, (wm, wc), mu_bar, Sigma_bar, dx


def _ukf(mu, Sigma, u, z, c, m, dt, alpha, sigmas, params):
    """Table 7.4 on validated input; returns μ_t, Σ_t and log p(z_t)."""
    k = z.shape[0]
    chi_x_bar, chi_z, (wm, wc), mu_bar, Sigma_bar, dx = _ukf_predict(
        mu, Sigma, u, dt, alpha, sigmas, k, params
    )  # lines 2-9
    if k == 0:
        mu_t, Sigma_t = _finish(mu_bar, Sigma_bar)
        return mu_t, Sigma_t, 0.0
    Z_bar = _landmark_measurement_core(chi_x_bar[:, None, :], m[c][None, :, :2])  # line 10
    Z_bar += chi_z.reshape(-1, k, 2)  # (2n+1, k, 2)
    z_hat = wm.dot(Z_bar.reshape(-1, 2 * k)).reshape(k, 2)  # line 11
    z_hat[:, 1] = _circular_mean(wm, Z_bar[:, :, 1])
    # The residuals of the sigma points (lines 12, 13) and the innovation (line 15), the
    # bearings wrapped together.
    residuals = _innovation(np.concatenate([Z_bar, z[None, :, :2]]), z_hat)
    dz, nu = residuals[:-1].reshape(-1, 2 * k), residuals[-1].reshape(2 * k)
    S = (wc[:, None] * dz).T.dot(dz)  # line 12
    S = 0.5 * (S + S.T)
    Sigma_xz = (wc[:, None] * dx).T.dot(dz)  # line 13
    S_inv, L = _inverse(S)
    K = Sigma_xz.dot(S_inv)  # line 14
    mu_t = mu_bar + K.dot(nu)  # line 15
    Sigma_t = Sigma_bar - K.dot(S).dot(K.T)  # line 16
    log_p = _log_normal_one(nu, L)  # line 17
    mu_t, Sigma_t = _finish(mu_t, Sigma_t)
    return mu_t, Sigma_t, log_p


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
    r"""Table 7.4, lines 1–18: return :math:`\mu_t, \Sigma_t, p(z_t)` of one UKF step.

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
        On bad input (``ukf_alpha``, ``beta``, ``kappa`` as in :func:`ukf_weights`), a
        non-positive-definite ``Sigma``, predicted covariance or ``S`` (a very small
        ``ukf_alpha`` makes :math:`w_0^{(c)}` so negative that the predicted covariance
        can lose definiteness), or an estimate that overflows float64.
    """
    args = _filter_arguments(mu, Sigma, u, z, m, dt, alpha, sigmas, (2, 3))
    mu, Sigma, u, z, m, dt, alpha, sigmas = args
    c = check.landmark_indices(c, "c", z.shape[0], m.shape[0])
    log = check.flag(log, "log")
    params = _ukf_params(ukf_alpha, beta, kappa)
    _weights_cached(5 + 2 * z.shape[0], *params)
    mu_t, Sigma_t, log_p = _checked(
        lambda: _ukf(mu, Sigma, u, z, c, m, dt, alpha, sigmas, params),
        "Table 7.4's step",
        lambda: dict(mu=mu, Sigma=Sigma, u=u, z=z, dt=dt, alpha=alpha, sigmas=sigmas),
    )
    return mu_t, Sigma_t, (log_p if log else math.exp(log_p))


def _ukf_ml(mu, Sigma, u, z, m, dt, alpha, sigmas, params, threshold):
    k = z.shape[0]
    if k == 0:
        mu_t, Sigma_t, _ = _ukf(mu, Sigma, u, z, np.zeros(0, int), m, dt, alpha, sigmas, params)
        return mu_t, Sigma_t, np.zeros(0, dtype=int)
    # The one-feature Table 7.4 (n = 7), lines 2-12, for every landmark at once.
    chi_x_bar, chi_z, (wm, wc), *_ = _ukf_predict(mu, Sigma, u, dt, alpha, sigmas, 1, params)
    Z_bar = _landmark_measurement_core(chi_x_bar[:, None, :], m[None, :, :2])  # (15, L, 2)
    Z_bar += chi_z[:, None, :]
    z_hat = np.einsum("i,ild->ld", wm, Z_bar)
    z_hat[:, 1] = _circular_mean(wm, Z_bar[:, :, 1])
    dz = _innovation(Z_bar, z_hat)
    S = np.einsum("i,ila,ilb->lab", wc, dz, dz)  # (L, 2, 2)
    L = _cholesky(S)
    j = np.full(k, -1, dtype=int)
    for i in range(k):
        d2, log_p = _log_normal(_innovation(z[i, :2], z_hat), L)
        best = int(np.argmax(log_p))
        if threshold is None or d2[best] <= threshold:
            j[i] = best
    keep = j >= 0
    mu_t, Sigma_t, _ = _ukf(mu, Sigma, u, z[keep], j[keep], m, dt, alpha, sigmas, params)
    return mu_t, Sigma_t, j


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
    r"""Table 7.4 with the association of Table 7.3: :math:`\mu_t, \Sigma_t` and each feature's landmark.

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
    args = _filter_arguments(mu, Sigma, u, z, m, dt, alpha, sigmas, (2, 3))
    mu, Sigma, u, z, m, dt, alpha, sigmas = args
    params = _ukf_params(ukf_alpha, beta, kappa)
    threshold = _gate_threshold(gate, 2)
    return _checked(
        lambda: _ukf_ml(mu, Sigma, u, z, m, dt, alpha, sigmas, params, threshold),
        "Table 7.4's step",
        lambda: dict(mu=mu, Sigma=Sigma, u=u, z=z, dt=dt, alpha=alpha, sigmas=sigmas),
    )


# --------------------------------------------------------------------------- runs


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


_STEP_FIELDS = ("t", "dt", "u", "z", "c")


def _step_number(value, name: str) -> float:
    """A step's ``t`` or ``dt``: one real number (finiteness is checked for all steps at once)."""
    if type(value) is float or type(value) is np.float64:  # the common case, fast
        return value
    arr = check.as_float_array(value, name)
    if arr.ndim != 0:
        raise ValueError(f"{name} must be one number, got shape {arr.shape}")
    return float(arr)


def _step_control(value, name: str):
    """A step's ``u``: (v, ω), two real numbers."""
    if type(value) is np.ndarray and value.dtype == np.float64 and value.shape == (2,):
        return value
    arr = check.as_float_array(value, name)
    if arr.shape != (2,):
        raise ValueError(f"{name} must be (v, omega), shape (2,), got shape {arr.shape}")
    return arr


def _read_steps(steps, m, signatures, known):
    """The steps' times, lengths, controls, features and correspondences, checked."""
    if (
        isinstance(steps, str | bytes | dict)
        or not hasattr(steps, "__len__")
        or not hasattr(steps, "__iter__")
    ):
        raise ValueError(f"steps must be a sequence of steps, got {check._short(steps)}")
    T = len(steps)
    if T == 0:
        raise ValueError("steps is empty: a run needs at least one step")
    t, dts, us = np.empty(T), np.empty(T), np.empty((T, 2))
    zs, cs = [], []
    no_z = np.zeros((0, 3 if signatures else 2))
    no_c = np.zeros(0, dtype=int)
    for i, step in enumerate(steps):
        try:
            t_i, dt_i, u_i, z_i = step.t, step.dt, step.u, step.z
        except AttributeError:
            missing = [f for f in _STEP_FIELDS if not hasattr(step, f)]
            raise ValueError(
                f"steps[{i}] must have the attributes t, dt, u, z and c (e.g. a "
                f"probrob.simulation.Step), got {type(step).__name__} without "
                f"{', '.join(missing)}"
            ) from None
        t[i] = _step_number(t_i, f"steps[{i}].t")
        dts[i] = _step_number(dt_i, f"steps[{i}].dt")
        us[i] = _step_control(u_i, f"steps[{i}].u")
        try:
            n_features = len(z_i)
        except TypeError:
            raise ValueError(
                f"steps[{i}].z must be the step's features, shape (k, 3) (k = 0: none), got "
                f"{check._short(z_i)}"
            ) from None
        if n_features == 0:  # most steps of a real run: nothing to check
            zs.append(no_z)
            cs.append(no_c)
            continue
        z = check.features(z_i, f"steps[{i}].z")
        zs.append(z if signatures else z[:, :2])
        if known and not hasattr(step, "c"):
            raise ValueError(f"steps[{i}] has features but no attribute c (their landmarks)")
        cs.append(
            check.landmark_indices(step.c, f"steps[{i}].c", z.shape[0], m.shape[0])
            if known
            else None
        )
    for name, values in (("t", t), ("u", us), ("dt", dts)):
        bad = np.flatnonzero(~np.all(np.isfinite(values.reshape(T, -1)), axis=1))
        if bad.size:
            i = int(bad[0])
            raise ValueError(f"steps[{i}].{name} must be finite, got {values[i]!r}")
    if np.any(dts <= 0):
        i = int(np.flatnonzero(dts <= 0)[0])
        raise ValueError(f"steps[{i}].dt must be > 0, got {dts[i]!r}")
    return t, dts, us, zs, cs


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
    r"""Tables 7.2–7.4 along a run: return the :class:`FilterRun` of one filter over ``steps``.

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

    Returns
    -------
    FilterRun

    Raises
    ------
    ValueError
        On bad input (a step's ``u`` or ``dt`` named by its index), or an estimate that
        overflows float64 (naming the step's most extreme value).
    """
    check.choice(method, "method", _METHODS)
    mu = check.single_pose(mu0, "mu0")
    Sigma = Sigma0 = check.covariance(Sigma0, "Sigma0")
    signatures = check.flag(signatures, "signatures")
    m = check.landmark_map(m, "m")
    alpha = check.alphas(alpha, "alpha", 4)
    sigmas = check.sigmas(sigmas, "sigmas", (3,) if method[0] == "e" else (2, 3), positive=True)
    if gate is not None and method not in ("ekf_ml", "ukf_ml"):
        raise ValueError("gate applies to method='ekf_ml' or 'ukf_ml' only")
    threshold = _gate_threshold(gate, 3 if signatures and method == "ekf_ml" else 2)
    params = _ukf_params(ukf_alpha, beta, kappa)
    t, dts, us, zs, cs_given = _read_steps(steps, m, signatures, method in ("ekf", "ukf"))

    T = len(t)
    mus, Sigmas = np.empty((T, 3)), np.empty((T, 3, 3))
    cs = [None] * T
    log_pz = np.full(T, np.nan)
    dt_list = dts.tolist()  # Python floats: the models' scalar path
    i = 0
    # One np.errstate for the whole run (the cores report overflow as _NonFinite).
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        while i < T:
            if method[0] == "e" and zs[i].shape[0] == 0:
                # A stretch without features: the exact vectorised composition of predictions.
                j = i
                while j < T and zs[j].shape[0] == 0:
                    j += 1
                try:
                    seg_mu, seg_Sigma = _predict_segment(mu, Sigma, us[i:j], dts[i:j], alpha)
                except _NonFinite as exc:
                    raise _step_error(
                        exc, slice(i, j), us, dts, Sigma0=Sigma0, alpha=alpha
                    ) from None
                seg_mu[:, 2] = _wrap(seg_mu[:, 2])
                mus[i:j], Sigmas[i:j] = seg_mu, seg_Sigma
                cs[i:j] = [np.zeros(0, dtype=int) for _ in range(i, j)]
                log_pz[i:j] = 0.0 if method == "ekf" else np.nan
                mu, Sigma = seg_mu[-1], seg_Sigma[-1]
                i = j
                continue
            args = (mu, Sigma, us[i], zs[i])
            try:
                if method == "ekf":
                    mu, Sigma, out = _ekf_known(*args, cs_given[i], m, dt_list[i], alpha, sigmas)
                elif method == "ekf_ml":
                    mu, Sigma, out = _ekf_ml(*args, m, dt_list[i], alpha, sigmas, threshold)
                elif method == "ukf":
                    mu, Sigma, out = _ukf(*args, cs_given[i], m, dt_list[i], alpha, sigmas, params)
                else:
                    mu, Sigma, out = _ukf_ml(
                        *args, m, dt_list[i], alpha, sigmas, params, threshold
                    )
            except _NonFinite as exc:
                raise _step_error(
                    exc, i, us, dts, Sigma0=Sigma0, alpha=alpha, sigmas=sigmas
                ) from None
            if method in ("ekf", "ukf"):
                log_pz[i], cs[i] = out, cs_given[i]
            else:
                cs[i] = out
            mus[i], Sigmas[i] = mu, Sigma
            i += 1
    return FilterRun(t=t, mu=mus, Sigma=Sigmas, c=cs, log_pz=log_pz)


def _step_error(exc, index, us, dts, **arguments) -> ValueError:
    """The overflow of one step (or stretch) of :func:`run_filter`, blamed on its own values.

    ``index`` is the step's index or the stretch's slice; ``arguments`` the other arguments
    of :func:`run_filter` the step was computed from.
    """
    label = index if isinstance(index, int) else f"{index.start}:{index.stop}"
    named = {f"steps[{label}].u": us[index], f"steps[{label}].dt": dts[index], **arguments}
    return check.overflow_error(f"step {label} ({exc})", **named)
