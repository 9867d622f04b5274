"""The exercise checks of the chapter "Trabalho 4": the right answer passes, typical slips fail,
and no slip's message prints the right answer."""

import re

import numpy as np
import pytest

import probrob.exercises.trabalho4 as ch
from probrob.datasets import load_intel_lab, load_mrclam
from probrob.exercises import verdict
from probrob.maps import OccupancyGrid
from probrob.sensors import (
    beam_range_finder_model,
    landmark_model_known_correspondence,
    learn_intrinsic_parameters,
    likelihood_field_range_finder_model,
    sample_beam_mixture,
)


def is_correct(name, answer, test):
    return verdict(name, answer, test=test) == f"{name}: correct"


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


def assert_not_yet(name, answer, test, right):
    """``answer`` is "not yet", and its message does not print ``right``."""
    line = verdict(name, answer, test=test)
    assert line.startswith(f"{name}: not yet"), (answer, line)
    assert "give more digits" not in line, (answer, line)  # a wrong answer hears the concept
    assert_answer_not_printed(line, right)


@pytest.fixture(scope="module")
def intel():
    d = load_intel_lab()
    grid = OccupancyGrid.from_scans(d.poses, d.ranges, d.beam_angles, 0.05, max_range=d.max_range)
    return d, grid


@pytest.fixture(scope="module")
def mrclam():
    d = load_mrclam()
    i = ch.MRCLAM_MEASUREMENT
    truth = d.ground_truth[np.searchsorted(d.ground_truth_t, d.measurement_t[i])]
    return d.measurements[i], int(d.correspondences[i]), d.landmarks, truth


def test_settings_are_the_chapters():
    assert ch.P_INTEL.max_range == load_intel_lab().max_range
    assert ch.P_DEMO.weights.sum() == pytest.approx(1.0)


def test_exercise_1_point_mass_count():
    z = sample_beam_mixture(3.0, ch.P_DEMO, size=10_000, rng=1)
    n = int(np.sum(z == ch.P_DEMO.max_range))
    assert n != 500  # so that the expected count is not also the drawn one
    assert is_correct("Exercise 1", (n, 500), ch.exercise_1)
    assert is_correct("Exercise 1", (float(n), 500.0), ch.exercise_1)
    for wrong in [
        (500, 500),  # the expectation given for the draw
        (0, 500),  # counted readings equal to z* or forgot the point mass
        (n, 0.05),  # the weight, not a count
        (n, 10_000 * ch.P_DEMO.z_hit),  # the wrong weight
        (n, n),  # the draw given as the expectation
        (int(np.sum(z >= 9.0)), 500),  # counted near r_max, not at it
        n,  # one number for a pair
    ]:
        assert_not_yet("Exercise 1", wrong, ch.exercise_1, right=(n, 500))


def is_short(name, answer, test):
    """The check says the answer is right to the digits it gives, and asks for more."""
    line = verdict(name, answer, test=test)
    return line.startswith(f"{name}: not yet — give more digits")


def test_exercise_2_underflow(intel):
    d, grid = intel
    k = ch.INTEL_SCAN
    x = d.poses[k] + [0.0, 0.0, ch.EX2_TURN]
    q_log = beam_range_finder_model(d.ranges[k], x, grid, d.beam_angles, ch.P_INTEL, log=True)
    q_true = beam_range_finder_model(
        d.ranges[k], d.poses[k], grid, d.beam_angles, ch.P_INTEL, log=True
    )
    quarter = beam_range_finder_model(
        d.ranges[k], d.poses[k] + [0, 0, np.pi / 2], grid, d.beam_angles, ch.P_INTEL, log=True
    )
    assert round(quarter) == -1061  # erratum B7's pose: the exercise asks for another one
    assert abs(q_log - quarter) > 10
    assert is_correct("Exercise 2", (0.0, q_log), ch.exercise_2)
    assert is_correct("Exercise 2", (0.0, float(round(q_log))), ch.exercise_2)  # 4 digits
    assert is_short("Exercise 2", (0.0, float(round(q_log, -1))), ch.exercise_2)
    for wrong in [
        (0.0, -1000.0),  # any very negative number
        (0.0, q_true),  # the corrected pose's log-likelihood
        (0.0, quarter),  # erratum B7's pose, turned by 90°
        (0.0, -q_log),  # the wrong sign
        (0.0, q_log / np.log(10)),  # log10 for ln
        (1e-300, q_log),  # q_linear that did not underflow
        (np.exp(q_true), q_log),  # q at the corrected pose
        (q_log, 0.0),  # swapped
    ]:
        assert_not_yet("Exercise 2", wrong, ch.exercise_2, right=(0.0, q_log))
    assert "corrected pose" in verdict("Exercise 2", (0.0, q_true), test=ch.exercise_2)


