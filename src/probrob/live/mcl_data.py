r"""The data a live particle filter embeds (:func:`probrob.live.mcl.particle_filter_live`).

Holds the page's constants, the random numbers it replays (:func:`particle_filter_draws`),
its choice of beams (:func:`particle_filter_beams`), where its kidnap button moves the
particles (:func:`particle_filter_kidnap_target`), the encodings of the map, the ranges and
the draws, and :func:`particle_filter_decoded` (what the page decodes, for feeding
:mod:`probrob.mcl` the same numbers). Does not hold the widget's controls and checks
(:mod:`probrob.live.mcl`) or the filters (:mod:`probrob.mcl`).
"""

from __future__ import annotations

import base64
import json
import re

import numpy as np

from .. import _validation as check
from ..distributions import sample_normal_distribution
from .core import LiveWidget, b64

__all__ = [
    "PF_HEADING_BINS",
    "PF_RADIUS",
    "particle_filter_beams",
    "particle_filter_decoded",
    "particle_filter_draws",
    "particle_filter_kidnap_target",
]

#: Particles within which the live particle filter's ``estimate_pose`` clusters (m).
PF_RADIUS = 0.5
#: Heading sectors of the live particle filter's ``estimate_pose`` (its default, 30° each).
PF_HEADING_BINS = 12
#: The embedded ranges are whole millimetres (uint16); this code marks a max-range reading.
PF_MAX_RANGE_CODE = 0xFFFF
#: The most steps and map cells a page carries (its size budget is 400 kB).
PF_MAX_STEPS, PF_MAX_CELLS = 300, 400_000
#: KLD-sampling's histogram bins (x, y, θ) and its fewest particles (Table 8.4's defaults of
#: :func:`probrob.mcl.kld_sampling_mcl`, but n_min: the particles slider's lower end).
PF_KLD_BINS, PF_KLD_N_MIN = (0.5, 0.5, np.pi / 18), 100
#: KLD-sampling's rounds past the first take their low-variance offsets from this many columns.
PF_ROUNDS = 4
#: The δ slider's step: the page looks z_{1-δ} up in a table over its values.
PF_DELTA_STEP, PF_DELTA_MAX = 0.001, 0.2


