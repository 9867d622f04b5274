"""Every figure of every chapter has a text alternative that says what it shows.

myst-nb writes a cell's image outputs as ``<img alt="...">`` from the cell's metadata
``mystnb.image.alt``; without it the alt is the image's file name, which a screen reader reads
out as a path. The built pages are checked in a browser too (``.ci/browser_check.py``).
"""

import re
from pathlib import Path

import nbformat
import pytest

NOTEBOOKS = sorted((Path(__file__).resolve().parent.parent / "notebooks").glob("*.ipynb"))
FILE_NAME = re.compile(r"\.(png|jpe?g|svg|gif)\b|_images/|^\S+$", re.I)


def figure_cells(path):
    """``[(index, cell), ...]``: the code cells whose stored outputs include an image."""
    cells = nbformat.read(path, as_version=4).cells
    return [
        (k, c)
        for k, c in enumerate(cells)
        if c.cell_type == "code"
        and any(
            mime.startswith("image/") for o in c.get("outputs", []) for mime in o.get("data", {})
        )
    ]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_every_figure_has_a_describing_alt(path):
    cells = figure_cells(path)
    assert cells, f"{path.name} has no figure"
    for k, cell in cells:
        alt = cell.metadata.get("mystnb", {}).get("image", {}).get("alt", "")
        assert alt.strip(), f"{path.name}: cell {k} has a figure and no mystnb.image.alt"
        assert len(alt) >= 40 and not FILE_NAME.search(alt), (
            f"{path.name}: cell {k}: the alt {alt!r} does not describe the figure"
        )


@pytest.mark.parametrize("alt", ["../_images/ab12.png", "figure.png", "plot", ""])
def test_a_file_name_or_a_word_is_not_an_alt(alt):
    assert not alt.strip() or len(alt) < 40 or FILE_NAME.search(alt)
