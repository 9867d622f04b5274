r"""Benchmark the range finder models of :mod:`probrob.sensors` against per-beam Python loops.

What is measured
----------------
A synthetic office map of 400 x 400 cells at 5 cm (20 m x 20 m: outer walls 15 cm thick,
a corridor, eight rooms with 1 m doors, desks and pillars), 1,000 particles drawn
uniformly in its free space with uniform headings, and one scan of 180 beams (1° apart
over 180°, the Intel Lab's SICK layout) with ``max_range = 20`` m, sampled from the beam
model at a "true" pose. Workloads, each on the 1,000 x 180 = 180,000 rays:

1. ``ray_cast`` with each method: ``"hybrid"`` (default; exact), ``"dda"`` (plain
   Amanatides–Woo, exact) and ``"march"`` (range_libc-style ray marching, approximate);
2. ``beam_range_finder_model(..., log=True)`` (Table 6.1): ray casting plus the mixture;
3. ``likelihood_field_range_finder_model(..., log=True)`` (Table 6.3), with its
   log-likelihood table already built (it is built once per map and parameter set;
   its build time is reported separately).

The naive loops run, in the same process, over the first particles of the same set
and are scaled linearly to 1,000 particles: for the beam model, per particle and per
beam a scalar Amanatides–Woo traversal and the four components written out with
:mod:`math` (the slides' Table 6.1, line by line); for the likelihood field, per beam
the end point, its cell and the distance looked up in the same distance field, and
the factor of Table 6.3 with :mod:`math`. Both loops must agree with the library to a
relative 1e-9 on the subset (a failed check exits with status 2).

Ray-casting error: every method's ranges are compared with ``"dda"`` (the exact
traversal, itself checked against the tests' scalar reference in
``tests/test_maps.py``) on all 180,000 rays, in cells (5 cm). The exact default is also
compared, to the last bit, with a scalar Python traversal that performs the library's
operations in the library's order (``scalar_exact``) on the first particles' rays, and
timed against it.

Compilation: ray casting is compiled by numba on its first call and cached on disk. Two
fresh processes with an empty cache directory (``NUMBA_CACHE_DIR``) time the import and
the first call of each method: the first compiles, the second loads the cache.

Timing: :func:`time.perf_counter`, one warm-up, minimum of 5 repeats (numpy) or 1
(loops), the garbage collector paused. The machine is shared: minima are the stable
statistic.

Targets (from the issues; reported, not asserted unless ``--check``): exact ray casting
(the default) >= 8e6 rays/s single-threaded, about range_libc's compiled ray marching on
this machine class, with its ranges equal to the scalar reference; beam model with ray
casting >= 2e6 rays/s with p99 range error <= 1 cell against the exact traversal;
likelihood field >= 2e7 beams/s.

How to run: ``make bench``, or ``python benchmarks/bench_sensors.py [--quick] [--check]``.
"""

from __future__ import annotations

import argparse
import gc
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

from probrob.maps import OccupancyGrid, ray_cast
from probrob.sensors import (
    BeamModelParams,
    beam_range_finder_model,
    likelihood_field_range_finder_model,
    likelihood_field_table,
    sample_beam_mixture,
)

RES = 0.05
N_CELLS = 400
N_PARTICLES = 1000
ANGLES = np.deg2rad(np.arange(-90, 90) + 0.0)
PARAMS = BeamModelParams(0.8, 0.05, 0.05, 0.1, 0.05, 0.5, 20.0)
RAYS_TARGET = 2e6
EXACT_TARGET = 8e6
LF_TARGET = 2e7


def office_map(n=N_CELLS, res=RES, seed=0):
    """A 20 m x 20 m office: outer walls, a corridor, rooms with doors, furniture."""
    rng = np.random.default_rng(seed)
    occ = np.zeros((n, n), bool)
    t = 3  # wall thickness in cells
    occ[:t, :] = occ[-t:, :] = occ[:, :t] = occ[:, -t:] = True
    c0, c1 = int(9.2 / res), int(10.8 / res)  # the corridor
    occ[c0 - t : c0, :] = True
    occ[c1 : c1 + t, :] = True
    for k in range(1, 4):
        x = k * n // 4
        occ[:c0, x - 1 : x + 2] = True
        occ[c1:, x - 1 : x + 2] = True
    for k in range(4):
        x = k * n // 4 + n // 8
        occ[c0 - t : c0, x - 10 : x + 10] = False  # doors, 1 m
        occ[c1 : c1 + t, x - 10 : x + 10] = False
    yy, xx = np.mgrid[:n, :n]
    for _ in range(30):  # desks and pillars
        cx, cy = rng.integers(10, n - 10, 2)
        if c0 - 25 < cy < c1 + 25:
            continue
        if rng.random() < 0.5:
            w, h = rng.integers(8, 30, 2)
            occ[cy : cy + h, cx : cx + w] = True
        else:
            occ[(xx - cx) ** 2 + (yy - cy) ** 2 < rng.integers(4, 40)] = True
    return OccupancyGrid(occ, res)