def test_exercise_3_deck_table_6_2():
    rng = np.random.default_rng(ch.EM_SEED)
    z_star = rng.uniform(0.5, 9.0, ch.EM_SIZE)
    z = sample_beam_mixture(z_star, ch.EM_TRUE, rng=rng)
    printed = learn_intrinsic_parameters(z, z_star, 10.0, e_step="deck", m_step="book").z_hit
    z, z_star = z[: ch.EX3_N], z_star[: ch.EX3_N]
    deck = learn_intrinsic_parameters(z, z_star, 10.0, e_step="deck", m_step="book").z_hit
    deck_e = learn_intrinsic_parameters(z, z_star, 10.0, e_step="deck").z_hit
    em = learn_intrinsic_parameters(z, z_star, 10.0).z_hit
    assert abs(deck - printed) > 2e-3  # the chapter's table (all readings) is not the answer
    assert is_correct("Exercise 3", deck, ch.exercise_3)
    assert is_correct("Exercise 3", round(deck, 3), ch.exercise_3)  # the 3 digits asked
    assert is_short("Exercise 3", round(deck, 2), ch.exercise_3)
    for wrong in [deck_e, em, 0.7, 0.0, printed, round(printed, 3), round(deck_e, 3)]:
        assert_not_yet("Exercise 3", wrong, ch.exercise_3, right=deck)
    assert "exact M-step" in verdict("Exercise 3", round(deck_e, 3), test=ch.exercise_3)


def test_exercise_4_likelihood_field_drop(intel):
    d, grid = intel
    k = ch.INTEL_SCAN
    x = d.poses[k]

    def ll(p, model=likelihood_field_range_finder_model):
        return model(d.ranges[k], p, grid, d.beam_angles, ch.P_INTEL, log=True)

    ahead = x + [0.1 * np.cos(x[2]), 0.1 * np.sin(x[2]), 0.0]
    drop = ll(x) - ll(ahead)
    assert drop > 0
    assert is_correct("Exercise 4", drop, ch.exercise_4)
    assert is_correct("Exercise 4", round(drop, 1), ch.exercise_4)  # 67.6 for 67.569
    assert is_short("Exercise 4", float(round(drop)), ch.exercise_4)
    for wrong in [
        -drop,  # moved minus corrected
        ll(x) - ll(x + [0.1, 0.0, 0.0]),  # 10 cm along x, not along the heading
        ll(x, beam_range_finder_model) - ll(ahead, beam_range_finder_model),  # beam model
        np.exp(-drop),  # a likelihood ratio, not nats
        0.0,
    ]:
        assert_not_yet("Exercise 4", wrong, ch.exercise_4, right=drop)
    assert "moved minus corrected" in verdict("Exercise 4", -round(drop, 1), test=ch.exercise_4)


def test_exercise_5_sigma_or_variance(mrclam):
    f, c, m, truth = mrclam
    sig = np.asarray(ch.EX5_SIGMAS)

    def lq(s, pose=truth):
        return landmark_model_known_correspondence(f, c, pose, m, s, log=True)

    right, deck = lq(sig), lq(np.sqrt(sig))
    chapter = np.asarray(ch.LANDMARK_SIGMAS)
    assert abs(right - lq(chapter)) > 0.1  # not the chapter's printed log-likelihood
    assert is_correct("Exercise 5", (right, deck), ch.exercise_5)
    assert is_correct("Exercise 5", (round(right, 2), round(deck, 3)), ch.exercise_5)
    assert is_short("Exercise 5", (round(right, 1), deck), ch.exercise_5)
    for wrong in [
        (deck, right),  # swapped
        (right, lq(sig**2)),  # squared the σ instead (the other direction)
        (right, right),  # no difference
        (np.exp(right), np.exp(deck)),  # likelihoods, not logs
        (lq(sig, truth * [1, 1, 0]), deck),  # heading left out (errata L2)
        (lq(chapter), lq(np.sqrt(chapter))),  # the chapter's SIGMAS
    ]:
        assert_not_yet("Exercise 5", wrong, ch.exercise_5, right=(right, deck))


