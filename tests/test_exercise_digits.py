"""The one rule of digits shared by every chapter's checks (issue 23, item 11):
:func:`probrob.exercises.more_digits` and :func:`probrob.exercises.agrees`."""

import math

import numpy as np
import pytest

from probrob.exercises import agrees, more_digits, not_a_number, verdict

SHORT = "close, but give more digits"


@pytest.mark.parametrize(
    ("answer", "truth", "kw"),
    [
        (0.31, 0.3125, {}),  # rounded to 2 digits
        (0.312, 0.3125, {}),  # cut to 3 digits
        (0.313, 0.3125, {}),  # rounded half up
        (3.14, math.pi, {"rtol": 1e-4}),
        (625, 625.3, {"rtol": 1e-4}),  # a whole number
        (630, 625.3, {"rtol": 1e-4}),  # trailing zero not significant: 2 digits
        (-0.0707, -0.07071067811865475, {}),  # the sign kept
        ([0.0707, 2.0], [0.07071067811865475, 2.0], {}),  # one value short, one right
        (1.2e-5, 1.234e-5, {}),
    ],
)
def test_a_right_value_short_of_digits_is_told_to_give_more(answer, truth, kw):
    message = more_digits(answer, truth, **kw)
    assert message is not None and message.startswith(SHORT), message
    assert agrees(answer, truth, **kw)


@pytest.mark.parametrize(
    ("answer", "truth", "kw"),
    [
        (0.3125, 0.3125, {}),  # right
        (0.31250001, 0.3125, {"rtol": 1e-6}),  # right to the tolerance
        (0.3, 0.3125, {}),  # one digit only: a guess, not a rounding
        (0.32, 0.3125, {}),  # the second digit is not the truth's
        (0.3124999, 0.3125, {"rtol": 1e-9}),  # many digits, wrong in the last: computed wrong
        (-0.31, 0.3125, {}),  # the wrong sign
        (0.0, 1e-12, {}),
        ([0.31, 3.0], [0.3125, 2.0], {}),  # one short, one wrong: wrong
        ("0.31", 0.3125, {}),  # not a number
        (True, 1.0, {}),
        (float("nan"), 0.3125, {}),
    ],
)
def test_right_wrong_and_non_numbers_are_not_short_of_digits(answer, truth, kw):
    assert more_digits(answer, truth, **kw) is None


@pytest.mark.parametrize("rtol", [1e-3, 1e-4, 1e-6, 1e-9])
def test_the_message_says_how_many_digits_and_never_the_truth(rtol):
    truth = 0.07071067811865475
    message = more_digits(0.071, truth, rtol=rtol)
    n = int(message.rsplit("needs ", 1)[1].split()[0])
    assert message == f"{SHORT}: the check needs {n} significant digits"
    assert "707" not in message
    # the truth rounded to n digits passes the tolerance, to n - 1 digits it does not
    assert np.isclose(float(f"{truth:.{n - 1}e}"), truth, rtol=rtol, atol=0)
    assert not np.isclose(float(f"{truth:.{n - 2}e}"), truth, rtol=rtol, atol=0)
    assert verdict("E", float(f"{truth:.{n - 1}e}"), truth, rtol=rtol) == "E: correct"


def test_agrees_recognises_a_typed_wrong_value():
    sd = math.sqrt(2 * 2e-4) / 0.3  # 0.0666...
    assert agrees(0.0667, sd) and agrees(0.066, sd) and agrees(sd, sd)
    assert not agrees(0.0025, sd) and not agrees("0.0667", sd) and not agrees(0.07, sd)
    assert not agrees(0.068, sd)


def test_verdict_with_expected_uses_the_rule():
    assert verdict("E", 3.14, math.pi, rtol=1e-6).startswith(f"E: not yet — {SHORT}")
    assert verdict("E", 3.0, math.pi, rtol=1e-6) == "E: not yet — too small"
    assert verdict("E", math.pi, math.pi) == "E: correct"


@pytest.mark.parametrize(
    ("answer", "what"),
    [
        ("625", "a string"),
        (("0", "4", "1", "3"), "a string"),
        ((0.3, False), "a bool"),
        (True, "a bool"),
        (np.array([1.0, np.nan]), "NaN"),
        ((float("nan"), 0.0), "NaN"),
        (np.inf, "infinity"),
        (1 + 2j, "complex"),
        ((None, 1.0), "None"),
        ({"a": 1}, "dict"),
    ],
)
def test_not_a_number_says_what_the_answer_is(answer, what):
    message = not_a_number(answer)
    assert message is not None and what in message


@pytest.mark.parametrize(
    "answer", [0.3, 4, np.float32(2.5), np.int64(7), (0.3, (1, 2)), np.zeros((2, 3)), [], ()]
)
def test_numbers_are_numbers(answer):
    assert not_a_number(answer) is None
