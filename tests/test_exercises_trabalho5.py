"""The checks of the Trabalho 5 exercises say "correct" to the right answer and "not yet" to
the typical wrong ones (each part of a multi-part answer checked)."""

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


def test_exercise_1_nees_band():
    right = chi2_quantile(0.975, 150) / 50
    assert _ok("Ex 1", right, ch.exercise_1)
    for wrong in (
        0.0,
        chi2_quantile(0.975, 150),  # not divided by N
        chi2_quantile(0.975, 50) / 50,  # N degrees of freedom, not 3N
        chi2_quantile(0.975, 3),  # one run
        chi2_quantile(0.95, 150) / 50,  # one-sided 95 %
        chi2_quantile(0.025, 150) / 50,  # the lower end
        3.0,
        "3.7",
        [right, right],
    ):
        assert _no("Ex 1", wrong, ch.exercise_1), wrong


def test_exercise_2_both_parts():
    wrapped, raw = ch._exercise_2_truth()
    assert wrapped == pytest.approx(-0.0278, abs=1e-4)  # the value
    assert raw == pytest.approx(5.79, abs=0.005)
    assert _ok("Ex 2", (wrapped, raw), ch.exercise_2)
    assert _ok("Ex 2", (round(wrapped, 6), round(raw, 5)), ch.exercise_2)
    for wrong in (
        (0.0, raw),  # zero
        (0.03, raw),  # the measurement error itself
        (-wrapped, raw),  # wrong sign
        (raw, raw),  # the unwrapped update for (a)
        (wrapped, 0.0),  # second part missing
        (wrapped, wrapped),  # (b) wrapped too
        (wrapped, -raw),
        (wrapped, -2 * math.pi),  # the raw innovation, not the heading change
        wrapped,  # one number only
    ):
        assert _no("Ex 2", wrong, ch.exercise_2), wrong
    assert "(a)" in verdict("Ex 2", (0.0, raw), test=ch.exercise_2)
    assert "(b)" in verdict("Ex 2", (wrapped, 0.0), test=ch.exercise_2)


def test_exercise_3_association_probability():
    d_m = ch._exercise_3_dm()
    assert 0.5 < norm.cdf(d_m / 2) < 1.0  # a case where the answer is not trivial
    assert _ok("Ex 3", norm.cdf(d_m / 2), ch.exercise_3)
    for wrong in (
        0.5,  # a coin toss
        1.0,
        0.0,
        norm.cdf(-d_m / 2),  # the probability of the wrong choice
        norm.cdf(d_m),  # forgot the half
        1.5,  # not a probability
        norm.cdf(0.3 / 0.1 / 2),  # Euclidean spacing over σ_r
    ):
        assert _no("Ex 3", wrong, ch.exercise_3), wrong


def test_exercise_4_ukf_weights_every_part():
    gamma, wm, wc = ukf_weights(9, ukf_alpha=0.5, beta=2.0, kappa=0.0)
    right = (9, gamma, wm[0], wc[0], wm[1])
    assert _ok("Ex 4", right, ch.exercise_4)
    g7, wm7, wc7 = ukf_weights(7, ukf_alpha=0.5, beta=2.0, kappa=0.0)
    for wrong in (
        (7, g7, wm7[0], wc7[0], wm7[1]),  # one feature's L
        (9, gamma**2, wm[0], wc[0], wm[1]),  # γ² for γ
        (9, gamma, wm[0], wm[0], wm[1]),  # w0(c) = w0(m)
        (9, gamma, wc[0], wc[0], wm[1]),  # w0(m) = w0(c)
        (9, gamma, wm[0], wc[0], 1 / 19),  # equal weights
        (9, gamma, -wm[0], wc[0], wm[1]),  # sign
        (0, 0, 0, 0, 0),
        (9, gamma, wm[0], wc[0]),  # a part missing
    ):
        assert _no("Ex 4", wrong, ch.exercise_4), wrong


def test_exercise_5_deck_V11():
    right, deck = ch._exercise_5_truth()
    assert right == pytest.approx(0.1 * math.cos(0.5 + 0.005) * math.sin(0.005) / 0.005, rel=1e-12)
    assert _ok("Ex 5", (right, deck), ch.exercise_5)
    for wrong in (
        (deck, deck),  # the deck's formula for the right one
        (right, right),  # the right one for the deck's
        (0.0, deck),
        (-right, deck),  # wrong sign
        (0.1 * math.cos(0.5), deck),  # the straight-line value
        (right, -deck),
        (deck, right),  # swapped
        (right,),
    ):
        assert _no("Ex 5", wrong, ch.exercise_5), wrong
    assert np.isfinite(deck) and deck < -9  # the deck's value is ≈ -2 sin θ / ω
