#!/usr/bin/env python3
"""Open the chapter notebooks in a real JupyterLab, driven by headless Chromium, and Run All.

For each notebook this script
  1. copies it (with its folder) to a temporary directory, so that Run All and autosave never
     touch the checkout;
  2. starts nothing new but a fresh page of one JupyterLab server (token-less, on a free port of
     127.0.0.1, ``--allow-root`` as root, its own settings and workspace folders), opens the
     notebook, waits for the kernel to be connected and idle, then waits a few seconds more and
     fails if the notebook is already marked modified (it names the metadata that JupyterLab
     changed: the stored metadata must be what JupyterLab writes, see ``.ci/normalize_notebooks.py``);
  3. runs ``notebook:run-all-cells`` and waits until the kernel is idle and every code cell has
     run (a per-notebook timeout);
  4. fails on a cell error (an ``error`` output, or a code cell left unexecuted), on raw MyST
     markup in any rendered markdown cell (``{eval}`...```, ``{glue:text}`...```, ``{math}``,
     ``{eq}`...```, ``:::{``, a directive fence ```` ```{ ````; i.e. markup that jupyterlab-myst
     did not render), on an ``{eval}`` role that rendered no value, on a ``to_jshtml`` player
     whose image has no ``src`` or is laid out at 0x0 once scrolled into view, and on an uncaught
     JavaScript error or a console error of the page.

It checks what is installed: ``jupyter labextension list`` must show jupyterlab-myst enabled
and "OK" (a version-compatible pair; see requirements-lab.txt).

Usage:  python .ci/jupyterlab_check.py [NOTEBOOK.ipynb ...] [--timeout 900] [--chromium PATH]
Default: every notebook in notebooks/. Exit status 0 only if every notebook passes.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

from cdp import Browser, CheckError, Tab, find_chromium

ROOT = Path(__file__).resolve().parent.parent
BIN = Path(sys.executable).parent

# Markup that only shows as text when jupyterlab-myst did not parse it.
RAW_MYST = [
    "{eval}`",
    "{glue:text}`",
    "{glue:}`",
    "{glue}`",
    "{math}",
    "{eq}`",
    "{ref}`",
    "{numref}`",
    ":::{",
    "```{",
    "{admonition}",
    "{note}",
    "{figure}",
]

# Messages jupyterlab-myst logs with console.error about the markup it rendered.
MYST_DIAGNOSTICS = ["Legacy syntax used for link target", "Cross reference target was not found"]

# The faults planted in the broken fixture, each of which the check must report (--self-test).
BROKEN_FIXTURE = ROOT / ".ci" / "fixtures" / "broken" / "myst_broken.ipynb"
BROKEN_FAULTS = [
    "marked modified on open",
    "raw MyST in markdown cell 2: ...source: {glue:text}`key`",
    "{eval} not rendered in markdown cell 2",
    "references that JupyterLab cannot resolve (shown as a warning sign and the label; "
    "cells [2]): errata-x1",
    "player 2 blank",
    "redraw error in cell 5",
    "cut label in cell 5",
    "stray repr in cell 6: <function",
    "error in cell 7: ZeroDivisionError",
]

# --------------------------------------------------------------------------------------------
# JavaScript run in the JupyterLab page (window.jupyterapp: LabApp.expose_app_in_browser)

JS_WAIT_APP = """
(async () => {
  const t0 = Date.now();
  while (!(window.jupyterapp && window.jupyterapp.shell)) {
    if (Date.now() - t0 > %d) return "JupyterLab did not start";
    await new Promise(r => setTimeout(r, 200));
  }
  await window.jupyterapp.restored;
  return "ok";
})()
"""

JS_OPEN = """
(async () => {
  const app = window.jupyterapp;
  const panel = await app.commands.execute("docmanager:open", {path: %s, factory: "Notebook"});
  window.__probrob_panel = panel;
  await panel.context.ready;
  await panel.sessionContext.ready;
  const t0 = Date.now();
  for (;;) {
    const k = panel.sessionContext.session && panel.sessionContext.session.kernel;
    if (k && k.connectionStatus === "connected" && k.status === "idle") break;
    if (Date.now() - t0 > %d) return {error: "kernel not idle: " + (k ? k.status : "none")};
    await new Promise(r => setTimeout(r, 200));
  }
  return {kernel: panel.sessionContext.kernelDisplayName, ms: Date.now() - t0};
})()
"""

JS_DIRTY = """
(() => {
  const panel = window.__probrob_panel;
  return {dirty: panel.context.model.dirty, metadata: panel.context.model.toJSON().metadata};
})()
"""

JS_RUN_ALL = """
(async () => {
  const app = window.jupyterapp, panel = window.__probrob_panel;
  app.shell.activateById(panel.id);
  const t0 = Date.now();
  await app.commands.execute("notebook:run-all-cells");
  const kernel = () => panel.sessionContext.session.kernel;
  const pending = () => panel.content.widgets.filter(c => c.model.type === "code" &&
      c.model.sharedModel.getSource().trim() && (c.model.executionCount === null ||
      (c.promptNode && c.promptNode.textContent.includes("*")))).length;
  let idleSince = null;
  for (;;) {
    const idle = kernel().status === "idle" && pending() === 0;
    if (idle && idleSince === null) idleSince = Date.now();
    if (!idle) idleSince = null;
    if (idleSince !== null && Date.now() - idleSince > 2000) break;
    const errors = panel.content.widgets.filter(c => c.model.type === "code" &&
        c.model.toJSON().outputs.some(o => o.output_type === "error"));
    if (errors.length && kernel().status === "idle") { idleSince = Date.now() - 2000; break; }
    if (Date.now() - t0 > %d) return {timeout: true, ms: Date.now() - t0, pending: pending()};
    await new Promise(r => setTimeout(r, 500));
  }
  return {ms: Date.now() - t0 - 2000};
})()
"""

# After Run All: what a reader sees. Text of the rendered markdown cells without code, math
# source and KaTeX/MathJax internals; the {eval} roles; errors; players (scrolled into view).
JS_SURVEY = r"""
(async (RAW) => {
  const panel = window.__probrob_panel;
  const SKIP = new Set(["PRE", "CODE", "SCRIPT", "STYLE", "TEXTAREA", "ANNOTATION", "MJX-CONTAINER",
                        "MJX-ASSISTIVE-MML", "MATH"]);
  const textOf = root => {
    const out = [];
    const w = document.createTreeWalker(root, NodeFilter.SHOW_TEXT, {acceptNode(n) {
      for (let p = n.parentElement; p && p !== root; p = p.parentElement) {
        if (SKIP.has(p.tagName.toUpperCase()) || p.classList.contains("katex-mathml") ||
            p.classList.contains("jp-InputArea-editor"))
          return NodeFilter.FILTER_REJECT;
      }
      return NodeFilter.FILTER_ACCEPT;
    }});
    for (let n = w.nextNode(); n; n = w.nextNode()) out.push(n.nodeValue);
    return out.join("");
  };
  const cells = panel.content.widgets;
  const raw = [], unrendered = [], errors = [], unrun = [], evals = [], badEvals = [];
  const unresolved = [], deadLinks = [];
  let markdown = 0;
  cells.forEach((c, i) => {
    const src = c.model.sharedModel.getSource();
    if (c.model.type === "markdown") {
      markdown++;
      if (!c.rendered) { unrendered.push(i); return; }
      const t = textOf(c.node);  // the rendered markdown (the hidden editor is skipped)
      for (const pat of RAW) {
        const k = t.indexOf(pat);
        if (k >= 0) raw.push({cell: i, text: t.slice(Math.max(0, k - 40), k + 60)});
      }
      // Roles jupyterlab-myst does not know render as their bare content, silently (a glued
      // value shows its key): found in the source.
      for (const m of src.matchAll(/\{glue(:[a-z]+)?\}`[^`]*`/g)) {
        raw.push({cell: i, text: "source: " + m[0] + " (jupyterlab-myst shows only its key)"});
      }
      // A reference jupyterlab-myst cannot resolve (e.g. to a label on another page) shows as
      // a warning sign and the bare label.
      for (const el of c.node.querySelectorAll('[title="Cross Reference Not Found"]')) {
        unresolved.push({cell: i, label: el.textContent.trim()});
      }
      // ... and one with its own text, {ref}`text <label>`, as that text on a link to "#".
      for (const el of c.node.querySelectorAll('a.hover-link[href="#"]')) {
        deadLinks.push({cell: i, text: el.textContent.trim()});
      }
      const n = (src.match(/\{eval\}`/g) || []).length;
      if (n) {
        const ue = c.model.getMetadata("user_expressions") || [];
        const values = ue.map(e => e.result || {});
        const ok = values.filter(r => r.status === "ok" &&
            (r.data || {})["text/plain"] !== undefined);
        evals.push(n);
        if (ok.length < n) {
          badEvals.push({cell: i, roles: n, values: ok.length,
                         statuses: values.map(r => r.status + (r.ename ? " " + r.ename : ""))});
        }
      }
    } else if (c.model.type === "code" && src.trim()) {
      const outs = c.model.toJSON().outputs || [];
      for (const o of outs) if (o.output_type === "error")
        errors.push({cell: i, ename: o.ename, evalue: String(o.evalue).slice(0, 200)});
      if (c.model.executionCount === null) unrun.push(i);
    }
  });
  // Players: scroll each into view (lazy layout), then measure its frame.
  const players = [];
  const imgs = Array.from(panel.node.querySelectorAll('img[id^="_anim_img"]'));
  for (const [k, im] of imgs.entries()) {
    im.scrollIntoView({block: "center"});
    await new Promise(r => setTimeout(r, 300));
    const r = im.getBoundingClientRect();
    players.push({k: k, src: (im.getAttribute("src") || "").length, w: Math.round(r.width),
                  h: Math.round(r.height), natural: im.naturalWidth});
  }
  return {cells: cells.length, markdown: markdown, raw: raw, unrendered: unrendered,
          errors: errors, unrun: unrun, unresolved: unresolved, deadLinks: deadLinks, evalRoles: evals.reduce((a, b) => a + b, 0),
          badEvals: badEvals, players: players};
})(%s)
"""

# The controls a reader moves after Run All: per code cell, its ipywidgets sliders (noUiSlider
# handles), and the range inputs of the kernel-free live widgets and players.
JS_CONTROLS = r"""
(() => {
  const panel = window.__probrob_panel;
  const out = [];
  panel.content.widgets.forEach((c, i) => {
    if (c.model.type !== "code") return;
    const handles = c.node.querySelectorAll(".jp-OutputArea .widget-slider .noUi-handle");
    const selects = c.node.querySelectorAll(".jp-OutputArea .widget-dropdown select");
    const ranges = c.node.querySelectorAll(".jp-OutputArea input[type=range]");
    const canvases = c.node.querySelectorAll(".jp-OutputArea canvas");
    if (handles.length || selects.length || ranges.length)
      out.push({cell: i, sliders: handles.length, selects: selects.length, ranges: ranges.length, canvases: canvases.length});
  });
  return out;
})()
"""
# What a cell shows (its images' src, its canvases' pixels, its widget output's text), folded
# into a hash; its stderr/error outputs; whether the kernel is idle; optionally focus a control.
JS_FINGERPRINT = r"""
((i, focus) => {
  const panel = window.__probrob_panel;
  const c = panel.content.widgets[i];
  c.node.scrollIntoView({block: "center"});
  let h = 0;
  const mix = s => { for (let k = 0; k < s.length; k += 7) h = (h * 31 + s.charCodeAt(k)) | 0; };
  c.node.querySelectorAll(".jp-OutputArea img").forEach(im => mix(im.getAttribute("src") || ""));
  c.node.querySelectorAll(".jp-OutputArea canvas").forEach(cv => { try { mix(cv.toDataURL()); } catch (e) {} });
  const texts = Array.from(c.node.querySelectorAll(".jp-OutputArea .widget-output .jp-RenderedText, .jp-OutputArea .widget-output pre"));
  texts.forEach(t => mix(t.textContent));
  const errs = Array.from(c.node.querySelectorAll('.jp-OutputArea [data-mime-type="application/vnd.jupyter.stderr"]'))
     .map(e => e.textContent.slice(0, 300));
  const k = panel.sessionContext.session.kernel;
  let focused = null;
  if (focus) {
    const [kind, j] = focus;
    const sel = kind === "slider" ? ".jp-OutputArea .widget-slider .noUi-handle" :
                kind === "range" ? ".jp-OutputArea input[type=range]" : ".jp-OutputArea .widget-dropdown select";
    const el = c.node.querySelectorAll(sel)[j];
    if (el) { el.focus(); focused = document.activeElement === el; }
  }
  return {hash: h, errors: errs, idle: k.status === "idle", focused: focused};
})(%d, %s)
"""
# Labels cut off (text wider than its box), controls past the output's right edge, and stray
# reprs (an execute_result that is only "<function ...>", "(<Axes: ...>, None)", ...).
JS_CUT = r"""
(() => {
  const panel = window.__probrob_panel;
  const cut = [], stray = [];
  panel.content.widgets.forEach((c, i) => {
    if (c.model.type !== "code") return;
    for (const o of (c.model.toJSON().outputs || [])) {
      const t = o.data && o.data["text/plain"];
      const s = Array.isArray(t) ? t.join("") : (t || "");
      if (o.output_type === "execute_result" && /^[(\[]?<(Axes|Figure|function|matplotlib|module|bound method|[\w.]+ object at)/.test(s)
          && !(o.data["text/html"] || o.data["application/vnd.jupyter.widget-view+json"] || o.data["image/png"]))
        stray.push({cell: i, text: s.slice(0, 100)});
    }
    c.node.scrollIntoView({block: "center"});
    const area = c.node.querySelector(".jp-OutputArea");
    if (!area) return;
    const right = area.getBoundingClientRect().right;
    for (const el of c.node.querySelectorAll(".jp-OutputArea .widget-label, .jp-OutputArea label")) {
      if (el.offsetParent && el.scrollWidth > el.clientWidth + 1)
        cut.push({cell: i, text: el.textContent.trim().slice(0, 60), need: el.scrollWidth, has: el.clientWidth});
    }
    for (const el of c.node.querySelectorAll(".jp-OutputArea .jupyter-widgets, .jp-OutputArea select, .jp-OutputArea input")) {
      const r = el.getBoundingClientRect();
      if (el.offsetParent && r.width && r.right > right + 1)
        cut.push({cell: i, text: (el.className || el.tagName).toString().slice(0, 60) + " past the output's edge", need: Math.round(r.right), has: Math.round(right)});
    }
  });
  return {cut: cut, stray: stray};
})()
"""

JS_SHUTDOWN = """
(async () => {
  const panel = window.__probrob_panel;
  if (panel) { await panel.sessionContext.shutdown(); panel.dispose(); }
  return "ok";
})()
"""


# --------------------------------------------------------------------------------------------
# The server


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def labextensions() -> tuple[str, list[str]]:
    """`jupyter labextension list` output and its problems.

    jupyterlab-myst must be installed and enabled. An extension the list calls "not
    compatible" passes only if every conflicting package is one that its bundle never loads
    (absent from all of its JavaScript): then the conflict is in its package.json alone. A
    conflict that matters at run time also shows in the browser as an "Unsatisfied version"
    warning, which fails each notebook's check.
    """
    out = subprocess.run(
        [str(BIN / "jupyter"), "labextension", "list"],
        capture_output=True,
        text=True,
        env=os.environ,
    )
    text = re.sub(r"\x1b\[[0-9;]*m", "", out.stdout + out.stderr)
    problems = []
    line = next((ln for ln in text.splitlines() if ln.strip().startswith("jupyterlab-myst ")), "")
    if not line:
        problems.append(
            "jupyterlab-myst is not installed (make lab installs requirements-lab.txt)"
        )
    elif "enabled" not in line:
        problems.append(f"jupyterlab-myst is not enabled: {line.strip()}")
    # '"name@version" is not compatible ...', 'Conflicting Dependencies:', a header line, then
    # one line per package ending in the package name.
    for m in re.finditer(
        r'"(?P<ext>[^"]+)@[^"@]+" is not compatible[^\n]*\nConflicting Dependencies:\n[^\n]*\n'
        r"(?P<rows>(?:[^\n]*\S[^\n]*\n?)*)",
        text,
    ):
        ext = m["ext"]
        packages = [row.split()[-1] for row in m["rows"].splitlines() if row.strip()]
        static = BIN.parent / "share" / "jupyter" / "labextensions" / ext / "static"
        bundle = "".join(f.read_text(errors="replace") for f in sorted(static.glob("*.js")))
        used = [pkg for pkg in packages if f'"{pkg}"' in bundle or f"'{pkg}'" in bundle]
        if not bundle or used:
            problems.append(f"{ext} is not compatible with this JupyterLab: {used or packages}")
        else:
            print(
                f"{ext}: the conflict on {', '.join(packages)} is in its package.json only "
                f"(its bundle of {len(bundle):,} characters never loads them)"
            )
    return text, problems


class Lab:
    """A JupyterLab server on 127.0.0.1 serving ``root`` (no token, no browser)."""

    def __init__(self, root: Path, timeout: float):
        self.dir = Path(tempfile.mkdtemp(prefix="probrob-lab-"))
        self.port = free_port()
        self.url = f"http://127.0.0.1:{self.port}"
        args = [
            str(BIN / "jupyter"),
            "lab",
            "--no-browser",
            f"--ServerApp.port={self.port}",
            "--ServerApp.port_retries=0",
            "--ServerApp.ip=127.0.0.1",
            "--IdentityProvider.token=",
            "--ServerApp.password=",
            f"--ServerApp.root_dir={root}",
            "--LabApp.expose_app_in_browser=True",
            f"--LabApp.user_settings_dir={self.dir / 'settings'}",
            f"--LabApp.workspaces_dir={self.dir / 'workspaces'}",
            "--LabServerApp.open_browser=False",
        ]
        if os.geteuid() == 0:
            args.append("--allow-root")
        env = dict(os.environ)
        env.setdefault("JUPYTER_PATH", str(BIN.parent / "share" / "jupyter"))
        env["JUPYTER_CONFIG_DIR"] = str(self.dir / "config")  # no user config
        env["JUPYTER_RUNTIME_DIR"] = str(self.dir / "runtime")
        env.pop("MPLBACKEND", None)  # the kernels must use the inline backend
        self.log = open(self.dir / "server.log", "wb")  # noqa: SIM115 -- closed in close()
        self.proc = subprocess.Popen(
            args,
            stdin=subprocess.DEVNULL,
            stdout=self.log,
            stderr=subprocess.STDOUT,
            env=env,
            start_new_session=True,
        )
        deadline = time.monotonic() + timeout
        while True:
            try:
                with urllib.request.urlopen(f"{self.url}/api/status", timeout=5) as r:
                    if r.status == 200:
                        break
            except OSError:
                pass
            if self.proc.poll() is not None or time.monotonic() > deadline:
                raise CheckError(f"JupyterLab did not start:\n{self.output()}")
            time.sleep(0.5)

    def output(self) -> str:
        self.log.flush()
        return (self.dir / "server.log").read_text(errors="replace")[-3000:]

    def close(self) -> None:
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGTERM)  # the server and its kernels
            try:
                self.proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait()
        self.log.close()
        shutil.rmtree(self.dir, ignore_errors=True)


# --------------------------------------------------------------------------------------------
# One notebook


def console_problems(tab: Tab) -> list[str]:
    """Uncaught errors and console errors of the page (the browser's own log included)."""
    out = []
    for ev in tab.events():
        m, prm = ev["method"], ev.get("params", {})
        if m == "Runtime.exceptionThrown":
            d = prm["exceptionDetails"]
            out.append(
                "uncaught: "
                + ((d.get("exception") or {}).get("description") or d.get("text") or "")[:300]
            )
        elif m == "Runtime.consoleAPICalled" and prm.get("type") == "error":
            text = " ".join(
                str(a.get("value", a.get("description", ""))) for a in prm.get("args", [])
            )
            out.append("console.error: " + "\nconsole.error: ".join(text.splitlines()))
        elif m == "Log.entryAdded" and prm["entry"].get("level") == "error":
            e = prm["entry"]
            if e.get("url", "").endswith("/favicon.ico"):
                continue
            out.append(f"log ({e.get('source')}): {e.get('text', '')[:300]}")
    return out


def console_warnings(tab: Tab) -> list[str]:
    out = []
    for ev in tab.events():
        prm = ev.get("params", {})
        if ev["method"] == "Runtime.consoleAPICalled" and prm.get("type") == "warning":
            out.append(
                " ".join(
                    str(a.get("value", a.get("description", ""))) for a in prm.get("args", [])
                )[:200]
            )
    return out


JS_STEP_RANGE = """
(() => {
  const el = document.activeElement;
  if (!el || el.type !== "range") return null;
  el.stepUp();
  el.dispatchEvent(new Event("input", {bubbles: true}));
  el.dispatchEvent(new Event("change", {bubbles: true}));
  return el.value;
})()
"""


def check_controls(tab: Tab, timeout: float = 15.0) -> tuple[list[str], list[str]]:
    """Move the first ipywidgets slider and the first live range input of every cell that has
    them; each must redraw its cell (images, canvas or text) within ``timeout`` seconds,
    with the kernel idle again and no error in the cell's outputs. Returns (lines, failures).

    An ipywidgets slider is moved with the keyboard (its focused handle, ArrowRight) and
    recomputes in the kernel; a live widget's or player's ``<input type=range>`` is stepped up
    by script with an ``input`` event (JupyterLab's keyboard handling keeps ArrowRight from
    reaching a focused range input in an output), as a drag would."""
    lines, failures = [], []
    for c in tab.js(JS_CONTROLS):
        for kind, n in (("slider", c["sliders"]), ("range", c["ranges"])):
            if not n:
                continue
            s0 = tab.js(JS_FINGERPRINT % (c["cell"], json.dumps([kind, 0])))
            time.sleep(0.3)  # scrolled into view: let lazy outputs lay out
            s0 = tab.js(JS_FINGERPRINT % (c["cell"], json.dumps([kind, 0])))
            if kind == "range":
                tab.js(JS_STEP_RANGE)
            else:
                tab.key("ArrowRight", "ArrowRight", 39)
            t0 = time.monotonic()
            changed = False
            while time.monotonic() - t0 < timeout:
                time.sleep(0.1)
                s1 = tab.js(JS_FINGERPRINT % (c["cell"], "null"))
                if s1["errors"] and s1["idle"]:
                    break
                if s1["hash"] != s0["hash"] and s1["idle"]:
                    changed = True
                    break
            what = "ipywidgets slider" if kind == "slider" else "live/player range input"
            dt = time.monotonic() - t0
            if s1["errors"]:
                failures.append(
                    f"redraw error in cell {c['cell']} after moving its {what}: "
                    f"{s1['errors'][0][:200]}"
                )
            elif not changed or not s0["focused"]:
                failures.append(
                    f"no redraw in cell {c['cell']} within {timeout:.0f} s of moving its {what}"
                )
            lines.append(
                f"cell {c['cell']}: {what} moved, "
                + (f"redrawn in {dt:.2f} s" if changed else "NOT redrawn")
            )
    cut = tab.js(JS_CUT)
    for k in cut["cut"]:
        failures.append(
            f"cut label in cell {k['cell']}: {k['text']!r} needs {k['need']} px, has {k['has']}"
        )
    for k in cut["stray"]:
        failures.append(f"stray repr in cell {k['cell']}: {k['text']}")
    return lines, failures


def check_notebook(browser: Browser, lab: Lab, name: str, args) -> list[str]:
    failures: list[str] = []
    tab = Tab.open(browser, width=1280, height=1000)
    try:
        # The page a reader looks at: in front, focused, so it renders every frame (a background
        # tab is not rendered, and JupyterLab's off-screen cells, content-visibility: auto, are
        # then never laid out when scrolled to: players at 0x0).
        tab.send("Page.bringToFront")
        tab.send("Emulation.setFocusEmulationEnabled", {"enabled": True})
        tab.navigate(f"{lab.url}/lab?reset")
        state = tab.js(JS_WAIT_APP % int(args.timeout * 1000), timeout=args.timeout + 10)
        if state != "ok":
            return [state]
        t0 = time.monotonic()
        opened = tab.js(
            JS_OPEN % (json.dumps(name), int(args.timeout * 1000)), timeout=args.timeout + 10
        )
        if "error" in opened:
            return [f"open: {opened['error']}"]
        print(f"  opened; kernel {opened['kernel']!r} idle after {time.monotonic() - t0:.1f} s")
        time.sleep(args.settle)
        d = tab.js(JS_DIRTY)
        stored = json.loads((lab.root / name).read_text(encoding="utf-8"))["metadata"]
        changed = sorted(
            k for k in set(stored) | set(d["metadata"]) if stored.get(k) != d["metadata"].get(k)
        )
        print(
            f"  {args.settle:.0f} s after the kernel was idle: "
            f"{'MODIFIED' if d['dirty'] else 'not modified'}"
            + (f" (metadata changed: {', '.join(changed)})" if changed else "")
        )
        if d["dirty"]:
            detail = "; ".join(
                f"{k}: stored {json.dumps(stored.get(k))} -> {json.dumps(d['metadata'].get(k))}"
                for k in changed
            )
            failures.append(f"marked modified on open, before Run All ({detail or 'cells'})")

        run = tab.js(JS_RUN_ALL % int(args.timeout * 1000), timeout=args.timeout + 30)
        if run.get("timeout"):
            failures.append(
                f"Run All did not finish in {args.timeout:.0f} s "
                f"({run['pending']} code cells pending)"
            )
        print(f"  Run All: {run['ms'] / 1000:.1f} s")
        time.sleep(1.0)  # let the last markdown cells render
        s = tab.js(JS_SURVEY % json.dumps(RAW_MYST), timeout=args.timeout)
        blank = [
            p for p in s["players"] if not p["src"] or not p["w"] or not p["h"] or not p["natural"]
        ]
        print(
            f"  {s['cells']} cells ({s['markdown']} markdown, {len(s['unrendered'])} not "
            f"rendered); {len(s['raw'])} raw MyST roles; {s['evalRoles']} {{eval}} roles "
            f"({len(s['badEvals'])} cells with an unrendered value); {len(s['errors'])} cell "
            f"errors, {len(s['unrun'])} code cells not run; {len(s['players'])} players "
            f"({len(blank)} blank)"
        )
        for r in s["raw"]:
            failures.append(f"raw MyST in markdown cell {r['cell']}: ...{r['text']}...")
        labels = sorted({u["label"] for u in s["unresolved"]})
        if labels:
            failures.append(
                f"{len(s['unresolved'])} references that JupyterLab cannot resolve (shown as a "
                f"warning sign and the label; cells {sorted({u['cell'] for u in s['unresolved']})}"
                f"): {', '.join(labels)}"
            )
        if s["deadLinks"]:
            texts = sorted({d["text"] for d in s["deadLinks"]})
            print(
                f"  note: {len(s['deadLinks'])} references with their own text lead nowhere in "
                f"JupyterLab (a label on another page; the web book resolves them): "
                + ", ".join(texts[:12])
                + (" ..." if len(texts) > 12 else "")
            )
        for b in s["badEvals"]:
            failures.append(
                f"{{eval}} not rendered in markdown cell {b['cell']}: {b['roles']} "
                f"roles, {b['values']} values {b['statuses']}"
            )
        if s["unrendered"]:
            failures.append(f"markdown cells not rendered: {s['unrendered'][:10]}")
        for e in s["errors"]:
            failures.append(f"error in cell {e['cell']}: {e['ename']}: {e['evalue']}")
        if s["unrun"] and not s["errors"]:
            failures.append(f"code cells not run: {s['unrun'][:10]}")
        for p in blank:
            failures.append(
                f"player {p['k'] + 1} blank: src {p['src']} chars, "
                f"laid out {p['w']}x{p['h']}, natural width {p['natural']}"
            )
        if len(s["players"]) < args.min_players:
            failures.append(f"{len(s['players'])} players, expected >= {args.min_players}")
        if True:  # the cells before an error have run: their controls are checked too
            lines, control_failures = check_controls(tab)
            moved = [ln for ln in lines if "redrawn in" in ln]
            times = [float(ln.rsplit("in ", 1)[1].split(" s")[0]) for ln in moved]
            print(
                f"  controls: {len(lines)} moved, {len(moved)} redrawn"
                + (f" (slowest {max(times):.2f} s)" if times else "")
                + f"; {len(control_failures)} problems (redraw errors, cut labels, stray reprs)"
            )
            failures += control_failures
        console = console_problems(tab)
        warnings = console_warnings(tab)
        print(f"  console: {len(console)} errors, {len(warnings)} warnings")
        for w in warnings[: args.show_warnings]:
            print(f"    warning: {w}")
        # one failure per distinct message line (a renderer may log the same line per render);
        # jupyterlab-myst's own diagnostics are reported, not failed: an unresolved reference
        # fails above, from what the reader sees, and a "legacy" [text](label) link works.
        distinct = sorted(
            {ln.strip()[:300] for c in console for ln in c.splitlines() if ln.strip()}
        )
        myst = [c for c in distinct if any(k in c for k in MYST_DIAGNOSTICS)]
        if myst:
            print(f"  jupyterlab-myst diagnostics ({len(myst)} distinct):")
            for c in myst:
                print(f"    {c.removeprefix('console.error: ')}")
        failures += [f"console: {c}" for c in distinct if c not in myst]
        failures += [
            f"console: shared-module version mismatch: {w}"
            for w in warnings
            if "Unsatisfied version" in w or "No satisfying version" in w
        ]
        tab.js(JS_SHUTDOWN, timeout=60)
    finally:
        tab.close()
    return failures


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument(
        "notebooks", nargs="*", type=Path, help="notebooks (default: notebooks/*.ipynb)"
    )
    ap.add_argument("--chromium", help="Chromium binary (default: Debian's chromium)")
    ap.add_argument(
        "--timeout",
        type=float,
        default=900.0,
        help="seconds for JupyterLab to start, a kernel to be idle, or Run All",
    )
    ap.add_argument(
        "--settle",
        type=float,
        default=5.0,
        help="seconds to wait after the kernel is idle before the modified check",
    )
    ap.add_argument("--min-players", type=int, default=0)
    ap.add_argument("--show-warnings", type=int, default=5)
    ap.add_argument(
        "--skip-extension-check",
        action="store_true",
        help="run even if jupyter labextension list reports a problem",
    )
    ap.add_argument(
        "--self-test",
        action="store_true",
        help="first check that the broken fixture fails with each of its faults",
    )
    args = ap.parse_args(argv)
    notebooks = [p.resolve() for p in args.notebooks] or sorted(
        (ROOT / "notebooks").glob("*.ipynb")
    )
    if args.self_test:
        notebooks.insert(0, BROKEN_FIXTURE)
    if not notebooks:
        print("jupyterlab check: no notebooks", file=sys.stderr)
        return 1

    text, problems = labextensions()
    print(text.strip())
    if problems and not args.skip_extension_check:
        for p in problems:
            print(f"FAIL {p}")
        return 1

    # Copies of the notebooks' folders: Run All and autosave change only the copies. The
    # copies import the checkout's probrob (editable install) and find the data beside it.
    work = Path(tempfile.mkdtemp(prefix="probrob-nb-"))
    names = []
    for nb in notebooks:
        dest = work / nb.parent.name
        if not dest.exists():
            shutil.copytree(nb.parent, dest, ignore=shutil.ignore_patterns(".ipynb_checkpoints"))
        names.append(f"{nb.parent.name}/{nb.name}")

    chromium = find_chromium(args.chromium)
    version = subprocess.run([chromium, "--version"], capture_output=True, text=True).stdout
    print(f"jupyterlab check: {version.strip() or chromium}, {len(names)} notebook(s)")
    lab = Lab(work, args.timeout)
    lab.root = work
    browser = Browser(chromium, args.timeout)
    passed = failed = 0
    try:
        for name in names:
            print(f"{name}:")
            t0 = time.monotonic()
            try:
                failures = check_notebook(browser, lab, name, args)
            except CheckError as e:
                failures = [str(e)]
            for f in failures:
                print(f"  FAIL {f}")
            if args.self_test and name == f"{BROKEN_FIXTURE.parent.name}/{BROKEN_FIXTURE.name}":
                missed = [k for k in BROKEN_FAULTS if not any(k in f for f in failures)]
                print(
                    f"  self-test: {len(BROKEN_FAULTS) - len(missed)} of {len(BROKEN_FAULTS)} "
                    f"planted faults found" + (f"; MISSED {missed}" if missed else "")
                )
                failures = [f"self-test missed {k!r}" for k in missed]
            print(f"  {'ok' if not failures else 'FAILED'} ({time.monotonic() - t0:.0f} s)")
            passed += not failures
            failed += bool(failures)
    finally:
        browser.close()
        lab.close()
        shutil.rmtree(work, ignore_errors=True)
    print(f"jupyterlab-check: {passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
