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
from probrob.exercises.trabalho4 import agreement, more_digits
from probrob.localization import ekf_localization_known_correspondences, ukf_weights
from probrob.motion import velocity_motion_jacobians
from probrob.sensors import landmark_measurement, landmark_measurement_jacobian

__all__ = [
    "DIGITS",
    "EX2_BEARING",
    "EX2_LANDMARK",
    "exercise_1",
    "exercise_2",
    "exercise_3",
    "exercise_4",
    "exercise_5",
]

# The chapter's measurement noise (σ_r [m], σ_φ [rad], σ_s), used by exercises 2 and 3.
SIGMAS = np.array([0.1, 0.02, 0.1])
#: Exercise 2: the landmark behind the robot, and the bearing the camera reports (not the
#: numbers of erratum F4, whose answer the errata page prints).
EX2_LANDMARK = (-4.0, -0.2)
EX2_BEARING = math.pi - 0.02
#: Significant digits each exercise asks for (exercise 4's L is an integer).
DIGITS = {1: 4, 2: 3, 3: 3, 4: 4, 5: 3}


def _numbers(answer, n: int, what: str):
    """``answer`` as a float array of ``n`` entries, or the message saying why not (a string
    such as ``"3.7"`` is not a number, though numpy would read it as one)."""
    try:
        raw = np.asarray(answer)
        if raw.dtype.kind not in "iuf":  # strings, bools, objects, complex
            raise TypeError
        a = raw.astype(float).reshape(-1)
    except (TypeError, ValueError):
        return None, f"expected {what}, got {type(answer).__name__}"
    if a.size != n:
        return None, f"expected {what} ({n} number{'s' if n > 1 else ''}), got {a.size}"
    if not np.all(np.isfinite(a)):
        return None, "the answer contains NaN or infinity"
    return a, None


def _is(a: float, b: float, digits: int) -> bool:
    """``a`` is ``b`` to ``digits`` significant digits (the book's rule for answers)."""
    return agreement(a, b, digits) is None


def _verdict(wrong: list[str], parts) -> str | None:
    """The concept messages if any; else "give more digits" if a part in ``parts``
    (``[(answer, truth, digits), ...]``) is right only to fewer digits; else ``None``."""
    if wrong:
        return "; ".join(wrong)
    short = [d for a, t, d in parts if agreement(a, t, d) == "short"]
    return more_digits(max(short)) if short else None


def exercise_1(answer):
    """Upper end of the two-sided 95 % band of the 50-run mean NEES of a 3-D pose."""
    a, problem = _numbers(answer, 1, "a number")
    if problem:
        return problem
    a, n, d = float(a[0]), 50, DIGITS[1]
    truth = chi2_quantile(0.975, 3 * n) / n
    state = agreement(a, truth, d)
    if state is None:
        return None
    if state == "short":
        return more_digits(d)
    if _is(a, chi2_quantile(0.975, 3 * n), d):
        return "that is the band of N·(mean NEES): divide by N"
    if _is(a, chi2_quantile(0.975, n) / n, d) or _is(a, chi2_quantile(0.975, 3) / n, d):
        return "N·(mean NEES) is χ² with 3N degrees of freedom"
    if _is(a, chi2_quantile(0.95, 3 * n) / n, d):
        return "a two-sided 95 % band leaves 2.5 % above it"
    return "the band of N·(mean NEES) is χ² with 3N degrees of freedom"


def _exercise_2_truth():
    x = np.zeros(3)
    landmark = np.array([[*EX2_LANDMARK, 0.0]])
    z = np.array([[math.hypot(*EX2_LANDMARK), EX2_BEARING, 0.0]])
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
    d = DIGITS[2]
    wrong = []
    if agreement(a[0], wrapped, d) == "wrong":
        if _is(a[0], -wrapped, d):
            wrong.append("(a) has the wrong sign: which way does a bearing error turn the robot?")
        elif _is(a[0], unwrapped, d):
            wrong.append("(a) is the unwrapped update: wrap the innovation first")
        else:
            wrong.append("(a) is not the EKF's change of heading")
    if agreement(a[1], unwrapped, d) == "wrong":
        if _is(a[1], wrapped, d):
            wrong.append("(b) uses the wrapped innovation; the deck's is the raw z - ẑ")
        else:
            wrong.append("(b) is not K (z - ẑ) with the raw bearing difference")
    return _verdict(wrong, [(a[0], wrapped, d), (a[1], unwrapped, d)])


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
    p, d = float(a[0]), DIGITS[3]
    if not 0.0 <= p <= 1.0:
        return "a probability lies in [0, 1]"
    d_m = _exercise_3_dm()
    truth = norm.cdf(d_m / 2)
    state = agreement(p, truth, d)
    if state is None:
        return None
    if state == "short":
        return more_digits(d)
    if _is(p, norm.cdf(-d_m / 2), d):
        return "that is the probability of the wrong choice"
    if _is(p, norm.cdf(d_m), d):
        return "the decision line lies half way between the two predictions"
    return "not Φ(d_M / 2) with d_M from S = H Σ Hᵀ + Q of the first landmark"


def exercise_4(answer):
    """(L, γ, w0(m), w0(c), wi) of the UKF with two features, α = 0.5, β = 2, κ = 0."""
    a, problem = _numbers(answer, 5, "(L, gamma, w0m, w0c, wi)")
    if problem:
        return problem
    n, d = 3 + 2 + 2 * 2, DIGITS[4]
    if a[0] != n:
        return "L counts the pose, the control noise and every feature's measurement noise"
    gamma, wm, wc = ukf_weights(n, ukf_alpha=0.5, beta=2.0, kappa=0.0)
    truths = [gamma, wm[0], wc[0], wm[1]]
    wrong = []
    if agreement(a[1], gamma, d) == "wrong":
        wrong.append("γ = √(L + λ)" if _is(a[1], gamma**2, d) else "γ is not √(L + λ)")
    if agreement(a[2], wm[0], d) == "wrong":
        wrong.append("w0(m) = λ / (L + λ)")
    if agreement(a[3], wc[0], d) == "wrong":
        wrong.append("w0(c) adds 1 - α² + β to w0(m)")
    if agreement(a[4], wm[1], d) == "wrong":
        wrong.append("wi = 1 / (2 (L + λ))")
    return _verdict(wrong, [(v, t, d) for v, t in zip(a[1:], truths, strict=True)])


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
    d = DIGITS[5]
    wrong = []
    if agreement(a[0], right, d) == "wrong":
        if _is(a[0], deck, d):
            wrong.append("the first value is the deck's")
        elif _is(a[0], 0.1 * math.cos(0.5), d):
            wrong.append("Δt cos θ is the straight-line value; the robot turns")
        else:
            wrong.append("the first value is not ∂x'/∂v")
    if agreement(a[1], deck, d) == "wrong":
        wrong.append("the second value is not the deck's -(sin θ + sin(θ + ωΔt))/ω")
    return _verdict(wrong, [(a[0], right, d), (a[1], deck, d)])
