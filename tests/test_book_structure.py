"""The book's structure: numbered chapters with English titles and the deck's own title, every
erratum linked to its chapter and back, a references page that holds every cited key, and a
table index that names real functions whose docstrings cite its tables."""

import functools
import importlib
import json
import re
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).parent.parent
BOOK = ROOT / "book"
TOC = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))

# The deck's own title beside each chapter's English title (or "beyond the decks").
DECK_TITLES = {
    "trabalho3_motion_models": "*Trabalho 3*",
    "turkish_lecture_motion": "*Olasılıksal Robotik*",
    "cir_odometry": "*Assignment Submission 1.1*",
    "mrclam_motion_noise": "*beyond the decks*",
    "trabalho4_measurement_models": "*Trabalho 4*",
    "trabalho5_localization": "*Trabalho 5*",
    "mcl_intel_lab": "*beyond the decks*",
}


def page(name):
    """The page's text with every run of whitespace one space."""
    return " ".join((BOOK / name).read_text(encoding="utf-8").split())


@functools.cache
def markdown_cells(stem):
    nb = json.loads((ROOT / "notebooks" / f"{stem}.ipynb").read_text(encoding="utf-8"))
    return ["".join(c["source"]) for c in nb["cells"] if c["cell_type"] == "markdown"]


def toc_parts():
    return TOC["parts"]


# ------------------------------------------------------------------------ numbered chapters


def test_every_notebook_is_a_numbered_chapter_of_the_toc():
    numbered = [p for p in toc_parts() if p.get("numbered")]
    assert len(numbered) == 1
    files = [c["file"] for c in numbered[0]["chapters"]]
    notebooks = {f"notebooks/{p.stem}" for p in (ROOT / "notebooks").glob("*.ipynb")}
    assert set(files) == notebooks and len(files) == len(notebooks)
    others = [c["file"] for p in toc_parts() if not p.get("numbered") for c in p["chapters"]]
    assert not any(f.startswith("notebooks/") for f in others)
    for name in ("book/tables", "book/references", "book/errata"):
        assert name in others


@pytest.mark.parametrize("stem", sorted(DECK_TITLES))
def test_chapter_title_is_english_with_the_decks_title_beside_it(stem):
    first = markdown_cells(stem)[0].splitlines()[0]
    assert first.startswith("# "), first
    english, _, deck = first[2:].partition(" — ")
    assert deck.startswith(DECK_TITLES[stem]), first
    # the English title comes first: no deck title (nor its words) before the dash
    for word in ("Trabalho", "Olasılıksal", "Assignment"):
        assert word not in english, first
    assert re.search(r"[a-z]{4,}", english), first


# ---------------------------------------------------------------------------------- errata


@functools.cache
def errata_entries():
    text = (BOOK / "errata.md").read_text(encoding="utf-8")
    parts = re.split(r"^\(errata-(\w+)\)=\n", text, flags=re.M)[1:]
    entries = {}
    for key, body in zip(parts[::2], parts[1::2], strict=True):
        entries[key] = " ".join(re.split(r"^## ", body, flags=re.M)[0].split())
    return entries


@functools.cache
def chapter_sections():
    """label -> (notebook stem, the chapter's markdown from the label to the next label; for a
    label that ends its cell (a figure's anchor) also the text of that cell before it)."""
    sections = {}
    for nb in (ROOT / "notebooks").glob("*.ipynb"):
        text = "\n".join(markdown_cells(nb.stem))
        marks = list(re.finditer(r"^\(([\w-]+)\)=[ \t]*$", text, flags=re.M))
        for k, mark in enumerate(marks):
            end = marks[k + 1].start() if k + 1 < len(marks) else len(text)
            region = text[mark.end() : end]
            cell = next(c for c in markdown_cells(nb.stem) if mark.group(0) in c)
            before, _, after = cell.partition(mark.group(0))
            if not after.strip():
                region = before + region
            sections[mark.group(1)] = (nb.stem, region)
    return sections


def test_there_are_errata_of_every_family():
    keys = errata_entries()
    assert len(keys) >= 33
    assert {k[0] for k in keys} == set("dvolwcbfg")


@pytest.mark.parametrize("key", sorted(errata_entries()))
def test_every_erratum_links_to_its_chapter_and_the_chapter_links_back(key):
    body = errata_entries()[key]
    on_page = re.search(r"- \*\*On the page:\*\* (.*?)(?= - \*\*|$)", body)
    assert on_page, f"erratum {key} has no 'On the page:' line"
    labels = re.findall(r"\{ref\}`(?:[^`<]*<)?([\w-]+)>?`", on_page.group(1))
    assert labels, f"erratum {key}: 'On the page' has no {{ref}} to a chapter label"
    sections = chapter_sections()
    for label in labels:
        assert label in sections, f"erratum {key}: no label ({label})= in a chapter"
        back = rf"(<errata-{key}>`|`errata-{key}`|\]\(errata-{key}\))"
        assert re.search(back, sections[label][1]), (
            f"erratum {key}: section {label} of {sections[label][0]} does not link back"
        )


# ------------------------------------------------------------------------------ references


