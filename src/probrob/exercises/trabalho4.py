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
    "EM_TRUE",
    "INTEL_SCAN",
    "LANDMARK_SIGMAS",
    "MRCLAM_MEASUREMENT",
    "P_DEMO",
    "P_INTEL",
    "exercise_1",
    "exercise_2",
    "exercise_3",
    "exercise_4",
    "exercise_5",
    "exercise_6",
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


def exercise_2(answer):
    """(q at the turned pose with ``log=False``, log q with ``log=True``)."""
    q_linear, q_log = _pair(answer, "q_linear, q_log")
    intel, grid = _intel()
    k = INTEL_SCAN
    x = intel.poses[k] + [0.0, 0.0, np.pi / 2]
    truth = beam_range_finder_model(intel.ranges[k], x, grid, intel.beam_angles, P_INTEL, log=True)
    problems = []
    if _number(q_linear, "q_linear") != 0.0:
        problems.append("q_linear is not what log=False returns there")
    if abs(_number(q_log, "q_log") - truth) > 1e-6 * abs(truth):
        problems.append("q_log is not the log-likelihood of the turned pose")
    return "; ".join(problems) or None


def exercise_3(answer):
    """z_hit of Table 6.2 as printed (``e_step="deck", m_step="book"``)."""
    rng = np.random.default_rng(EM_SEED)
    z_star = rng.uniform(0.5, 9.0, EM_SIZE)
    z = sample_beam_mixture(z_star, EM_TRUE, rng=rng)
    truth = learn_intrinsic_parameters(z, z_star, 10.0, e_step="deck", m_step="book").z_hit
    v = _number(answer)
    if abs(v - truth) > 1e-9:
        return "that is not the z_hit of the deck's Table 6.2 (both its E-step and M-step)"
    return None


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
    if abs(v - (lf[0] - lf[1])) > 1e-6 * abs(lf[0] - lf[1]):
        return "not the drop of the likelihood field's log-likelihood (corrected minus moved)"
    return None


def exercise_5(answer):
    """(log q at the Vicon pose, the same with the deck's σ passed as a variance)."""
    log_q, log_q_deck = _pair(answer, "log_q, log_q_deck")
    f, c, m, truth = _mrclam()
    sig = np.asarray(LANDMARK_SIGMAS)
    right = landmark_model_known_correspondence(f, c, truth, m, sig, log=True)
    # The deck's prob(a, σ) is a normal of variance σ, i.e. of standard deviation √σ.
    deck = landmark_model_known_correspondence(f, c, truth, m, np.sqrt(sig), log=True)
    problems = []
    if abs(_number(log_q, "log_q") - right) > 1e-9:
        problems.append("log_q is not Table 6.4's log-likelihood with standard deviations")
    if abs(_number(log_q_deck, "log_q_deck") - deck) > 1e-9:
        problems.append("log_q_deck is not the deck's version (σ read as a variance)")
    return "; ".join(problems) or None


def exercise_6(answer):
    """The heading (rad) at the Vicon position from which the landmark is seen at φ."""
    f, c, m, truth = _mrclam()
    th = _number(answer)
    if not -np.pi <= th < np.pi:
        return "give the heading in radians, wrapped to [-π, π)"
    seen = landmark_measurement([truth[0], truth[1], th], m[c])
    if abs(wrap_angle(seen[1] - f[1])) > 1e-9:
        return "from that heading the landmark is not seen at the measured bearing"
    return None