def free_poses(grid, n, rng):
    free = np.argwhere(~grid.occupied)
    cells = free[rng.choice(len(free), n)]
    xy = grid.cell_to_world(cells) + rng.uniform(-0.49, 0.49, (n, 2)) * grid.resolution
    return np.c_[xy, rng.uniform(-np.pi, np.pi, n)]


# --------------------------------------------------------------------------- naive loops
def naive_ray_cast(occ, res, origin, x, y, heading, max_range):
    """Amanatides–Woo for one ray, scalar Python."""
    h, w = len(occ), len(occ[0])
    gx, gy = (x - origin[0]) / res, (y - origin[1]) / res
    dx, dy = math.cos(heading), math.sin(heading)
    j, i = math.floor(gx), math.floor(gy)
    t_max = max_range / res
    t = 0.0
    while True:
        if not (0 <= i < h and 0 <= j < w) or t >= t_max:
            return max_range
        if occ[i][j]:
            return t * res
        tx = (j + (dx > 0) - gx) / dx if dx != 0 else math.inf
        ty = (i + (dy > 0) - gy) / dy if dy != 0 else math.inf
        if tx <= ty:
            t, j = tx, j + (1 if dx > 0 else -1)
        else:
            t, i = ty, i + (1 if dy > 0 else -1)


def scalar_exact(grid, poses, angles, max_range):
    """The exact default's ranges from a scalar Python traversal: the plain Amanatides–Woo
    walk with the library's operations in its order (directions from numpy's cos and sin
    of the same arrays, crossings as ``(j + c) * (1 / d)``), so the floats must be equal."""
    occ, res = grid.occupied, grid.resolution
    h, w = occ.shape
    t_max = max_range / res
    ct, st, ca, sa = np.cos(poses[:, 2]), np.sin(poses[:, 2]), np.cos(angles), np.sin(angles)
    out = np.empty((len(poses), len(angles)))
    for p, (x, y, _) in enumerate(poses):
        x0, y0 = (x - grid.origin[0]) / res, (y - grid.origin[1]) / res
        for k in range(len(angles)):
            dx = ct[p] * ca[k] - st[p] * sa[k]
            dy = st[p] * ca[k] + ct[p] * sa[k]
            j, i = math.floor(x0), math.floor(y0)
            inv_x, c_x = (1.0 / dx, float(dx > 0) - x0) if dx != 0 else (1.0, math.inf)
            inv_y, c_y = (1.0 / dy, float(dy > 0) - y0) if dy != 0 else (1.0, math.inf)
            t = 0.0
            while not occ[i, j]:
                tx, ty = (j + c_x) * inv_x, (i + c_y) * inv_y
                if tx <= ty:
                    t, j = tx, j + (1 if dx > 0 else -1)
                else:
                    t, i = ty, i + (1 if dy > 0 else -1)
                if t >= t_max or not (0 <= i < h and 0 <= j < w):
                    t = t_max
                    break
            out[p, k] = min(t * res, max_range)
    return out


def compile_times():
    """Seconds to import probrob.maps and cast one ray by each method, in a fresh process
    with an empty numba cache, then in a second one that finds the cache."""
    script = (
        "import time; t0 = time.perf_counter(); import numpy as np; from probrob import maps; "
        "t1 = time.perf_counter(); g = maps.OccupancyGrid(np.eye(3, dtype=bool), 1.0); "
        "[maps.ray_cast(g, [1.5, 0.5, 0.0], [0.0], 2.0, method=m) "
        "for m in ('hybrid', 'dda', 'march')]; print(t1 - t0, time.perf_counter() - t1)"
    )
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        runs = [
            subprocess.run(
                [sys.executable, "-c", script], env=env, capture_output=True, text=True, check=True
            )
            for _ in range(2)
        ]
    return [tuple(float(v) for v in r.stdout.split()) for r in runs]


