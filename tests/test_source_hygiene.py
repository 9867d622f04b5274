"""The library's sources are plain text that says what it means.

* No file of ``src/``, ``tests/``, ``benchmarks/`` or ``.ci/`` holds a control character
  other than the newline: a ``\\b``, ``\\r`` or ``\\t`` typed into a docstring as a byte
  renders as garbage (``\\bar\\Sigma`` became "ar\\Sigma").
* No library file refers to a developer's file outside the repository (the design notes,
  ``DESIGN.md``, or the developers' folder ``../shared``): a docstring says what is meant.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = ("src", "tests", "benchmarks", ".ci")
SKIP_PARTS = {"__pycache__", ".pytest_cache", ".hypothesis", "node_modules"}  # npm ci: not ours
CONTROL = re.compile(rb"[\x00-\x09\x0b-\x1f\x7f]")


def _files(folder):
    for path in sorted((ROOT / folder).rglob("*")):
        parts = set(path.relative_to(ROOT).parts)
        if (
            path.is_file()
            and not parts & SKIP_PARTS
            and not any(p.endswith(".egg-info") for p in parts)
        ):
            yield path


SOURCES = [path for folder in FOLDERS for path in _files(folder)]


def test_the_scan_sees_the_sources():
    names = {p.relative_to(ROOT).as_posix() for p in SOURCES}
    assert "src/probrob/localization.py" in names and ".ci/run" in names
    assert len(SOURCES) > 50


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_no_control_characters(path):
    data = path.read_bytes()
    newline = b"\n"
    bad = [
        f"line {data.count(newline, 0, m.start()) + 1}: {m.group()!r}"
        for m in CONTROL.finditer(data)
    ]
    assert bad == [], bad[:5]


def test_the_check_finds_a_control_character():
    assert CONTROL.search(b":math:`\x08ar\\Sigma`")
    assert CONTROL.search(b"a\r\nb") and CONTROL.search(b"\tindent")
    assert not CONTROL.search(b"plain text\n")


@pytest.mark.parametrize(
    "path",
    [p for p in SOURCES if p.relative_to(ROOT).parts[0] == "src"],
    ids=lambda p: p.relative_to(ROOT).as_posix(),
)
def test_the_library_refers_to_no_file_outside_the_repository(path):
    text = path.read_text(encoding="utf-8")
    assert "DESIGN.md" not in text
    assert "../shared" not in text


CONFLICT_MARKER = re.compile(r"^(<{7}|>{7}) |^={7}$", re.M)


def test_no_merge_conflict_markers_left_anywhere():
    """A merge committed with its conflict unresolved (``<<<<<<<`` lines) fails here, not in
    the notebook runner that cannot parse the file."""
    suffixes = {".py", ".md", ".ipynb", ".yml", ".toml", ".txt", ".js", ".css", ".bib", ".cfg"}
    found = [
        str(path.relative_to(ROOT))
        for path in ROOT.rglob("*")
        if path.is_file()
        and path.suffix in suffixes
        and not {".git", ".venv", "_build", "node_modules"} & set(path.relative_to(ROOT).parts)
        and CONFLICT_MARKER.search(path.read_text(encoding="utf-8", errors="replace"))
    ]
    assert found == []
