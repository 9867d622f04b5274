"""The Turkish chapter's exercise checks say "correct" to the right answer and "not yet" to
typical wrong ones (zero, the wrong sign, the slides' formula, degrees, variance for σ, ...)."""

import numpy as np
import pytest

from probrob.exercises import turkish as ch
from probrob.exercises import verdict
from probrob.kinematics import arc_update, diff_drive_odometry
from probrob.motion import motion_model_velocity, velocity_motion

START = np.zeros(3)


def _ok(test, answer):
    return verdict("Ex", answer, test=test) == "Ex: correct"


def _right_turn_controls():
    # from the geometry: the end (a, b) ahead/left; signed r, Δθ = 2 arctan(b/a)
    a, b = ch.END_4[:2]
    dth = 2 * np.arctan(b / a)
    r = (a**2 + b**2) / (2 * b)
    return np.array([dth * r, dth, (ch.END_4[2] - dth + np.pi) % (2 * np.pi) - np.pi])


def _arc_deltas():
    ds, dth, _ = diff_drive_odometry(0.8, 1.2, 0.5)
    return np.array([dth / 2, ds * np.sinc(dth / 2 / np.pi), dth / 2])


RIGHT = {
    ch.exercise_1: 2.5,  # R = ΔS/Δθ = 1/0.4
    ch.exercise_2: np.arctan(0.5),
    ch.exercise_3: 0.0,  # the Δθ telescope: no heading error at all
    ch.exercise_4: _right_turn_controls(),
    ch.exercise_5: (0.2, 0.1),
    ch.exercise_6: _arc_deltas(),
}

WRONG = {
    ch.exercise_1: [0.0, -2.5, 0.4, 0.25, 1.0],  # zero, wrong side, ΔS·Δθ, d/2, ΔS
    ch.exercise_2: [0.0, np.arctan(2.0), np.degrees(np.arctan(0.5)), -np.arctan(0.5), 0.5],
    ch.exercise_3: [0.3, 1e-3, 1.2 * (1 - np.cos(10.0))],  # a position error, a guess, θ itself
    ch.exercise_4: [
        (0.0, 0.0, 0.0),
        _right_turn_controls() * [-1, 1, 1],  # the slides' unsigned r: v̂ = −1.30 m/s
        _right_turn_controls() * [1, -1, 1],  # ω̂ of a left turn
        (_right_turn_controls()[0], 2 * np.pi + _right_turn_controls()[1], 0.0),  # unwrapped
        (*_right_turn_controls()[:2], -1.22),  # γ̂ without subtracting ω̂Δt
    ],
    ch.exercise_5: [(0.04, 0.01), (0.0, 0.0), (0.2, 0.2), (0.0016, 0.0001), (0.2, 0.01)],
    ch.exercise_6: [
        (0.0, 0.0, 0.0),
        (0.4, 1.0, 0.4),  # the arc length for the chord
        (0.0, 1.0, 0.8),  # the whole turn at the end
        (0.8, _arc_deltas()[1], 0.0),  # the whole turn first
        (-0.4, _arc_deltas()[1], -0.4),  # wrong sign
    ],
}


@pytest.mark.parametrize("test", list(RIGHT), ids=lambda f: f.__name__)
def test_the_right_answer_is_correct(test):
    assert _ok(test, RIGHT[test])


@pytest.mark.parametrize(
    ("test", "answer"),
    [(t, a) for t, answers in WRONG.items() for a in answers],
    ids=lambda x: getattr(x, "__name__", None),
)
def test_typical_wrong_answers_are_not_yet(test, answer):
    out = verdict("Ex", answer, test=test)
    assert out.startswith("Ex: not yet — "), out


@pytest.mark.parametrize("test", list(RIGHT), ids=lambda f: f.__name__)
def test_missing_or_malformed_answers_are_not_yet(test):
    for answer in (None, "one", (1.0, 2.0, 3.0, 4.0), float("nan")):
        assert verdict("Ex", answer, test=test).startswith("Ex: not yet")


def test_the_right_turn_answer_reaches_the_end_pose_and_is_the_density_mode():
    """The answer of exercise 4 is not only the library's number: driving it reaches END_4."""
    v, w, g = RIGHT[ch.exercise_4]
    assert v == pytest.approx(1.30, abs=0.005) and w < 0
    end = velocity_motion(START, (v, w), 1.0)
    np.testing.assert_allclose(end[:2], ch.END_4[:2], atol=1e-12)
    assert end[2] + g == pytest.approx(ch.END_4[2], abs=1e-12)
    alpha = np.full(6, 0.1)
    at = motion_model_velocity(ch.END_4, (v, w), START, 1.0, alpha)
    flipped = motion_model_velocity(ch.END_4, (-v, w), START, 1.0, alpha)
    assert flipped < 1e-4 * at  # the slides' v̂ is far off the command


def test_the_arc_deltas_are_the_librarys():
    ds, dth, _ = diff_drive_odometry(0.8, 1.2, 0.5)
    from probrob.motion import odometry_deltas

    np.testing.assert_allclose(
        odometry_deltas(START, arc_update(START, ds, dth)), _arc_deltas(), atol=1e-15
    )
