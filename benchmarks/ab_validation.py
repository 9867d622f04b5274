r"""What the validation layer of issue 11 costs: the motion models now against a base revision.

Both versions of the library run in one process: ``git archive <base> src/probrob`` is unpacked
into a temporary folder as the package ``probrob_base`` (its imports are relative). Each of
eight workloads on ``N`` particles (the four samplers of ``bench_motion.py`` and the velocity
and odometry densities in their ``"book"`` and ``"pose"`` modes) is timed ``--repeats`` times
per version, the versions alternating, in **thread CPU time** (``time.thread_time``): on a
shared machine the wall clock also counts the time other processes hold the core, which
swings by a factor of two between runs, while CPU time does not. The table gives the median
and the minimum per version and their ratio (after / before).

Run: ``python benchmarks/ab_validation.py [--base dfc1749] [--n 1000000] [--repeats 41]``.
"""

from __future__ import annotations

import argparse
import functools
import gc
import importlib
import io
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import numpy as np


def _load_base(rev: str, folder: Path):
    root = Path(__file__).resolve().parents[1]
    archive = subprocess.run(
        ["git", "archive", rev, "src/probrob"], cwd=root, check=True, capture_output=True
    ).stdout
    with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
        tar.extractall(folder, filter="data")
    (folder / "src" / "probrob").rename(folder / "probrob_base")
    sys.path.insert(0, str(folder))
    return (
        importlib.import_module("probrob_base.motion"),
        importlib.import_module("probrob_base.distributions"),
    )


def workloads(motion, distributions, n):
    rng = np.random.default_rng(0)
    x = np.column_stack([rng.normal(size=n), rng.normal(size=n), rng.uniform(-np.pi, np.pi, n)])
    x_t = x + rng.normal(0, 0.3, (n, 3))
    u_vel, a6 = (1.0, 0.5), (0.02, 0.02, 0.02, 0.02, 0.01, 0.01)
    u_odo, a4 = np.array([[0.0, 0.0, 0.0], [1.0, 0.3, 0.2]]), (0.05, 0.005, 0.05, 0.005)
    exact = functools.partial(distributions.sample_normal_distribution, method="exact")
    m = motion
    return {
        "sample velocity, sum12": lambda: m.sample_motion_model_velocity(u_vel, x, 1.0, a6, rng=1),
        "sample velocity, exact": lambda: m.sample_motion_model_velocity(
            u_vel, x, 1.0, a6, sample=exact, rng=1
        ),
        "sample odometry, sum12": lambda: m.sample_motion_model_odometry(u_odo, x, a4, rng=1),
        "sample odometry, exact": lambda: m.sample_motion_model_odometry(
            u_odo, x, a4, sample=exact, rng=1
        ),
        "velocity density, book": lambda: m.motion_model_velocity(x_t, u_vel, x, 1.0, a6),
        "velocity density, pose": lambda: m.motion_model_velocity(
            x_t, u_vel, x, 1.0, a6, density="pose"
        ),
        "odometry density, book": lambda: m.motion_model_odometry(x_t, u_odo, x, a4),
        "odometry density, pose": lambda: m.motion_model_odometry(
            x_t, u_odo, x, a4, density="pose"
        ),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--base", default="dfc1749", help="git revision to compare against")
    parser.add_argument("--n", type=int, default=1_000_000)
    parser.add_argument("--repeats", type=int, default=41)
    args = parser.parse_args()

    import probrob.distributions as new_distributions
    import probrob.motion as new_motion

    with tempfile.TemporaryDirectory() as tmp:
        old = workloads(*_load_base(args.base, Path(tmp)), args.n)
        new = workloads(new_motion, new_distributions, args.n)
        print(f"N = {args.n:,}, {args.repeats} alternating repeats, thread CPU time in ms")
        print(
            f"{'workload':24s} {'before: median / min':>22s} {'after: median / min':>22s}  after/before (median, min)"
        )
        for name in old:
            times = {"old": [], "new": []}
            old[name](), new[name]()
            gc.disable()
            for r in range(args.repeats):
                order = ("old", "new") if r % 2 == 0 else ("new", "old")
                for which in order:
                    func = (old if which == "old" else new)[name]
                    t0 = time.thread_time()
                    func()
                    times[which].append(time.thread_time() - t0)
            gc.enable()
            mo, mn = (statistics.median(times[k]) * 1e3 for k in ("old", "new"))
            lo, ln = (min(times[k]) * 1e3 for k in ("old", "new"))
            print(
                f"{name:24s} {mo:12.1f} / {lo:7.1f} {mn:12.1f} / {ln:7.1f}   {mn / mo:6.3f}  {ln / lo:6.3f}"
            )


if __name__ == "__main__":
    main()
