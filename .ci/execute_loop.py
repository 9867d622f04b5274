#!/usr/bin/env python3
"""Execute notebooks again and again with nbclient and record every notebook's and cell's time.

The stall experiment of the build (a kernel idle with no cell running): each execution starts
a fresh kernel, runs every cell with a per-cell timeout, and records per cell the wall time and
the kernel's CPU time over it (a stalled cell has a long wall time and no CPU), the kernel's
startup time, and the notebook's total. Outputs are discarded (the notebooks are not changed).

Usage:  python .ci/execute_loop.py [NB.ipynb ...] [--loops 5] [--transport tcp|ipc]
        [--timeout 300] [--startup-timeout 60] [--log /tmp/loop.jsonl]
Prints one line per execution and, at the end, the slowest execution of each notebook, the
slowest cell, and every stall (a cell whose wall time exceeds --stall seconds with less than
10 % CPU). Exit status 1 if a cell failed, timed out or stalled.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

import nbformat
import psutil
from jupyter_client.manager import KernelManager
from nbclient import NotebookClient

ROOT = Path(__file__).resolve().parent.parent


def execute(path: Path, args) -> dict:
    nb = nbformat.read(path, as_version=4)
    km = KernelManager(kernel_name="python3", transport=args.transport)
    if args.transport == "ipc":
        # an absolute socket path prefix (the default is relative to the kernel's cwd)
        km.ip = os.path.join(tempfile.mkdtemp(prefix="probrob-ipc-"), "kernel")
    client = NotebookClient(
        nb,
        km=km,
        timeout=args.timeout,
        startup_timeout=args.startup_timeout,
        resources={"metadata": {"path": str(path.parent)}},
    )
    cells: list[dict] = []
    state: dict = {}

    def cpu() -> float:
        try:
            proc = psutil.Process(km.provisioner.pid)
            times = proc.cpu_times()
            return times.user + times.system
        except Exception:
            return float("nan")

    def start(cell, cell_index):
        state.update(index=cell_index, t=time.monotonic(), cpu=cpu())

    def done(cell, cell_index, execute_reply=None):
        wall = time.monotonic() - state["t"]
        cells.append(
            {"cell": cell_index, "wall": round(wall, 3), "cpu": round(cpu() - state["cpu"], 3)}
        )

    client.on_cell_execute = start
    client.on_cell_executed = done
    t0 = time.monotonic()
    error = startup = None
    try:
        with client.setup_kernel():
            startup = time.monotonic() - t0
            client.wait_for_reply(client.kc.kernel_info())
            for index, cell in enumerate(nb.cells):
                client.execute_cell(cell, index)
    except Exception as e:  # a cell error, a timeout, a kernel death: recorded, not raised
        error = f"{type(e).__name__}: {str(e)[:300]}"
    total = time.monotonic() - t0
    if args.transport == "ipc":
        shutil.rmtree(os.path.dirname(km.ip), ignore_errors=True)
    return {
        "notebook": path.name,
        "transport": args.transport,
        "total": round(total, 2),
        "startup": None if startup is None else round(startup, 2),
        "cells": cells,
        "error": error,
        "running_cell": state.get("index") if error else None,
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("notebooks", nargs="*", type=Path)
    ap.add_argument("--loops", type=int, default=5)
    ap.add_argument("--transport", choices=["tcp", "ipc"], default="tcp")
    ap.add_argument("--timeout", type=float, default=300.0, help="seconds per cell")
    ap.add_argument("--startup-timeout", type=float, default=60.0)
    ap.add_argument("--stall", type=float, default=30.0, help="wall seconds of an idle cell")
    ap.add_argument("--log", type=Path, help="append one JSON line per execution")
    ap.add_argument(
        "--no-wakeup-fix",
        action="store_true",
        help="do not install _ext/probrob_zmq_wakeup.py (to reproduce the stall)",
    )
    args = ap.parse_args(argv)
    if not args.no_wakeup_fix:
        sys.path.insert(0, str(ROOT / "_ext"))
        import probrob_zmq_wakeup

        probrob_zmq_wakeup.install()
    notebooks = args.notebooks or sorted((ROOT / "notebooks").glob("*.ipynb"))
    results = []
    for loop in range(args.loops):
        for path in notebooks:
            r = execute(path.resolve(), args)
            r["loop"] = loop
            results.append(r)
            slow = max(r["cells"], key=lambda c: c["wall"], default={"cell": None, "wall": 0})
            print(
                f"loop {loop + 1} {r['notebook']}: {r['total']:.1f} s (kernel {r['startup']} s; "
                f"slowest cell {slow['cell']}: {slow['wall']:.1f} s)"
                + (f"  ERROR in cell {r['running_cell']}: {r['error']}" if r["error"] else ""),
                flush=True,
            )
            if args.log:
                with args.log.open("a") as f:
                    f.write(json.dumps(r) + "\n")
    print(f"\n{len(results)} executions ({args.loops} loops, transport {args.transport})")
    bad = 0
    for name in sorted({r["notebook"] for r in results}):
        runs = [r for r in results if r["notebook"] == name]
        worst = max(runs, key=lambda r: r["total"])
        cell = max(
            (c for r in runs for c in r["cells"]),
            key=lambda c: c["wall"],
            default={"cell": None, "wall": 0.0, "cpu": 0.0},
        )
        print(
            f"  {name}: slowest execution {worst['total']:.1f} s (loop {worst['loop'] + 1}), "
            f"fastest {min(r['total'] for r in runs):.1f} s; slowest cell {cell['cell']} "
            f"{cell['wall']:.1f} s wall / {cell['cpu']:.1f} s CPU"
        )
    for r in results:
        for c in r["cells"]:
            if c["wall"] > args.stall and c["cpu"] < 0.1 * c["wall"]:
                bad += 1
                print(f"  STALL {r['notebook']} loop {r['loop'] + 1} cell {c['cell']}: {c}")
        if r["error"]:
            bad += 1
            print(f"  FAILED {r['notebook']} loop {r['loop'] + 1}: {r['error']}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
