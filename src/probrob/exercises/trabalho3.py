r"""Checks for the exercises of the Trabalho 3 chapter (velocity and odometry motion models).

Holds the checks of the Trabalho 3 chapter's exercises.
Does not hold the answers or the models (each check computes the truth with :mod:`probrob.motion`).

Each ``exercise_N(answer)`` computes the truth with :mod:`probrob` (the densities and
samplers of Tables 5.1–5.6) and returns ``None`` when the answer is right, or a short
message saying what is wrong (never the right value). The chapter's check cells call them
through :func:`probrob.exercises.check`::

    check("Exercise 1", w, test=trabalho3.exercise_1)

The exercises' settings are the chapter's: :data:`START`, :data:`U_VEL`, :data:`ALPHA_VEL`,
:data:`DELTAS`, :data:`ODOM_START` and :func:`u_odom`.
"""

from __future__ import annotations

import numpy as np

from probrob.angles import wrap_angle
from probrob.distributions import prob_triangular_distribution
from probrob.motion import (
    apply_odometry_deltas,
    odometry_deltas,
    sample_motion_model_odometry,
    sample_motion_model_velocity,
    velocity_motion,
)

from . import more_digits, not_a_number, one_number

__all__ = [
    "exercise_1",
    "exercise_2",
    "exercise_3",
    "exercise_4",
    "exercise_5",
    "exercise_6",
    "exercise_7",
    "u_odom",
]

START = np.array([0.0, 0.0, 0.0])
"""The robot's start pose :math:`x_{t-1}`: the origin, facing :math:`+x`."""
U_VEL = np.array([1.0, 0.8])
"""The velocity command :math:`(v, \\omega)` = (1 m/s, 0.8 rad/s), for :math:`\\Delta t` = 1 s."""
ALPHA_VEL = np.array([0.02, 0.02, 0.02, 0.02, 0.01, 0.01])
"""The velocity model's moderate noise :math:`\\alpha_1 \\ldots \\alpha_6`."""
DELTAS = (0.6, 1.0, -0.4)
"""The odometry's :math:`(\\delta_{rot1}, \\delta_{trans}, \\delta_{rot2})`: rad, m, rad."""
ODOM_START = np.array([2.0, 1.0, 1.2])
"""The odometry's own start pose :math:`\\bar x_{t-1}` (its frame differs from the robot's)."""

EX1_B2 = 0.3
"""Exercise 1: the variance of the triangular density."""
EX6_ALPHA_VAR = (0.04, 0.01, 0.0, 0.0, 0.0, 0.0)
"""Exercise 6: the variance-form :math:`\\alpha`."""
EX7_ODOMETRY = ((0.0, 0.0, 3.1), (-1.0, -0.1, 2.9))
"""Exercise 7: two odometry poses, the heading just below :math:`\\pi` and the step just past
the :math:`\\pm\\pi` cut."""


def u_odom():
    """The odometry control :math:`(\\bar x_{t-1}, \\bar x_t)` of the chapter, shape (2, 3)."""
    return np.stack([ODOM_START, apply_odometry_deltas(ODOM_START, *DELTAS)])


def exercise_1(w):
    """The half-width ``w`` of the triangle's support for :math:`b^2` = :data:`EX1_B2`:
    the density is zero beyond it, positive inside, and holds mass 1 on [−w, w]."""
    w, problem = one_number(w)
    if problem:
        return problem
    if w <= 0:
        return "a half-width is positive"
    inside, outside = prob_triangular_distribution(np.array([0.999, 1.001]) * w, EX1_B2)
    if outside > 0 or inside == 0:
        # the check resolves w to 0.1 %: a half-width short of digits is told so
        short = more_digits(w, np.sqrt(6 * EX1_B2), rtol=5e-4)
        if short:
            return short
    if outside > 0:
        return "the density is still positive just beyond w: the support is wider"
    if inside == 0:
        return "the density is already zero just inside w: the support is narrower"
    a = np.linspace(-w, w, 100_001)
    mass = np.trapezoid(prob_triangular_distribution(a, EX1_B2), a)
    return None if abs(mass - 1) < 1e-6 else f"the mass over [-w, w] is {mass:.6f}, not 1"


def exercise_2(n):
    """How many uniforms on (−b, b), summed and halved, have variance :math:`b^2`. Checked
    on 200 000 such sums with :math:`b = 1`."""
    n, problem = one_number(n)
    if problem:
        return problem
    if int(n) != n or n < 1:
        return "n must be a positive whole number"
    draws = 0.5 * np.random.default_rng(0).uniform(-1.0, 1.0, (200_000, int(n))).sum(axis=1)
    var = draws.var()  # b = 1; the standard error of var is 0.003
    return None if abs(var - 1) < 0.02 else f"with {int(n)} uniforms the variance is {var:.3f} b²"


def exercise_3(wrap):
    """A function ``wrap(angles)`` for numpy arrays that maps every angle to the same
    direction in :math:`[-\\pi, \\pi)` (compared with :func:`probrob.angles.wrap_angle`)."""
    if not callable(wrap):
        return f"expected a function, got {type(wrap).__name__}"
    angles = np.array([0.0, 3.0, 3.2, -3.2, np.pi, -np.pi, 7.0, -20.0, 100.0])
    got = np.asarray(wrap(angles.copy()), dtype=float)
    if got.shape != angles.shape:
        return "wrap must return one angle for each angle it is given"
    truth = wrap_angle(angles)
    bad = np.flatnonzero(~np.isclose(got, truth, rtol=0, atol=1e-9))
    if bad.size:
        k = bad[0]
        same_direction = np.isclose(np.cos(got[k] - angles[k]), 1.0, rtol=0, atol=1e-12)
        why = "is outside [-π, π)" if same_direction else "is not the same direction"
        return f"wrap({angles[k]:g}) = {got[k]:.4f} {why}"
    return None


