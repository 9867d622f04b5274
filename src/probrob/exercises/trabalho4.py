r"""Checks of the exercises of the chapter "Trabalho 4" (measurement models, book ch. 6).

Each ``exercise_N(answer)`` computes the right answer with the library and returns
``None`` when ``answer`` is right, else a short message of what is wrong (never the right
value). The chapter calls them through :func:`probrob.exercises.check`.

The exercises use the chapter's settings, repeated here so that a check needs nothing
from the reader's kernel: the demonstration beam model :data:`P_DEMO`, the Intel Lab
scan :data:`INTEL_SCAN` with the beam parameters :data:`P_INTEL` in the map built from
all its scans, and the MRCLAM measurement :data:`MRCLAM_MEASUREMENT` with the standard
deviations :data:`LANDMARK_SIGMAS`.

Does not hold: the models (``probrob.sensors``), nor the chapter's solutions.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from probrob.angles import wrap_angle
from probrob.sensors import (
    BeamModelParams,
    beam_range_finder_model,
    landmark_measurement,
    landmark_model_known_correspondence,
    learn_intrinsic_parameters,
    likelihood_field_range_finder_model,
    sample_beam_mixture,
)

__all__ = [
    "DIGITS",
    "EM_TRUE",
    "EX2_TURN",
    "EX3_N",
    "EX5_SIGMAS",
    "INTEL_SCAN",
    "LANDMARK_SIGMAS",
    "MRCLAM_MEASUREMENT",
    "P_DEMO",
    "P_INTEL",
    "agreement",
    "exercise_1",
    "exercise_2",
    "exercise_3",
    "exercise_4",
    "exercise_5",
    "exercise_6",
    "more_digits",
    "significant_digits",
]

#: The chapter's demonstration beam model (its first figure).
P_DEMO = BeamModelParams(0.7, 0.15, 0.05, 0.1, 0.2, 0.6, 10.0)
#: The parameters the chapter gives the Intel Lab scans.
P_INTEL = BeamModelParams(0.85, 0.05, 0.03, 0.07, 0.05, 0.5, 81.83)
#: Index of the Intel Lab scan of the chapter.
INTEL_SCAN = 400
#: The parameters the chapter's synthetic EM data are drawn from, its seed and size.
EM_TRUE = BeamModelParams(0.7, 0.1, 0.05, 0.15, 0.1, 0.8, 10.0)
EM_SEED, EM_SIZE = 11, 30_000
#: Index of the MRCLAM measurement of the chapter, and its (σ_r, σ_φ, σ_s).
MRCLAM_MEASUREMENT = 500
LANDMARK_SIGMAS = (0.15, 0.1, 0.5)


def _number(a, name="the answer"):
    try:
        v = float(a)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number") from None
    if not np.isfinite(v):
        raise ValueError(f"{name} must be finite")
    return v


def _pair(a, names):
    if not isinstance(a, (tuple, list)) or len(a) != 2:
        raise ValueError(f"expected a pair ({names})")
    return a


# The book's rule for numbers (issue 23, item 11): an answer right to the significant digits an
# exercise asks for is correct (rounded or cut off there: one unit of the last asked digit); one
# that gives fewer digits and is right to those is told to give more digits; only an answer
# that is wrong at the digits it gives gets the exercise's message about the concept. Local to
# the Trabalho 4 and 5 checks until probrob.exercises holds the shared rule.
def significant_digits(value) -> int:
    """The significant digits of ``value`` as Python writes it (``0.66`` has 2, ``67.569`` 5)."""
    mantissa = repr(float(value)).lower().lstrip("-").split("e")[0]
    digits = mantissa.replace(".", "").lstrip("0")
    if "." in mantissa and mantissa.endswith(".0"):
        digits = digits[:-1].rstrip("0") or digits[:1]  # 1000.0 -> "1"; 0.0 -> ""
    return max(len(digits), 1)


def _unit(truth: float, digits: int) -> float:
    return 10.0 ** (np.floor(np.log10(abs(truth))) - digits + 1)


def agreement(answer: float, truth: float, digits: int) -> str | None:
    """``None`` if ``answer`` is ``truth`` to ``digits`` significant digits, ``"short"`` if it
    gives fewer (at least two) and is ``truth`` to those, else ``"wrong"``."""
    if truth == 0.0:
        return None if answer == 0.0 else "wrong"
    if abs(answer - truth) <= _unit(truth, digits) * (1 + 1e-9):
        return None
    given = significant_digits(answer)
    if 2 <= given < digits and abs(answer - truth) <= _unit(truth, given) * (1 + 1e-9):
        return "short"
    return "wrong"


def more_digits(digits: int) -> str:
    """The message for an answer right to fewer digits than the ``digits`` asked."""
    return f"give more digits: the exercise asks for {digits} significant digits"


def _digits_verdict(parts):
    """``parts``: ``[(answer, truth, digits, concept message), ...]``; the check's message."""
    states = [(agreement(a, t, d), d, msg) for a, t, d, msg in parts]
    wrong = [msg for state, _, msg in states if state == "wrong"]
    if wrong:
        return "; ".join(wrong)
    short = [d for state, d, _ in states if state == "short"]
    return more_digits(max(short)) if short else None


