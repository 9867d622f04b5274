r"""Checks for the exercises of the Turkish lecture's chapter (motion models, wheel kinematics).

Holds the checks of the Turkish lecture chapter's exercises.
Does not hold the answers or the models (each check computes the truth with the library).

Each ``exercise_N(answer)`` computes the truth with the library and returns ``None`` when the
answer is right, otherwise a short message saying what is wrong (never the right value). Use
them through :func:`probrob.exercises.check`:
``check("Exercise 4", answer, test=exercise_4)``.

The exercises: (1) the signed turning radius of a differential drive; (2) the steering angle
of a tricycle for a radius; (3) the position and heading errors of Euler-step odometry at
:math:`\Delta t` = 2 s; (4) the controls :math:`(\hat v, \hat\omega, \hat\gamma)` of Table 5.1
for a right turn, with the signed and with the slides' unsigned :math:`r`, and which of them
drives there (erratum V1); (5) the
noise standard deviations of Table 5.3's variance form (erratum D2); (6) the odometry
controls :math:`(\delta_{rot1}, \delta_{trans}, \delta_{rot2})` of one wheel-odometry arc
step (Table 5.5, lines 2–4).
"""

from __future__ import annotations

import numpy as np

from ..angles import wrap_angle
from ..kinematics import arc_update, dead_reckon, diff_drive_odometry, tricycle_odometry
from ..motion import _invert_velocity, _velocity_controls, odometry_deltas
from . import agrees, more_digits, not_a_number

__all__ = [
    "ALPHA_5",
    "END_4",
    "exercise_1",
    "exercise_2",
    "exercise_3",
    "exercise_4",
    "exercise_5",
    "exercise_6",
    "simulated_wheel_readings",
]

START = np.array([0.0, 0.0, 0.0])
#: Exercise 4: the hypothesised end pose (x', y', θ') of a right turn, from START in Δt = 1 s.
END_4 = np.array([1.0, -0.7, -1.22])
#: Exercise 5: α of the variance form, and the command u = (v, ω).
ALPHA_5 = np.array([0.04, 0.0, 0.04, 0.0, 0.01, 0.0])
U_5 = np.array([1.0, 0.8])


