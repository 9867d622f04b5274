r"""Benchmark the vectorised motion models of :mod:`probrob.motion` against Python loops.

What is measured
----------------
Five workloads on a particle set of ``N = 1_000_000`` poses (float64, shape ``(N, 3)``,
:math:`x, y \sim \mathcal N(0, 1)` m, :math:`\theta \sim U[-\pi, \pi)`):

1. ``sample_motion_model_velocity`` (Table 5.3), default sampler: the book's sum of
   twelve uniforms (``sample_normal_distribution``, ``method="sum12"``, Table 5.4);
2. the same with exact normal noise
   (``functools.partial(sample_normal_distribution, method="exact")``); this row is
   also held to the target of at most 150 ms per million particles;
3. ``sample_motion_model_odometry`` (Table 5.6), sum of twelve uniforms;
4. the same with exact normal noise;
5. the density ``motion_model_velocity`` (Table 5.1) at ``N`` hypothesised poses.

Each is compared with a naive per-particle Python loop, a textbook transcription of
the same table in scalar ``math`` code, called once per particle: it draws its noise
with twelve scalar ``uniform(-b, b)`` calls (or one ``gauss``) from a seeded
``random.Random`` (``--loop-rng random``, the default and the faster, so the harder,
baseline) or from a seeded ``numpy.random.Generator`` (``--loop-rng numpy``), and
treats a sampled :math:`\hat\omega = 0` as a straight line, as the textbook scripts
do. The loop's particles are Python lists of tuples (converted before timing, which
favours the loop). The loop runs on a subset (``--n-loop``, default 20,000) and its
time is scaled linearly to one million particles.

Timing: :func:`time.perf_counter`, one warm-up call, then the minimum of several
repeats (5 for numpy, 3 for the loop), with the garbage collector paused (as
:mod:`timeit` does). The machine is shared and noisy; minima are the stable
statistic. The vectorised time is reported per million particles (scaled linearly
when ``N`` is smaller, as with ``--quick``).

Targets (reported, not asserted unless ``--check``): every loop/numpy ratio
at least 30x, and the exact-normal velocity sampler at most 150 ms per 1e6.

Agreement checks (always run; a failure exits with status 2)
------------------------------------------------------------
* Density: the loop mirrors the library's math in scalar form (the signed radius
  :math:`(a^2 + b^2)/(2b)` of the robot-frame displacement, the tangent-chord turn
  :math:`2\arctan(b/a)`, wrapped angle differences; see :mod:`probrob.motion`) and
  must equal the library on the subset to ``rtol=1e-9``, for the benchmark control
  and for a reversing right turn. As an independent check, the book's own
  circle-centre construction (Table 5.1, lines 2-6), with the errata's corrections
  (wrapped :math:`\Delta\theta`, signed radius, :math:`\hat\gamma` using
  :math:`\hat\omega`), must agree to ``rtol=1e-6`` away from straight lines.
* Samplers: loop and library use different random streams, so their outputs are
  compared statistically. Both models are invariant under rotations and
  translations, so the displacement :math:`(x', y', \theta') - (x, y, \theta)`
  expressed in the frame of :math:`x_{t-1}` (ahead, left, turn) is i.i.d. over
  particles; its mean and standard deviation must agree between loop and library
  within 4 standard errors for each component.

How to run
----------
``make bench`` runs ``python benchmarks/bench_motion.py`` (10-20 s on two cores)::

    python benchmarks/bench_motion.py               # full run, N = 1e6
    python benchmarks/bench_motion.py --quick       # smoke test, a few seconds
    python benchmarks/bench_motion.py --json results.json   # also write JSON
    python benchmarks/bench_motion.py --check       # exit 1 if a target is missed

Exit status: 0 (targets missed are only reported) unless ``--check`` is given and a
target is missed (1), or an agreement check fails (2).
"""

from __future__ import annotations

