#!/usr/bin/env python3
"""Open every page of the built book in a real headless Chromium and check what a reader sees.

Every page is opened in four views, each as a first visit (empty local storage, the book's
default colour mode "auto"): 1280 px light, 1280 px dark, and a phone, 390 x 844 px at device
pixel ratio 3 with touch, light and dark (``prefers-color-scheme`` emulated; ``<html
data-theme>`` must then be that mode). In every view it checks that
  * MathJax typeset the math (``mjx-container`` elements, no ``mjx-merror``, and no raw ``$$``,
    ``\\(`` or ``\\[`` left in the visible text outside code blocks) and the images load;
  * the page is not wider than the viewport (the widest offending elements are named);
  * no paragraph starts with ``|`` (a Markdown table the parser did not recognise), and no
    cell's printout is cut into several boxes (two stream outputs side by side);
  * no display equation is wider than the text column at 1280 px (its TeX is reported; on a
    phone an equation may scroll in its own box, but must not widen the page);
  * every ``<img>`` in the article has an ``alt`` text and no ``alt`` is a file name or path;
  * every live widget canvas is shown at its bitmap's aspect ratio and its bitmap is its CSS
    size x devicePixelRatio (within 2 %: otherwise circles become ellipses or the canvas text
    is scaled), its background matches the page's colour mode (a dark canvas on a dark page, a
    light one on a light page), none of its plots is narrower than 250 CSS px (its
    ``data-plots``: on a phone a live widget stacks its panels instead of shrinking them), and
    no ``to_jshtml`` player overflows its box or the column;
  * every live widget draws in the page's colour mode, and each of its sliders, moved with the
    keyboard, changes its value, its number box and the canvas (``.ci/live_widgets_check.py``);
  * in the light views, the theme's buttons work when clicked with the mouse: on the phone ☰
    opens the site navigation and the page-contents button the page's contents; at 1280 px ☰
    collapses the primary sidebar (the main area gets wider) and a second click restores it;
  * axe-core (``.ci/node_modules``, pinned in ``.ci/package.json``) finds no violation of any
    impact, with every rule of its default run (every ``<details>`` is opened first, so the
    content a reader can unfold is checked too);
  * the page loads nothing from outside the local server, throws no JavaScript error, logs no
    console error or warning, and carries no thebe script.
At 1280 px light it also checks that the figures are readable (no figure or player image
shrunk below its own size or wider than the column; ``probrob.plotting.use_book_style`` sizes
figures for the column), that every ``to_jshtml`` player changes its frame on "Next frame" and
on "Play", and that every live widget updates within its time budget and its HTML within its
size budget (``.ci/live_widgets_check.py``).
Screenshots go to ``_build/screenshots/``: ``<page>.png`` (the whole page at 1280 px light,
continued in ``<page>-2.png``, ... past ``--max-shot-height``) and the first screen of the
other views, ``<page>-dark.png``, ``<page>-390.png``, ``<page>-390-dark.png``.

``--self-test`` first checks ``.ci/fixtures/browser/defects.html``, a page with one planted
defect of each class, and fails unless every one is reported (``make browser-check`` does).

Only the standard library is used: Chromium is driven through its DevTools protocol over a pipe
(``--remote-debugging-pipe``; the driver is ``.ci/cdp.py``), the book is served by
``http.server`` on 127.0.0.1 (or opened as file:// URLs with ``--file-urls``).

Usage:  python .ci/browser_check.py [PAGE.html ...] [--self-test] [--views 1280-light,...]
        [--findings FILE] [--min-players 0] [--file-urls] ...
PAGE is relative to the HTML folder (default: every page listed in _toc.yml; the minimum counts
of formulas, plots and players apply to the notebook chapters).
Exit status 0 only if every page passes in every view (and the self-test finds every defect).
"""

from __future__ import annotations

import argparse
import base64
import contextlib
import json
import re
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

# The DevTools-pipe driver, shared with tests/test_live_widgets.py, and the live widgets' check
# (this script's folder is on sys.path when it runs as a script).
from cdp import Browser, CheckError, Tab, find_chromium, serve
from live_widgets_check import check_live_widgets

ROOT = Path(__file__).resolve().parent.parent


# --------------------------------------------------------------------------------------------
# Pages to check


def toc_pages(root: Path) -> list[tuple[str, bool]]:
    """``(<file>.html, is_notebook)`` for every _toc.yml entry, in order."""
    text = (root / "_toc.yml").read_text(encoding="utf-8")
    files = re.findall(r"^\s*(?:-\s*)?(?:file|root)\s*:\s*[\"']?([^\"'#\s]+)", text, re.M)
    pages = []
    for f in files:
        stem = f.removesuffix(".ipynb").removesuffix(".md")
        pages.append((f"{stem}.html", (root / f"{stem}.ipynb").is_file()))
    return pages


# --------------------------------------------------------------------------------------------
# The checks, as JavaScript run in the page

JS_MATHJAX_READY = """
(async () => {
  const t0 = Date.now();
  while (!(window.MathJax && MathJax.startup && MathJax.startup.promise)) {
    if (Date.now() - t0 > %d) return "MathJax was not loaded";
    await new Promise(r => setTimeout(r, 100));
  }
  await MathJax.startup.promise;
  if (MathJax.typesetPromise) await MathJax.typesetPromise();
  return "ok";
})()
"""

JS_SURVEY = r"""
(() => {
  const SKIP = new Set(["PRE", "CODE", "SCRIPT", "STYLE", "TEXTAREA", "MJX-CONTAINER",
                        "MJX-ASSISTIVE-MML", "NOSCRIPT", "TEMPLATE"]);
  const walker = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT, {
    acceptNode(node) {
      for (let p = node.parentElement; p; p = p.parentElement) {
        if (SKIP.has(p.tagName.toUpperCase())) return NodeFilter.FILTER_REJECT;
      }
      return NodeFilter.FILTER_ACCEPT;
    }
  });
  const raw = [];
  for (let n = walker.nextNode(); n; n = walker.nextNode()) {
    const t = n.nodeValue;
    for (const pat of ["$$", "\\(", "\\[", "\\begin{"]) {
      const i = t.indexOf(pat);
      if (i >= 0) raw.push(t.slice(Math.max(0, i - 40), i + 60).replace(/\s+/g, " "));
    }
  }
  const imgs = Array.from(document.images);
  const ok = im => im.complete && im.naturalWidth > 0 && im.naturalHeight > 0;
  const plots = imgs.filter(im => im.closest(".cell_output") && !im.id.startsWith("_anim_img"));
  return {
    mathElements: document.querySelectorAll(".math").length,
    mathUntypeset: Array.from(document.querySelectorAll(".math"))
      .filter(el => !el.querySelector("mjx-container")).length,
    mjx: document.querySelectorAll("mjx-container").length,
    mjxErrors: Array.from(document.querySelectorAll("mjx-merror"))
      .map(e => e.getAttribute("data-mjx-error") || e.textContent).slice(0, 5),
    raw: raw.slice(0, 5),
    rawCount: raw.length,
    images: imgs.length,
    broken: imgs.filter(im => !ok(im)).map(im => (im.getAttribute("src") || "").slice(0, 80)),
    plots: plots.length,
    plotsOk: plots.filter(ok).length,
    players: document.querySelectorAll('img[id^="_anim_img"]').length,
    height: Math.ceil(document.documentElement.scrollHeight),
  };
})()
"""

