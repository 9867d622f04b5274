"""The MRCLAM chapter's exercise checks say "correct" to the answer and "not yet" to slips.

The checks take the chapter's fitted α and windows as arguments; here they get α and
windows made up for the test (windows drawn from the odometry model), so the tests need no
data set and no fit of the real run.
"""

import re
from functools import partial
from pathlib import Path

import nbformat
import numpy as np
import pytest

from probrob.exercises import mrclam as ch
from probrob.exercises import verdict
from probrob.fitting import MotionWindows, fit_odometry_alpha, odometry_log_likelihood
from probrob.motion import (
    apply_odometry_deltas,
    motion_model_velocity,
    odometry_deltas,
    sample_motion_model_odometry,
)

ALPHA_V = np.array([0.011, 0.0075, 1.8, 0.2, 2.1, 0.08])
ALPHA_V_STD = np.array([0.097, 0.058, 1.3, 0.18, 1.4, 0.062])
ALPHA_O = np.array([0.15, 0.64, 0.0093, 0.015])


def correct(name, answer, test):
    return verdict(name, answer, test=test) == f"{name}: correct"


def not_yet(name, answer, test, right=None):
    """``answer`` is "not yet" and (given ``right``) its message does not print ``right``."""
    line = verdict(name, answer, test=test)
    if right is not None:
        assert_answer_not_printed(line, right)
    return line.startswith(f"{name}: not yet")


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


# ------------------------------------------------------------------------------ exercise 1


def _ratio(alpha=ALPHA_V, density="book"):
    s = ch.EXERCISE_1
    p_a, p_b = (
        motion_model_velocity(s[x], s["u"], s["x_prev"], s["dt"], alpha, density=density)
        for x in ("x_a", "x_b")
    )
    return float(p_b / p_a)


def test_exercise_1_right_answer_by_hand_and_by_the_library():
    test = partial(ch.exercise_1, alpha=ALPHA_V)
    s = ch.EXERCISE_1
    gamma, v = s["x_b"][2] / s["dt"], s["u"][0]
    by_hand = np.exp(-(gamma**2) / (2 * ALPHA_V[4] * v**2))  # only the γ̂ factor differs
    assert np.isclose(_ratio(), by_hand, rtol=1e-12)
    assert np.isclose(_ratio(density="pose"), by_hand, rtol=1e-12)  # the Jacobian cancels
    assert correct("Exercise 1", by_hand, test)
    assert correct("Exercise 1", np.float64(by_hand), test)


@pytest.mark.parametrize(
    "slip",
    [
        "zero",
        "one (gamma forgotten)",
        "inverted",
        "log",
        "sigma for variance",
        "std-form formula",
        "other alpha",
        "text",
    ],
)
def test_exercise_1_slips_are_not_yet(slip):
    s = ch.EXERCISE_1
    gamma, v = s["x_b"][2] / s["dt"], s["u"][0]
    right = _ratio()
    answer = {
        "zero": 0.0,
        "one (gamma forgotten)": 1.0,
        "inverted": 1 / right,
        "log": np.log(right),
        "sigma for variance": np.exp(-(gamma**2) / (2 * np.sqrt(ALPHA_V[4]) * v)),
        "std-form formula": np.exp(-(gamma**2) / (2 * (ALPHA_V[4] * v) ** 2)),
        "other alpha": _ratio(alpha=ALPHA_V_STD),
        "text": "0.88",
    }[slip]
    assert not_yet("Exercise 1", answer, partial(ch.exercise_1, alpha=ALPHA_V), right=right)


# ------------------------------------------------------------------------------ exercise 2

X_PREV = np.array([1.0, 2.0, 0.4])
X_T = np.array([1.06, 2.03, 0.47])
ODOMETRY = np.array([[5.0, -1.0, 2.0], [4.96, -0.95, 2.09]])


def _variances():
    def var(rot1, trans, rot2):
        return ALPHA_O[2] * trans**2 + ALPHA_O[3] * (rot1**2 + rot2**2)

    return (
        var(*odometry_deltas(X_PREV, X_T)),
        var(*odometry_deltas(ODOMETRY[0], ODOMETRY[1])),
    )


def _test_2():
    return partial(ch.exercise_2, x_prev=X_PREV, x_t=X_T, odometry=ODOMETRY, alpha=ALPHA_O)


def test_exercise_2_right_answer():
    var_55, var_56 = _variances()
    assert not np.isclose(var_55, var_56, rtol=0.05)  # the example tells the two apart
    assert correct("Exercise 2", (var_55, var_56), _test_2())
    assert correct("Exercise 2", [var_55, var_56], _test_2())