def naive_beam(z, z_star, p):
    """Table 6.1, line 5, for one beam, with the book's normalisers."""
    zmax, s, lam = p.max_range, p.sigma_hit, p.lambda_short
    z = min(z, zmax)
    phi = lambda u: 0.5 * math.erfc(-u / math.sqrt(2.0))  # noqa: E731
    hit = math.exp(-0.5 * ((z - z_star) / s) ** 2) / (s * math.sqrt(2 * math.pi))
    hit /= phi((zmax - z_star) / s) - phi(-z_star / s)
    short = lam * math.exp(-lam * z) / (1 - math.exp(-lam * z_star)) if z <= z_star else 0.0
    mx = 1.0 if z >= zmax else 0.0
    rnd = 1.0 / zmax if z < zmax else 0.0
    return p.z_hit * hit + p.z_short * short + p.z_max * mx + p.z_rand * rnd


def naive_beam_model(z, poses, grid, angles, p):
    occ = grid.occupied.tolist()
    out = []
    for x, y, th in poses:
        q = 0.0
        for zk, a in zip(z, angles, strict=True):
            z_star = naive_ray_cast(occ, grid.resolution, grid.origin, x, y, th + a, p.max_range)
            q += math.log(naive_beam(zk, z_star, p))
        out.append(q)
    return np.array(out)


def naive_likelihood_field(z, poses, grid, angles, p):
    dist = grid.distance_field
    h, w = grid.shape
    ox, oy = grid.origin
    out = []
    for x, y, th in poses:
        q = 0.0
        for zk, a in zip(z, angles, strict=True):
            if zk >= p.max_range:
                continue
            xz = x + zk * math.cos(th + a)
            yz = y + zk * math.sin(th + a)
            j, i = math.floor((xz - ox) / grid.resolution), math.floor((yz - oy) / grid.resolution)
            if 0 <= i < h and 0 <= j < w:
                d = dist[i, j]
                hit = math.exp(-0.5 * (d / p.sigma_hit) ** 2) / (
                    p.sigma_hit * math.sqrt(2 * math.pi)
                )
            else:
                hit = 0.0
            q += math.log(p.z_hit * hit + p.z_rand / p.max_range)
        out.append(q)
    return np.array(out)


