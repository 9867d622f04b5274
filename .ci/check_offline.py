#!/usr/bin/env python3
"""Fail if any built page would load something from the network.

Scans every ``*.html`` under the HTML folder (default ``_build/html``) for tags that make the
browser fetch a resource at page load -- ``<script src>``, ``<link href>`` (stylesheets, fonts,
preloads, icons), ``<img>``/``<iframe>``/``<source>``/... ``src``, ``srcset``, ``<object data>`` --
and every ``*.css`` file and inline ``<style>`` for ``url(...)`` / ``@import``. Anything that is
not a relative path, ``data:`` or ``#`` is reported. Plain ``<a href>`` links are fine: they are
only followed when clicked. (Code shown on a page is escaped text, not tags, so it is not flagged.)

A common culprit is matplotlib's ``to_jshtml()``: it starts with a ``<link>`` to a Font Awesome
stylesheet on a CDN. Strip that ``<link>`` before displaying the player (the book's theme already
ships Font Awesome, so the player's buttons keep their icons).

Usage:  python .ci/check_offline.py [HTML_DIR]
"""

from __future__ import annotations

import re
import sys
from html.parser import HTMLParser
from pathlib import Path

EXTERNAL = re.compile(r"^\s*(?:[a-z][a-z0-9+.-]*:|//)", re.I)  # a scheme, or protocol-relative
LOCAL_SCHEMES = ("data:", "blob:", "about:", "javascript:")
CSS_URL = re.compile(r"(?:url\(\s*['\"]?|@import\s+['\"])([^'\")\s]+)", re.I)
# rel values of <link> that do not make the browser fetch anything at load time
INERT_RELS = {"index", "search", "next", "prev", "canonical", "alternate", "author", "license"}
INERT_RELS |= {"help", "bookmark", "top", "up", "first", "last", "copyright", "glossary"}
FETCH_ATTRS = {
    "script": ("src",),
    "img": ("src", "srcset"),
    "iframe": ("src",),
    "frame": ("src",),
    "embed": ("src",),
    "source": ("src", "srcset"),
    "video": ("src", "poster"),
    "audio": ("src",),
    "track": ("src",),
    "input": ("src",),
    "object": ("data",),
}


def is_external(url: str) -> bool:
    url = url.strip()
    return bool(EXTERNAL.match(url)) and not url.lower().startswith(LOCAL_SCHEMES)


class Scanner(HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.found: list[str] = []
        self.in_style = False

    def handle_starttag(self, tag, attrs):
        a = {k: (v or "") for k, v in attrs}
        urls = []
        if tag == "link":
            rels = set(a.get("rel", "").lower().split())
            if rels - INERT_RELS:
                urls.append(a.get("href", ""))
        for attr in FETCH_ATTRS.get(tag, ()):
            value = a.get(attr, "")
            urls += (
                [u.split()[0] for u in value.split(",") if u.strip()]
                if attr == "srcset"
                else [value]
            )
        if "style" in a:
            urls += CSS_URL.findall(a["style"])
        self.found += [f"<{tag}> {u}" for u in urls if u and is_external(u)]
        self.in_style = tag == "style"

    def handle_endtag(self, tag):
        if tag == "style":
            self.in_style = False

    def handle_data(self, data):
        if self.in_style:
            self.found += [f"<style> {u}" for u in CSS_URL.findall(data) if is_external(u)]


def main(argv: list[str]) -> int:
    root = Path(argv[1] if len(argv) > 1 else "_build/html")
    if not root.is_dir():
        print(f"check_offline: {root} does not exist (build the book first)", file=sys.stderr)
        return 1
    problems: dict[str, list[str]] = {}
    n_html = n_css = 0
    for path in sorted(root.rglob("*")):
        if path.suffix == ".html":
            n_html += 1
            s = Scanner()
            s.feed(path.read_text(encoding="utf-8", errors="replace"))
            s.close()
            found = s.found
        elif path.suffix == ".css":
            n_css += 1
            text = path.read_text(encoding="utf-8", errors="replace")
            found = [f"css {u}" for u in CSS_URL.findall(text) if is_external(u)]
        else:
            continue
        if found:
            problems[str(path.relative_to(root))] = sorted(set(found))
    if problems:
        print("check_offline: these pages load resources from the network:", file=sys.stderr)
        for page, found in problems.items():
            for f in found:
                print(f"  {page}: {f}", file=sys.stderr)
        print(
            "(a to_jshtml() player? strip its Font Awesome <link>; see .ci/check_offline.py)",
            file=sys.stderr,
        )
        return 1
    print(
        f"check_offline: {n_html} HTML pages and {n_css} stylesheets load nothing from the network"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