# Figure readability: the displayed size of every plot and player image against its natural
# (intended) size and against the width of the text column; alt texts and slider labels.
JS_FIGURES = r"""
(() => {
  const article = document.querySelector("article.bd-article") || document.querySelector("main")
    || document.body;
  const style = getComputedStyle(article);
  const column = article.clientWidth - parseFloat(style.paddingLeft)
    - parseFloat(style.paddingRight);
  const figures = Array.from(document.querySelectorAll(".cell_output img"))
    .filter(im => im.complete && im.naturalWidth > 0)
    .map((im, k) => {
      const r = im.getBoundingClientRect();
      return {k: k, player: im.id.startsWith("_anim_img"), natural: im.naturalWidth,
              shown: Math.round(r.width * 10) / 10, scale: r.width / im.naturalWidth,
              src: (im.getAttribute("src") || "").slice(0, 60)};
    });
  const unlabelled = Array.from(document.querySelectorAll(".animation input[type=range]"))
    .filter(el => !el.getAttribute("aria-label") && !(el.labels && el.labels.length))
    .map(el => el.id.slice(0, 30));
  return {column: Math.round(column), figures: figures, unlabelled: unlabelled};
})()
"""

# A cheap fingerprint of a (data:) URL, so frames can be compared without shipping megabytes.
JS_PLAYER_STATE = r"""
((k) => {
  const img = document.querySelectorAll('img[id^="_anim_img"]')[k];
  const s = img.getAttribute("src") || "";
  let h = 0;
  for (let i = 0; i < s.length; i += 7) h = (h * 31 + s.charCodeAt(i)) | 0;
  const slider = img.closest(".animation").querySelector('input[type="range"]');
  return {len: s.length, hash: h, frame: slider ? Number(slider.value) : null,
          frames: slider ? Number(slider.max) + 1 : null,
          loaded: img.complete && img.naturalWidth > 0};
})(%d)
"""

JS_BUTTON_CENTER = r"""
((k, title) => {
  const anim = document.querySelectorAll('img[id^="_anim_img"]')[k].closest(".animation");
  const b = anim && anim.querySelector('button[title="' + title + '"]');
  if (!b) return null;
  b.scrollIntoView({block: "center"});
  const r = b.getBoundingClientRect();
  return {x: r.left + r.width / 2, y: r.top + r.height / 2};
})(%d, %s)
"""


# Layout and rendering checks of one view (run after every <details> was opened, so that the
# content a reader can unfold is measured too). %(width)d is the emulated viewport width.
JS_LAYOUT = r"""
(() => {
  const W = %(width)d;
  const article = document.querySelector("article.bd-article") || document.querySelector("main")
    || document.body;
  const ast = getComputedStyle(article);
  const ar = article.getBoundingClientRect();
  const colLeft = ar.left + parseFloat(ast.paddingLeft);
  const column = article.clientWidth - parseFloat(ast.paddingLeft) - parseFloat(ast.paddingRight);
  const colRight = colLeft + column;
  const snip = (t, n) => (t || "").replace(/\s+/g, " ").trim().slice(0, n);
  const describe = (el) => {
    const cls = (typeof el.className === "string" ? el.className : "").trim().split(/\s+/)
      .filter(Boolean).slice(0, 3).join(".");
    return el.tagName.toLowerCase() + (el.id ? "#" + el.id.slice(0, 30) : "") + (cls ? "." + cls : "");
  };
  const shown = (el) => { const r = el.getBoundingClientRect(); return r.width > 0 && r.height > 0; };

  // (a) the page wider than the viewport: the leaf-most elements that reach past its right edge
  // (not inside a scrolling or clipping box, nor fixed), the widest first.
  const pageWidth = document.documentElement.scrollWidth;
  let wide = [];
  if (pageWidth > W + 1) {
    const free = (el) => {
      for (let q = el; q && q !== document.documentElement; q = q.parentElement) {
        const cs = getComputedStyle(q);
        if (cs.position === "fixed") return false;
        if (q !== el && cs.overflowX !== "visible") return false;
      }
      return true;
    };
    const over = Array.from(document.body.querySelectorAll("*")).filter((el) => {
      const r = el.getBoundingClientRect();
      return r.width > 0 && r.right > W + 1;
    }).filter(free);
    const parents = new Set();
    for (const el of over) for (let q = el.parentElement; q; q = q.parentElement) parents.add(q);
    // each leaf offender reported as the nearest block a reader would recognise
    const BLOCK = "code, pre, table, mjx-container, img, canvas, svg, iframe, .animation, "
      + ".probrob-live, figure, .cell_output, .highlight";
    wide = Array.from(new Set(over.filter((el) => !parents.has(el))
      .map((el) => el.closest(BLOCK) || el)))
      .map((el) => ({el: describe(el), text: snip(el.textContent, 60),
                     width: Math.round(el.getBoundingClientRect().width),
                     right: Math.round(el.getBoundingClientRect().right)}))
      .sort((x, y) => y.right - x.right);
    // one entry per element description and text
    const seen = new Set();
    wide = wide.filter((w) => { const k = w.el + w.text; if (seen.has(k)) return false;
                                seen.add(k); return true; }).slice(0, 6);
  }

  // (b) raw Markdown tables: a paragraph whose text starts with "|"
  const rawTables = Array.from(document.querySelectorAll("article p, main p"))
    .filter((p) => (p.innerText || p.textContent || "").trim().startsWith("|"))
    .map((p) => snip(p.innerText || p.textContent, 90));

  // (b') a cell's printout cut into boxes: two stream outputs side by side in one cell output
  // (myst-nb shows each stream output of the notebook in its own box unless nb_merge_streams)
  const splitStreams = Array.from(document.querySelectorAll(".cell_output"))
    .filter((o) => Array.from(o.children).some((c, k, all) => k > 0
      && c.matches(".output.stream") && all[k - 1].matches(".output.stream")))
    .map((o) => snip(o.innerText || o.textContent, 90));

  // (c) display equations: the typeset width against the column; the TeX source for the report
  const tex = new Map();
  try {
    for (const item of MathJax.startup.document.math) tex.set(item.typesetRoot, item.math);
  } catch (e) {}
  const equations = Array.from(document.querySelectorAll('mjx-container[display="true"]'))
    .map((c, k) => {
      const m = c.querySelector("mjx-math") || c;
      const w = m.getBoundingClientRect().width;
      const mml = c.querySelector("mjx-assistive-mml");
      return {k: k, shown: w > 0, width: Math.round(w * 10) / 10,
              scrolls: c.scrollWidth > c.clientWidth + 1,
              right: Math.round(c.getBoundingClientRect().right),
              tex: snip(tex.get(c) || (mml && mml.textContent) || c.textContent, 90)};
    });

  // (d) images: no alt text (in the article), or an alt that is a file name or path (anywhere)
  const fileAlt = /(\.(png|jpe?g|svg|gif|webp)\s*$)|_images\//i;
  const noAlt = Array.from(document.querySelectorAll("article img"))
    .filter((im) => !(im.getAttribute("alt") || "").trim())
    .map((im) => (im.id || im.getAttribute("src") || "").slice(0, 60));
  const fileNameAlt = Array.from(document.images)
    .filter((im) => fileAlt.test((im.getAttribute("alt") || "").trim()))
    .map((im) => im.getAttribute("alt").slice(0, 80));

  // (e) live widget canvases: displayed aspect = the bitmap's, bitmap = CSS size x DPR; the
  // background (the bitmap's top-left pixel over the CSS background behind it) and the plots'
  // sizes the widget lays out (data-plots, CSS px)
  const dpr = window.devicePixelRatio || 1;
  const behind = (el) => {
    for (let e = el; e; e = e.parentElement) {
      const m = getComputedStyle(e).backgroundColor.match(/[\d.]+/g);
      if (m && (m.length < 4 || Number(m[3]) > 0)) return m.slice(0, 3).map(Number);
    }
    return [255, 255, 255];
  };
  const background = (c) => {
    let bg = behind(c);
    try {
      const px = c.getContext("2d").getImageData(0, 0, 1, 1).data;
      bg = bg.map((b, i) => Math.round(px[i] * px[3] / 255 + b * (1 - px[3] / 255)));
    } catch (e) {}
    return bg;
  };
  const canvases = Array.from(document.querySelectorAll(".probrob-live canvas, article canvas"))
    .filter((c, i, all) => all.indexOf(c) === i)
    .map((c) => {
      const r = c.getBoundingClientRect();
      const live = c.closest(".probrob-live");
      let plots = null;
      try { plots = JSON.parse(c.dataset.plots || "null"); } catch (e) { plots = "unreadable"; }
      return {id: (live && live.id) || describe(c), shown: r.width > 0 && r.height > 0,
              cssW: Math.round(r.width * 10) / 10, cssH: Math.round(r.height * 10) / 10,
              bmpW: c.width, bmpH: c.height, dpr: dpr, bg: background(c), plots: plots};
    });

  // (e) players (to_jshtml): the content inside its box and the box inside the column
  const players = Array.from(document.querySelectorAll(".animation")).map((a, k) => {
    const r = a.getBoundingClientRect();
    let right = r.right, widest = "";
    for (const d of a.querySelectorAll("*")) {
      const dr = d.getBoundingClientRect();
      if (dr.width > 0 && dr.right > right + 0.5) { right = dr.right; widest = describe(d); }
    }
    return {k: k, shown: r.width > 0, box: Math.round(r.width * 10) / 10,
            content: Math.round((right - r.left) * 10) / 10, widest: widest,
            overflowBox: Math.round((right - r.right) * 10) / 10,
            overflowColumn: Math.round((Math.max(right, r.right) - colRight) * 10) / 10,
            scrolls: a.scrollWidth > a.clientWidth + 1};
  });
  return {column: Math.round(column * 10) / 10, pageWidth: pageWidth,
          innerWidth: window.innerWidth, wide: wide, rawTables: rawTables,
          splitStreams: splitStreams,
          equations: equations, noAlt: noAlt, fileNameAlt: fileNameAlt, canvases: canvases,
          players: players, images: document.images.length,
          theme: document.documentElement.dataset.theme || "",
          mode: document.documentElement.dataset.mode || ""};
})()
"""

