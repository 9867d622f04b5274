r"""Benchmark one step of Monte Carlo localization (:func:`probrob.mcl.mcl`, Table 8.2).

What is measured
----------------
The Intel Research Lab map built from its corrected scans (10 cm cells), 10,000 particles
around the corrected pose of scan 100, the log's real odometry pair of that step and its next
scan reduced to 60 beams (every third of 180), ``max_range`` 25 m. One step is: the odometry
sampler on every particle (Table 5.6), the scan's log-likelihood at every particle, the
low-variance resampling (Table 4.4). Three implementations of the same step run in the same
process, on the same particles:

1. ``probrob.mcl.mcl``, with the likelihood field (Table 6.3) and with the beam model (Table 6.1,
   whose cost is ray casting: 10,000 x 60 = 600,000 rays a step);
2. a plain numpy transcription of Table 8.2, as a student would write it from the book with
   numpy: the same motion sampler, the likelihood field's end points and table look-up
   written inline, weights as a plain product of per-beam likelihoods (no logs), and
   ``rng.choice(p=w)`` (multinomial) for lines 8–11;
3. a per-particle Python loop: Table 8.2's ``for m = 1 to M`` with each model called on one
   particle (``sample_motion_model_odometry`` and
   ``likelihood_field_range_finder_model`` of one pose), run on the first 500 particles and
   scaled linearly to 10,000.

The transcription's weights must equal the library's to a relative 1e-9 (checked; exit status 2
otherwise), so the comparison is of the same arithmetic.

Timing: :func:`time.perf_counter`, one warm-up, the minimum of 7 repeats (numpy) or 1 (loop),
the garbage collector paused. The machine is shared: minima are the stable statistic.

Targets (reported; asserted with ``--check``): the likelihood-field step well under 20 ms, and
no slower than the numpy transcription (the issue on Monte Carlo localization); the
beam-model step, ray casting and the mixture included, within 100 ms (the issue on compiled
ray casting: range_libc-class speed).

How to run: ``make bench``, or ``python benchmarks/bench_mcl.py [--quick] [--check]``.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np
from _timing import best

from probrob.datasets import load_intel_lab
from probrob.maps import OccupancyGrid
from probrob.mcl import low_variance_sampler, mcl, measurement_log_weights
from probrob.motion import sample_motion_model_odometry
from probrob.sensors import (
    BeamModelParams,
    likelihood_field_range_finder_model,
    likelihood_field_table,
)

N = 10_000
N_LOOP = 500
STEP = 100
ALPHA = [0.05, 0.01, 0.05, 0.01]
PARAMS = BeamModelParams(0.8, 0.0, 0.05, 0.15, 0.1, 1.0, 25.0)
TARGET_MS = 20.0
BEAM_TARGET_MS = 100.0


def transcription(particles, u, z, grid, angles, rng):
    """Table 8.2 in plain numpy: product of likelihoods, multinomial draw."""
    x_bar = sample_motion_model_odometry(u, particles, ALPHA, rng=rng)  # line 4
    table = np.exp(likelihood_field_table(grid, PARAMS))  # p per cell, padded
    th = x_bar[:, 2:3] + angles
    ex = (x_bar[:, 0:1] + z * np.cos(th) - grid.origin[0]) / grid.resolution
    ey = (x_bar[:, 1:2] + z * np.sin(th) - grid.origin[1]) / grid.resolution
    h, w = grid.shape
    j = np.floor(np.clip(ex, -1, w)).astype(int) + 1
    i = np.floor(np.clip(ey, -1, h)).astype(int) + 1
    p = np.where(z < PARAMS.max_range, table[i, j], 1.0)
    weights = np.prod(p, axis=1)  # line 5: q = product over beams
    inside = grid.contains(x_bar[:, :2])
    weights = np.where(inside, weights, 0.0)
    idx = rng.choice(len(x_bar), size=len(x_bar), p=weights / weights.sum())  # lines 8-11
    return x_bar[idx], weights


def loop(particles, u, z, grid, angles, rng):
    """Table 8.2 one particle at a time."""
    x_bar = np.empty_like(particles)
    weights = np.empty(len(particles))
    for m in range(len(particles)):
        x_bar[m] = sample_motion_model_odometry(u, particles[m], ALPHA, rng=rng)
        if grid.contains(x_bar[m, :2]):
            weights[m] = likelihood_field_range_finder_model(z, x_bar[m], grid, angles, PARAMS)
        else:
            weights[m] = 0.0
    idx = low_variance_sampler(weights, rng=rng)
    return x_bar[idx]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats")
    ap.add_argument("--check", action="store_true", help="exit 1 if a target is missed")
    args = ap.parse_args(argv)
    repeats = 2 if args.quick else 7

    data = load_intel_lab()
    grid = OccupancyGrid.from_scans(
        data.poses, data.ranges, data.beam_angles, 0.1, max_range=data.max_range
    )
    sel = np.arange(0, 180, 3)
    angles = data.beam_angles[sel]
    z = np.minimum(data.ranges[STEP + 1, sel], PARAMS.max_range)
    u = data.odometry[STEP]
    rng = np.random.default_rng(0)
    particles = data.poses[STEP] + rng.normal(0.0, [0.3, 0.3, 0.1], (N, 3))

    # the transcription computes the library's weights (same motion draws: same seed)
    x_bar = sample_motion_model_odometry(u, particles, ALPHA, rng=np.random.default_rng(1))
    _, w_plain = transcription(particles, u, z, grid, angles, np.random.default_rng(1))
    log_w = measurement_log_weights(x_bar, z, grid, angles, PARAMS)
    ok = np.isfinite(log_w)
    rel = np.abs(np.log(w_plain[ok]) - log_w[ok]) / np.maximum(1.0, np.abs(log_w[ok]))
    if rel.max() > 1e-9 or np.any(w_plain[~ok] != 0):
        print(f"transcription disagrees with probrob: max relative error {rel.max():.2e}")
        return 2

    t_lf = best(lambda: mcl(particles, u, z, grid, angles, ALPHA, PARAMS, rng=rng), repeats)
    t_beam = best(
        lambda: mcl(particles, u, z, grid, angles, ALPHA, PARAMS, sensor="beam", rng=rng),
        max(2, repeats // 2),
    )
    t_plain = best(lambda: transcription(particles, u, z, grid, angles, rng), repeats)
    sub = particles[:N_LOOP]
    t_loop = best(lambda: loop(sub, u, z, grid, angles, rng), 1) * N / N_LOOP

    rays = N * len(sel)
    print(f"MCL step, Intel lab map {grid.shape[0]}x{grid.shape[1]} at 0.1 m, {N:,} particles, "
          f"{len(sel)} beams")  # fmt: skip
    print(f"  probrob mcl, likelihood field : {t_lf * 1e3:8.2f} ms")
    print(f"  numpy transcription (Table 8.2): {t_plain * 1e3:8.2f} ms  "
          f"probrob is {t_plain / t_lf:5.2f}x its speed")  # fmt: skip
    print(f"  per-particle loop (scaled)     : {t_loop * 1e3:8.0f} ms  "
          f"probrob is {t_loop / t_lf:5.0f}x its speed")  # fmt: skip
    print(f"  probrob mcl, beam model        : {t_beam * 1e3:8.2f} ms  "
          f"({rays / t_beam:.3g} rays/s including the mixture and resampling)")  # fmt: skip
    failed = []
    if t_lf * 1e3 >= TARGET_MS:
        failed.append(f"likelihood-field step {t_lf * 1e3:.1f} ms >= {TARGET_MS} ms")
    if t_lf > t_plain:
        failed.append("slower than the numpy transcription")
    if t_beam * 1e3 > BEAM_TARGET_MS:
        failed.append(f"beam-model step {t_beam * 1e3:.1f} ms > {BEAM_TARGET_MS} ms")
    for f in failed:
        print("  MISSED:", f)
    return 1 if (args.check and failed) else 0


if __name__ == "__main__":
    sys.exit(main())
