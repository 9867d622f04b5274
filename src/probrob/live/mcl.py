r"""Live widget of chapter 8: Monte Carlo localization (Tables 8.2-8.4) over a stretch of a laser log.

Holds :func:`particle_filter_live` (kernel ``assets/mcl_filter.js``, the filters, and
``assets/mcl.js``, which draws its own picture: the map, the particles, the reference and the
estimate, the particle count over the steps, with step, play and kidnap buttons; the beam
model's exact ray casting is ``assets/beam_model.js``): its controls and the checks of its
arguments. Re-exports what :mod:`probrob.live.mcl_data` holds: the random numbers it embeds
(:func:`particle_filter_draws`), its choice of beams (:func:`particle_filter_beams`), where its
kidnap button moves the particles (:func:`particle_filter_kidnap_target`) and
:func:`particle_filter_decoded` (what the page decodes, for feeding :mod:`probrob.mcl` the
same numbers). Does not hold the filters (:mod:`probrob.mcl`, which the kernel mirrors and
``tests/test_live_mcl.py`` holds it to, step by step).
"""

from __future__ import annotations

import numpy as np

from .. import _validation as check
from .core import Choice, LiveWidget, Slider, alpha_sliders, render, spec
from .mcl_data import (
    PF_DELTA_MAX,
    PF_DELTA_STEP,
    PF_HEADING_BINS,
    PF_KLD_BINS,
    PF_KLD_N_MIN,
    PF_MAX_CELLS,
    PF_MAX_STEPS,
    PF_RADIUS,
    PF_ROUNDS,
    _cells,
    _data,
    _kld_quantiles,
    particle_filter_beams,
    particle_filter_decoded,
    particle_filter_draws,
    particle_filter_kidnap_target,
)

__all__ = [
    "PF_HEADING_BINS",
    "PF_RADIUS",
    "particle_filter_beams",
    "particle_filter_decoded",
    "particle_filter_draws",
    "particle_filter_kidnap_target",
    "particle_filter_live",
]


def _snap(value, name, lo, hi, step):
    """A start value checked against its slider's range and rounded to the slider's step."""
    value = check.in_range(value, name, lo, hi)
    return float(min(hi, max(lo, round(round((value - lo) / step) * step + lo, 10))))


def _check_log(odometry, scans, beam_angles):
    """The log's arrays checked against each other: u (T, 2, 3), z (T, K), the angles (K,)."""
    u = check.finite(odometry, "odometry")
    if u.ndim != 3 or u.shape[1:] != (2, 3) or not 1 <= u.shape[0] <= PF_MAX_STEPS:
        raise ValueError(f"odometry must have shape (T, 2, 3) with 1 <= T <= 300, got {u.shape}")
    steps = u.shape[0]
    angles = check.finite(beam_angles, "beam_angles")
    if angles.ndim != 1 or angles.size == 0:
        raise ValueError(f"beam_angles must have shape (K,) with K >= 1, got {angles.shape}")
    z = check.finite(scans, "scans")
    if z.shape != (steps, angles.size):
        raise ValueError(
            f"scans must have shape (T, K) = {(steps, angles.size)} (odometry's T, "
            f"beam_angles' K), got {z.shape}"
        )
    if np.any(z < 0):
        raise ValueError(f"scans must be non-negative ranges, got min {z.min()!r}")
    return u, z, angles


def _check_model(grid, alpha, params):
    """The map and the models' start values checked: (grid, alpha)."""
    from ..maps import _check_grid
    from ..sensors import BeamModelParams

    grid = _check_grid(grid)
    if grid.occupied.size > PF_MAX_CELLS:
        raise ValueError(f"grid must have at most 400,000 cells, got {grid.occupied.size:,}")
    if not grid.occupied.any() or not grid.free.any():
        raise ValueError("grid must have an occupied cell and a free cell")
    alpha = alpha_sliders(alpha, 4)  # checked as the sliders' start values
    if not isinstance(params, BeamModelParams):
        raise ValueError(f"params must be a BeamModelParams, got {type(params).__name__}")
    if params.z_hit + params.z_rand <= 0:
        raise ValueError("params must have z_hit + z_rand > 0 (the likelihood field's weights)")
    if params.max_range < 1.0:
        raise ValueError(
            f"params.max_range must be at least 1 m (the σ_hit slider's end), got "
            f"{params.max_range!r}"
        )
    return grid, [s.value for s in alpha]


