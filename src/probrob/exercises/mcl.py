"""The checks of the Monte Carlo localization chapter's exercises (each computes the truth
with the library and returns ``None`` when the answer is right, else what is wrong).

Holds the checks of the Monte Carlo localization chapter's exercises.
Does not hold the answers or the filters (each check computes the truth with :mod:`probrob.mcl`).
"""

from __future__ import annotations

import numpy as np
from scipy.stats import norm

from ..mcl import kld_sample_size
from ..motion import odometry_deltas
from . import agrees, more_digits, not_a_number, one_number


def _number(answer, what="a number"):
    """``(value, None)`` for one real finite number, else ``(None, what is wrong)``."""
    return one_number(answer, what)


def exercise_1(answer) -> str | None:
    """k = 40, ε = 0.05, δ = 0.01: the KLD bound of Table 8.4, rounded up."""
    got, problem = _number(answer, "one integer")
    if problem:
        return problem
    want = kld_sample_size(40, 0.05, 0.01)
    if got == want:
        return None
    if got == kld_sample_size(40, 0.05, float(norm.sf(0.99))):
        return "that is z = 0.99 (amcl's pf_z read as a probability): use the quantile z_{1-δ}"
    if got == want - 1 or (got != int(got) and abs(got - want) < 1):
        return "round up: the bound is a smallest number of particles"
    return "recompute (k-1)/(2ε) · {1 - 2/(9(k-1)) + sqrt(2/(9(k-1))) z_{1-δ}}³"


def exercise_2(answer) -> str | None:
    """Weights (0.05, 0.42, 0.18, 0.35), M = 10: the floor and ceiling of M·w."""
    problem = not_a_number(answer)
    if problem:
        return problem
    try:
        low, high = (np.asarray(part, dtype=float) for part in answer)
    except (TypeError, ValueError):
        return "answer with two tuples: (lowest counts, highest counts)"
    w = np.array([0.05, 0.42, 0.18, 0.35])
    if low.shape != (4,) or high.shape != (4,):
        return "give four counts in each tuple, one per particle"
    if np.array_equal(low, np.rint(10 * w)) or np.array_equal(high, np.rint(10 * w)):
        return "the count is not M·w rounded: it is one of floor(M·w) and ceil(M·w)"
    if not np.array_equal(low, np.floor(10 * w)):
        return "the lowest counts are not right"
    if not np.array_equal(high, np.ceil(10 * w)):
        return "the highest counts are not right"
    return None


def exercise_3(answer) -> str | None:
    """w_slow = 2e-4, w_fast = 1.5e-4: max(0, 1 - w_fast/w_slow)."""
    got, problem = _number(answer, "one probability")
    if problem:
        return problem
    want = max(0.0, 1.0 - 1.5e-4 / 2.0e-4)
    if not 0.0 <= got <= 1.0:
        return "a probability lies between 0 and 1"
    if np.isclose(got, want, rtol=1e-3, atol=0.0):
        return None
    if agrees(got, 1.0 - 2.0e-4 / 1.5e-4) or agrees(got, 1.5e-4 / 2.0e-4):
        return "not line 14 of Table 8.3: check which average is on top, and the 1 - ..."
    return more_digits(got, want, rtol=1e-3) or "not the probability of line 14 of Table 8.3"


def exercise_4(answer) -> str | None:
    """Weights (1, 1, 1, 5): N_eff = 1 / Σ w̃² of the normalised weights."""
    got, problem = _number(answer)
    if problem:
        return problem
    w = np.array([1.0, 1.0, 1.0, 5.0])
    want = 1.0 / np.sum((w / w.sum()) ** 2)
    if np.isclose(got, want, rtol=1e-3, atol=0.0):
        return None
    if agrees(got, 1.0 / np.sum(w**2)):
        return "normalise the weights first"
    if got == 4.0:
        return "the weights are not equal: N_eff is less than N"
    return more_digits(got, want, rtol=1e-3) or "N_eff = 1 / Σ w̃ᵢ² with w̃ the normalised weights"


def exercise_5(answer) -> str | None:
    """Odometry (0, 0, 0) → (−0.004, 0.001, 0.5), α1 = 0.1, α2 = 0: (book σ, amcl σ) of δrot1."""
    problem = not_a_number(answer)
    if problem:
        return problem
    try:
        book, amcl = (float(np.asarray(a, dtype=float)) for a in answer)
    except (TypeError, ValueError):
        return "answer with two numbers: (book, amcl)"
    r1, _, _ = odometry_deltas(np.array([0.0, 0.0, 0.0]), np.array([-0.004, 0.001, 0.5]))
    want = float(np.sqrt(0.1) * abs(r1))
    if not np.isclose(book, want, rtol=1e-3, atol=0.0):
        if agrees(book, 0.1 * float(r1) ** 2):
            return "the book's term is a variance; the standard deviation is its square root"
        if agrees(book, np.sqrt(0.1) * 0.5):
            return "δrot1 is the direction of the translation, not the turn"
        return (
            more_digits(book, want, rtol=1e-3)
            or "the book's value is not right: compute δrot1 with odometry_deltas"
        )
    if amcl != 0.0:
        return "amcl's value is not right: what does amcl do below 1 cm of translation?"
    return None


# Exercise 6: Table 8.1 on a ring corridor of five cells
RING_PRIOR = np.array([0.1, 0.2, 0.4, 0.2, 0.1])
RING_MOVE = {0: 0.1, 1: 0.8, 2: 0.1}  # cells moved forward: probability
RING_DOOR = np.array([0.6, 0.1, 0.1, 0.6, 0.1])  # p(z = door | cell): doors at cells 0 and 3


def _ring_step(prior, move, likelihood):
    """Table 8.1 on the ring: line 3 (a sum over the previous cells), line 4 (times the
    likelihood, normalised); returns ``(p_bar, posterior)``."""
    n = len(prior)
    p_bar = np.array(
        [sum(prior[i] * move.get((k - i) % n, 0.0) for i in range(n)) for k in range(n)]
    )
    p = likelihood * p_bar
    return p_bar, p / p.sum()


def exercise_6(answer) -> str | None:
    """Ring of five cells, prior (0.1, 0.2, 0.4, 0.2, 0.1), one cell forward (0.1 stays, 0.8
    one, 0.1 two), door seen (0.6 at cells 0 and 3, else 0.1): the posterior of cell 3."""
    got, problem = _number(answer, "one probability")
    if problem:
        return problem
    p_bar, p = _ring_step(RING_PRIOR, RING_MOVE, RING_DOOR)
    want = p[3]
    if not 0.0 <= got <= 1.0:
        return "a probability lies between 0 and 1"
    if np.isclose(got, want, rtol=1e-3, atol=0.0):
        return None
    if agrees(got, RING_DOOR[3] * p_bar[3], rtol=1e-3):
        return "line 4 ends with η: normalise over the five cells"
    if agrees(got, p_bar[3], rtol=1e-3):
        return "that is line 3's prediction: line 4 weighs it by the door's likelihood"
    backward = {(-k) % 5: q for k, q in RING_MOVE.items()}
    if agrees(got, _ring_step(RING_PRIOR, backward, RING_DOOR)[1][3], rtol=1e-3):
        return "the robot moves to higher cell numbers: p̄_k sums p_i over the cells i behind k"
    if agrees(got, _ring_step(RING_PRIOR, {0: 1.0}, RING_DOOR)[1][3], rtol=1e-3):
        return "the robot moved before the door was seen: predict first (line 3)"
    return more_digits(got, want, rtol=1e-3) or "not Table 8.1's posterior of cell 3"