import argparse
import datetime
import functools
import gc
import json
import math
import os
import platform
import random
import sys
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass

import numpy as np

from probrob.angles import wrap_angle
from probrob.distributions import sample_normal_distribution
from probrob.motion import (
    motion_model_velocity,
    sample_motion_model_odometry,
    sample_motion_model_velocity,
)

# --------------------------------------------------------------------------- set-up

DT = 0.1  # s
U_VEL = (1.0, 0.5)  # (v, ω): 1 m/s, turning left at 0.5 rad/s
U_VEL_REVERSE = (-0.5, -0.8)  # reversing while turning right (density check only)
ALPHA_VEL = (0.05, 0.01, 0.01, 0.05, 0.01, 0.01)
U_ODO = ((0.0, 0.0, 0.0), (0.10, 0.02, 0.05))  # odometry poses (x̄_{t-1}, x̄_t)
ALPHA_ODO = (0.05, 0.01, 0.05, 0.01)

RATIO_TARGET = 30.0  # loop time / numpy time, at least
VEL_EXACT_TARGET_MS = 150.0  # exact-normal velocity sampler, per 1e6 particles, at most
PER = 1_000_000  # times are reported per this many particles
Z_MAX = 4.0  # sampler statistics must agree within this many standard errors
RTOL_MIRROR = 1e-9
RTOL_BOOK = 1e-6

TWO_PI = 2.0 * math.pi
exact_normal = functools.partial(sample_normal_distribution, method="exact")


# --------------------------------------------------------------------------- scalar loops


def loop_wrap(a: float) -> float:
    """Wrap to [-π, π), as :func:`probrob.angles.wrap_angle`."""
    w = (a + math.pi) % TWO_PI - math.pi
    return w - TWO_PI if w >= math.pi else w


def loop_sample_sum12(b2: float, uniform: Callable[[float, float], float]) -> float:
    """Table 5.4, line 2: ½ Σ_{i=1}^{12} rand(-b, b)."""
    b = math.sqrt(b2)
    return 0.5 * sum(uniform(-b, b) for _ in range(12))


def loop_sample_exact(b2: float, normal: Callable[[float, float], float]) -> float:
    """An exact normal draw with variance ``b2``."""
    return normal(0.0, math.sqrt(b2))


def loop_prob_normal(a: float, b2: float) -> float:
    """Table 5.2, line 2, with the point-mass limit at ``b2 == 0``."""
    if b2 > 0:
        return math.exp(-0.5 * a * a / b2) / math.sqrt(2.0 * math.pi * b2)
    return math.inf if a == 0 else 0.0


def loop_sample_motion_model_velocity(u, x_prev, dt, alpha, sample):
    """Table 5.3 for one particle."""
    v, w = u
    x, y, th = x_prev
    a1, a2, a3, a4, a5, a6 = alpha
    v_hat = v + sample(a1 * v * v + a2 * w * w)
    w_hat = w + sample(a3 * v * v + a4 * w * w)
    gamma_hat = sample(a5 * v * v + a6 * w * w)
    if w_hat == 0.0:  # straight line, the limit of the arc
        xn = x + v_hat * dt * math.cos(th)
        yn = y + v_hat * dt * math.sin(th)
    else:
        r = v_hat / w_hat
        xn = x - r * math.sin(th) + r * math.sin(th + w_hat * dt)
        yn = y + r * math.cos(th) - r * math.cos(th + w_hat * dt)
    return xn, yn, th + w_hat * dt + gamma_hat * dt