def bib_keys():
    text = (ROOT / "references.bib").read_text(encoding="utf-8")
    return set(re.findall(r"^@\w+\{([\w:-]+),", text, flags=re.M))


def cited_keys():
    """Keys cited by {cite} roles on the prose pages and by ref-<key> links in the chapters."""
    keys = set()
    for md in BOOK.glob("*.md"):
        for group in re.findall(r"\{cite(?::\w+)?\}`([\w,\s-]+)`", md.read_text(encoding="utf-8")):
            keys.update(k.strip() for k in group.split(","))
    for nb in (ROOT / "notebooks").glob("*.ipynb"):
        for cell in markdown_cells(nb.stem):
            keys.update(re.findall(r"\]\(ref-([\w-]+)\)", cell))
    return keys


def test_every_cited_key_is_in_the_bib_and_has_its_anchor_on_the_references_page():
    text = (BOOK / "references.md").read_text(encoding="utf-8")
    anchors = set(re.findall(r"^\(ref-([\w-]+)\)=", text, flags=re.M))
    cited = cited_keys()
    assert cited <= bib_keys(), cited - bib_keys()
    assert bib_keys() <= anchors, bib_keys() - anchors
    assert "```{bibliography}" in text


def test_the_works_the_issue_names_are_cited():
    cited = cited_keys()
    for key in ("thrun2005", "fox2003", "julier2004", "wan2000", "leung2011", "howard2003"):
        assert key in cited
    for key in ("grisetti2007", "ueda2019"):
        assert key in cited


def test_config_loads_the_bib():
    config = yaml.safe_load((ROOT / "_config.yml").read_text(encoding="utf-8"))
    assert config["bibtex_bibfiles"] == ["references.bib"]


# ----------------------------------------------------------------------------- table index

COVERED = ["4.4", "5.1", "5.2", "5.3", "5.4", "5.5", "5.6", "6.1", "6.2", "6.3", "6.4", "6.5"]
COVERED += ["7.2", "7.3", "7.4", "8.2", "8.3", "8.4"]


def table_rows():
    rows = {}
    for line in (BOOK / "tables.md").read_text(encoding="utf-8").splitlines():
        m = re.match(r"\| (\d\.\d) \| [^|]+ \| ([^|]+) \| ([^|]+) \|$", line)
        if m:
            rows[m.group(1)] = (re.findall(r"`(probrob\.[\w.]+)`", m.group(2)), m.group(3))
    return rows


def test_table_index_lists_every_covered_table():
    rows = table_rows()
    assert set(COVERED) <= set(rows), set(COVERED) - set(rows)


@pytest.mark.parametrize("table", sorted(table_rows()))
def test_table_index_names_functions_whose_docstring_cites_the_table(table):
    functions, shown = table_rows()[table]
    assert functions, table
    for path in functions:
        module, name = path.rsplit(".", 1)
        function = getattr(importlib.import_module(module), name)
        assert re.search(rf"Table {re.escape(table)}(?!\d)", function.__doc__ or ""), (
            f"{path}'s docstring does not cite Table {table}"
        )
    labels = re.findall(r"\{ref\}`[^`<]*<([\w-]+)>`", shown)
    assert labels, f"Table {table}: no {{ref}} to a chapter section"
    sections = chapter_sections()
    for label in labels:
        assert label in sections, f"Table {table}: no label ({label})= in a chapter"


def test_the_intros_chapter_numbers_follow_the_toc():
    numbered = next(p for p in toc_parts() if p.get("numbered"))["chapters"]
    number = {c["file"].split("/")[-1]: k + 1 for k, c in enumerate(numbered)}
    text = page("intro.md")
    named = {
        "trabalho3_motion_models": r"chapter 1, \*Motion models\* \(Trabalho 3\)",
        "mrclam_motion_noise": r"chapter \*\*(\d)\*\* \(MRCLAM\)",
        "trabalho4_measurement_models": r"chapter \*\*(\d)\*\* \(Trabalho 4\)",
        "trabalho5_localization": r"chapter \*\*(\d)\*\* \(Trabalho 5\)",
        "mcl_intel_lab": r"chapter \*\*(\d)\*\* \(Monte Carlo localization\)",
    }
    assert re.search(named.pop("trabalho3_motion_models"), text)
    assert number["trabalho3_motion_models"] == 1
    for stem, pattern in named.items():
        (found,) = re.findall(pattern, text)
        assert int(found) == number[stem], stem
    # the source-deck table names each deck's chapter by its number
    rows = re.findall(r'^\| "([^"]+)" \| \w+ \| [^|]+ \| (\d) \|$', _raw("intro.md"), flags=re.M)
    decks = {
        "Trabalho 3": "trabalho3_motion_models",
        "Olasılıksal Robotik": "turkish_lecture_motion",
        "Assignment Submission 1.1": "cir_odometry",
        "Trabalho 4": "trabalho4_measurement_models",
        "Trabalho #5": "trabalho5_localization",
    }
    assert {deck: int(n) for deck, n in rows} == {d: number[s] for d, s in decks.items()}


def _raw(name):
    return (BOOK / name).read_text(encoding="utf-8")
