"""The CIR chapter's exercise checks say "correct" to the right answer and "not yet" to the
typical wrong ones (``probrob.exercises.cir``)."""

import re

import numpy as np
import pytest

from probrob.exercises import cir, verdict
from probrob.kinematics import (
    cir_pose_matrix,
    cir_radius_angle,
    cir_state_function,
    cir_state_jacobians,
)


def _spellings(value):
    """The ways the right answer could be printed in a message: each of its non-zero numbers,
    without its sign, to 1-6 decimals, in %g, %.2e and repr."""
    out = set()
    for x in np.ravel(np.array(value, dtype=object)):
        for y in np.ravel(np.asarray(x, dtype=float)):
            if np.isfinite(y) and abs(y) > 1e-9:
                z = abs(float(y))
                out |= {f"{z:.{d}f}" for d in range(1, 7)} | {f"{z:g}", f"{z:.2e}", repr(z)}
    return {s for s in out if s.strip("0.")}  # "0.00" is not a spelling of 0.0016


def _numbers_in(message):
    """The numbers a message prints, without their signs (a "−" or "-" before them)."""
    return set(re.findall(r"(?<![\w.])\d+(?:\.\d+)?(?:e[-+]?\d+)?", message))


def _leaks(right, message, given=()):
    """The spellings of the right answer that the message prints, other than those of the
    numbers the reader gave or the exercise states (``given``), which a message may repeat.
    A right value of zero counts as printed when the message prints any zero."""
    numbers = _numbers_in(message) - _spellings(given)
    zero_is_right = _has_zero(right) and not _has_zero(given)
    return sorted(
        t for t in numbers if t in _spellings(right) or (zero_is_right and float(t) == 0)
    )


def _has_zero(value):
    values = [np.asarray(x, dtype=float) for x in np.ravel(np.array(value, dtype=object))]
    return any(np.any(np.abs(v) <= 1e-9) for v in values)


L = cir.WHEELS
FLIP = cir.FLIP


def _right_2():
    return FLIP * cir_state_function(FLIP * np.array(cir.EX2_BOOK_POSE), cir.EX2_U, L)


def _var_3():
    _, W = cir_state_jacobians(np.zeros(3), cir.EX3_U, L)
    return float((W @ np.diag(cir.EX3_K * np.abs(cir.EX3_U)) @ W.T)[2, 2])


def _cir_world(pose, u, rho_from_right_wheel=False):
    r, _ = cir_radius_angle(u, L)
    offset = -r if rho_from_right_wheel else -(r + L / 2)
    return (cir_pose_matrix(np.array(pose)) @ [0.0, offset, 1.0])[:2]


RIGHT = {
    "exercise_1": (-cir.EX1_S_SX, (0.0, 0.0)),
    "exercise_2": _right_2(),
    "exercise_3": 2 * cir.EX3_K / L**2,
    "exercise_4": _cir_world(cir.EX4_POSE, cir.EX4_U),
}

# The registry that tests/test_exercises.py reads: every check, its typical wrong answers.
WRONG_ANSWERS = {
    "exercise_1": [
        None,
        (0.0, (0.0, 0.0)),  # zero: a pivot on the right wheel, the robot moves
        (cir.EX1_S_SX, (0.0, 0.0)),  # the wrong sign: a straight drive
        (-cir.EX1_S_SX, (0.0, -L / 2)),  # right s_dx, CIR put at the right wheel
        (-cir.EX1_S_SX, (0.0, L / 2)),  # right s_dx, CIR put at the left wheel
        (-cir.EX1_S_SX, (0.0, np.inf)),  # "at infinity"
        -cir.EX1_S_SX,  # only the first part
        (cir.EX1_S_SX - 2 * np.pi * L, (0.0, 0.0)),  # a whole loop (α = 2π), back in place
        (
            cir.EX1_S_SX - 2 * np.pi * L,
            (0.0, -cir_radius_angle([0.2, 0.2 - 0.8 * np.pi], L)[0] - L / 2),
        ),
    ],
    "exercise_2": [
        np.zeros(3),
        FLIP * _right_2(),  # left in the report's convention
        cir_state_function(cir.EX2_BOOK_POSE, cir.EX2_U, L),  # no map M (erratum C1)
        FLIP * cir_state_function(FLIP * np.array(cir.EX2_BOOK_POSE), cir.EX2_U[::-1], L),
        _right_2()[:2],  # the position only
    ],
    "exercise_3": [
        0.0,  # "a straight drive does not turn"
        np.sqrt(2 * cir.EX3_K) / L,  # the standard deviation
        cir.EX3_K / L**2,  # one wheel's error only
        2 * cir.EX3_K / L,  # l not squared
        2 * cir.EX3_K / L**2 * (180 / np.pi) ** 2,  # deg²
        -2 * cir.EX3_K / L**2,
    ],
    "exercise_4": [
        np.zeros(2),
        np.array(cir.EX4_POSE[:2]),  # the robot's position
        _cir_world(FLIP * np.array(cir.EX4_POSE), cir.EX4_U),  # the usual R(θ): erratum C1
        _cir_world(cir.EX4_POSE, cir.EX4_U, rho_from_right_wheel=True),  # r from the middle
        2 * np.array(cir.EX4_POSE[:2]) - _cir_world(cir.EX4_POSE, cir.EX4_U),  # the left side
    ],
}


