"""The timing helper of the benchmarks that report the best of several wall-clock runs."""

from __future__ import annotations

import gc
import time


def best(fn, repeats: int) -> float:
    """Seconds of the fastest of ``repeats`` calls of ``fn``, after one warm-up call (which
    fills the caches: likelihood-field tables, traversal tables, a state space's centres),
    with the garbage collector paused. On a shared machine the minimum is the stable
    statistic."""
    fn()
    gc.disable()
    try:
        times = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t0)
    finally:
        gc.enable()
    return min(times)