# Open every collapsed <details> (dropdowns, hidden cells); return how many were opened.
JS_OPEN_DETAILS = r"""
(() => {
  const closed = Array.from(document.querySelectorAll("details:not([open])"));
  closed.forEach((d) => { d.open = true; d.setAttribute("data-probrob-opened", ""); });
  return new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(
    () => r(closed.length))));
})()
"""

JS_CLOSE_DETAILS = r"""
document.querySelectorAll("details[data-probrob-opened]").forEach((d) => {
  d.open = false; d.removeAttribute("data-probrob-opened"); })
"""

JS_LIVE_READY = r"""
(async () => {
  const t0 = Date.now();
  const pending = () => Array.from(document.querySelectorAll(".probrob-live"))
    .filter((el) => el.getAttribute("data-ready") !== "true").length;
  while (pending() && Date.now() - t0 < %d) await new Promise((r) => setTimeout(r, 100));
  await new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)));
  return pending();
})()
"""

# axe-core (injected before): every rule of its default run, violations only.
JS_AXE = r"""
(async () => {
  if (!window.axe) return {error: "axe-core is not loaded in the page"};
  const res = await axe.run(document, {resultTypes: ["violations"]});
  return {version: axe.version, violations: res.violations.map((v) => ({
    id: v.id, impact: v.impact || "unknown", help: v.help, count: v.nodes.length,
    targets: v.nodes.slice(0, 3).map((n) => n.target.map(String).join(" ").slice(0, 120))}))};
})()
"""

# The sidebars and their toggles. A toggle counts when a reader can see and hit it: a non-empty
# box whose centre hit-tests to the toggle itself.
JS_TOGGLES = r"""
((kind) => Array.from(document.querySelectorAll("." + kind + "-toggle")).map((b, k) => {
  const r = b.getBoundingClientRect();
  const cs = getComputedStyle(b);
  const x = r.left + r.width / 2, y = r.top + r.height / 2;
  const hit = document.elementFromPoint(x, y);
  const ok = r.width > 0 && r.height > 0 && cs.visibility === "visible" && x >= 0 && y >= 0
    && x < innerWidth && y < innerHeight && hit && (hit === b || b.contains(hit));
  return {k: k, visible: !!ok, x: x, y: y,
          label: (b.getAttribute("aria-label") || b.getAttribute("title") || b.className)
            .slice(0, 40)};
}).filter((t) => t.visible))(%s)
"""

# How much of the primary/secondary sidebar a reader sees: the widest visible candidate (the
# sidebar itself or the theme's modal that shows it), its visible width within the viewport,
# whether its centre hit-tests to it, and how many of its links are in view; the width of the
# main area (article + secondary sidebar).
JS_SIDEBAR = r"""
((kind) => {
  const cands = Array.from(document.querySelectorAll(
    "#pst-" + kind + "-sidebar-modal, .bd-sidebar-" + kind + ", #pst-" + kind + "-sidebar"));
  let best = {width: 0, hit: false, links: 0, what: ""};
  for (const c of cands) {
    const cs = getComputedStyle(c);
    if (cs.display === "none" || cs.visibility !== "visible" || Number(cs.opacity) < 0.1) continue;
    if (c.tagName === "DIALOG" && !c.open) continue;
    const r = c.getBoundingClientRect();
    const left = Math.max(0, r.left), right = Math.min(innerWidth, r.right);
    const top = Math.max(0, r.top), bottom = Math.min(innerHeight, r.bottom);
    const w = right - left, h = bottom - top;
    if (w <= 0 || h <= 0) continue;
    const hitEl = document.elementFromPoint((left + right) / 2, (top + bottom) / 2);
    const hit = !!hitEl && (c.contains(hitEl) || hitEl.contains(c));
    const links = Array.from(c.querySelectorAll("a")).filter((a) => {
      const ar = a.getBoundingClientRect();
      return ar.width > 0 && ar.height > 0 && ar.right > 0 && ar.left < innerWidth
        && ar.bottom > 0 && ar.top < innerHeight;
    }).length;
    if (hit && w > best.width) best = {width: Math.round(w), hit: hit, links: links,
                                       what: c.id || c.className.split(" ")[0]};
  }
  const main = document.querySelector(".bd-main") || document.querySelector("main");
  const toc = document.querySelectorAll(
    ".bd-sidebar-secondary nav a, .bd-sidebar-secondary .bd-toc-nav a").length;
  return {sidebar: best, main: main ? Math.round(main.getBoundingClientRect().width) : 0,
          tocLinks: toc};
})(%s)
"""