@lru_cache(maxsize=1)
def _intel():
    from probrob.datasets import load_intel_lab
    from probrob.maps import OccupancyGrid

    intel = load_intel_lab()
    grid = OccupancyGrid.from_scans(
        intel.poses, intel.ranges, intel.beam_angles, 0.05, max_range=intel.max_range
    )
    return intel, grid


@lru_cache(maxsize=1)
def _mrclam():
    from probrob.datasets import load_mrclam

    d = load_mrclam()
    i = MRCLAM_MEASUREMENT
    truth = d.ground_truth[np.searchsorted(d.ground_truth_t, d.measurement_t[i])]
    return d.measurements[i], int(d.correspondences[i]), d.landmarks, truth


def exercise_1(answer):
    """(count of the 10 000 draws at r_max with ``rng=1``, expected count)."""
    drawn, expected = _pair(answer, "n_drawn, n_expected")
    z = sample_beam_mixture(3.0, P_DEMO, size=10_000, rng=1)
    n = int(np.sum(z == P_DEMO.max_range))
    problems = []
    if _number(drawn, "n_drawn") != n:
        problems.append("n_drawn is not the count of your draws at max_range")
    if abs(_number(expected, "n_expected") - 10_000 * P_DEMO.z_max) > 1e-9:
        problems.append("n_expected is not the expected count")
    return "; ".join(problems) or None


#: The turn of the Intel Lab scan's heading in exercise 2 (the robot facing backwards).
EX2_TURN = np.pi
#: Exercise 3 runs Table 6.2 on the first EX3_N readings of the chapter's synthetic data.
EX3_N = 15_000
#: The standard deviations (σ_r, σ_φ, σ_s) of exercise 5 (not the chapter's).
EX5_SIGMAS = (0.1, 0.05, 0.2)
#: Significant digits each exercise asks for.
DIGITS = {2: 4, 3: 3, 4: 3, 5: 3, 6: 4}


def exercise_2(answer):
    """(q with ``log=False``, log q with ``log=True``) at the pose turned by :data:`EX2_TURN`."""
    q_linear, q_log = _pair(answer, "q_linear, q_log")
    intel, grid = _intel()
    k = INTEL_SCAN
    x = intel.poses[k] + [0.0, 0.0, EX2_TURN]
    truth = beam_range_finder_model(intel.ranges[k], x, grid, intel.beam_angles, P_INTEL, log=True)
    right = beam_range_finder_model(
        intel.ranges[k], intel.poses[k], grid, intel.beam_angles, P_INTEL, log=True
    )
    problems = []
    if _number(q_linear, "q_linear") != 0.0:
        problems.append("q_linear is not what log=False returns there")
    v = _number(q_log, "q_log")
    state = agreement(v, truth, DIGITS[2])
    if state == "wrong":
        if agreement(v, right, DIGITS[2]) is None:
            problems.append("q_log is the corrected pose's: turn the heading")
        else:
            problems.append("q_log is not the log-likelihood of the turned pose")
    if problems:
        return "; ".join(problems)
    return more_digits(DIGITS[2]) if state == "short" else None