def _controls(steps, n_beams, alpha, params, start, view, n_particles, n_max, beams, exponent,
              step, sensor, method, recovery, kld, kidnap):  # fmt: skip
    """The sliders and choices of the filter, their start values checked and snapped."""
    check.choice(start, "start", ("known", "global"))
    check.choice(view, "view", ("map", "robot"))
    check.choice(sensor, "sensor", ("likelihood_field", "beam"))
    check.choice(method, "method", ("mcl", "augmented", "kld"))
    alpha_slow, alpha_fast = recovery
    epsilon, delta = kld
    from ..mcl import _kld_constants

    _kld_constants(epsilon, delta)  # epsilon > 0, delta in (0, 1/2), or a ValueError naming it
    kidnap = check.count(kidnap, "kidnap", 0)
    if kidnap > steps:
        raise ValueError(f"kidnap must lie in [0, T = {steps}] (0: never), got {kidnap}")
    n_max = check.count(n_max, "n_max", 100)
    if n_max > 5000 or n_max % 100:
        raise ValueError(f"n_max must be a multiple of 100 in [100, 5000], got {n_max}")
    n_particles = check.count(n_particles, "n_particles", 1)
    if not 100 <= n_particles <= n_max:
        raise ValueError(f"n_particles must lie in [100, n_max = {n_max}], got {n_particles}")
    beams = check.count(beams, "beams", 1)
    if beams > n_beams:
        raise ValueError(f"beams must be at most the {n_beams} beams of a scan, got {beams}")
    step = check.count(step, "step", 0)
    if step > steps:
        raise ValueError(f"step must lie in [0, T = {steps}], got {step}")
    share = params.z_rand / (params.z_hit + params.z_rand)
    sigma = _snap(params.sigma_hit, "params.sigma_hit", 0.01, 1.0, 0.001)
    sliders = [
        Slider("t", "step t", float(step), 0.0, float(steps), 1.0, snap=True),
        *(
            Slider(f"a{k + 1}", f"α{k + 1}", _snap(a, f"alpha[{k}]", 0, 0.5, 1e-4), 0.0, 0.5, 1e-4)
            for k, a in enumerate(alpha)
        ),
        Slider("sigma", "σ_hit [m]", sigma, 0.01, 1.0, 0.001),
        Slider("zrand", "z_rand share", _snap(share, "z_rand share", 0, 1, 0.001), 0.0, 1.0, 0.001),
        Slider("beams", "beams", float(beams), 1.0, float(n_beams), 1.0, snap=True),
        Slider("kappa", "exponent", _snap(exponent, "exponent", 0.01, 1, 0.01), 0.01, 1.0, 0.01),
        Slider(
            "n", "particles", _snap(n_particles, "n_particles", 100, n_max, 100), 100.0,
            float(n_max), 100.0, snap=True,
        ),
        Slider("aslow", "α_slow", _snap(alpha_slow, "alpha_slow", 0, 0.04, 1e-4), 0.0, 0.04, 1e-4),
        Slider(
            "afast", "α_fast", _snap(alpha_fast, "alpha_fast", 0.05, 1, 1e-3), 0.05, 1.0, 1e-3
        ),
        Slider("eps", "ε (KLD)", _snap(epsilon, "epsilon", 0.01, 0.5, 0.005), 0.01, 0.5, 0.005),
        Slider(
            "delta", "δ (KLD)", _snap(delta, "delta", PF_DELTA_STEP, PF_DELTA_MAX, PF_DELTA_STEP),
            PF_DELTA_STEP, PF_DELTA_MAX, PF_DELTA_STEP, snap=True,
        ),
        Slider("kidnap", "kidnap after", float(kidnap), 0.0, float(steps), 1.0, snap=True),
    ]  # fmt: skip
    choices = [
        Choice("start", "start", (("known", "known pose"), ("global", "uniform (global)")), start),
        Choice("view", "view", (("map", "whole map"), ("robot", "around the robot")), view),
        Choice(
            "sensor", "sensor",
            (("likelihood_field", "likelihood field"), ("beam", "beam model")),
            sensor,
        ),
        Choice(
            "method", "method",
            (("mcl", "MCL"), ("augmented", "augmented MCL"), ("kld", "KLD-sampling")),
            method,
        ),
    ]  # fmt: skip
    return sliders, choices, n_max