def test_exercise_6_heading(mrclam):
    f, c, m, truth = mrclam
    gamma = np.arctan2(truth[1] - m[c, 1], truth[0] - m[c, 0])
    theta = float(np.mod(gamma - np.pi - f[1] + np.pi, 2 * np.pi) - np.pi)
    assert abs(theta - truth[2]) < 0.05  # the Vicon heading agrees with the feature
    assert is_correct("Exercise 6", theta, ch.exercise_6)
    assert is_correct("Exercise 6", round(theta, 3), ch.exercise_6)  # 1.779 for 1.77856
    assert is_short("Exercise 6", round(theta, 2), ch.exercise_6)
    for wrong in [
        theta + 2 * np.pi,  # not wrapped (same direction, outside [-π, π))
        float(np.mod(gamma - np.pi + f[1] + np.pi, 2 * np.pi) - np.pi),  # + φ for - φ
        float(np.mod(gamma - f[1] + np.pi, 2 * np.pi) - np.pi),  # forgot the π
        np.rad2deg(theta),  # degrees
        round(float(truth[2]), 3),  # the Vicon heading itself
        0.0,
    ]:
        assert_not_yet("Exercise 6", wrong, ch.exercise_6, right=theta)


@pytest.mark.parametrize(
    ("value", "digits"),
    [
        (0.66, 2),
        (67.569, 5),
        (1.779, 4),
        (-1006.0, 4),
        (1000.0, 1),
        (67.0, 2),
        (0.0, 1),
        (2.5e-10, 2),
        (0.0875, 3),
        (3.0, 1),
    ],
)
def test_significant_digits_as_python_writes_the_number(value, digits):
    assert ch.significant_digits(value) == digits


def test_the_digit_rule():
    """Right to the digits asked (rounded or cut off) passes; right to fewer digits (at
    least two) is short; anything else is wrong, and so gets the concept message."""
    t = 67.56869
    assert [ch.agreement(a, t, 3) for a in (67.6, 67.5, 67.569, 67.56869)] == [None] * 4
    assert [ch.agreement(a, t, 3) for a in (68.0, 67.0)] == ["short", "short"]
    assert [ch.agreement(a, t, 3) for a in (67.8, 67.7, 70.0, -67.6, 6.76)] == ["wrong"] * 5
    assert ch.agreement(67.7001, t, 3) == "wrong"  # many digits, wrong at the third
    assert ch.agreement(0.0, 0.0, 3) is None and ch.agreement(1e-9, 0.0, 3) == "wrong"


def test_checks_never_raise_on_nonsense():
    for test in (ch.exercise_1, ch.exercise_2, ch.exercise_5):
        assert "not yet" in verdict("Ex", "text", test=test)
        assert "not yet" in verdict("Ex", (1, 2, 3), test=test)
    for test in (ch.exercise_3, ch.exercise_4, ch.exercise_6):
        assert "not yet" in verdict("Ex", "text", test=test)
        assert "not yet" in verdict("Ex", float("nan"), test=test)


def test_the_leak_check_can_fail():
    """The expected count printed as the issue found it is caught (so the check above can fail)."""
    with pytest.raises(AssertionError, match="gives the answer away"):
        assert_answer_not_printed("n_expected: expected about 10 000 × z_max = 500", (123, 500))
    with pytest.raises(AssertionError, match="gives the answer away"):
        assert_answer_not_printed("too small: the drop is 12.3 nats", 12.3456)
    assert_answer_not_printed("n_expected is not the expected count", (123, 500))