JS_CLOSE_SIDEBARS = r"""
(() => {
  document.querySelectorAll("dialog[open]").forEach((d) => d.close());
  document.querySelectorAll("input.sidebar-toggle, input[id$='sidebar-checkbox']")
    .forEach((i) => { i.checked = false; });
  return new Promise((r) => setTimeout(r, 300));
})()
"""


class Page(Tab):
    """A chapter page in the browser's first target (sending and page scripts from ``Tab``)."""

    def __init__(self, browser: Browser, session: str):
        super().__init__(browser, target=None, session=session)

    def click_at(self, x: float, y: float) -> None:
        """A real mouse click (moved, pressed, released) at viewport point (x, y)."""
        for kind in ("mouseMoved", "mousePressed", "mouseReleased"):
            self.send(
                "Input.dispatchMouseEvent",
                {"type": kind, "x": x, "y": y, "button": "left", "clickCount": 1},
            )

    def click_button(self, player: int, title: str) -> None:
        pos = self.js(JS_BUTTON_CENTER % (player, json.dumps(title)))
        if pos is None:
            raise CheckError(f'player {player + 1}: no "{title}" button')
        time.sleep(0.1)  # let the scroll settle
        self.click_at(pos["x"], pos["y"])


# --------------------------------------------------------------------------------------------
# Views: a desktop and a phone, each in both colour modes. Every view is a first visit (empty
# local storage) with the book's default mode (auto), so the mode follows prefers-color-scheme.


@dataclass(frozen=True)
class View:
    width: int
    mode: str  # "light" or "dark"

    @property
    def mobile(self) -> bool:
        return self.width < 800

    @property
    def height(self) -> int:
        return 844 if self.mobile else 1600

    @property
    def scale(self) -> int:
        return 3 if self.mobile else 1

    @property
    def full(self) -> bool:
        """The view that also clicks the players and moves the live widgets' sliders."""
        return self == VIEWS[0]

    @property
    def name(self) -> str:
        return f"{self.width} {self.mode}"

    @property
    def suffix(self) -> str:
        return ("" if self.width == 1280 else f"-{self.width}") + (
            "-dark" if self.mode == "dark" else ""
        )


VIEWS = [View(1280, "light"), View(1280, "dark"), View(390, "light"), View(390, "dark")]
IMPACTS = ["critical", "serious", "moderate", "minor"]


def set_viewport(p: Page, view: View, height: int | None = None) -> None:
    p.send(
        "Emulation.setDeviceMetricsOverride",
        {
            "width": view.width,
            "height": height or view.height,
            "deviceScaleFactor": view.scale,
            "mobile": view.mobile,
        },
    )


class Findings:
    """The failures of one page view, each with its defect class (for the summary and the
    self-test) and a precise message."""

    def __init__(self, view: View):
        self.view = view
        self.items: list[tuple[str, str]] = []

    def add(self, cls: str, message: str) -> None:
        self.items.append((cls, message))

    def __bool__(self) -> bool:
        return bool(self.items)


def check_view(
    browser: Browser,
    base_url: str,
    page: str,
    view: View,
    shots: Path | None,
    args,
    axe_js: str,
    notebook: bool = True,
) -> tuple[Findings, dict]:
    """Open ``page`` as a first visit in ``view`` and run the checks; return the findings and
    the counts for the summary."""
    f = Findings(view)
    stats: dict = {"axe": dict.fromkeys(IMPACTS, 0)}
    url = f"{base_url}/{page}"
    target = browser.send("Target.createTarget", {"url": "about:blank"})["targetId"]
    session = browser.send("Target.attachToTarget", {"targetId": target, "flatten": True})[
        "sessionId"
    ]
    p = Page(browser, session)
    tag = f"  [{view.name}]"
    try:
        _check_view(
            p,
            browser,
            session,
            base_url,
            url,
            page,
            view,
            shots,
            args,
            axe_js,
            notebook,
            f,
            stats,
            tag,
        )
    except CheckError as e:
        f.add("browser", str(e))
    finally:
        with contextlib.suppress(CheckError):
            browser.send("Target.closeTarget", {"targetId": target})
        with browser.cond:
            browser.events = [e for e in browser.events if e.get("sessionId") != session]
    return f, stats


