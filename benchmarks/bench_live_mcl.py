"""The live particle filter in the browser: its size and its time per filter step.

Builds ``probrob.widgets.particle_filter_live`` on the Intel lab's first 100 steps as the MCL
chapter shows it (the 10 cm map from the corrected scans, the fitted beam parameters), opens it
in headless Chromium (``.ci/cdp.py``) and times, through the widget's ``bench`` hook, 100 filter
steps (one step and the estimate, then the redraw) at 500 and 2,000 particles, 60 beams, from
the known and the global start, for every sensor (likelihood field, beam model) and method
(MCL, augmented MCL, KLD-sampling: Tables 8.2-8.4; KLD-sampling's set then holds as many
particles as its bound asks, at most 2,000); best median of three runs (the machine is shared).
Then one slider move at the last step, which re-runs the 100 steps. Needs Chromium and the
Intel log.

    MPLBACKEND=Agg .venv/bin/python benchmarks/bench_live_mcl.py
"""

from __future__ import annotations

import importlib.util
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from probrob.widgets import particle_filter_live  # noqa: E402
from tests.test_live_mcl import _intel  # noqa: E402


def main() -> None:
    spec = importlib.util.spec_from_file_location("cdp", ROOT / ".ci" / "cdp.py")
    cdp = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(cdp)
    world = _intel()
    if world is None:
        sys.exit("the Intel lab log is absent")
    widget = particle_filter_live(**world)
    print(f"widget: {len(widget.html.encode()) / 1000:.0f} kB of HTML, 100 steps, 180 beams")
    with tempfile.TemporaryDirectory() as tmp:
        page = Path(tmp) / "mcl.html"
        page.write_text(
            f"<!doctype html><meta charset='utf-8'><body>{widget.html}</body>", "utf-8"
        )
        browser = cdp.Browser(cdp.find_chromium(None), timeout=60)
        try:
            tab = cdp.Tab.open(browser, page.as_uri())
            w = "probrobLive.widgets[0]"
            modes = [
                (sensor, method)
                for sensor in ("likelihood_field", "beam")
                for method in ("mcl", "augmented", "kld")
            ]
            for sensor, method in modes:
                for start in ("known", "global"):
                    for n in (500, 2000):
                        tab.js(
                            f"{w}.set({{n: {n}, start: '{start}', beams: 60, "
                            f"sensor: '{sensor}', method: '{method}'}})"
                        )
                        runs = [tab.js(f"{w}.bench(100)", timeout=600) for _ in range(3)]
                        b = min(runs, key=lambda r: r["total"]["median"])
                        print(
                            f"{sensor:16s} {method:9s} {start:6s} start, {n:4d} particles: "
                            f"{b['total']['median']:.1f} ms per step (median of 100; compute "
                            f"{b['compute']['median']:.1f}, draw {b['draw']['median']:.1f}; "
                            f"90th percentile {b['total']['p90']:.1f})"
                        )
            tab.js(f"{w}.set({{sensor: 'likelihood_field', method: 'mcl'}})")
            for n in (500, 2000):
                ms = tab.js(
                    f"(() => {{ const w = {w}; w.set({{n: {n}, start: 'known', t: 100}});"
                    " const out = []; for (let k = 0; k < 5; k++) { const t0 = performance.now();"
                    " w.set({a1: 0.1 + 0.001 * k}); out.push(performance.now() - t0); }"
                    " out.sort((a, b) => a - b); return out[2]; })()",
                    timeout=300,
                )
                print(
                    f"a slider moved at step 100, {n:4d} particles: {ms:.0f} ms (re-runs 100 steps)"
                )
            assert tab.exceptions() == []
            tab.close()
        finally:
            browser.close()


if __name__ == "__main__":
    main()
