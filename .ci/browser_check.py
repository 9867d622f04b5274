#!/usr/bin/env python3
"""Open built chapter pages in a real headless Chromium and check what a reader would see.

For every page it checks that
  * MathJax typeset the math (``mjx-container`` elements, no ``mjx-merror``, and no raw ``$$``,
    ``\\(`` or ``\\[`` left in the visible text outside code blocks);
  * the plots are there (``<img>`` in cell outputs with a non-zero natural size, no broken image
    anywhere on the page);
  * the figures are readable: no figure or player image is shrunk by the page below its own size
    (a shrunk image shrinks its tick labels with it; ``probrob.plotting.use_book_style`` sizes
    figures for the column with 9-pt = 12.5-px tick labels), none is wider than the text column,
    every ``<img>`` has an ``alt`` text and every player slider a label;
  * every ``to_jshtml`` animation player changes its frame when its "Next frame" button is
    clicked, and again while "Play" runs;
  * every live widget redraws when two of its sliders are moved with the keyboard, updates
    within 16 ms and weighs at most 200 kB, or the budgets its block states
    (``.ci/live_widgets_check.py``);
  * the page loads nothing from outside the local server (no external script, stylesheet, font,
    image), throws no JavaScript error, logs no console error or warning (each page is opened
    as a first visit, with empty local storage), and carries no thebe script;
and saves screenshots to ``_build/screenshots/<page>.png`` (a page taller than
``--max-shot-height`` continues in ``<page>-2.png``, ...).

Only the standard library is used: Chromium is driven through its DevTools protocol over a pipe
(``--remote-debugging-pipe``; the driver is ``.ci/cdp.py``), the book is served by
``http.server`` on 127.0.0.1 (or opened as file:// URLs with ``--file-urls``, as a reader
opening index.html would).

Usage:  python .ci/browser_check.py [PAGE.html ...] [--min-players 0] [--file-urls] ...
PAGE is relative to the HTML folder (default: every page listed in _toc.yml; the minimum counts
of formulas, plots and players apply to the notebook chapters).
Exit status 0 only if every page passes.
"""

from __future__ import annotations

import argparse
import base64
import contextlib
import json
import re
import subprocess
import sys
import time
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
  const noAlt = Array.from(document.querySelectorAll("article img"))
    .filter(im => !(im.getAttribute("alt") || "").trim())
    .map(im => (im.id || im.getAttribute("src") || "").slice(0, 60));
  const unlabelled = Array.from(document.querySelectorAll(".animation input[type=range]"))
    .filter(el => !el.getAttribute("aria-label") && !(el.labels && el.labels.length))
    .map(el => el.id.slice(0, 30));
  return {column: Math.round(column), figures: figures, noAlt: noAlt, unlabelled: unlabelled};
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


class Page(Tab):
    """A chapter page in the browser's first target (sending and page scripts from ``Tab``)."""

    def __init__(self, browser: Browser, session: str):
        super().__init__(browser, target=None, session=session)

    def click_button(self, player: int, title: str) -> None:
        pos = self.js(JS_BUTTON_CENTER % (player, json.dumps(title)))
        if pos is None:
            raise CheckError(f'player {player + 1}: no "{title}" button')
        time.sleep(0.1)  # let the scroll settle
        for kind in ("mouseMoved", "mousePressed", "mouseReleased"):
            self.send(
                "Input.dispatchMouseEvent",
                {"type": kind, "x": pos["x"], "y": pos["y"], "button": "left", "clickCount": 1},
            )


