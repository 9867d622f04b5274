"""What the chapters' figures promise: no text below the book's 9 pt, and no curve hidden.

The book's style (``probrob.plotting.use_book_style``) sets legends and tick labels to 9 pt;
a ``fontsize=7`` in a chapter undoes it for that figure. And a curve drawn under another of
the same width where the two coincide is not in the figure at all, though the legend lists
it: the chapters that draw coinciding curves check each such figure with ``hidden_share``
(defined once per chapter, the same code in each) and assert that no curve hides another.
This file proves that check can fail: on planted figures it finds each way of hiding a curve.
"""

import ast
import re
from pathlib import Path

import matplotlib.pyplot as plt
import nbformat
import numpy as np
import pytest

NOTEBOOKS = sorted((Path(__file__).resolve().parent.parent / "notebooks").glob("*.ipynb"))
SIZE = re.compile(r"\b(?:fontsize|labelsize)\s*=\s*(?:(\d+(?:\.\d+)?)|[\"']((?:xx?-)?small)[\"'])")


def code_cells(path):
    return [
        (k, c.source)
        for k, c in enumerate(nbformat.read(path, as_version=4).cells)
        if c.cell_type == "code"
    ]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_no_text_below_the_books_nine_points(path):
    small = []
    for k, source in code_cells(path):
        for m in SIZE.finditer(source):
            if m[2] or float(m[1]) < 9:
                small.append(f"cell {k}: {m[0]}")
    assert not small, f"{path.name}: text set below the book's 9 pt: {small}"


def test_the_size_check_can_fail():
    assert SIZE.search('ax.legend(fontsize=7, loc="upper left")')[1] == "7"
    assert SIZE.search('ax.legend(fontsize="small")')[2] == "small"
    assert SIZE.search("ax.set_title('t', fontsize=9)")[1] == "9"  # allowed: not below 9


def _hidden_share_sources():
    """Every notebook's definition of ``hidden_share``, as source text."""
    found = {}
    for path in NOTEBOOKS:
        for _, source in code_cells(path):
            if "def hidden_share(" not in source:
                continue
            tree = ast.parse(source)
            fn = next(
                n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "hidden_share"
            )
            found[path.stem] = ast.get_source_segment(source, fn)
    return found


@pytest.fixture(scope="module")
def hidden_share():
    sources = _hidden_share_sources()
    assert {"trabalho4_measurement_models", "trabalho5_localization"} <= set(sources)
    assert len(set(sources.values())) == 1, "the chapters' hidden_share differ"
    namespace = {"np": np}
    exec(next(iter(sources.values())), namespace)
    return namespace["hidden_share"]


def _two_lines(first, second, y_offset=0.0):
    fig, ax = plt.subplots(figsize=(6.4, 3.6), dpi=100)
    x = np.linspace(0, 10, 400)
    y = np.exp(-((x - 5) ** 2))
    below = ax.plot(x, y, **first)[0]
    above = ax.plot(x, y + y_offset, **second)[0]
    fig.canvas.draw()
    return fig, below, above


@pytest.mark.parametrize(
    ("first", "second", "hidden"),
    [
        (dict(lw=1.0), dict(lw=1.0), True),  # the same curve twice: the first is gone
        (dict(lw=1.0), dict(lw=1.6, color="k"), True),  # a wider one on top (Trabalho 4's)
        (dict(lw=3.5, color="0.6"), dict(lw=1.1), False),  # wide below, thin on top: both show
        (dict(lw=1.0), dict(lw=1.0, ls="--"), False),  # dashed on top: gaps show the first
        (dict(lw=1.0), dict(lw=2.0, alpha=0.5), False),  # translucent on top
    ],
)
def test_hidden_share_finds_a_hidden_curve(hidden_share, first, second, hidden):
    fig, below, above = _two_lines(first, second)
    try:
        share = hidden_share(below, above)
        assert (share > 0.9) if hidden else (share == 0.0), share
        assert hidden_share(above, below) == 0.0  # the one on top is never hidden by it
    finally:
        plt.close(fig)


def test_hidden_share_sees_curves_apart(hidden_share):
    fig, below, above = _two_lines(dict(lw=1.0), dict(lw=1.0), y_offset=0.3)
    try:
        assert hidden_share(below, above) < 0.5  # only the flat tails, where they meet
    finally:
        plt.close(fig)
