"""The Monte Carlo localization chapter's exercise checks say "correct" to the right answer and
"not yet" to the typical wrong ones (``probrob.exercises.mcl``)."""

import math
import re

import numpy as np
import pytest
from scipy.stats import chi2, norm

from probrob.exercises import mcl, verdict
from probrob.mcl import kld_sample_size
from probrob.motion import odometry_deltas

W2 = np.array([0.05, 0.42, 0.18, 0.35])
# Exercise 6 by hand: p̄ = (0.11, 0.11, 0.21, 0.36, 0.21); times the door likelihood
# (0.066, 0.011, 0.021, 0.216, 0.021), whose sum 0.335 is 1/η
RING_RIGHT = 0.216 / 0.335
R1, _, _ = odometry_deltas(np.zeros(3), np.array([-0.004, 0.001, 0.5]))

RIGHT = {
    "exercise_1": kld_sample_size(40, 0.05, 0.01),
    "exercise_2": (tuple(np.floor(10 * W2)), tuple(np.ceil(10 * W2))),
    "exercise_3": 0.25,
    "exercise_4": 1 / np.sum((np.array([1, 1, 1, 5]) / 8) ** 2),
    "exercise_5": (math.sqrt(0.1) * abs(R1), 0.0),
    "exercise_6": RING_RIGHT,
}

# The registry that tests/test_exercises.py reads: every check, its typical wrong answers.
WRONG_ANSWERS = {
    "exercise_1": [
        0,
        kld_sample_size(40, 0.05, float(norm.sf(0.99))),  # amcl's pf_z = 0.99 used as z
        kld_sample_size(40, 0.05, 0.01) - 1,  # rounded down
        -kld_sample_size(40, 0.05, 0.01),
        # δ = 0.99 in the formula (a quantile of about -2.33; kld_sample_size refuses it)
        math.ceil(39 / 0.1 * (1 - 2 / 351 + math.sqrt(2 / 351) * norm.isf(0.99)) ** 3),
    ],
    "exercise_2": [
        ((0, 0, 0, 0), (0, 0, 0, 0)),
        (tuple(np.rint(10 * W2)), tuple(np.rint(10 * W2))),  # M·w rounded
        (tuple(np.ceil(10 * W2)), tuple(np.floor(10 * W2))),  # swapped
        (tuple(10 * W2), tuple(10 * W2)),  # M·w itself
        tuple(np.floor(10 * W2)),  # one tuple only
    ],
    "exercise_3": [
        0.0,
        1.5e-4 / 2.0e-4,  # w_fast / w_slow
        1 - 2.0e-4 / 1.5e-4,  # the ratio upside down (negative)
        1.0,
    ],
    "exercise_4": [
        4.0,  # N, as if the weights were equal
        1 / np.sum(np.array([1, 1, 1, 5.0]) ** 2),  # unnormalised weights
        0.0,
        np.sum((np.array([1, 1, 1, 5]) / 8) ** 2),  # Σ w² instead of its inverse
    ],
    "exercise_5": [
        (0.0, 0.0),
        (0.1 * R1**2, 0.0),  # the variance, not the standard deviation
        (math.sqrt(0.1) * 0.5, 0.0),  # the turn instead of δrot1
        (math.sqrt(0.1) * abs(R1), math.sqrt(0.1) * abs(R1)),  # amcl as the book
        math.sqrt(0.1) * abs(R1),  # one number only
    ],
    "exercise_6": [
        0.0,
        0.216,  # line 4 without η
        0.36,  # line 3's prediction only
        0.4 * 0.6 / (0.1 * 0.6 + 0.2 * 0.1 + 0.4 * 0.1 + 0.2 * 0.6 + 0.1 * 0.1),  # no motion
        # the motion the wrong way round: p̄ = (0.11, 0.21, 0.36, 0.21, 0.11)
        0.21 * 0.6 / (0.11 * 0.6 + 0.21 * 0.1 + 0.36 * 0.1 + 0.21 * 0.6 + 0.11 * 0.1),
        0.6,  # the likelihood itself
        1.5,
    ],
}