def check_page(
    browser: Browser, base_url: str, page: str, shots: Path, args, notebook: bool = True
) -> list[str]:
    """Run every check on one page; return the list of failures (empty = pass).

    The minimum counts of formulas, plots and players apply to notebook chapters only; every
    other check (and the console) applies to every page."""
    failures: list[str] = []
    url = f"{base_url}/{page}"
    target = browser.send("Target.createTarget", {"url": "about:blank"})["targetId"]
    session = browser.send("Target.attachToTarget", {"targetId": target, "flatten": True})[
        "sessionId"
    ]
    p = Page(browser, session)
    for domain in ("Page", "Runtime", "Network", "Log"):
        p.send(f"{domain}.enable")
    p.send(
        "Emulation.setDeviceMetricsOverride",
        {"width": args.width, "height": args.height, "deviceScaleFactor": 1, "mobile": False},
    )
    # Every page is visited as a first visit (no colour mode stored by an earlier page).
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
            failures.append(f"math: {state}")
    time.sleep(0.5)  # the players start from a setTimeout(0) after load
    info = p.js(JS_SURVEY)

    # Math
    print(
        f"  math: {info['mjx']} MathJax-typeset formulas "
        f"({info['mathElements']} math elements, {info['mathUntypeset']} not typeset, "
        f"{len(info['mjxErrors'])} TeX errors, {info['rawCount']} raw delimiters in the text)"
    )
    if notebook and info["mjx"] < args.min_math:
        failures.append(f"math: {info['mjx']} typeset formulas, expected >= {args.min_math}")
    if info["mathUntypeset"]:
        failures.append(f"math: {info['mathUntypeset']} math elements were not typeset")
    if info["mjxErrors"]:
        failures.append(f"math: TeX errors {info['mjxErrors']}")
    if info["rawCount"]:
        failures.append(f"math: raw TeX left in the visible text: {info['raw']}")

    # Images
    print(
        f"  images: {info['plots']} plot images in cell outputs ({info['plotsOk']} rendered), "
        f"{info['images']} <img> on the page, {len(info['broken'])} broken"
    )
    if notebook and info["plotsOk"] < args.min_images:
        failures.append(f"images: {info['plotsOk']} rendered plots, expected >= {args.min_images}")
    if info["broken"]:
        failures.append(f"images: broken {info['broken'][:5]}")

    # Figure readability
    fig = p.js(JS_FIGURES)
    figures = fig["figures"]
    if figures:
        smallest = min(figures, key=lambda f: f["scale"])
        widest = max(figures, key=lambda f: f["natural"])
        print(
            f"  figures: {len(figures)} images (plots and players) in a {fig['column']}-px "
            f"column; widest {widest['natural']} px; smallest display scale "
            f"{smallest['scale']:.3f} (image {smallest['k'] + 1}); "
            f"{len(fig['noAlt'])} without alt text, {len(fig['unlabelled'])} unlabelled sliders"
        )
    shrunk = [f for f in figures if f["scale"] < args.min_figure_scale]
    if shrunk:
        failures.append(
            f"figures: {len(shrunk)} shrunk by the page below {args.min_figure_scale:.0%} of "
            "their size (their text shrinks with them): "
            + ", ".join(
                f"image {f['k'] + 1} {f['natural']} px shown at {f['shown']}" for f in shrunk[:5]
            )
        )
    # An image up to 1/min-figure-scale of the column is shrunk by the page no more than the
    # shrink check allows (bbox_inches="tight" may add a few pixels to a column-wide figure);
    # a wider one, or a player (which overflows instead of shrinking), fails.
    too_wide = [f for f in figures if f["natural"] > fig["column"] / args.min_figure_scale]
    if too_wide:
        failures.append(
            f"figures: {len(too_wide)} wider than the {fig['column']}-px column "
            f"(by more than {1 / args.min_figure_scale - 1:.0%}): "
            + ", ".join(f"image {f['k'] + 1} ({f['natural']} px)" for f in too_wide[:5])
        )
    if fig["noAlt"]:
        failures.append(f"accessibility: images without alt text {fig['noAlt'][:5]}")
    if fig["unlabelled"]:
        failures.append(f"accessibility: player sliders without a label {fig['unlabelled'][:5]}")

    # Players
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
            f"  player {k + 1}: {s0['frames']} frames; next-frame button "
            f"{'changed' if stepped else 'did NOT change'} the image (frame {s0['frame']} -> "
            f"{s1['frame']}); play {'advanced' if played else 'did NOT advance'} it "
            f"(frame 0 -> {s2['frame']})"
        )
        if not ok:
            failures.append(f"player {k + 1}: frames do not change (or do not load)")
    if notebook and info["players"] < args.min_players:
        failures.append(
            f"players: {info['players']} to_jshtml players, expected >= {args.min_players}"
        )

    # Live widgets (probrob.widgets.*_live): two sliders moved by keyboard on each, the canvas
    # redrawn; update time and HTML size against their budgets (.ci/live_widgets_check.py)
    live_lines, live_failures = check_live_widgets(p)
    for line in live_lines:
        print(f"  {line}")
    failures += live_failures

    # Screenshots of the whole page, after the players were used: the viewport is made as tall
    # as the page (up to --max-shot-height), so the fixed sidebars are laid out as a reader sees;
    # a taller page is scrolled and saved in further parts, <page>-2.png, <page>-3.png, ...
    height = min(info["height"], args.max_shot_height)
    p.send(
        "Emulation.setDeviceMetricsOverride",
        {"width": args.width, "height": height, "deviceScaleFactor": 1, "mobile": False},
    )
    shots.mkdir(parents=True, exist_ok=True)
    for part, top in enumerate(range(0, info["height"], height)):
        p.js(f"window.scrollTo(0, {top})")
        time.sleep(0.5)
        shot = p.send("Page.captureScreenshot", {"format": "png"}, timeout=120)
        out = shots / (Path(page).stem + (f"-{part + 1}" if part else "") + ".png")
        out.write_bytes(base64.b64decode(shot["data"]))
        print(
            f"  screenshot: {out.relative_to(ROOT) if out.is_relative_to(ROOT) else out} "
            f"({args.width}x{height}, from y = {top})"
        )

    # Network and JavaScript errors, from the events gathered during the whole visit
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
            js_errors.append(err)
        elif m == "Runtime.consoleAPICalled" and prm.get("type") in ("error", "warning", "assert"):
            text = " ".join(
                str(a.get("value", a.get("description", ""))) for a in prm.get("args", [])
            )
            console.append(f"console.{prm['type']}: {text[:200]}")
        elif m == "Log.entryAdded" and prm["entry"].get("level") in ("error", "warning"):
            e = prm["entry"]
            if not e.get("url", "").endswith("/favicon.ico"):
                console.append(f"{e['level']} ({e.get('source')}): {e.get('text', '')[:200]}")
    print(
        f"  network: {len(requests)} requests, all local"
        if not external
        else f"  network: {len(external)} EXTERNAL requests: {sorted(external)[:5]}"
    )
    if external:
        failures.append(f"network: external requests {sorted(external)[:5]}")
    if failed:
        failures.append(f"network: failed requests {failed[:5]}")
    print(
        f"  javascript: {len(js_errors)} uncaught errors, {len(console)} console errors/warnings"
    )
    if js_errors:
        failures.append(f"javascript errors: {js_errors[:3]}")
    if console:
        failures.append(f"console: {console[:3]}")
    # No trace of thebe (off in this book: _ext/probrob_no_thebe.py removes it from the pages).
    thebe = p.js(
        "Array.from(document.querySelectorAll('script,link')).filter(e => /thebe/i.test("
        "(e.src || e.href || '') + (e.type || '') + (e.textContent || '').slice(0, 2000))).length"
    )
    if thebe:
        failures.append(f"thebe: {thebe} thebe scripts or stylesheets on the page")

    browser.send("Target.closeTarget", {"targetId": target})
    with browser.cond:
        browser.events = [e for e in browser.events if e.get("sessionId") != session]
    return failures


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
    ap.add_argument("--width", type=int, default=1280)
    ap.add_argument("--height", type=int, default=1600)
    ap.add_argument("--max-shot-height", type=int, default=16000)
    args = ap.parse_args(argv)

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

    chromium = find_chromium(args.chromium)
    version = subprocess.run([chromium, "--version"], capture_output=True, text=True).stdout
    print(f"browser check: {version.strip() or chromium}, {len(pages)} page(s)")
    browser = Browser(chromium, args.timeout)
    passed = failed = 0
    try:
        server = contextlib.nullcontext(html.as_uri()) if args.file_urls else serve(html)
        with server as base_url:
            for page, notebook in pages:
                print(f"{page}:")
                try:
                    failures = check_page(
                        browser, base_url, page, args.screenshots, args, notebook
                    )
                except CheckError as e:
                    failures = [str(e)]
                for f in failures:
                    print(f"  FAIL {f}")
                if failures:
                    failed += 1
                else:
                    passed += 1
                    print("  ok")
    finally:
        browser.close()
    print(f"browser-check: {passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