def _check_view(
    p, browser, session, base_url, url, page, view, shots, args, axe_js, notebook, f, stats, tag
):
    for domain in ("Page", "Runtime", "Network", "Log"):
        p.send(f"{domain}.enable")
    set_viewport(p, view)
    if view.mobile:
        p.send("Emulation.setTouchEmulationEnabled", {"enabled": True, "maxTouchPoints": 5})
    p.send(
        "Emulation.setEmulatedMedia",
        {"features": [{"name": "prefers-color-scheme", "value": view.mode}]},
    )
    # Every view is a first visit (no colour mode stored by an earlier page or view).
    with contextlib.suppress(CheckError):
        p.send(
            "Storage.clearDataForOrigin",
            {
                "origin": base_url if base_url.startswith("http") else "file://",
                "storageTypes": "local_storage,session_storage",
            },
        )
    with browser.cond:
        mark = len(browser.events)
    nav = p.send("Page.navigate", {"url": url})
    if nav.get("errorText"):
        raise CheckError(f"{page}: cannot load {url}: {nav['errorText']}")
    browser.wait_event("Page.loadEventFired", session, args.timeout, since=mark)

    # Sphinx loads MathJax only on pages that contain math.
    if p.js('document.querySelectorAll(".math").length') > 0:
        state = p.js(JS_MATHJAX_READY % int(args.timeout * 1000), timeout=args.timeout + 10)
        if state != "ok":
            f.add("math", state)
    not_ready = p.js(JS_LIVE_READY % 10000, timeout=30)
    if view.full:
        time.sleep(0.5)  # the players start from a setTimeout(0) after load
    info = p.js(JS_SURVEY)

    # Math and images (every view: a phone must typeset and load them too)
    if view.full:
        print(
            f"{tag} math: {info['mjx']} MathJax-typeset formulas "
            f"({info['mathElements']} math elements, {info['mathUntypeset']} not typeset, "
            f"{len(info['mjxErrors'])} TeX errors, {info['rawCount']} raw delimiters in the text)"
        )
        print(
            f"{tag} images: {info['plots']} plot images in cell outputs "
            f"({info['plotsOk']} rendered), {info['images']} <img> on the page, "
            f"{len(info['broken'])} broken"
        )
    if notebook and info["mjx"] < args.min_math:
        f.add("math", f"{info['mjx']} typeset formulas, expected >= {args.min_math}")
    if info["mathUntypeset"]:
        f.add("math", f"{info['mathUntypeset']} math elements were not typeset")
    if info["mjxErrors"]:
        f.add("math", f"TeX errors {info['mjxErrors']}")
    if info["rawCount"]:
        f.add("math", f"raw TeX left in the visible text: {info['raw']}")
    if notebook and info["plotsOk"] < args.min_images:
        f.add("images", f"{info['plotsOk']} rendered plots, expected >= {args.min_images}")
    if info["broken"]:
        f.add("images", f"broken {info['broken'][:5]}")
    stats["formulas"] = info["mjx"]

    # Figure readability at the desktop width (on a phone a figure is meant to shrink)
    if not view.mobile:
        fig = p.js(JS_FIGURES)
        figures = fig["figures"]
        if figures and view.full:
            smallest = min(figures, key=lambda x: x["scale"])
            widest = max(figures, key=lambda x: x["natural"])
            print(
                f"{tag} figures: {len(figures)} images (plots and players) in a "
                f"{fig['column']}-px column; widest {widest['natural']} px; smallest display "
                f"scale {smallest['scale']:.3f} (image {smallest['k'] + 1}); "
                f"{len(fig['unlabelled'])} unlabelled sliders"
            )
        shrunk = [x for x in figures if x["scale"] < args.min_figure_scale]
        if shrunk:
            f.add(
                "figure-size",
                f"{len(shrunk)} shrunk by the page below {args.min_figure_scale:.0%} of their "
                "size (their text shrinks with them): "
                + ", ".join(
                    f"image {x['k'] + 1} {x['natural']} px shown at {x['shown']}"
                    for x in shrunk[:5]
                ),
            )
        # An image up to 1/min-figure-scale of the column is shrunk by the page no more than
        # the shrink check allows (bbox_inches="tight" may add a few pixels to a column-wide
        # figure); a wider one, or a player (which overflows instead of shrinking), fails.
        too_wide = [x for x in figures if x["natural"] > fig["column"] / args.min_figure_scale]
        if too_wide:
            f.add(
                "figure-size",
                f"{len(too_wide)} wider than the {fig['column']}-px column (by more than "
                f"{1 / args.min_figure_scale - 1:.0%}): "
                + ", ".join(f"image {x['k'] + 1} ({x['natural']} px)" for x in too_wide[:5]),
            )
        if fig["unlabelled"]:
            f.add("accessibility", f"player sliders without a label {fig['unlabelled'][:5]}")

    # Players clicked: once per page, at the desktop light view
    if view.full:
        check_players(p, info, f, tag)
        if notebook and info["players"] < args.min_players:
            f.add(
                "players",
                f"{info['players']} to_jshtml players, expected >= {args.min_players}",
            )
    # Live widgets: their mode and every slider in every view; time and size in the full one
    if not_ready:
        f.add("live-widget", f"{not_ready} live widgets not ready (no data-ready) after 10 s")
    else:
        live_lines, live_failures = check_live_widgets(p, full=view.full)
        for line in live_lines:
            print(f"{tag} {line}")
        for x in live_failures:
            f.add("live-widget", x)

    # Layout and rendering (every view), with every <details> opened
    opened = p.js(JS_OPEN_DETAILS)
    lay = p.js(JS_LAYOUT % {"width": view.width})
    check_layout(lay, view, f, stats)

    # axe-core, with the details still open (their content is checked too)
    p.js(axe_js + "\n;true", timeout=60)
    axe = p.js(JS_AXE, timeout=args.timeout * 3)
    if axe.get("error"):
        f.add("axe", axe["error"])
    else:
        stats["axe_version"] = axe["version"]
        for v in axe["violations"]:
            impact = v["impact"] if v["impact"] in stats["axe"] else "minor"
            stats["axe"][impact] += 1
            f.add(
                "axe",
                f"{v['impact']} {v['id']} ({v['count']} elements: {v['help']}), e.g. "
                + "; ".join(v["targets"]),
            )
    p.js(JS_CLOSE_DETAILS)

    a = stats["axe"]
    print(
        f"{tag} page {lay['pageWidth']} px wide in a {view.width}-px viewport "
        f"(theme {lay['theme'] or '?'}); column {lay['column']} px; "
        f"{stats['formulas']} formulas, {stats['equations']} display equations "
        f"({stats['eq_wide']} too wide, {stats['eq_scroll']} scroll in their box, "
        f"{stats['eq_hidden']} hidden); {lay['images']} images ({stats['bad_alt']} bad alts); "
        f"{stats['raw_tables']} raw tables; {stats['canvases']} canvases "
        f"({stats['canvas_bad']} failing); {stats['players']} players "
        f"({stats['players_over']} overflow); {opened} details opened; "
        f"axe {axe.get('version', '?')}: " + ", ".join(f"{a[k]} {k}" for k in IMPACTS)
    )

    # Screenshots: the whole page at the desktop light view (in parts of --max-shot-height),
    # the first screen at the other views (none of the self-test's fixture)
    if shots is not None:
        take_screenshots(p, page, view, info, shots, args, tag)

    # The theme's buttons (light views: the colour mode does not change what they do)
    if view.mode == "light":
        check_toggles(p, view, f, tag)

    check_console(p, browser, session, base_url, f, tag, view)


def take_screenshots(p: Page, page: str, view: View, info: dict, shots: Path, args, tag: str):
    shots.mkdir(parents=True, exist_ok=True)
    stem = Path(page).stem + view.suffix
    if view.full:
        height = min(info["height"], args.max_shot_height)
        set_viewport(p, view, height)
        parts = list(enumerate(range(0, info["height"], height)))
    else:
        parts = [(0, 0)]
        height = view.height
    for part, top in parts:
        if view.full or top:
            p.js(f"window.scrollTo(0, {top})")
            time.sleep(0.5)
        shot = p.send("Page.captureScreenshot", {"format": "png"}, timeout=120)
        out = shots / (stem + (f"-{part + 1}" if part else "") + ".png")
        out.write_bytes(base64.b64decode(shot["data"]))
        if view.full or args.verbose:
            print(
                f"{tag} screenshot: "
                f"{out.relative_to(ROOT) if out.is_relative_to(ROOT) else out} "
                f"({view.width}x{height}, from y = {top})"
            )
    set_viewport(p, view)
    p.js("window.scrollTo(0, 0)")


def check_players(p: Page, info: dict, f: Findings, tag: str) -> None:
    for k in range(info["players"]):
        # Step: first frame, then "Next frame" must show a different image (frame 1).
        p.click_button(k, "First frame")
        time.sleep(0.2)
        s0 = p.js(JS_PLAYER_STATE % k)
        p.click_button(k, "Next frame")
        time.sleep(0.3)
        s1 = p.js(JS_PLAYER_STATE % k)
        stepped = (s0["hash"], s0["len"]) != (s1["hash"], s1["len"]) and s1["frame"] == 1
        # Play: from the first frame again, the image must change within a few seconds (works
        # in any repetition mode and at any frame interval up to ~5 s).
        p.click_button(k, "First frame")
        time.sleep(0.2)
        p.click_button(k, "Play")
        deadline = time.monotonic() + 6.0
        while True:
            time.sleep(0.2)
            s2 = p.js(JS_PLAYER_STATE % k)
            played = (s2["hash"], s2["len"]) != (s0["hash"], s0["len"])
            if played or time.monotonic() > deadline:
                break
        p.click_button(k, "Pause")
        ok = s0["loaded"] and s1["loaded"] and s2["loaded"] and stepped and played
        print(
            f"{tag} player {k + 1}: {s0['frames']} frames; next-frame button "
            f"{'changed' if stepped else 'did NOT change'} the image (frame {s0['frame']} -> "
            f"{s1['frame']}); play {'advanced' if played else 'did NOT advance'} it "
            f"(frame 0 -> {s2['frame']})"
        )
        if not ok:
            f.add("players", f"player {k + 1}: frames do not change (or do not load)")