@pytest.mark.parametrize(
    "slip", ["zeros", "swapped", "standard deviations", "both at delta-hat", "one number"]
)
def test_exercise_2_slips_are_not_yet(slip):
    var_55, var_56 = _variances()
    answer = {
        "zeros": (0.0, 0.0),
        "swapped": (var_56, var_55),
        "standard deviations": (np.sqrt(var_55), np.sqrt(var_56)),
        "both at delta-hat": (var_55, var_55),
        "one number": var_55,
    }[slip]
    assert not_yet("Exercise 2", answer, _test_2(), right=(var_55, var_56))


def test_exercise_2_says_which_part_is_off():
    var_55, var_56 = _variances()
    line = verdict("Exercise 2", (var_55, 2 * var_56), test=_test_2())
    assert "second" in line and "first" not in line
    assert "swapped" in verdict("Exercise 2", (var_56, var_55), test=_test_2())


# ------------------------------------------------------------------------------ exercise 3


def _windows(n, scale, seed):
    """``n`` windows drawn from the odometry model with ``scale`` × ALPHA_O."""
    rng = np.random.default_rng(seed)
    x_prev = np.column_stack([rng.uniform(-3, 3, n), rng.uniform(-3, 3, n), rng.uniform(-3, 3, n)])
    start = np.column_stack([rng.uniform(-9, 9, n), rng.uniform(-9, 9, n), rng.uniform(-3, 3, n)])
    deltas = (rng.normal(0, 0.2, n), rng.uniform(0.04, 0.08, n), rng.normal(0, 0.2, n))
    odometry = np.stack([start, apply_odometry_deltas(start, *deltas)], axis=1)
    x_t = sample_motion_model_odometry(odometry, x_prev, scale * ALPHA_O, rng=rng)
    zeros = np.zeros((n, 2))
    return MotionWindows(
        t0=np.arange(n, dtype=float),
        dt=1.0,
        u=zeros,
        u_min=zeros,
        u_max=zeros,
        x_prev=x_prev,
        x_t=x_t,
        odometry=odometry,
    )


@pytest.fixture(scope="module")
def split():
    """Training windows noisier than the test windows, as in the chapter's run."""
    train, test = _windows(200, 2.0, seed=1), _windows(90, 0.5, seed=2)

    def score(fit_on, on, density="pose"):
        f = fit_odometry_alpha(fit_on.x_t, fit_on.odometry, fit_on.x_prev, density=density)
        ll = odometry_log_likelihood(on.x_t, on.odometry, on.x_prev, f.alpha, density="pose")
        return float(np.mean(ll)), f.mean_log_likelihood

    swapped, in_sample = score(test, train)
    original, _ = score(train, test)
    book, _ = score(test, train, density="book")
    return {
        "test": partial(ch.exercise_3, train=train, test=test),
        "swapped": swapped,
        "in_sample": in_sample,
        "original": original,
        "book": book,
        "word": "higher" if swapped > original else "lower",
    }


def test_exercise_3_right_answer(split):
    assert split["word"] == "lower"  # harder windows scored: lower, as in the chapter
    assert correct("Exercise 3", (split["swapped"], split["word"]), split["test"])


@pytest.mark.parametrize(
    "slip",
    ["wrong word", "in-sample score", "original score", "book fit", "number only", "other word"],
)
def test_exercise_3_slips_are_not_yet(split, slip):
    other = "higher" if split["word"] == "lower" else "lower"
    answer = {
        "wrong word": (split["swapped"], other),
        "in-sample score": (split["in_sample"], split["word"]),
        "original score": (split["original"], split["word"]),
        "book fit": (split["book"], split["word"]),
        "number only": split["swapped"],
        "other word": (split["swapped"], "better"),
    }[slip]
    assert not_yet("Exercise 3", answer, split["test"], right=split["swapped"])


# ------------------------------------------------------------------------------ exercise 4

V, W = 0.067, -0.038  # a right turn: |ω| matters


def _sigmas(alpha=ALPHA_V_STD):
    return tuple(alpha[2 * k] * abs(V) + alpha[2 * k + 1] * abs(W) for k in range(3))


def _test_4():
    return partial(ch.exercise_4, alpha=ALPHA_V_STD, v=V, w=W)


def test_exercise_4_right_answer():
    assert correct("Exercise 4", _sigmas(), _test_4())
    assert correct("Exercise 4", np.array(_sigmas()), _test_4())