def loop_sample_motion_model_odometry(u, x_prev, alpha, sample):
    """Table 5.6 for one particle (rotations wrapped, as the library does)."""
    (xb, yb, thb), (xbn, ybn, thbn) = u
    x, y, th = x_prev
    a1, a2, a3, a4 = alpha
    dx, dy = xbn - xb, ybn - yb
    trans = math.sqrt(dx * dx + dy * dy)
    rot1 = loop_wrap(math.atan2(dy, dx) - thb) if trans > 0 else 0.0
    rot2 = loop_wrap(thbn - thb - rot1)
    rot1_hat = rot1 - sample(a1 * rot1 * rot1 + a2 * trans * trans)
    trans_hat = trans - sample(a3 * trans * trans + a4 * rot1 * rot1 + a4 * rot2 * rot2)
    rot2_hat = rot2 - sample(a1 * rot2 * rot2 + a2 * trans * trans)
    return (
        x + trans_hat * math.cos(th + rot1_hat),
        y + trans_hat * math.sin(th + rot1_hat),
        th + rot1_hat + rot2_hat,
    )


def loop_motion_model_velocity(x_t, u, x_prev, dt, alpha):
    """Table 5.1 for one pose, mirroring :func:`probrob.motion.motion_model_velocity`."""
    x, y, th = x_prev
    xn, yn, thn = x_t
    v, w = u
    a1, a2, a3, a4, a5, a6 = alpha
    dx, dy = xn - x, yn - y
    c, s = math.cos(th), math.sin(th)
    ahead = c * dx + s * dy
    left = c * dy - s * dx
    if ahead == 0 and left == 0:  # rotation in place
        half = 0.5 * loop_wrap(thn - th)
        ratio = 0.0
    else:
        sign = -1.0 if ahead < 0 else 1.0
        half = math.atan2(sign * left, abs(ahead))
        ratio = half / left if left != 0 else 1.0 / ahead
    v_hat = (ahead**2 + left**2) * ratio / dt  # signed radius × turn / Δt
    w_hat = 2.0 * half / dt
    gamma_hat = loop_wrap(thn - (th + 2.0 * half)) / dt
    return (
        loop_prob_normal(v - v_hat, a1 * v**2 + a2 * w**2)
        * loop_prob_normal(w - w_hat, a3 * v**2 + a4 * w**2)
        * loop_prob_normal(gamma_hat, a5 * v**2 + a6 * w**2)
    )


def book_motion_model_velocity(x_t, u, x_prev, dt, alpha):
    """Table 5.1 as printed (circle centre), with the errata's corrections.

    Independent of the library's derivation; undefined on straight lines (μ = ±∞),
    which the caller excludes.
    """
    x, y, th = x_prev
    xn, yn, thn = x_t
    v, w = u
    a1, a2, a3, a4, a5, a6 = alpha
    c, s = math.cos(th), math.sin(th)
    mu = 0.5 * ((x - xn) * c + (y - yn) * s) / ((y - yn) * c - (x - xn) * s)
    xs = 0.5 * (x + xn) + mu * (y - yn)
    ys = 0.5 * (y + yn) + mu * (xn - x)
    r = math.hypot(x - xs, y - ys)
    # Corrections: wrapped Δθ; radius signed by the side of the centre (left > 0).
    dtheta = loop_wrap(math.atan2(yn - ys, xn - xs) - math.atan2(y - ys, x - xs))
    signed_r = r if (c * (ys - y) - s * (xs - x)) > 0 else -r
    w_hat = dtheta / dt
    v_hat = dtheta * signed_r / dt
    gamma_hat = loop_wrap(thn - th - w_hat * dt) / dt  # ω̂, not ω
    return (
        loop_prob_normal(v - v_hat, a1 * v**2 + a2 * w**2)
        * loop_prob_normal(w - w_hat, a3 * v**2 + a4 * w**2)
        * loop_prob_normal(gamma_hat, a5 * v**2 + a6 * w**2)
    )


# --------------------------------------------------------------------------- timing


def time_calls(fn: Callable[[], object], repeats: int) -> tuple[list[float], object]:
    """Warm up once, then time ``repeats`` calls; return the times (s) and last result."""
    result = fn()
    times = []
    gc.collect()
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        for _ in range(repeats):
            t0 = time.perf_counter()
            result = fn()
            times.append(time.perf_counter() - t0)
    finally:
        if was_enabled:
            gc.enable()
    return times, result