def check_layout(lay: dict, view: View, f: Findings, stats: dict) -> None:
    """The defect classes a-e of issue 17 on one view's layout survey (``JS_LAYOUT``)."""
    # (a) the page wider than the viewport
    if lay["pageWidth"] > view.width + 1:
        f.add(
            "page-width",
            f"the page is {lay['pageWidth']} px wide in a {view.width}-px viewport; widest: "
            + "; ".join(
                f"{w['el']} {w['width']} px to x = {w['right']} ({w['text']!r})"
                for w in lay["wide"]
            ),
        )
    # (b) raw Markdown tables
    stats["raw_tables"] = len(lay["rawTables"])
    for t in lay["rawTables"]:
        f.add("raw-table", f"a paragraph starts with '|' (a table not parsed): {t!r}")
    # (b') one printout, one box
    for t in lay["splitStreams"]:
        f.add("split-stream", f"a cell's printout is cut into several boxes: {t!r}")
    # (c) display equations: not wider than the column at the desktop width; on a phone one
    # may scroll in its own box (the page width check above catches one that widens the page)
    eqs = lay["equations"]
    shown = [e for e in eqs if e["shown"]]
    wide = [e for e in shown if e["width"] > lay["column"] + 1]
    stats.update(
        equations=len(eqs),
        eq_hidden=len(eqs) - len(shown),
        eq_scroll=sum(e["scrolls"] for e in shown),
        eq_wide=0,
    )
    if not view.mobile:
        stats["eq_wide"] = len(wide)
        for e in wide:
            f.add(
                "equation-width",
                f"display equation {e['k'] + 1} is {e['width']:.0f} px wide in the "
                f"{lay['column']:.0f}-px column: {e['tex']!r}",
            )
    # (d) alt texts
    stats["bad_alt"] = len(lay["noAlt"]) + len(lay["fileNameAlt"])
    if lay["noAlt"]:
        f.add("alt-text", f"{len(lay['noAlt'])} images without alt text: {lay['noAlt'][:5]}")
    for alt in lay["fileNameAlt"][:8]:
        f.add("alt-text", f"an image's alt is a file name: {alt!r}")
    if len(lay["fileNameAlt"]) > 8:
        f.add("alt-text", f"... {len(lay['fileNameAlt']) - 8} more alts that are file names")
    # (e) live widget canvases: same aspect as the bitmap; bitmap = CSS size x DPR (2 %)
    stats["canvases"] = len(lay["canvases"])
    stats["canvas_bad"] = 0
    for c in lay["canvases"]:
        if not c["shown"]:
            continue
        want_w, want_h = c["cssW"] * c["dpr"], c["cssH"] * c["dpr"]
        aspect = (c["cssW"] / c["cssH"]) / (c["bmpW"] / c["bmpH"]) - 1
        scale = c["bmpW"] / want_w
        desc = (
            f"{c['id']}: a {c['bmpW']}x{c['bmpH']} bitmap shown at {c['cssW']:g}x{c['cssH']:g} "
            f"CSS px (x DPR {c['dpr']:g} = {want_w:.0f}x{want_h:.0f})"
        )
        bad = False
        if abs(aspect) > 0.02:
            f.add("canvas-aspect", f"{desc}: the aspect ratio is off by {aspect:+.1%}")
            bad = True
        if abs(scale - 1) > 0.02:
            f.add(
                "canvas-scale",
                f"{desc}: drawn at {scale:.2f}x the displayed resolution "
                f"(bitmap width must be round(CSS width x DPR) within 2 %)",
            )
            bad = True
        bad |= check_canvas_page(c, view, f, desc)
        stats["canvas_bad"] += bad
    # (e) players: the content inside its box, the box inside the column
    stats["players"] = len(lay["players"])
    stats["players_over"] = 0
    for pl in lay["players"]:
        if not pl["shown"]:
            continue
        msgs = []
        if pl["overflowBox"] > 1 or pl["scrolls"]:
            msgs.append(
                f"its content ({pl['content']:g} px, widest {pl['widest']}) overflows its "
                f"{pl['box']:g}-px box by {pl['overflowBox']:g} px"
            )
        if pl["overflowColumn"] > 1:
            msgs.append(
                f"it reaches {pl['overflowColumn']:g} px past the {lay['column']:g}-px column"
            )
        if msgs:
            stats["players_over"] += 1
            f.add("player-overflow", f"player {pl['k'] + 1}: " + "; ".join(msgs))
    # the colour mode really applied (the book's default mode is auto)
    if lay["theme"] != view.mode:
        f.add(
            "colour-mode",
            f"<html data-theme> is {lay['theme']!r} (data-mode {lay['mode']!r}) on a first visit "
            f"with prefers-color-scheme: {view.mode}; expected {view.mode!r}",
        )


#: The narrowest a live widget's plot may be, in CSS px (its runtime stacks panels and moves a
#: colour bar or a legend below the plot rather than shrink the plot below it).
MIN_PLOT_CSS_PX = 250


def check_canvas_page(c: dict, view: View, f: Findings, desc: str) -> bool:
    """A canvas against the page: its background in the view's colour mode (luminance below
    half on a dark page, above on a light one) and its plots at least MIN_PLOT_CSS_PX wide."""
    bad = False
    if c.get("bg") is not None:
        r, g, b = c["bg"]
        mode = "dark" if 0.2126 * r + 0.7152 * g + 0.0722 * b < 128 else "light"
        if mode != view.mode:
            f.add(
                "canvas-background",
                f"{desc}: its background rgb({r}, {g}, {b}) is {mode} on a {view.mode} page",
            )
            bad = True
    plots = c.get("plots")
    if plots is not None:
        widths = [p[0] for p in plots] if isinstance(plots, list) else []
        if not widths or min(widths) < MIN_PLOT_CSS_PX:
            f.add(
                "plot-width",
                f"{desc}: plots {plots} (width, height in CSS px): one is narrower than "
                f"{MIN_PLOT_CSS_PX} px at a {view.width}-px viewport",
            )
            bad = True
    return bad


