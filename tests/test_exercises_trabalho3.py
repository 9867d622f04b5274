"""The Trabalho 3 chapter's exercise checks say "correct" to the right answer and "not yet"
to the typical wrong ones (``probrob.exercises.trabalho3``)."""

import re

import numpy as np
import pytest

from probrob.exercises import trabalho3 as t3
from probrob.exercises import verdict
from probrob.motion import motion_model_velocity, odometry_deltas, velocity_motion


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


def _mass_20cm(step=0.001):
    end = velocity_motion(t3.START, t3.U_VEL, 1.0)
    offsets = np.arange(-0.2, 0.2, step) + step / 2
    gx, gy = np.meshgrid(end[0] + offsets, end[1] + offsets)
    disc = np.hypot(gx - end[0], gy - end[1]) <= 0.2
    p = motion_model_velocity(
        np.stack([gx, gy], -1), t3.U_VEL, t3.START, 1.0, t3.ALPHA_VEL, density="xy"
    )
    return float(p[disc].sum() * step**2), float(p.max())


def _alpha_95():
    lo, hi = 1e-6, 1.0
    for _ in range(40):
        mid = np.sqrt(lo * hi)
        lo, hi = (mid, hi) if t3._share_within_10cm(mid) > 0.95 else (lo, mid)
    return float(np.sqrt(lo * hi))


ALPHA_95 = _alpha_95()
MASS_20CM, PEAK_DENSITY = _mass_20cm()
V, W_CMD = t3.U_VEL
ALPHA1_STD = float(np.sqrt(0.04 * V**2 + 0.01 * W_CMD**2) / abs(V))
DELTAS_7 = np.array(odometry_deltas(*(np.array(p) for p in t3.EX7_ODOMETRY)))
(XB, YB, THB), (XB2, YB2, THB2) = t3.EX7_ODOMETRY
DECK_ROT1_7 = np.arctan2(YB2 - YB, XB2 - XB) - THB  # the deck's line 2, unwrapped
DECK_7 = np.array([DECK_ROT1_7, DELTAS_7[1], THB2 - THB - DECK_ROT1_7])

RIGHT = {
    "exercise_1": np.sqrt(6 * t3.EX1_B2),
    "exercise_2": 12,
    "exercise_3": lambda a: (np.asarray(a, float) + np.pi) % (2 * np.pi) - np.pi,
    "exercise_4": ALPHA_95,
    "exercise_5": MASS_20CM,
    "exercise_6": ALPHA1_STD,
    "exercise_7": DELTAS_7,
}

# The registry that tests/test_exercises.py reads: every check, its typical wrong answers.
WRONG_ANSWERS = {
    "exercise_1": [
        0.0,
        np.sqrt(t3.EX1_B2),  # b: the normal's σ, not the triangle's half-width
        np.sqrt(6) * t3.EX1_B2,  # the variance b² read as b
        -np.sqrt(6 * t3.EX1_B2),  # the wrong sign
        6 * t3.EX1_B2,
        np.sqrt(3 * t3.EX1_B2),  # a uniform's half-width for variance b²
    ],
    "exercise_2": [0, 1, 6, 24, 12.5, 3],
    "exercise_3": [
        lambda a: a,  # the deck: no wrapping
        lambda a: np.mod(a, 2 * np.pi),  # [0, 2π)
        lambda a: np.arctan2(np.sin(a), np.cos(a)),  # (-π, π]: π stays π
        lambda a: np.fmod(a, np.pi),  # a remainder by π
        lambda a: (np.asarray(a) + np.pi) % np.pi - np.pi,
        lambda a: 0.0,  # not one angle per angle
    ],
    "exercise_4": [
        0.0,  # no noise: all samples within 10 cm
        10 * ALPHA_95,
        ALPHA_95 / 10,
        np.sqrt(ALPHA_95),  # a standard deviation given for the variance factor
        -ALPHA_95,
    ],
    "exercise_5": [
        0.0,
        1.0,
        0.95,
        PEAK_DENSITY,  # the density itself, not a probability
        MASS_20CM + 0.05,
        _mass_20cm(step=0.001)[0] * np.pi * 0.2**2,  # times the disc's area again
    ],
    "exercise_6": [
        0.04,  # the variance-form α1 as is
        0.2,  # √α1: drops the α2 ω² term
        ALPHA1_STD**2,
        -ALPHA1_STD,
        0.0,
        np.sqrt(0.04) + np.sqrt(0.01) * W_CMD,  # √α1|v| + √α2|ω|: the forms do not add so
    ],
    "exercise_7": [
        np.zeros(3),
        DECK_7,  # the deck: nothing wrapped (erratum O1)
        np.array([np.arctan(DELTAS_7[0]), DELTAS_7[1], DELTAS_7[2]]),
        np.degrees(DELTAS_7),  # degrees for radians
        DELTAS_7[[2, 1, 0]],  # the rotations swapped
        -DELTAS_7,
        DELTAS_7[:2],
    ],
}