def scalar_rng(kind: str, seed: int) -> tuple[Callable, Callable]:
    """``(uniform(a, b), normal(mu, sigma))`` of a seeded scalar generator."""
    if kind == "random":
        r = random.Random(seed)
        return r.uniform, r.gauss
    g = np.random.default_rng(seed)
    return g.uniform, g.normal


# --------------------------------------------------------------------------- checks


def local_displacement(x_prev: np.ndarray, x_t: np.ndarray) -> np.ndarray:
    """(ahead, left, turn) of ``x_t`` in the frame of ``x_prev``; shape (n, 3)."""
    dx = x_t[:, 0] - x_prev[:, 0]
    dy = x_t[:, 1] - x_prev[:, 1]
    c, s = np.cos(x_prev[:, 2]), np.sin(x_prev[:, 2])
    return np.column_stack([c * dx + s * dy, c * dy - s * dx, x_t[:, 2] - x_prev[:, 2]])


def _moments(d: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Mean, std and their standard errors per column (std's SE from the 4th moment)."""
    n = d.shape[0]
    mean = d.mean(axis=0)
    centred = d - mean
    var = (centred**2).mean(axis=0)
    m4 = (centred**4).mean(axis=0)
    std = np.sqrt(var)
    return mean, std, std / np.sqrt(n), np.sqrt(np.maximum(m4 - var**2, 0.0) / (4.0 * n * var))


@dataclass
class Check:
    name: str
    passed: bool
    detail: str


def compare_samples(name: str, d_loop: np.ndarray, d_vec: np.ndarray) -> Check:
    m_l, s_l, se_ml, se_sl = _moments(d_loop)
    m_v, s_v, se_mv, se_sv = _moments(d_vec)
    z_mean = np.abs(m_l - m_v) / np.hypot(se_ml, se_mv)
    z_std = np.abs(s_l - s_v) / np.hypot(se_sl, se_sv)
    passed = bool(np.all(z_mean <= Z_MAX) and np.all(z_std <= Z_MAX))
    parts = [
        f"{c}: mean {ml:+.5f}/{mv:+.5f} ({zm:.1f} SE), std {sl:.5f}/{sv:.5f} ({zs:.1f} SE)"
        for c, ml, mv, zm, sl, sv, zs in zip(
            ("ahead", "left", "turn"), m_l, m_v, z_mean, s_l, s_v, z_std, strict=True
        )
    ]
    return Check(name, passed, "loop/numpy " + "; ".join(parts))


def compare_values(name: str, loop: np.ndarray, lib: np.ndarray, rtol: float) -> Check:
    try:
        np.testing.assert_allclose(loop, lib, rtol=rtol, atol=0)
    except AssertionError as exc:
        first = str(exc).strip().splitlines()
        return Check(name, False, " | ".join(line.strip() for line in first[:6]))
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.abs(loop - lib) / np.abs(lib)
    rel = rel[np.isfinite(rel)]
    worst = float(rel.max()) if rel.size else 0.0
    positive = int(np.count_nonzero(lib > 0))
    return Check(
        name,
        True,
        f"{lib.size} values (rtol {rtol:g}), max rel. diff {worst:.1e}, "
        f"{positive} positive, median {np.median(lib):.3g}",
    )


# --------------------------------------------------------------------------- workloads


@dataclass
class Result:
    workload: str
    n: int
    n_loop: int
    numpy_times_s: list[float]
    loop_times_s: list[float]
    numpy_ms_per_1e6: float = 0.0
    loop_s_per_1e6: float = 0.0
    ratio: float = 0.0
    meets_ratio: bool = False
    time_target_ms: float | None = None
    meets_time_target: bool | None = None

    def __post_init__(self):
        self.numpy_ms_per_1e6 = min(self.numpy_times_s) * PER / self.n * 1e3
        self.loop_s_per_1e6 = min(self.loop_times_s) * PER / self.n_loop
        self.ratio = self.loop_s_per_1e6 * 1e3 / self.numpy_ms_per_1e6
        self.meets_ratio = self.ratio >= RATIO_TARGET
        if self.time_target_ms is not None:
            self.meets_time_target = self.numpy_ms_per_1e6 <= self.time_target_ms


def particles(n: int, rng: np.random.Generator) -> np.ndarray:
    x = np.empty((n, 3))
    x[:, 0] = rng.normal(0.0, 1.0, n)
    x[:, 1] = rng.normal(0.0, 1.0, n)
    x[:, 2] = rng.uniform(-np.pi, np.pi, n)
    return x


def as_tuples(a: np.ndarray) -> list[tuple[float, ...]]:
    return [tuple(row) for row in a.tolist()]


def run(args: argparse.Namespace) -> tuple[list[Result], list[Check]]:
    seeds = np.random.SeedSequence(args.seed).generate_state(10)
    x_prev = particles(args.n, np.random.default_rng(seeds[0]))
    sub = x_prev[: args.n_loop]
    sub_t = as_tuples(sub)
    results: list[Result] = []
    checks: list[Check] = []

    def loop_timed(body: Callable[[], list]) -> tuple[list[float], np.ndarray]:
        times, out = time_calls(body, args.loop_repeats)
        return times, np.asarray(out, dtype=float)

    # ---- samplers: each (model, noise) pair has its own seeded generators.
    alpha_v = np.array(ALPHA_VEL)
    alpha_o = np.array(ALPHA_ODO)
    u_v = np.array(U_VEL)
    u_o = np.array(U_ODO)

    def vel_numpy(vec_sample, rng):
        return sample_motion_model_velocity(u_v, x_prev, DT, alpha_v, sample=vec_sample, rng=rng)

    def vel_loop(draw):
        return [loop_sample_motion_model_velocity(U_VEL, p, DT, ALPHA_VEL, draw) for p in sub_t]

    def odo_numpy(vec_sample, rng):
        return sample_motion_model_odometry(u_o, x_prev, alpha_o, sample=vec_sample, rng=rng)

    def odo_loop(draw):
        return [loop_sample_motion_model_odometry(U_ODO, p, ALPHA_ODO, draw) for p in sub_t]

    cases = (
        ("velocity", "sum12", vel_numpy, vel_loop, None),
        ("velocity", "exact", vel_numpy, vel_loop, VEL_EXACT_TARGET_MS),
        ("odometry", "sum12", odo_numpy, odo_loop, None),
        ("odometry", "exact", odo_numpy, odo_loop, None),
    )
    for i, (model, label, f_numpy, f_loop, target) in enumerate(cases):
        rng = np.random.default_rng(seeds[1 + 2 * i])
        uniform, normal = scalar_rng(args.loop_rng, int(seeds[2 + 2 * i]))
        if label == "sum12":
            vec_sample = sample_normal_distribution
            draw = functools.partial(loop_sample_sum12, uniform=uniform)
        else:
            vec_sample = exact_normal
            draw = functools.partial(loop_sample_exact, normal=normal)
        name = f"sample_motion_model_{model} [{label}]"
        t_np, out_np = time_calls(functools.partial(f_numpy, vec_sample, rng), args.repeats)
        t_loop, out_loop = loop_timed(functools.partial(f_loop, draw))
        results.append(Result(name, args.n, args.n_loop, t_np, t_loop, time_target_ms=target))
        checks.append(
            compare_samples(
                name, local_displacement(sub, out_loop), local_displacement(x_prev, out_np)
            )
        )
        del out_np

    # ---- density: the hypotheses are poses drawn from the model (exact noise), their
    # headings wrapped so that θ' - θ crosses ±π for particles heading near ±π.
    rng = np.random.default_rng(seeds[9])
    x_t = sample_motion_model_velocity(u_v, x_prev, DT, alpha_v, sample=exact_normal, rng=rng)
    x_t[:, 2] = wrap_angle(x_t[:, 2])
    sub_xt = as_tuples(x_t[: args.n_loop])

    def dens_numpy():
        return motion_model_velocity(x_t, u_v, x_prev, DT, alpha_v)

    def dens_loop():
        return [
            loop_motion_model_velocity(q, U_VEL, p, DT, ALPHA_VEL)
            for q, p in zip(sub_xt, sub_t, strict=True)
        ]

    t_np, p_np = time_calls(dens_numpy, args.repeats)
    t_loop, p_loop = loop_timed(dens_loop)
    results.append(Result("motion_model_velocity", args.n, args.n_loop, t_np, t_loop))
    p_lib = p_np[: args.n_loop]
    checks.append(compare_values("motion_model_velocity: loop mirror", p_loop, p_lib, RTOL_MIRROR))

    # Book construction (independent), away from straight lines.
    d = local_displacement(sub, x_t[: args.n_loop])
    curved = np.abs(d[:, 1]) > 1e-6 * np.hypot(d[:, 0], d[:, 1])
    p_book = np.array(
        [
            book_motion_model_velocity(q, U_VEL, p, DT, ALPHA_VEL)
            for q, p, keep in zip(sub_xt, sub_t, curved, strict=True)
            if keep
        ]
    )
    checks.append(
        compare_values(
            "motion_model_velocity: book circle centre", p_book, p_lib[curved], RTOL_BOOK
        )
    )

    # Reversing right turn: exercises the signed radius.
    u_r = np.array(U_VEL_REVERSE)
    x_r = sample_motion_model_velocity(u_r, sub, DT, alpha_v, sample=exact_normal, rng=rng)
    x_r[:, 2] = wrap_angle(x_r[:, 2])
    p_lib_r = motion_model_velocity(x_r, u_r, sub, DT, alpha_v)
    p_loop_r = np.array(
        [
            loop_motion_model_velocity(q, U_VEL_REVERSE, p, DT, ALPHA_VEL)
            for q, p in zip(as_tuples(x_r), sub_t, strict=True)
        ]
    )
    checks.append(
        compare_values(
            "motion_model_velocity (reversing right): loop mirror",
            p_loop_r,
            p_lib_r,
            RTOL_MIRROR,
        )
    )
    return results, checks


# --------------------------------------------------------------------------- report


def print_report(args, results: list[Result], checks: list[Check], meta: dict) -> None:
    print(
        f"probrob motion-model benchmark: numpy {meta['numpy']}, Python {meta['python']}, "
        f"{meta['machine']}, {meta['cpus']} CPUs"
    )
    print(
        f"N = {args.n:,} (numpy, min of {args.repeats}), loop on {args.n_loop:,} "
        f"(min of {args.loop_repeats}, scaled to 1e6), loop RNG: {args.loop_rng}, "
        f"seed {args.seed}" + (", QUICK" if args.quick else "")
    )
    scaled = " (scaled)" if args.n != PER else ""
    head = (
        f"{'workload':<40} {'N':>9} {'N loop':>7} {'loop s/1e6':>11} "
        f"{'numpy ms/1e6':>13} {'ratio':>8} {'>=30x':>6} {'<=150ms':>8}"
    )
    print()
    print(head)
    print("-" * len(head))
    for r in results:
        target = "-" if r.meets_time_target is None else ("yes" if r.meets_time_target else "NO")
        print(
            f"{r.workload:<40} {r.n:>9,} {r.n_loop:>7,} {r.loop_s_per_1e6:>11.2f} "
            f"{r.numpy_ms_per_1e6:>13.1f} {r.ratio:>7.1f}x "
            f"{'yes' if r.meets_ratio else 'NO':>6} {target:>8}"
        )
    print("-" * len(head))
    if scaled:
        print(f"numpy times measured at N = {args.n:,} and scaled linearly to 1e6.")
    print("numpy ms, all repeats:")
    for r in results:
        print(f"  {r.workload:<40} " + " ".join(f"{t * 1e3:7.1f}" for t in r.numpy_times_s))
    print()
    print("agreement checks:")
    for c in checks:
        print(f"  [{'ok' if c.passed else 'FAIL'}] {c.name}: {c.detail}")
    missed = [r.workload for r in results if not r.meets_ratio or r.meets_time_target is False]
    print()
    if missed:
        print("targets missed: " + ", ".join(missed))
    else:
        print(
            f"all targets met (ratio >= {RATIO_TARGET:g}x, exact velocity sampler <= "
            f"{VEL_EXACT_TARGET_MS:g} ms/1e6)"
        )


def parse_args(argv=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smoke test: small N, few repeats")
    parser.add_argument("--n", type=int, help="particles for numpy (default 1e6; quick 1e5)")
    parser.add_argument("--n-loop", type=int, help="particles for the loop (default 20000)")
    parser.add_argument("--repeats", type=int, help="numpy repeats (default 5; quick 2)")
    parser.add_argument("--loop-repeats", type=int, help="loop repeats (default 3; quick 1)")
    parser.add_argument(
        "--loop-rng",
        choices=("random", "numpy"),
        default="random",
        help="scalar RNG of the loop: random.Random (default) or numpy Generator",
    )
    parser.add_argument("--seed", type=int, default=20050901)
    parser.add_argument("--json", metavar="PATH", help="also write the results as JSON")
    parser.add_argument(
        "--check", action="store_true", help="exit with status 1 if a target is missed"
    )
    args = parser.parse_args(argv)
    defaults = (100_000, 2_000, 2, 1) if args.quick else (PER, 20_000, 5, 3)
    for name, default in zip(("n", "n_loop", "repeats", "loop_repeats"), defaults, strict=True):
        if getattr(args, name) is None:
            setattr(args, name, default)
    args.n_loop = min(args.n_loop, args.n)
    if args.n <= 0 or args.n_loop <= 0 or args.repeats <= 0 or args.loop_repeats <= 0:
        parser.error("--n, --n-loop, --repeats and --loop-repeats must be positive")
    return args


def main(argv=None) -> int:
    args = parse_args(argv)
    meta = {
        "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "machine": f"{platform.system()} {platform.machine()}",
        "processor": platform.processor(),
        "cpus": os.cpu_count(),
    }
    results, checks = run(args)
    print_report(args, results, checks, meta)
    if args.json:
        payload = {
            "meta": meta,
            "config": {
                "n": args.n,
                "n_loop": args.n_loop,
                "repeats": args.repeats,
                "loop_repeats": args.loop_repeats,
                "loop_rng": args.loop_rng,
                "seed": args.seed,
                "quick": args.quick,
                "dt": DT,
                "u_velocity": U_VEL,
                "alpha_velocity": ALPHA_VEL,
                "u_odometry": U_ODO,
                "alpha_odometry": ALPHA_ODO,
            },
            "targets": {
                "ratio_min": RATIO_TARGET,
                "velocity_exact_ms_per_1e6_max": VEL_EXACT_TARGET_MS,
            },
            "results": [asdict(r) for r in results],
            "checks": [asdict(c) for c in checks],
        }
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(payload, fh, indent=2)
            fh.write("\n")
        print(f"wrote {args.json}")
    if not all(c.passed for c in checks):
        print("agreement check FAILED", file=sys.stderr)
        return 2
    missed = any(not r.meets_ratio or r.meets_time_target is False for r in results)
    return 1 if args.check and missed else 0


if __name__ == "__main__":
    sys.exit(main())