def particle_filter_draws(n_max=2000, steps=100, rng=0) -> dict[str, np.ndarray]:
    r"""Return the seeded random numbers the live particle filter embeds and replays.

    One generator makes, in this order,

    * ``"normal"`` shape ``(3 n_max,)``: a pool of standardized normals of
      :func:`~probrob.distributions.sample_normal_distribution` (the book's sum of twelve
      uniforms, variance 1), rounded to float32 (to halve their size in the page);
    * ``"offsets"`` shape ``(steps, 3)``: integers in ``[0, 3 n_max)``. At step ``t``
      (1-based) the motion sampler's noise term ``k`` (:math:`\hat\delta_{rot1}`,
      :math:`\hat\delta_{trans}`, :math:`\hat\delta_{rot2}`) of particle ``i`` is
      :math:`\sqrt{b^2}\, z` with ``z = normal[(offsets[t - 1, k] + i) % (3 n_max)]``: every
      step reads the pool from three fresh random places, so no particle index keeps its noise;
    * ``"resample"`` shape ``(steps,)``: uniforms in [0, 1), the low-variance sampler's
      random number of each step (``offset`` of :func:`probrob.mcl.low_variance_sampler`);
    * ``"uniforms"`` shape ``(n_max, 4)``: uniforms ``k / 2**24`` (exact in float32) for a global
      start (``uniforms`` of :func:`probrob.mcl.uniform_particles`);
    * ``"rounds"`` shape ``(steps, PF_ROUNDS)``: uniforms ``k / 2**24``, the low-variance
      sampler's random number of KLD-sampling's rounds after the first (round ``r >= 1`` of
      step ``t`` takes ``rounds[t - 1, (r - 1) % PF_ROUNDS]``; round 0 takes ``resample``);
    * ``"shuffle"`` shape ``(steps, 2)``: integers, a start ``s`` in ``[0, 4 n_max)`` into the
      ``uniforms`` read as one flat pool ``U`` of ``4 n_max``, and a row ``q`` in
      ``[0, n_max)``. At step ``t`` augmented MCL's number of random particles (Table 8.3,
      line 14, a binomial count) is the number of ``i < M`` with
      ``U[(s + i) % 4 n_max] < max(0, 1 - w_fast / w_slow)``, and its ``c``-th random particle
      is drawn from the uniforms' row ``(q + c) % n_max``. KLD-sampling puts each round's
      indices (Table 8.4, line 8) in random order by Fisher-Yates, from the last index down,
      swapping ``i`` with ``floor(u (i + 1))``, ``u`` the next of ``U[s], U[s + 1], ...``.

    The known start uses the pool's first ``3 n_max``: particle ``i`` is
    ``start + spread * (normal[i], normal[n_max + i], normal[2 n_max + i])``. Motion noise of
    KLD-sampling's particles: particle ``i`` of the step (counted over its rounds) reads the
    pool as particle ``i`` of MCL does.

    Parameters
    ----------
    n_max : int
        The most particles the widget offers (>= 1).
    steps : int
        Filter steps (>= 1).
    rng : None, int or numpy.random.Generator
        Seed.

    Returns
    -------
    draws : dict
    """
    n_max = check.count(n_max, "n_max", 1)
    steps = check.count(steps, "steps", 1)
    gen = check.rng(rng)
    pool = 3 * n_max
    normal = sample_normal_distribution(1.0, size=pool, rng=gen).astype(np.float32)
    return {
        "normal": normal.astype(np.float64),
        "offsets": gen.integers(0, pool, size=(steps, 3)),
        "resample": gen.random(steps),
        "uniforms": gen.integers(0, 2**24, size=(n_max, 4)) / 2.0**24,
        "rounds": gen.integers(0, 2**24, size=(steps, PF_ROUNDS)) / 2.0**24,
        "shuffle": np.column_stack(
            [gen.integers(0, 4 * n_max, size=steps), gen.integers(0, n_max, size=steps)]
        ),
    }


def particle_filter_kidnap_target(truth, step) -> int:
    r"""Return the step whose reference pose the live filter's kidnapping moves the particles to.

    The kidnap button of :func:`particle_filter_live` kidnaps the robot after step ``k``
    (``step``): the particle set :math:`\mathcal X_k` is replaced by
    ``X - truth[k] + truth[s]`` (as the chapter's kidnapping does on the log), with ``s`` the
    step whose reference position lies farthest from ``truth[k]`` (the first of equals), while
    the robot itself, and the log, go on where they are.

    Parameters
    ----------
    truth : array_like, shape (T + 1, 3)
    step : int
        ``k``, in [1, T].

    Returns
    -------
    s : int
    """
    truth = check.poses(truth, "truth")
    if truth.ndim != 2:
        raise ValueError(f"truth must have shape (T + 1, 3), got {truth.shape}")
    k = check.count(step, "step", 1)
    if k >= truth.shape[0]:
        raise ValueError(f"step must lie in [1, T = {truth.shape[0] - 1}], got {k}")
    return int(np.argmax(np.hypot(*(truth[:, :2] - truth[k, :2]).T)))


def particle_filter_beams(total, k) -> np.ndarray:
    """Return the indices of ``k`` of ``total`` beams spread evenly over the scan.

    ``round(linspace(0, total - 1, k))`` (half to even), the selection of the live particle
    filter's "beams" slider; shape ``(k,)``.
    """
    total = check.count(total, "total", 1)
    k = check.count(k, "k", 1)
    if k > total:
        raise ValueError(f"k must be at most the {total} beams of a scan, got {k}")
    return np.round(np.linspace(0, total - 1, k)).astype(np.intp)