def check_toggles(p: Page, view: View, f: Findings, tag: str) -> None:
    """(f) The theme's sidebar buttons, clicked with the mouse at their centre.

    Phone: every visible primary toggle (☰) opens the site navigation (in view, at least half
    the viewport wide, its links visible) and, on a page with contents, every visible
    secondary toggle opens them. Desktop: ☰ collapses the primary sidebar (the main area gets
    wider) and a second click restores it."""
    notes = []
    if view.mobile:
        for kind, what in (("primary", "site navigation (☰)"), ("secondary", "page contents")):
            before = p.js(JS_SIDEBAR % json.dumps(kind))
            if kind == "secondary" and not before["tocLinks"]:
                notes.append("no page contents")
                continue
            toggles = p.js(JS_TOGGLES % json.dumps(kind))
            if not toggles:
                f.add("sidebar-toggle", f"no visible {kind}-sidebar toggle for the {what}")
                continue
            for t in toggles:
                p.js(JS_CLOSE_SIDEBARS)
                p.click_at(t["x"], t["y"])
                time.sleep(0.6)  # the theme's transition
                after = p.js(JS_SIDEBAR % json.dumps(kind))
                sb = after["sidebar"]
                ok = sb["width"] >= view.width / 2 and sb["links"] > 0
                notes.append(
                    f"{kind} toggle {t['label']!r}: {'opens' if ok else 'does NOT open'} the "
                    f"{what} ({sb['width']} px visible, {sb['links']} links in view)"
                )
                if not ok:
                    f.add(
                        "sidebar-toggle",
                        f"clicking the {kind}-sidebar toggle {t['label']!r} does not open the "
                        f"{what}: afterwards {sb['width']} px of it are visible in the "
                        f"{view.width}-px viewport with {sb['links']} links in view (want >= "
                        f"{view.width // 2} px and links)",
                    )
                p.key("Escape", "Escape", 27)
                p.js(JS_CLOSE_SIDEBARS)
    else:
        before = p.js(JS_SIDEBAR % json.dumps("primary"))
        toggles = p.js(JS_TOGGLES % json.dumps("primary"))
        if not toggles:
            f.add("sidebar-toggle", "no visible primary-sidebar toggle (☰)")
        elif before["sidebar"]["width"] < 100:
            f.add(
                "sidebar-toggle",
                f"the primary sidebar is not shown at {view.width} px before any click "
                f"({before['sidebar']['width']} px visible)",
            )
        else:
            t = toggles[0]
            p.click_at(t["x"], t["y"])
            time.sleep(0.6)
            mid = p.js(JS_SIDEBAR % json.dumps("primary"))
            t2 = p.js(JS_TOGGLES % json.dumps("primary"))
            if t2:
                p.click_at(t2[0]["x"], t2[0]["y"])
                time.sleep(0.6)
            after = p.js(JS_SIDEBAR % json.dumps("primary"))
            collapsed = mid["sidebar"]["width"] < 5 and mid["main"] > before["main"] + 1
            restored = (
                abs(after["sidebar"]["width"] - before["sidebar"]["width"]) <= 2
                and abs(after["main"] - before["main"]) <= 2
            )
            notes.append(
                f"☰ {t['label']!r}: sidebar {before['sidebar']['width']} -> "
                f"{mid['sidebar']['width']} -> {after['sidebar']['width']} px, main area "
                f"{before['main']} -> {mid['main']} -> {after['main']} px"
            )
            if not collapsed:
                f.add(
                    "sidebar-toggle",
                    f"clicking ☰ {t['label']!r} does not collapse the primary sidebar: "
                    f"{mid['sidebar']['width']} px of it still visible (was "
                    f"{before['sidebar']['width']}), main area {before['main']} -> "
                    f"{mid['main']} px",
                )
            elif not t2:
                f.add("sidebar-toggle", "after collapsing, no visible ☰ to restore the sidebar")
            elif not restored:
                f.add(
                    "sidebar-toggle",
                    f"clicking ☰ again does not restore the primary sidebar: "
                    f"{after['sidebar']['width']} px (was {before['sidebar']['width']}), main "
                    f"area {after['main']} px (was {before['main']})",
                )
    print(f"{tag} sidebar toggles: " + ("; ".join(notes) or "-"))


def check_console(p, browser, session, base_url, f: Findings, tag: str, view: View) -> None:
    """(g) Network and JavaScript errors, from the events gathered during the whole visit."""
    with browser.cond:
        events = [e for e in browser.events if e.get("sessionId") == session]
    requests, external, failed, js_errors, console = set(), set(), [], [], []
    for ev in events:
        m, prm = ev["method"], ev.get("params", {})
        if m == "Network.requestWillBeSent":
            u = prm["request"]["url"]
            if u.startswith(("data:", "blob:", "about:")):
                continue
            requests.add(u)
            if not u.startswith(base_url + "/"):
                external.add(u)
        elif m == "Network.responseReceived":
            r = prm["response"]
            if r["status"] >= 400 and not r["url"].endswith("/favicon.ico"):
                failed.append(f"{r['status']} {r['url']}")
        elif m == "Network.loadingFailed" and not prm.get("canceled"):
            failed.append(f"{prm.get('errorText')} ({prm.get('type')})")
        elif m == "Runtime.exceptionThrown":
            d = prm["exceptionDetails"]
            err = (d.get("exception") or {}).get("description") or d.get("text") or ""
            js_errors.append(err[:300])
        elif m == "Runtime.consoleAPICalled" and prm.get("type") in ("error", "warning", "assert"):
            text = " ".join(
                str(a.get("value", a.get("description", ""))) for a in prm.get("args", [])
            )
            console.append(f"console.{prm['type']}: {text[:200]}")
        elif m == "Log.entryAdded" and prm["entry"].get("level") in ("error", "warning"):
            e = prm["entry"]
            if not e.get("url", "").endswith("/favicon.ico"):
                console.append(f"{e['level']} ({e.get('source')}): {e.get('text', '')[:200]}")
    known = [k for k in KNOWN_CONSOLE if any(k in x for x in js_errors + console)]
    print(
        f"{tag} network: {len(requests)} requests"
        + (f", {len(external)} EXTERNAL" if external else ", all local")
        + f"; javascript: {len(js_errors)} uncaught errors, {len(console)} console "
        f"errors/warnings" + (f" (among them {known})" if known else "")
    )
    if external:
        f.add("network", f"external requests {sorted(external)[:5]}")
    if failed:
        f.add("network", f"failed requests {failed[:5]}")
    for x in js_errors[:3]:
        f.add("console", f"uncaught JavaScript error: {x}")
    for x in console[:5]:
        f.add("console", x)
    if len(console) > 5:
        f.add("console", f"... {len(console) - 5} more console errors/warnings")
    # No trace of thebe (off in this book: _ext/probrob_no_thebe.py removes it from the pages).
    thebe = p.js(
        "Array.from(document.querySelectorAll('script,link')).filter(e => /thebe/i.test("
        "(e.src || e.href || '') + (e.type || '') + (e.textContent || '').slice(0, 2000))).length"
    )
    if thebe:
        f.add("console", f"thebe: {thebe} thebe scripts or stylesheets on the page")


# Console messages issue 17 names (a failure like any other console message; named in the
# output so a reader sees at once whether they are back).
KNOWN_CONSOLE = ["Identifier 'THEBE_JS_URL' has already been declared", "Got invalid theme mode"]


# --------------------------------------------------------------------------------------------
# The self-test: a page with one planted defect of each class; the check must report each.

FIXTURE = ROOT / ".ci" / "fixtures" / "browser" / "defects.html"
# (defect class, a piece of its message) that the fixture must produce, in some view
PLANTED = [
    ("page-width", "code.planted-wide"),
    ("raw-table", "| a | b |"),
    ("split-stream", "planted first line"),
    ("equation-width", "\\text{planted too-wide equation}"),
    ("alt-text", "'../_images/x.png'"),
    ("alt-text", "images without alt text"),
    ("canvas-aspect", "probrob-live-planted"),
    ("canvas-scale", "probrob-live-planted"),
    ("canvas-background", "probrob-live-planted"),
    ("plot-width", "probrob-live-planted"),
    ("player-overflow", "player 1"),
    ("sidebar-toggle", "toggle"),
    ("colour-mode", "<html data-theme>"),
    ("console", "planted console error"),
    ("axe", "image-alt"),
    ("axe", "color-contrast"),
]


def self_test_missed(findings: list[Findings]) -> list[tuple[str, str]]:
    got = [(c, m) for f in findings for c, m in f.items]
    return [(c, k) for c, k in PLANTED if not any(c == gc and k in gm for gc, gm in got)]