def test_the_registry_covers_every_check():
    names = {n for n in t3.__all__ if n.startswith("exercise")}
    assert set(WRONG_ANSWERS) == set(RIGHT) == names
    assert all(len(wrong) >= 3 for wrong in WRONG_ANSWERS.values())


@pytest.mark.parametrize("name", sorted(RIGHT))
def test_right_answer_is_correct(name):
    assert verdict(name, RIGHT[name], test=getattr(t3, name)) == f"{name}: correct"


@pytest.mark.parametrize(
    ("name", "k"), [(n, k) for n, wrong in WRONG_ANSWERS.items() for k in range(len(wrong))]
)
def test_wrong_answer_is_not_yet(name, k):
    message = verdict(name, WRONG_ANSWERS[name][k], test=getattr(t3, name))
    assert message.startswith(f"{name}: not yet — "), message


def test_the_deck_answers_of_the_errata_exercises_are_named():
    assert "not wrapped" in verdict("e", DECK_7, test=t3.exercise_7)
    assert "variance is 0.083" in verdict("e", 1, test=t3.exercise_2)  # 1/12 of b²
    assert "outside [-π, π)" in verdict("e", WRONG_ANSWERS["exercise_3"][2], test=t3.exercise_3)
    assert "not the same direction" in verdict(
        "e", WRONG_ANSWERS["exercise_3"][3], test=t3.exercise_3
    )


def test_the_answers_of_the_chapter_stay_what_its_solutions_print():
    assert f"{ALPHA_95:.5f}" == "0.00215"
    assert f"{MASS_20CM:.4f}" == "0.6727"
    assert f"{ALPHA1_STD:.5f}" == "0.21541"


# Exercise 3's answer is a function: its right values are those of the angles its check uses.
ANGLES_3 = np.array([0.0, 3.0, 3.2, -3.2, np.pi, -np.pi, 7.0, -20.0, 100.0])


@pytest.mark.parametrize("name", sorted(RIGHT))
def test_no_message_gives_the_answer_away(name):
    """A "not yet" message may say what is wrong (a sign, a unit, a factor), never the right
    value, in any of the ways it could be printed (1-6 decimals, %g, %e, repr, no sign)."""
    right = RIGHT[name](ANGLES_3) if callable(RIGHT[name]) else RIGHT[name]
    for answer in [*WRONG_ANSWERS[name], "one"]:
        message = verdict(name, answer, test=getattr(t3, name))
        given = _numeric(answer(ANGLES_3) if callable(answer) else answer)
        assert not _leaks(right, message, given=[*given, *ANGLES_3]), (name, message)


def _numeric(answer):
    """The numbers of a (wrong) answer, which its message may repeat back to the reader."""
    try:
        return list(np.ravel(np.asarray(answer, dtype=float)))
    except (TypeError, ValueError):
        return []


@pytest.mark.parametrize(
    ("name", "answer"),
    [("exercise_1", 1.34), ("exercise_6", 0.2154), ("exercise_7", np.round(DELTAS_7, 4))],
)
def test_a_right_value_short_of_digits_is_told_so(name, answer):
    """Issue 23, item 11: the truth rounded short of the check's tolerance is told to give
    more digits (it was "the support is wider", "the std form's cloud is wider", "... is not
    right"), and a rounding to the digits the message asks for passes."""
    line = verdict(name, answer, test=getattr(t3, name))
    assert "close, but give more digits" in line, line
    n = int(line.rsplit("needs ", 1)[1].split()[0])
    right = np.asarray(RIGHT[name], dtype=float)
    rounded = np.vectorize(lambda x: float(f"{x:.{n - 1}e}"))(right)
    assert verdict(
        name, rounded if rounded.ndim else float(rounded), test=getattr(t3, name)
    ).endswith("correct")
