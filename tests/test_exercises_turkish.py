"""The Turkish chapter's exercise checks say "correct" to the right answer and "not yet" to
typical wrong ones (zero, the wrong sign, the slides' formula, degrees, variance for σ, ...)."""

import re

import numpy as np
import pytest

from probrob.exercises import turkish as ch
from probrob.exercises import verdict
from probrob.kinematics import arc_update, diff_drive_odometry
from probrob.motion import motion_model_velocity, velocity_motion


def _spellings(value):
    """The ways the right answer could be printed in a message: each of its non-zero numbers,
    without its sign, to 1-6 decimals, in %g, %.2e and repr."""
    out = set()
    for x in np.ravel(np.array(value, dtype=object)):
        if isinstance(x, str):  # a word of the answer ("signed") is not a number
            continue
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
    values = [
        np.asarray(x, dtype=float)
        for x in np.ravel(np.array(value, dtype=object))
        if not isinstance(x, str)
    ]
    return any(np.any(np.abs(v) <= 1e-9) for v in values)


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


def _euler_errors(dt=2.0):
    """(position error, heading error) of Euler odometry after 20 s, against the truth that
    the chapter integrates (solve_ivp, DOP853), not the check's quadrature."""
    from scipy.integrate import solve_ivp

    from probrob.kinematics import dead_reckon

    def v(t):
        return 0.5 + 0.2 * np.sin(0.7 * t)

    def heading(t):
        return 1.2 * (1 - np.cos(0.5 * t))

    truth = solve_ivp(
        lambda t, p: [v(t) * np.cos(heading(t)), v(t) * np.sin(heading(t))],
        (0.0, 20.0),
        [0.0, 0.0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-12,
    ).y[:, -1]
    t = np.linspace(0.0, 20.0, round(20.0 / dt) + 1)
    left, right = ch.simulated_wheel_readings(t)
    ds, dth, _ = diff_drive_odometry(np.diff(left), np.diff(right), 0.5)
    end = dead_reckon(START, ds, dth, method="euler")[-1]
    return (float(np.hypot(*(end[:2] - truth))), float(end[2] - heading(20.0)))


EULER_2S = _euler_errors()
SIGNED = _right_turn_controls()
SLIDES = SIGNED * [-1, 1, 1]  # the slides' unsigned r: v̂ = −1.30 m/s

RIGHT = {
    "exercise_1": 2.5,  # R = ΔS/Δθ = 1/0.4
    "exercise_2": np.arctan(0.5),
    "exercise_3": EULER_2S,  # the heading error is 0: the Δθ telescope
    "exercise_4": (tuple(SIGNED), tuple(SLIDES), "signed"),
    "exercise_5": (0.2, 0.1),
    "exercise_6": _arc_deltas(),
}

# The registry that tests/test_exercises.py reads: every check, its typical wrong answers.
WRONG_ANSWERS = {
    "exercise_1": [0.0, -2.5, 0.4, 0.25, 1.0],  # zero, wrong side, ΔS·Δθ, d/2, ΔS
    "exercise_2": [0.0, np.arctan(2.0), np.degrees(np.arctan(0.5)), -np.arctan(0.5), 0.5],
    "exercise_3": [
        0.0,  # the guess (and the old question's answer): one number
        (0.0, 0.0),
        (EULER_2S[0], 1.2 * (1 - np.cos(10.0))),  # θ itself for its error
        (_euler_errors(1.0)[0], 0.0),  # Δt = 1 s, the table's
        (-EULER_2S[0], 0.0),
        (0.2 * np.pi, 0.0),  # 0.628318..., 5.8e-5 away from the position error
        EULER_2S[::-1],
    ],
    "exercise_4": [
        (0.0, 0.0, 0.0),
        tuple(SIGNED),  # the first set only (the old question's answer)
        (tuple(SLIDES), tuple(SIGNED), "signed"),  # the sets swapped
        (tuple(SIGNED), tuple(SLIDES), "unsigned"),  # the wrong one drives there
        (tuple(SIGNED), tuple(SIGNED), "signed"),  # the second set with the signed r
        (tuple(SIGNED * [1, -1, 1]), tuple(SLIDES), "signed"),  # ω̂ of a left turn
        ((SIGNED[0], 2 * np.pi + SIGNED[1], 0.0), tuple(SLIDES), "signed"),  # unwrapped
        ((*SIGNED[:2], -1.22), tuple(SLIDES), "signed"),  # γ̂ without subtracting ω̂Δt
        (tuple(SIGNED), (SLIDES[0], SLIDES[1], -1.22), "signed"),  # the slides' γ̂ changed
        [list(SIGNED), list(SLIDES), "signed "],  # a word with a space
    ],
    "exercise_5": [(0.04, 0.01), (0.0, 0.0), (0.2, 0.2), (0.0016, 0.0001), (0.2, 0.01)],
    "exercise_6": [
        (0.0, 0.0, 0.0),
        (0.4, 1.0, 0.4),  # the arc length for the chord
        (0.0, 1.0, 0.8),  # the whole turn at the end
        (0.8, _arc_deltas()[1], 0.0),  # the whole turn first
        (-0.4, _arc_deltas()[1], -0.4),  # wrong sign
    ],
}


def test_the_registry_covers_every_check():
    names = {n for n in ch.__all__ if n.startswith("exercise_")}
    assert set(WRONG_ANSWERS) == set(RIGHT) == names
    assert all(len(wrong) >= 3 for wrong in WRONG_ANSWERS.values())


@pytest.mark.parametrize("name", sorted(RIGHT))
def test_the_right_answer_is_correct(name):
    assert _ok(getattr(ch, name), RIGHT[name])


@pytest.mark.parametrize(
    ("name", "k"), [(n, k) for n, wrong in WRONG_ANSWERS.items() for k in range(len(wrong))]
)
def test_typical_wrong_answers_are_not_yet(name, k):
    out = verdict("Ex", WRONG_ANSWERS[name][k], test=getattr(ch, name))
    assert out.startswith("Ex: not yet — "), out


@pytest.mark.parametrize("name", sorted(RIGHT))
def test_missing_or_malformed_answers_are_not_yet(name):
    for answer in (None, "one", (1.0, 2.0, 3.0, 4.0), float("nan")):
        assert verdict("Ex", answer, test=getattr(ch, name)).startswith("Ex: not yet")


@pytest.mark.parametrize("name", sorted(RIGHT))
def test_no_message_gives_the_answer_away(name):
    """A "not yet" message may say what is wrong (a sign, a unit, a factor), never the right
    value, in any of the ways it could be printed."""
    for answer in [*WRONG_ANSWERS[name], None, "one"]:
        message = verdict("Ex", answer, test=getattr(ch, name))
        assert not _leaks(RIGHT[name], message), (name, message)


def test_the_right_turn_answer_reaches_the_end_pose_and_is_the_density_mode():
    """The answer of exercise 4 is not only the library's number: driving it reaches END_4."""
    v, w, g = RIGHT["exercise_4"][0]
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


def test_exercise_3_cannot_be_guessed_and_the_heading_part_is_zero():
    """Issue 23, item 19: a bare 0 was the whole answer (|answer| <= 1e-9 passed). The answer
    is now the pair (position error, heading error) at Δt = 2 s, which no guess hits; its
    heading part is still the chapter's point (zero: the Δθ telescope)."""
    assert EULER_2S[1] == 0.0 and EULER_2S[0] > 0.5
    for guess in (0, 0.0, (0, 0), [0.0, 0.0]):
        assert verdict("Ex", guess, test=ch.exercise_3).startswith("Ex: not yet")
    assert _ok(ch.exercise_3, list(EULER_2S))
    assert _ok(ch.exercise_3, (round(EULER_2S[0], 7), 1e-16))
    short = verdict("Ex", (round(EULER_2S[0], 3), 0.0), test=ch.exercise_3)
    assert "give more digits" in short, short


def test_exercise_4_checks_the_slides_controls_and_the_choice():
    """Issue 23, item 19: the second part of exercise 4 (the slides' unsigned r) is checked."""
    assert _ok(ch.exercise_4, [list(SIGNED), list(SLIDES), "signed"])
    messages = {
        "second set": (tuple(SIGNED), tuple(SIGNED), "signed"),
        "velocity_motion": (tuple(SIGNED), tuple(SLIDES), "unsigned"),
        "both sets": tuple(SIGNED),
    }
    for expected, answer in messages.items():
        line = verdict("Ex", answer, test=ch.exercise_4)
        assert line.startswith("Ex: not yet") and expected in line, line