def printed_forms(right):
    """The strings under which a message could print the right answer ``right`` (a number or
    nested tuples of numbers): repr, %g, 2 to 6 significant digits, 1 to 3 decimals, scientific,
    with thousands separators, and the tuples themselves. Forms with fewer than two
    significant digits ("0.2", "4") are left out: too short to tell from other text."""
    forms = set()
    if isinstance(right, tuple | list):
        for part in (right, *right):
            if np.ndim(part) and np.all(np.mod(np.asarray(part, dtype=float), 1) == 0):
                forms.add(str(tuple(np.asarray(part, dtype=int).ravel().tolist())))
            else:
                forms.add(str(part))
    for x in np.asarray(right, dtype=float).ravel():
        if not np.isfinite(x):
            continue
        x = float(x)
        forms |= {repr(x), f"{x:g}", f"{x:,.0f}", f"{x:,.0f}".replace(",", " ")}
        forms |= {f"{x:.{n}g}" for n in range(2, 7)} | {f"{x:.{n}f}" for n in (1, 2, 3)}
        forms |= {f"{x:.{n}e}" for n in (1, 2, 3)}
        if x == int(x):
            forms |= {str(int(x)), f"{int(x):,}".replace(",", " ")}
    return {f for f in forms if len(re.sub(r"[^0-9]", "", f).lstrip("0")) >= 2}


def assert_answer_not_printed(line, right):
    leaked = sorted(f for f in printed_forms(right) if f in line)
    assert not leaked, f"the message gives the answer away ({leaked}): {line}"


@pytest.mark.parametrize(
    ("name", "wrong"), [(n, w) for n, ws in WRONG_ANSWERS.items() for w in ws]
)
def test_no_wrong_answers_message_prints_the_right_answer(name, wrong):
    assert_answer_not_printed(verdict(name, wrong, test=getattr(mcl, name)), RIGHT[name])


def test_the_leak_check_can_fail():
    with pytest.raises(AssertionError, match="gives the answer away"):
        assert_answer_not_printed("not yet: it is 1 - 0.75 = 0.25", RIGHT["exercise_3"])
    with pytest.raises(AssertionError, match="gives the answer away"):
        assert_answer_not_printed("the highest are (1, 5, 2, 4)", ((0, 4, 1, 3), (1, 5, 2, 4)))


@pytest.mark.parametrize("name", sorted(RIGHT))
def test_the_right_answer_is_correct(name):
    assert verdict(name, RIGHT[name], test=getattr(mcl, name)) == f"{name}: correct"


@pytest.mark.parametrize(
    ("name", "wrong"), [(n, w) for n, ws in WRONG_ANSWERS.items() for w in ws]
)
def test_a_typical_wrong_answer_is_not_yet(name, wrong):
    assert verdict(name, wrong, test=getattr(mcl, name)).startswith(f"{name}: not yet")


def test_the_right_answers_agree_with_the_chapters_solutions():
    z = norm.isf(0.01)
    a = 2 / (9 * 39)
    assert RIGHT["exercise_1"] == math.ceil(39 / 0.1 * (1 - a + math.sqrt(a) * z) ** 3)
    assert RIGHT["exercise_4"] == pytest.approx(64 / 28)
    p_bar, p = mcl._ring_step(mcl.RING_PRIOR, mcl.RING_MOVE, mcl.RING_DOOR)
    np.testing.assert_allclose(p_bar, [0.11, 0.11, 0.21, 0.36, 0.21], rtol=1e-12)
    assert p[3] == pytest.approx(RIGHT["exercise_6"], rel=1e-12)
    # the Wilson-Hilferty approximation is so close at k = 40 that the exact chi-square
    # quantile gives the same count: not a wrong answer, so the check accepts it
    exact = math.ceil(chi2.ppf(0.99, 39) / (2 * 0.05))
    assert exact == RIGHT["exercise_1"]
    assert verdict("exercise_1", exact, test=mcl.exercise_1).endswith("correct")


@pytest.mark.parametrize(
    ("name", "answer"),
    [
        ("exercise_4", 2.29),  # 64/28 = 2.2857...: was "N_eff = 1 / Σ w̃ᵢ² ..."
        ("exercise_5", (0.1, 0.0)),  # wrong, not a rounding: the concept message
        ("exercise_5", (float(f"{math.sqrt(0.1) * abs(R1):.2g}"), 0.0)),
        ("exercise_6", 0.64),  # 0.6448 to two digits
    ],
)
def test_the_rule_of_digits_issue_23_item_11(name, answer):
    line = verdict(name, answer, test=getattr(mcl, name))
    assert line.startswith(f"{name}: not yet")
    short = isinstance(answer, float) or len(f"{answer[0]:g}".strip("0.")) >= 2
    assert ("give more digits" in line) == short, line
    assert_answer_not_printed(line, RIGHT[name])