def axe_source(path: Path) -> str:
    if not path.is_file():
        raise CheckError(
            f"axe-core is not installed ({path} is missing): run `make browser-check`, which "
            "installs it with `npm ci --prefix .ci` from .ci/package-lock.json"
        )
    return path.read_text(encoding="utf-8")


def write_findings(path: Path, results: list[tuple[str, Findings]]) -> None:
    """The failures grouped by defect class, then page, for the authors who fix them."""
    by_class: dict[str, dict[str, list[str]]] = {}
    for page, f in results:
        for cls, msg in f.items:
            by_class.setdefault(cls, {}).setdefault(page, []).append(f"[{f.view.name}] {msg}")
    lines = [f"# browser check findings, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}"]
    for cls in sorted(by_class):
        n = sum(len(v) for v in by_class[cls].values())
        lines.append(f"\n## {cls} ({n})")
        for page in by_class[cls]:
            lines.append(f"\n{page}:")
            lines += [f"  {m}" for m in by_class[cls][page]]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument(
        "pages",
        nargs="*",
        help="pages relative to --html (default: every page of _toc.yml)",
    )
    ap.add_argument("--html", type=Path, default=ROOT / "_build" / "html")
    ap.add_argument("--screenshots", type=Path, default=ROOT / "_build" / "screenshots")
    ap.add_argument(
        "--file-urls",
        action="store_true",
        help="open the pages as file:// URLs (as a reader opening index.html) instead of serving",
    )
    ap.add_argument("--chromium", help="Chromium binary (default: Debian's chromium)")
    ap.add_argument(
        "--axe",
        type=Path,
        default=ROOT / ".ci" / "node_modules" / "axe-core" / "axe.min.js",
        help="axe-core's axe.min.js (installed by `make browser-check` from .ci/package.json)",
    )
    ap.add_argument(
        "--views",
        default=",".join(f"{v.width}-{v.mode}" for v in VIEWS),
        help="the views to check, e.g. 1280-light,390-dark (default: all four)",
    )
    ap.add_argument(
        "--self-test",
        action="store_true",
        help="first check that the fixture page with planted defects fails with each of them",
    )
    ap.add_argument("--findings", type=Path, help="write the failures, grouped, to this file")
    ap.add_argument("--verbose", action="store_true")
    ap.add_argument("--min-math", type=int, default=1, help="typeset formulas per page")
    ap.add_argument("--min-images", type=int, default=2, help="rendered plot images per page")
    ap.add_argument("--min-players", type=int, default=1, help="to_jshtml players per page")
    ap.add_argument(
        "--min-figure-scale",
        type=float,
        default=0.98,
        help="smallest displayed/natural width of a figure image (1 = shown at its own size)",
    )
    ap.add_argument("--timeout", type=float, default=60.0, help="seconds per page load / wait")
    ap.add_argument("--max-shot-height", type=int, default=16000)
    args = ap.parse_args(argv)
    t_start = time.monotonic()

    try:
        views = [
            VIEWS[[f"{v.width}-{v.mode}" for v in VIEWS].index(s)] for s in args.views.split(",")
        ]
    except ValueError:
        ap.error(f"--views: choose among {', '.join(f'{v.width}-{v.mode}' for v in VIEWS)}")
    html = args.html.resolve()
    if args.pages:
        pages = [(pg, (ROOT / f"{pg.removesuffix('.html')}.ipynb").is_file()) for pg in args.pages]
    else:
        pages = toc_pages(ROOT)
    if not pages:
        print("browser check: no pages in _toc.yml", file=sys.stderr)
        return 1
    missing = [pg for pg, _ in pages if not (html / pg).is_file()]
    if missing:
        print(f"browser check: not built: {missing} (run `make book`)", file=sys.stderr)
        return 1
    try:
        axe_js = axe_source(args.axe)
    except CheckError as e:
        print(f"browser check: FAIL {e}", file=sys.stderr)
        return 1

    fixture_dir = None
    if args.self_test:
        # The fixture uses the built book's MathJax: it is copied into the HTML tree for the run.
        if not (html / "_static" / "mathjax" / "tex-chtml.js").is_file():
            print(
                f"browser check: no MathJax in {html}/_static (run `make book`)", file=sys.stderr
            )
            return 1
        fixture_dir = html / "_probrob_selftest"
        fixture_dir.mkdir(exist_ok=True)
        shutil.copy2(FIXTURE, fixture_dir / FIXTURE.name)
        pages.insert(0, (f"{fixture_dir.name}/{FIXTURE.name}", False))

    chromium = find_chromium(args.chromium)
    version = subprocess.run([chromium, "--version"], capture_output=True, text=True).stdout
    print(
        f"browser check: {version.strip() or chromium}, {len(pages)} page(s) x {len(views)} "
        f"view(s) ({', '.join(v.name for v in views)})"
    )
    browser = Browser(chromium, args.timeout)
    results: list[tuple[str, Findings]] = []
    passed = failed = 0
    axe_total = dict.fromkeys(IMPACTS, 0)
    self_test_ok = None
    try:
        server = contextlib.nullcontext(html.as_uri()) if args.file_urls else serve(html)
        with server as base_url:
            for page, notebook in pages:
                print(f"{page}:")
                t0 = time.monotonic()
                page_findings = []
                for view in views:
                    is_fixture = fixture_dir is not None and page.startswith(fixture_dir.name)
                    shots = None if is_fixture else args.screenshots
                    findings, stats = check_view(
                        browser, base_url, page, view, shots, args, axe_js, notebook
                    )
                    page_findings.append(findings)
                    for cls, msg in findings.items:
                        print(f"  FAIL [{view.name}] {cls}: {msg}")
                    if not is_fixture:
                        for k in IMPACTS:
                            axe_total[k] += stats["axe"][k]
                        results.append((page, findings))
                        passed += not findings
                        failed += bool(findings)
                if fixture_dir is not None and page.startswith(fixture_dir.name):
                    missed = self_test_missed(page_findings)
                    self_test_ok = not missed
                    print(
                        f"  self-test: {len(PLANTED) - len(missed)} of {len(PLANTED)} planted "
                        "defects found" + (f"; MISSED {missed}" if missed else "")
                    )
                n_fail = sum(bool(x) for x in page_findings)
                print(
                    f"  {'ok' if not n_fail else f'FAILED in {n_fail} of {len(views)} views'} "
                    f"({time.monotonic() - t0:.0f} s)"
                )
    finally:
        browser.close()
        if fixture_dir is not None:
            shutil.rmtree(fixture_dir, ignore_errors=True)
    if args.findings:
        write_findings(args.findings, results)
        print(f"findings written to {args.findings}")
    n_pages = len(pages) - (fixture_dir is not None)
    print(
        f"browser check: {n_pages} pages x {len(views)} views = {passed + failed} page views "
        f"checked in {time.monotonic() - t_start:.0f} s; axe violations: "
        f"{sum(axe_total.values())} ("
        + ", ".join(f"{axe_total[k]} {k}" for k in IMPACTS)
        + ")"
        + ("" if self_test_ok is None else f"; self-test {'passed' if self_test_ok else 'FAILED'}")
    )
    if self_test_ok is False:
        failed += 1
    print(f"browser-check: {passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
