r"""Checks for the exercises of the CIR chapter (the Italian report on the CIR state function).

Holds the checks of the CIR chapter's exercises.
Does not hold the answers or the models (each check computes the truth with :mod:`probrob.kinematics`).

Each ``exercise_N(answer)`` computes the truth with :mod:`probrob.kinematics` and returns
``None`` when the answer is right, or a short message saying what is wrong (never the right
value). The chapter's check cells call them through :func:`probrob.exercises.check`::

    check("Exercise 1", answer, test=cir.exercise_1)

The report's convention is used throughout: poses :math:`(x, y, \theta)` with the heading
measured clockwise (its eq. 2, erratum C1), controls :math:`(s_{sx}, s_{dx})`, the wheels
:data:`WHEELS` apart.
"""

from __future__ import annotations

import numpy as np

from probrob.kinematics import (
    arc_update,
    cir_pose_matrix,
    cir_radius_angle,
    cir_state_function,
    cir_state_jacobians,
    diff_drive_odometry,
)

from . import agrees, more_digits, not_a_number, one_number

__all__ = ["exercise_1", "exercise_2", "exercise_3", "exercise_4"]

WHEELS = 0.4
"""The distance :math:`l` between the wheels in every exercise, m."""
FLIP = np.array([1.0, 1.0, -1.0])
"""The map :math:`M` between the report's and the book's poses: the heading changes sign."""

EX1_S_SX = 0.2
"""Exercise 1: the left wheel's arc, m."""
EX2_BOOK_POSE = (1.0, 2.0, 0.5)
"""Exercise 2: the start pose in the book's convention (heading counter-clockwise)."""
EX2_U = (0.3, 0.5)
"""Exercise 2: the wheel arcs :math:`(s_{sx}, s_{dx})`, m."""
EX3_K = 2e-4
"""Exercise 3: the wheel-noise variance per metre of travel, m."""
EX3_U = (1.0, 1.0)
"""Exercise 3: the straight step's wheel arcs, m."""
EX4_POSE = (1.0, 0.5, 0.6)
"""Exercise 4: the robot's pose in the report's convention."""
EX4_U = (0.6, 0.3)
"""Exercise 4: the wheel arcs, m."""


def _vector(answer, n, what):
    problem = not_a_number(answer)
    if problem:
        return None, f"{what}: {problem}"
    value = np.asarray(answer, dtype=float)
    if value.shape != (n,):
        return None, f"{what}: expected {n} numbers, got shape {value.shape}"
    return value, None


def _cir_in_robot_frame(u):
    """The CIR of one step in the robot's frame (x ahead, y to the left), eq. 6."""
    r, _ = cir_radius_angle(u, WHEELS)
    return np.array([0.0, -(r + WHEELS / 2)])


def exercise_1(answer):
    """A spin in place: ``answer = (s_dx, (cx, cy))``.

    ``s_dx`` turns the robot on the spot when the left wheel travels :data:`EX1_S_SX`;
    ``(cx, cy)`` is where the CIR is then, in the robot's frame (x ahead, y to the left), m.
    """
    try:
        s_dx, cir = answer
    except (TypeError, ValueError):
        return "give a pair: (s_dx, (cx, cy))"
    s_dx, problem = one_number(s_dx)
    if problem:
        return f"s_dx: {problem}"
    start = np.array([1.0, 2.0, 0.5])
    end = cir_state_function(start, [EX1_S_SX, s_dx], WHEELS)
    if np.hypot(*(end[:2] - start[:2])) > 1e-12:
        return "with this s_dx the robot's position still moves: a spin leaves it in place"
    if abs(end[2] - start[2]) < 1e-12:
        return "with this s_dx the robot does not turn at all"
    r, _ = cir_radius_angle([EX1_S_SX, s_dx], WHEELS)
    if not abs(r + WHEELS / 2) <= 1e-9:
        return (
            "with this s_dx the robot is back where it started only after a whole loop "
            "(α a multiple of 2π) around a point off the axle: a spin turns it on the spot, "
            "its position never moving"
        )
    cir, problem = _vector(cir, 2, "the CIR")
    if problem:
        return problem
    truth = _cir_in_robot_frame([EX1_S_SX, s_dx])
    if not np.allclose(cir, truth, rtol=0, atol=1e-9):
        return "s_dx is right; the CIR is not where you put it"
    return None


