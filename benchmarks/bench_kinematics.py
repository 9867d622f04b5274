"""Speed of probrob.kinematics against per-item Python loops, measured in one run.

Workloads (one million items each):

* ``dead_reckon``: one trajectory of 1e6 odometry steps (a 2.8-hour log at 100 Hz) chained
  with exact arcs; the loop chains them one step at a time, as a student script would;
* ``arc_update``: 1e6 particles moved along their own arcs;
* ``cir_state_function``: 1e6 particles through the CIR report's f (deck 003), whose library
  version multiplies three 3x3 matrices per particle, as printed; the loop evaluates the
  report's closed form.

The loops run on a subset and are scaled to 1e6; before timing, the script checks that loops
and library agree to 1e-9. Run: ``make bench`` or ``python benchmarks/bench_kinematics.py``.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from probrob.kinematics import arc_update, cir_state_function, dead_reckon

N = 1_000_000
WHEELS = 0.4


def best_of(fn, repeats):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def loop_dead_reckon(x0, ds, dth):
    x, y, th = x0
    out = [(x, y, th)]
    for s, d in zip(ds.tolist(), dth.tolist(), strict=True):
        if d == 0.0:
            x += s * math.cos(th)
            y += s * math.sin(th)
        else:
            r = s / d
            x += r * (math.sin(th + d) - math.sin(th))
            y += r * (math.cos(th) - math.cos(th + d))
        th += d
        out.append((x, y, th))
    return out


def loop_arc_update(poses, ds, dth):
    out = []
    for (x, y, th), s, d in zip(poses.tolist(), ds.tolist(), dth.tolist(), strict=True):
        if d == 0.0:
            out.append((x + s * math.cos(th), y + s * math.sin(th), th))
        else:
            r = s / d
            out.append(
                (
                    x + r * (math.sin(th + d) - math.sin(th)),
                    y + r * (math.cos(th) - math.cos(th + d)),
                    th + d,
                )
            )
    return out


def loop_cir(poses, u, ell):
    out = []
    for (x, y, th), (s_sx, s_dx) in zip(poses.tolist(), u.tolist(), strict=True):
        alpha = (s_sx - s_dx) / ell
        if s_sx == s_dx:
            out.append((x + s_sx * math.cos(th), y - s_sx * math.sin(th), th + alpha))
            continue
        h = ell / 2 + ell * s_dx / (s_sx - s_dx)
        out.append(
            (
                x - math.sin(th) * (h - math.cos(alpha) * h) + math.cos(th) * math.sin(alpha) * h,
                y - math.cos(th) * (h - math.cos(alpha) * h) - math.sin(alpha) * math.sin(th) * h,
                th + alpha,
            )
        )
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-loop", type=int, default=50_000, help="items in each loop run")
    parser.add_argument("--repeats", type=int, default=5, help="repeats of the numpy runs")
    parser.add_argument("--loop-repeats", type=int, default=3, help="repeats of the loops")
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    m = args.n_loop
    scale = N / m

    ds = rng.uniform(0.0, 0.02, N)
    dth = rng.uniform(-0.02, 0.02, N)
    poses = rng.uniform([-5, -5, -np.pi], [5, 5, np.pi], (N, 3))
    u = rng.uniform(-0.1, 0.1, (N, 2))
    x0 = np.array([0.0, 0.0, 0.0])

    # agreement first (on the loop's subset)
    np.testing.assert_allclose(
        dead_reckon(x0, ds[:m], dth[:m]), loop_dead_reckon(x0, ds[:m], dth[:m]), atol=1e-9
    )
    np.testing.assert_allclose(
        arc_update(poses[:m], ds[:m], dth[:m]),
        loop_arc_update(poses[:m], ds[:m], dth[:m]),
        atol=1e-9,
    )
    np.testing.assert_allclose(
        cir_state_function(poses[:m], u[:m], WHEELS), loop_cir(poses[:m], u[:m], WHEELS), atol=1e-9
    )

    rows = [
        (
            "dead_reckon, 1e6 chained steps",
            lambda: loop_dead_reckon(x0, ds[:m], dth[:m]),
            lambda: dead_reckon(x0, ds, dth),
        ),
        (
            "arc_update, 1e6 particles",
            lambda: loop_arc_update(poses[:m], ds[:m], dth[:m]),
            lambda: arc_update(poses, ds, dth),
        ),
        (
            "cir_state_function, 1e6 particles",
            lambda: loop_cir(poses[:m], u[:m], WHEELS),
            lambda: cir_state_function(poses, u, WHEELS),
        ),
    ]
    print(f"{'workload':38s} {'loop (scaled)':>14s} {'numpy':>10s} {'ratio':>8s}")
    for name, loop, vec in rows:
        t_loop = best_of(loop, args.loop_repeats) * scale
        t_vec = best_of(vec, args.repeats)
        print(f"{name:38s} {t_loop:12.2f} s {t_vec * 1e3:8.0f} ms {t_loop / t_vec:7.0f}x")


if __name__ == "__main__":
    main()
