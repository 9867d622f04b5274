"""The checks of the Trabalho 5 exercises say "correct" to the right answer and "not yet" to
the typical wrong ones (each part of a multi-part answer checked), and no "not yet" message
states the right answer."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import norm

import probrob.exercises.trabalho5 as ch
from probrob.evaluation import chi2_quantile
from probrob.exercises import verdict
from probrob.localization import ukf_weights


def _ok(name, answer, test):
    return verdict(name, answer, test=test) == f"{name}: correct"


def _no(name, answer, test):
    return "not yet" in verdict(name, answer, test=test)


UPPER_50 = chi2_quantile(0.975, 150) / 50
WRAPPED, RAW = ch._exercise_2_truth()
D_M = ch._exercise_3_dm()
GAMMA, WM, WC = ukf_weights(9, ukf_alpha=0.5, beta=2.0, kappa=0.0)
G7, WM7, WC7 = ukf_weights(7, ukf_alpha=0.5, beta=2.0, kappa=0.0)
V11_RIGHT, V11_DECK = ch._exercise_5_truth()

RIGHT = {
    "exercise_1": UPPER_50,
    "exercise_2": (WRAPPED, RAW),
    "exercise_3": norm.cdf(D_M / 2),
    "exercise_4": (9, GAMMA, WM[0], WC[0], WM[1]),
    "exercise_5": (V11_RIGHT, V11_DECK),
}

# The registry that tests/test_exercises.py reads: every check, its typical wrong answers.
WRONG_ANSWERS = {
    "exercise_1": [
        0.0,
        chi2_quantile(0.975, 150),  # not divided by N
        chi2_quantile(0.975, 50) / 50,  # N degrees of freedom, not 3N
        chi2_quantile(0.975, 3),  # one run
        chi2_quantile(0.95, 150) / 50,  # one-sided 95 %
        chi2_quantile(0.025, 150) / 50,  # the lower end
        3.0,
        "3.7",
        [UPPER_50, UPPER_50],
    ],
    "exercise_2": [
        (0.0, RAW),  # zero
        (0.07, RAW),  # the measurement error itself
        (-WRAPPED, RAW),  # wrong sign
        (RAW, RAW),  # the unwrapped update for (a)
        (WRAPPED, 0.0),  # second part missing
        (WRAPPED, WRAPPED),  # (b) wrapped too
        (WRAPPED, -RAW),
        (WRAPPED, -2 * math.pi),  # the raw innovation, not the heading change
        WRAPPED,  # one number only
    ],
    "exercise_3": [
        0.5,  # a coin toss
        1.0,
        0.0,
        norm.cdf(-D_M / 2),  # the probability of the wrong choice
        norm.cdf(D_M),  # forgot the half
        1.5,  # not a probability
        norm.cdf(0.3 / 0.1 / 2),  # Euclidean spacing over σ_r
    ],
    "exercise_4": [
        (7, G7, WM7[0], WC7[0], WM7[1]),  # one feature's L
        (9, GAMMA**2, WM[0], WC[0], WM[1]),  # γ² for γ
        (9, GAMMA, WM[0], WM[0], WM[1]),  # w0(c) = w0(m)
        (9, GAMMA, WC[0], WC[0], WM[1]),  # w0(m) = w0(c)
        (9, GAMMA, WM[0], WC[0], 1 / 19),  # equal weights
        (9, GAMMA, -WM[0], WC[0], WM[1]),  # sign
        (0, 0, 0, 0, 0),
        (9, GAMMA, WM[0], WC[0]),  # a part missing
    ],
    "exercise_5": [
        (V11_DECK, V11_DECK),  # the deck's formula for the right one
        (V11_RIGHT, V11_RIGHT),  # the right one for the deck's
        (0.0, V11_DECK),
        (-V11_RIGHT, V11_DECK),  # wrong sign
        (0.1 * math.cos(0.5), V11_DECK),  # the straight-line value
        (V11_RIGHT, -V11_DECK),
        (V11_DECK, V11_RIGHT),  # swapped
        (V11_RIGHT,),
    ],
}


def test_the_registry_covers_every_check():
    names = {n for n in ch.__all__ if n.startswith("exercise")}
    assert set(WRONG_ANSWERS) == set(RIGHT) == names
    assert all(len(wrong) >= 3 for wrong in WRONG_ANSWERS.values())


@pytest.mark.parametrize("name", sorted(RIGHT))
def test_right_answer_is_correct(name):
    assert _ok(name, RIGHT[name], getattr(ch, name))


@pytest.mark.parametrize(
    ("name", "k"), [(n, k) for n, wrong in WRONG_ANSWERS.items() for k in range(len(wrong))]
)
def test_wrong_answer_is_not_yet(name, k):
    message = verdict(name, WRONG_ANSWERS[name][k], test=getattr(ch, name))
    assert message.startswith(f"{name}: not yet — "), message
    assert "give more digits" not in message, message  # a wrong answer hears the concept


def _printed(value):
    """The ways a number could appear in a message."""
    x = float(value)
    forms = {repr(x), f"{x:.6g}", f"{x:.4g}", f"{x:.3g}", f"{x:.4f}", f"{x:.3f}", f"{x:.2f}"}
    if x == round(x):
        forms.add(str(int(x)))
    return {f for f in forms if f not in ("0", "0.0", "-0", "1", "2", "3")}  # digits of prose


@pytest.mark.parametrize(
    ("name", "k"), [(n, k) for n, wrong in WRONG_ANSWERS.items() for k in range(len(wrong))]
)
def test_no_message_states_the_right_answer(name, k):
    """A "not yet" says what is wrong (a unit, a sign, a factor), never the expected value."""
    message = verdict(name, WRONG_ANSWERS[name][k], test=getattr(ch, name))
    for part in np.atleast_1d(np.asarray(RIGHT[name], dtype=float)):
        for form in _printed(part):
            assert form not in message, (form, message)


def test_the_planted_answer_would_be_caught():
    """The test above can fail: a message holding the answer (as the check once showed) is found."""
    leaky = f"{verdict('e', 0.0, test=ch.exercise_1)} (expected {UPPER_50:.4f})"
    assert any(form in leaky for form in _printed(UPPER_50))


def test_exercise_2_values_and_parts():
    wrapped, raw = ch._exercise_2_truth()
    assert wrapped == pytest.approx(0.0635, abs=1e-4)
    assert raw == pytest.approx(-5.64, abs=0.005)
    # not erratum F4's step, whose numbers (-0.028 and +5.79 rad) the errata page prints
    assert abs(wrapped + 0.028) > 0.01 and abs(raw - 5.79) > 1
    assert _ok("Ex 2", (round(WRAPPED, 6), round(RAW, 5)), ch.exercise_2)
    assert "(a)" in verdict("Ex 2", (0.0, RAW), test=ch.exercise_2)
    assert "(b)" in verdict("Ex 2", (WRAPPED, 0.0), test=ch.exercise_2)


# Right to the digits each exercise asks for (ch.DIGITS): rounded there, or cut off there.
ROUNDED = {
    "exercise_1": round(UPPER_50, 3),  # 4 digits: 3.716
    "exercise_2": (round(WRAPPED, 4), round(RAW, 2)),  # 3 digits
    "exercise_3": round(float(norm.cdf(D_M / 2)), 3),
    "exercise_4": (9, round(GAMMA, 3), round(WM[0], 3), round(WC[0], 3), round(WM[1], 4)),
    "exercise_5": (round(V11_RIGHT, 4), round(V11_DECK, 2)),  # (0.0875, -9.68)
}
# Right, but to fewer digits than asked: "give more digits", not a message about the concept.
SHORT = {
    "exercise_1": round(UPPER_50, 2),
    "exercise_2": (round(WRAPPED, 3), RAW),
    "exercise_3": round(float(norm.cdf(D_M / 2)), 2),
    "exercise_4": (9, GAMMA, WM[0], WC[0], round(WM[1], 2)),
    "exercise_5": (round(V11_RIGHT, 3), V11_DECK),
}


@pytest.mark.parametrize("name", sorted(ROUNDED))
def test_an_answer_right_to_the_asked_digits_is_correct(name):
    assert _ok(name, ROUNDED[name], getattr(ch, name))


@pytest.mark.parametrize("name", sorted(SHORT))
def test_an_answer_right_to_fewer_digits_is_told_to_give_more(name):
    message = verdict(name, SHORT[name], test=getattr(ch, name))
    assert message == f"{name}: not yet — give more digits: the exercise asks for " + (
        f"{ch.DIGITS[int(name[-1])]} significant digits"
    ), message


def test_issue_answers_at_three_or_four_digits_pass():
    """The answers issue 23 found rejected: (0.0875, -9.676) and 3.716 now pass."""
    assert _ok("Ex 5", (0.0875, -9.676), ch.exercise_5)
    assert _ok("Ex 1", 3.716, ch.exercise_1)


def test_exercise_3_is_not_trivial():
    assert 0.5 < norm.cdf(D_M / 2) < 1.0  # a case where the answer is not trivial


def test_exercise_5_deck_V11():
    right, deck = ch._exercise_5_truth()
    assert right == pytest.approx(0.1 * math.cos(0.5 + 0.005) * math.sin(0.005) / 0.005, rel=1e-12)
    assert np.isfinite(deck) and deck < -9  # the deck's value is ≈ -2 sin θ / ω