def _caption(steps) -> str:
    return (
        f"One filter step per scan, {steps} scans of the log: every particle moves by the "
        "odometry model (Table 5.6) with the α of the sliders, is weighted by the chosen sensor "
        "model (the likelihood field of Table 6.3, or the beam model of Table 6.1 with its "
        "ranges ray-cast in the page) of the chosen beams, and the set is redrawn by the "
        "low-variance sampler (Table 4.4). MCL is Table 8.2; augmented MCL (Table 8.3) adds "
        "random particles when the fast average of the likelihood w_fast falls below the slow "
        "one w_slow (α_slow, α_fast); KLD-sampling (Table 8.4) draws as many particles as the "
        "bound of ε and δ asks for the bins they occupy. The kidnap button kidnaps the robot "
        "after the step shown: the particles are moved by the difference between the reference "
        "pose farthest from the robot and the robot's, while the robot and the log go on "
        "(the kidnap slider holds the step; 0: never). {Black|White}: occupied cells; "
        "{white|dark}: free; grey: unexplored. Green: the reference (corrected) path and pose; "
        "blue arrow: the estimate (the heaviest cluster, "
        f"{PF_RADIUS} m cells and {360 // PF_HEADING_BINS}° of heading). Below: the particles "
        "per step (and augmented MCL's random ones). Moving a slider re-runs the filter from "
        "the start on the same random numbers. Step, play or drag the step slider."
    )