@pytest.mark.parametrize(
    "slip", ["zeros", "variances", "variance-form formula", "signed omega", "v only", "reversed"]
)
def test_exercise_4_slips_are_not_yet(slip):
    a = ALPHA_V_STD
    right = np.array(_sigmas())
    answer = {
        "zeros": (0.0, 0.0, 0.0),
        "variances": tuple(right**2),
        "variance-form formula": tuple(
            np.sqrt(a[2 * k] * V**2 + a[2 * k + 1] * W**2) for k in range(3)
        ),
        "signed omega": tuple(a[2 * k] * V + a[2 * k + 1] * W for k in range(3)),
        "v only": tuple(a[2 * k] * abs(V) for k in range(3)),
        "reversed": tuple(right[::-1]),
    }[slip]
    assert not_yet("Exercise 4", answer, _test_4(), right=tuple(right))


# ------------------------------------------------------------------------------ all


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_no_message_gives_the_answer_away(n, split):
    """A wrong answer's message never prints the right value (to 3 significant digits)."""
    cases = {
        1: (_ratio(), 0.5, partial(ch.exercise_1, alpha=ALPHA_V)),
        2: (_variances()[0], (1.0, 1.0), _test_2()),
        3: (split["swapped"], (0.0, "lower"), split["test"]),
        4: (_sigmas()[0], (1.0, 1.0, 1.0), _test_4()),
    }
    right, wrong, test = cases[n]
    line = verdict(f"Exercise {n}", wrong, test=test)
    assert "not yet" in line
    assert f"{right:.3g}" not in line and f"{right:.3e}" not in line


@pytest.mark.parametrize("answer", [None, ..., float("nan"), "x", (1.0,), [[1.0, 2.0]]])
def test_odd_answers_are_reported_not_raised(answer):
    for name, test in [
        ("Exercise 1", partial(ch.exercise_1, alpha=ALPHA_V)),
        ("Exercise 2", _test_2()),
        ("Exercise 4", _test_4()),
    ]:
        assert not_yet(name, answer, test)


def test_exercise_1_prose_states_the_scenario_the_check_uses():
    """The numbers of Exercise 1's task are those of :data:`EXERCISE_1` (typed in the prose,
    as the question's inputs, so they must agree with the check)."""
    path = Path(__file__).parent.parent / "notebooks" / "mrclam_motion_noise.ipynb"
    text = next(
        c.source
        for c in nbformat.read(path, as_version=4).cells
        if c.cell_type == "markdown" and "Table 5.1 at two end poses" in c.source
    )
    s = ch.EXERCISE_1

    def pose(p):
        return "(" + ", ".join(f"{c:g}" for c in p) + ")"

    assert f"$x_{{t-1}} = {pose(s['x_prev'])}$" in text
    assert f"$(v, \\omega) = ({s['u'][0]:g}\\ \\text{{m/s}}, {s['u'][1]:g})$" in text
    assert f"$\\Delta t = {s['dt']:g}$ s" in text
    assert f"$x_a = {pose(s['x_a'])}$" in text and f"$x_b = {pose(s['x_b'])}$" in text
    assert f"heading\n   {s['x_b'][2]:g} rad further left" in text


# ------------------------------------------------------ issue 23, items 11 and 19


def test_exercise_2_two_parts_off_are_off():
    var_55, var_56 = _variances()
    line = verdict("Exercise 2", (3 * var_55, 2 * var_56), test=_test_2())
    assert line.endswith("are off"), line  # was "... and the second ... is off"
    assert verdict("Exercise 2", (var_55, 2 * var_56), test=_test_2()).endswith(" is off")


def test_exercise_3_accepts_a_list(split):
    # [score, "lower"] was "expected a pair"
    assert correct("Exercise 3", [split["swapped"], split["word"]], split["test"])
    assert not_yet("Exercise 3", [split["swapped"]], split["test"])


def test_exercise_4_names_the_parts_off_in_a_sentence():
    s = np.array(_sigmas())
    assert verdict("Exercise 4", s * [1, 2, 1], test=_test_4()).endswith("σ_ω is off")
    assert verdict("Exercise 4", s * [2, 2, 1], test=_test_4()).endswith("σ_v and σ_ω are off")


def test_a_right_value_short_of_digits_is_told_so(split):
    ratio, (var_55, var_56), sig = _ratio(), _variances(), _sigmas()
    cases = [
        ("Exercise 1", float(f"{ratio:.3g}"), partial(ch.exercise_1, alpha=ALPHA_V)),
        ("Exercise 2", (float(f"{var_55:.3g}"), var_56), _test_2()),
        ("Exercise 3", (float(f"{split['swapped']:.4g}"), split["word"]), split["test"]),
        ("Exercise 4", tuple(float(f"{x:.3g}") for x in sig), _test_4()),
    ]
    for name, answer, test in cases:
        line = verdict(name, answer, test=test)
        assert "give more digits" in line, (name, answer, line)