# --------------------------------------------------------------------------- timing
def best_time(fn, repeats, warmup=True):
    if warmup:
        fn()
    best = math.inf
    gc.disable()
    try:
        for _ in range(repeats):
            t0 = time.perf_counter()
            out = fn()
            best = min(best, time.perf_counter() - t0)
    finally:
        gc.enable()
    return best, out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer particles and loop items")
    ap.add_argument("--check", action="store_true", help="exit 1 if a target is missed")
    args = ap.parse_args(argv)
    n = 100 if args.quick else N_PARTICLES
    n_loop_beam = 3 if args.quick else 10
    n_loop_lf = 20 if args.quick else 100
    rng = np.random.default_rng(0)
    grid = office_map()
    poses = free_poses(grid, n, rng)
    truth = free_poses(grid, 1, rng)[0]
    z = sample_beam_mixture(ray_cast(grid, truth, ANGLES, PARAMS.max_range), PARAMS, rng=rng)
    rays = n * ANGLES.size
    print(
        f"map {grid.shape[0]}x{grid.shape[1]} cells at {RES} m, {n} particles x {ANGLES.size} beams"
    )

    t_field, _ = best_time(lambda: OccupancyGrid(grid.occupied, RES).distance_field, 3)
    ranges, times = {}, {}
    for method in ("hybrid", "dda", "march"):
        times[method], ranges[method] = best_time(
            lambda m=method: ray_cast(grid, poses, ANGLES, PARAMS.max_range, method=m), 5
        )
    t_beam, lp_beam = best_time(
        lambda: beam_range_finder_model(z, poses, grid, ANGLES, PARAMS, log=True), 5
    )
    t_table, _ = best_time(
        lambda: likelihood_field_table(OccupancyGrid(grid.occupied, RES), PARAMS), 3
    )
    likelihood_field_table(grid, PARAMS)
    t_lf, lp_lf = best_time(
        lambda: likelihood_field_range_finder_model(z, poses, grid, ANGLES, PARAMS, log=True), 5
    )
    n_scalar = 3 if args.quick else 20
    t_scalar, scalar_ranges = best_time(
        lambda: scalar_exact(grid, poses[:n_scalar], ANGLES, PARAMS.max_range), 1, warmup=False
    )
    exact_equal = np.array_equal(scalar_ranges, ranges["hybrid"][:n_scalar])
    (import_cold, first_cold), (import_warm, first_warm) = compile_times()
    t_naive_beam, naive_b = best_time(
        lambda: naive_beam_model(z, poses[:n_loop_beam], grid, ANGLES, PARAMS), 1, warmup=False
    )
    t_naive_lf, naive_l = best_time(
        lambda: naive_likelihood_field(z, poses[:n_loop_lf], grid, ANGLES, PARAMS), 1, warmup=False
    )
    ok = np.allclose(naive_b, lp_beam[:n_loop_beam], rtol=1e-9) and np.allclose(
        naive_l, lp_lf[:n_loop_lf], rtol=1e-9
    )
    t_naive_beam *= n / n_loop_beam
    t_naive_lf *= n / n_loop_lf

    print(
        f"\ndistance field (scipy EDT): {t_field * 1e3:.1f} ms; likelihood table: {t_table * 1e3:.1f} ms"
    )
    print("\nray casting, error against the exact traversal (dda), in cells of 5 cm:")
    print(f"{'method':8} {'time':>9} {'rays/s':>10} {'p50':>8} {'p99':>8} {'max':>8}")
    for method in ("hybrid", "dda", "march"):
        err = np.abs(ranges[method] - ranges["dda"]) / RES
        p50, p99 = np.percentile(err, [50, 99])
        print(
            f"{method:8} {times[method] * 1e3:7.1f}ms {rays / times[method]:10.3g} "
            f"{p50:8.2g} {p99:8.2g} {err.max():8.3g}"
        )
    rate_exact = rays / times["hybrid"]
    rate_scalar = n_scalar * ANGLES.size / t_scalar
    print(
        f"\nexact default against the scalar traversal on {n_scalar * ANGLES.size} rays: "
        f"ranges {'equal to the last bit' if exact_equal else 'DIFFERENT'}; "
        f"{rate_scalar:.3g} rays/s scalar, {rate_exact / rate_scalar:.0f}x faster compiled"
    )
    print(
        f"numba: import + first call of the three methods {import_cold:.2f} + {first_cold:.2f} s "
        f"compiling (empty cache), {import_warm:.2f} + {first_warm:.2f} s from the cache"
    )
    err_default = np.abs(ranges["hybrid"] - ranges["dda"]) / RES
    p99_default = float(np.percentile(err_default, 99))
    rate_beam = rays / t_beam
    rate_lf = rays / t_lf
    print(f"\n{'workload':40} {'naive loop':>11} {'numpy':>9} {'ratio':>7} {'rays/s':>9}")
    print(
        f"{'beam model (Table 6.1, log=True)':40} {t_naive_beam:10.2f}s {t_beam * 1e3:7.1f}ms "
        f"{t_naive_beam / t_beam:6.0f}x {rate_beam:9.3g}"
    )
    print(
        f"{'likelihood field (Table 6.3, log=True)':40} {t_naive_lf:10.2f}s {t_lf * 1e3:7.1f}ms "
        f"{t_naive_lf / t_lf:6.0f}x {rate_lf:9.3g}"
    )
    print(f"(naive loops on {n_loop_beam} and {n_loop_lf} particles, scaled to {n})")
    targets = {
        "exact ray casting >= 8e6 rays/s, equal to the scalar reference": rate_exact
        >= EXACT_TARGET
        and exact_equal,
        "beam model >= 2e6 rays/s": rate_beam >= RAYS_TARGET,
        "beam model ray error p99 <= 1 cell": p99_default <= 1.0,
        "likelihood field >= 2e7 beams/s": rate_lf >= LF_TARGET,
    }
    print()
    for name, met in targets.items():
        print(f"target {name}: {'met' if met else 'MISSED'}")
    if not ok:
        print("AGREEMENT CHECK FAILED: the naive loops and the library differ", file=sys.stderr)
        return 2
    print("agreement: naive loops equal the library to 1e-9 (relative)")
    if args.check and not all(targets.values()):
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