def _numbers(answer, n: int):
    """The answer as ``n`` finite floats, or a message."""
    wanted = "one number" if n == 1 else f"{n} numbers"
    problem = not_a_number(answer)
    if problem:
        return f"{problem}; give {wanted}"
    try:
        values = np.asarray(answer, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        return f"give {wanted}"
    if values.size != n:
        return f"give {wanted}, got {values.size}"
    return values


def _number(answer):
    values = _numbers(answer, 1)
    return values if isinstance(values, str) else float(values[0])


def exercise_1(answer):
    """Signed distance R [m] from the axle's middle to the centre of rotation (left > 0)
    of a differential drive with d = 0.5 m reading ΔS_L = 0.9 m, ΔS_R = 1.1 m."""
    r = _number(answer)
    if isinstance(r, str):
        return r
    truth = diff_drive_odometry(0.9, 1.1, 0.5)[2]
    if not np.isclose(abs(r), abs(truth), rtol=1e-4):
        return (
            more_digits(abs(r), abs(truth), rtol=1e-4) or "the distance is not right: R = ΔS / Δθ"
        )
    if np.sign(r) != np.sign(truth):
        return "right distance, wrong side (R > 0 is the robot's left)"
    return None


def exercise_2(answer):
    """Steering angle α [rad] of a tricycle with d = 1 m turning about a point 2 m to the
    left of the middle of its rear axle."""
    steer = _number(answer)
    if isinstance(steer, str):
        return steer
    if abs(steer) >= np.pi / 2:
        return "a steering angle lies within ±π/2 rad: degrees instead of radians?"
    ds, dth = tricycle_odometry(1.0, steer, 1.0)
    if dth == 0:
        return "that drives straight"
    radius = ds / dth
    if not np.isclose(radius, 2.0, rtol=1e-4):
        # R = d / tan α: R to 1e-4 is α to 1e-4 · sin α cos α / α, 8.6e-5 of it; 5e-5 is within
        short = more_digits(steer, np.arctan(1.0 / 2.0), rtol=5e-5)
        return short or f"that steers about a point {radius:.3f} m to the left (negative: right)"
    return None


def simulated_wheel_readings(t, wheelbase=0.5):
    """Cumulative wheel travel (left, right) [m] of the chapter's simulated robot at times t:
    v(t) = 0.5 + 0.2 sin(0.7 t) m/s, ω(t) = 0.6 sin(0.5 t) rad/s, integrated in closed form."""
    t = np.asarray(t, dtype=float)
    distance = 0.5 * t + (0.2 / 0.7) * (1 - np.cos(0.7 * t))
    heading = 1.2 * (1 - np.cos(0.5 * t))
    return distance - heading * wheelbase / 2, distance + heading * wheelbase / 2


def _true_end_position():
    """Where the chapter's simulated robot really is at t = 20 s: the integrals of
    v(t) (cos Θ(t), sin Θ(t)) by 200-point Gauss-Legendre quadrature (exact to rounding for
    these smooth integrands; the chapter's ``solve_ivp`` agrees to 1e-12 m)."""
    nodes, weights = np.polynomial.legendre.leggauss(200)
    t = 10.0 * (nodes + 1.0)
    v = 0.5 + 0.2 * np.sin(0.7 * t)
    heading = 1.2 * (1 - np.cos(0.5 * t))
    return 10.0 * np.array([weights @ (v * np.cos(heading)), weights @ (v * np.sin(heading))])


def exercise_3(answer):
    """(position error [m], heading error [rad]) of Euler-step odometry at Δt = 2 s after the
    20 s of the chapter's simulated robot: the distance of its final position from the true
    one, and its final heading minus the true 1.2 (1 − cos 10) rad."""
    values = _numbers(answer, 2)
    if isinstance(values, str):
        return f"{values}: (position error, heading error)"
    position, heading = values
    t = np.linspace(0.0, 20.0, 11)
    left, right = simulated_wheel_readings(t)
    ds, dth, _ = diff_drive_odometry(np.diff(left), np.diff(right), 0.5)
    final = dead_reckon(START, ds, dth, method="euler")[-1]
    truth_position = float(np.hypot(*(final[:2] - _true_end_position())))
    truth_heading = float(final[2] - 1.2 * (1 - np.cos(10.0)))
    problems = []
    if not np.isclose(position, truth_position, rtol=1e-6, atol=0.0):
        if position < 0:
            problems.append("a distance is not negative")
        else:
            short = more_digits(position, truth_position, rtol=1e-6)
            problems.append(
                f"the position error is {short}"
                if short
                else "the position error is not the distance of the final position from the "
                "true one (Euler steps of Δt = 2 s from the wheel readings)"
            )
    if abs(heading - truth_heading) > 1e-9:
        problems.append("the heading error is not right: what does Δθ sum to?")
    return "; ".join(problems) or None


def _slides_controls(truth):
    """The slides' (v̂, ω̂, γ̂): v̂ = ω̂ |r| with the unsigned r (erratum V1)."""
    v, w, g = truth
    return np.array([w * abs(v / w), w, g])


def exercise_4(answer):
    """``((v̂, ω̂, γ̂), (v̂, ω̂, γ̂), which)`` of Table 5.1 from START to END_4 in Δt = 1 s:
    the controls with the signed r, those with the slides' unsigned r (erratum V1), and
    ``"signed"`` or ``"unsigned"``, the one that drives there; v̂ [m/s], ω̂ [rad/s],
    γ̂ [rad/s]."""
    shape = "((v̂, ω̂, γ̂) with the signed r, (v̂, ω̂, γ̂) with the slides' r, 'signed' or 'unsigned')"
    if not isinstance(answer, tuple | list) or len(answer) != 3:
        return f"expected {shape}"
    signed, slides, which = answer
    if not_a_number(signed) is None and np.size(signed) == 1:
        return f"give both sets of controls, and which one drives there: {shape}"
    truth = np.array([float(q) for q in _invert_velocity(END_4, START, 1.0)[:3]])
    problem = _right_turn(signed, truth, "the first set")
    if problem:
        return problem
    problem = _slides_turn(slides, _slides_controls(truth))
    if problem:
        return problem
    if not isinstance(which, str) or which not in ("signed", "unsigned"):
        return (
            "the third part is the word 'signed' or 'unsigned': the r whose controls drive there"
        )
    if which != "signed":
        return "drive both sets with velocity_motion: which one reaches the end pose?"
    return None


def _right_turn(values, truth, what):
    values = _numbers(values, 3)
    if isinstance(values, str):
        return f"{what}: {values}"
    v, w, g = values
    if np.sign(v) != np.sign(truth[0]):
        return f"{what}: v̂ has the wrong sign: the robot drives forwards (the slides' unsigned r?)"
    if not np.isclose(v, truth[0], rtol=1e-3):
        return f"{what}: " + (more_digits(v, truth[0], rtol=1e-3) or "v̂ is off")
    if np.sign(w) != np.sign(truth[1]):
        return f"{what}: ω̂ has the wrong sign: the end lies to the right"
    if not np.isclose(w, truth[1], rtol=1e-3):
        short = more_digits(w, truth[1], rtol=1e-3)
        return f"{what}: " + (short or "ω̂ is off (Δθ = 2 arctan(b/a), wrapped)")
    if not np.isclose(g, truth[2], rtol=1e-2, atol=1e-4):
        short = more_digits(g, truth[2], rtol=1e-2, atol=1e-4)
        return f"{what}: " + (
            short or "γ̂ is off: the turn left over after the arc, wrap(θ' − θ − ω̂Δt)/Δt"
        )
    return None


def _slides_turn(values, truth):
    values = _numbers(values, 3)
    if isinstance(values, str):
        return f"the second set: {values}"
    v, w, g = values
    if np.sign(v) != np.sign(truth[0]):
        return "the second set: with the unsigned r, v̂ = ω̂ |r| takes the sign of ω̂"
    if not np.isclose(v, truth[0], rtol=1e-3):
        return "the second set: " + (more_digits(v, truth[0], rtol=1e-3) or "v̂ is off")
    if not (np.isclose(w, truth[1], rtol=1e-3) and np.isclose(g, truth[2], rtol=1e-2, atol=1e-4)):
        return "the second set: only r is the slides'; ω̂ and γ̂ are those of the first set"
    return None


def exercise_5(answer):
    """(σ of v̂ − v, σ of γ̂) [m/s, rad/s] of Table 5.3 in the variance form with α = ALPHA_5
    and u = (1 m/s, 0.8 rad/s)."""
    values = _numbers(answer, 2)
    if isinstance(values, str):
        return values
    _, _, var_v, _, var_g = _velocity_controls(ALPHA_5, U_5, "variance")
    truth = np.sqrt([float(var_v), float(var_g)])
    for got, want, name in zip(values, truth, ("v̂ − v", "γ̂"), strict=True):
        if np.isclose(got, want, rtol=1e-3):
            continue
        if agrees(got, want**2, rtol=1e-3):
            return f"the σ of {name} is given as the variance (the slides' sample(b), erratum D2)"
        return more_digits(got, want, rtol=1e-3) or f"the σ of {name} is off"
    return None


def exercise_6(answer):
    """(δrot1, δtrans, δrot2) [rad, m, rad] of one odometry step of a differential drive
    (d = 0.5 m) that reads ΔS_L = 0.8 m, ΔS_R = 1.2 m, from the pose (0, 0, 0)."""
    values = _numbers(answer, 3)
    if isinstance(values, str):
        return values
    ds, dth, _ = diff_drive_odometry(0.8, 1.2, 0.5)
    truth = np.array(odometry_deltas(START, arc_update(START, ds, dth)))
    rot1, trans, rot2 = values
    if not np.isclose(trans, truth[1], rtol=1e-4):
        if agrees(trans, ds, rtol=1e-4):
            return "δtrans is the chord, not the arc length ΔS"
        return more_digits(trans, truth[1], rtol=1e-4) or "δtrans is off"
    if not np.isclose(wrap_angle(rot1 - truth[0]), 0.0, atol=1e-4):
        short = more_digits(rot1, truth[0], rtol=0.0, atol=1e-4)
        return short or "δrot1 is off: the chord points halfway through the turn"
    if not np.isclose(wrap_angle(rot2 - truth[2]), 0.0, atol=1e-4):
        return more_digits(rot2, truth[2], rtol=0.0, atol=1e-4) or "δrot2 is off"
    return None