def exercise_3(answer):
    """z_hit of Table 6.2 as printed (``e_step="deck", m_step="book"``) on the first
    :data:`EX3_N` readings."""
    rng = np.random.default_rng(EM_SEED)
    z_star = rng.uniform(0.5, 9.0, EM_SIZE)
    z = sample_beam_mixture(z_star, EM_TRUE, rng=rng)
    z, z_star = z[:EX3_N], z_star[:EX3_N]
    truth = learn_intrinsic_parameters(z, z_star, 10.0, e_step="deck", m_step="book").z_hit
    deck_e = learn_intrinsic_parameters(z, z_star, 10.0, e_step="deck").z_hit
    v = _number(answer)
    if agreement(v, deck_e, DIGITS[3]) is None:
        return "that is the deck's E-step with the exact M-step: the deck's M-step is the book's"
    return _digits_verdict(
        [
            (
                v,
                truth,
                DIGITS[3],
                f"that is not the z_hit of the deck's Table 6.2 (both its E-step and M-step)"
                f" on the first {EX3_N:,} readings",
            )
        ]
    )


def exercise_4(answer):
    """Nats lost by the likelihood field when the robot moves 10 cm along its heading."""
    intel, grid = _intel()
    k = INTEL_SCAN
    x = intel.poses[k]
    moved = x + [0.1 * np.cos(x[2]), 0.1 * np.sin(x[2]), 0.0]
    lf = [
        likelihood_field_range_finder_model(
            intel.ranges[k], p, grid, intel.beam_angles, P_INTEL, log=True
        )
        for p in (x, moved)
    ]
    v = _number(answer)
    message = "not the drop of the likelihood field's log-likelihood (corrected minus moved)"
    if agreement(v, lf[1] - lf[0], DIGITS[4]) is None:
        message = "that is moved minus corrected: the drop is corrected minus moved"
    return _digits_verdict([(v, lf[0] - lf[1], DIGITS[4], message)])


def exercise_5(answer):
    """(log q at the Vicon pose, the same with the deck's σ passed as a variance), for the
    standard deviations :data:`EX5_SIGMAS`."""
    log_q, log_q_deck = _pair(answer, "log_q, log_q_deck")
    f, c, m, truth = _mrclam()
    sig = np.asarray(EX5_SIGMAS)
    right = landmark_model_known_correspondence(f, c, truth, m, sig, log=True)
    # The deck's prob(a, σ) is a normal of variance σ, i.e. of standard deviation √σ.
    deck = landmark_model_known_correspondence(f, c, truth, m, np.sqrt(sig), log=True)
    a, b = _number(log_q, "log_q"), _number(log_q_deck, "log_q_deck")
    chapter = landmark_model_known_correspondence(
        f, c, truth, m, np.asarray(LANDMARK_SIGMAS), log=True
    )
    if agreement(a, chapter, DIGITS[5]) is None:
        return "log_q uses the chapter's SIGMAS: the exercise gives other σ"
    return _digits_verdict(
        [
            (
                a,
                right,
                DIGITS[5],
                "log_q is not Table 6.4's log-likelihood with standard deviations",
            ),
            (b, deck, DIGITS[5], "log_q_deck is not the deck's version (σ read as a variance)"),
        ]
    )


def exercise_6(answer):
    """The heading (rad) at the Vicon position from which the landmark is seen at φ."""
    f, c, m, truth = _mrclam()
    th = _number(answer)
    if not -np.pi <= th < np.pi:
        return "give the heading in radians, wrapped to [-π, π)"
    gamma = np.arctan2(truth[1] - m[c, 1], truth[0] - m[c, 0])  # direction from the landmark
    right = float(wrap_angle(gamma - np.pi - f[1]))
    seen = landmark_measurement([truth[0], truth[1], th], m[c])
    if abs(wrap_angle(seen[1] - f[1])) <= 1e-9:
        return None
    return _digits_verdict(
        [
            (
                th,
                right,
                DIGITS[6],
                "from that heading the landmark is not seen at the measured bearing",
            )
        ]
    )