def exercise_2(answer):
    """From the book's pose to the report's and back: the book's pose after the step.

    ``answer`` is :math:`(x', y', \\varphi')` in the book's convention, reached from
    :data:`EX2_BOOK_POSE` with the wheel arcs :data:`EX2_U`.
    """
    value, problem = _vector(answer, 3, "the pose")
    if problem:
        return problem
    ds, dphi, _ = diff_drive_odometry(*EX2_U, WHEELS)
    truth = arc_update(np.array(EX2_BOOK_POSE), ds, dphi)
    tol = {"rtol": 0.0, "atol": 1e-9}
    if np.allclose(value, truth, **tol):
        return None
    if agrees(value, truth * FLIP, **tol):
        return "this is the book's pose in the report's convention: flip the heading back"
    if agrees(value, cir_state_function(EX2_BOOK_POSE, EX2_U, WHEELS), **tol):
        return "the report's f was fed the book's pose as it is: map it with M first (erratum C1)"
    short = more_digits(value, truth, **tol)
    if short:
        return short
    if agrees(value[:2], truth[:2], **tol):
        return "the position is right, the heading is not"
    if agrees(value[2], truth[2], **tol):
        return "the heading is right, the position is not"
    return "neither the position nor the heading is the one the book's model reaches"


def exercise_3(answer):
    """The variance of the heading after one straight step, rad², with the wheel noise
    :math:`Q = \\mathrm{diag}(k|s_{sx}|, k|s_{dx}|)`, :math:`k` = :data:`EX3_K`, from a
    perfectly known pose."""
    value, problem = one_number(answer)
    if problem:
        return problem
    _, W = cir_state_jacobians(np.zeros(3), EX3_U, WHEELS)
    Q = np.diag(EX3_K * np.abs(EX3_U))
    truth = float((W @ Q @ W.T)[2, 2])
    if np.isclose(value, truth, rtol=1e-6, atol=0):
        return None
    if agrees(value, np.sqrt(truth)):
        return "that is a standard deviation: the question asks for the variance"
    if agrees(value, truth / 2):
        return "both wheels' errors turn the robot, not only one"
    if agrees(value, truth * (180 / np.pi) ** 2):
        return "give the variance in rad², not deg²"
    return more_digits(value, truth, rtol=1e-6) or ("too large" if value > truth else "too small")


def exercise_4(answer):
    """The CIR of the step :data:`EX4_U` from the report's pose :data:`EX4_POSE`, in
    world coordinates :math:`(x, y)`, m."""
    value, problem = _vector(answer, 2, "the CIR")
    if problem:
        return problem
    frame = cir_pose_matrix(np.array(EX4_POSE))
    truth = (frame @ [*_cir_in_robot_frame(EX4_U), 1.0])[:2]
    tol = {"rtol": 0.0, "atol": 1e-9}
    if np.allclose(value, truth, **tol):
        return None
    book_frame = cir_pose_matrix(np.array(EX4_POSE) * FLIP)  # the usual R(θ): erratum C1
    if agrees(value, (book_frame @ [*_cir_in_robot_frame(EX4_U), 1.0])[:2], **tol):
        return "the report's rotation matrix is the transpose of the usual one (erratum C1)"
    r, _ = cir_radius_angle(EX4_U, WHEELS)
    if agrees(value, (frame @ [0.0, -r, 1.0])[:2], **tol):
        return "r is measured from the right wheel, not from the middle of the axle"
    return (
        more_digits(value, truth, **tol) or "this point is not the centre that both wheels circle"
    )
