r"""Checks of the exercises of the chapter "Trabalho 5 — EKF and UKF localization".

Holds the checks of the Trabalho 5 chapter's exercises.
Does not hold the answers or the filters (each check computes the truth with :mod:`probrob.localization`).

Each ``exercise_N(answer)`` computes the truth with the library and returns ``None`` when
``answer`` is right, else a short message of what is wrong (never the right value); the
chapter passes it to :func:`probrob.exercises.check` as ``test``.

Does not hold: the chapter's experiments, nor any model (they are in
:mod:`probrob.localization`, :mod:`probrob.motion` and :mod:`probrob.sensors`).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.stats import norm

from probrob.angles import wrap_angle
from probrob.evaluation import chi2_quantile
from probrob.localization import ekf_localization_known_correspondences, ukf_weights
from probrob.motion import velocity_motion_jacobians
from probrob.sensors import landmark_measurement, landmark_measurement_jacobian

__all__ = ["exercise_1", "exercise_2", "exercise_3", "exercise_4", "exercise_5"]

# The chapter's measurement noise (σ_r [m], σ_φ [rad], σ_s), used by exercises 2 and 3.
SIGMAS = np.array([0.1, 0.02, 0.1])


def _numbers(answer, n: int, what: str):
    """``answer`` as a float array of ``n`` entries, or the message saying why not."""
    try:
        a = np.asarray(answer, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        return None, f"expected {what}, got {type(answer).__name__}"
    if a.size != n:
        return None, f"expected {what} ({n} number{'s' if n > 1 else ''}), got {a.size}"
    if not np.all(np.isfinite(a)):
        return None, "the answer contains NaN or infinity"
    return a, None


def _close(a: float, b: float, rtol: float = 1e-4, atol: float = 1e-9) -> bool:
    return math.isclose(a, b, rel_tol=rtol, abs_tol=atol)


def exercise_1(answer):
    """Upper end of the two-sided 95 % band of the 50-run mean NEES of a 3-D pose."""
    a, problem = _numbers(answer, 1, "a number")
    if problem:
        return problem
    a, n = float(a[0]), 50
    if _close(a, chi2_quantile(0.975, 3 * n) / n):
        return None
    if _close(a, chi2_quantile(0.975, 3 * n)):
        return "that is the band of N·(mean NEES): divide by N"
    if _close(a, chi2_quantile(0.975, n) / n) or _close(a, chi2_quantile(0.975, 3) / n):
        return "N·(mean NEES) is χ² with 3N degrees of freedom"
    if _close(a, chi2_quantile(0.95, 3 * n) / n):
        return "a two-sided 95 % band leaves 2.5 % above it"
    return "the band of N·(mean NEES) is χ² with 3N degrees of freedom"


def _exercise_2_truth():
    x = np.zeros(3)
    landmark = np.array([[-5.0, 0.1, 0.0]])
    z = np.array([[math.hypot(-5.0, 0.1), -math.pi + 0.01, 0.0]])
    Sigma = 0.01 * np.eye(3)
    mu, _, _ = ekf_localization_known_correspondences(
        x, Sigma, [0.0, 0.0], z, [0], landmark, 1.0, np.zeros(4), SIGMAS
    )
    wrapped = float(wrap_angle(mu[2] - x[2]))
    H = landmark_measurement_jacobian(x, landmark[0])
    K = Sigma @ H.T @ np.linalg.inv(H @ Sigma @ H.T + np.diag(SIGMAS**2))
    unwrapped = float((K @ (z[0] - landmark_measurement(x, landmark[0])))[2])
    return wrapped, unwrapped


def exercise_2(answer):
    """(heading change of the library's EKF step, the one of the deck's unwrapped innovation)."""
    a, problem = _numbers(answer, 2, "a pair (wrapped, unwrapped)")
    if problem:
        return problem
    wrapped, unwrapped = _exercise_2_truth()
    wrong = []
    if not _close(a[0], wrapped, rtol=1e-3):
        if _close(a[0], -wrapped, rtol=1e-3):
            wrong.append("(a) has the wrong sign: which way does a bearing error turn the robot?")
        elif _close(a[0], unwrapped, rtol=1e-3):
            wrong.append("(a) is the unwrapped update: wrap the innovation first")
        else:
            wrong.append("(a) is not the EKF's change of heading")
    if not _close(a[1], unwrapped, rtol=1e-3):
        if _close(a[1], wrapped, rtol=1e-3):
            wrong.append("(b) uses the wrapped innovation; the deck's is the raw z - ẑ")
        else:
            wrong.append("(b) is not K (z - ẑ) with the raw bearing difference")
    return "; ".join(wrong) or None


def _exercise_3_dm():
    pose = np.zeros(3)
    pair = np.array([[4.0, -0.15], [4.0, 0.15]])
    Sigma = np.diag([0.05**2, 0.05**2, 0.02**2])
    H = landmark_measurement_jacobian(pose, pair[0])
    S = H @ Sigma @ H.T + np.diag(SIGMAS[:2] ** 2)
    dz = landmark_measurement(pose, pair[1]) - landmark_measurement(pose, pair[0])
    dz[1] = wrap_angle(dz[1])
    return math.sqrt(float(dz @ np.linalg.solve(S, dz)))


def exercise_3(answer):
    """Probability that ML association picks the right one of two landmarks: Φ(d_M / 2)."""
    a, problem = _numbers(answer, 1, "a probability")
    if problem:
        return problem
    p = float(a[0])
    if not 0.0 <= p <= 1.0:
        return "a probability lies in [0, 1]"
    d_m = _exercise_3_dm()
    if _close(p, norm.cdf(d_m / 2), rtol=1e-3):
        return None
    if _close(p, norm.cdf(-d_m / 2), rtol=1e-3):
        return "that is the probability of the wrong choice"
    if _close(p, norm.cdf(d_m), rtol=1e-3):
        return "the decision line lies half way between the two predictions"
    return "not Φ(d_M / 2) with d_M from S = H Σ Hᵀ + Q of the first landmark"


def exercise_4(answer):
    """(L, γ, w0(m), w0(c), wi) of the UKF with two features, α = 0.5, β = 2, κ = 0."""
    a, problem = _numbers(answer, 5, "(L, gamma, w0m, w0c, wi)")
    if problem:
        return problem
    n = 3 + 2 + 2 * 2
    if not _close(a[0], n):
        return "L counts the pose, the control noise and every feature's measurement noise"
    gamma, wm, wc = ukf_weights(n, ukf_alpha=0.5, beta=2.0, kappa=0.0)
    wrong = []
    if not _close(a[1], gamma):
        wrong.append("γ = √(L + λ)" if _close(a[1], gamma**2) else "γ is not √(L + λ)")
    if not _close(a[2], wm[0]):
        wrong.append("w0(m) = λ / (L + λ)")
    if not _close(a[3], wc[0]):
        wrong.append("w0(c) adds 1 - α² + β to w0(m)")
    if not _close(a[4], wm[1]):
        wrong.append("wi = 1 / (2 (L + λ))")
    return "; ".join(wrong) or None


def _exercise_5_truth():
    th, v, w, dt = 0.5, 1.0, 0.1, 0.1
    _, V = velocity_motion_jacobians(np.array([0.0, 0.0, th]), np.array([v, w]), dt)
    deck = -(math.sin(th) + math.sin(th + w * dt)) / w  # deck 004, line 4, as printed
    return float(V[0, 0]), deck


def exercise_5(answer):
    """(V11 = ∂x'/∂v, the deck's printed V11) at θ = 0.5, u = (1, 0.1), Δt = 0.1."""
    a, problem = _numbers(answer, 2, "a pair (right, deck)")
    if problem:
        return problem
    right, deck = _exercise_5_truth()
    wrong = []
    if not _close(a[0], right):
        if _close(a[0], deck):
            wrong.append("the first value is the deck's")
        elif _close(a[0], 0.1 * math.cos(0.5), rtol=1e-6):
            wrong.append("Δt cos θ is the straight-line value; the robot turns")
        else:
            wrong.append("the first value is not ∂x'/∂v")
    if not _close(a[1], deck):
        wrong.append("the second value is not the deck's -(sin θ + sin(θ + ωΔt))/ω")
    return "; ".join(wrong) or None