def particle_filter_live(
    odometry,
    scans,
    grid,
    beam_angles,
    alpha,
    params,
    truth,
    *,
    start="known",
    spread=(0.1, 0.1, 0.05),
    n_particles=500,
    n_max=2000,
    beams=60,
    exponent=1.0,
    step=0,
    view="map",
    sensor="likelihood_field",
    method="mcl",
    alpha_slow=0.001,
    alpha_fast=0.1,
    epsilon=0.05,
    delta=0.01,
    kidnap=0,
    rng=0,
    title="Monte Carlo localization (Tables 8.2-8.4)",
    width=600,
    height=700,
) -> LiveWidget:
    r"""Return a live particle filter: MCL, augmented MCL or KLD-sampling over a stretch of a laser log, in the page.

    The reader moves :math:`\alpha_1 \ldots \alpha_4` (the odometry model, Table 5.6),
    :math:`\sigma_{hit}`, the share :math:`z_{rand} / (z_{hit} + z_{rand})` (their sum held at
    ``params``'s), the number of beams (spread evenly by :func:`particle_filter_beams`), the
    exponent of the beam product (:func:`probrob.mcl.measurement_log_weights`) and the number
    of particles, chooses a known or a global start, the sensor model and the filter, and
    steps or plays it. One step is, by the "method" choice,

    * ``"mcl"``: :func:`probrob.mcl.mcl` (Table 8.2), the low-variance sampler (Table 4.4);
    * ``"augmented"``: :func:`probrob.mcl.augmented_mcl` (Table 8.3) with the
      :math:`\alpha_{slow}`, :math:`\alpha_{fast}` sliders, :math:`w_{slow} = w_{fast} = 0`
      at the start; the status text shows both averages, their ratio and the random particles;
    * ``"kld"``: :func:`probrob.mcl.kld_sampling_mcl` (Table 8.4) with the :math:`\varepsilon`,
      :math:`\delta` sliders, the bins ``PF_KLD_BINS``, at least ``PF_KLD_N_MIN`` and at
      most ``n_max`` particles (the particles slider sets the initial set); its weighted sets
      go on to the next step and into the estimate, as :func:`probrob.mcl.run_mcl` passes them;

    with the sensor of the "sensor" choice: the likelihood field (Table 6.3) or the beam model
    (Table 6.1, :func:`probrob.sensors.beam_range_finder_model`, its expected ranges ray-cast in
    the page by the exact traversal of :func:`probrob.maps.ray_cast`; ``params.z_short``,
    ``params.z_max`` and ``params.lambda_short`` fixed). The kidnap button kidnaps the robot
    after the step shown (the "kidnap after" slider, 0: never): the particle set of that
    step is moved by ``truth[s] - truth[k]`` (:func:`particle_filter_kidnap_target`), as
    ``run_mcl(on_step=...)`` does in the chapter, and the filter goes on with the log.

    The canvas shows the map, the particles, the corrected pose (``truth``) and
    :func:`probrob.mcl.estimate_pose` with radius ``PF_RADIUS`` and ``PF_HEADING_BINS`` heading
    sectors (weighted, for KLD-sampling), and below it the number of particles per step (and
    augmented MCL's random ones); the text under it the estimate's error. Moving a slider
    re-runs the filter from the start to the step shown, on the same random numbers
    (:func:`particle_filter_draws`).

    The page embeds the map's cells (2 bits each) and computes the exact distance field, the
    likelihood-field table and the ray casting in the browser, so that the JavaScript computes
    what :mod:`probrob.mcl` computes on ``grid``: ``tests/test_live_mcl.py`` holds the two
    equal in Chromium, step by step, for every sensor and method, resampling included.

    Parameters
    ----------
    odometry : array_like, shape (T, 2, 3)
        One odometry pair per step (as :func:`probrob.mcl.run_mcl`), ``1 <= T <= 300``.
    scans : array_like, shape (T, K)
        The scan at the end of each step (m); kept to whole millimetres, and readings
        ``>= params.max_range`` as max-range readings.
    grid : OccupancyGrid
        The map (it must have an occupied and a free cell; at most 400,000 cells).
    beam_angles : array_like, shape (K,)
    alpha : array_like, shape (4,)
        Start values of :math:`\alpha_1 \ldots \alpha_4` (variance form), in [0, 0.5].
    params : BeamModelParams
        ``sigma_hit`` (in [0.01, 1] m), ``z_hit``, ``z_rand`` (their split is a slider),
        ``max_range`` (at least 1 m) and, for the beam model, ``z_short``, ``z_max`` and
        ``lambda_short``.
    truth : array_like, shape (T + 1, 3)
        The reference poses (e.g. the log's corrected poses): the known start is
        ``truth[0]``, the error of step ``t`` is against ``truth[t]``.
    start : {"known", "global"}
        Start value of the start choice: ``truth[0]`` plus ``spread`` times normals, or
        :func:`probrob.mcl.uniform_particles` over ``grid.free``.
    spread : array_like, shape (3,)
        Standard deviations (m, m, rad) of the known start, each >= 0.
    n_particles : int
        Start value of the particles slider, in [100, n_max] (a multiple of 100).
    n_max : int
        Most particles (the slider's end), in [100, 5000], a multiple of 100.
    beams : int
        Start value of the beams slider, in [1, K].
    exponent : float
        Start value of the exponent slider, in [0.01, 1].
    step : int
        The step shown first, in [0, T].
    view : {"map", "robot"}
        The whole map, or a 12 m square around the reference pose.
    sensor : {"likelihood_field", "beam"}
        Start value of the sensor choice.
    method : {"mcl", "augmented", "kld"}
        Start value of the method choice.
    alpha_slow, alpha_fast : float
        Start values of Table 8.3's decay rates, in [0, 0.04] and [0.05, 1] (so that
        :math:`\alpha_{slow} < \alpha_{fast}` anywhere on the sliders).
    epsilon, delta : float
        Start values of Table 8.4's :math:`\varepsilon` in [0.01, 0.5] and :math:`\delta` in
        [0.001, 0.2] (a multiple of 0.001).
    kidnap : int
        Start value of the "kidnap after" slider, in [0, T] (0: no kidnapping).
    rng : None, int or numpy.random.Generator
        Seed of :func:`particle_filter_draws`.
    title : str
    width, height : int
        The canvas's largest width and its aspect ratio, in CSS pixels.

    Returns
    -------
    widget : LiveWidget
        Start values are rounded to their slider's step.
    """
    u, z, angles = _check_log(odometry, scans, beam_angles)
    grid, alpha = _check_model(grid, alpha, params)
    steps = u.shape[0]
    truth = check.poses(truth, "truth")
    if truth.shape != (steps + 1, 3):
        raise ValueError(f"truth must have shape (T + 1, 3) = {(steps + 1, 3)}, got {truth.shape}")
    spread = check.finite(spread, "spread")
    if spread.shape != (3,) or np.any(spread < 0):
        raise ValueError(f"spread must be 3 standard deviations >= 0, got {spread.tolist()}")
    sliders, choices, n_max = _controls(
        steps, angles.size, alpha, params, start, view, n_particles, n_max, beams, exponent, step,
        sensor, method, (alpha_slow, alpha_fast), (epsilon, delta), kidnap,
    )  # fmt: skip
    h, w = grid.shape
    config = {
        "kernel": "mcl",
        "width": check.count(width, "width", 1),
        "height": check.count(height, "height", 1),
        "steps": steps,
        "beamsTotal": int(angles.size),
        "nMax": n_max,
        **spec(sliders, choices),
        "buttons": (
            ("step", "step"),
            ("play", "play"),
            ("start", "to start"),
            ("kidnap", "kidnap"),
            ("reset", "reset"),
        ),
        "status": True,
        "constants": {
            "zSum": params.z_hit + params.z_rand,
            "maxRange": params.max_range,
            "radius": PF_RADIUS,
            "headingBins": PF_HEADING_BINS,
            "spread": spread.tolist(),
            "zShort": params.z_short,
            "zMaxWeight": params.z_max,
            "lambdaShort": params.lambda_short,
            "kldBins": list(PF_KLD_BINS),
            "kldMin": PF_KLD_N_MIN,
            "kldRounds": PF_ROUNDS,
            "deltaStep": PF_DELTA_STEP,
            "kldZ": _kld_quantiles(),
        },
        "map": {
            "h": h,
            "w": w,
            "origin": [float(grid.origin[0]), float(grid.origin[1])],
            "resolution": float(grid.resolution),
            "cells": _cells(grid),
        },
        "data": _data(u, z, truth, angles, params, particle_filter_draws(n_max, steps, rng)),
    }
    return render(
        "mcl",
        config,
        title=title,
        caption=_caption(steps),
        aria_label=(
            "Map of the building with the particle cloud of Monte Carlo localization (red dots), "
            "the reference pose (green circle) and the filter's estimate (blue arrow); below it, "
            "the number of particles per step."
        ),
        scripts=(
            "maths.js",
            "likelihood_field.js",
            "beam.js",
            "beam_model.js",
            "mcl_filter.js",
            "mcl.js",
        ),
        budgets={"size-budget": 400_000, "update-budget": 16},
    )