def _share_within_10cm(alpha, n=20_000, rng=0):
    poses = sample_motion_model_odometry(
        u_odom(), START, alpha * np.array([1.0, 0.1, 1.0, 0.1]), size=n, rng=rng
    )
    end = apply_odometry_deltas(START, *DELTAS)
    return np.mean(np.hypot(*(poses[:, :2] - end[:2]).T) <= 0.1)


def exercise_4(alpha):
    """The :math:`\\alpha` of :math:`(\\alpha, \\alpha/10, \\alpha, \\alpha/10)` for which 95 %
    (±1 %) of 20 000 samples of Table 5.6 lie within 10 cm of the noise-free end position."""
    alpha, problem = one_number(alpha)
    if problem:
        return problem
    if alpha < 0:
        return "α is a variance factor: it must be ≥ 0"
    share = _share_within_10cm(alpha)
    if share > 0.96:
        return f"{share:.1%} of the samples lie within 10 cm: α can be larger"
    if share < 0.94:
        return f"only {share:.1%} of the samples lie within 10 cm: α must be smaller"
    return None


def _share_in_disc():
    end = velocity_motion(START, U_VEL, 1.0)
    poses = sample_motion_model_velocity(U_VEL, START, 1.0, ALPHA_VEL, size=200_000, rng=21)
    return np.mean(np.hypot(*(poses[:, :2] - end[:2]).T) <= 0.2)


def exercise_5(mass):
    """The probability that the velocity model's density (``density="xy"``) holds in the
    disc of radius 20 cm around the noise-free end position; compared (±0.01) with the share
    of 200 000 samples of Table 5.3 in the disc."""
    mass, problem = one_number(mass)
    if problem:
        return problem
    if not 0 <= mass <= 1:
        return "a probability lies in [0, 1]"
    if abs(mass - _share_in_disc()) > 0.01:
        return "more than 0.01 away from the share of samples in the disc"
    return None


def exercise_6(alpha1):
    """The :math:`\\alpha_1` of ``noise="std"`` (all other :math:`\\alpha` zero) that draws
    exactly the samples of ``noise="variance"`` with :data:`EX6_ALPHA_VAR` (same seed)."""
    alpha1, problem = one_number(alpha1)
    if problem:
        return problem
    if alpha1 < 0:
        return "α1 scales a standard deviation: it must be ≥ 0"
    kw = {"size": 2000, "rng": 4}
    ref = sample_motion_model_velocity(U_VEL, START, 1.0, EX6_ALPHA_VAR, **kw)
    std = sample_motion_model_velocity(
        U_VEL, START, 1.0, [alpha1, 0, 0, 0, 0, 0], noise="std", **kw
    )
    if np.allclose(ref, std, rtol=0, atol=1e-9):
        return None
    v, w = U_VEL  # the samples agree to 1e-9 m when α1 does to about 1e-9 of itself
    short = more_digits(
        alpha1, np.sqrt(EX6_ALPHA_VAR[0] * v**2 + EX6_ALPHA_VAR[1] * w**2) / v, rtol=1e-9
    )
    if short:
        return short
    end = velocity_motion(START, U_VEL, 1.0)
    spread_ref, spread_std = (np.abs(s - end).mean() for s in (ref, std))
    return f"the std form's cloud is {'wider' if spread_std > spread_ref else 'narrower'}"


def exercise_7(deltas):
    """The odometry's :math:`(\\delta_{rot1}, \\delta_{trans}, \\delta_{rot2})` between the
    two poses :data:`EX7_ODOMETRY` (Table 5.5, lines 2–4, wrapped: erratum O1)."""
    problem = not_a_number(deltas)
    if problem:
        return f"{problem}; expected three numbers (δrot1, δtrans, δrot2)"
    try:
        value = np.asarray(deltas, dtype=float)
    except (TypeError, ValueError):
        return "expected three numbers (δrot1, δtrans, δrot2)"
    if value.shape != (3,):
        return f"expected three numbers (δrot1, δtrans, δrot2), got shape {value.shape}"
    truth = np.array(odometry_deltas(*(np.array(p) for p in EX7_ODOMETRY)), dtype=float)
    in_range = np.array([wrap_angle(value[0]), value[1], wrap_angle(value[2])])
    short = more_digits(in_range, truth, rtol=0.0, atol=1e-9)
    if short:
        return short
    wrong = [
        name
        for name, ok in [
            ("δrot1", np.isclose(wrap_angle(value[0]), truth[0], atol=1e-9)),
            ("δtrans", np.isclose(value[1], truth[1], atol=1e-9)),
            ("δrot2", np.isclose(wrap_angle(value[2]), truth[2], atol=1e-9)),
        ]
        if not ok
    ]
    if wrong:
        return f"{' and '.join(wrong)} {'is' if len(wrong) == 1 else 'are'} not right"
    unwrapped = [n for n, k in [("δrot1", 0), ("δrot2", 2)] if not -np.pi <= value[k] < np.pi]
    if unwrapped:
        return f"{' and '.join(unwrapped)}: the right direction, but not wrapped to [-π, π)"
    return None
