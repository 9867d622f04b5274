"""The build's own settings agree with each other (Makefile, _config.yml)."""

from __future__ import annotations

import re
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parent.parent
MAKEFILE = (ROOT / "Makefile").read_text(encoding="utf-8")


def make_variable(name: str) -> str:
    m = re.search(rf"^{name}\s*:?=\s*(\S+)\s*$", MAKEFILE, re.M)
    assert m, f"Makefile defines no {name}"
    return m.group(1)


def test_cell_timeout_is_the_same_for_every_runner():
    # a stall fails after the same time in the book, in nbval and in `make execute`
    timeout = int(make_variable("CELL_TIMEOUT"))
    config = yaml.safe_load((ROOT / "_config.yml").read_text(encoding="utf-8"))
    assert config["execute"]["timeout"] == timeout
    assert "--nbval-cell-timeout=$(CELL_TIMEOUT)" in MAKEFILE
    assert "--nbval-kernel-startup-timeout=$(KERNEL_STARTUP_TIMEOUT)" in MAKEFILE
    assert "$(JUPYTER_EXECUTE) --inplace --timeout $(CELL_TIMEOUT)" in MAKEFILE
    assert "--startup_timeout $(KERNEL_STARTUP_TIMEOUT)" in MAKEFILE
    # far below the 600 s of the stall it must catch, far above the slowest real cell (24.7 s)
    assert 60 <= timeout <= 300
    assert 30 <= int(make_variable("KERNEL_STARTUP_TIMEOUT")) <= 120


# ---- the browser check: axe-core pinned, installed by the Makefile, run with its self-test ----

CI = ROOT / ".ci"


def browser_check_module():
    import importlib
    import sys

    sys.path.insert(0, str(CI))
    try:
        return importlib.import_module("browser_check")
    finally:
        sys.path.remove(str(CI))


def test_axe_core_is_pinned_and_locked():
    import json

    package = json.loads((CI / "package.json").read_text(encoding="utf-8"))
    version = package["devDependencies"]["axe-core"]
    assert re.fullmatch(r"\d+\.\d+\.\d+", version), f"axe-core not pinned exactly: {version}"
    lock = json.loads((CI / "package-lock.json").read_text(encoding="utf-8"))
    assert lock["packages"]["node_modules/axe-core"]["version"] == version
    assert lock["packages"][""]["devDependencies"]["axe-core"] == version


def test_browser_check_target_installs_axe_once_and_runs_the_self_test():
    target = re.search(r"^browser-check:(.*)\n((?:\t.*\n)+)", MAKEFILE, re.M)
    assert target, "no browser-check target"
    assert "$(NPM_STAMP)" in target.group(1)
    assert ".ci/browser_check.py --self-test" in target.group(2)
    assert make_variable("NPM_STAMP").startswith(".ci/node_modules/")
    stamp = re.search(r"^\$\(NPM_STAMP\):(.*)\n((?:\t.*\n)+)", MAKEFILE, re.M)
    assert stamp and ".ci/package-lock.json" in stamp.group(1)
    assert "npm ci --prefix .ci --no-audit --no-fund" in stamp.group(2)
    assert "npm is not installed" in stamp.group(2)
    run = (CI / "run").read_text(encoding="utf-8")
    assert "make browser-check" in run
    assert "browser_check.py" not in run  # through make, so axe-core is installed first
    ignored = (ROOT / ".gitignore").read_text(encoding="utf-8").split()
    assert ".ci/node_modules/" in ignored


def test_the_self_test_plants_every_defect_class():
    bc = browser_check_module()
    classes = {c for c, _ in bc.PLANTED}
    assert classes >= {
        "page-width",
        "raw-table",
        "equation-width",
        "alt-text",
        "canvas-aspect",
        "canvas-scale",
        "player-overflow",
        "sidebar-toggle",
        "colour-mode",
        "console",
        "axe",
    }
    fixture = bc.FIXTURE.read_text(encoding="utf-8")
    for marker in (
        "planted-wide",
        "<p>| a | b |</p>",
        "planted too-wide equation",
        'alt="../_images/x.png"',
        'id="probrob-live-planted"',
        'class="animation"',
        "planted console error",
    ):
        assert marker in fixture
    # nothing found = every planted defect missed
    assert bc.self_test_missed([]) == [(c, k) for c, k in bc.PLANTED]


def layout(**over):
    base = {
        "column": 623.0,
        "pageWidth": 1280,
        "innerWidth": 1280,
        "wide": [],
        "rawTables": [],
        "splitStreams": [],
        "equations": [],
        "noAlt": [],
        "fileNameAlt": [],
        "canvases": [],
        "players": [],
        "images": 0,
        "theme": "light",
        "mode": "auto",
    }
    return base | over


def classes_of(bc, lay, view):
    f = bc.Findings(view)
    bc.check_layout(lay, view, f, {})
    return [c for c, _ in f.items]


def test_layout_rules_of_the_browser_check():
    bc = browser_check_module()
    desk, phone = bc.View(1280, "light"), bc.View(390, "dark")
    assert classes_of(bc, layout(), desk) == []
    assert classes_of(bc, layout(pageWidth=1282), desk) == ["page-width"]
    assert classes_of(bc, layout(pageWidth=391, theme="dark"), phone) == []
    assert classes_of(bc, layout(theme="light", pageWidth=390), phone) == ["colour-mode"]
    eq = {"k": 0, "shown": True, "width": 700.0, "scrolls": True, "right": 0, "tex": "x"}
    assert classes_of(bc, layout(equations=[eq]), desk) == ["equation-width"]
    # on a phone an equation may scroll in its own box
    assert (
        classes_of(bc, layout(equations=[eq], theme="dark", column=358, pageWidth=390), phone)
        == []
    )
    assert classes_of(bc, layout(equations=[eq | {"width": 623.5}]), desk) == []
    assert classes_of(bc, layout(rawTables=["| a | b |"]), desk) == ["raw-table"]
    assert classes_of(bc, layout(splitStreams=["x = 1 | y = 2"]), desk) == ["split-stream"]
    assert classes_of(bc, layout(fileNameAlt=["../_images/a.png"]), desk) == ["alt-text"]
    canvas = {
        "id": "w",
        "shown": True,
        "cssW": 332,
        "cssH": 500,
        "bmpW": 600,
        "bmpH": 500,
        "dpr": 1,
    }
    assert classes_of(bc, layout(canvases=[canvas]), desk) == ["canvas-aspect", "canvas-scale"]
    exact = canvas | {"cssW": 200, "cssH": 166.7, "dpr": 3}
    assert classes_of(bc, layout(canvases=[exact]), desk) == []
    assert classes_of(bc, layout(canvases=[exact | {"dpr": 1}]), desk) == ["canvas-scale"]
    player = {
        "k": 0,
        "shown": True,
        "box": 600,
        "content": 616,
        "widest": "div",
        "overflowBox": 16,
        "overflowColumn": -7,
        "scrolls": False,
    }
    assert classes_of(bc, layout(players=[player]), desk) == ["player-overflow"]
    fits = player | {"content": 600, "overflowBox": 0}
    assert classes_of(bc, layout(players=[fits]), desk) == []
