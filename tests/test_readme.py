"""The README's claims about the book, checked like the book's own pages.

Its first paragraph says how many course decks the book reproduces and names the chapters
beyond them; its "Reading the book" section lists every chapter, in the book's order, with the
live widgets it shows. Each test fails when a chapter or a widget the README names is gone, or
when one it does not name exists.
"""

import json
import re
from pathlib import Path

import pytest
import yaml

import probrob.widgets

ROOT = Path(__file__).parent.parent
README = (ROOT / "README.md").read_text(encoding="utf-8")
TOC = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))
NUMBERS = {"four": 4, "five": 5, "six": 6, "seven": 7}
# The chapters beyond the decks, by the name the README's first paragraph gives them.
BEYOND = {"mrclam_motion_noise": "MRCLAM", "mcl_intel_lab": "Monte Carlo localization"}
LIVE_CALL = re.compile(r"(?<![\w.])([a-z]\w*_live)\(")


def chapters():
    """The notebooks of the book's numbered chapters, in order (stems)."""
    numbered = next(p for p in TOC["parts"] if p.get("numbered"))["chapters"]
    return [c["file"].split("/")[-1] for c in numbered]


def cells(stem):
    return json.loads((ROOT / "notebooks" / f"{stem}.ipynb").read_text(encoding="utf-8"))["cells"]


def beyond_the_decks(stem):
    return "beyond the decks" in "".join(cells(stem)[0]["source"])


def widgets_shown(stem):
    """The live-widget factories a chapter calls, and how many live widgets its outputs hold."""
    calls, shown = set(), 0
    for cell in cells(stem):
        if cell["cell_type"] != "code":
            continue
        calls |= set(LIVE_CALL.findall("".join(cell["source"])))
        for out in cell.get("outputs", []):
            shown += "".join(out.get("data", {}).get("text/plain", "")).count(
                "<probrob live widget"
            )
    return calls, shown


def section(title):
    start = README.index(f"## {title}\n")
    end = README.find("\n## ", start + 1)
    return README[start : end if end > 0 else None]


def reading_list():
    """``[(notebook stem, {widget names}), ...]`` of the README's chapter list, in order."""
    items = re.split(r"\n- ", section("Reading the book"))[1:]
    listed = []
    for item in items:
        item = item.split("\n\n")[0]
        (stem,) = re.findall(r"`notebooks/(\w+)\.ipynb`", item)
        listed.append((stem, set(re.findall(r"`([a-z]\w*_live)`", item))))
    return listed


def test_the_first_paragraph_counts_the_decks_and_names_the_chapters_beyond_them():
    first = " ".join(README.split("\n\n")[1].split())
    decks = [s for s in chapters() if not beyond_the_decks(s)]
    (word,) = re.findall(r"reproduces (\w+) course decks", first)
    assert NUMBERS[word] == len(decks)
    assert {s for s in chapters() if beyond_the_decks(s)} == set(BEYOND)
    for name in BEYOND.values():
        assert name in first, name
    if "mcl_intel_lab" in chapters():
        assert "chapter 8" in first


def test_the_reading_list_is_the_books_chapters_in_order():
    assert [stem for stem, _ in reading_list()] == chapters()


@pytest.mark.parametrize("stem", chapters())
def test_the_reading_list_names_each_chapters_live_widgets(stem):
    named = dict(reading_list())[stem]
    calls, shown = widgets_shown(stem)
    assert named == calls, (
        f"{stem}: the README names {sorted(named)}, the chapter calls {sorted(calls)}"
    )
    assert shown >= len(calls), f"{stem}: a live widget the chapter calls is not in its outputs"
    for name in named:
        assert callable(getattr(probrob.widgets, name, None)), name
    if not named:
        item = section("Reading the book").split(f"`notebooks/{stem}.ipynb`")[1].split("\n- ")[0]
        assert "no live widget" in item, f"{stem}: say that the chapter has no live widget"


def test_the_check_can_fail():
    """A README list that misses a widget, or names one a chapter does not call, is caught."""
    calls, _ = widgets_shown("trabalho4_measurement_models")
    assert calls == {"beam_model_live", "landmark_model_live"}
    assert {"beam_model_live"} != calls and calls | {"ukf_step_live"} != calls
    assert LIVE_CALL.findall(
        "def _live(s):\n    cir_step_live(s_sx=1)\nx.velocity_model_live()"
    ) == ["cir_step_live"]  # a private helper or a method is not a widget the chapter shows