def test_the_registry_covers_every_check():
    assert set(WRONG_ANSWERS) == set(RIGHT) == {n for n in cir.__all__ if n.startswith("exercise")}
    assert all(len(wrong) >= 3 for wrong in WRONG_ANSWERS.values())


@pytest.mark.parametrize("name", sorted(RIGHT))
def test_right_answer_is_correct(name):
    assert verdict(name, RIGHT[name], test=getattr(cir, name)) == f"{name}: correct"


@pytest.mark.parametrize(
    ("name", "k"), [(n, k) for n, wrong in WRONG_ANSWERS.items() for k in range(len(wrong))]
)
def test_wrong_answer_is_not_yet(name, k):
    message = verdict(name, WRONG_ANSWERS[name][k], test=getattr(cir, name))
    assert message.startswith(f"{name}: not yet — "), message


def test_messages_do_not_give_the_answer_away():
    for name, wrong in WRONG_ANSWERS.items():
        truth = np.ravel(np.asarray(RIGHT[name], dtype=object))
        for answer in wrong:
            message = verdict(name, answer, test=getattr(cir, name))
            for value in truth:
                value = np.ravel(value).astype(float)
                for v in value[value != 0]:
                    assert f"{v:.3f}" not in message, (name, message)


def test_the_spin_s_dx_is_checked_before_the_cir():
    message = verdict("e", (0.0, (0.0, 0.0)), test=cir.exercise_1)
    assert "still moves" in message
    message = verdict("e", (-cir.EX1_S_SX, (0.0, -L / 2)), test=cir.exercise_1)
    assert "s_dx is right" in message and "CIR" in message


def test_the_erratum_answers_name_erratum_c1():
    assert "C1" in verdict("e", WRONG_ANSWERS["exercise_2"][2], test=cir.exercise_2)
    assert "C1" in verdict("e", WRONG_ANSWERS["exercise_4"][2], test=cir.exercise_4)


@pytest.mark.parametrize("name", sorted(RIGHT))
def test_no_message_prints_the_right_answer_in_any_spelling(name):
    """Like the test above, for every way a number could be printed (1-6 decimals, %g, %e,
    repr, without its sign)."""
    for answer in [*WRONG_ANSWERS[name], "one"]:
        message = verdict(name, answer, test=getattr(cir, name))
        assert not _leaks(RIGHT[name], message), (name, message)


def test_a_whole_loop_is_not_a_spin_issue_23_item_19():
    """s_dx = 0.2 - 0.8π turns the robot by α = 2π about a CIR off the axle: it ends where it
    started but drove a circle; with the CIR the check itself computes, it printed correct."""
    s_dx = cir.EX1_S_SX - 2 * np.pi * L
    r, alpha = cir_radius_angle([cir.EX1_S_SX, s_dx], L)
    assert alpha == pytest.approx(2 * np.pi) and abs(r + L / 2) > 0.1
    for cx_cy in [(0.0, 0.0), (0.0, -(r + L / 2))]:
        message = verdict("e", (s_dx, cx_cy), test=cir.exercise_1)
        assert message.startswith("e: not yet") and "loop" in message, message
    assert verdict("e", RIGHT["exercise_1"], test=cir.exercise_1) == "e: correct"


def test_a_right_value_short_of_digits_is_told_so():
    for name, answer in [
        ("exercise_2", np.round(RIGHT["exercise_2"], 3)),
        ("exercise_4", np.round(RIGHT["exercise_4"], 4)),
    ]:
        message = verdict(name, answer, test=getattr(cir, name))
        assert "give more digits" in message, message