def _cells(grid) -> str:
    """The grid's cells as 2-bit codes (0 unexplored, 1 free, 2 occupied), four per byte,
    row-major from row 0 (the lowest y); base64."""
    codes = grid.free.astype(np.uint8).ravel() + 2 * grid.occupied.astype(np.uint8).ravel()
    codes = np.concatenate([codes, np.zeros(-codes.size % 4, np.uint8)]).reshape(-1, 4)
    packed = codes[:, 0] | codes[:, 1] << 2 | codes[:, 2] << 4 | codes[:, 3] << 6
    return b64(packed, "u1")


def _ranges(scans, max_range) -> np.ndarray:
    """The ranges as whole millimetres, max-range readings (z >= max_range) as the code."""
    mm = np.round(scans * 1000.0)
    if np.any(mm[scans < max_range] >= PF_MAX_RANGE_CODE):
        raise ValueError(
            f"scans must be below {PF_MAX_RANGE_CODE / 1000} m (the page keeps whole "
            "millimetres in 16 bits) or at least params.max_range"
        )
    return np.where(scans < max_range, mm, PF_MAX_RANGE_CODE).astype(np.uint16)


def particle_filter_decoded(widget: LiveWidget) -> dict[str, np.ndarray]:
    """Return the arrays a live particle filter embeds, decoded as its JavaScript decodes them.

    ``scans`` in metres (a max-range reading as ``max_range``), ``odometry`` ``(T, 2, 3)``,
    ``truth`` ``(T + 1, 3)``, ``beam_angles`` ``(K,)`` and the draws of
    :func:`particle_filter_draws`; for feeding :mod:`probrob.mcl` exactly what the page uses.
    """
    match = re.search(r"const config = (\{.*?\});\n", widget.html)
    if widget.kernel != "mcl" or match is None:
        raise ValueError("widget must be a live particle filter (particle_filter_live)")
    config = json.loads(match.group(1))
    data = config["data"]

    def raw(name, dtype):
        return np.frombuffer(base64.b64decode(data[name]), dtype)

    steps, k, n_max = config["steps"], config["beamsTotal"], config["nMax"]
    mm = raw("scans", "<u2").reshape(steps, k).astype(np.float64)
    max_range = config["constants"]["maxRange"]
    return {
        "scans": np.where(mm == PF_MAX_RANGE_CODE, max_range, mm / 1000.0),
        "odometry": raw("odometry", "<f8").reshape(steps, 2, 3),
        "truth": raw("truth", "<f8").reshape(steps + 1, 3),
        "beam_angles": raw("beamAngles", "<f8"),
        "normal": raw("normal", "<f4").astype(np.float64),
        "offsets": raw("offsets", "<u4").reshape(steps, 3).astype(np.intp),
        "resample": raw("resample", "<f8"),
        "uniforms": raw("uniforms", "<f4").reshape(n_max, 4).astype(np.float64),
        "rounds": raw("rounds", "<f4").reshape(steps, PF_ROUNDS).astype(np.float64),
        "shuffle": raw("shuffle", "<u4").reshape(steps, 2).astype(np.intp),
    }


def _kld_quantiles() -> list[float]:
    """z_{1-δ} of every value of the δ slider, k times its step for k = 1 .. 200 (the page's
    snapped values, the same product), as :func:`probrob.mcl.kld_sample_size` computes it."""
    from ..mcl import _kld_constants

    count = round(PF_DELTA_MAX / PF_DELTA_STEP)
    return [_kld_constants(1.0, k * PF_DELTA_STEP)[1] for k in range(1, count + 1)]


def _data(u, z, truth, angles, params, draws) -> dict[str, str]:
    """The embedded log and random numbers, each as base64 of the type the page decodes."""
    return {
        "odometry": b64(u),
        "scans": b64(_ranges(z, params.max_range), "<u2"),
        "truth": b64(truth),
        "beamAngles": b64(angles),
        "normal": b64(draws["normal"], "<f4"),
        "offsets": b64(draws["offsets"], "<u4"),
        "resample": b64(draws["resample"]),
        "uniforms": b64(draws["uniforms"], "<f4"),
        "rounds": b64(draws["rounds"], "<f4"),
        "shuffle": b64(draws["shuffle"], "<u4"),
    }
